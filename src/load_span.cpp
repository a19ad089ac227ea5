#include "load_span.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>

namespace frix {

namespace {

// A load lies in the span where its part off it is within this share of it (2-norms): loads a
// host forms as combinations of a few are off by round-off, far below it; the backward error
// then decides.
constexpr double kSpanFit = 1e-12;
// A combination sum c_i f_i with sum |c_i| |f_i| above this many times |f| cancels large terms
// (loads nearly parallel, a point far along their line): the round-off of the answers grows by
// as much, and the load is solved.
constexpr double kSpanGrowth = 16.0;
// A solved load adds a direction to the span only where its part off it is at least this share
// of it: a direction found by cancellation would carry its round-off into every combination.
constexpr double kNewDirection = 1e-6;
// A combination is as accurate as a solve where its backward error is within this many times
// the kept solves' largest, or within kBackwardFloor (a solve exact to the last bit leaves 0).
constexpr double kBackwardShare = 4.0;
constexpr double kBackwardFloor = 4.0 * DBL_EPSILON;

// a . b in twice the working precision (Ogita, Rump and Oishi's Dot2: each product's and
// each sum's round-off carried along). A plain sum over n terms is off by about sqrt(n) units
// of round-off, and a combination's coefficients taken from it leave a load's residual that
// much above a solve's (1e-14 of it at 6e4 dofs).
double dot(const double *a, const double *b, int64_t n) {
    double s = 0.0, err = 0.0;
    for (int64_t i = 0; i < n; ++i) {
        const double p = a[i] * b[i], pe = std::fma(a[i], b[i], -p);
        const double t = s + p, z = t - s, se = (s - (t - z)) + (p - z);
        s = t;
        err += pe + se;
    }
    return s + err;
}

double max_abs(const double *a, int64_t n) {
    double m = 0.0;
    for (int64_t i = 0; i < n; ++i) m = std::max(m, std::fabs(a[i]));
    return m;
}

}  // namespace

void LoadSpan::clear() {
    k_ = 0;
    f_.clear();
    x_.clear();
    q_.clear();
    backward_.clear();
    std::fill(r_, r_ + kLoadSpan * kLoadSpan, 0.0);
    m_norm_ = -1.0;
}

void LoadSpan::forget(int i) {
    const size_t n = (size_t)n_;
    f_.erase(f_.begin() + (ptrdiff_t)(i * n), f_.begin() + (ptrdiff_t)((i + 1) * n));
    x_.erase(x_.begin() + (ptrdiff_t)(i * n), x_.begin() + (ptrdiff_t)((i + 1) * n));
    backward_.erase(backward_.begin() + i);
    --k_;
}

void LoadSpan::orthonormalise() {
    const int64_t n = n_;
    std::fill(r_, r_ + kLoadSpan * kLoadSpan, 0.0);
    q_.resize((size_t)(k_ * n));
    for (int i = 0; i < k_;) {
        const double *fi = &f_[(size_t)(i * n)];
        double *qi = &q_[(size_t)(i * n)];
        std::copy(fi, fi + n, qi);
        double h[kLoadSpan] = {};
        // Gram-Schmidt twice: the second pass takes what the first left to round-off.
        for (int pass = 0; pass < 2; ++pass)
            for (int j = 0; j < i; ++j) {
                const double *qj = &q_[(size_t)(j * n)];
                const double t = dot(qj, qi, n);
                h[j] += t;
                for (int64_t e = 0; e < n; ++e) qi[e] -= t * qj[e];
            }
        const double off = std::sqrt(dot(qi, qi, n)), f_norm = std::sqrt(dot(fi, fi, n));
        if (!(off >= kNewDirection * f_norm) || !std::isfinite(off)) {
            forget(i);  // no new direction: the loads after it move down
            q_.resize((size_t)(k_ * n));
            continue;
        }
        for (int64_t e = 0; e < n; ++e) qi[e] /= off;
        for (int j = 0; j < i; ++j) r_[j + kLoadSpan * i] = h[j];
        r_[i + kLoadSpan * i] = off;
        ++i;
    }
}

void LoadSpan::add(const double *f, const double *x, int64_t n) {
    if (n != n_) {
        clear();
        n_ = n;
    }
    const double f_norm = std::sqrt(dot(f, f, n));
    if (!(f_norm > 0.0) || !std::isfinite(f_norm)) return;
    // f's part off the span.
    work_.assign(f, f + n);
    for (int pass = 0; pass < 2; ++pass)
        for (int i = 0; i < k_; ++i) {
            const double *qi = &q_[(size_t)(i * n)];
            const double t = dot(qi, work_.data(), n);
            for (int64_t j = 0; j < n; ++j) work_[(size_t)j] -= t * qi[j];
        }
    const bool new_direction = std::sqrt(dot(work_.data(), work_.data(), n)) >= kNewDirection * f_norm;
    if (k_ > 0 && (!new_direction || k_ == kLoadSpan)) forget(0);
    f_.insert(f_.end(), f, f + n);
    x_.insert(x_.end(), x, x + n);
    backward_.push_back(NAN);
    ++k_;
    orthonormalise();
}

double LoadSpan::backward_error(const double *f, const double *x, const linalg::CscView &M) {
    const int64_t n = n_;
    std::vector<double> y((size_t)n, 0.0);
    if (m_norm_ < 0.0) {
        std::vector<double> row_sum((size_t)n, 0.0);
        for (int64_t j = 0; j < M.cols; ++j)
            for (int64_t e = M.colptr[j]; e < M.colptr[j + 1]; ++e) row_sum[(size_t)M.rowind[e]] += std::fabs(M.values[e]);
        m_norm_ = max_abs(row_sum.data(), n);
    }
    for (int64_t j = 0; j < M.cols; ++j) {
        const double xj = x[j];
        for (int64_t e = M.colptr[j]; e < M.colptr[j + 1]; ++e) y[(size_t)M.rowind[e]] += M.values[e] * xj;
    }
    double residual = 0.0;
    for (int64_t i = 0; i < n; ++i) residual = std::max(residual, std::fabs(f[i] - y[(size_t)i]));
    const double scale = m_norm_ * max_abs(x, n) + max_abs(f, n);
    if (!(scale > 0.0)) return residual == 0.0 ? 0.0 : INFINITY;
    const double eta = residual / scale;
    return std::isfinite(eta) ? eta : INFINITY;
}

bool LoadSpan::answer(const double *f, const linalg::CscView &M, double *x) {
    const int64_t n = n_;
    if (k_ == 0 || M.rows != n || M.cols != n) return false;
    const double f_norm = std::sqrt(dot(f, f, n));
    if (!(f_norm > 0.0) || !std::isfinite(f_norm)) return false;
    // g = Q^T f, and the part of f off the span, f - Q g.
    double g[kLoadSpan] = {};
    for (int i = 0; i < k_; ++i) g[i] = dot(&q_[(size_t)(i * n)], f, n);
    double off = 0.0;
    for (int64_t j = 0; j < n; ++j) {
        double t = f[j];
        for (int i = 0; i < k_; ++i) t -= g[i] * q_[(size_t)(i * n + j)];
        off += t * t;
    }
    if (!(std::sqrt(off) <= kSpanFit * f_norm)) return false;
    // f = F c: c = R^-1 g; the loads' norms are R's columns'.
    double c[kLoadSpan] = {}, growth = 0.0;
    for (int i = k_ - 1; i >= 0; --i) {
        double t = g[i];
        for (int j = i + 1; j < k_; ++j) t -= r_[i + kLoadSpan * j] * c[j];
        c[i] = t / r_[i + kLoadSpan * i];
    }
    for (int i = 0; i < k_; ++i) {
        double column = 0.0;
        for (int j = 0; j <= i; ++j) column += r_[j + kLoadSpan * i] * r_[j + kLoadSpan * i];
        growth += std::fabs(c[i]) * std::sqrt(column);
    }
    if (!(growth <= kSpanGrowth * f_norm)) return false;
    // The kept solves' own backward errors, once.
    double kept = 0.0;
    for (int i = 0; i < k_; ++i) {
        if (std::isnan(backward_[(size_t)i]))
            backward_[(size_t)i] = backward_error(&f_[(size_t)(i * n)], &x_[(size_t)(i * n)], M);
        kept = std::max(kept, backward_[(size_t)i]);
    }
    work_.assign((size_t)n, 0.0);
    for (int i = 0; i < k_; ++i) {
        const double *xi = &x_[(size_t)(i * n)];
        for (int64_t j = 0; j < n; ++j) work_[(size_t)j] += c[i] * xi[j];
    }
    const double eta = backward_error(f, work_.data(), M);
    if (!(eta <= std::max(kBackwardShare * kept, kBackwardFloor))) return false;
    std::copy(work_.begin(), work_.end(), x);
    return true;
}

}  // namespace frix
