#include "solvers/kit/anderson_mixing.hpp"

#include <algorithm>
#include <cmath>

#include "src/coulomb.hpp"

namespace frix {
namespace nsgs {

// gamma minimising |f_k - sum_j gamma_j (f_{j+1} - f_j)| over `columns` differences, by
// modified Gram-Schmidt; a difference within rounding of the span of the earlier ones is left
// out (gamma_j = 0). Returns the differences kept.
int64_t AndersonMixing::fit(int64_t columns) {
    const size_t c = (size_t)columns, m = m_;
    r_fit_.assign(c * c, 0.0);
    gamma_.assign(c, 0.0);
    kept_column_.assign(c, 0);
    std::vector<double> &rhs = rhs_;
    rhs.assign(c, 0.0);
    const double *fk = f_.data() + slot(count_ - 1) * m;
    int64_t kept = 0;
    for (size_t j = 0; j < c; ++j) {
        double *q = columns_.data() + j * m;
        const double *a = f_.data() + slot((int64_t)j + 1) * m, *b = f_.data() + slot((int64_t)j) * m;
        double before = 0.0;
        for (size_t i = 0; i < m; ++i) {
            q[i] = a[i] - b[i];
            before += q[i] * q[i];
        }
        for (size_t l = 0; l < j; ++l) {
            if (!kept_column_[l]) continue;
            const double *ql = columns_.data() + l * m;
            double d = 0.0;
            for (size_t i = 0; i < m; ++i) d += ql[i] * q[i];
            r_fit_[l * c + j] = d;
            for (size_t i = 0; i < m; ++i) q[i] -= d * ql[i];
        }
        double after = 0.0;
        for (size_t i = 0; i < m; ++i) after += q[i] * q[i];
        if (!(after > 1e-20 * before) || !(after > 0.0)) continue;
        const double norm = std::sqrt(after);
        for (size_t i = 0; i < m; ++i) q[i] /= norm;
        r_fit_[j * c + j] = norm;
        double d = 0.0;
        for (size_t i = 0; i < m; ++i) d += q[i] * fk[i];
        rhs[j] = d;
        kept_column_[j] = 1;
        ++kept;
    }
    for (size_t j = c; j-- > 0;) {
        if (!kept_column_[j]) continue;
        double t = rhs[j];
        for (size_t l = j + 1; l < c; ++l)
            if (kept_column_[l]) t -= r_fit_[j * c + l] * gamma_[l];
        gamma_[j] = t / r_fit_[j * c + j];
    }
    return kept;
}

void AndersonMixing::shift_states(const std::vector<double> &correction) {
    const size_t n = correction.size();
    if (n == 0 || k_.size() != ((size_t)depth_ + 1) * n) return;
    for (int64_t i = 0; i < count_; ++i) {
        double *k = k_.data() + slot(i) * n;
        for (size_t j = 0; j < n; ++j) k[j] += correction[j];
    }
}

void AndersonMixing::after_sweep(double *r, const double *mu, Workspace &ws, SweepForm &form, double *u) {
    if (!on()) return;
    const SweepForm::AffineState state = form.affine_state(u);
    if (!state.combines) {
        off();
        return;
    }
    const size_t m = m_, slots = (size_t)depth_ + 1;
    if (k_.size() != slots * state.size) k_.resize(slots * state.size);
    double f2 = 0.0;
    for (size_t i = 0; i < m; ++i) f2 += (r[i] - x_[i]) * (r[i] - x_[i]);
    // A step that grew: the older sweeps describe another map.
    if (count_ > 0 && f2 > last_f2_) count_ = 0;
    last_f2_ = f2;
    newest_ = (newest_ + 1) % (int64_t)slots;
    count_ = std::min<int64_t>(count_ + 1, (int64_t)slots);
    {
        double *g = g_.data() + (size_t)newest_ * m, *f = f_.data() + (size_t)newest_ * m;
        for (size_t i = 0; i < m; ++i) {
            g[i] = r[i];
            f[i] = r[i] - x_[i];
        }
        if (state.size) std::copy(state.values, state.values + state.size, k_.data() + (size_t)newest_ * state.size);
    }
    if (count_ < 2 || fit(count_ - 1) == 0) {
        std::copy(r, r + m, x_.begin());
        return;
    }
    // line = g_k - sum_j gamma_j (g_{j+1} - g_j); the affine state alike.
    std::copy(r, r + m, line_.begin());
    for (int64_t j = 0; j + 1 < count_; ++j) {
        const double w = gamma_[(size_t)j];
        if (w == 0.0) continue;
        const double *a = g_.data() + slot(j + 1) * m, *b = g_.data() + slot(j) * m;
        for (size_t i = 0; i < m; ++i) line_[i] -= w * (a[i] - b[i]);
        const double *ka = k_.data() + slot(j + 1) * state.size, *kb = k_.data() + slot(j) * state.size;
        for (size_t i = 0; i < state.size; ++i) state.values[i] -= w * (ka[i] - kb[i]);
    }
    std::copy(line_.begin(), line_.end(), r);
    coulomb::project_on_cones(r, mu, (int64_t)(m / 3));
    push_projection(form, ws, line_.data(), r, m, u);
    std::copy(r, r + m, x_.begin());
}

}  // namespace nsgs
}  // namespace frix
