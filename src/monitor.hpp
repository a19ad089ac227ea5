// The solve contract in one place: every solver asks the Monitor whether its time is up,
// hands it each iteration's error for the user's callback, and records its factorisation
// counters with it, so that no solver writes these again.
#pragma once

#include <cmath>
#include <cstdint>
#include <functional>

#include "info.hpp"
#include "linalg/linalg.hpp"
#include "options.hpp"
#include "solver_api.hpp"

namespace frix {

class Monitor {
   public:
    Monitor(const frix_options &o, const Stopwatch &clock) : o_(o), clock_(clock) {}
    // With the solve's context, report() also watches ctx.r for a runaway (runs_away).
    explicit Monitor(const SolveContext &ctx) : o_(ctx.options), clock_(ctx.clock), ctx_(&ctx) {}

    // The error the solve must reach (option tolerance, on the solve's error measure) and its
    // iteration limit (option max_iter): read here, so that every solver stops on the same rule.
    double tolerance() const { return std::isnan(tol_) ? o_.d(FRIX_OPT_TOLERANCE) : tol_; }
    int64_t max_iterations() const { return max_iter_ < 0 ? o_.i(FRIX_OPT_MAX_ITER) : max_iter_; }
    // A run inside a solve (an inner solve, a stage) stops on its own tolerance and
    // iteration limit instead of the options'; the time limit and the callback stay.
    Monitor &with_limits(double tol, int64_t max_iter) {
        tol_ = tol;
        max_iter_ = max_iter;
        return *this;
    }
    bool out_of_iterations(int64_t done) const { return done >= max_iterations(); }

    // The time limit (option time_limit > 0) is reached.
    bool out_of_time() const {
        const double tl = o_.d(FRIX_OPT_TIME_LIMIT);
        return tl > 0.0 && clock_.seconds() >= tl;
    }
    bool time_limited() const { return o_.d(FRIX_OPT_TIME_LIMIT) > 0.0; }
    // Whether a factorisation fits in what is left of the time and memory limits:
    // FRIX_STATUS_NOT_RUN if it does, else the limit it would overrun. A factorisation cannot
    // be stopped once started, so one that would overrun is not started. Time: without a time
    // limit it always fits; a repeat is priced at its last time (price.seconds), a first one
    // at its flop count and its writes (each at the machine's rate). Memory: its peak
    // (price.bytes) against memory_left(); below kMemoryAskedAbove and without the option
    // memory_limit the system is not asked.
    frix_status affords(const linalg::FactorPrice &price) const {
        if (!fits_memory(price.bytes)) return FRIX_STATUS_MEMORY_LIMIT;
        const double tl = o_.d(FRIX_OPT_TIME_LIMIT);
        if (!(tl > 0.0)) return FRIX_STATUS_NOT_RUN;
        const double left = tl - clock_.seconds();
        // One that fits even at the slowest rates is afforded without timing the machine.
        if (price.flops / kSlowestRate + price.writes / kSlowestWriteRate <= left) return FRIX_STATUS_NOT_RUN;
        if (std::isfinite(price.seconds))
            return kRepeatMargin * price.seconds <= left ? FRIX_STATUS_NOT_RUN : FRIX_STATUS_TIME_LIMIT;
        const double share = price.flops_upper_bound ? kUpperBoundShare : kExactCountShare;
        const double seconds = price.flops / (share * clock_.factor_rate()) +
                               (price.writes > 0.0 ? price.writes / clock_.write_rate() : 0.0);
        return seconds <= left ? FRIX_STATUS_NOT_RUN : FRIX_STATUS_TIME_LIMIT;
    }
    // The budget to give a factorisation (linalg::FactorBudget), on this Monitor's limits.
    linalg::FactorBudget budget() const {
        return [o = &o_, c = &clock_](const linalg::FactorPrice &price) { return Monitor(*o, *c).affords(price); };
    }
    // The same, on the memory limit alone: for the factorisations a time limit must not stop.
    linalg::FactorBudget memory_budget() const {
        return [o = &o_, c = &clock_](const linalg::FactorPrice &price) {
            return Monitor(*o, *c).fits_memory(price.bytes) ? FRIX_STATUS_NOT_RUN : FRIX_STATUS_MEMORY_LIMIT;
        };
    }
    // The memory the solve may still take, in bytes (Stopwatch::memory_left on the option
    // memory_limit), and whether that option is set.
    double memory_left() const { return clock_.memory_left(o_.d(FRIX_OPT_MEMORY_LIMIT)); }
    bool memory_limited() const { return o_.d(FRIX_OPT_MEMORY_LIMIT) > 0.0; }
    // Whether `bytes` more fit in memory_left() (asked only as affords() says).
    bool fits_memory(double bytes) const {
        return !(bytes > 0.0) || !(memory_limited() || bytes >= kMemoryAskedAbove) || bytes <= memory_left();
    }

    // The user's callback after iteration `iteration`, whose error `error` was measured on the
    // iterate by the solve's measure: true if it asks to stop. Without a callback, false.
    // With a context, every kRunawayEvery iterations it also checks whether the iterate has
    // run away (r, for a solver that iterates on its own copy; else ctx.r): then it asks to
    // stop and marks the run (frix_info::ran_away), which the driver reports as diverged.
    bool report(int64_t iteration, double error, const double *r = nullptr) const {
        return call(iteration, error, r, true);
    }
    // The same for an error that is only an estimate (a light error, an inner solve's): the
    // callback sees it unless the option callback_estimates is 0.
    bool report_estimate(int64_t iteration, double estimate, const double *r = nullptr) const {
        return call(iteration, estimate, r, false);
    }
    // Whether the iterate (r, or ctx.r) has run away (runs_away past ctx.runaway_bound; never
    // without a context): then it marks the run as report() does. For a solver whose steps are
    // few and each a solve of its own (a proximal step), asked after every one.
    bool ran_away(const double *r = nullptr) const {
        if (!ctx_ || !(ctx_->runaway_bound > 0.0) || !runs_away(ctx_->problem, r ? r : ctx_->r, ctx_->runaway_bound))
            return false;
        ctx_->info.ran_away = true;
        return true;
    }

    // Whether a flag raised on this process is raised anywhere (frix::Agree).
    using Agree = ::frix::Agree;

    // The one place a run's status is decided (the convergence test of PETSc's SNES). After
    // iteration `it` (the caller's count, against max_iterations()) whose error is `error` (on
    // the measure the tolerance is on), reported (report(): the callback sees the last
    // iteration too, a converged one included): CONVERGED (error <= tolerance()), DIVERGED
    // (error not finite), then the limits as limits() has them; FRIX_STATUS_NOT_RUN to go on.
    // r: as for report().
    frix_status verdict(int64_t it, double error, const double *r = nullptr, const Agree &agree = nullptr) const {
        const bool asked = report(it, error, r);
        const frix_status settled = settles(error);
        return settled != FRIX_STATUS_NOT_RUN ? settled : limits_after_report(it, asked, agree);
    }
    // The same without the error test, for an iteration whose error is only an estimate the
    // solver confirms apart: STOPPED_BY_CALLBACK (report_estimate(): the callback, or a
    // runaway), TIME_LIMIT, MAX_ITER, in that order; FRIX_STATUS_NOT_RUN to go on.
    frix_status limits(int64_t it, double estimate, const double *r = nullptr, const Agree &agree = nullptr) const {
        return limits_after_report(it, report_estimate(it, estimate, r), agree);
    }
    // verdict() for a solver that calls report() itself after every iteration (the one that
    // converges too: Newton's callback sees each step) and decides before the next one: `asked`
    // is what report() answered (with agree, on any rank). The iteration limit comes before the
    // callback and the time: a run on a budget of iterations (a stage of auto) that spent it says
    // so, though the callback asked to stop after its last one.
    frix_status verdict_after_report(int64_t it, double error, bool asked, const Agree &agree = nullptr) const {
        const frix_status settled = settles(error);
        if (settled != FRIX_STATUS_NOT_RUN) return settled;
        if (out_of_iterations(it)) return FRIX_STATUS_MAX_ITER;
        return limits_after_report(it, asked, agree);
    }
    // limits() with report()'s answer `asked`.
    frix_status limits_after_report(int64_t it, bool asked, const Agree &agree = nullptr) const {
        if (agreed(asked, agree)) return FRIX_STATUS_STOPPED_BY_CALLBACK;
        if (agreed(out_of_time(), agree)) return FRIX_STATUS_TIME_LIMIT;
        if (out_of_iterations(it)) return FRIX_STATUS_MAX_ITER;
        return FRIX_STATUS_NOT_RUN;
    }

    // The factorisations of a solve: set into info, or added to what it already counts.
    static void record_factorizations(frix_info &info, const linalg::FactorStats &fs) {
        info.factorizations = fs.numeric;
        info.symbolic_analyses = fs.symbolic;
        info.factorization_time = fs.seconds;
    }
    static void add_factorizations(frix_info &into, const frix_info &from) {
        into.factorizations += from.factorizations;
        into.symbolic_analyses += from.symbolic_analyses;
        into.factorization_time += from.factorization_time;
    }
    // Adds the counters of `from`'s work (Newton steps, line searches, factorisations,
    // hybrid sweeps, inner iterations, setup) to `into`: one run made of several.
    static void add_work(frix_info &into, const frix_info &from) {
        into.newton_iterations += from.newton_iterations;
        into.line_search_steps += from.line_search_steps;
        add_factorizations(into, from);
        into.hybrid_sweeps += from.hybrid_sweeps;
        into.inner_iterations += from.inner_iterations;
        into.setup_time += from.setup_time;
        into.reduction_time += from.reduction_time;
    }

   private:
    bool call(int64_t iteration, double error, const double *r, bool measured) const {
        if (iteration % kRunawayEvery == 0 && ran_away(r)) return true;
        if (o_.callback_with_kind) return o_.callback_with_kind(o_.callback_data, iteration, error, measured) != 0;
        if (!o_.callback || !(measured || o_.i(FRIX_OPT_CALLBACK_ESTIMATES))) return false;
        return o_.callback(o_.callback_data, iteration, error, clock_.seconds()) != 0;
    }
    static bool agreed(bool flag, const Agree &agree) { return agree ? agree(flag) : flag; }
    // CONVERGED (error <= tolerance()), DIVERGED (error not finite), else FRIX_STATUS_NOT_RUN.
    frix_status settles(double error) const {
        if (error <= tolerance()) return FRIX_STATUS_CONVERGED;
        return std::isfinite(error) ? FRIX_STATUS_NOT_RUN : FRIX_STATUS_DIVERGED;
    }
    // A first factorisation is priced at a share of a dense LU's rate: CHOLMOD's flop count
    // is exact and its supernodes run dense kernels, at about the dense rate (a smaller share
    // refused factorisations that fitted); UMFPACK's is an upper bound that overstates the
    // real one several times, on smaller fronts: a quarter, the price errs long.
    static constexpr double kExactCountShare = 1.0, kUpperBoundShare = 0.25;
    // Flops per second no machine we run on is slower than, sparse kernels included: below
    // it the rate (a timed dense LU of a few milliseconds, once per solve) is not needed.
    static constexpr double kSlowestRate = 1e8;
    // Entries per second no machine we run on writes more slowly, its first touch of a page
    // included: below it the write rate (tens of milliseconds of timed writes) is not needed.
    static constexpr double kSlowestWriteRate = 1e7;
    // A factorisation repeated on the same analysis is priced at its last time, with this margin.
    static constexpr double kRepeatMargin = 1.5;
    // Without the option memory_limit, a factorisation smaller than this is not checked (the
    // check reads the system's counters; no machine we run on lacks 64 MB).
    static constexpr double kMemoryAskedAbove = 64e6;
    // A runaway check costs a pass over r: every this many iterations.
    static constexpr int64_t kRunawayEvery = 8;
    const frix_options &o_;
    const Stopwatch &clock_;
    const SolveContext *ctx_ = nullptr;
    double tol_ = NAN;
    int64_t max_iter_ = -1;
};

// The progress reports of an inner solve, forwarded to the caller's options: numbered on by
// `offset` (the iterations done before it), and told as estimates where `as_estimates` (the
// inner problem's errors are not the caller's measure).
struct ForwardedReports {
    const frix_options *outer;
    const Stopwatch *clock;
    int64_t offset = 0;
    bool as_estimates = false;
    static int forward(void *data, int64_t iteration, double error, bool measured) {
        const ForwardedReports *c = static_cast<const ForwardedReports *>(data);
        const Monitor monitor(*c->outer, *c->clock);
        const int64_t it = c->offset + iteration;
        return (measured && !c->as_estimates ? monitor.report(it, error) : monitor.report_estimate(it, error)) ? 1 : 0;
    }
    // o with its callback replaced by this forwarder, where the caller's options have one.
    frix_options applied_to(frix_options o) {
        if (!outer->has_callback()) return o;
        o.callback = nullptr;
        o.callback_with_kind = &forward;
        o.callback_data = this;
        return o;
    }
};

}  // namespace frix
