// auto's strategy on one part (an island, the small islands together, or the whole problem):
// NSGS first, then rounds of the other stages with budgets that double, each stage built as
// a StageRequest by one of the rules below.
#pragma once

#include <cstdint>
#include <vector>

#include "solvers/auto/stage.hpp"

namespace frix::autosolve {

class IslandSolver {
   public:
    // cache: the part's states kept by a persistent solver (null for a one-shot solve).
    IslandSolver(const frix_problem &p, Shared &shared, int64_t island, SolveCache *cache);

    // Phase kFirst runs the first NSGS stage, phase kRest one round of the others: every
    // part gets its cheap chance before any part gets a long one, and the parts take their
    // rounds in turn (with a time limit, a hard part must not starve the others).
    enum Phase { kFirst, kRest };

    // Whether another round may help this part.
    bool active() const;
    // r: the part's reactions (warm start in, best iterate out); *best_error: the best error
    // reached (the measure selected by the caller's options, on this part).
    frix_error solve(Phase phase, double *r, double tolerance, double *best_error);
    // The measures of the r that solve() last returned, with u = W r + q copied into `u`,
    // when they are at hand (the stage that found it was the last to use the part's u).
    bool final_measures(Measures *m, double *u) const;
    // The part's u at r is known: W r + q = u, its measures m (the caller measured r, the
    // warm start of solve(kFirst), which then does not measure it again).
    void know_start(const double *r, const double *u, const Measures &m);
    // The first stage ran before this part was set up (direct_nsgs: solver `id`, its record
    // in the trace, its iterate the warm start of solve(kFirst)), which then goes on from there.
    void first_stage_ran(int id);

    const std::vector<TraceEvent> &events() const { return events_; }
    // The part's work: the stages' counters and the switches between them.
    const frix_info &ledger() const { return ledger_; }
    // Whether the caller's callback stopped one of its stages.
    bool stopped() const { return stopped_; }

   private:
    double measure(const double *r);
    double error_of(const Measures &m) const;
    // Whether u_ holds W r + q (its measures u_measures_), and the note that it does.
    bool u_holds(const double *r) const;
    void u_now_at(const double *r, const Measures &m);
    void note(TraceEvent e);
    bool can_continue() const;

    frix_error first_stage(double *r);
    frix_error probe_admm(double *r, const StageOutcome &nsgs, const StageCosts &c);
    frix_error run_round(double *r);
    frix_error opening_stages(double *r, bool &cut_short);
    frix_error ipm_stage(double *r, bool &cut_short);
    frix_error round_stages(double *r, bool &cut_short);
    void close_round(double before, bool cut_short);
    frix_error random_restarts(const StageSpec &spec, double *r, bool &cut_short);
    void draw_start(double *r);
    frix_error polish(double *r);

    StageRequest rate(int solver, int64_t budget) const { return rate_request(solver, budget, tolerance_); }
    StageRequest stall(int solver, int64_t patience, int64_t budget) const {
        return stall_request(solver, patience, budget, tolerance_);
    }
    // A stage recorded in the trace (every stage after the part's first is a switch); `out`,
    // when given, gets what it did.
    frix_error stage(const StageRequest &req, double *r, StageOutcome *out = nullptr);
    // A stage of this round: `cut_short` also tells whether the caller's max_iter cut it.
    frix_error round_stage(const StageRequest &req, double *r, bool &cut_short);
    // A stage's work, not yet recorded: the best iterate and the counters follow it.
    frix_error run(const StageRequest &req, double *r, StageOutcome &out);
    void record(const TraceEvent &ev);
    bool fits_memory(double StageCosts::*bytes);
    const StageCosts *prices();

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
    // Where u_ = W r + q is known: at r = u_r_, with measures u_measures_ (a stage from there
    // takes them instead of measuring its start again; so does the driver, for the r returned).
    std::vector<double> u_r_;
    Measures u_measures_;
    bool u_known_ = false;
    bool returned_best_ = false;  // whether solve() last returned best_r_ (not the held result)
    int best_solver_ = 0;       // the stage that found the best iterate
    uint64_t rng_;              // random restarts: seeded by the part, so threads do not matter
    double start_scale_ = 0.0;  // of the random starts (draw_start); 0 until first needed
    int round_ = 0, idle_rounds_ = 0;
    StageCosts costs_;
    bool priced_ = false;
    bool finished_ = false;
    std::vector<TraceEvent> events_;
    int64_t stages_run_ = 0;
    bool first_ran_ = false;
    int first_solver_ = 0;
    frix_info ledger_;
    bool stopped_ = false;
};

}  // namespace frix::autosolve
