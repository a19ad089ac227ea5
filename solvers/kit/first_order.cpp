#include "solvers/kit/first_order.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>

#include "solvers/kit/local3x3.hpp"
#include "src/coulomb.hpp"
#include "src/matrix.hpp"

namespace frix::first_order {

void de_saxce_map(const frix_problem &p, const double *r, double *u, double *F) {
    const frix_matrix &W = *p.W;
    for (int64_t a = 0; a < p.nc; ++a) {
        double t[3];
        block_row_product(W, a, r, t);
        const double *qa = p.q + 3 * a;
        double *ua = u + 3 * a, *Fa = F + 3 * a;
        ua[0] = t[0] + qa[0];
        ua[1] = t[1] + qa[1];
        ua[2] = t[2] + qa[2];
        Fa[0] = ua[0] + p.mu[a] * std::sqrt(ua[1] * ua[1] + ua[2] * ua[2]);
        Fa[1] = ua[1];
        Fa[2] = ua[2];
    }
}

void project_on_cones(const frix_problem &p, double *r) { coulomb::project_on_cones(r, p.mu, p.nc); }

double contact_diagonal_norm(const frix_problem &p, int64_t a) {
    const frix_matrix &W = *p.W;
    const int64_t d = W.diag_index[a];
    if (d < 0) return NAN;
    local::Contact c;
    local::contact_setup(&W.block_val[9 * d], p.mu[a], c);
    return c.rho0 > 0.0 ? 1.0 / c.rho0 : NAN;
}

void diagonal_scales(const frix_problem &p, double *max_norm, double *mean_norm) {
    double mx = 0.0, sum = 0.0;
    int64_t counted = 0;
    for (int64_t a = 0; a < p.nc; ++a) {
        const double n = contact_diagonal_norm(p, a);
        if (std::isnan(n)) continue;
        mx = std::max(mx, n);
        sum += n;
        ++counted;
    }
    if (!(mx > 0.0) || !std::isfinite(mx)) mx = 1.0;
    *max_norm = mx;
    *mean_norm = counted > 0 && sum > 0.0 && std::isfinite(sum) ? sum / (double)counted : mx;
}

Loop::Loop(SolveContext &c, const char *solver_name)
    : p(c.problem),
      o(c.options),
      ctx(c),
      name(solver_name),
      tol(Monitor(c).tolerance()),
      max_iter(Monitor(c).max_iterations()),
      verbosity(c.options.i(FRIX_OPT_VERBOSITY)),
      measure(c.options.i(FRIX_OPT_ERROR_MEASURE)),
      norm_q(vec::norm(c.problem.q, 3 * c.problem.nc)),
      m(3 * c.problem.nc) {}

double Loop::scale(double norm_r, double norm_u) const {
    const double s = measure == FRIX_MEASURE_Q_RELATIVE ? norm_q
                     : measure == FRIX_MEASURE_RELATIVE ? std::max({norm_q, norm_r, norm_u})
                                                        : std::max(norm_q, norm_u);
    return s > DBL_EPSILON ? s : 1.0;
}

void RestartedNesterov::reset(const double *x, const double *y) {
    const size_t m = xh_.size();
    std::copy(x, x + m, xh_.begin());
    std::copy(y, y + m, yh_.begin());
    std::copy(x, x + m, x_old_.begin());
    std::copy(y, y + m, y_old_.begin());
    alpha_ = 1.0;
    c_prev_ = INFINITY;
}

void RestartedNesterov::advance(double comb, const double *x, const double *y) {
    const size_t m = xh_.size();
    if (!on_) {
        std::copy(x, x + m, xh_.begin());
        std::copy(y, y + m, yh_.begin());
        return;
    }
    if (!(comb < kRestartEta * c_prev_)) {  // the momentum is dropped
        reset(x, y);
        c_prev_ = comb;
        ++restarts_;
        return;
    }
    const double alpha_next = 0.5 * (1.0 + std::sqrt(1.0 + 4.0 * alpha_ * alpha_));
    const double beta = (alpha_ - 1.0) / alpha_next;
    for (size_t k = 0; k < m; ++k) {
        xh_[k] = x[k] + beta * (x[k] - x_old_[k]);
        yh_[k] = y[k] + beta * (y[k] - y_old_[k]);
    }
    alpha_ = alpha_next;
    c_prev_ = comb;
    std::copy(x, x + m, x_old_.begin());
    std::copy(y, y + m, y_old_.begin());
}

}  // namespace frix::first_order
