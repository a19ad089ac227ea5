// The driver's rolling path: what frix_solve owns for every solver of rolling-friction
// problems (solver_api.hpp), kept apart from the three-component paths, whose helpers
// (runaway checks, reduction, existence) know three entries a contact.
#include <algorithm>
#include <cmath>
#include <vector>

#include "error_state.hpp"
#include "measures.hpp"
#include "reduction.hpp"
#include "solver_api.hpp"

namespace frix {

namespace {

bool all_finite(const double *x, int64_t n) {
    return std::all_of(x, x + n, [](double y) { return std::isfinite(y); });
}

// r back to the start (or 0 where the start is not finite), and v = M^-1 (H r + f) for it:
// a diverged run's answer.
frix_error fall_back(const frix_problem &p, const std::vector<double> &start, double *r, double *v) {
    const int64_t m = 5 * p.nc;
    std::copy(start.begin(), start.end(), r);
    if (p.kind != FRIX_PROBLEM_ROLLING_GLOBAL) return FRIX_OK;
    MassSolver ms;
    if (frix_error e = ms.factor(*p.M)) return e;
    if (frix_error e = recover_velocity(p, ms, r, v)) return e;
    if (all_finite(v, p.n)) return FRIX_OK;
    std::fill(r, r + m, 0.0);
    return recover_velocity(p, ms, r, v);
}

}  // namespace

frix_error solve_rolling_problem(const frix_problem &p, const frix_options &opts, const SolverEntry &entry,
                                 double *r, double *u, double *v, frix_info &info, const Stopwatch &clock,
                                 SolveCache *cache) {
    const int64_t m = 5 * p.nc;
    const bool local = p.kind == FRIX_PROBLEM_ROLLING_LOCAL;
    // A non-finite warm start would poison every iterate; start such entries from 0.
    for (int64_t i = 0; i < m; ++i)
        if (!std::isfinite(r[i])) r[i] = 0.0;
    std::vector<double> start(r, r + m);
    if (separates_at_zero(p)) {
        std::fill(r, r + m, 0.0);
        info.status = FRIX_STATUS_CONVERGED;
        info.iterations = 0;
    } else {
        SolveContext ctx = local ? SolveContext::local(p, opts, r, u, info, clock)
                                 : SolveContext::global(p, opts, r, u, v, info, clock, nullptr);
        ctx.with_cache(cache);
        if (frix_error e = entry.solve(ctx)) return e;
    }
    bool broken = !all_finite(r, m) || (!local && !all_finite(v, p.n));
    Measures meas = broken ? Measures{}
                           : (local ? local_measures(p, r, u) : global_measures(p, r, v, u, &info.equilibrium));
    broken = broken || !std::isfinite(meas.relative) || !std::isfinite(meas.norm_u);
    if (broken) {
        // Diverged past the doubles: the start is returned, measured, never a non-finite u.
        if (frix_error e = fall_back(p, start, r, v)) return e;
        meas = local ? local_measures(p, r, u) : global_measures(p, r, v, u, &info.equilibrium);
        info.status = FRIX_STATUS_DIVERGED;
    }
    record_measures(info, meas, opts.i(FRIX_OPT_ERROR_MEASURE));
    // The status must agree with the final, independent measure.
    const bool met = local ? info.error <= info.tolerance : meets_global_tolerance(info, info.tolerance);
    if (info.status == FRIX_STATUS_CONVERGED && !met) info.status = FRIX_STATUS_STAGNATED;
    return FRIX_OK;
}

}  // namespace frix
