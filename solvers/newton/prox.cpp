// PROX (id 502): the proximal point method. Each outer step solves the regularised problem
//   u = (W + alpha I) r + (q - alpha r_k),
// whose W + alpha I has full rank even when W does not (rigid scenes), with a semismooth
// Newton (newton.hpp) run on the shifted operator: W and q are never modified or copied (the
// Siconos 4.4 PROX adds alpha to W's diagonal in place and restores it afterwards).
// alpha follows the error: alpha = sigma * error^nu * |W| (Siconos' variable rule, here in
// units of W so that it does not depend on the problem's scaling), times 10 after a failed
// inner solve; a fixed alpha can be set instead.
// A rejected step leaves the iterate where it was, so when the alpha rule comes back to a value
// it has already tried from the same iterate, the steps that follow would repeat (RockPile_tob1:
// alpha 1.5e-3, 1.5e-2, 1.5e-3, ... until max_iter): the method stops, stagnated.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "solvers/kit/newton.hpp"
#include "src/error_state.hpp"
#include "src/log.hpp"
#include "src/measures.hpp"
#include "src/monitor.hpp"
#include "solvers/entries.hpp"

namespace frix {
namespace prox {

namespace {

// Inner Newton steps per proximal step before alpha is raised.
constexpr int64_t kInnerMaxIter = 50;
// alpha stays within [kAlphaMin, kAlphaMax] * |W|: below, the inner problem is as singular as
// the original; above, a proximal step barely moves.
constexpr double kAlphaMin = 1e-12, kAlphaMax = 1e6;

// The run's counters into ctx.info (the status is there already).
void record(SolveContext &ctx, int64_t outer, const newton::Engine &engine, int64_t verbosity) {
    frix_info &info = ctx.info;
    info.iterations = outer;
    info.newton_iterations = engine.counters.newton;
    info.line_search_steps = engine.counters.line_search;
    Monitor::record_factorizations(info, engine.factor_stats());
    if (verbosity >= 1)
        log_line(&ctx.options, "prox: %s after %lld proximal steps (%lld Newton)", frix_status_string(info.status),
                 (long long)outer, (long long)engine.counters.newton);
}

frix_error solve(SolveContext &ctx) {
    const frix_problem &p = ctx.problem;
    const frix_options &o = ctx.options;
    if (!p.W || !p.W->block) return fail(FRIX_ERR_INTERNAL, "prox: W is not stored as 3x3 blocks");
    const int inner_id = (int)o.i(FRIX_OPT_INNER_SOLVER);
    newton::Settings s = newton::settings_from(o, inner_id);
    const Monitor monitor(ctx);
    const double tol = monitor.tolerance();
    const double fixed_alpha = o.d(FRIX_OPT_PROX_ALPHA);
    const double sigma = o.d(FRIX_OPT_PROX_SIGMA), nu = o.d(FRIX_OPT_PROX_NU);
    const int64_t m = 3 * p.nc;
    frix_info &info = ctx.info;

    Kept<newton::KeptEngine> kept(ctx.cache, FRIX_SOLVER_PROX);
    s.weight = p.weight.data();
    newton::Engine &engine = newton::engine_for(*kept, ctx.cache, *p.W, p.mu, p.nc, s);
    engine.full_step_on_failure = true;
    const double scale = engine.w_scale();
    auto adapted = [&](double err) {
        return std::clamp(sigma * std::pow(err, nu), kAlphaMin, kAlphaMax) * scale;
    };
    double *r = ctx.r;
    std::vector<double> qk(m), rk(r, r + m);
    double norm_q = 0.0;
    for (int64_t i = 0; i < m; ++i) norm_q += p.q[i] * p.q[i];
    norm_q = std::sqrt(norm_q);
    double err = selected_error(local_measures(p, r, ctx.u), s.measure);
    double alpha = fixed_alpha > 0.0 ? fixed_alpha : adapted(err);
    std::vector<double> tried;  // alphas tried from the current accepted iterate rk
    int64_t outer = 0;
    info.status = FRIX_STATUS_MAX_ITER;
    // The Newton steps, on each proximal step's limits; their errors are the inner problems'.
    kit::Steps inner{Monitor(ctx), kit::Steps::Errors::kOfAnInnerProblem};
    while (true) {
        frix_status stop = kit::status_before_step(monitor, err, outer, inner);
        // Each step starts from rk (a rejected step restores it): the same alpha from the same
        // rk would repeat a step already taken.
        if (stop == FRIX_STATUS_NOT_RUN && std::find(tried.begin(), tried.end(), alpha) != tried.end())
            stop = FRIX_STATUS_STAGNATED;
        if (stop != FRIX_STATUS_NOT_RUN) {
            info.status = stop;
            break;
        }
        tried.push_back(alpha);
        ++outer;
        for (int64_t i = 0; i < m; ++i) qk[i] = p.q[i] - alpha * rk[i];
        newton::RunResult res;
        // The inner problem is solved a decade below the current error: tighter wastes Newton
        // steps on a problem about to change, looser slows the outer convergence.
        inner.monitor.with_limits(0.1 * std::max(err, tol), inner.done + kInnerMaxIter);
        if (frix_error e = engine.run(r, qk.data(), alpha, inner, res, norm_q)) return e;
        const frix_status stopped = kit::status_after_step(monitor, res.status);
        if (stopped != FRIX_STATUS_NOT_RUN) {
            std::copy(rk.begin(), rk.end(), r);
            info.status = stopped;
            break;
        }
        const double e_new = selected_error(local_measures(p, r, ctx.u), s.measure);
        if (s.verbosity >= 1)
            log_line(&o, "prox: step %lld alpha %.3e inner %s (%.2e) error %.3e",
                     (long long)outer, alpha / scale, frix_status_string(res.status),
                     res.error, e_new);
        const bool inner_ok = res.status == FRIX_STATUS_CONVERGED;
        if (e_new < err) {  // progress on the original problem: keep the step
            err = e_new;
            std::copy(r, r + m, rk.begin());
            tried.clear();
        } else {
            std::copy(rk.begin(), rk.end(), r);
        }
        if (fixed_alpha <= 0.0) {
            // A solved inner problem lets alpha fall tenfold at least (Siconos' REGULARIZATION
            // rule), down to what the error asks for; a failed one (stalled Newton) raises it
            // tenfold, which makes the next inner problem better conditioned.
            alpha = inner_ok ? std::max(std::min(adapted(err), 0.1 * alpha), kAlphaMin * scale)
                             : std::min(alpha * 10.0, kAlphaMax * scale);
        }
        inner.report_measured(err);
    }
    std::copy(rk.begin(), rk.end(), r);  // the last accepted proximal iterate
    record(ctx, outer, engine, s.verbosity);
    kept.keep();
    return FRIX_OK;
}

const frix_option_key kExtraKeys[] = {
    FRIX_OPT_INNER_SOLVER, FRIX_OPT_PROX_ALPHA,  FRIX_OPT_PROX_SIGMA,           FRIX_OPT_PROX_NU,
    FRIX_OPT_RHO_STRATEGY, FRIX_OPT_RHO,         FRIX_OPT_LINE_SEARCH, FRIX_OPT_LINE_SEARCH_MAX_ITER,
    (frix_option_key)0};

const OptionDefault kDefaults[] = {{FRIX_OPT_MAX_ITER, 1000},
                                   {FRIX_OPT_INNER_SOLVER, FRIX_SOLVER_NSN_AC},
                                   {(frix_option_key)0, 0}};

}  // namespace
}  // namespace prox

const SolverEntry kProxEntry = {
    FRIX_SOLVER_PROX, "prox", "FRICTION_3D_PROX",
    "Proximal point: each step solves the problem with W + alpha I and q - alpha r_k by a "
    "semismooth Newton solver (inner_solver: 504 Alart-Curnier by default, 513, 520), so that "
    "the inner Jacobians stay regular on rank-deficient W; the solution of the original problem "
    "is the fixed point r_k = r_k+1. alpha = prox_sigma * error^prox_nu * mean|W_aa| adapts to "
    "the error (raised tenfold after a failed inner solve), or is fixed by prox_alpha; a step "
    "that does not lower the error is undone, and when alpha comes back to a value already "
    "tried from the same iterate the method stops (stagnated) rather than repeat itself. The "
    "caller's W and q are only read. "
    "Iterations count proximal steps; the Newton steps are reported separately.",
    prox::solve, true, false, prox::kExtraKeys, prox::kDefaults};

}  // namespace frix
