// auto (id 900), frix's default solver: one solver that is both robust and fast.
//
// No single method wins everywhere (docs/benchmarks.md): NSGS is the fastest on small and
// well-conditioned problems and stalls on stiff ones; Newton converges in a few steps near a
// solution and wanders on rank-deficient rigid problems; PROX and ADMM solve nearly
// everything, slowly. auto therefore
//   1. analyses the problem (sizes, |W_aa| and mu ranges, islands: the connected components
//      of W's block graph) and solves each large island as a part of its own, the small ones
//      together (at once on several threads when the caller allows them): a part that
//      converges stops costing work;
//   2. runs on each part, from the best iterate so far, NSGS while its convergence rate
//      promises the tolerance soon (on a large part: for less than the next stage's price,
//      StageCosts), on a large part ADMM and the interior-point method, then rounds of Newton (Alart-Curnier; on a small part
//      also from random starts, the problem not being convex), NSGS (its stages one chain,
//      steady drifts carried ahead), ADMM and PROX with budgets that double every round
//      (each at most half of the iterations left); a watchdog on every stage's progress
//      callback stops a stage that stalls, and every stage is recorded in the trace
//      (frix_info_trace). The parts take their turns, so a hard one does not starve the rest;
//   3. combines the parts exactly: the final error is measured on the whole problem, and the
//      parts are re-solved to a tighter tolerance until that measure meets the tolerance;
//   4. when it fails, checks whether a solution exists at all (frix_problem_check_existence)
//      and says so.
// Global problems go through the reduction W = H^T M^-1 H with the same strategy, and fall
// back on Newton on (v, r) (607) when the reduced solve misses the tolerance; where a dense W
// (a deformable body) is priced above the route without it, or would overrun the time or
// memory limit, that route (613, then 901; 607 where M has no Cholesky factor).
// docs/auto.md describes the strategy for users.
#include <algorithm>
#include <atomic>
#include <cfloat>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "solvers/auto.hpp"
#include "solvers/auto_analysis.hpp"
#include "solvers/auto_trace.hpp"
#include "solvers/global_newton.hpp"
#include "solvers/mass_plus_contacts.hpp"
#include "solvers/nsgs.hpp"
#include "src/error_state.hpp"
#include "src/existence.hpp"
#include "src/linalg/linalg.hpp"
#include "src/log.hpp"
#include "src/measures.hpp"
#include "src/monitor.hpp"
#include "src/random.hpp"
#include "src/reduction.hpp"
#include "src/solver_api.hpp"

namespace frix {
namespace autosolve {

namespace {

// ---- Tuning. The measurements behind each constant: docs/notes/2026-11-25-auto-constants.md.
// Every rule counts iterations, never seconds: without a time limit the result does not
// depend on the machine's speed or load.

// NSGS goes on while the rate of its second half predicts the tolerance within this many
// times the sweeps it has already run (a doubling rule: giving up late wastes at most a
// constant share of the total) ...
constexpr double kNsgsPatience = 3.0;
// ... and is not judged before this many sweeps (early sweeps are erratic), nor before it
// has done this much work (sweeps x W blocks): NSGS judged too early hands a problem it was
// about to solve to the costlier stages.
constexpr int64_t kNsgsMinSweeps = 30;
constexpr double kNsgsMinWork = 1e5;
// The first NSGS stage's sweep limit (the NSGS default).
constexpr int64_t kFirstNsgsSweeps = 20000;
// On a part of fewer contacts than this, the first stage is plain NSGS (500) without
// freezing: over the few sweeps such a part needs, the velocity form's setup (W's block
// columns) costs more than it saves, and freezing at a loose tolerance can trap the sweeps in
// a cycle that plain NSGS does not enter. Where such a problem is one part, that stage runs
// before the part is set up (direct_nsgs): the setup costs more than the few sweeps most such
// problems need.
constexpr int64_t kPlainNsgsMaxContacts = 64;
// Sweeps of plain NSGS on the whole of a problem of several parts before they are set up.
constexpr int64_t kWholeNsgsSweeps = 30;
// A stage is stopped when its best error has not fallen tenfold within half its iterations
// so far, and at least within `patience` of them.
struct StageSpec {
    int solver_id;
    int64_t patience;      // iterations as the solver's callback counts them
    int64_t first_budget;  // iterations of the first round; doubled every round
};
// Newton first (a few steps tell whether it converges), then NSGS again (velocity form,
// freezing, drifts carried ahead), ADMM (the robust workhorse of large rigid problems), PROX
// (regularised Newton). PROX's callback counts its inner Newton steps; its budget counts
// proximal steps. A sweep costs about a fifth of an ADMM iteration, so NSGS gets five times
// ADMM's iterations: both get about the same time in a round. NSGS's stages are one chain,
// each going on from where the previous one stopped and running its whole budget: on
// rank-deficient piles its progress is a drift of r at an error that does not fall, which a
// restart from the best iterate would undo; it runs before ADMM, which would otherwise cost
// as much again where the chain is what converges.
constexpr StageSpec kRound[] = {
    {FRIX_SOLVER_NSN_AC, 50, 100},  // its iterations count the hybrid NSGS sweeps too
    {FRIX_SOLVER_NSGS_VELOCITY, 10000, 10000},
    {FRIX_SOLVER_ADMM, 3000, 2000},
    {FRIX_SOLVER_PROX, 200, 3},
};
// NSGS's stages carry steady drifts of r ahead every this many sweeps (nsgs.cpp, option
// drift_window): on piles whose sweeps cross plateaus of the error, two contacts handing
// load to each other at a steady rate, the jump saves most of the sweeps; the window matters
// little between 1000 and 20000 sweeps.
constexpr int64_t kDriftWindow = 1000;
// Parts of at least this many contacts start their first round with the interior-point
// method (524): where NSGS does not finish a large part, the IPM usually gets within reach
// of Newton in tens of factorisations, while Newton from NSGS's iterate needs hundreds of
// steps or stalls. It cannot start from the best iterate (an interior point is needed), so it
// runs in the first round only. When it stalls below the best error, one Newton stage runs
// from its iterate (near a solution Newton often finishes what the IPM could not). The rounds
// start from the result only within kIpmKeepRatio of the tolerance, where the next stages
// finish it in a few steps; a point far above sends them on a longer path than NSGS's, so
// such a result is set aside, and returned if the rounds end above it (a time or iteration
// limit). Patience and budget count its iterations (interior points and then Newton steps).
constexpr int64_t kIpmMinContacts = 200;
// Smaller parts get the interior-point stage (without ADMM before it) where their tolerance
// is this loose or looser, after kNewtonProbeSteps of Newton from r = 0: where Newton
// converges it usually does so in a few steps, where it does not it can take tens of
// line-searched steps, while the IPM's few tens of factorisations reach a loose tolerance
// either way. At tight tolerances Newton's quadratic end usually wins: the rounds decide.
constexpr double kIpmLooseTolerance = 1e-6;
constexpr int64_t kNewtonProbeSteps = 10;
constexpr StageSpec kIpmStage = {FRIX_SOLVER_IPM, 50, 500};
constexpr double kIpmKeepRatio = 100.0;
// Before the IPM, ADMM under the rate watch (judged on its best error, from this many
// iterations on), up to this many iterations.
constexpr int64_t kAdmmMinIterations = 50;
constexpr int64_t kAdmmRateBudget = 100000;
// What NSGS is weighed against where ADMM comes next: ADMM's factorisation and this many of
// its iterations.
constexpr double kAdmmExpectedIterations = 300.0;
// The iterations of ADMM's probe that NSGS is first weighed against (first_stage).
constexpr double kAdmmProbeIterations = 100.0;
// NSGS whose error is within this factor of the tolerance when the probe ends goes on for at
// least the probe's work (first_stage).
constexpr double kPlateauRatio = 10.0;
// NSGS stopped by its rate within this factor of the tolerance goes on for the probe's work
// before the probe (first_stage): a plateau that close to the tolerance usually ends in fewer
// sweeps than the probe and NSGS after it cost.
constexpr double kNearPlateauRatio = 3.0;
// When max_a |W_aa| / min_a |W_aa| exceeds this, ADMM gives each contact a penalty scaled by
// its |W_aa| (rho_strategy 1, i.e. ADMM on the problem scaled to equal diagonal blocks): one
// penalty needs many times the iterations when the contacts' stiffness spreads over decades.
// Below it the one penalty stays.
constexpr double kScaledPenaltySpread = 100.0;
// The random restarts' seed (any fixed value: the results must not depend on the run).
constexpr uint64_t kRestartSeed = 0x6672697872657374ull;
constexpr double kTwoPi = 6.283185307179586;  // M_PI is POSIX, not C++
// Islands smaller than this are solved together (see solve_local).
constexpr int64_t kMinIslandContacts = 16;
// Random restarts of Newton (see IslandSolver::random_restarts) on parts up to this size: the
// chance that a random start lands in the solution's basin falls with the size.
constexpr int64_t kRestartMaxContacts = 64;
// Polish (see IslandSolver::polish): islands up to this size, PROX steps, target ratio.
constexpr int64_t kPolishMaxContacts = 64;
constexpr int64_t kPolishSteps = 10;
constexpr double kPolishRatio = 1e-3;
// Without a deadline, this many rounds in a row without halving the error end the sequence.
constexpr int kMaxIdleRounds = 3;
// Tightenings of the islands' tolerance when their combined error misses the tolerance
// (after the passes that shrink the loosening of part_loosening, which are not counted).
constexpr int kMaxTightenings = 4;
// A global problem is reduced to W = H^T M^-1 H. Where W would have more than this many
// entries and more than kReductionMaxGrowth times those of M and H (a deformable body makes W
// dense among its contacts), forming it is priced first from M's factor (its flops, and W's
// memory): when it would overrun the time or memory limit, Newton on (v, r), which factorises
// the sparse (v, r) system instead, goes first. Rigid bodies give W a few entries per entry
// of M and H.
constexpr double kReductionMaxEntries = 1e6;
constexpr double kReductionMaxGrowth = 30.0;
// There, the route without W (ADMM on (v, r), then Newton on v; see RoutePrices) is taken
// when it is priced below forming W. Memory-bound flops (sweeps, triangular solves) count
// kMemoryBoundWork times a factorisation's; kSweepsOnW sweeps over W and kWFreeIterations of
// ADMM are what either takes to a tight tolerance on elastic bodies.
constexpr double kMemoryBoundWork = 3.0;
constexpr double kSweepsOnW = 30.0;
constexpr double kWFreeIterations = 50.0;
// The route's stages stop at these counts (ADMM iterations, outer steps of the augmented
// Lagrangian Newton), far past what they take where they work, so that where they do not the
// reduction still gets its turn.
constexpr int64_t kWFreeAdmmIterations = 1000, kWFreeNewtonSteps = 50;
// Rigid bodies with a large W: gnsgs is judged by its rate only after this many sweeps:
// forming W, which the reduction route needs, costs as much as many sweeps, and a time step
// pays it again whenever its contacts change (docs/notes/2026-11-26-scale.md).
constexpr int64_t kProductPatience = 200;

// Prices of the stages, in one unit: the work of one 3x3 block of W times a vector. They are
// known before anything runs (sizes, and CHOLMOD's symbolic analysis of the block graph of
// W), so that the choices they drive do not depend on the machine's speed or load.
// One contact's local solve in an NSGS sweep or an ADMM projection, in that unit.
constexpr double kContactWork = 4.0;
// A scalar flop of a sparse factorisation or solve, in that unit: factorisations run at
// many flops per memory access (dense kernels on supernodes), a block product at few.
constexpr double kFactorFlopWork = 1.0 / 12.0;
// Factorisations of W's size an interior-point stage makes on its way to a solution.
constexpr double kIpmFactorizations = 50.0;
// A first-order stage on a part whose alternative is a factorising stage goes on while its
// rate predicts the tolerance at a cost below that alternative's, or within kPricedPatience
// times its own work so far (less than kNsgsPatience: here the alternative's price also bounds
// what giving up costs, and a slow rate that promises the tolerance late would otherwise keep
// a stage going long past that price): giving up late costs at most the alternative once more.
constexpr double kPricedPatience = 2.0;
// Nor is it judged before it has cost this share of the alternative: its early rate says
// little, and an early judgement wastes at most this share.
constexpr double kJudgeShare = 0.1;
struct StageCosts {
    double sweep = 0.0;           // one NSGS sweep
    double admm_iteration = 0.0;  // one ADMM iteration: two triangular solves, products, projections
    double admm_setup = 0.0;      // ADMM's factorisation of W + rho I
    double ipm = 0.0;             // an interior-point stage to its end
    double admm_bytes = 0.0;      // peak memory of ADMM's factorisation (Cholesky of W's pattern)
    double ipm_bytes = 0.0;       // of the IPM's (LU, priced at twice Cholesky's)
};

// The prices of p's stages. The IPM and Newton factorise an unsymmetric matrix of W's
// pattern by LU (about twice Cholesky's flops).
frix_error price_stages(const frix_problem &p, StageCosts *c) {
    const frix_matrix &W = *p.W;
    const double blocks = (double)W.nblocks(), contacts = (double)p.nc;
    linalg::FactorCost fc;
    if (frix_error e = block_cholesky_cost(W, &fc)) return e;
    const double cholesky = fc.flops * kFactorFlopWork;
    const double solve = 2.0 * 2.0 * fc.factor_entries * kFactorFlopWork;
    c->sweep = blocks + kContactWork * contacts;
    c->admm_iteration = solve + 4.0 * blocks + kContactWork * contacts;
    c->admm_setup = cholesky;
    c->ipm = kIpmFactorizations * (2.0 * cholesky + solve + blocks);
    c->admm_bytes = fc.bytes;
    c->ipm_bytes = 2.0 * fc.bytes;
    return FRIX_OK;
}

enum class Watch { Rate, Stall };

// Shared by the islands of one solve: the caller's callback (called under a lock, with the
// iterations of all islands summed) and the stop it may request.
struct Shared {
    const frix_options &user;
    const Stopwatch &clock;
    std::mutex lock;
    std::atomic<int64_t> iterations{0};
    std::atomic<bool> stop_requested{false};
    bool scaled_penalty = false;  // ADMM with per-contact penalties (kScaledPenaltySpread)
    Shared(const frix_options &u, const Stopwatch &c) : user(u), clock(c) {}

    double deadline() const {
        const double tl = user.d(FRIX_OPT_TIME_LIMIT);
        return tl > 0.0 ? tl : INFINITY;
    }
    bool out_of_time() const { return Monitor(user, clock).out_of_time(); }
    bool out_of_iterations() const { return Monitor(user, clock).out_of_iterations(iterations.load()); }

    // The user's log sink, one line at a time: stages on several threads share it.
    std::mutex log_lock;
    static void log(void *data, const char *line) {
        Shared *shared = static_cast<Shared *>(data);
        std::lock_guard<std::mutex> guard(shared->log_lock);
        log_line(&shared->user, "%s", line);
    }
};

// The watchdog, installed as the progress callback of every stage.
struct Watchdog {
    Shared *shared = nullptr;
    Watch kind = Watch::Stall;
    double tolerance = 0.0;
    int64_t patience = 0;
    int64_t min_sweeps = kNsgsMinSweeps;
    // Watch::Rate: the price of one iteration and of the stage that would replace this one
    // (0: none; the rate is then judged against the stage's own work alone).
    double iteration_work = 0.0, alternative_work = 0.0;
    // Whether the rate may also go on for a multiple of the iterations done (kNsgsPatience,
    // or kPricedPatience on a priced part; a stage weighed against a whole alternative), or
    // only within alternative_work (a stage weighed against a probe of the alternative, which
    // costs little if it fails).
    bool patient = true;
    double predicted = NAN;  // iterations the rate last predicted to the tolerance
    const char *slow = "NSGS rate too slow";
    int64_t last_iteration = 0;  // the stage's iteration count at the previous call
    double best = INFINITY;      // best error of the stage
    double ref = INFINITY;       // the error that tenfold progress is measured from
    int64_t ref_iteration = 0;   // when the best error last fell tenfold
    // Watch::Rate on an unpriced part: the error near half the sweeps so far.
    double mid_error = NAN, last_error = NAN;
    int64_t mid_sweep = 0, last_sweep = 0;
    // Watch::Rate on a priced part: the errors at iterations 1, 2, 4, 8, ... (the first call
    // at or after each); the rate is measured from the last of them at or below half the
    // iterations so far.
    std::vector<std::pair<int64_t, double>> samples;
    int64_t next_sample = 1;
    bool stopped_by_watchdog = false;
    const char *why = nullptr;

    static int callback(void *data, int64_t iteration, double error, double /*elapsed*/) {
        return static_cast<Watchdog *>(data)->on_progress(iteration, error);
    }

    int stop(const char *reason) {
        why = reason;
        stopped_by_watchdog = true;
        return 1;
    }

    int on_progress(int64_t iteration, double error) {
        shared->iterations += iteration - last_iteration;
        last_iteration = iteration;
        if (shared->stop_requested) return 1;  // asked by the caller, seen in another island
        if (shared->user.callback) {
            std::lock_guard<std::mutex> guard(shared->lock);
            if (Monitor(shared->user, shared->clock).report(shared->iterations.load(), error))
                shared->stop_requested = true;
        }
        if (shared->stop_requested) return 1;
        // The caller's max_iter bounds the sum of the stages' own units, PROX's inner Newton
        // steps among them, which PROX's own limit (on its outer steps) does not bound.
        if (shared->out_of_iterations()) return stop("iteration limit");
        if (std::isfinite(error) && error < best) best = error;
        if (best <= 0.1 * ref || (!std::isfinite(ref) && std::isfinite(best))) {
            ref = best;
            ref_iteration = iteration;
        }
        if (kind == Watch::Rate) return judge_rate(judged_error(error), iteration);
        const int64_t idle = iteration - ref_iteration;
        if (idle >= patience && 2 * idle >= iteration) return stop("no tenfold progress");
        return 0;
    }

    // The error the rate is measured on: on a priced part the stage's best (NSGS reports a
    // light error between its full checks, which differ from it by a factor of about 2, and
    // ADMM's restarts are not monotone), elsewhere its last.
    double judged_error(double error) const { return iteration_work > 0.0 ? best : error; }

    // The iterations the rate may predict to the tolerance before the stage is stopped.
    double limit(int64_t sweeps, double allowed) const {
        if (!patient) return allowed;
        const double multiple = iteration_work > 0.0 ? kPricedPatience : kNsgsPatience;
        return std::max(multiple * (double)sweeps, allowed);
    }

    int judge_rate(double error, int64_t sweeps) {
        if (!std::isfinite(error)) return stop("non-finite error");
        double gained = 0.0;  // > 0 when converging
        int64_t from = 0;     // over the sweeps from `from` on
        if (iteration_work > 0.0) {
            if (sweeps >= next_sample) {
                samples.emplace_back(sweeps, error);
                while (next_sample <= sweeps) next_sample *= 2;
            }
            if (sweeps < min_sweeps) return 0;
            const std::pair<int64_t, double> *mid = nullptr;
            for (const auto &x : samples)
                if (2 * x.first <= sweeps) mid = &x;
            if (!mid) return 0;
            from = mid->first;
            gained = std::log(mid->second / error);
        } else {
            // Keep a sample near half the sweeps so far: the rate over the second half.
            if (std::isnan(mid_error) || 4 * mid_sweep < sweeps) {
                mid_error = std::isnan(last_error) ? error : last_error;
                mid_sweep = std::isnan(last_error) ? sweeps : last_sweep;
            }
            last_error = error, last_sweep = sweeps;
            if (sweeps < min_sweeps || sweeps <= mid_sweep) return 0;
            from = mid_sweep;
            gained = std::log(mid_error / error);
        }
        const double needed = std::log(error / tolerance);
        if (needed <= 0.0) return 0;
        predicted = gained > 0.0 ? needed / gained * (double)(sweeps - from) : INFINITY;
        const double allowed = iteration_work > 0.0 ? alternative_work / iteration_work : 0.0;
        if (shared->user.i(FRIX_OPT_VERBOSITY) >= 3 && !samples.empty() && samples.back().first == sweeps) {
            char line[200];
            std::snprintf(line, sizeof line, "auto: rate watch at %lld: error %.3e, predicts %.4g more, allowed %.4g",
                          (long long)sweeps, error, predicted, limit(sweeps, allowed));
            Shared::log(shared, line);
        }
        if (predicted > limit(sweeps, allowed)) return stop(slow);
        return 0;
    }
};

// The options of a stage running solver `entry` to `tolerance` for at most `max_iter` of its
// iterations, on the caller's clock, limits and log.
void stage_options(const SolverEntry &entry, Shared &shared, double tolerance, int64_t max_iter, frix_options &o) {
    const frix_options &user = shared.user;
    default_options(entry, o);
    o.dvalue[FRIX_OPT_TOLERANCE] = tolerance;
    o.ivalue[FRIX_OPT_ERROR_MEASURE] = user.i(FRIX_OPT_ERROR_MEASURE);
    o.ivalue[FRIX_OPT_VERBOSITY] = std::max<int64_t>(0, user.i(FRIX_OPT_VERBOSITY) - 1);
    o.log = &Shared::log;
    o.log_data = &shared;
    if (entry.id == FRIX_SOLVER_ADMM && shared.scaled_penalty) o.ivalue[FRIX_OPT_RHO_STRATEGY] = FRIX_RHO_SPECTRAL;
    if (entry.id == FRIX_SOLVER_NSGS_VELOCITY || entry.id == FRIX_SOLVER_NSGS) o.ivalue[FRIX_OPT_DRIFT_WINDOW] = kDriftWindow;
    o.ivalue[FRIX_OPT_MAX_ITER] = max_iter;
    // The stage runs on the shared clock (started by frix_solve): its limit is the caller's
    // deadline itself.
    const double deadline = shared.deadline();
    o.dvalue[FRIX_OPT_TIME_LIMIT] = std::isfinite(deadline) ? deadline : 0.0;
    o.dvalue[FRIX_OPT_MEMORY_LIMIT] = user.d(FRIX_OPT_MEMORY_LIMIT);
}

// A record's line to the caller's log, at verbosity 1 and above.
void log_event(Shared &shared, const TraceEvent &e) {
    if (shared.user.i(FRIX_OPT_VERBOSITY) < 1) return;
    std::string line = "auto: " + autosolve::format_event(frix_info(), e);
    while (!line.empty() && line.back() == '\n') line.pop_back();
    Shared::log(&shared, line.c_str());
}

// The sweeps before the rate watch judges NSGS on a problem of `blocks` blocks of W.
int64_t nsgs_min_sweeps(int64_t blocks) {
    return std::max<int64_t>(kNsgsMinSweeps, (int64_t)(kNsgsMinWork / (double)std::max<int64_t>(1, blocks)));
}

// After a stage's solve (solver `id`, its info, `seconds` long, ending at `error`): the
// iterations its callback did not see (solvers report at their own pace) go to the shared
// count, and its record is returned.
TraceEvent close_stage(int id, const frix_info &info, const Watchdog &dog, double seconds, double error) {
    if (info.iterations > dog.last_iteration) dog.shared->iterations += info.iterations - dog.last_iteration;
    TraceEvent ev = trace_event(kStage);
    ev.solver_id = id;
    ev.status = info.status;
    ev.why = dog.stopped_by_watchdog ? dog.why : nullptr;
    ev.iterations = info.iterations;
    ev.seconds = seconds;
    ev.error = std::isfinite(error) ? error : INFINITY;
    return ev;
}

// Solves one local problem (an island, or the whole problem) with the stage sequence.
class IslandSolver {
   public:
    // cache: the part's states kept by a persistent solver (null for a one-shot solve).
    IslandSolver(const frix_problem &p, Shared &shared, int64_t island, SolveCache *cache)
        : p_(p), shared_(shared), island_(island), cache_(cache), m_(3 * p.nc), u_((size_t)m_),
          best_r_((size_t)m_), rng_(kRestartSeed + (uint64_t)island) {}

    // Phase kFirst runs the first NSGS stage, phase kRest one round of the others: every
    // part gets its cheap chance before any part gets a long one, and the parts take their
    // rounds in turn (with a time limit, a hard part must not starve the others).
    enum Phase { kFirst, kRest };

    // Whether another round may help this part.
    bool active() const {
        return !finished_ && !(best_error_ <= tolerance_) && !shared_.stop_requested.load() &&
               !shared_.out_of_iterations() && !shared_.out_of_time();
    }
    // r: the part's reactions (warm start in, best iterate out); *best_error: the best error
    // reached (the measure selected by the caller's options, on this part).
    frix_error solve(Phase phase, double *r, double tolerance, double *best_error) {
        if (phase == kFirst) {
            tolerance_ = tolerance;
            round_ = idle_rounds_ = 0;
            finished_ = false;
            std::copy(r, r + m_, best_r_.begin());
            held_error_ = INFINITY;
            // From r = 0 the first stage measures its own start; a warm start is measured
            // here, since it may already be the answer (a tightened pass over the parts).
            if (std::any_of(r, r + m_, [](double x) { return x != 0.0; })) best_error_ = measure(r);
        }
        if (phase == kFirst && first_ran_) {
            best_solver_ = first_solver_;
        } else if (active()) {
            if (frix_error e = phase == kFirst ? first_stage(r) : run_round(r)) return e;
        }
        const bool held = held_error_ < best_error_;
        std::copy(held ? held_r_.begin() : best_r_.begin(), held ? held_r_.end() : best_r_.end(), r);
        *best_error = held ? held_error_ : best_error_;
        returned_best_ = !held;
        return FRIX_OK;
    }

    // The measures of the r that solve() last returned, with u = W r + q copied into `u`,
    // when they are at hand (the stage that found it was the last to use the part's u).
    bool final_measures(Measures *m, double *u) const {
        if (!returned_best_ || !u_at_best_) return false;
        *m = best_measures_;
        std::copy(u_.begin(), u_.end(), u);
        return true;
    }

    // The first stage ran before this part was set up (direct_nsgs: solver `id`, its record
    // in the trace, its iterate the warm start of solve(kFirst)), which then goes on from there.
    void first_stage_ran(int id) {
        first_ran_ = true;
        first_solver_ = id;
        ++stages_run_;
    }

    const std::vector<TraceEvent> &events() const { return events_; }
    int64_t switches() const { return switches_; }
    const frix_info &counters() const { return counters_; }
    bool stopped() const { return stopped_; }

   private:
    // The part's error at r (a non-finite one counts as infinite).
    double measure(const double *r) {
        u_at_best_ = false;
        const double e = selected_error(local_measures(p_, r, u_.data()), shared_.user.i(FRIX_OPT_ERROR_MEASURE));
        return std::isfinite(e) ? e : INFINITY;
    }

    void note(TraceEvent e) {
        e.island = island_;
        e.island_contacts = island_ > 0 ? p_.nc : 0;
        events_.push_back(e);
        log_event(shared_, e);
    }

    bool can_continue() const {
        return !(best_error_ <= tolerance_) && !shared_.out_of_time() && !shared_.out_of_iterations() &&
               !shared_.stop_requested.load();
    }

    // The sequence. First NSGS (velocity form, freezing; plain on a small part) under its
    // rate watch: it finishes the easy problems at once. Then rounds of Newton, NSGS again,
    // ADMM and PROX, each from the best iterate so far (NSGS from where its previous stage
    // stopped, see kRound) under the stall watch and a budget that doubles every round, so
    // that the method that suits the problem gets enough time while the others cost at most a
    // constant factor (a portfolio with restarts).
    //
    // On a priced part NSGS is first weighed against a probe of ADMM (its factorisation and
    // kAdmmProbeIterations iterations): where its rate predicts more than that, ADMM runs from
    // r = 0, weighed against what NSGS's rate predicted; where ADMM is the slower, NSGS goes on
    // from where it stopped under its usual watch (and ADMM runs again in round 0, weighed
    // against the IPM, which may cost far more than NSGS's prediction). Which of the two
    // reaches the tolerance first depends on the tolerance and the problem (ADMM's iterations
    // range from tens on towers of blocks to thousands on piles of spheres), which a few
    // iterations of each tell.
    frix_error first_stage(double *r) {
        if (p_.nc < kPlainNsgsMaxContacts) return stage(FRIX_SOLVER_NSGS, Watch::Rate, 0, kFirstNsgsSweeps, r);
        const StageCosts *c = prices();
        if (!c || !fits_memory(&StageCosts::admm_bytes))
            return stage(FRIX_SOLVER_NSGS_VELOCITY, Watch::Rate, 0, kFirstNsgsSweeps, r);
        const double probe = c->admm_setup + kAdmmProbeIterations * c->admm_iteration;
        probe_alternative_ = probe;
        frix_error e = stage(FRIX_SOLVER_NSGS_VELOCITY, Watch::Rate, 0, kFirstNsgsSweeps, r);
        // NSGS stopped within kNearPlateauRatio of the tolerance first goes on for the
        // probe's work: there its rate says little (a plateau ends when a contact changes
        // status), and the probe, then NSGS again, would cost more where NSGS finishes.
        if (!e && last_slow_ && can_continue() && events_.back().error <= kNearPlateauRatio * tolerance_) {
            min_work_ = probe;
            e = stage(FRIX_SOLVER_NSGS_VELOCITY, Watch::Rate, 0, kFirstNsgsSweeps, r);
            min_work_ = NAN;
        }
        probe_alternative_ = NAN;
        // NSGS that gained nothing predicts nothing to weigh ADMM against: the rounds decide.
        if (e || !last_slow_ || !std::isfinite(last_predicted_work_) || !can_continue()) return e;
        const std::vector<double> nsgs_r(r, r + m_);
        const double nsgs_error = events_.back().error;
        probe_alternative_ = last_predicted_work_;
        std::fill(r, r + m_, 0.0);
        e = stage(FRIX_SOLVER_ADMM, Watch::Rate, 0, kAdmmRateBudget, r);
        probe_alternative_ = NAN;
        if (e || !can_continue()) return e;
        std::copy(nsgs_r.begin(), nsgs_r.end(), r);
        // NSGS within kPlateauRatio of the tolerance then gets at least the work the probe
        // took before it is judged again: a rate says nothing on a plateau of the error, which
        // NSGS crosses when a contact changes status, and this way each of the two has had
        // the same chance.
        if (nsgs_error <= kPlateauRatio * tolerance_)
            min_work_ = c->admm_setup + (double)events_.back().iterations * c->admm_iteration;
        e = stage(FRIX_SOLVER_NSGS_VELOCITY, Watch::Rate, 0, kFirstNsgsSweeps, r);
        min_work_ = NAN;
        return e;
    }

    // One round of the stages (the caller calls it again while `active()`): round k gives
    // each stage 2^k times its first budget and 2^k times its patience.
    frix_error run_round(double *r) {
        const double before = best_error_;
        cut_short_ = false;
        if (round_ == 0 && p_.nc >= kIpmMinContacts && can_continue() && fits_memory(&StageCosts::admm_bytes)) {
            // ADMM first, while its rate predicts the tolerance for less than the IPM costs.
            // From r = 0: its dual variable starts at 0, which fits an iterate of NSGS poorly.
            std::fill(r, r + m_, 0.0);
            if (frix_error e = stage(FRIX_SOLVER_ADMM, Watch::Rate, 0, kAdmmRateBudget, r)) return e;
        }
        const bool small_and_loose = p_.nc < kIpmMinContacts && tolerance_ >= kIpmLooseTolerance;
        if (round_ == 0 && small_and_loose && can_continue()) {
            std::fill(r, r + m_, 0.0);
            if (frix_error e = stage(FRIX_SOLVER_NSN_AC, Watch::Stall, kNewtonProbeSteps, kNewtonProbeSteps, r))
                return e;
        }
        if (round_ == 0 && (p_.nc >= kIpmMinContacts || small_and_loose) && can_continue() &&
            fits_memory(&StageCosts::ipm_bytes)) {
            // The rounds start from its iterate only within kIpmKeepRatio of the tolerance.
            const std::vector<double> keep_r = best_r_;
            const double keep_error = best_error_;
            const int keep_solver = best_solver_;
            if (frix_error e = stage(kIpmStage.solver_id, Watch::Stall, kIpmStage.patience,
                                     kIpmStage.first_budget, r))
                return e;
            // A stalled run that lowered the error gets one Newton stage (the round's, with
            // the first round's budget) from its iterate before that is judged.
            if (!(best_error_ <= tolerance_) && best_error_ < keep_error && can_continue()) {
                std::copy(best_r_.begin(), best_r_.end(), r);
                const StageSpec &newton = kRound[0];
                if (frix_error e = stage(newton.solver_id, Watch::Stall, newton.patience, newton.first_budget, r))
                    return e;
            }
            if (!(best_error_ <= kIpmKeepRatio * tolerance_)) {
                // Set aside, not lost: where the rounds do not get below it (a time or
                // iteration limit that ends them early) it is still the part's answer.
                if (best_error_ < keep_error) held_r_ = best_r_, held_error_ = best_error_;
                best_r_ = keep_r;
                best_error_ = keep_error;
                best_solver_ = keep_solver;
            }
        }
        for (const StageSpec &spec : kRound) {
            if (!can_continue()) break;
            if (spec.solver_id != FRIX_SOLVER_NSGS_VELOCITY &&
                !fits_memory(spec.solver_id == FRIX_SOLVER_ADMM ? &StageCosts::admm_bytes : &StageCosts::ipm_bytes))
                continue;
            const bool chain = spec.solver_id == FRIX_SOLVER_NSGS_VELOCITY && !nsgs_chain_.empty();
            if (chain)
                std::copy(nsgs_chain_.begin(), nsgs_chain_.end(), r);
            else
                std::copy(best_r_.begin(), best_r_.end(), r);
            const int shift = std::min(round_, 30);
            const int64_t patience = spec.patience << shift, budget = spec.first_budget << shift;
            // The first Newton stage also starts afresh: where NSGS stalls it has often
            // drifted along a degenerate set (W singular, contacts at the cone's edge) from
            // which Newton stalls too, while from r = 0 it converges. On a small part only
            // from r = 0; on a larger one from NSGS's iterate first (usually a few steps).
            if (round_ == 0 && spec.solver_id == FRIX_SOLVER_NSN_AC) {
                if (p_.nc > kPolishMaxContacts) {
                    if (frix_error e = stage(spec.solver_id, Watch::Stall, patience, budget, r)) return e;
                    if (!can_continue()) break;
                }
                std::fill(r, r + m_, 0.0);
            }
            if (frix_error e = stage(spec.solver_id, Watch::Stall, patience, budget, r)) return e;
            if (spec.solver_id == FRIX_SOLVER_NSGS_VELOCITY) nsgs_chain_.assign(r, r + m_);
            if (spec.solver_id == FRIX_SOLVER_NSN_AC && p_.nc <= kRestartMaxContacts)
                if (frix_error e = random_restarts(spec, r)) return e;
        }
        ++round_;
        if (best_error_ <= tolerance_) {
            finished_ = true;
            return polish(r);
        }
        // Without a deadline, rounds that do not halve the error end the sequence; a round
        // whose stages the caller's iteration limit cut short does not count (that is the
        // limit's doing: the status is then max_iter, not stagnated).
        idle_rounds_ = best_error_ < 0.5 * before ? 0 : idle_rounds_ + (cut_short_ ? 0 : 1);
        if (!std::isfinite(shared_.deadline()) && idle_rounds_ >= kMaxIdleRounds) {
            TraceEvent e = trace_event(kGiveUp);
            e.error = best_error_;
            note(e);
            finished_ = true;
        }
        return FRIX_OK;
    }

    // Newton from random points of the cones, 2^k of them in round k. Where Newton from r = 0
    // and from the best iterate stalls on a small part, it has usually stopped at a stationary
    // point of its merit function that is not a solution; the problem is not convex, and a
    // random start often lands in the solution's basin.
    // Each start gets the first round's budget and patience: a start that converges does so
    // within it, and the restarts' work doubles every round like the other stages', rather
    // than crowding them out. The round's starts make one trace event (their number, summed
    // iterations and time, best error), so that the trace stays as short as the rounds.
    frix_error random_restarts(const StageSpec &spec, double *r) {
        const int64_t starts = int64_t{1} << std::min(round_, 40);
        TraceEvent sum = trace_event(kStage);
        sum.solver_id = spec.solver_id;
        sum.error = INFINITY;
        for (int64_t k = 0; k < starts && can_continue(); ++k) {
            draw_start(r);
            TraceEvent ev = trace_event(kStage);
            if (frix_error e = run_stage(spec.solver_id, Watch::Stall, spec.patience, spec.first_budget, r, ev))
                return e;
            ++sum.random_starts;
            sum.iterations += ev.iterations;
            sum.seconds += ev.seconds;
            sum.status = ev.status, sum.why = ev.why;  // the last start's ending
            sum.error = std::min(sum.error, ev.error);
        }
        if (sum.random_starts > 0) record(sum);
        return FRIX_OK;
    }

    // r_N uniform on [0, s], r_T uniform on the disk of radius mu r_N, where s is the largest
    // reaction that stops a single contact on its own (max over a of -q_aN / W_aN,aN): the
    // problem's own scale of normal reactions.
    void draw_start(double *r) {
        if (!(start_scale_ > 0.0)) {
            start_scale_ = 0.0;
            for (int64_t a = 0; a < p_.nc; ++a) {
                const int64_t d = p_.W->diag_index[a];
                const double wnn = d >= 0 ? p_.W->block_val[9 * d] : 0.0;
                if (wnn > 0.0 && p_.q[3 * a] < 0.0) start_scale_ = std::max(start_scale_, -p_.q[3 * a] / wnn);
            }
            if (!(start_scale_ > 0.0) || !std::isfinite(start_scale_)) start_scale_ = 1.0;
        }
        for (int64_t a = 0; a < p_.nc; ++a) {
            const double rn = start_scale_ * next_uniform(rng_);
            const double radius = p_.mu[a] * rn * std::sqrt(next_uniform(rng_));
            const double angle = kTwoPi * next_uniform(rng_);
            r[3 * a] = rn;
            r[3 * a + 1] = radius * std::cos(angle);
            r[3 * a + 2] = radius * std::sin(angle);
        }
    }

    // A first-order method (ADMM, NSGS) that meets the tolerance after a hard start may stop
    // anywhere in a thin set of iterates that the relative measure cannot tell apart, and on
    // degenerate problems (a slope at tan = mu) some of them are visibly wrong (velocities off
    // by 1e3 x the measure). On a small island a few proximal Newton steps from there cost
    // little and land on the solution to rounding; the best iterate is kept either way. The
    // Newton-type stages (Newton, PROX, the interior point) end on a solution, not in that set.
    frix_error polish(double *r) {
        if (p_.nc > kPolishMaxContacts || best_solver_ == FRIX_SOLVER_NSN_AC || best_solver_ == FRIX_SOLVER_PROX ||
            best_solver_ == FRIX_SOLVER_IPM)
            return FRIX_OK;
        const double keep = tolerance_;
        tolerance_ = std::max(kPolishRatio * tolerance_, DBL_MIN);
        std::copy(best_r_.begin(), best_r_.end(), r);
        frix_error e = stage(FRIX_SOLVER_PROX, Watch::Stall, 20 * kPolishSteps, kPolishSteps, r);
        tolerance_ = keep;
        return e;
    }

    // One stage: solver `id` from r, for at most `budget` of its iterations, half the
    // caller's remaining iterations and the caller's deadline; recorded in the trace.
    frix_error stage(int id, Watch kind, int64_t patience, int64_t budget, double *r) {
        TraceEvent ev = trace_event(kStage);
        if (frix_error e = run_stage(id, kind, patience, budget, r, ev)) return e;
        record(ev);
        return FRIX_OK;
    }

    // A stage's event into the trace; every stage after the part's first is a switch.
    void record(const TraceEvent &ev) {
        if (++stages_run_ > 1) ++switches_;
        note(ev);
    }

    // The work of a stage, its event (not yet recorded) in `ev`: the best iterate and the
    // counters are updated here.
    frix_error run_stage(int id, Watch kind, int64_t patience, int64_t budget, double *r, TraceEvent &ev) {
        const SolverEntry *entry = find_solver(id);
        const frix_options &user = shared_.user;
        // At most half of the caller's iterations left: under a tight limit the stages after
        // this one still get their turn.
        const int64_t left = Monitor(user, shared_.clock).max_iterations() - shared_.iterations.load();
        frix_options o;
        stage_options(*entry, shared_, tolerance_, std::max<int64_t>(1, std::min(left / 2, budget)), o);
        if (left / 2 < budget) cut_short_ = true;
        Watchdog dog;
        dog.shared = &shared_;
        dog.kind = kind;
        dog.tolerance = tolerance_;
        dog.patience = patience;
        dog.min_sweeps = nsgs_min_sweeps(p_.W->nblocks());
        if (kind == Watch::Rate) {
            const bool admm = id == FRIX_SOLVER_ADMM;
            if (admm) {
                dog.slow = "ADMM rate too slow";
                dog.min_sweeps = kAdmmMinIterations;
            }
            if (const StageCosts *c = prices()) {
                dog.iteration_work = admm ? c->admm_iteration : c->sweep;
                // NSGS's alternative is ADMM (priced at kAdmmExpectedIterations) or the IPM.
                dog.alternative_work =
                    admm ? c->ipm
                         : std::min(c->ipm, c->admm_setup + kAdmmExpectedIterations * c->admm_iteration);
                if (std::isfinite(probe_alternative_)) {
                    dog.alternative_work = probe_alternative_;
                    dog.patient = false;
                }
                dog.min_sweeps =
                    std::max(dog.min_sweeps, (int64_t)(kJudgeShare * dog.alternative_work / dog.iteration_work));
                if (std::isfinite(min_work_))
                    dog.min_sweeps = std::max(dog.min_sweeps, (int64_t)(min_work_ / dog.iteration_work));
            }
        }
        o.callback = Watchdog::callback;
        o.callback_data = &dog;

        frix_info info;
        info.solver_id = id;
        info.contacts = p_.nc;
        info.tolerance = tolerance_;
        const double t0 = shared_.clock.seconds();
        Measures measures;
        u_at_best_ = false;
        if (frix_error e = solve_local_problem(p_, o, *entry, r, u_.data(), info, shared_.clock, cache_, &measures))
            return e;
        Monitor::add_work(counters_, info);
        ev = close_stage(id, info, dog, shared_.clock.seconds() - t0, info.error);
        const double err = ev.error;
        last_slow_ = dog.stopped_by_watchdog && dog.why == dog.slow;
        last_predicted_work_ = dog.predicted * dog.iteration_work;
        if (info.status == FRIX_STATUS_STOPPED_BY_CALLBACK && !dog.stopped_by_watchdog) stopped_ = true;
        if (err < best_error_) {
            best_error_ = err;
            best_solver_ = id;
            std::copy(r, r + m_, best_r_.begin());
            best_measures_ = measures;
            u_at_best_ = true;
        }
        return FRIX_OK;
    }

    // Whether a priced stage's factorisation (its field of StageCosts; Newton's and PROX's
    // are priced as the IPM's, an LU of W's pattern) fits in the memory the solve may still
    // take: one that does not is left out rather than started and refused (its solver's
    // setup alone costs). Unpriced: its solver's own check decides.
    bool fits_memory(double StageCosts::*bytes) {
        const StageCosts *c = prices();
        return !c || Monitor(shared_.user, shared_.clock).fits_memory(c->*bytes);
    }

    // The stages' prices on a part large enough for the interior-point stage (kIpmMinContacts),
    // where they weigh a first-order stage against it; null on a smaller part (and where
    // pricing failed: the rate is then judged on the stage's own work).
    const StageCosts *prices() {
        if (p_.nc < kIpmMinContacts) return nullptr;
        if (!priced_) {
            priced_ = true;
            if (price_stages(p_, &costs_) != FRIX_OK) {
                clear_error();
                costs_ = StageCosts{};
            }
            if (shared_.user.i(FRIX_OPT_VERBOSITY) >= 1) {
                char line[200];
                std::snprintf(line, sizeof line,
                              "auto: part %lld prices (block products): sweep %.3g, admm %.3g + %.3g an iteration, ipm %.3g",
                              (long long)island_, costs_.sweep, costs_.admm_setup, costs_.admm_iteration, costs_.ipm);
                Shared::log(&shared_, line);
            }
        }
        return costs_.ipm > 0.0 ? &costs_ : nullptr;
    }

    const frix_problem &p_;
    Shared &shared_;
    int64_t island_;
    SolveCache *cache_;
    int64_t m_;
    std::vector<double> u_, best_r_;
    std::vector<double> nsgs_chain_;  // where the last NSGS stage of the rounds stopped
    // The interior-point stage's result when the rounds do not start from it (kIpmKeepRatio):
    // returned instead of the best iterate if that stays worse.
    std::vector<double> held_r_;
    double held_error_ = INFINITY;
    double tolerance_ = 0.0, best_error_ = INFINITY;
    // The measures of best_r_, and whether u_ is still W best_r_ + q; whether solve() last
    // returned best_r_ (not the held result).
    Measures best_measures_;
    bool u_at_best_ = false, returned_best_ = false;
    int best_solver_ = 0;  // the stage that found the best iterate
    uint64_t rng_;               // random restarts: seeded by the part, so threads do not matter
    double start_scale_ = 0.0;   // of the random starts (draw_start); 0 until first needed
    int round_ = 0, idle_rounds_ = 0;
    bool cut_short_ = false;  // a stage of this round got less than its budget (max_iter)
    StageCosts costs_;
    bool priced_ = false;
    // The probe (first_stage): the work a Watch::Rate stage is weighed against instead of its
    // usual alternative (NaN: none); whether the last stage was stopped for its rate, and the
    // work its rate then predicted to the tolerance.
    double probe_alternative_ = NAN;
    double min_work_ = NAN;  // the work a Watch::Rate stage does before it is judged (NaN: none)
    bool last_slow_ = false;
    double last_predicted_work_ = NAN;
    bool finished_ = false;
    std::vector<TraceEvent> events_;
    int64_t switches_ = 0, stages_run_ = 0;
    bool first_ran_ = false;
    int first_solver_ = 0;
    frix_info counters_;
    bool stopped_ = false;
};

// The islands of a local problem, each with its sub-problem (none when the problem is one
// island) and its solver.
struct Island {
    std::vector<int64_t> contacts;
    std::unique_ptr<frix_problem, void (*)(frix_problem *)> sub{nullptr, frix_problem_free};
    std::unique_ptr<IslandSolver> solver;
    std::vector<double> r;
    double error = INFINITY;
    double loosening = 1.0;  // its tolerance over the whole problem's (part_loosening)
    frix_error status = FRIX_OK;
    std::string message;  // the error message of a failed solve, from its thread
};

// How much looser than the whole problem's tolerance a part's may be: the whole problem's
// residual is the parts' in quadrature, and each part's error is relative to its own size,
// so a part whose |q_part| is small next to |q| may stop at a larger error of its own:
// |q| / (|q_part| sqrt(2 parts)) (the parts below that share give at most half of the whole
// residual's square), never below 1 and at most kMaxPartLoosening. The whole problem is
// measured after the parts; where it misses, the parts are solved again with their
// loosening shrunk by the miss, and then tighter.
constexpr double kMaxPartLoosening = 100.0;
double part_loosening(double norm_q, double part_norm_q, size_t parts) {
    const double share = part_norm_q * std::sqrt(2.0 * (double)parts);
    if (!(share > 0.0)) return kMaxPartLoosening;
    return std::clamp(norm_q / share, 1.0, kMaxPartLoosening);
}

// What a persistent solver keeps for auto (solve_cache.hpp): its parts' states (each part's
// stages reuse their analyses and factorisations), while W's pattern, and so the parts, stay;
// and for a global problem, the driver's states of the reduction auto runs (M's
// factorisation, W).
struct KeptAuto : CachedState {
    uint64_t w_pattern = 0;
    std::vector<std::vector<int64_t>> parts;
    std::vector<std::unique_ptr<SolveCache>> part_caches;
    SolveCache reduction;
};

// The cache of each part for this solve: the kept ones when the parts are those of the last
// solve on the same pattern, new ones otherwise; their W versions are the problem's.
void part_caches(KeptAuto &kept, const SolveCache &cache, const std::vector<std::vector<int64_t>> &parts) {
    if (kept.w_pattern != cache.w_pattern || kept.parts != parts) {
        kept.part_caches.clear();
        for (size_t k = 0; k < parts.size(); ++k) kept.part_caches.push_back(std::make_unique<SolveCache>());
        kept.parts = parts;
        kept.w_pattern = cache.w_pattern;
    }
    for (std::unique_ptr<SolveCache> &c : kept.part_caches) {
        c->w_values = cache.w_values;
        c->w_pattern = cache.w_pattern;
    }
}

// Plain NSGS on ctx's problem from ctx.r, before any part is set up: with sweeps = 0 the
// first stage of a problem that is one part of fewer than kPlainNsgsMaxContacts contacts (the
// rate watch, as IslandSolver::first_stage runs it), otherwise that many sweeps unwatched. Its
// sweeps are counted in `shared`, its record goes into the trace. Sets *converged; ctx holds
// its iterate, counters and measures either way.
frix_error direct_nsgs(SolveContext &ctx, Shared &shared, double tol, int64_t sweeps, bool *converged) {
    const frix_problem &p = ctx.problem;
    const frix_options &user = ctx.options;
    const SolverEntry &nsgs = *find_solver(FRIX_SOLVER_NSGS);
    const int64_t left = Monitor(user, ctx.clock).max_iterations();
    frix_options o;
    stage_options(nsgs, shared, tol, std::max<int64_t>(1, std::min(left / 2, sweeps > 0 ? sweeps : kFirstNsgsSweeps)), o);
    Watchdog dog;
    dog.shared = &shared;
    dog.kind = sweeps > 0 ? Watch::Stall : Watch::Rate;
    dog.patience = sweeps + 1;  // (the stall watch then only counts)
    dog.tolerance = tol;
    dog.min_sweeps = nsgs_min_sweeps(p.W->nblocks());
    o.callback = Watchdog::callback;
    o.callback_data = &dog;

    frix_info &info = ctx.info;
    info.status = FRIX_STATUS_NOT_RUN;
    info.iterations = 0;
    const double t0 = ctx.clock.seconds();
    SolveContext sub{p, o, ctx.r, ctx.u, nullptr, info, ctx.clock, nullptr, nullptr, nullptr};
    if (frix_error e = nsgs.solve(sub)) return e;
    ctx.has_measured = sub.has_measured;
    ctx.measured = sub.measured;
    const double err = selected_error(sub.has_measured ? sub.measured : local_measures(p, ctx.r, ctx.u),
                                      user.i(FRIX_OPT_ERROR_MEASURE));
    const TraceEvent ev = close_stage(FRIX_SOLVER_NSGS, info, dog, ctx.clock.seconds() - t0, err);
    info.trace.push_back(ev);
    log_event(shared, ev);
    *converged = err <= tol;
    if (info.status == FRIX_STATUS_STOPPED_BY_CALLBACK && !dog.stopped_by_watchdog) shared.stop_requested = true;
    return FRIX_OK;
}

frix_error solve_local(SolveContext &ctx) {
    const frix_problem &p = ctx.problem;
    const frix_options &user = ctx.options;
    frix_info &info = ctx.info;
    const double tol = Monitor(ctx).tolerance();
    Shared shared(user, ctx.clock);

    Analysis a = analyse_local(p);
    info.islands = a.islands;
    info.analysis.contacts = a.contacts;
    info.analysis.blocks = a.blocks;
    info.analysis.islands = a.islands;
    info.analysis.largest_island = a.largest_island;
    info.analysis.diag_min = a.diag_min, info.analysis.diag_max = a.diag_max;
    info.analysis.mu_min = a.mu_min, info.analysis.mu_max = a.mu_max;
    info.trace.push_back(trace_event(kAnalysis));
    shared.scaled_penalty = !(a.diag_max <= kScaledPenaltySpread * a.diag_min);
    // A small problem that is one part gets its first stage at once; a problem of several
    // parts first gets kWholeNsgsSweeps sweeps of plain NSGS on the whole of it, which end
    // many easy problems before the parts cost their setup (the parts go on from there).
    const bool several_parts = a.islands > 1 && a.largest_island >= kMinIslandContacts;
    const bool direct = p.nc < kPlainNsgsMaxContacts && !several_parts;
    if (direct || several_parts) {
        bool converged = false;
        if (frix_error e = direct_nsgs(ctx, shared, tol, several_parts ? kWholeNsgsSweeps : 0, &converged)) return e;
        if (converged || shared.stop_requested.load() || shared.out_of_time() || shared.out_of_iterations()) {
            info.iterations = shared.iterations.load();
            info.status = converged                        ? FRIX_STATUS_CONVERGED
                          : shared.stop_requested.load() ? FRIX_STATUS_STOPPED_BY_CALLBACK
                          : shared.out_of_time()         ? FRIX_STATUS_TIME_LIMIT
                                                         : FRIX_STATUS_MAX_ITER;
            return FRIX_OK;
        }
        ctx.has_measured = false;
    }
    // Taken after the direct run: a problem that it solves leaves the kept state in the cache
    // as it was.
    Kept<KeptAuto> kept(ctx.cache, FRIX_SOLVER_AUTO);

    // The units of work: every island of at least kMinIslandContacts contacts on its own, the
    // smaller ones together (one sub-problem, still block-diagonal): a sub-problem per tiny
    // island would cost more in setup than its solve.
    std::vector<std::vector<int64_t>> units = solve_units(a, kMinIslandContacts);
    if (ctx.cache) part_caches(*kept, *ctx.cache, units);
    if (direct && units.size() != 1) return fail(FRIX_ERR_INTERNAL, "auto: a direct first stage on %zu parts", units.size());
    std::vector<Island> islands(units.size());
    const bool whole = islands.size() == 1;
    for (size_t k = 0; k < islands.size(); ++k) {
        Island &is = islands[k];
        is.contacts = std::move(units[k]);
        const frix_problem *sub = &p;
        if (!whole) {
            if (frix_error e = extract_island(p, is.contacts, is.sub)) return e;
            sub = is.sub.get();
            is.r.resize(3 * is.contacts.size());
            for (size_t c = 0; c < is.contacts.size(); ++c)
                for (int d = 0; d < 3; ++d) is.r[3 * c + (size_t)d] = ctx.r[3 * is.contacts[c] + d];
        }
        is.solver = std::make_unique<IslandSolver>(*sub, shared, whole ? 0 : (int64_t)k + 1,
                                                   ctx.cache ? kept->part_caches[k].get() : nullptr);
        if (direct) is.solver->first_stage_ran(FRIX_SOLVER_NSGS);
    }
    if (!whole) {
        const double norm_q = norm2(p.q, 3 * p.nc);
        for (Island &is : islands)
            is.loosening = part_loosening(norm_q, norm2(is.sub->q, 3 * is.sub->nc), islands.size());
    }

    // Solve every island to `island_tol`; several at once when threads allow.
    auto solve_all = [&](double island_tol) {
        const int64_t threads = std::min<int64_t>(user.i(FRIX_OPT_THREADS), (int64_t)islands.size());
        for (int pass = 0;; ++pass) {
            const IslandSolver::Phase phase = pass == 0 ? IslandSolver::kFirst : IslandSolver::kRest;
            if (phase == IslandSolver::kRest &&
                std::none_of(islands.begin(), islands.end(), [](const Island &is) { return is.solver->active(); }))
                break;
            std::atomic<size_t> next{0};
            auto work = [&]() {
                for (size_t k = next++; k < islands.size(); k = next++) {
                    Island &is = islands[k];
                    double *r = whole ? ctx.r : is.r.data();
                    is.status = guard("frix_solve (auto)", [&] {
                        return is.solver->solve(phase, r, island_tol * is.loosening, &is.error);
                    });
                    // The message lives in this thread's error state: keep it for the caller's.
                    if (is.status != FRIX_OK) is.message = frix_last_error_message();
                }
            };
            if (threads <= 1) {
                work();
            } else {
                std::vector<std::thread> pool;
                for (int64_t t = 1; t < threads; ++t) pool.emplace_back(work);
                work();
                for (std::thread &t : pool) t.join();
            }
            for (const Island &is : islands)
                if (is.status != FRIX_OK) return fail(is.status, "%s", is.message.c_str());
        }
        return FRIX_OK;
    };

    // The parts' trace events, in part order, as far as they have been copied into info.
    std::vector<size_t> copied(islands.size(), 0);
    auto flush_events = [&]() {
        for (size_t k = 0; k < islands.size(); ++k) {
            const std::vector<TraceEvent> &ev = islands[k].solver->events();
            info.trace.insert(info.trace.end(), ev.begin() + (std::ptrdiff_t)copied[k], ev.end());
            copied[k] = ev.size();
        }
    };
    double island_tol = tol;
    Measures whole_measures;
    double error = INFINITY;
    for (int tightening = 0;;) {
        if (frix_error e = solve_all(island_tol)) return e;
        if (!whole)
            for (const Island &is : islands)
                for (size_t c = 0; c < is.contacts.size(); ++c)
                    for (int d = 0; d < 3; ++d) ctx.r[3 * is.contacts[c] + d] = is.r[3 * c + (size_t)d];
        if (whole) {  // the part's own measure is the whole problem's
            error = islands[0].error;
            ctx.has_measured = islands[0].solver->final_measures(&ctx.measured, ctx.u);
            break;
        }
        whole_measures = local_measures(p, ctx.r, ctx.u);
        error = selected_error(whole_measures, user.i(FRIX_OPT_ERROR_MEASURE));
        if (whole || error <= tol || tightening >= kMaxTightenings || shared.out_of_time() ||
            shared.stop_requested.load())
            break;
        bool all_met = true, loosened = false;
        for (const Island &is : islands) {
            all_met = all_met && is.error <= island_tol * is.loosening;
            loosened = loosened || is.loosening > 1.0;
        }
        if (!all_met) break;  // an island failed: tightening the others would not help
        if (loosened) {
            // The parts' shares misjudged the whole (their errors are relative to |r| and
            // |u| too, which |q| does not tell): first their loosening shrinks by the observed
            // ratio (and a margin), at least halving, down to the tolerance itself; each part
            // goes on from where it stopped.
            for (Island &is : islands) is.loosening = std::max(1.0, is.loosening * 0.5 * tol / error);
        } else {
            // The islands' relative errors are normalised by their own sizes; the whole
            // problem's by its own. Tighten by the observed ratio (and a margin).
            island_tol *= std::max(1e-3, 0.5 * tol / error);
            ++tightening;
        }
        flush_events();
        TraceEvent e = trace_event(kTighten);
        e.error = error;
        e.value = island_tol;
        info.trace.push_back(e);
    }
    flush_events();
    for (size_t k = 0; k < islands.size(); ++k) {
        info.switches += islands[k].solver->switches();
        Monitor::add_work(info, islands[k].solver->counters());
    }
    info.iterations = shared.iterations.load();
    bool stopped = shared.stop_requested.load();
    for (const Island &is : islands) stopped = stopped || is.solver->stopped();
    if (error <= tol)
        info.status = FRIX_STATUS_CONVERGED;
    else if (stopped)
        info.status = FRIX_STATUS_STOPPED_BY_CALLBACK;
    else if (shared.out_of_time())
        info.status = FRIX_STATUS_TIME_LIMIT;
    else if (shared.out_of_iterations())
        info.status = FRIX_STATUS_MAX_ITER;
    else
        info.status = FRIX_STATUS_STAGNATED;
    kept.keep();
    return FRIX_OK;
}

// When a solve failed (not stopped by the caller), whether a solution exists at all.
void check_existence_on_failure(SolveContext &ctx) {
    frix_info &info = ctx.info;
    if (info.status == FRIX_STATUS_CONVERGED || info.status == FRIX_STATUS_STOPPED_BY_CALLBACK ||
        !ctx.options.i(FRIX_OPT_EXISTENCE_CHECK))
        return;
    // Within the caller's time limit: what is left of it, and no check once it is spent
    // (frix solve then checks on its own, outside the solve).
    const double tl = ctx.options.d(FRIX_OPT_TIME_LIMIT);
    const double left = tl > 0.0 ? tl - ctx.clock.seconds() : 0.0;
    if (tl > 0.0 && left <= 0.0) return;
    double margin = NAN;
    info.existence = check_existence(ctx.problem, left, &margin);
    info.existence_margin = margin;
    info.trace.push_back(trace_event(kExistence));
}

// The reduction route's local step: the strategy above, not registered on its own.
frix_error solve_reduced(SolveContext &ctx) { return solve_local(ctx); }

frix_error solve(SolveContext &ctx);

const frix_option_key kExtraKeys[] = {FRIX_OPT_THREADS, (frix_option_key)0};
const OptionDefault kDefaults[] = {{FRIX_OPT_MAX_ITER, 1e9}, {(frix_option_key)0, 0.0}};

}  // namespace

#define FRIX_AUTO_DESCRIPTION                                                                       \
    "The default solver. Analyses the problem (sizes, the ranges of |W_aa| and mu, the islands: "   \
    "groups of contacts that do not interact, each large one solved as a part of its own, the "    \
    "small ones together, with threads > 1 at once), then runs on each part NSGS while its "       \
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
                                         solve_reduced, true, false, kExtraKeys, kDefaults};

namespace {

// A global answer (r, v) set aside while another route runs from elsewhere: the caller gets
// the better of the two by the global measure (the larger of the error and the equilibrium
// residual), as auto's local stages keep their best iterate.
struct GlobalAnswer {
    std::vector<double> r, v;
    double error, equilibrium;
    GlobalAnswer(const SolveContext &ctx, const frix_info &info)
        : r(ctx.r, ctx.r + 3 * ctx.problem.nc), v(ctx.v, ctx.v + ctx.problem.n), error(info.error),
          equilibrium(info.equilibrium) {}
    static double score(double error, double equilibrium) {
        const double s = std::max(error, equilibrium);
        return std::isfinite(s) ? s : INFINITY;
    }
    // Puts the set-aside (r, v) back, whatever the caller holds.
    void put_back(SolveContext &ctx) const {
        std::copy(r.begin(), r.end(), ctx.r);
        std::copy(v.begin(), v.end(), ctx.v);
    }
    // Puts the set-aside answer back where it is better than the one the route left, with its
    // error and equilibrium (the driver measures the answer returned again in full).
    void restore_if_better(SolveContext &ctx, frix_info &info) const {
        if (info.status == FRIX_STATUS_CONVERGED || !(score(error, equilibrium) < score(info.error, info.equilibrium)))
            return;
        std::copy(r.begin(), r.end(), ctx.r);
        std::copy(v.begin(), v.end(), ctx.v);
        info.error = error;
        info.equilibrium = equilibrium;
    }
};

// A solver of global problems (`entry`: 607, 613, 901) from ctx's (r, v), for at most
// max_iter iterations (and its own limit), on the caller's clock, tolerance, measure and
// callback: ctx.info becomes its info (status, counters, measures), `stage` its trace event.
// Converged is the driver's verdict on the returned (r, v) (error and equilibrium), whatever
// the solver's own stopping test said.
frix_error run_global(SolveContext &ctx, const SolverEntry &entry, int64_t max_iter, TraceEvent &stage,
                      SolveCache *reduction, Watchdog *dog = nullptr) {
    frix_options o;
    default_options(entry, o);
    o.ivalue[FRIX_OPT_MAX_ITER] = std::max<int64_t>(1, std::min(o.ivalue[FRIX_OPT_MAX_ITER], max_iter));
    o.dvalue[FRIX_OPT_TOLERANCE] = Monitor(ctx).tolerance();
    o.ivalue[FRIX_OPT_ERROR_MEASURE] = ctx.options.i(FRIX_OPT_ERROR_MEASURE);
    o.dvalue[FRIX_OPT_TIME_LIMIT] = ctx.options.d(FRIX_OPT_TIME_LIMIT);  // the same clock: the same deadline
    o.dvalue[FRIX_OPT_MEMORY_LIMIT] = ctx.options.d(FRIX_OPT_MEMORY_LIMIT);
    o.ivalue[FRIX_OPT_THREADS] = ctx.options.i(FRIX_OPT_THREADS);
    o.callback = ctx.options.callback;
    o.callback_data = ctx.options.callback_data;
    if (dog) {  // it passes the caller's callback on
        o.callback = &Watchdog::callback;
        o.callback_data = dog;
        if (entry.id == FRIX_SOLVER_GLOBAL_NSGS) o.ivalue[FRIX_OPT_DRIFT_WINDOW] = kDriftWindow;
    }
    o.log = ctx.options.log;
    o.log_data = ctx.options.log_data;
    frix_info run;
    run.solver_id = ctx.info.solver_id;
    run.contacts = ctx.info.contacts;
    run.tolerance = ctx.info.tolerance;
    run.analysis = ctx.info.analysis;
    const double t0 = ctx.clock.seconds();
    if (frix_error e = solve_global_problem(ctx.problem, o, entry, ctx.r, ctx.u, ctx.v, run, ctx.clock, reduction,
                                            ctx.mass))
        return e;
    if (meets_global_tolerance(run, Monitor(ctx).tolerance())) run.status = FRIX_STATUS_CONVERGED;
    stage.solver_id = entry.id;
    stage.status = run.status;
    stage.iterations = run.iterations;
    stage.seconds = ctx.clock.seconds() - t0;
    stage.error = run.error;
    ctx.info = std::move(run);
    return FRIX_OK;
}

// Where W would be dense: what the two routes are priced at, in flops of a factorisation.
// Forming W: its exact flops (SparseCholesky::congruence_cost), then kSweepsOnW sweeps over
// its blocks (18 flops each), memory-bound. Without W: one factorisation of M + rho H H^T
// (CHOLMOD's analysis of its pattern), then kWFreeIterations of ADMM, each two triangular
// solves with that factor (4 flops per entry of L), memory-bound too.
struct RoutePrices {
    double with_w = NAN, without_w = NAN, without_w_bytes = NAN;
};
bool price_w_free_route(const frix_problem &p, const linalg::FactorPrice &forming_w, double w_blocks,
                        RoutePrices *prices) {
    Csc M, H;
    MassPlusContacts system;
    linalg::FactorCost cost;
    if (to_csc(*p.M, M) || to_csc(*p.H, H) || system.build(M, H, p.nc, "auto") || system.cost(&cost)) {
        clear_error();
        return false;
    }
    prices->with_w = forming_w.flops + kMemoryBoundWork * kSweepsOnW * 18.0 * w_blocks;
    prices->without_w = cost.flops + kMemoryBoundWork * kWFreeIterations * 4.0 * cost.factor_entries;
    prices->without_w_bytes = cost.bytes;
    return true;
}

// The route without W: ADMM on (v, r) (613) with at most kWFreeAdmmShare of max_iter, then,
// where it misses the tolerance, the augmented Lagrangian Newton (901) from its result with
// the rest. ctx.info becomes the route's info, `trace` gets its stages.
frix_error w_free_route(SolveContext &ctx, int64_t max_iter, SolveCache *reduction, std::vector<TraceEvent> &trace) {
    frix_info &info = ctx.info;
    const AnalysisSummary analysis = info.analysis;
    TraceEvent admm = trace_event(kStage);
    if (frix_error e = run_global(ctx, kGlobalAdmmEntry, std::clamp<int64_t>(max_iter / 2, 1, kWFreeAdmmIterations),
                                  admm, reduction))
        return e;
    trace.push_back(admm);
    const double tl = ctx.options.d(FRIX_OPT_TIME_LIMIT);
    const int64_t left = max_iter - info.iterations;
    if (info.status == FRIX_STATUS_CONVERGED || info.status == FRIX_STATUS_STOPPED_BY_CALLBACK ||
        (tl > 0.0 && ctx.clock.seconds() >= tl) || left <= 0) {
        info.analysis = analysis;
        return FRIX_OK;
    }
    const frix_info before = info;
    const int64_t iterations = info.iterations;
    const GlobalAnswer admm_answer(ctx, info);
    TraceEvent newton = trace_event(kStage);
    if (frix_error e = run_global(ctx, kGlobalAlNewtonEntry, std::min(left, kWFreeNewtonSteps), newton, reduction))
        return e;
    admm_answer.restore_if_better(ctx, info);
    trace.push_back(newton);
    Monitor::add_work(info, before);
    info.analysis = analysis;
    info.iterations += iterations;
    info.switches += 1;
    return FRIX_OK;
}

frix_error reduce_then_newton(SolveContext &ctx, int64_t max_iter, int64_t reduction_iter, SolveCache *cache);

// After a route that missed the tolerance: the reduction route with `left` iterations, from
// `from` (null: from the route's answer), the better of the two answers kept; ctx.info sums
// both routes' work, `trace` gets the reduction's stages.
frix_error reduce_after(SolveContext &ctx, int64_t left, SolveCache *cache, const GlobalAnswer *from,
                        std::vector<TraceEvent> &trace) {
    frix_info &info = ctx.info;
    const frix_info before = info;
    const GlobalAnswer answer(ctx, info);
    if (from) from->put_back(ctx);
    if (frix_error e = reduce_then_newton(ctx, left, left / 2, cache)) return e;
    answer.restore_if_better(ctx, info);
    trace.insert(trace.end(), info.trace.begin(), info.trace.end());
    Monitor::add_work(info, before);
    info.iterations += before.iterations;
    info.switches += before.switches + 1;
    return FRIX_OK;
}

// Rigid bodies whose W would be large and hold more entries than M^-1 H: NSGS without W
// (gnsgs, the caller's threads) with half the iterations, under the NSGS rate watch from
// kProductPatience sweeps on; where it misses the tolerance, the reduction route from its
// answer with what is left. ctx.info becomes the route's info, `trace` gets its stages.
frix_error product_then_reduce(SolveContext &ctx, int64_t max_iter, bool may_reduce, SolveCache *cache,
                               std::vector<TraceEvent> &trace) {
    frix_info &info = ctx.info;
    const AnalysisSummary analysis = info.analysis;
    Shared shared(ctx.options, ctx.clock);
    Watchdog dog;
    dog.shared = &shared;
    dog.kind = Watch::Rate;
    dog.min_sweeps = kProductPatience;
    dog.tolerance = Monitor(ctx).tolerance();
    TraceEvent stage = trace_event(kStage);
    if (frix_error e = run_global(ctx, kGlobalNsgsEntry, std::max<int64_t>(1, max_iter / 2), stage, cache, &dog))
        return e;
    stage.why = dog.stopped_by_watchdog ? dog.why : nullptr;
    trace.push_back(stage);
    info.analysis = analysis;
    const double tl = ctx.options.d(FRIX_OPT_TIME_LIMIT);
    const int64_t left = max_iter - info.iterations;
    if (info.status == FRIX_STATUS_CONVERGED || shared.stop_requested.load() || !may_reduce ||
        (tl > 0.0 && ctx.clock.seconds() >= tl) || left <= 0) {
        if (info.status == FRIX_STATUS_STOPPED_BY_CALLBACK && dog.stopped_by_watchdog) info.status = FRIX_STATUS_STAGNATED;
        return FRIX_OK;
    }
    return reduce_after(ctx, left, cache, nullptr, trace);
}

// The reduction route on a global problem: the local strategy on W = H^T M^-1 H with
// `reduction_iter` of the `max_iter` iterations, then, where the global measure (error and
// equilibrium) is not met, Newton on (v, r) from its result with what is left. ctx.info
// becomes the route's info; the existence check is the caller's.
frix_error reduce_then_newton(SolveContext &ctx, int64_t max_iter, int64_t reduction_iter, SolveCache *cache) {
    const frix_problem &p = ctx.problem;
    frix_info &info = ctx.info;
    const double tol = Monitor(ctx).tolerance(), tl = ctx.options.d(FRIX_OPT_TIME_LIMIT);
    frix_options reduction = ctx.options;
    reduction.ivalue[FRIX_OPT_MAX_ITER] = std::max<int64_t>(1, reduction_iter);
    const AnalysisSummary global_analysis = info.analysis;
    frix_info reduced;
    reduced.solver_id = info.solver_id;
    reduced.contacts = info.contacts;
    reduced.tolerance = info.tolerance;
    if (frix_error e = solve_global_problem(p, reduction, kAutoReductionEntry, ctx.r, ctx.u, ctx.v, reduced,
                                            ctx.clock, cache, ctx.mass))
        return e;
    info = std::move(reduced);
    info.analysis.dofs = global_analysis.dofs;
    info.analysis.rank_ratio = global_analysis.rank_ratio;
    info.analysis.reduced_entries = global_analysis.reduced_entries;
    info.analysis.input_entries = global_analysis.input_entries;
    // The reduced problem's own tolerance test is not the global one: the global measure of
    // (r, v) decides, both ways.
    if (meets_global_tolerance(info, tol)) info.status = FRIX_STATUS_CONVERGED;
    if (info.status == FRIX_STATUS_CONVERGED || info.status == FRIX_STATUS_STOPPED_BY_CALLBACK) return FRIX_OK;
    const int64_t left = max_iter - info.iterations;
    if ((tl > 0.0 && ctx.clock.seconds() >= tl) || left <= 0) return FRIX_OK;
    std::vector<TraceEvent> trace = std::move(info.trace);
    TraceEvent fallback = trace_event(kGlobalFallback);
    fallback.status = info.status;
    fallback.error = info.error;
    fallback.value = info.equilibrium;
    fallback.solver_id = FRIX_SOLVER_GLOBAL_NSN_AC;
    trace.push_back(fallback);
    const AnalysisSummary analysis = info.analysis;
    const int64_t islands = info.islands, switches = info.switches + 1, iterations = info.iterations;
    const frix_info before = info;
    const GlobalAnswer reduced_answer(ctx, info);
    TraceEvent stage = trace_event(kStage);
    if (frix_error e = run_global(ctx, kGlobalNsnAcEntry, left, stage, cache)) return e;
    reduced_answer.restore_if_better(ctx, info);
    trace.push_back(stage);
    Monitor::add_work(info, before);
    info.trace = std::move(trace);
    info.analysis = analysis;
    info.islands = islands;
    info.switches = switches;
    info.iterations += iterations;
    return FRIX_OK;
}

frix_error solve(SolveContext &ctx) {
    if (ctx.problem.kind != FRIX_PROBLEM_GLOBAL) {
        if (frix_error e = solve_local(ctx)) return e;
        check_existence_on_failure(ctx);
        return FRIX_OK;
    }
    // Global: the reduction route with the local strategy, then, if that fails, Newton on
    // (v, r) from its result. The two share the caller's max_iter: the reduction route gets
    // half (as every stage of the local strategy, see run_stage), Newton on (v, r) the rest.
    // Where forming a dense W (deformable bodies) would overrun the time or memory limit,
    // Newton on (v, r) alone.
    const frix_problem &p = ctx.problem;
    frix_info &info = ctx.info;
    // A persistent solver keeps the driver's states of the reductions below (their own
    // cache, which follows the versions of the caller's M and H).
    Kept<KeptAuto> kept(ctx.cache, FRIX_SOLVER_AUTO);
    kept.keep();
    SolveCache *reduction = nullptr;
    if (ctx.cache) {
        reduction = &kept->reduction;
        reduction->m_values = ctx.cache->m_values;
        reduction->h_values = ctx.cache->h_values;
    }
    const ReductionSize size = reduction_size(p);
    info.analysis.dofs = p.n;
    info.analysis.contacts = p.nc;
    info.analysis.rank_ratio = p.n > 0 ? 3.0 * (double)p.nc / (double)p.n : 0.0;
    info.analysis.reduced_entries = size.w_entries;
    info.analysis.input_entries = size.input_entries;
    const int64_t max_iter = Monitor(ctx).max_iterations();
    frix_status reduction_refused = FRIX_STATUS_NOT_RUN;  // the limit forming W would overrun
    RoutePrices prices;
    bool w_free = false;  // the route without W is priced below forming W, and fits
    if (size.w_entries > kReductionMaxEntries && size.w_entries > kReductionMaxGrowth * size.input_entries) {
        linalg::FactorPrice price;
        if (ctx.mass && ctx.mass->congruence_price(*p.H, &price)) {
            reduction_refused = Monitor(ctx).affords(price);
            w_free = price_w_free_route(p, price, size.w_blocks, &prices) &&
                     Monitor(ctx).fits_memory(prices.without_w_bytes) &&
                     (reduction_refused || prices.without_w < prices.with_w);
            if (ctx.options.i(FRIX_OPT_VERBOSITY) >= 1)
                log_line(&ctx.options, "auto: forming W priced %.3g flops, the route without W %.3g", prices.with_w,
                         prices.without_w);
        } else {
            // Not priced (M factorised by LU): W's blocks against the memory alone.
            if (!reduction_memory(size, Monitor(ctx)).fits) reduction_refused = FRIX_STATUS_MEMORY_LIMIT;
        }
    }
    // Rigid bodies with a large W: W's entries against M^-1 H's.
    const bool product = !w_free && size.largest_component <= nsgs::kMaxRigidBodyDofs &&
                         size.w_entries > kReductionMaxEntries && size.w_entries > size.product_entries;
    if (product) {
        std::vector<TraceEvent> trace;
        if (frix_error e = product_then_reduce(ctx, max_iter, !reduction_refused, reduction, trace)) return e;
        info.trace = std::move(trace);
        check_existence_on_failure(ctx);
        return FRIX_OK;
    }
    if (!reduction_refused && !w_free) {
        if (frix_error e = reduce_then_newton(ctx, max_iter, max_iter / 2, reduction)) return e;
        check_existence_on_failure(ctx);
        return FRIX_OK;
    }
    TraceEvent direct = trace_event(kGlobalDirect);
    direct.status = reduction_refused;
    direct.value = prices.with_w / prices.without_w;
    std::vector<TraceEvent> trace;
    if (w_free) {
        // W is not formed: ADMM on (v, r), then Newton on v, both on M + H S H^T. Where they
        // miss the tolerance (a body so stiff that M's rounding bounds the equilibrium of their
        // answer) and forming W fits the limits, the reduction from their answer.
        direct.solver_id = FRIX_SOLVER_GLOBAL_ADMM;
        const GlobalAnswer start(ctx, info);
        if (frix_error e = w_free_route(ctx, max_iter, reduction, trace)) return e;
        const double tl = ctx.options.d(FRIX_OPT_TIME_LIMIT);
        const int64_t left = max_iter - info.iterations;
        if (info.status != FRIX_STATUS_CONVERGED && info.status != FRIX_STATUS_STOPPED_BY_CALLBACK &&
            !reduction_refused && !(tl > 0.0 && ctx.clock.seconds() >= tl) && left > 0) {
            TraceEvent after = trace_event(kGlobalReduceAfter);
            after.status = info.status;
            after.error = info.error;
            after.value = info.equilibrium;
            trace.push_back(after);
            // From the caller's start, not from that answer: on such a body r is far from
            // unique, and the reduction's own path leads where the equilibrium's rounding is
            // smaller relative to H r.
            if (frix_error e = reduce_after(ctx, left, reduction, &start, trace)) return e;
        }
    } else {
        // Forming W would overrun a limit, and M + H H^T has no Cholesky factor or would not
        // fit either: Newton on (v, r) alone, whose answer is what there is.
        direct.solver_id = FRIX_SOLVER_GLOBAL_NSN_AC;
        TraceEvent stage = trace_event(kStage);
        if (frix_error e = run_global(ctx, kGlobalNsnAcEntry, max_iter, stage, reduction)) return e;
        trace.push_back(stage);
    }
    trace.insert(trace.begin(), direct);
    info.trace = std::move(trace);
    check_existence_on_failure(ctx);
    return FRIX_OK;
}

}  // namespace

}  // namespace autosolve

const SolverEntry kAutoEntry = {FRIX_SOLVER_AUTO,          "auto", nullptr, FRIX_AUTO_DESCRIPTION,
                                autosolve::solve,          true,   true,    autosolve::kExtraKeys,
                                autosolve::kDefaults};

}  // namespace frix
