// What auto's stages share (the caller's options, clock, callback and log, the iterations of
// all parts) and the watchdog every stage runs under: the rate watch (does the stage's rate
// promise the tolerance soon enough?), the stall watch (tenfold progress within its patience)
// and the Newton watch (steps that creep).
#pragma once

#include <atomic>
#include <cmath>
#include <cstdint>
#include <mutex>
#include <utility>
#include <vector>

#include "solvers/auto/policy.hpp"
#include "src/monitor.hpp"

namespace frix::autosolve {

// Rate: does the stage's rate promise the tolerance soon enough; Stall: tenfold progress within
// its patience; Newton: a Newton polish, stopped after `patience` steps in a row that do not
// bring its best error below kNewtonSlowStepRatio times the best before (steps cut short by
// the line search, or a proximal restart that undid the progress). Its steps are the stage's
// reports: Newton steps, or proximal steps once it reports measured errors.
enum class Watch { Rate, Stall, Newton };

// Shared by the parts of one solve: the caller's callback (called under a lock, with the
// iterations of all parts summed) and the stop it may request.
struct Shared {
    const frix_options &user;
    const Stopwatch &clock;
    std::mutex lock;
    std::atomic<int64_t> iterations{0};
    std::atomic<bool> stop_requested{false};
    // A stage's iterate ran away (frix_info::ran_away): no solution, and no other stage will find
    // one; stop_requested is raised with it, and the solve is reported as diverged.
    std::atomic<bool> ran_away{false};
    bool scaled_penalty = false;  // ADMM with per-contact penalties (kScaledPenaltySpread)
    // The contacts of the whole problem (-1: every stage runs on all of them): a stage on
    // fewer measures its part only, so the caller's callback takes its errors as estimates.
    int64_t contacts = -1;
    // The threads a part's stage may use for its own loops: the caller's where it is the only
    // part, else one (the parts share the threads).
    int64_t part_threads = 1;
    Shared(const frix_options &u, const Stopwatch &c) : user(u), clock(c) {}

    double deadline() const {
        const double tl = user.d(FRIX_OPT_TIME_LIMIT);
        return tl > 0.0 ? tl : INFINITY;
    }
    bool out_of_time() const { return Monitor(user, clock).out_of_time(); }
    bool out_of_iterations() const { return Monitor(user, clock).out_of_iterations(iterations.load()); }
    // The status of a solve that ends here: converged, stopped by the caller, or the limit
    // that ended it; FRIX_STATUS_NOT_RUN where none did.
    frix_status ending(bool converged, bool stopped) const;

    // The user's log sink, one line at a time: stages on several threads share it.
    std::mutex log_lock;
    static void log(void *data, const char *line);
};

// The watchdog, installed as the progress callback of every stage.
struct Watchdog {
    Watchdog(Shared &s, Watch k, double tol, int64_t patience_, int64_t min_sweeps_)
        : shared(&s), kind(k), tolerance(tol), patience(patience_), min_sweeps(min_sweeps_) {}
    Watchdog(const Watchdog &) = delete;  // its address is the stage's callback data
    Watchdog &operator=(const Watchdog &) = delete;

    Shared *shared;
    Watch kind;
    double tolerance;
    int64_t patience;
    int64_t min_sweeps;
    // Watch::Rate: the price of one iteration and of the stage that would replace this one
    // (0: none; the rate is then judged against the stage's own work alone).
    double iteration_work = 0.0, alternative_work = 0.0;
    // Whether the rate may also go on for a multiple of the iterations done (kNsgsPatience, or
    // kPricedPatience on a priced part), or only within alternative_work (a probe of it).
    bool patient = true;
    double predicted = NAN;  // iterations the rate last predicted to the tolerance
    const char *slow = "NSGS rate too slow";
    int64_t last_iteration = 0;  // the stage's iteration count at the previous call
    double best = INFINITY;      // best error of the stage
    // Watch::Newton: the measured error the stage starts from (INFINITY: not known), the slow
    // steps in a row, and whether the stage has reported a measured error (its estimates are
    // then ignored: they may be those of an inner problem).
    double newton_start = INFINITY;
    int64_t slow_steps = 0;
    bool measured_seen = false;
    const char *creeping = "Newton steps too slow";
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
    bool whole_problem = true;  // the stage runs on every contact (Shared::contacts)

    // Installed as the stage's options' callback_with_kind, on the watchdog as its data.
    static int callback(void *data, int64_t iteration, double error, bool measured) {
        return static_cast<Watchdog *>(data)->on_progress(iteration, error, measured);
    }
    void install(frix_options &o) {
        o.callback = nullptr;
        o.callback_with_kind = &Watchdog::callback;
        o.callback_data = this;
    }
    int on_progress(int64_t iteration, double error, bool measured);
    // Whether the stage ended for its rate (not its stall, a limit or the caller).
    bool stopped_slow() const { return stopped_by_watchdog && why == slow; }
    // Whether the Newton watch ended the stage for its creeping steps.
    bool stopped_creeping() const { return stopped_by_watchdog && why == creeping; }

   private:
    int stop(const char *reason) {
        why = reason;
        stopped_by_watchdog = true;
        return 1;
    }
    // The error the rate is measured on: on a priced part the stage's best (NSGS reports a
    // light error between its full checks, and ADMM's restarts are not monotone), elsewhere
    // its last.
    double judged_error(double error) const { return iteration_work > 0.0 ? best : error; }
    double limit(int64_t sweeps, double allowed) const;
    int judge_rate(double error, int64_t sweeps);
    int judge_newton(double error, bool measured);
    // The gain of log(error) over the sweeps from *from on, for the rate; false: not judged yet.
    bool rate_gain(double error, int64_t sweeps, double *gained, int64_t *from);
    void log_rate(int64_t sweeps, double error, double allowed) const;
};

// The sweeps before the rate watch judges NSGS on a problem of `blocks` blocks of W.
int64_t nsgs_min_sweeps(int64_t blocks);

}  // namespace frix::autosolve
