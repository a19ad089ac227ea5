// frix_solve: the driver around every solver. It owns what must be the same for all of them:
// argument checks, the empty and all-separating cases, a finite warm start, timing, and the
// final measures computed by the one error module from the r actually returned.
#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "error_state.hpp"
#include "measures.hpp"
#include "solver_api.hpp"

using frix::fail;

namespace frix {

frix_error solve_local_problem(const frix_problem &p, const frix_options &opts,
                               const SolverEntry &entry, double *r, double *u, frix_info &info,
                               const Stopwatch &clock, SolveCache *cache, Measures *measures) {
    const int64_t m = 3 * p.nc;
    bool separating = true;
    for (int64_t a = 0; a < p.nc && separating; ++a) separating = p.q[3 * a] >= 0.0;
    // Kept to fall back on if the solver diverges: a finite but huge r can make W r + q
    // overflow, and the caller must never get a non-finite u or error back. Not copied when
    // it is r = 0 (the usual cold start: no allocation for it).
    std::vector<double> warm_start;
    bool ran = false, has_measured = false, non_finite = false;
    frix::Measures measured;
    if (p.nc == 0 || separating) {
        // r = 0 is then the exact solution: u = q has u_N >= 0, so u^ lies in K*.
        for (int64_t i = 0; i < m; ++i) r[i] = 0.0;
        info.status = FRIX_STATUS_CONVERGED;
        info.iterations = 0;
    } else {
        // A non-finite warm start would poison every iterate; start such entries from 0.
        for (int64_t i = 0; i < m; ++i)
            if (!std::isfinite(r[i])) r[i] = 0.0;
        if (!entry.solves_local)
            return fail(FRIX_ERR_UNSUPPORTED, "frix_solve: solver %s does not solve local problems", entry.name);
        if (std::any_of(r, r + m, [](double x) { return x != 0.0; })) warm_start.assign(r, r + m);
        ran = true;
        frix::SolveContext ctx{p, opts, r, u, nullptr, info, clock, nullptr, nullptr, cache};
        if (frix_error e = entry.solve(ctx)) return e;
        // A solver whose iterates ran away past the doubles (no solution to approach) has
        // diverged: the fallback below answers with a finite r.
        non_finite = std::any_of(r, r + m, [](double x) { return !std::isfinite(x); });
        has_measured = ctx.has_measured && !non_finite;
        measured = ctx.measured;
    }
    // |u| is part of the test: an overflowed u can leave the relative error finite (it
    // divides by |u| = Inf).
    auto finite = [](const frix::Measures &x) { return std::isfinite(x.relative) && std::isfinite(x.norm_u); };
    frix::Measures meas = has_measured ? measured : (non_finite ? frix::Measures{} : frix::local_measures(p, r, u));
    if ((non_finite || !finite(meas)) && ran) {
        if (warm_start.empty())
            std::fill(r, r + m, 0.0);
        else
            std::copy(warm_start.begin(), warm_start.end(), r);
        meas = frix::local_measures(p, r, u);
        if (!finite(meas)) {
            std::fill(r, r + m, 0.0);  // u = q then: finite, since q was checked
            meas = frix::local_measures(p, r, u);
        }
        info.status = FRIX_STATUS_DIVERGED;
    }
    frix::record_measures(info, meas, opts.i(FRIX_OPT_ERROR_MEASURE));
    if (measures) *measures = meas;
    // The status must agree with the final, independent measure.
    if (info.status == FRIX_STATUS_CONVERGED && !(info.error <= info.tolerance))
        info.status = FRIX_STATUS_STAGNATED;
    return FRIX_OK;
}

frix_error solve_problem(const char *caller, const frix_problem *problem, const frix_options *options,
                         double *r, double *u, double *v, frix_info *info, SolveCache *cache) {
    Stopwatch clock;
    if (!problem) return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: problem is NULL", caller);
    const int64_t m = 3 * problem->nc;
    if (m > 0 && (!r || !u))
        return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: r and u are required (%lld entries each)", caller,
                    (long long)m);
    std::unique_ptr<frix_options> default_options;
    if (!options) {
        frix_options *o = nullptr;
        if (frix_error e = frix_options_create(kDefaultSolver, &o)) return e;
        default_options.reset(o);
        options = o;
    }
    const SolverEntry *entry = find_solver(options->solver_id);
    if (!entry) return fail(FRIX_ERR_UNKNOWN_SOLVER, "%s: no solver has id %d", caller, options->solver_id);
    if (frix_error e = check_problem_vectors(*problem)) return e;

    frix_info local_info;
    frix_info &out = info ? *info : local_info;
    {   // A fresh info, but the trace's buffers kept: a caller solving every time step
        // should not pay for their allocation each time.
        std::vector<TraceEvent> trace = std::move(out.trace);
        std::string text = std::move(out.trace_text);
        trace.clear();
        text.clear();
        out = frix_info();
        out.trace = std::move(trace);
        out.trace_text = std::move(text);
    }
    out.solver_id = entry->id;
    out.contacts = problem->nc;
    out.tolerance = options->d(FRIX_OPT_TOLERANCE);

    frix_error err;
    if (problem->kind == FRIX_PROBLEM_GLOBAL) {
        if (problem->n > 0 && !v)
            return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: v is required for a global problem (%lld entries)", caller,
                        (long long)problem->n);
        err = solve_global_problem(*problem, *options, *entry, r, u, v, out, clock, cache);
    } else if (!entry->solves_local) {
        err = fail(FRIX_ERR_UNSUPPORTED, "%s: solver %s solves global problems only", caller, entry->name);
    } else {
        err = solve_local_problem(*problem, *options, *entry, r, u, out, clock, cache);
    }
    out.solve_time = clock.seconds();
    return err;
}

}  // namespace frix

extern "C" {

FRIX_API frix_error frix_solve(const frix_problem *problem, const frix_options *options, double *r,
                               double *u, double *v, frix_info *info) {
    return frix::guard("frix_solve", [&]() -> frix_error {
        return frix::solve_problem("frix_solve", problem, options, r, u, v, info, nullptr);
    });
}

}  // extern "C"
