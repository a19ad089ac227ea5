// Stopwatch::factor_rate: dense LUs timed once per solve that needs it; memory_left.
#include <algorithm>
#include <chrono>
#include <cmath>
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
}  // namespace

double Stopwatch::factor_rate() const {
    std::call_once(rate_once_, [this] {
        const int64_t n = kRateSize;
        std::vector<double> a((size_t)(n * n));
        for (int64_t j = 0; j < n; ++j)
            for (int64_t i = 0; i < n; ++i)
                a[(size_t)(i + n * j)] = i == j ? (double)n : 1.0 / (double)(1 + ((i * 7 + j * 13) % 17));
        double fastest = INFINITY;
        bool failed = false;
        for (int run = 0; run < kRateRuns && !failed; ++run) {
            linalg::DenseLU lu;  // factorises its own copy of a
            const auto t0 = std::chrono::steady_clock::now();
            failed = lu.factor(n, a.data(), n) != FRIX_OK;
            fastest = std::min(fastest, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        }
        const double flops = 2.0 / 3.0 * (double)n * (double)n * (double)n;
        // A failed or unmeasurably fast run: a rate no machine reaches, so that nothing is refused.
        rate_ = !failed && fastest > 0.0 ? flops / fastest : 1e15;
        if (failed) clear_error();
    });
    return rate_;
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
