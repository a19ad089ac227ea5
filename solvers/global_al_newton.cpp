// Solver 901 (gnsn-al): the augmented Lagrangian method on the global problem, each of its
// steps a minimisation in v alone by semismooth Newton, whose linear systems are
// M + rho H J H^T: symmetric positive definite, factorised by CHOLMOD in one pattern (one
// symbolic analysis per solve). W = H^T M^-1 H is never formed.
//
// With s = mu |u_T| e_N held (the De Saxce term, updated after every outer step) the problem
// is  min_v 1/2 v'M v - f'v  subject to  g(v) = H^T v + w + s in K*, r in K the multiplier of
// the constraint. The augmented Lagrangian step from r_k:
//   v_k+1 = argmin phi(v),  phi(v) = 1/2 v'M v - f'v + 1/(2 rho) |P_K(r_k - rho g(v))|^2,
//   r_k+1 = P_K(r_k - rho g(v_k+1)).
// phi is convex, its gradient M v - f - H P_K(r_k - rho g(v)) (zero: M v = H r_k+1 + f, the
// equilibrium), its generalized Hessian M + rho H J H^T with J = dP_K block-diagonal, symmetric
// and 0 <= J <= I: Newton with Armijo's line search converges from any v, and every system is
// at least as well posed as M. A fixed point r = P_K(r - rho g) is r in K, g in K*, r'g = 0.
// A persistent solver keeps the pattern and its analysis while M and H stay.
// rho grows while the outer steps gain little: the outer rate improves with rho, and Newton
// refactorises every step anyway, so a new rho costs nothing more.
#include <algorithm>
#include <cmath>
#include <vector>

#include "solvers/first_order.hpp"
#include "solvers/global_newton.hpp"
#include "solvers/mass_plus_contacts.hpp"
#include "solvers/nsn_functions.hpp"
#include "src/error_state.hpp"
#include "src/log.hpp"
#include "src/matrix.hpp"
#include "src/measures.hpp"
#include "src/monitor.hpp"
#include "src/reduction.hpp"

namespace frix {
namespace gal {

namespace {

constexpr int kScaleSamples = 8;      // contacts whose W_aa set rho's unit
constexpr double kArmijo = 1e-4;
constexpr int kLineSearchSteps = 40;  // halvings of the Newton step at most
constexpr int kInnerSteps = 30;       // Newton steps per outer step at most
// An outer step's minimisation ends when the gradient (the equilibrium residual) is below
// this share of the force the step moved, |H (r_k+1 - r_k)|: the next multiplier is then as
// good as an exact minimiser's to first order.
constexpr double kInnerShare = 0.1;
constexpr double kSlowOuter = 0.5;    // an outer step gaining less than this ...
constexpr double kRhoGrowth = 5.0;    // ... multiplies rho by this
constexpr double kRhoMax = 1e8;       // rho at most, in units of 1 / scale
constexpr int kStallOuter = 8;        // outer steps without halving the best error: stagnated

using vec::dot;

frix_error solve(SolveContext &ctx) {
    const frix_problem &p = ctx.problem;
    const frix_options &o = ctx.options;
    frix_info &info = ctx.info;
    const Monitor monitor(ctx);
    const double tol = monitor.tolerance();
    const int64_t max_iter = monitor.max_iterations();
    const int64_t verbosity = o.i(FRIX_OPT_VERBOSITY), measure = o.i(FRIX_OPT_ERROR_MEASURE);
    const int64_t n = p.n, nc = p.nc, m = 3 * nc;
    double *r = ctx.r, *u = ctx.u, *v = ctx.v;
    // A persistent solver's next step with the same M and H keeps the pattern, its symbolic
    // analysis and rho's unit.
    Kept<KeptMassPlusContacts> kept(ctx.cache, FRIX_SOLVER_GLOBAL_AL_NEWTON);
    const linalg::FactorStats before = kept->system.stats();
    MassPlusContacts &system = kept->system;
    if (frix_error e = prepare_mass_plus_contacts(ctx, *kept, "gnsn-al", kScaleSamples)) return e;
    kept.keep();
    const double scale = kept->scale;
    double rho = o.d(FRIX_OPT_RHO) / scale;
    const double rho_max = kRhoMax / scale;

    std::vector<double> rk(r, r + m), shift(m, 0.0), y(m), z(m), J(9 * nc), S(9 * nc);
    std::vector<double> Mv(n), Hz(n), grad(n), d(n), Md(n), Htd(m), ut(m), zt(m);
    std::vector<double> best_r(r, r + m), best_v(v, v + n), fk(p.f, p.f + n), Kd(n), skew_work(n);
    // out = (M + M^T) / 2 x: M x, less M's skew part where M is not exactly symmetric.
    auto symmetric_mass = [&](const double *x, double *out) {
        matrix_gemv(*p.M, 1.0, x, 0.0, out);
        if (!system.skewed()) return;
        matrix_skew_gemv(*p.M, x, Kd.data(), skew_work.data());
        for (int64_t j = 0; j < n; ++j) out[j] -= Kd[j];
    };
    const double norm_f = std::sqrt(dot(p.f, p.f, n));
    // u = H^T v + w, the De Saxce term from it.
    auto velocities = [&](const double *vv, double *uu) {
        if (m > 0) matrix_gemv_transposed(*p.H, 1.0, vv, 0.0, uu);
        for (int64_t i = 0; i < m; ++i) uu[i] += p.w[i];
    };
    // z = P_K(r_k - rho (uu + s)) into zz, with J's blocks when asked; returns |z|^2.
    auto multiplier = [&](const double *uu, double *zz, bool jacobian) {
        double sq = 0.0;
        for (int64_t a = 0; a < nc; ++a) {
            double yy[3];
            for (int i = 0; i < 3; ++i) yy[i] = rk[3 * a + i] - rho * (uu[3 * a + i] + shift[3 * a + i]);
            double Ja[9];
            nsn::project_with_jacobian(yy, p.mu[a], zz + 3 * a, Ja);
            if (jacobian) std::copy(Ja, Ja + 9, &J[9 * a]);
            for (int i = 0; i < 3; ++i) sq += zz[3 * a + i] * zz[3 * a + i];
        }
        return sq;
    };
    double equilibrium = 0.0;

    velocities(v, u);
    de_saxce_shift(p, u, shift.data());
    double err = global_error(p, measure, r, v, u, &equilibrium), best_err = err, ref_err = err;
    int64_t outer = 0, newton_steps = 0, ls_steps = 0;
    int since_progress = 0;
    frix_status status = FRIX_STATUS_NOT_RUN;
    while (status == FRIX_STATUS_NOT_RUN) {
        if (err <= tol) {
            status = FRIX_STATUS_CONVERGED;
            break;
        }
        if (!std::isfinite(err)) {
            status = FRIX_STATUS_DIVERGED;
            break;
        }
        if (outer >= max_iter) {
            status = FRIX_STATUS_MAX_ITER;
            break;
        }
        // The outer step: minimise phi from the current v.
        velocities(v, u);
        // M's skew part K, if any, at this step's start: the step minimises phi with M's
        // symmetric part and f - K v_k, which at a fixed point is M v = f + H r.
        if (system.skewed()) {
            matrix_skew_gemv(*p.M, v, fk.data(), Kd.data());
            for (int64_t j = 0; j < n; ++j) fk[j] = p.f[j] - fk[j];
        }
        symmetric_mass(v, Mv.data());
        double zsq = multiplier(u, z.data(), true);
        for (int step = 0; step < kInnerSteps; ++step) {
            if (m > 0) matrix_gemv(*p.H, 1.0, z.data(), 0.0, Hz.data());
            for (int64_t j = 0; j < n; ++j) grad[j] = Mv[j] - fk[j] - Hz[j];
            // The force this step moved, H (z - r_k) = H z - H r_k.
            for (int64_t i = 0; i < m; ++i) y[i] = z[i] - rk[i];
            std::vector<double> &moved = d;  // scratch until the Newton direction is solved
            if (m > 0) matrix_gemv(*p.H, 1.0, y.data(), 0.0, moved.data());
            const double gnorm = std::sqrt(dot(grad.data(), grad.data(), n));
            const double eq_scale = std::max({norm_f, std::sqrt(dot(Mv.data(), Mv.data(), n)),
                                              std::sqrt(dot(Hz.data(), Hz.data(), n))});
            if (gnorm <= std::max(0.5 * tol * eq_scale, kInnerShare * std::sqrt(dot(moved.data(), moved.data(), n))))
                break;
            if (monitor.out_of_time()) {
                status = FRIX_STATUS_TIME_LIMIT;
                break;
            }
            for (int64_t k = 0; k < 9 * nc; ++k) S[k] = rho * J[k];
            if (system.factor(S.data(), monitor.budget()) != FRIX_OK) {
                status = system.refused() ? system.refused() : FRIX_STATUS_NUMERICAL_FAILURE;
                clear_error();
                break;
            }
            if (frix_error e = system.solve(grad.data(), d.data())) return e;
            for (int64_t j = 0; j < n; ++j) d[j] = -d[j];
            ++newton_steps;
            // phi along v + t d, from products computed once.
            symmetric_mass(d.data(), Md.data());
            if (m > 0) matrix_gemv_transposed(*p.H, 1.0, d.data(), 0.0, Htd.data());
            const double vMv = dot(v, Mv.data(), n), dMv = dot(d.data(), Mv.data(), n), dMd = dot(d.data(), Md.data(), n);
            const double fv = dot(fk.data(), v, n), fd = dot(fk.data(), d.data(), n);
            const double phi0 = 0.5 * vMv - fv + zsq / (2.0 * rho);
            const double slope = dot(grad.data(), d.data(), n);
            if (!(slope < 0.0)) break;  // no descent left: the minimiser to rounding
            double t = 1.0, zsq_t = 0.0;
            bool accepted = false;
            for (int k = 0; k < kLineSearchSteps; ++k, t *= 0.5) {
                for (int64_t i = 0; i < m; ++i) ut[i] = u[i] + t * Htd[i];
                zsq_t = multiplier(ut.data(), zt.data(), false);
                ++ls_steps;
                const double phit = 0.5 * (vMv + 2.0 * t * dMv + t * t * dMd) - fv - t * fd + zsq_t / (2.0 * rho);
                if (phit <= phi0 + kArmijo * t * slope) {
                    accepted = true;
                    break;
                }
            }
            if (!accepted) break;
            for (int64_t j = 0; j < n; ++j) {
                v[j] += t * d[j];
                Mv[j] += t * Md[j];
            }
            for (int64_t i = 0; i < m; ++i) u[i] = ut[i];
            zsq = multiplier(u, z.data(), true);
        }
        if (status != FRIX_STATUS_NOT_RUN) break;
        ++outer;
        const double previous = err;
        std::copy(z.begin(), z.end(), r);
        err = global_error_or_recovered(p, ctx.mass, measure, tol, r, v, u, &equilibrium);
        if (verbosity >= 2)
            log_line(&o, "gnsn-al: outer %lld rho %.3e newton %lld error %.3e equilibrium %.3e", (long long)outer,
                     rho * scale, (long long)newton_steps, err, equilibrium);
        if (err < best_err) {
            best_err = err;
            std::copy(r, r + m, best_r.begin());
            std::copy(v, v + n, best_v.begin());
        }
        if (monitor.report(outer, err)) {
            status = FRIX_STATUS_STOPPED_BY_CALLBACK;
            break;
        }
        if (err <= tol) continue;
        if (best_err < 0.5 * ref_err) {
            ref_err = best_err;
            since_progress = 0;
        } else if (++since_progress >= kStallOuter) {
            status = FRIX_STATUS_STAGNATED;
            break;
        }
        if (err > kSlowOuter * previous && rho < rho_max) rho = std::min(rho * kRhoGrowth, rho_max);
        std::copy(r, r + m, rk.begin());
        de_saxce_shift(p, u, shift.data());
    }
    if (!(err <= best_err)) {  // also when the last iterate is not finite
        std::copy(best_r.begin(), best_r.end(), r);
        std::copy(best_v.begin(), best_v.end(), v);
    }
    info.status = status;
    info.iterations = outer;
    info.newton_iterations = newton_steps;
    info.line_search_steps = ls_steps;
    Monitor::record_factorizations(info, system.stats() - before);
    if (verbosity >= 1)
        log_line(&o, "gnsn-al: %s after %lld outer steps, %lld Newton steps (rho %.3g / scale)",
                 frix_status_string(status), (long long)outer, (long long)newton_steps, rho * scale);
    return FRIX_OK;
}

const frix_option_key kExtraKeys[] = {FRIX_OPT_RHO, (frix_option_key)0};
const OptionDefault kDefaults[] = {{FRIX_OPT_MAX_ITER, 500}, {FRIX_OPT_RHO, 10.0}, {(frix_option_key)0, 0}};

}  // namespace
}  // namespace gal

const SolverEntry kGlobalAlNewtonEntry = {
    FRIX_SOLVER_GLOBAL_AL_NEWTON, "gnsn-al", nullptr,
    "Augmented Lagrangian method on the global problem itself, each outer step a minimisation "
    "in v by semismooth Newton with Armijo's line search: its linear systems are M + rho H J H^T "
    "(J the Jacobian of the projection on the cones), symmetric positive definite, factorised "
    "by CHOLMOD in one fixed pattern (one symbolic analysis per solve). W = H^T M^-1 H is never "
    "formed: for deformable bodies whose W would be dense and too large. The De Saxce term is "
    "updated after every outer step; rho, in units of the mean normal entry of W_aa over 8 sampled contacts (one solve with M "
    "each), grows 5-fold while an outer step does not halve the "
    "error. Converged means both the error and the equilibrium residual are below the "
    "tolerance. Global problems with a symmetric positive definite M only. Options: rho "
    "(the initial penalty, in units of 1 / that mean; default 10); max_iter counts outer steps.",
    gal::solve, false, true, gal::kExtraKeys, gal::kDefaults};

}  // namespace frix
