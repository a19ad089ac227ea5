// auto (id 900), frix's default solver: one solver that is both robust and fast.
//
// No single method wins everywhere (docs/reports/benchmarks.md): NSGS is the fastest on small and
// well-conditioned problems and stalls on stiff ones; Newton converges in a few steps near a
// solution and wanders on rank-deficient rigid problems; PROX and ADMM solve nearly
// everything, slowly. auto therefore
//   1. analyses the problem (analysis.cpp: sizes, |W_aa| and mu ranges, islands) and solves
//      each large island as a part of its own, the small ones together, on several threads
//      when the caller allows them (parts.cpp);
//   2. runs on each part, from the best iterate so far, NSGS while its rate promises the
//      tolerance soon, then rounds of Newton, NSGS, ADMM and PROX (the IPM first on large
//      parts) with budgets that double every round (part.cpp, its constants in policy.hpp,
//      their prices in pricing.cpp); a watchdog stops a stage that stalls (watchdog.cpp), and
//      every stage is recorded in the trace (trace.cpp);
//   3. combines the parts exactly: the whole problem is measured, and the parts are solved
//      again, tighter, until it meets the tolerance;
//   4. when it fails, checks whether a solution exists at all and says so.
// Global problems go through the reduction W = H^T M^-1 H with the same strategy, or a route
// without W where W would be dense (global_routes.cpp). docs/auto.md describes the strategy
// for users.
#include "solvers/entries.hpp"

#include <algorithm>
#include <cmath>

#include "solvers/auto/policy.hpp"
#include "solvers/auto/routes.hpp"
#include "solvers/auto/trace.hpp"
#include "solvers/auto/stage.hpp"
#include "src/error_state.hpp"
#include "src/existence.hpp"
#include "src/monitor.hpp"

namespace frix {
namespace autosolve {

namespace {

// When a solve failed (not stopped by the caller, and not ended before any run: M found
// singular, whose passes the driver runs next), whether a solution exists at all: within
// what is left of the caller's time limit, and not once it is spent (frix solve then checks
// on its own, outside the solve).
void check_existence_on_failure(SolveContext &ctx) {
    frix_info &info = ctx.info;
    if (info.status == FRIX_STATUS_CONVERGED || info.status == FRIX_STATUS_STOPPED_BY_CALLBACK ||
        info.status == FRIX_STATUS_NOT_RUN || !ctx.options.i(FRIX_OPT_EXISTENCE_CHECK))
        return;
    const double tl = ctx.options.d(FRIX_OPT_TIME_LIMIT);
    const double left = tl > 0.0 ? tl - ctx.clock.seconds() : 0.0;
    if (tl > 0.0 && left <= 0.0) return;
    double margin = NAN;
    info.existence = check_existence(ctx.problem, left, &margin);
    info.existence_margin = margin;
    info.trace.push_back(trace_event(kExistence));
}

// One stage of a rolling-friction solve: `id` from r to `tol` within `max_iter` iterations on
// the caller's limits (and under `dog`, where given, which passes the caller's callback on),
// recorded in the trace; the iterations add up in info. A stage the Newton watch stopped for
// its creeping steps ends stagnated.
frix_error rolling_stage(SolveContext &ctx, int id, double tol, int64_t max_iter, int64_t &done,
                         Watchdog *dog = nullptr) {
    const SolverEntry *entry = find_solver(id);
    if (!entry) return fail(FRIX_ERR_INTERNAL, "auto: solver %d of rolling-friction problems is not registered", id);
    frix_options o = stage_options(*entry, ctx.options, tol, max_iter, nullptr);
    o.ivalue[FRIX_OPT_MAX_ITER] = std::max<int64_t>(max_iter, 1);  // (set by stage_options for parts only)
    if (dog) dog->install(o);
    SolveContext inner = ctx.problem.kind == FRIX_PROBLEM_ROLLING_LOCAL
                             ? SolveContext::local(ctx.problem, o, ctx.r, ctx.u, ctx.info, ctx.clock)
                             : SolveContext::global(ctx.problem, o, ctx.r, ctx.u, ctx.v, ctx.info, ctx.clock, ctx.mass);
    inner.runaway_bound = ctx.runaway_bound;  // each stage's Monitor watches the iterate, as the driver asked
    const double t0 = ctx.clock.seconds();
    ctx.info.error = INFINITY;
    if (frix_error e = entry->solve(inner)) return e;
    ctx.has_measured = inner.has_measured;  // the stage's measures of the r it returned, if it took them
    ctx.measured = inner.measured;
    const double error = ctx.info.error;
    const bool creeping = dog && dog->stopped_creeping() && ctx.info.status == FRIX_STATUS_STOPPED_BY_CALLBACK &&
                          !ctx.info.ran_away;
    if (creeping) ctx.info.status = FRIX_STATUS_STAGNATED;
    TraceEvent stage =
        stage_event(entry->id, ctx.info, ctx.clock.seconds() - t0, std::isfinite(error) ? error : INFINITY);
    stage.why = creeping ? dog->why : nullptr;
    ctx.info.trace.push_back(stage);
    done += ctx.info.iterations;
    return FRIX_OK;
}

// A rolling-friction problem (docs/rolling.md): rolling-nsgs to kRollingLoose (or to the
// tolerance, if looser) on at most half the iterations; where the tolerance is tighter and
// not met, a rolling-nsn polish of at most kRollingNewtonSteps Newton steps from the sweeps'
// answer, ended early where the sweeps got there and its steps creep (Watch::Newton; it
// returns an iterate no worse than its start); where that fails too, or its factorisation
// was refused for memory or for the time left, the sweeps again with the iterations and the
// time left: they factorise nothing. The driver measures the answer and checks the status.
frix_error solve_rolling(SolveContext &ctx) {
    const Monitor monitor(ctx);
    const double tol = monitor.tolerance();
    const int64_t budget = monitor.max_iterations();
    int64_t done = 0;
    const double loose = std::max(tol, kRollingLoose);
    const int64_t first = loose > tol ? std::max<int64_t>(budget / 2, 1) : budget;
    if (frix_error e = rolling_stage(ctx, FRIX_SOLVER_ROLLING_NSGS, loose, first, done)) return e;
    const auto finished = [&](bool memory_ends) {
        const frix_status s = ctx.info.status;
        return (s == FRIX_STATUS_CONVERGED && ctx.info.error <= tol) ||
               (s == FRIX_STATUS_TIME_LIMIT && monitor.out_of_time()) ||
               (memory_ends && s == FRIX_STATUS_MEMORY_LIMIT) || s == FRIX_STATUS_STOPPED_BY_CALLBACK ||
               done >= budget;
    };
    if (!finished(true)) {
        const int64_t steps = std::min(kRollingNewtonSteps, budget - done);
        const bool sweeps_reached_loose = ctx.info.status == FRIX_STATUS_CONVERGED;
        Shared shared(ctx.options, ctx.clock);
        shared.iterations = done;  // the watch's iteration limit is the caller's, over all stages
        Watchdog dog(shared, Watch::Newton, tol, kRollingNewtonSlowSteps, 0);
        dog.newton_start = ctx.info.error;
        Watchdog *probe = sweeps_reached_loose ? &dog : nullptr;
        if (frix_error e = rolling_stage(ctx, FRIX_SOLVER_ROLLING_NSN, tol, steps, done, probe)) return e;
    }
    if (!finished(false))
        if (frix_error e = rolling_stage(ctx, FRIX_SOLVER_ROLLING_NSGS, tol, budget - done, done)) return e;
    ctx.info.iterations = done;
    if (ctx.info.status == FRIX_STATUS_CONVERGED && !(ctx.info.error <= tol)) ctx.info.status = FRIX_STATUS_MAX_ITER;
    if (done >= budget && ctx.info.status != FRIX_STATUS_CONVERGED) ctx.info.status = FRIX_STATUS_MAX_ITER;
    return FRIX_OK;
}

frix_error solve(SolveContext &ctx) {
    if (is_rolling(ctx.problem)) return solve_rolling(ctx);
    const bool global = ctx.problem.kind == FRIX_PROBLEM_GLOBAL;
    if (frix_error e = global ? solve_global(ctx) : solve_local(ctx)) return e;
    check_existence_on_failure(ctx);
    return FRIX_OK;
}

const frix_option_key kExtraKeys[] = {FRIX_OPT_THREADS, FRIX_OPT_ACCELERATION, (frix_option_key)0};
const OptionDefault kDefaults[] = {{FRIX_OPT_MAX_ITER, 1e9}, {FRIX_OPT_ACCELERATION, 1}, {(frix_option_key)0, 0.0}};

}  // namespace

#define FRIX_AUTO_DESCRIPTION                                                                       \
    "The default solver. Analyses the problem (sizes, the ranges of |W_aa| and mu, the islands: "   \
    "groups of contacts that do not interact, each large one solved as a part of its own, the "    \
    "small ones together, with threads > 1 at once), then runs on each part NSGS (with momentum, or "  \
    "Anderson's mix of the last ten sweeps on a global problem with 3 nc <= n dofs, where W may be " \
    "regular; plain with acceleration = 0) while its "  \
    "convergence rate promises the tolerance soon, and otherwise rounds of semismooth Newton "     \
    "(Alart-Curnier; on parts of at most 64 contacts also from seeded random starts), NSGS (one " \
    "chain over the rounds, steady drifts of r carried ahead), ADMM and PROX (from the best "    \
    "iterate so far), with budgets that double every round (each at most half of the "           \
    "iterations left) and a watchdog "                                                            \
    "stopping any stage that stalls; deterministic (iteration counts, " \
    "not seconds). Global problems are reduced to W = H^T M^-1 H, with Newton on (v, r) as the "   \
    "fallback; where a dense W is priced above the route without it (or would overrun the time "  \
    "or memory limit), gadmm then gnsn-al, which never form W. Every stage is in "                 \
    "frix_info_trace; on failure an existence check says whether a solution may not exist. "      \
    "Options: threads, existence_check (and the common ones). See docs/auto.md."

const SolverEntry kAutoReductionEntry = {FRIX_SOLVER_AUTO, "auto", nullptr, FRIX_AUTO_DESCRIPTION,
                                         solve_local,      true,   false,   kExtraKeys,
                                         kDefaults};

}  // namespace autosolve

const SolverEntry kAutoEntry = {FRIX_SOLVER_AUTO,          "auto", nullptr, FRIX_AUTO_DESCRIPTION,
                                autosolve::solve,          true,   true,    autosolve::kExtraKeys,
                                autosolve::kDefaults,      true,   true,
                                true};

}  // namespace frix
