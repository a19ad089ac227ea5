// One stage of auto: a solver run inside it, as a StageRequest asks, under the watchdog, on the
// caller's clock and limits. What a part's rules (part.cpp), the first sweeps on the whole
// problem (parts.cpp) and the global routes (global_routes.cpp) share.
#pragma once

#include <cmath>
#include <cstdint>

#include "solvers/auto/policy.hpp"
#include "solvers/auto/pricing.hpp"
#include "solvers/auto/trace.hpp"
#include "solvers/auto/watchdog.hpp"
#include "src/measures.hpp"
#include "src/solve_cache.hpp"
#include "src/solver_api.hpp"

namespace frix::autosolve {

// What a stage is asked to do.
struct StageRequest {
    int solver = 0;
    Watch watch = Watch::Stall;
    int64_t patience = 0;  // the stall watch: iterations without tenfold progress it allows
    int64_t budget = 0;    // its iterations (and at most half of the caller's left)
    double tolerance = 0.0;
    // The rate watch on a priced part: the work it is weighed against (NaN: its priced
    // alternative, ADMM or the IPM); whether it may also go on for a multiple of its own work
    // (false: only within that work, a probe that costs little if it fails); the work it does
    // before it is judged (NaN: kJudgeShare of the alternative).
    double alternative_work = NAN;
    bool patient = true;
    double min_work = NAN;
};
StageRequest rate_request(int solver, int64_t budget, double tolerance);
StageRequest stall_request(int solver, int64_t patience, int64_t budget, double tolerance);

// What a stage did.
struct StageOutcome {
    TraceEvent event;            // its record, not yet in the trace
    frix_info info;              // its run's status and counters
    Measures measures;           // at the r it returned (u holds W r + q)
    bool slow = false;           // stopped by the rate watch
    double predicted_work = NAN; // what the rate last predicted to the tolerance
    bool cut_short = false;      // given fewer iterations than its budget (the caller's max_iter)
    bool stopped_by_caller = false;
};

// Where a part's stages run: its problem, its u (W r + q, written by every stage), the states
// its solvers keep (null: none), its stages' prices (null: unpriced) and, where u already holds
// W r + q for the stage's start r, their measures (null: not known; SolveContext::measured_start).
struct StageGround {
    const frix_problem &p;
    Shared &shared;
    double *u;
    SolveCache *cache;
    const StageCosts *prices;
    const Measures *measured_start;
};

// One stage on a part from r (its iterate out); the iterations its callback did not see go to
// the shared count.
frix_error run_stage(const StageGround &ground, const StageRequest &req, double *r, StageOutcome &out);

// The options of a stage that runs solver `entry` to `tolerance` for at most `max_iter` of its
// iterations, on the caller's deadline, memory limit and error measure: the local and the
// global routes alike. `part`: a part's stage, which logs through it one level quieter than the
// caller; null: a global route's stage, on the caller's log, callback and threads.
frix_options stage_options(const SolverEntry &entry, const frix_options &user, double tolerance, int64_t max_iter,
                           Shared *part);

// The iterations a stage of `budget` gets: at most half of the caller's left, so that under a
// tight limit the stages after it still get their turn. *cut_short: fewer than its budget.
int64_t stage_iterations(const Shared &shared, int64_t budget, bool *cut_short);

// A stage's trace record: solver `id`'s run as `info` reports it (status, iterations),
// `seconds` long, ending at `error` (as given: callers that record a non-finite one as
// INFINITY say so).
TraceEvent stage_event(int id, const frix_info &info, double seconds, double error);

// After a stage's solve (solver `id`, its info, `seconds` long, ending at `error`): the
// iterations its callback did not see go to the shared count, and its record is returned.
TraceEvent close_stage(int id, const frix_info &info, const Watchdog &dog, double seconds, double error);

// A record's line to the caller's log, at verbosity 1 and above.
void log_event(Shared &shared, const TraceEvent &e);

}  // namespace frix::autosolve
