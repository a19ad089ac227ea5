// Solver 613 (gadmm): ADMM on the global problem itself (Siconos' GFC3D_ADMM), W never formed.
// With s = mu |u_T| e_N (the De Saxce term, updated every iteration) the problem is
//   min_v 1/2 v'M v - f'v  subject to  xi = H^T v + w + s,  xi in K*,
// r in K the multiplier of the splitting. One iteration, with (r^, xi^) Nesterov's
// extrapolations of (r, xi), restarted whenever the combined residual does not decrease:
//   (M + rho H H^T) v = f + H (r^ + rho (xi^ - w - s))
//   g = H^T v + w + s,  r = P_K(r^ - rho g),  xi = g - (r^ - r) / rho  (= P_K*(g - r^ / rho))
// so that M v = f + H r + rho H (xi - xi^): the equilibrium residual is the dual residual.
// M + rho H H^T is symmetric positive definite (M is): CHOLMOD factorises it once per value
// of rho, one symbolic analysis for all. rho, in units of the mean normal entry of W_aa over a
// few sampled contacts, follows the residual balance (the ratio of the relative primal and dual
// residuals), checked every kBalancePeriod iterations and changed only by a factor >= 5.
#include <algorithm>
#include <cmath>
#include <vector>

#include "solvers/first_order.hpp"
#include "solvers/global_newton.hpp"
#include "solvers/mass_plus_contacts.hpp"
#include "src/coulomb.hpp"
#include "src/error_state.hpp"
#include "src/log.hpp"
#include "src/matrix.hpp"
#include "src/measures.hpp"
#include "src/monitor.hpp"
#include "src/reduction.hpp"

namespace frix {
namespace gadmm {

namespace {

constexpr int kScaleSamples = 8;          // contacts whose W_aa set rho's unit
constexpr double kRestartEta = 0.999;     // Nesterov restart threshold
constexpr int64_t kBalancePeriod = 25;
constexpr double kBalanceFactor = 5.0;    // rho changes only by this factor or more
constexpr double kRhoMin = 1e-6, kRhoMax = 1e6;  // in units of 1 / scale
constexpr int64_t kFullCheckPeriod = 32;

using fo::dot;

frix_error solve(SolveContext &ctx) {
    const frix_problem &p = ctx.problem;
    const frix_options &o = ctx.options;
    frix_info &info = ctx.info;
    const Monitor monitor(ctx);
    const double tol = monitor.tolerance();
    const int64_t max_iter = monitor.max_iterations();
    const int64_t verbosity = o.i(FRIX_OPT_VERBOSITY), measure = o.i(FRIX_OPT_ERROR_MEASURE);
    const bool adaptive = o.i(FRIX_OPT_RHO_ADAPTIVE) != 0, accelerate = o.i(FRIX_OPT_ACCELERATION) != 0;
    const int64_t n = p.n, nc = p.nc, m = 3 * nc;
    double *r = ctx.r, *u = ctx.u, *v = ctx.v;

    // A persistent solver's next step with the same M and H starts from the last step's
    // factorisation and its rho: a time-stepping host pays the factorisation once.
    Kept<KeptMassPlusContacts> kept(ctx.cache, FRIX_SOLVER_GLOBAL_ADMM);
    const linalg::FactorStats before = kept->system.stats();
    MassPlusContacts &system = kept->system;
    if (frix_error e = prepare_mass_plus_contacts(ctx, *kept, "gadmm", kScaleSamples)) return e;
    const double scale = kept->scale;
    double rho = std::isfinite(kept->factored_rho) ? kept->factored_rho : o.d(FRIX_OPT_RHO) / scale;
    std::vector<double> S(9 * nc, 0.0);
    auto factor = [&]() {
        if (rho == kept->factored_rho) return true;
        kept->factored_rho = NAN;
        for (int64_t a = 0; a < nc; ++a) S[9 * a] = S[9 * a + 4] = S[9 * a + 8] = rho;
        const frix_error e = system.factor(S.data(), monitor.budget());
        if (e) clear_error();
        else kept->factored_rho = rho;
        return e == FRIX_OK;
    };
    kept.keep();

    std::vector<double> shift(m, 0.0), xi(m), rh(r, r + m), xih(m), r_old(r, r + m), xi_old(m);
    std::vector<double> rhs(n), Hx(m), dxi(m), Hdxi(n), Hr(n), kv(n), work(n);
    double equilibrium = 0.0;
    auto checked_error = [&]() { return global_error_or_recovered(p, ctx.mass, measure, tol, r, v, u, &equilibrium); };
    // The start: u from the driver's v (M v = H r + f), xi = P_K*(u + s) = x + P_K(-x).
    double err = global_error(p, measure, r, v, u, &equilibrium);
    de_saxce_shift(p, u, shift.data());
    for (int64_t a = 0; a < nc; ++a) {
        double *x = &xi[3 * a], neg[3];
        for (int i = 0; i < 3; ++i) x[i] = u[3 * a + i] + shift[3 * a + i], neg[i] = -x[i];
        coulomb::project_on_cone(neg, p.mu[a]);
        for (int i = 0; i < 3; ++i) x[i] += neg[i];
    }
    xih = xi;
    xi_old = xi;
    const double norm_f = std::sqrt(dot(p.f, p.f, n));

    frix_status status = err <= tol ? FRIX_STATUS_CONVERGED : FRIX_STATUS_NOT_RUN;
    if (status == FRIX_STATUS_NOT_RUN && !factor())
        status = system.refused() ? system.refused() : FRIX_STATUS_NUMERICAL_FAILURE;
    double alpha = 1.0, c_prev = INFINITY, tol_light = tol;
    int64_t it = 0, restarts = 0, changes = 0, since_change = 0;
    while (status == FRIX_STATUS_NOT_RUN) {
        ++it;
        ++since_change;
        for (int64_t i = 0; i < m; ++i) Hx[i] = rh[i] + rho * (xih[i] - p.w[i] - shift[i]);
        std::copy(p.f, p.f + n, rhs.begin());
        if (m > 0) matrix_gemv(*p.H, 1.0, Hx.data(), 1.0, rhs.data());
        // M's skew part K, if any, at the previous v: exact at the fixed point.
        if (system.skewed()) {
            matrix_skew_gemv(*p.M, v, kv.data(), work.data());
            for (int64_t j = 0; j < n; ++j) rhs[j] -= kv[j];
        }
        if (frix_error e = system.solve(rhs.data(), v)) return e;
        if (m > 0) matrix_gemv_transposed(*p.H, 1.0, v, 0.0, u);
        double prim2 = 0.0, dual_xi2 = 0.0, comb = 0.0, g2 = 0.0, r2 = 0.0;
        for (int64_t a = 0; a < nc; ++a) {
            double g[3];
            for (int i = 0; i < 3; ++i) {
                const int64_t k = 3 * a + i;
                u[k] += p.w[k];
                g[i] = u[k] + shift[k];
                r[k] = rh[k] - rho * g[i];
            }
            coulomb::project_on_cone(&r[3 * a], p.mu[a]);
            for (int i = 0; i < 3; ++i) {
                const int64_t k = 3 * a + i;
                xi[k] = g[i] - (rh[k] - r[k]) / rho;
                dxi[k] = xi[k] - xih[k];
                prim2 += (g[i] - xi[k]) * (g[i] - xi[k]);
                dual_xi2 += dxi[k] * dxi[k];
                comb += (r[k] - rh[k]) * (r[k] - rh[k]) / rho + rho * dxi[k] * dxi[k];
                g2 += g[i] * g[i];
                r2 += r[k] * r[k];
            }
        }
        de_saxce_shift(p, u, shift.data());
        if (!std::isfinite(prim2 + dual_xi2 + g2 + r2)) {
            status = FRIX_STATUS_DIVERGED;
            break;
        }
        // Relative residuals: primal against |g|, dual (the equilibrium residual rho H dxi)
        // against max(|f|, |H r|), as the equilibrium measure.
        if (m > 0) {
            matrix_gemv(*p.H, rho, dxi.data(), 0.0, Hdxi.data());
            matrix_gemv(*p.H, 1.0, r, 0.0, Hr.data());
        }
        const double prim = std::sqrt(prim2) / std::max(std::sqrt(g2), 1e-300);
        const double dual = std::sqrt(dot(Hdxi.data(), Hdxi.data(), n)) /
                            std::max({norm_f, std::sqrt(dot(Hr.data(), Hr.data(), n)), 1e-300});
        const double light = std::max(prim, dual);

        if (!accelerate) {
            rh.assign(r, r + m);
            xih = xi;
        } else if (comb < kRestartEta * c_prev) {
            const double alpha_next = 0.5 * (1.0 + std::sqrt(1.0 + 4.0 * alpha * alpha));
            const double beta = (alpha - 1.0) / alpha_next;
            for (int64_t k = 0; k < m; ++k) {
                rh[k] = r[k] + beta * (r[k] - r_old[k]);
                xih[k] = xi[k] + beta * (xi[k] - xi_old[k]);
            }
            alpha = alpha_next;
            c_prev = comb;
            r_old.assign(r, r + m);
            xi_old = xi;
        } else {
            alpha = 1.0;
            rh.assign(r, r + m);
            xih = xi;
            r_old.assign(r, r + m);
            xi_old = xi;
            c_prev = comb;
            ++restarts;
        }

        double estimate = light;
        bool checked = false;
        if (light <= tol_light || it % kFullCheckPeriod == 0) {
            err = checked_error();
            checked = true;
            estimate = err;
            if (err <= tol) status = FRIX_STATUS_CONVERGED;
            else if (!std::isfinite(err)) status = FRIX_STATUS_DIVERGED;
            else if (light > 0.0) tol_light = std::min(tol, light / err * tol);
        }
        if (verbosity >= 2 || (verbosity >= 1 && checked))
            log_line(&o, "gadmm: iteration %lld rho %.3e primal %.3e dual %.3e%s%.3e", (long long)it, rho * scale,
                     prim, dual, checked ? " full " : " tol_light ", checked ? err : tol_light);
        if (status != FRIX_STATUS_NOT_RUN) break;
        if (monitor.report(it, estimate)) status = FRIX_STATUS_STOPPED_BY_CALLBACK;
        else if (monitor.out_of_time()) status = FRIX_STATUS_TIME_LIMIT;
        else if (it >= max_iter) status = FRIX_STATUS_MAX_ITER;
        if (status != FRIX_STATUS_NOT_RUN) break;

        // Residual balancing: rho <- rho sqrt(primal / dual) when that changes it 5-fold.
        if (adaptive && since_change >= kBalancePeriod && dual > 0.0 && prim > 0.0) {
            const double target = std::clamp(rho * std::sqrt(prim / dual), kRhoMin / scale, kRhoMax / scale);
            if (target > kBalanceFactor * rho || target * kBalanceFactor < rho) {
                rho = target;
                alpha = 1.0;
                c_prev = INFINITY;
                rh.assign(r, r + m);
                xih = xi;
                r_old.assign(r, r + m);
                xi_old = xi;
                since_change = 0;
                ++changes;
                if (!factor()) status = system.refused() ? system.refused() : FRIX_STATUS_NUMERICAL_FAILURE;
            }
        }
    }
    // The last (r, v): r is in K, and v the velocity of the last linear solve.
    info.status = status;
    info.iterations = it;
    Monitor::record_factorizations(info, system.stats() - before);
    if (verbosity >= 1)
        log_line(&o, "gadmm: %s after %lld iterations (%lld rho changes, %lld restarts)", frix_status_string(status),
                 (long long)it, (long long)changes, (long long)restarts);
    return FRIX_OK;
}

const frix_option_key kExtraKeys[] = {FRIX_OPT_RHO, FRIX_OPT_RHO_ADAPTIVE, FRIX_OPT_ACCELERATION, (frix_option_key)0};
const OptionDefault kDefaults[] = {{FRIX_OPT_MAX_ITER, 100000},
                                   {FRIX_OPT_RHO, 1.0},
                                   {FRIX_OPT_RHO_ADAPTIVE, 1},
                                   {FRIX_OPT_ACCELERATION, 1},
                                   {(frix_option_key)0, 0}};

}  // namespace
}  // namespace gadmm

const SolverEntry kGlobalAdmmEntry = {
    FRIX_SOLVER_GLOBAL_ADMM, "gadmm", "GLOBAL_FRICTION_3D_ADMM",
    "ADMM on the global problem itself (Siconos' GFC3D_ADMM): the splitting xi = H^T v + w + s, "
    "xi in the dual cones, r the multiplier; one solve with M + rho H H^T and one projection per "
    "iteration, the De Saxce term s = mu |u_T| e_N updated every iteration, Nesterov "
    "acceleration with restart, rho balanced between the relative primal and dual residuals "
    "(checked every 25 iterations, changed only 5-fold or more: each change refactorises). "
    "M + rho H H^T is factorised by CHOLMOD (one symbolic analysis per solve; a persistent solver "
    "keeps the factorisation, and its rho, while M and H stay); W = H^T M^-1 H is "
    "never formed: for deformable bodies whose W would be dense and too large. Converged means "
    "both the error and the equilibrium residual are below the tolerance. Global problems with "
    "a symmetric positive definite M only. Options: rho (initial penalty, in units of the mean "
    "normal entry of W_aa over 8 sampled contacts), rho_adaptive (0: keep rho), acceleration (0: plain "
    "ADMM).",
    gadmm::solve, false, true, gadmm::kExtraKeys, gadmm::kDefaults};

}  // namespace frix
