// One semismooth Newton loop for every Newton of frix (models: PETSc's SNESNEWTONLS with
// SNESLineSearch and SNESConverged; Siconos's fc3d_nonsmooth_Newton_solvers): the
// regularisation of a singular Jacobian (delta), the line search (line_search.hpp), the
// watchdog, the best iterate, the stall test and the status (Monitor, through Steps), written
// once over a System that knows the equations, their Jacobian and its linear solver:
//   - the local problem's, W's blocks with UMFPACK or a dense LU (newton.cpp: 504/513/520,
//     PROX's inner problems, the interior points' Newton finish);
//   - the global problem's on (v, r) (gnsn_ac.cpp: 607);
//   - the same two over MPI ranks, with PETSc and MUMPS (mpi/distributed_newton.cpp,
//     mpi/distributed_global_newton.cpp).
// And the hybrid's rounds of Newton and NSGS sweeps (newton_with_sweeps), serial and distributed.
// Where the loops differed, each caller's rule is kept as a field of Rules, so that each gives
// the same bits as before it was shared.
//
// A System provides (SystemDefaults gives the optional ones):
//   using Point = ...;                              an iterate (the best one, the watchdog's start)
//   frix_error evaluate(double &psi, double &err);  at the iterate: the merit 1/2 |F|^2 (and the
//                                                   Jacobian's parts for the next step), the error
//   frix_error prepare(double delta);               once a step, before factorising (optional)
//   frix_error factor(double delta, Factorisation &f);  J + delta (scaled by the system) factorised
//   frix_error solve(bool &finite);                 the direction d; finite: all of it is (on every rank)
//   frix_error directional(double &slope);          what the trials need along d, and the merit's slope
//   double merit_at(double t);                      the merit at x + t d
//   frix_error full_step_error(double &err);        the error at x + d (kWatchable: the watchdog's and
//                                                   Rules::full_first_step_by_error's test)
//   void move(double t);                            x += t d
//   void save(Point &) const; void load(const Point &);
//   frix_error rejected(int64_t taken, bool &changed, double &psi);  after a rejected step (optional;
//                                                   `taken` steps taken): changed, its equations (psi: the new merit)
//   frix_error restored_best();                     the best iterate was put back (optional)
//   Monitor::Agree agree() const;                   an OR over ranks (optional: none)
//   void log_step(...), log_return(...)             progress lines (optional)
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "solvers/kit/line_search.hpp"
#include "src/monitor.hpp"

namespace frix::kit {

// The Jacobian regularisation delta (in the system's unit): where it starts and restarts, below
// which a full step drops it, and above which a Jacobian that does not factorise is given up
// (tuned on the rank-deficient FCLIB problems).
constexpr double kDeltaStart = 1e-6, kDeltaFloor = 1e-8, kDeltaMax = 1e6;
// Factorisations of one step at most, delta rising a hundredfold between them.
constexpr int kMaxFactorAttempts = 12;
// Newton is stalled after this many steps without halving the best error, or this many
// rejected steps in a row.
constexpr int kStallSteps = 25, kMaxLineSearchFailures = 3;
// The watchdog (Rules::watchdog = k; Chamberlain, Powell, Lemarechal and Pedersen's technique,
// judged by the error measure instead of the merit, which can rise on a step that lowers the
// error manyfold: notes/2026-11-28-newton-kit.md). Where the line search stalls (its step below
// kWatchdogShortStep, or none) while the full step at least halves the best error
// (kWatchdogTrigger), the full step is taken, then k - 1 more, full too where the search would
// cut them short; unless the error then stands tenfold below the best error at the start
// (kWatchdogGain), the run goes back to the start with everything it knew there, once a run.
constexpr double kWatchdogShortStep = 1e-2, kWatchdogTrigger = 0.5, kWatchdogGain = 0.1;
// The hybrid gives up after this many Newton + sweeps rounds in a row without halving the error.
constexpr int kMaxIdleRounds = 10;

// The regularisation delta of a run: rank-deficient W (rigid scenes) make J singular on the
// sticking contacts, and the raw Newton step then runs along W's null space; a small delta
// costs nothing in u and keeps the steps acceptable. It falls after full steps, down to 0 on
// well-posed problems.
class Regularisation {
   public:
    explicit Regularisation(double start) : delta_(start) {}
    double delta() const { return delta_; }
    void factorisation_failed() { delta_ = delta_ == 0.0 ? kDeltaStart : delta_ * 100.0; }
    void step_taken(double t) {
        if (t == 1.0) delta_ = delta_ < kDeltaFloor ? 0.0 : delta_ * 0.1;
    }
    // No descent along d: a more regularised Jacobian gives a shorter, safer step.
    void step_rejected() { delta_ = std::max(delta_ * 10.0, kDeltaStart); }

   private:
    double delta_;
};

// The iterations of one solve (Newton steps, with the sweeps or outer steps it counts with
// them) against its Monitor's tolerance and limits, and the callback's answer: once it asked
// to stop it is not asked again, though an outer solver may still report before it stops.
class Steps {
   public:
    // Whose errors report() hands to the callback: the solve's iterates' (measured on its
    // measure), or an inner problem's (a proximal step's), which only estimate the solve's.
    enum class Errors { kOfTheSolve, kOfAnInnerProblem };
    explicit Steps(const Monitor &run, Errors errors = Errors::kOfTheSolve) : monitor(run), errors_(errors) {}
    Monitor monitor;
    int64_t done = 0;
    // r: as for Monitor::report (a solver that iterates on its own copy; null: ctx.r).
    bool report(double error, const double *r = nullptr) {
        return hand_on(error, r, errors_ == Errors::kOfTheSolve);
    }
    // report() of an error measured on the solve's iterate (a proximal method's own step).
    bool report_measured(double error, const double *r = nullptr) { return hand_on(error, r, true); }
    // report() of an estimate, whatever the kind.
    bool report_estimate(double error, const double *r = nullptr) { return hand_on(error, r, false); }
    // Whether the callback asked to stop (with agree: on any rank).
    bool stop_asked(const Monitor::Agree &agree = nullptr) const { return agree ? agree(asked_) : asked_; }
    frix_status verdict(double error, const Monitor::Agree &agree = nullptr) const {
        return monitor.verdict_after_report(done, error, asked_, agree);
    }
    frix_status limits(const Monitor::Agree &agree = nullptr) const {
        return monitor.limits_after_report(done, asked_, agree);
    }

   private:
    bool hand_on(double error, const double *r, bool measured) {
        if (!asked_ && (measured ? monitor.report(done, error, r) : monitor.report_estimate(done, error, r)))
            asked_ = true;
        return asked_;
    }
    Errors errors_;
    bool asked_ = false;
};

// Before a proximal step (PROX, rolling-nsn), after `outer` of them, at the error err:
// converged, the iteration limit, a stop the callback asked for, the time limit, in that order;
// FRIX_STATUS_NOT_RUN to go on. Not Monitor::limits: the callback is not called here, only its last answer read, for
// the inner Newton calls it (through inner, on the Newton steps' count), and so does each
// proximal step's end, once no answer asked to stop.
inline frix_status status_before_step(const Monitor &monitor, double err, int64_t outer, const Steps &inner) {
    if (err <= monitor.tolerance()) return FRIX_STATUS_CONVERGED;
    if (monitor.out_of_iterations(outer)) return FRIX_STATUS_MAX_ITER;
    if (inner.stop_asked()) return FRIX_STATUS_STOPPED_BY_CALLBACK;
    if (inner.monitor.out_of_time()) return FRIX_STATUS_TIME_LIMIT;
    return FRIX_STATUS_NOT_RUN;
}

// After a proximal step's inner solve ended with `inner`: the status that ends the proximal
// method there (a limit or a stop of the inner solve; or its answer, ctx.r, has run away:
// Monitor::ran_away, a stop the driver reports as diverged); FRIX_STATUS_NOT_RUN to go on.
// Each answer is asked: on a problem without a solution the answers run away as alpha falls,
// and a rejected one is undone before the Monitor's next periodic check could see it.
inline frix_status status_after_step(const Monitor &monitor, frix_status inner) {
    if (inner == FRIX_STATUS_TIME_LIMIT || inner == FRIX_STATUS_MEMORY_LIMIT ||
        inner == FRIX_STATUS_STOPPED_BY_CALLBACK)
        return inner;
    return monitor.ran_away() ? FRIX_STATUS_STOPPED_BY_CALLBACK : FRIX_STATUS_NOT_RUN;
}

// Each caller's rules, where the Newtons differ.
struct Rules {
    Search search;
    double delta_start = kDeltaStart;  // 0: no delta until J fails to factorise (gnsn-ac, PROX)
    double delta_cap = kDeltaMax;      // INFINITY: kMaxFactorAttempts whatever delta (gnsn-ac)
    int watchdog = 0;                  // steps of an excursion (0: none)
    // Take the first step full where it lowers the error, before the merit's search (a
    // kWatchable System). Newton on (v, r) from v = 0: the merit is then mostly the equilibrium
    // rows', which only the full step zeroes, and a step cut short at Phi's kinks leaves the
    // rest for later steps (gnsn-ac on deformable bodies: notes/2026-11-28-gnsn-ac-first-step.md).
    bool full_first_step_by_error = false;
    // Take the full step where the search finds no sufficient decrease (Siconos's rule): PROX's
    // regularised inner problems tolerate full steps, which short ones stall on.
    bool full_step_on_failure = false;
    // gnsn-ac's: the callback's stop ends the run at the step it is asked (before the best
    // iterate, the stall test and convergence); elsewhere it is weighed before the next step.
    bool stop_at_once = false;
    // The distributed nsn-ac's own rules (true, true, NUMERICAL_FAILURE, false elsewhere): it
    // returns its last iterate, has no stall test, stagnates where J does not factorise and
    // where a rejected step raises delta above delta_cap.
    bool keep_best = true, stall = true;
    frix_status singular = FRIX_STATUS_NUMERICAL_FAILURE;
    bool stagnate_above_cap = false;
};

struct Counters {
    int64_t newton = 0, line_search = 0, sweeps = 0;
};

struct RunResult {
    frix_status status = FRIX_STATUS_MAX_ITER;  // STAGNATED when Newton stalls
    double error = 0.0;                         // of the returned iterate
};

// A Newton solve's status and counters into info (iterations: steps.done).
inline void record(frix_info &info, const RunResult &res, const Steps &steps, const Counters &counters) {
    info.status = res.status;
    info.iterations = steps.done;
    info.newton_iterations = counters.newton;
    info.line_search_steps = counters.line_search;
    info.hybrid_sweeps = counters.sweeps;
}

struct Factorisation {
    bool factored = false;
    frix_status refused = FRIX_STATUS_NOT_RUN;  // the time or memory limit refused it
};

// The optional parts of a System. kWatchable: it has full_step_error (the watchdog's test).
struct SystemDefaults {
    static constexpr bool kWatchable = false;
    frix_error prepare(double) { return FRIX_OK; }
    frix_error rejected(int64_t, bool &, double &) { return FRIX_OK; }
    frix_error restored_best() { return FRIX_OK; }
    Monitor::Agree agree() const { return nullptr; }
    void log_step(int64_t, double, double, double, double) const {}
    void log_return(int64_t) const {}
};

// The iterate of a local Newton system on the caller's r (m entries, changed in place) with
// its velocity u beside it: the step d, du its change of u, the trial point (rt, ut) along
// them, and the loop's move, save and load, which touch r alone (the system recomputes u in
// evaluate).
class InPlaceIterate {
   public:
    using Point = std::vector<double>;
    InPlaceIterate(double *r, int64_t m) : r_(r), m_(m), u_(m), d_(m), du_(m), rt_(m), ut_(m) {}
    void move(double t) {
        for (int64_t i = 0; i < m_; ++i) r_[i] += t * d_[i];
    }
    void save(Point &p) const { p.assign(r_, r_ + m_); }
    void load(const Point &p) { std::copy(p.begin(), p.end(), r_); }

   protected:
    // (r + t d, u + t du) into (rt, ut).
    void along(double t) {
        for (int64_t i = 0; i < m_; ++i) {
            rt_[i] = r_[i] + t * d_[i];
            ut_[i] = u_[i] + t * du_[i];
        }
    }
    double *r_;
    const int64_t m_;
    std::vector<double> u_, d_, du_, rt_, ut_;
};

template <class System>
class NewtonLoop {
   public:
    NewtonLoop(System &sys, Steps &steps, const Rules &rules, Counters &counters)
        : sys_(sys), steps_(steps), rules_(rules), counters_(counters), reg_(rules.delta_start) {}

    // Newton from the system's iterate to the status in res; the iterate returned is the best
    // one (Rules::keep_best) or the last.
    frix_error run(RunResult &res) {
        if (frix_error e = sys_.evaluate(psi_, err_)) return e;
        best_err_ = ref_err_ = err_;
        history_ = MeritHistory(psi_);
        if (rules_.keep_best) sys_.save(best_);
        frix_status status = FRIX_STATUS_NOT_RUN;
        while (status == FRIX_STATUS_NOT_RUN && (status = steps_.verdict(err_, sys_.agree())) == FRIX_STATUS_NOT_RUN)
            if (frix_error e = step(status)) return e;
        if (rules_.keep_best && !(err_ <= best_err_)) {  // also when the last iterate is not finite
            sys_.load(best_);
            err_ = best_err_;
            if (frix_error e = sys_.restored_best()) return e;
        }
        res.status = status;
        res.error = err_;
        return FRIX_OK;
    }

   private:
    // The watchdog's excursion, and what it goes back to when it fails.
    struct Excursion {
        bool active = false, spent = false;  // one failed excursion per run
        int steps = 0;
        typename System::Point start, best;
        double best_err = 0.0, ref_err = 0.0, err = 0.0, delta = 0.0;
        int since_progress = 0, failures = 0;
        MeritHistory history{0.0};
    };

    // One Newton step; status: what ends the run in the step (else NOT_RUN).
    frix_error step(frix_status &status) {
        if (frix_error e = factorise(status)) return e;
        if (status != FRIX_STATUS_NOT_RUN) return FRIX_OK;
        bool finite = true;
        if (frix_error e = sys_.solve(finite)) return e;
        ++counters_.newton;
        ++steps_.done;
        double t = 0.0;
        bool accepted = false;
        if (finite) {
            if (frix_error e = search(t, accepted)) return e;
        }
        // Within an excursion, the steps the search would cut short are full steps too.
        if (finite && excursion_.active && (!accepted || t < kWatchdogShortStep)) t = 1.0, accepted = true;
        if (accepted) {
            sys_.move(t);
            if (frix_error e = sys_.evaluate(psi_, err_)) return e;
            history_.push(psi_);
            failures_ = 0;
            ++taken_;
            reg_.step_taken(t);
        } else {
            ++failures_;
            reg_.step_rejected();
            if (rules_.stagnate_above_cap && reg_.delta() > rules_.delta_cap) {  // no step lowers the merit
                status = FRIX_STATUS_STAGNATED;
                return FRIX_OK;
            }
            bool changed = false;
            if (frix_error e = sys_.rejected(taken_, changed, psi_)) return e;
            if (changed) {
                failures_ = 0;
                history_ = MeritHistory(psi_);  // (merits of other equations)
            }
        }
        if (frix_error e = judge_excursion()) return e;
        sys_.log_step(counters_.newton, t, err_, psi_, reg_.delta());
        // During an excursion the callback sees the error of the point it may return to: not
        // the iterate's, an estimate.
        if (excursion_.active)
            steps_.report_estimate(excursion_.err);
        else
            steps_.report(err_);
        if (rules_.stop_at_once && steps_.stop_asked(sys_.agree())) {
            status = FRIX_STATUS_STOPPED_BY_CALLBACK;
            return FRIX_OK;
        }
        if (err_ < best_err_) {
            best_err_ = err_;
            if (rules_.keep_best) sys_.save(best_);
        }
        if (best_err_ < 0.5 * ref_err_) {
            ref_err_ = best_err_;
            since_progress_ = 0;
        } else if (rules_.stall &&
                   ((!excursion_.active && ++since_progress_ >= kStallSteps) || failures_ >= kMaxLineSearchFailures)) {
            status = FRIX_STATUS_STAGNATED;
        }
        return FRIX_OK;
    }

    // J (+ delta) factorised, delta raised until it factorises; status: why it did not.
    frix_error factorise(frix_status &status) {
        if (frix_error e = sys_.prepare(reg_.delta())) return e;
        Factorisation f;
        for (int attempt = 0; attempt < kMaxFactorAttempts; ++attempt) {
            if (frix_error e = sys_.factor(reg_.delta(), f)) return e;
            if (f.factored) return FRIX_OK;
            reg_.factorisation_failed();
            if (f.refused || reg_.delta() > rules_.delta_cap) break;
        }
        status = f.refused ? f.refused : rules_.singular;
        return FRIX_OK;
    }

    // The first step full where it lowers the error (Rules::full_first_step_by_error), else the
    // line search along d, then the watchdog, PROX's full step and the best trial step where it accepts nothing.
    frix_error search(double &t, bool &accepted) {
        if constexpr (System::kWatchable) {
            if (rules_.full_first_step_by_error && taken_ == 0) {
                double full = 0.0;
                if (frix_error e = sys_.full_step_error(full)) return e;
                if (full < err_) {
                    t = 1.0, accepted = true;
                    return FRIX_OK;
                }
            }
        }
        double slope = 0.0;
        if (frix_error e = sys_.directional(slope)) return e;
        const SearchResult s =
            line_search(rules_.search, [this](double step) { return sys_.merit_at(step); }, psi_, slope, history_,
                        counters_.line_search);
        t = s.t;
        accepted = s.accepted;
        if (!s.searched) return FRIX_OK;
        // The full step's error is measured only where the line search stalled.
        if constexpr (System::kWatchable) {
            if (may_watch() && (!accepted || t < kWatchdogShortStep)) {
                double full = 0.0;
                if (frix_error e = sys_.full_step_error(full)) return e;
                if (full <= kWatchdogTrigger * best_err_) {
                    start_excursion();
                    t = 1.0, accepted = true;
                }
            }
        }
        if (!accepted && rules_.full_step_on_failure) t = 1.0, accepted = true;
        if (!accepted && s.best_t > 0.0) t = s.best_t, accepted = true;  // no sufficient decrease, but a decrease
        return FRIX_OK;
    }

    bool may_watch() const {
        return rules_.watchdog > 0 && !rules_.full_step_on_failure && !excursion_.active && !excursion_.spent;
    }
    void start_excursion() {
        Excursion &x = excursion_;
        x.active = true;
        x.steps = 0;
        sys_.save(x.start);
        x.best = best_;
        x.best_err = best_err_, x.ref_err = ref_err_, x.err = err_, x.delta = reg_.delta();
        x.since_progress = since_progress_, x.failures = failures_;
        x.history = history_;
    }
    // The excursion's k steps (the full step first) are judged: kept when the error fell
    // tenfold below the best error at its start, otherwise undone.
    frix_error judge_excursion() {
        Excursion &x = excursion_;
        if (!x.active || ++x.steps < rules_.watchdog) return FRIX_OK;
        x.active = false;
        if (err_ <= kWatchdogGain * x.best_err) return FRIX_OK;
        x.spent = true;
        sys_.load(x.start);
        best_ = x.best;
        best_err_ = x.best_err, ref_err_ = x.ref_err;
        reg_ = Regularisation(x.delta);
        since_progress_ = x.since_progress, failures_ = x.failures;
        history_ = x.history;
        if (frix_error e = sys_.evaluate(psi_, err_)) return e;
        sys_.log_return(counters_.newton - rules_.watchdog);
        return FRIX_OK;
    }

    System &sys_;
    Steps &steps_;
    const Rules &rules_;
    Counters &counters_;
    Regularisation reg_;
    double psi_ = 0.0, err_ = 0.0, best_err_ = 0.0, ref_err_ = 0.0;
    int since_progress_ = 0, failures_ = 0;
    int64_t taken_ = 0;
    MeritHistory history_{0.0};
    typename System::Point best_;
    Excursion excursion_;
};

// A Newton run on sys (NewtonLoop::run).
template <class System>
frix_error newton(System &sys, Steps &steps, const Rules &rules, Counters &counters, RunResult &res) {
    return NewtonLoop<System>(sys, steps, rules, counters).run(res);
}

// Newton, and where it stalls (STAGNATED, or a Jacobian that does not factorise) NSGS sweeps
// (option hybrid = nsgs), which move r to where the active set is right; then Newton resumes
// from there (Siconos's hybrid). Rounds provides:
//   frix_error newton(RunResult &);   a Newton run from r
//   void keep(); void restore();      r before the sweeps, put back if they made it worse
//   void sweep();                     one NSGS sweep over every contact
//   double error();                   the error at r (on every rank alike)
//   void log_sweeps(double before, double after) const;  Monitor::Agree agree() const;
// Iterations count Newton steps and sweeps alike (steps.done).
template <class Rounds>
frix_error newton_with_sweeps(Rounds &rounds, Steps &steps, bool hybrid, int64_t sweeps, Counters &counters,
                              RunResult &res) {
    int idle_rounds = 0;            // rounds in a row that did not halve the error
    double round_start = INFINITY;  // the error at the last halving
    while (true) {
        if (frix_error e = rounds.newton(res)) return e;
        if (!hybrid || (res.status != FRIX_STATUS_STAGNATED && res.status != FRIX_STATUS_NUMERICAL_FAILURE))
            return FRIX_OK;
        rounds.keep();
        const double before = res.error;
        for (int64_t k = 0; k < sweeps && !steps.monitor.out_of_iterations(steps.done); ++k) {
            rounds.sweep();
            ++counters.sweeps;
            ++steps.done;
        }
        const double after = rounds.error();
        rounds.log_sweeps(before, after);
        // The callback hears the error of the iterate kept; the runaway watch, the sweeps' r.
        steps.report(after <= before ? after : before);
        if (!(after <= before)) rounds.restore();
        if (after <= steps.monitor.tolerance()) {
            res.status = FRIX_STATUS_CONVERGED;
            return FRIX_OK;
        }
        if (after < 0.5 * round_start) {
            round_start = after;
            idle_rounds = 0;
        } else {
            ++idle_rounds;
        }
        if (idle_rounds >= kMaxIdleRounds) {
            res.status = FRIX_STATUS_STAGNATED;  // neither Newton nor the sweeps make progress
            return FRIX_OK;
        }
        const frix_status stop = steps.limits(rounds.agree());
        if (stop != FRIX_STATUS_NOT_RUN) {
            res.status = stop;
            return FRIX_OK;
        }
    }
}

}  // namespace frix::kit
