// auto's strategy on one part (part.hpp). Each rule builds the StageRequest of its stage; what
// a stage did comes back in its StageOutcome.
#include "solvers/auto/part.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "src/error_state.hpp"
#include "src/random.hpp"

namespace frix::autosolve {

namespace {

constexpr double kTwoPi = 6.283185307179586;  // M_PI is POSIX, not C++

}  // namespace

IslandSolver::IslandSolver(const frix_problem &p, Shared &shared, int64_t island, SolveCache *cache)
    : p_(p), shared_(shared), island_(island), cache_(cache), m_(3 * p.nc), u_((size_t)m_), best_r_((size_t)m_),
      rng_(kRestartSeed + (uint64_t)island) {}

bool IslandSolver::active() const {
    return !finished_ && !(best_error_ <= tolerance_) && !shared_.stop_requested.load() &&
           !shared_.out_of_iterations() && !shared_.out_of_time();
}

frix_error IslandSolver::solve(Phase phase, double *r, double tolerance, double *best_error) {
    if (phase == kFirst) {
        tolerance_ = tolerance;
        round_ = idle_rounds_ = 0;
        finished_ = false;
        std::copy(r, r + m_, best_r_.begin());
        held_error_ = INFINITY;
        // From r = 0 the first stage measures its own start; a warm start is measured
        // here, since it may already be the answer (a tightened pass over the parts).
        if (std::any_of(r, r + m_, [](double x) { return x != 0.0; }))
            best_error_ = u_holds(r) ? error_of(u_measures_) : measure(r);
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

bool IslandSolver::final_measures(Measures *m, double *u) const {
    if (!returned_best_ || !u_holds(best_r_.data())) return false;
    *m = u_measures_;
    std::copy(u_.begin(), u_.end(), u);
    return true;
}

void IslandSolver::know_start(const double *r, const double *u, const Measures &m) {
    std::copy(u, u + m_, u_.begin());
    u_now_at(r, m);
}

void IslandSolver::first_stage_ran(int id) {
    first_ran_ = true;
    first_solver_ = id;
    ++stages_run_;
}

// The part's error at r (a non-finite one counts as infinite).
double IslandSolver::measure(const double *r) {
    u_now_at(r, local_measures(p_, r, u_.data()));
    return error_of(u_measures_);
}

double IslandSolver::error_of(const Measures &m) const {
    const double e = selected_error(m, shared_.user.i(FRIX_OPT_ERROR_MEASURE));
    return std::isfinite(e) ? e : INFINITY;
}

// Bit for bit: the r of a stage is a copy of one the part kept, or the stage's own result.
bool IslandSolver::u_holds(const double *r) const {
    return u_known_ && std::memcmp(r, u_r_.data(), sizeof(double) * (size_t)m_) == 0;
}

void IslandSolver::u_now_at(const double *r, const Measures &m) {
    u_r_.assign(r, r + m_);
    u_measures_ = m;
    u_known_ = true;
}

void IslandSolver::note(TraceEvent e) {
    e.island = island_;
    e.island_contacts = island_ > 0 ? p_.nc : 0;
    events_.push_back(e);
    log_event(shared_, e);
}

bool IslandSolver::can_continue() const {
    return !(best_error_ <= tolerance_) && !shared_.out_of_time() && !shared_.out_of_iterations() &&
           !shared_.stop_requested.load();
}

// NSGS first (velocity form, freezing; plain on a small part) under its rate watch: it
// finishes the easy problems at once. On a priced part it is first weighed against a probe of
// ADMM (its factorisation and kAdmmProbeIterations iterations): which of the two reaches the
// tolerance first depends on the tolerance and the problem, which a few iterations of each tell.
frix_error IslandSolver::first_stage(double *r) {
    if (p_.nc < kPlainNsgsMaxContacts) return stage(rate(FRIX_SOLVER_NSGS, kFirstNsgsSweeps), r);
    const StageCosts *c = prices();
    if (!c || !fits_memory(&StageCosts::admm_bytes)) return stage(rate(FRIX_SOLVER_NSGS_VELOCITY, kFirstNsgsSweeps), r);
    StageRequest weighed = rate(FRIX_SOLVER_NSGS_VELOCITY, kFirstNsgsSweeps);
    weighed.alternative_work = c->admm_setup + kAdmmProbeIterations * c->admm_iteration;
    weighed.patient = false;
    StageOutcome nsgs;
    if (frix_error e = stage(weighed, r, &nsgs)) return e;
    // NSGS stopped within kNearPlateauRatio of the tolerance first goes on for the probe's
    // work: there its rate says little, and the probe, then NSGS again, would cost more.
    if (nsgs.slow && can_continue() && nsgs.event.error <= kNearPlateauRatio * tolerance_) {
        weighed.min_work = weighed.alternative_work;
        if (frix_error e = stage(weighed, r, &nsgs)) return e;
    }
    // NSGS that gained nothing predicts nothing to weigh ADMM against: the rounds decide.
    if (!nsgs.slow || !std::isfinite(nsgs.predicted_work) || !can_continue()) return FRIX_OK;
    return probe_admm(r, nsgs, *c);
}

// ADMM from r = 0, weighed against what NSGS's rate predicted; where ADMM is the slower, NSGS
// goes on from where it stopped under its usual watch (and ADMM runs again in round 0,
// weighed against the IPM).
frix_error IslandSolver::probe_admm(double *r, const StageOutcome &nsgs, const StageCosts &c) {
    const std::vector<double> nsgs_r(r, r + m_);
    StageRequest admm = rate(FRIX_SOLVER_ADMM, kAdmmRateBudget);
    admm.alternative_work = nsgs.predicted_work;
    admm.patient = false;
    std::fill(r, r + m_, 0.0);
    StageOutcome probe;
    if (frix_error e = stage(admm, r, &probe)) return e;
    if (!can_continue()) return FRIX_OK;
    std::copy(nsgs_r.begin(), nsgs_r.end(), r);
    // NSGS within kPlateauRatio of the tolerance gets at least the probe's work before it is
    // judged again: each of the two then has had the same chance.
    StageRequest again = rate(FRIX_SOLVER_NSGS_VELOCITY, kFirstNsgsSweeps);
    if (nsgs.event.error <= kPlateauRatio * tolerance_)
        again.min_work = c.admm_setup + (double)probe.event.iterations * c.admm_iteration;
    return stage(again, r);
}

// One round of the stages (the caller calls it again while `active()`): round k gives each
// stage 2^k times its first budget and patience, from the best iterate so far, so that the
// method that suits the problem gets enough time while the others cost at most a constant
// factor (a portfolio with restarts).
frix_error IslandSolver::run_round(double *r) {
    const double before = best_error_;
    bool cut_short = false;  // a stage of this round got less than its budget (max_iter)
    if (round_ == 0)
        if (frix_error e = opening_stages(r, cut_short)) return e;
    if (frix_error e = round_stages(r, cut_short)) return e;
    ++round_;
    if (best_error_ <= tolerance_) {
        finished_ = true;
        return polish(r);
    }
    close_round(before, cut_short);
    return FRIX_OK;
}

// Round 0's extra stages: on a large part ADMM from r = 0 (its dual variable fits an iterate of
// NSGS poorly) while its rate predicts the tolerance for less than the IPM costs; on a small
// part at a loose tolerance a few Newton steps from r = 0; then on both the IPM.
frix_error IslandSolver::opening_stages(double *r, bool &cut_short) {
    if (p_.nc >= kIpmMinContacts && can_continue() && fits_memory(&StageCosts::admm_bytes)) {
        std::fill(r, r + m_, 0.0);
        if (frix_error e = round_stage(rate(FRIX_SOLVER_ADMM, kAdmmRateBudget), r, cut_short)) return e;
    }
    const bool small_and_loose = p_.nc < kIpmMinContacts && tolerance_ >= kIpmLooseTolerance;
    if (small_and_loose && can_continue()) {
        std::fill(r, r + m_, 0.0);
        if (frix_error e = round_stage(stall(FRIX_SOLVER_NSN_AC, kNewtonProbeSteps, kNewtonProbeSteps), r, cut_short))
            return e;
    }
    if ((p_.nc >= kIpmMinContacts || small_and_loose) && can_continue() && fits_memory(&StageCosts::ipm_bytes))
        return ipm_stage(r, cut_short);
    return FRIX_OK;
}

// The interior-point stage; the rounds go on from its result only within kIpmKeepRatio of the
// tolerance.
frix_error IslandSolver::ipm_stage(double *r, bool &cut_short) {
    const std::vector<double> keep_r = best_r_;
    const double keep_error = best_error_;
    const int keep_solver = best_solver_;
    const StageSpec &ipm = kIpmStage;
    if (frix_error e = round_stage(stall(ipm.solver_id, ipm.patience, ipm.first_budget), r, cut_short)) return e;
    // A stalled run that lowered the error gets one Newton stage (the round's, with the first
    // round's budget) from its iterate before that is judged.
    if (!(best_error_ <= tolerance_) && best_error_ < keep_error && can_continue()) {
        std::copy(best_r_.begin(), best_r_.end(), r);
        const StageSpec &newton = kRound[0];
        if (frix_error e = round_stage(stall(newton.solver_id, newton.patience, newton.first_budget), r, cut_short))
            return e;
    }
    if (!(best_error_ <= kIpmKeepRatio * tolerance_)) {
        // Set aside, not lost: where the rounds do not get below it (a time or iteration limit
        // that ends them early) it is still the part's answer.
        if (best_error_ < keep_error) held_r_ = best_r_, held_error_ = best_error_;
        best_r_ = keep_r;
        best_error_ = keep_error;
        best_solver_ = keep_solver;
    }
    return FRIX_OK;
}

// The stages of kRound, each from the best iterate (NSGS from where its last stage stopped).
frix_error IslandSolver::round_stages(double *r, bool &cut_short) {
    for (const StageSpec &spec : kRound) {
        if (!can_continue()) break;
        if (spec.solver_id != FRIX_SOLVER_NSGS_VELOCITY &&
            !fits_memory(spec.solver_id == FRIX_SOLVER_ADMM ? &StageCosts::admm_bytes : &StageCosts::ipm_bytes))
            continue;
        const bool chain = spec.solver_id == FRIX_SOLVER_NSGS_VELOCITY && !nsgs_chain_.empty();
        const std::vector<double> &from = chain ? nsgs_chain_ : best_r_;
        std::copy(from.begin(), from.end(), r);
        const int shift = std::min(round_, 30);
        const StageRequest req = stall(spec.solver_id, spec.patience << shift, spec.first_budget << shift);
        // The first Newton stage also starts afresh: where NSGS stalls it has often drifted
        // along a degenerate set from which Newton stalls too, while from r = 0 it converges.
        // On a small part only from r = 0; on a larger one from NSGS's iterate first.
        if (round_ == 0 && spec.solver_id == FRIX_SOLVER_NSN_AC) {
            if (p_.nc > kPolishMaxContacts) {
                if (frix_error e = round_stage(req, r, cut_short)) return e;
                if (!can_continue()) break;
            }
            std::fill(r, r + m_, 0.0);
        }
        if (frix_error e = round_stage(req, r, cut_short)) return e;
        if (spec.solver_id == FRIX_SOLVER_NSGS_VELOCITY) nsgs_chain_.assign(r, r + m_);
        if (spec.solver_id == FRIX_SOLVER_NSN_AC && p_.nc <= kRestartMaxContacts)
            if (frix_error e = random_restarts(spec, r, cut_short)) return e;
    }
    return FRIX_OK;
}

// Without a deadline, rounds that do not halve the error end the sequence; a round whose
// stages the caller's iteration limit cut short does not count (that is the limit's doing:
// the status is then max_iter, not stagnated).
void IslandSolver::close_round(double before, bool cut_short) {
    idle_rounds_ = best_error_ < 0.5 * before ? 0 : idle_rounds_ + (cut_short ? 0 : 1);
    if (!std::isfinite(shared_.deadline()) && idle_rounds_ >= kMaxIdleRounds) {
        TraceEvent e = trace_event(kGiveUp);
        e.error = best_error_;
        note(e);
        finished_ = true;
    }
}

// Newton from random points of the cones, 2^k of them in round k: where Newton from r = 0 and
// from the best iterate stalls on a small part, it has usually stopped at a stationary point
// of its merit function, and a random start often lands in the solution's basin. Each start
// gets the first round's budget and patience; the round's starts make one record (their
// number, summed iterations and time, best error), so that the trace stays as short as the rounds.
frix_error IslandSolver::random_restarts(const StageSpec &spec, double *r, bool &cut_short) {
    const int64_t starts = int64_t{1} << std::min(round_, 40);
    TraceEvent sum = trace_event(kStage);
    sum.solver_id = spec.solver_id;
    sum.error = INFINITY;
    StageOutcome start;
    for (int64_t k = 0; k < starts && can_continue(); ++k) {
        draw_start(r);
        if (frix_error e = run(stall(spec.solver_id, spec.patience, spec.first_budget), r, start)) return e;
        cut_short = cut_short || start.cut_short;
        const TraceEvent &ev = start.event;
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
void IslandSolver::draw_start(double *r) {
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
// anywhere in a thin set of iterates the relative measure cannot tell apart, some of them
// visibly wrong on degenerate problems: on a small part a few proximal Newton steps land on the
// solution to rounding (the best iterate is kept either way). The Newton-type stages end on a
// solution already.
frix_error IslandSolver::polish(double *r) {
    if (p_.nc > kPolishMaxContacts || best_solver_ == FRIX_SOLVER_NSN_AC || best_solver_ == FRIX_SOLVER_PROX ||
        best_solver_ == FRIX_SOLVER_IPM)
        return FRIX_OK;
    StageRequest req = stall(FRIX_SOLVER_PROX, 20 * kPolishSteps, kPolishSteps);
    req.tolerance = std::max(kPolishRatio * tolerance_, DBL_MIN);
    std::copy(best_r_.begin(), best_r_.end(), r);
    return stage(req, r);
}

frix_error IslandSolver::stage(const StageRequest &req, double *r, StageOutcome *out) {
    StageOutcome own;
    StageOutcome &outcome = out ? *out : own;
    if (frix_error e = run(req, r, outcome)) return e;
    record(outcome.event);
    return FRIX_OK;
}

frix_error IslandSolver::round_stage(const StageRequest &req, double *r, bool &cut_short) {
    StageOutcome out;
    if (frix_error e = stage(req, r, &out)) return e;
    cut_short = cut_short || out.cut_short;
    return FRIX_OK;
}

void IslandSolver::record(const TraceEvent &ev) {
    if (++stages_run_ > 1) ++ledger_.switches;
    note(ev);
}

frix_error IslandSolver::run(const StageRequest &req, double *r, StageOutcome &out) {
    const StageGround ground{p_, shared_, u_.data(), cache_, req.watch == Watch::Rate ? prices() : nullptr,
                             u_holds(r) ? &u_measures_ : nullptr};
    u_known_ = false;  // every stage writes the part's u
    if (frix_error e = run_stage(ground, req, r, out)) return e;
    u_now_at(r, out.measures);  // the driver's measures of the r the stage returned
    Monitor::add_work(ledger_, out.info);
    if (out.info.ran_away) {
        shared_.ran_away = true;
        shared_.stop_requested = true;
    }
    if (out.stopped_by_caller) stopped_ = true;
    if (out.event.error < best_error_) {
        best_error_ = out.event.error;
        best_solver_ = req.solver;
        std::copy(r, r + m_, best_r_.begin());
    }
    return FRIX_OK;
}

// Whether a priced stage's factorisation (its field of StageCosts; Newton's and PROX's are
// priced as the IPM's, an LU of W's pattern) fits in the memory the solve may still take: one
// that does not is left out rather than started and refused. Unpriced: its solver decides.
bool IslandSolver::fits_memory(double StageCosts::*bytes) {
    const StageCosts *c = prices();
    return !c || Monitor(shared_.user, shared_.clock).fits_memory(c->*bytes);
}

// The stages' prices on a part large enough for the interior-point stage (kIpmMinContacts),
// where they weigh a first-order stage against it; null on a smaller part (and where pricing
// failed: the rate is then judged on the stage's own work).
const StageCosts *IslandSolver::prices() {
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

}  // namespace frix::autosolve
