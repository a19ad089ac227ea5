// Small vector helpers shared by the core and the solvers: plain sums in index order, so that
// every caller gets the same bits. No scaling against overflow: norm2 (measures.hpp) for that.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

namespace frix::vec {

// Whether every x_i is finite (no NaN, no Inf).
inline bool all_finite(const double *x, int64_t n) {
    for (int64_t i = 0; i < n; ++i)
        if (!std::isfinite(x[i])) return false;
    return true;
}

// Whether every x_i is 0 (a cold start).
inline bool all_zero(const double *x, int64_t n) {
    for (int64_t i = 0; i < n; ++i)
        if (x[i] != 0.0) return false;
    return true;
}

inline double dot(const double *x, const double *y, int64_t n) {
    double s = 0.0;
    for (int64_t i = 0; i < n; ++i) s += x[i] * y[i];
    return s;
}
inline double dot(const std::vector<double> &x, const std::vector<double> &y) {
    return dot(x.data(), y.data(), (int64_t)x.size());
}
inline double norm(const double *x, int64_t n) { return std::sqrt(dot(x, x, n)); }
// |x - y|
inline double distance(const double *x, const double *y, int64_t n) {
    double s = 0.0;
    for (int64_t i = 0; i < n; ++i) s += (x[i] - y[i]) * (x[i] - y[i]);
    return std::sqrt(s);
}

// sqrt(x^2 + y^2) without hypot's overflow care: inputs here are finite physical values, and
// hypot costs as much as the rest of a local solve.
inline double norm2d(double x, double y) { return std::sqrt(x * x + y * y); }
inline double norm3(const double *x) { return std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]); }

// y(3) = B(3x3 column-major) x(3)
inline void gemv3(const double *B, const double *x, double *y) {
    y[0] = B[0] * x[0] + B[3] * x[1] + B[6] * x[2];
    y[1] = B[1] * x[0] + B[4] * x[1] + B[7] * x[2];
    y[2] = B[2] * x[0] + B[5] * x[1] + B[8] * x[2];
}

}  // namespace frix::vec
