// Stopwatch::factor_rate: a dense LU timed once per solve that needs it; memory_left.
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
// The timed LU: n = 256 (11 million flops, a few milliseconds), diagonally dominant so that
// pivoting does no extra work.
constexpr int64_t kRateSize = 256;
}  // namespace

double Stopwatch::factor_rate() const {
    std::call_once(rate_once_, [this] {
        const int64_t n = kRateSize;
        std::vector<double> a((size_t)(n * n));
        for (int64_t j = 0; j < n; ++j)
            for (int64_t i = 0; i < n; ++i)
                a[(size_t)(i + n * j)] = i == j ? (double)n : 1.0 / (double)(1 + ((i * 7 + j * 13) % 17));
        linalg::DenseLU lu;
        const auto t0 = std::chrono::steady_clock::now();
        const frix_error e = lu.factor(n, a.data(), n);
        const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const double flops = 2.0 / 3.0 * (double)n * (double)n * (double)n;
        // A failed or unmeasurably fast run: a rate no machine reaches, so that nothing is refused.
        rate_ = e == FRIX_OK && s > 0.0 ? flops / s : 1e15;
        if (e != FRIX_OK) clear_error();
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
