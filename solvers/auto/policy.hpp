// auto's tuning: every constant of its strategy, each with its rule and why. The measurements
// behind them: notes/2026-11-25-auto-constants.md (the first rounds, islands, the reduction),
// notes/2026-11-26-auto-at-simulation-tolerance.md (prices, ADMM's probe, plateaus, the parts'
// shares), notes/2026-11-26-solvers-without-w.md and notes/2026-11-26-scale.md (the routes of
// global problems).
// Every rule counts iterations, never seconds: without a time limit the result does not
// depend on the machine's speed or load.
#pragma once

#include <frix/frix_registry.h>

#include <cstdint>

namespace frix::autosolve {

// ---- Rolling friction (notes/2026-11-28-rolling.md)

// rolling-nsgs alone down to this error: it gets there in tens of sweeps on sphere piles,
// where the Newton polish would not pay.
constexpr double kRollingLoose = 1e-4;
// The rolling-nsn polish's Newton steps at most (one factorisation each): where W has full
// rank it converges in about ten; on rigid piles it stalls, and the sweeps take over again.
constexpr int64_t kRollingNewtonSteps = 20;
// Where the sweeps reached kRollingLoose they go on at their own rate, and the polish is a
// probe: it ends after this many steps in a row that creep (Watch::Newton; its steps are
// Newton steps, or proximal steps once rolling-nsn reports measured errors). Damped steps that
// creep cost a factorisation each, as much as hundreds of sweeps on a pile. Where the sweeps
// did not get there, the polish keeps its steps: a Newton from far creeps for a few steps
// before it converges.
constexpr int64_t kRollingNewtonSlowSteps = 2;
// A Newton step creeps where it leaves the best error above this many times the best before.
constexpr double kNewtonSlowStepRatio = 0.9;

// ---- NSGS's first stage (notes/2026-11-25-auto-constants.md)

// NSGS goes on while the rate of its second half predicts the tolerance within this many
// times the sweeps it has already run: giving up late wastes at most a constant share.
constexpr double kNsgsPatience = 3.0;
// It is not judged before this many sweeps nor this much work (sweeps x W blocks): judged too
// early, it hands a problem it was about to solve to the costlier stages.
constexpr int64_t kNsgsMinSweeps = 30;
constexpr double kNsgsMinWork = 1e5;
// The first NSGS stage's sweep limit (the NSGS default).
constexpr int64_t kFirstNsgsSweeps = 20000;
// A part of fewer contacts starts with plain NSGS (500), unfrozen, before it is set up (where
// the problem is one part): the velocity form's setup costs more than the few sweeps it needs,
// and freezing at a loose tolerance can trap the sweeps in a cycle
// (notes/2026-11-26-auto-at-simulation-tolerance.md).
constexpr int64_t kPlainNsgsMaxContacts = 64;
// A problem of several parts first gets this many sweeps of plain NSGS on the whole of it:
// they end many easy problems before the parts cost their setup (same note).
constexpr int64_t kWholeNsgsSweeps = 30;

// ---- The rounds (notes/2026-11-25-auto-constants.md)

// A stage of the rounds is stopped when its best error has not fallen tenfold within half its
// iterations so far, and at least within `patience` of them.
struct StageSpec {
    int solver_id;
    int64_t patience;      // iterations as the solver's callback counts them
    int64_t first_budget;  // iterations of the first round; doubled every round
};
// Newton (a few steps tell whether it converges), NSGS (velocity form, one chain over the
// rounds: its progress on piles is a drift a restart would undo), ADMM, PROX. NSGS gets five
// times ADMM's iterations: a sweep costs about a fifth of an ADMM iteration. PROX's callback
// counts its inner Newton steps, its budget proximal steps.
constexpr StageSpec kRound[] = {
    {FRIX_SOLVER_NSN_AC, 50, 100},  // its iterations count the hybrid NSGS sweeps too
    {FRIX_SOLVER_NSGS_VELOCITY, 10000, 10000},
    {FRIX_SOLVER_ADMM, 3000, 2000},
    {FRIX_SOLVER_PROX, 200, 3},
};
// NSGS's stages carry steady drifts of r ahead every this many sweeps (option drift_window):
// they cross the plateaus of piles; the window matters little between 1000 and 20000.
constexpr int64_t kDriftWindow = 1000;
// The sweeps' Anderson depth (option anderson) on a W that may be regular: the last ten sweeps
// span the slow modes of an elastic body's contacts; deeper mixes gain a sweep or two.
constexpr int64_t kRegularWAndersonDepth = 10;
// Without a deadline, this many rounds in a row without halving the error end the sequence.
constexpr int kMaxIdleRounds = 3;
// When max |W_aa| / min |W_aa| exceeds this, ADMM scales its penalty per contact
// (rho_strategy spectral): one penalty needs many times the iterations over decades of stiffness.
constexpr double kScaledPenaltySpread = 100.0;

// ---- The interior-point stage (notes/2026-11-25-auto-constants.md,
// notes/2026-11-26-auto-at-simulation-tolerance.md)

// Parts of at least this many contacts start round 0 with the IPM (524), which gets within
// Newton's reach in tens of factorisations where Newton from NSGS's iterate stalls.
constexpr int64_t kIpmMinContacts = 200;
// Smaller parts get it, after kNewtonProbeSteps of Newton from r = 0, at a tolerance this
// loose or looser: its few factorisations reach it either way, Newton's end wins tighter.
constexpr double kIpmLooseTolerance = 1e-6;
constexpr int64_t kNewtonProbeSteps = 10;
// Its patience and budget count interior points and then Newton steps.
constexpr StageSpec kIpmStage = {FRIX_SOLVER_IPM, 50, 500};
// The rounds go on from its result only within this factor of the tolerance: from farther,
// they take a longer path than from NSGS's (the result is set aside, not lost).
constexpr double kIpmKeepRatio = 100.0;

// ---- ADMM weighed against NSGS and the IPM (notes/2026-11-26-auto-at-simulation-tolerance.md)

// ADMM under the rate watch is judged on its best error from this many iterations on, and
// runs at most this many.
constexpr int64_t kAdmmMinIterations = 50;
constexpr int64_t kAdmmRateBudget = 100000;
// NSGS is weighed against ADMM's factorisation and this many of its iterations...
constexpr double kAdmmExpectedIterations = 300.0;
// ... and first against a probe of ADMM: its factorisation and this many iterations.
constexpr double kAdmmProbeIterations = 100.0;
// NSGS within this factor of the tolerance when the probe ends goes on for at least the
// probe's work: a rate says nothing on a plateau, which ends when a contact changes status.
constexpr double kPlateauRatio = 10.0;
// NSGS stopped by its rate within this factor goes on for the probe's work before the probe:
// so close, the plateau usually ends in fewer sweeps than the probe and NSGS after it cost.
constexpr double kNearPlateauRatio = 3.0;
// On a priced part a first-order stage goes on while its rate predicts the tolerance below
// its alternative's price, or within this multiple of its own work: giving up late costs at
// most the alternative once more.
constexpr double kPricedPatience = 2.0;
// Nor is it judged before it has cost this share of the alternative: its early rate says little.
constexpr double kJudgeShare = 0.1;

// ---- Prices, in the work of one 3x3 block of W times a vector
// (notes/2026-11-26-auto-at-simulation-tolerance.md). Known before anything runs (sizes and
// CHOLMOD's symbolic analysis), so that the choices do not depend on the machine.

// One contact's local solve in an NSGS sweep or an ADMM projection.
constexpr double kContactWork = 4.0;
// A scalar flop of a sparse factorisation or solve: dense kernels on supernodes run many
// flops per memory access, a block product few.
constexpr double kFactorFlopWork = 1.0 / 12.0;
// Factorisations of W's size an interior-point stage makes on its way to a solution.
constexpr double kIpmFactorizations = 50.0;

// ---- Random restarts and polish (notes/2026-11-25-auto-constants.md)

// Newton from random starts on parts up to this size: the chance that a start lands in the
// solution's basin falls with the size.
constexpr int64_t kRestartMaxContacts = 64;
// Any fixed seed: the results must not depend on the run.
constexpr uint64_t kRestartSeed = 0x6672697872657374ull;
// Polish: parts up to this size get this many PROX steps towards this share of the tolerance.
constexpr int64_t kPolishMaxContacts = 64;
constexpr int64_t kPolishSteps = 10;
constexpr double kPolishRatio = 1e-3;

// ---- Parts (notes/2026-11-25-auto-constants.md, notes/2026-11-26-auto-at-simulation-tolerance.md)

// Islands smaller than this are solved together: a sub-problem each would cost more in
// setup than its solve.
constexpr int64_t kMinIslandContacts = 16;
// A part's tolerance is at most this many times looser than the whole problem's (its share
// of |q|, see part_loosening).
constexpr double kMaxPartLoosening = 100.0;
// Tightenings of the parts' tolerance when their combined error misses the tolerance (after
// the passes that shrink their loosening, which are not counted).
constexpr int kMaxTightenings = 4;

// ---- Global problems (notes/2026-11-25-auto-constants.md, notes/2026-11-26-solvers-without-w.md)

// Where W = H^T M^-1 H would have more entries than this and than kReductionMaxGrowth times
// those of M and H (a deformable body makes W dense), forming it is priced first: when it
// would overrun the time or memory limit, a route that never forms W goes first.
constexpr double kReductionMaxEntries = 1e6;
constexpr double kReductionMaxGrowth = 20.0;
// The route without W is taken when priced below forming W: memory-bound flops count this many
// times a factorisation's; this many sweeps over W, or ADMM iterations without it, are what
// either takes to a tight tolerance on elastic bodies.
constexpr double kMemoryBoundWork = 3.0;
constexpr double kSweepsOnW = 30.0;
constexpr double kWFreeIterations = 50.0;
// Its stages stop at these counts (ADMM iterations, augmented Lagrangian Newton steps), far
// past what they take where they work: where they do not, the reduction still gets its turn.
constexpr int64_t kWFreeAdmmIterations = 1000, kWFreeNewtonSteps = 50;
// Where gnsn-ac finishes (a deformable body), ADMM stops at this count: the grids ADMM solves
// take 30-110 iterations; on stiff ones it is at 1e-4-1e-5 here, and gnsn-ac ends in 1-3 steps
// (notes/2026-11-29-rolling-sweeps-and-w-free-finish.md).
constexpr int64_t kWFreeAdmmBeforeNewton = 200;
// Rigid bodies with a large W: gnsgs is judged by its rate only after this many sweeps, since
// forming W costs as much as many sweeps (notes/2026-11-26-scale.md). With momentum (option
// acceleration) its error rises and falls while it converges: then only after
// nsgs::kMomentumPatience sweeps (solvers/kit/sweeps.hpp), as long as momentum itself waits
// (notes/2026-11-28-settled-piles.md).
constexpr int64_t kProductPatience = 200;

}  // namespace frix::autosolve
