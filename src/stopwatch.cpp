// Stopwatch::factor_rate and write_rate: small kernels timed once per solve that needs them;
// memory_left.
#include <sys/mman.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <vector>

#include "error_state.hpp"
#include "linalg/linalg.hpp"
#include "memory.hpp"
#include "solver_api.hpp"

namespace frix {

namespace {
// The timed LU: n = 96 (0.6 million flops, under a millisecond), diagonally dominant so that
// pivoting does no extra work, the fastest of kRateRuns. Small enough that the BLAS keeps it
// on one thread: on a shared machine an LU split over threads waits for the thread that lost
// its core, and ran many times slower than the large factorisations it prices
// (notes/2026-11-28-fem-setup.md); the first run also pays for starting the BLAS.
constexpr int64_t kRateSize = 96;
constexpr int kRateRuns = 9;
// The timed writes: kWriteEntries doubles in pages the process never touched (as W's, which
// is large), each first written, then kWriteAdds additions in an order that jumps kWriteStride
// entries (32 KB: past the caches' lines and pages), as the terms summed into W, the fastest
// of kWriteRuns. Larger than the caches, or it writes faster than forming W does
// (notes/2026-11-28-w-price.md).
// Fresh pages come from the system (mmap): the allocator would hand back the last run's.
constexpr int64_t kWriteEntries = int64_t(1) << 21;  // 16 MB
constexpr int64_t kWriteAdds = int64_t(1) << 20;
constexpr int64_t kWriteStride = 4099;
constexpr int kWriteRuns = 3;

// `work` units over the fastest of `runs` timings of `run` (which answers false when it
// failed); `unmeasured` when a run failed or none took measurable time.
template <class Run>
double fastest_rate(int runs, double work, double unmeasured, Run run) {
    double fastest = INFINITY;
    for (int k = 0; k < runs; ++k) {
        const auto t0 = std::chrono::steady_clock::now();
        if (!run()) return unmeasured;
        fastest = std::min(fastest, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    return fastest > 0.0 ? work / fastest : unmeasured;
}

bool timed_writes() {
    const size_t bytes = sizeof(double) * (size_t)kWriteEntries;
    void *pages = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (pages == MAP_FAILED) return false;
    volatile double *x = static_cast<double *>(pages);  // volatile: the writes are the work
    for (int64_t i = 0; i < kWriteEntries; ++i) x[i] = 0.0;
    for (int64_t i = 0, p = 0; i < kWriteAdds; ++i, p = (p + kWriteStride) % kWriteEntries) x[p] = x[p] + 1.0;
    return munmap(pages, bytes) == 0;
}
}  // namespace

double Stopwatch::factor_rate() const {
    std::call_once(rate_once_, [this] {
        const int64_t n = kRateSize;
        std::vector<double> a((size_t)(n * n));
        for (int64_t j = 0; j < n; ++j)
            for (int64_t i = 0; i < n; ++i)
                a[(size_t)(i + n * j)] = i == j ? (double)n : 1.0 / (double)(1 + ((i * 7 + j * 13) % 17));
        const double flops = 2.0 / 3.0 * (double)n * (double)n * (double)n;
        // A failed or unmeasurably fast run: a rate no machine reaches, so that nothing is refused.
        rate_ = fastest_rate(kRateRuns, flops, 1e15, [&] {
            linalg::DenseLU lu;  // factorises its own copy of a
            if (lu.factor(n, a.data(), n) == FRIX_OK) return true;
            clear_error();
            return false;
        });
    });
    return rate_;
}

double Stopwatch::write_rate() const {
    std::call_once(write_once_, [this] {
        write_rate_ = fastest_rate(kWriteRuns, (double)(kWriteEntries + kWriteAdds), 1e15, timed_writes);
    });
    return write_rate_;
}

double Stopwatch::memory_left(double limit) const {
    std::call_once(memory_once_, [this] {
        resident_at_start_ = resident_memory();
        available_ = memory_available();
    });
    const double grown = resident_at_start_ > 0.0 ? std::max(0.0, resident_memory() - resident_at_start_) : 0.0;
    if (limit > 0.0) return limit - grown;
    if (!(available_ > 0.0)) return INFINITY;
    return available_ - resident_at_start_ - grown;
}

}  // namespace frix
