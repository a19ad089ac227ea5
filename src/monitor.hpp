// The solve contract in one place: every solver asks the Monitor whether its time is up,
// hands it each iteration's error for the user's callback, and records its factorisation
// counters with it, so that no solver writes these again.
#pragma once

#include <cmath>
#include <cstdint>

#include "info.hpp"
#include "linalg/linalg.hpp"
#include "options.hpp"
#include "solver_api.hpp"

namespace frix {

class Monitor {
   public:
    Monitor(const frix_options &o, const Stopwatch &clock) : o_(o), clock_(clock) {}
    explicit Monitor(const SolveContext &ctx) : Monitor(ctx.options, ctx.clock) {}

    // The error the solve must reach (option tolerance, on the solve's error measure) and its
    // iteration limit (option max_iter): read here, so that every solver stops on the same rule.
    double tolerance() const { return o_.d(FRIX_OPT_TOLERANCE); }
    int64_t max_iterations() const { return o_.i(FRIX_OPT_MAX_ITER); }
    bool out_of_iterations(int64_t done) const { return done >= max_iterations(); }

    // The time limit (option time_limit > 0) is reached.
    bool out_of_time() const {
        const double tl = o_.d(FRIX_OPT_TIME_LIMIT);
        return tl > 0.0 && clock_.seconds() >= tl;
    }
    bool time_limited() const { return o_.d(FRIX_OPT_TIME_LIMIT) > 0.0; }
    // Whether a factorisation of `flops` fits in what is left of the time limit (always,
    // without one): a factorisation cannot be stopped once started, so one that would
    // overrun the limit is not started. seconds: what the same factorisation took last time
    // (NaN if unknown), the better price.
    bool affords(double flops, double seconds = NAN) const {
        const double tl = o_.d(FRIX_OPT_TIME_LIMIT);
        if (!(tl > 0.0)) return true;
        const double left = tl - clock_.seconds();
        if (std::isfinite(seconds)) return kRepeatMargin * seconds <= left;
        return flops <= kSparseFactorShare * clock_.factor_rate() * left;
    }
    // The budget to give a factorisation (linalg::FlopBudget), on this Monitor's limit.
    linalg::FlopBudget budget() const {
        return [o = &o_, c = &clock_](double flops, double seconds) { return Monitor(*o, *c).affords(flops, seconds); };
    }

    // The user's callback after iteration `iteration` with the current error estimate: true
    // if it asks to stop. Without a callback, false.
    bool report(int64_t iteration, double error) const {
        return o_.callback && o_.callback(o_.callback_data, iteration, error, clock_.seconds()) != 0;
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

   private:
    // A first factorisation is priced at this share of a dense LU's rate: sparse kernels run
    // on small fronts, more slowly, but UMFPACK's flop count is an upper bound that overstates
    // the real one several times; the price errs long.
    static constexpr double kSparseFactorShare = 0.25;
    // A factorisation repeated on the same analysis is priced at its last time, with this margin.
    static constexpr double kRepeatMargin = 1.5;
    const frix_options &o_;
    const Stopwatch &clock_;
};

}  // namespace frix
