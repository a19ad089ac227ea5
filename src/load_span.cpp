#include "load_span.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>

#include "measures.hpp"
#include "vec.hpp"

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
// the largest of the solves it combines, or within kBackwardFloor (a solve exact to the last
// bit leaves 0).
constexpr double kBackwardShare = 4.0;
constexpr double kBackwardFloor = 4.0 * DBL_EPSILON;

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

double LoadSpan::take_off_span(int count, double *y, double *h) const {
    const int64_t n = n_;
    std::fill(h, h + kLoadSpan, 0.0);
    // Gram-Schmidt twice: the second pass takes what the first left to round-off.
    for (int pass = 0; pass < 2; ++pass)
        for (int j = 0; j < count; ++j) {
            const double *qj = &q_[(size_t)(j * n)];
            const double t = vec::dot(qj, y, n);
            h[j] += t;
            for (int64_t e = 0; e < n; ++e) y[e] -= t * qj[e];
        }
    return vec::norm(y, n);
}

bool LoadSpan::orthonormalise(int i) {
    const int64_t n = n_;
    const double *fi = &f_[(size_t)(i * n)];
    q_.resize((size_t)((i + 1) * n));
    double *qi = &q_[(size_t)(i * n)];
    std::copy(fi, fi + n, qi);
    double h[kLoadSpan];
    const double off = take_off_span(i, qi, h);
    if (!(off >= kNewDirection * vec::norm(fi, n)) || !std::isfinite(off)) {
        q_.resize((size_t)(i * n));
        return false;
    }
    for (int64_t e = 0; e < n; ++e) qi[e] /= off;
    for (int j = 0; j < kLoadSpan; ++j) r_[j + kLoadSpan * i] = j < i ? h[j] : j == i ? off : 0.0;
    return true;
}

void LoadSpan::forget(int i) {
    const auto n = (ptrdiff_t)n_;
    f_.erase(f_.begin() + i * n, f_.begin() + (i + 1) * n);
    x_.erase(x_.begin() + i * n, x_.begin() + (i + 1) * n);
    backward_.erase(backward_.begin() + i);
    --k_;
    q_.clear();
    for (int j = 0; j < k_; ++j)
        if (!orthonormalise(j)) {  // no longer a direction of its own: forgotten too
            forget(j);
            return;
        }
}

void LoadSpan::add(const double *f, const double *x, int64_t n) {
    if (n != n_) {
        clear();
        n_ = n;
    }
    const double f_norm = vec::norm(f, n);
    if (!(f_norm > 0.0) || !std::isfinite(f_norm) || !vec::all_finite(x, n)) return;
    // f's part off the span, its coefficients on Q into h.
    work_.assign(f, f + n);
    double h[kLoadSpan];
    double off = take_off_span(k_, work_.data(), h);
    if (!(off >= kNewDirection * f_norm) || !std::isfinite(off)) {
        // In place of the oldest load where the others and f still span as much: a trial on a
        // copy, the rare path (a combination refused).
        const LoadSpan before = *this;
        forget(0);
        const int kept = k_;
        f_.insert(f_.end(), f, f + n);
        x_.insert(x_.end(), x, x + n);
        backward_.push_back(NAN);
        ++k_;
        if (kept != before.k_ - 1 || !orthonormalise(k_ - 1)) *this = before;
        return;
    }
    if (k_ == kLoadSpan) {
        // A fifth direction: the host's loads leave the span; it starts over from f (cheaper
        // than forgetting one load and orthonormalising the others again).
        const double m_norm = m_norm_;  // M is the same
        clear();
        m_norm_ = m_norm;
        work_.assign(f, f + n);
        std::fill(h, h + kLoadSpan, 0.0);
        off = f_norm;
    }
    f_.insert(f_.end(), f, f + n);
    x_.insert(x_.end(), x, x + n);
    backward_.push_back(NAN);
    q_.resize((size_t)((k_ + 1) * n));
    double *qk = &q_[(size_t)(k_ * n)];
    for (int64_t j = 0; j < n; ++j) qk[j] = work_[(size_t)j] / off;
    for (int i = 0; i < kLoadSpan; ++i) r_[i + kLoadSpan * k_] = i < k_ ? h[i] : i == k_ ? off : 0.0;
    ++k_;
}

double LoadSpan::backward_error(const double *f, const double *x, const linalg::CscView &M) {
    const int64_t n = n_;
    if (m_norm_ < 0.0) {
        product_.assign((size_t)n, 0.0);  // row sums of |M|
        for (int64_t j = 0; j < M.cols; ++j)
            for (int64_t e = M.colptr[j]; e < M.colptr[j + 1]; ++e) product_[(size_t)M.rowind[e]] += std::fabs(M.values[e]);
        m_norm_ = max_abs(product_.data(), n);
    }
    product_.assign((size_t)n, 0.0);
    for (int64_t j = 0; j < M.cols; ++j) {
        const double xj = x[j];
        for (int64_t e = M.colptr[j]; e < M.colptr[j + 1]; ++e) product_[(size_t)M.rowind[e]] += M.values[e] * xj;
    }
    double residual = 0.0;
    for (int64_t i = 0; i < n; ++i) {
        const double d = std::fabs(f[i] - product_[(size_t)i]);
        if (!(d <= residual)) residual = d;  // a NaN stays
    }
    const double scale = m_norm_ * max_abs(x, n) + max_abs(f, n);
    const double eta = residual / scale;
    return std::isfinite(eta) ? eta : INFINITY;
}

bool LoadSpan::answer(const double *f, const linalg::CscView &M, double *x) {
    const int64_t n = n_;
    if (k_ == 0 || M.rows != n || M.cols != n) return false;
    const double f_norm = vec::norm(f, n);
    if (!(f_norm > 0.0) || !std::isfinite(f_norm)) return false;
    // g = Q^T f, and the part of f off the span, f - Q g.
    double g[kLoadSpan] = {};
    for (int i = 0; i < k_; ++i) g[i] = vec::dot(&q_[(size_t)(i * n)], f, n);
    double off = 0.0;
    for (int64_t j = 0; j < n; ++j) {
        double t = f[j];
        for (int i = 0; i < k_; ++i) t -= g[i] * q_[(size_t)(i * n + j)];
        off += t * t;
    }
    if (!(std::sqrt(off) <= kSpanFit * f_norm)) return false;
    // f = F c: c = R^-1 Q^T f, then once more on the residual f - F c, taken against the kept
    // loads themselves: sums of n products leave c off by about sqrt(n) units of round-off,
    // and Q^T Q and Q R by as much; after the second pass c is exact to round-off.
    double c[kLoadSpan] = {};
    const auto solve_r = [this](double *rhs) {
        for (int i = k_ - 1; i >= 0; --i) {
            for (int j = i + 1; j < k_; ++j) rhs[i] -= r_[i + kLoadSpan * j] * rhs[j];
            rhs[i] /= r_[i + kLoadSpan * i];
        }
    };
    std::copy(g, g + k_, c);
    solve_r(c);
    work_.assign(f, f + n);
    for (int i = 0; i < k_; ++i) {
        const double *fi = &f_[(size_t)(i * n)];
        for (int64_t j = 0; j < n; ++j) work_[(size_t)j] -= c[i] * fi[j];
    }
    double dc[kLoadSpan] = {};
    for (int i = 0; i < k_; ++i) dc[i] = vec::dot(&q_[(size_t)(i * n)], work_.data(), n);
    solve_r(dc);
    double growth = 0.0;
    for (int i = 0; i < k_; ++i) {
        c[i] += dc[i];
        growth += std::fabs(c[i]) * vec::norm(&f_[(size_t)(i * n)], n);
    }
    if (!(growth <= kSpanGrowth * f_norm)) return false;
    // The solves combined, their own backward errors measured once each.
    double kept = 0.0;
    for (int i = 0; i < k_; ++i) {
        if (c[i] == 0.0) continue;
        if (std::isnan(backward_[(size_t)i]))
            backward_[(size_t)i] = backward_error(&f_[(size_t)(i * n)], &x_[(size_t)(i * n)], M);
        kept = std::max(kept, backward_[(size_t)i]);
    }
    if (!std::isfinite(kept)) return false;
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
