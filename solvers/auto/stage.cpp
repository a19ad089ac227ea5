// One stage of auto (stage.hpp).
#include "solvers/auto/stage.hpp"

#include <algorithm>
#include <string>

#include "src/options.hpp"

namespace frix::autosolve {

namespace {

// The rate watch of a part's stage: ADMM's own floor and, on a priced part, the work the
// stage is weighed against and when it is first judged.
void watch_rate(Watchdog &dog, const StageRequest &req, const StageCosts *prices) {
    const bool admm = req.solver == FRIX_SOLVER_ADMM;
    if (admm) {
        dog.slow = "ADMM rate too slow";
        dog.min_sweeps = kAdmmMinIterations;
    }
    if (!prices) return;
    dog.iteration_work = admm ? prices->admm_iteration : prices->sweep;
    // NSGS's alternative is ADMM (priced at kAdmmExpectedIterations) or the IPM.
    dog.alternative_work =
        admm ? prices->ipm : std::min(prices->ipm, prices->admm_setup + kAdmmExpectedIterations * prices->admm_iteration);
    if (std::isfinite(req.alternative_work)) dog.alternative_work = req.alternative_work;
    dog.patient = req.patient;
    dog.min_sweeps = std::max(dog.min_sweeps, (int64_t)(kJudgeShare * dog.alternative_work / dog.iteration_work));
    if (std::isfinite(req.min_work))
        dog.min_sweeps = std::max(dog.min_sweeps, (int64_t)(req.min_work / dog.iteration_work));
}

}  // namespace

StageRequest rate_request(int solver, int64_t budget, double tolerance) {
    StageRequest req;
    req.solver = solver;
    req.watch = Watch::Rate;
    req.budget = budget;
    req.tolerance = tolerance;
    return req;
}

StageRequest stall_request(int solver, int64_t patience, int64_t budget, double tolerance) {
    StageRequest req;
    req.solver = solver;
    req.watch = Watch::Stall;
    req.patience = patience;
    req.budget = budget;
    req.tolerance = tolerance;
    return req;
}

frix_error run_stage(const StageGround &ground, const StageRequest &req, double *r, StageOutcome &out) {
    Shared &shared = ground.shared;
    const SolverEntry &entry = *find_solver(req.solver);
    out = StageOutcome();
    const int64_t max_iter = stage_iterations(shared, req.budget, &out.cut_short);
    frix_options o = stage_options(entry, shared.user, req.tolerance, max_iter, &shared);
    Watchdog dog(shared, req.watch, req.tolerance, req.patience, nsgs_min_sweeps(ground.p.W->nblocks()));
    if (req.watch == Watch::Rate) watch_rate(dog, req, ground.prices);
    dog.whole_problem = shared.contacts < 0 || ground.p.nc == shared.contacts;
    dog.install(o);

    out.info.solver_id = req.solver;
    out.info.contacts = ground.p.nc;
    out.info.tolerance = req.tolerance;
    const double t0 = shared.clock.seconds();
    // The driver's local path watches the stage against the part's own runaway bound (its |q|):
    // a part is a problem of its own, whose solution scales with its q, not with the whole's.
    if (frix_error e = solve_local_problem(ground.p, o, entry, r, ground.u, out.info, shared.clock, ground.cache,
                                           &out.measures, false, false, ground.measured_start))
        return e;
    out.event = close_stage(req.solver, out.info, dog, shared.clock.seconds() - t0, out.info.error);
    out.slow = dog.stopped_slow();
    out.predicted_work = dog.predicted * dog.iteration_work;
    out.stopped_by_caller = out.info.status == FRIX_STATUS_STOPPED_BY_CALLBACK && !dog.stopped_by_watchdog;
    return FRIX_OK;
}

frix_options stage_options(const SolverEntry &entry, const frix_options &user, double tolerance, int64_t max_iter,
                           Shared *part) {
    frix_options o;
    default_options(entry, o);
    o.dvalue[FRIX_OPT_TOLERANCE] = tolerance;
    o.ivalue[FRIX_OPT_ERROR_MEASURE] = user.i(FRIX_OPT_ERROR_MEASURE);
    // The stage runs on the caller's clock (started by frix_solve): its limit is the caller's
    // deadline itself.
    o.dvalue[FRIX_OPT_TIME_LIMIT] = user.d(FRIX_OPT_TIME_LIMIT);
    o.dvalue[FRIX_OPT_MEMORY_LIMIT] = user.d(FRIX_OPT_MEMORY_LIMIT);
    // The sweeps' momentum is auto's own option: their Siconos ids keep Siconos's plain
    // iterates by default, while auto is free to take the fewer sweeps.
    if (entry.id == FRIX_SOLVER_NSGS_VELOCITY || entry.id == FRIX_SOLVER_NSGS || entry.id == FRIX_SOLVER_GLOBAL_NSGS) {
        o.ivalue[FRIX_OPT_DRIFT_WINDOW] = kDriftWindow;
        o.ivalue[FRIX_OPT_ACCELERATION] = user.i(FRIX_OPT_ACCELERATION);
        o.ivalue[FRIX_OPT_ANDERSON] = user.i(FRIX_OPT_ANDERSON);
    }
    if (part) {
        o.ivalue[FRIX_OPT_MAX_ITER] = max_iter;
        o.ivalue[FRIX_OPT_VERBOSITY] = std::max<int64_t>(0, user.i(FRIX_OPT_VERBOSITY) - 1);
        o.ivalue[FRIX_OPT_THREADS] = part->part_threads;
        o.log = &Shared::log;
        o.log_data = part;
        if (entry.id == FRIX_SOLVER_ADMM && part->scaled_penalty) o.ivalue[FRIX_OPT_RHO_STRATEGY] = FRIX_RHO_SPECTRAL;
        return o;
    }
    // A global route's stage also stops at its solver's own limit.
    o.ivalue[FRIX_OPT_MAX_ITER] = std::max<int64_t>(1, std::min(o.ivalue[FRIX_OPT_MAX_ITER], max_iter));
    o.ivalue[FRIX_OPT_THREADS] = user.i(FRIX_OPT_THREADS);
    o.callback = user.callback;
    o.callback_with_kind = user.callback_with_kind;
    o.callback_data = user.callback_data;
    o.ivalue[FRIX_OPT_CALLBACK_ESTIMATES] = user.i(FRIX_OPT_CALLBACK_ESTIMATES);
    o.log = user.log;
    o.log_data = user.log_data;
    return o;
}

int64_t stage_iterations(const Shared &shared, int64_t budget, bool *cut_short) {
    const int64_t left = Monitor(shared.user, shared.clock).max_iterations() - shared.iterations.load();
    *cut_short = left / 2 < budget;
    return std::max<int64_t>(1, std::min(left / 2, budget));
}

TraceEvent stage_event(int id, const frix_info &info, double seconds, double error) {
    TraceEvent ev = trace_event(kStage);
    ev.solver_id = id;
    ev.status = info.status;
    ev.iterations = info.iterations;
    ev.seconds = seconds;
    ev.error = error;
    return ev;
}

TraceEvent close_stage(int id, const frix_info &info, const Watchdog &dog, double seconds, double error) {
    if (info.iterations > dog.last_iteration) dog.shared->iterations += info.iterations - dog.last_iteration;
    TraceEvent ev = stage_event(id, info, seconds, std::isfinite(error) ? error : INFINITY);
    ev.why = dog.stopped_by_watchdog ? dog.why : nullptr;
    return ev;
}

void log_event(Shared &shared, const TraceEvent &e) {
    if (shared.user.i(FRIX_OPT_VERBOSITY) < 1) return;
    std::string line = "auto: " + autosolve::format_event(frix_info(), e);
    while (!line.empty() && line.back() == '\n') line.pop_back();
    Shared::log(&shared, line.c_str());
}

}  // namespace frix::autosolve
