// The NSGS iteration on a form (run_sweeps): sweeps, the light error calibrated by full
// checks, drift extrapolation, momentum or Anderson's mix (anderson_mixing.hpp), freezing, the
// best iterate, and the Monitor's limits.
// The forms (W's rows, W's columns, the product form, the distributed ones) only sweep and
// measure.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <vector>

#include "solvers/kit/anderson_mixing.hpp"
#include "solvers/kit/sweeps.hpp"
#include "src/coulomb.hpp"
#include "src/log.hpp"
#include "src/measures.hpp"
#include "src/monitor.hpp"

namespace frix {
namespace nsgs {

void push_projection(SweepForm &form, Workspace &ws, const double *line, const double *y, size_t m, double *u) {
    for (size_t a = 0; 3 * a < m; ++a) {
        const double d[3] = {y[3 * a] - line[3 * a], y[3 * a + 1] - line[3 * a + 1], y[3 * a + 2] - line[3 * a + 2]};
        if (d[0] != 0.0 || d[1] != 0.0 || d[2] != 0.0) form.push_change(ws, (int64_t)a, d, u);
    }
}

namespace {

// A full check also runs at the first evaluation and every kFullCheckPeriod evaluations: on
// rank-deficient W, r may keep drifting along the null space (large light error) while u,
// and the error, have converged, often from the first sweep on. Every full check but the
// first recalibrates the light tolerance, down or up.
constexpr int64_t kFullCheckPeriod = 16;
// The first check takes a drifting kept state's error where it exceeds the tolerance this many
// times (SweepRun::full_error).
constexpr double kFirstCheckMargin = 10.0;
// Freezing starts after this many sweeps (Siconos' rule): the first sweeps move every contact.
constexpr int64_t kFreezeAfter = 10;
// Drift extrapolation (option drift_window): two successive windows' displacements count as
// one steady drift when the cosine of their angle exceeds this; a jump goes at most this many
// windows ahead.
constexpr double kDriftCosine = 0.99;
constexpr double kMaxDriftJump = 1000.0;
// The flags of SweepForm::agree after a sweep.
constexpr unsigned kStopAsked = 1u, kOutOfTime = 2u;

// On rank-deficient W, NSGS can sit for millions of sweeps on a plateau of the error while r
// drifts at a steady rate along a nearly self-equilibrated transfer of load between contacts,
// until one of them loses contact and the error falls. The drift is carried ahead at once:
// every `window` sweeps, the displacement d of r over the window is compared with the
// previous window's; when both point the same way, r jumps along d to the first loss of contact
// ahead (t = min r_aN / -d_aN over the contacts with d_aN < 0; when |d| shrank, at most to
// the limit of the geometric series of displacements) and is projected on the cones. The
// sweeps that follow restore what the straight line missed. A jump raises the error for a
// while, so none is taken within two windows of the sweep limit.
class DriftExtrapolation {
   public:
    // r: the start of the first window.
    DriftExtrapolation(int64_t window, int64_t m, const double *r) : window_(window), m_((size_t)m) {
        if (window_ <= 0) return;
        both_.assign(2 * m_, 0.0);  // one allocation: solves of a few sweeps run often
        std::copy(r, r + m, both_.begin());
    }
    // After sweep `it` of at most `max_sweeps`: true when r jumped (then u and the frozen
    // contacts need a refresh).
    bool after_sweep(int64_t it, int64_t max_sweeps, double *r, const double *mu) {
        if (window_ <= 0 || it % window_ != 0) return false;
        const size_t m = m_;
        double *start_ = both_.data(), *last_ = both_.data() + m_;
        double dd = 0.0, dl = 0.0, ll = 0.0;
        for (size_t i = 0; i < m; ++i) {
            const double d = r[i] - start_[i];
            dd += d * d;
            dl += d * last_[i];
            ll += last_[i] * last_[i];
            last_[i] = d;
            start_[i] = r[i];
        }
        const bool steady = have_last_ && dd > 0.0 && dl > kDriftCosine * std::sqrt(dd * ll);
        have_last_ = dd > 0.0;
        if (!steady) return false;
        double t = INFINITY;
        for (size_t a = 0; 3 * a < m; ++a)
            if (last_[3 * a] < 0.0 && r[3 * a] > 0.0) t = std::min(t, -r[3 * a] / last_[3 * a]);
        const double ratio = std::sqrt(dd / ll);
        if (ratio < 1.0) t = std::min(t, ratio / (1.0 - ratio));
        if (!(t > 1.0) || !std::isfinite(t) || max_sweeps - it < 2 * window_) return false;
        t = std::min(t, kMaxDriftJump);
        for (size_t i = 0; i < m; ++i) r[i] += t * last_[i];
        coulomb::project_on_cones(r, mu, (int64_t)(m / 3));
        std::copy(r, r + m, start_);
        have_last_ = false;  // a new window history from the new point
        ++jumps_;
        return true;
    }
    int64_t jumps() const { return jumps_; }

   private:
    int64_t window_;
    size_t m_;
    std::vector<double> both_;  // r at the window's start, then the last window's displacement
    bool have_last_ = false;
    int64_t jumps_ = 0;
};

// Momentum on the sweep (option acceleration; MomentumSchedule's weights): after a sweep,
// r = x moves to P_K(x + beta (x - x_prev)), and the form's kept state follows. The sweeps'
// steps keep their direction for long where load crosses a pile a layer a sweep, which
// momentum follows; the sweep itself, and its fixed points, stay as they are. Freezing is off
// under it: the extrapolation moves the contacts freezing would skip, and the two together
// can hold the error on a plateau.
class Momentum {
   public:
    Momentum(bool on, int64_t m, const double *r) : schedule_(on) {
        if (!on) return;
        last_.assign(r, r + m);
        line_.resize((size_t)m);
    }
    bool on() const { return schedule_.on(); }
    void judge(int64_t sweep, double e) { schedule_.judge(sweep, e); }
    // Whether it keeps a copy of the form's affine state (its value at x_prev).
    bool holds_state() const { return !state_last_.empty(); }
    // That copy moves by `correction` (the form's exact() corrected the state by it).
    void shift_state(const std::vector<double> &correction) {
        if (state_last_.size() != correction.size()) return;
        for (size_t i = 0; i < correction.size(); ++i) state_last_[i] += correction[i];
    }
    // After a sweep that moved r by |dr|^2 = dr2 (jumped: r then jumped ahead of the sweep).
    void after_sweep(double dr2, bool jumped, double *r, const double *mu, Workspace &ws, SweepForm &form, double *u) {
        if (!schedule_.on()) return;
        const double beta = schedule_.next(dr2, jumped);
        const size_t m = last_.size();
        for (size_t i = 0; i < m; ++i) {
            const double x = r[i];
            line_[i] = x + beta * (x - last_[i]);
            last_[i] = x;
            r[i] = line_[i];
        }
        if (beta != 0.0) coulomb::project_on_cones(r, mu, (int64_t)(m / 3));
        // The affine state: state + beta (state - state at x_prev), then the projection's part.
        const SweepForm::AffineState state = form.affine_state(u);
        if (!state.combines) {
            if (beta != 0.0) form.restart(r, u);
            return;
        }
        if (state_last_.size() != state.size) state_last_.assign(state.size, 0.0);
        for (size_t i = 0; i < state.size; ++i) {
            const double now = state.values[i];
            state.values[i] = now + beta * (now - state_last_[i]);
            state_last_[i] = now;
        }
        if (beta != 0.0) push_projection(form, ws, line_.data(), r, m, u);
    }

   private:
    MomentumSchedule schedule_;
    std::vector<double> state_last_;  // the form's affine state at x_prev
    std::vector<double> last_, line_;  // x_{k-1}; the line point before its projection
};

// Monitor::Agree for run_sweeps's limits: SweepForm::agree is one exchange among the processes
// of a distributed form, so the callback's flag (asked first) travels with the clock's, which
// the time test (asked second) then reads.
class SweepAgreement {
   public:
    SweepAgreement(SweepForm &form, const Monitor &monitor) : form_(form), monitor_(monitor) {}
    bool operator()(bool raised) {
        if (asked_) return (flags_ & kOutOfTime) != 0;
        asked_ = true;
        flags_ = form_.agree((raised ? kStopAsked : 0u) | (monitor_.out_of_time() ? kOutOfTime : 0u));
        return (flags_ & kStopAsked) != 0;
    }

   private:
    SweepForm &form_;
    const Monitor &monitor_;
    bool asked_ = false;
    unsigned flags_ = 0;
};

// One run of run_sweeps: the sweeps, the light error and its full checks, drift extrapolation,
// momentum, freezing and the best iterate; ctx.info gets the status and the sweeps.
class SweepRun {
   public:
    SweepRun(SolveContext &ctx, Workspace &ws, SweepForm &form, const char *name);
    void run();

   private:
    double exact_error();
    Measures exact_following();
    void hand_over();
    double full_error(bool first_only);
    bool warm_start_solves();
    SweepStats sweep();
    bool after_sweep(const SweepStats &st);
    double evaluate(const SweepStats &st);
    void full_check(const SweepStats &st, double light, bool first_only);
    bool stops();
    void finish();

    SolveContext &ctx_;
    Workspace &ws_;
    SweepForm &form_;
    const char *name_;
    const frix_problem &p_;
    const frix_options &o_;
    const Monitor monitor_;
    const double tol_;
    const int64_t max_iter_, verbosity_, measure_, frequency_, freezing_, m_;
    double *r_, *u_;
    frix_info &info_;
    // The last exact measures, handed to the driver when r has not moved since (at_r_).
    Measures last_;
    bool at_r_ = false;
    const int64_t all_contacts_;
    DriftExtrapolation drift_;
    AndersonMixing anderson_;
    Momentum momentum_;
    std::vector<double> correction_;  // exact_following: exact()'s correction of the affine state
    // The best r of the full checks, returned when the run ends worse (ctx.return_best).
    std::vector<double> best_r_;
    double best_error_ = INFINITY;
    const bool keep_best_;
    double tol_light_;
    int64_t it_ = 0, evaluations_ = 0;
    bool checked_last_ = false;  // whether the last sweep ended with a full check
    double last_full_ = NAN, estimate_ = NAN, last_r2_ = 0.0;
    bool estimate_measured_ = false;  // estimate_ is the full error of the iterate
};

SweepRun::SweepRun(SolveContext &ctx, Workspace &ws, SweepForm &form, const char *name)
    : ctx_(ctx),
      ws_(ws),
      form_(form),
      name_(name),
      p_(ctx.problem),
      o_(ctx.options),
      monitor_(ctx),
      tol_(monitor_.tolerance()),
      max_iter_(monitor_.max_iterations()),
      verbosity_(o_.i(FRIX_OPT_VERBOSITY)),
      measure_(o_.i(FRIX_OPT_ERROR_MEASURE)),
      frequency_(o_.i(FRIX_OPT_ERROR_FREQUENCY)),
      freezing_(settings_from(o_).freezing),
      m_(3 * p_.nc),
      r_(ctx.r),
      u_(ctx.u),
      info_(ctx.info),
      all_contacts_(form.all_contacts(p_.nc)),
      drift_(o_.i(FRIX_OPT_DRIFT_WINDOW), m_, ctx.r),
      anderson_(o_.i(FRIX_OPT_ANDERSON), m_, ctx.r),
      momentum_(o_.i(FRIX_OPT_ACCELERATION) != 0 && !anderson_.on(), m_, ctx.r),
      keep_best_(ctx.return_best && form.restores()),
      tol_light_(tol_) {}

double SweepRun::exact_error() {
    last_ = exact_following();
    at_r_ = true;
    return selected_error(last_, measure_);
}

// form.exact(r, u) may recompute the form's affine state, clearing the drift of its updates:
// the accelerations' copies of it move by the same correction, Anderson's always, momentum's
// where the drift is more than rounding (SweepForm::state_drifts).
Measures SweepRun::exact_following() {
    const bool anderson = anderson_.holds_states(), momentum = momentum_.holds_state() && form_.state_drifts();
    const SweepForm::AffineState state = anderson || momentum ? form_.affine_state(u_) : SweepForm::AffineState{};
    if (state.size == 0) return form_.exact(r_, u_);
    correction_.assign(state.values, state.values + state.size);
    const Measures out = form_.exact(r_, u_);
    for (size_t i = 0; i < state.size; ++i) correction_[i] = state.values[i] - correction_[i];
    if (anderson) anderson_.shift_states(correction_);
    if (momentum) momentum_.shift_state(correction_);
    return out;
}

void SweepRun::hand_over() {
    ctx_.has_measured = at_r_ && form_.measures_are_local();
    ctx_.measured = last_;
}

// A periodic check: from what the form keeps up to date where it keeps something; a passing
// check is confirmed by the exact error.
// The first check (first_only) only ends a solve the first sweep finished: one sweep's drift
// of what the form keeps cannot hide an error ten times the tolerance, so such an error is
// taken from the kept state even where it drifts (no product with W).
double SweepRun::full_error(bool first_only) {
    Measures kept;
    const bool have = first_only ? form_.kept_drifting(r_, u_, kept) : form_.kept(r_, u_, kept);
    if (!have) return exact_error();
    const double e = selected_error(kept, measure_);
    if (first_only && !form_.kept(r_, u_, kept)) return e > kFirstCheckMargin * tol_ ? e : exact_error();
    return e <= tol_ ? exact_error() : e;
}

// A warm start that already solves the problem costs one product, not a sweep; none where
// the caller measured it (SolveContext::measured_start: u holds W r + q already).
bool SweepRun::warm_start_solves() {
    bool warm = false;
    for (int64_t i = 0; i < m_ && !warm; ++i) warm = r_[i] != 0.0;
    warm = form_.agree(warm ? 1u : 0u) != 0;
    if (!warm) {
        form_.restart(r_, u_);
        return false;
    }
    if (!ctx_.measured_start || !form_.measures_are_local()) return exact_error() <= tol_;
    last_ = *ctx_.measured_start;
    at_r_ = true;
    return selected_error(last_, measure_) <= tol_;
}

void SweepRun::run() {
    if (warm_start_solves()) {
        info_.status = FRIX_STATUS_CONVERGED;
        info_.iterations = 0;
        hand_over();
        return;
    }
    info_.status = FRIX_STATUS_MAX_ITER;
    while (it_ < max_iter_) {
        const SweepStats st = sweep();
        if (!std::isfinite(st.r2)) {
            info_.status = FRIX_STATUS_DIVERGED;
            break;
        }
        const bool jumped = after_sweep(st);
        checked_last_ = false;
        // (The sweep's light error predates a jump.)
        const double light = it_ % frequency_ == 0 && !jumped ? evaluate(st) : NAN;
        if (verbosity_ >= 2 || (verbosity_ >= 1 && checked_last_))
            log_line(&o_, "%s: sweep %lld light %.3e%s%.3e rejected %lld unsolved %lld frozen %lld", name_,
                     (long long)it_, light, checked_last_ ? " full " : " tol_light ",
                     checked_last_ ? last_full_ : tol_light_, (long long)st.rejected, (long long)st.unsolved,
                     (long long)st.frozen);
        if (stops()) break;
    }
    finish();
}

// One sweep, freezing the contacts that moved by less than a tenth of the light tolerance's
// share (not in the first sweeps, nor under momentum).
SweepStats SweepRun::sweep() {
    if (freezing_ > 0)
        ws_.set_freeze_threshold(it_ >= kFreezeAfter && !momentum_.on() && !anderson_.on()
                                     ? tol_light_ * tol_light_ * last_r2_ / (10.0 * (double)all_contacts_)
                                     : -1.0);
    const SweepStats st = form_.sweep(ws_, r_, u_);
    at_r_ = false;
    estimate_measured_ = false;  // until this iterate is measured
    ++it_;
    last_r2_ = st.r2;
    return st;
}

// The drift extrapolation and the momentum after a sweep; whether r jumped.
bool SweepRun::after_sweep(const SweepStats &st) {
    const bool jumped = drift_.after_sweep(it_, max_iter_, r_, p_.mu);
    if (jumped) {
        form_.restart(r_, u_);
        ws_.thaw();
        if (verbosity_ >= 1)
            log_line(&o_, "%s: sweep %lld: drift carried ahead (jump %lld)", name_, (long long)it_,
                     (long long)drift_.jumps());
    }
    if (jumped)
        anderson_.restart(r_);
    else
        anderson_.after_sweep(r_, p_.mu, ws_, form_, u_);
    momentum_.after_sweep(st.dr2, jumped, r_, p_.mu, ws_, form_, u_);
    return jumped;
}

// The light error |dr| / |r| of the sweep, and a full check when it passes its tolerance, at
// the first test, or every kFullCheckPeriod tests. The first test's full check only ends a
// solve that is already done; the light tolerance is calibrated by the periodic ones
// (calibrated after one sweep, it misjudges the sweeps to come).
double SweepRun::evaluate(const SweepStats &st) {
    ++evaluations_;
    const double light = st.r2 > 0.0 ? std::sqrt(st.dr2 / st.r2) : std::sqrt(st.dr2);
    estimate_ = light;
    const bool first_only = evaluations_ == 1 && light > tol_light_;
    if (light <= tol_light_ || first_only || evaluations_ % kFullCheckPeriod == 0) full_check(st, light, first_only);
    return light;
}

void SweepRun::full_check(const SweepStats &st, double light, bool first_only) {
    const double e = full_error(first_only);
    checked_last_ = true;
    last_full_ = e;
    momentum_.judge(it_, e);
    if (keep_best_ && e < best_error_) {
        best_error_ = e;
        best_r_.assign(r_, r_ + m_);
    }
    if (!first_only) estimate_ = e, estimate_measured_ = true;
    if (e <= tol_) {
        info_.status = FRIX_STATUS_CONVERGED;
        estimate_ = e;
        estimate_measured_ = true;
    } else if (!std::isfinite(e)) {
        info_.status = FRIX_STATUS_DIVERGED;
    } else if (st.dr2 == 0.0 && st.frozen == 0) {
        info_.status = FRIX_STATUS_STAGNATED;  // r is a fixed point of the sweep
    } else if (!first_only) {
        // LIGHT_WITH_FULL_FINAL: the light error that should mean full error = tol.
        if (light > 0.0) tol_light_ = light / e * tol_;
        // Frozen contacts may be what keeps the error up: sweep them all again.
        ws_.thaw();
    }
}

// Whether the run ends after this sweep: its status decided, or a limit (Monitor::limits,
// agreed over the processes of a distributed form). The callback sees every sweep, the last
// one too; it can only stop a running solve.
bool SweepRun::stops() {
    const bool asked = estimate_measured_ ? monitor_.report(it_, estimate_) : monitor_.report_estimate(it_, estimate_);
    if (info_.status != FRIX_STATUS_MAX_ITER) return true;
    SweepAgreement agreement(form_, monitor_);
    const frix_status stop = monitor_.limits_after_report(it_, asked, std::ref(agreement));
    if (stop == FRIX_STATUS_NOT_RUN) return false;
    info_.status = stop;
    return true;
}

void SweepRun::finish() {
    // The iteration limit may fall between two full checks.
    if (info_.status == FRIX_STATUS_MAX_ITER && !checked_last_ && exact_error() <= tol_)
        info_.status = FRIX_STATUS_CONVERGED;
    if (info_.status != FRIX_STATUS_CONVERGED && !best_r_.empty()) {
        bool finite_r = true;
        for (int64_t i = 0; i < m_ && finite_r; ++i) finite_r = std::isfinite(r_[i]);
        const double final_error = !finite_r ? INFINITY : at_r_ ? selected_error(last_, measure_) : exact_error();
        if (best_error_ < final_error) {
            std::copy(best_r_.begin(), best_r_.end(), r_);
            form_.restart(r_, u_);
            exact_error();
        }
    }
    info_.iterations = it_;
    hand_over();
    if (verbosity_ >= 1)
        log_line(&o_, "%s: %s after %lld sweeps", name_, frix_status_string(info_.status), (long long)it_);
}

}  // namespace

frix_error run_sweeps(SolveContext &ctx, Workspace &ws, SweepForm &form, const char *name) {
    SweepRun(ctx, ws, form, name).run();
    return FRIX_OK;
}

}  // namespace nsgs
}  // namespace frix
