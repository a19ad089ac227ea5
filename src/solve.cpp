// frix_solve: the driver around every solver. It owns what must be the same for all of them:
// argument checks, the empty and all-separating cases, a finite warm start, timing, and the
// final measures computed by the one error module from the r actually returned.
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "error_state.hpp"
#include "existence.hpp"
#include "measures.hpp"
#include "memory.hpp"
#include "solver_api.hpp"
#include "vec.hpp"

using frix::fail;

namespace {

// The share of a time limit kept for the existence check of a failed solve: a run that ends
// at its limit still says whether a solution exists at all.
constexpr double kExistenceShare = 0.05;
// The least time the check is given when a limit leaves it less (a few FISTA steps).
constexpr double kExistenceMinSeconds = 1e-3;

// A failed run (not stopped by the caller) without a verdict on existence gets one.
void check_existence_after_failure(const frix_problem &p, const frix_options &o, const frix::Stopwatch &clock,
                                   frix_info &info) {
    if (info.status == FRIX_STATUS_CONVERGED || info.status == FRIX_STATUS_STOPPED_BY_CALLBACK ||
        info.existence != FRIX_EXISTENCE_NOT_CHECKED || !o.i(FRIX_OPT_EXISTENCE_CHECK) || p.nc == 0)
        return;
    if (frix::is_rolling(p)) {  // the check cannot decide a rolling problem that r = 0 does not solve
        info.existence = FRIX_EXISTENCE_UNDETERMINED;
        return;
    }
    const double tl = o.d(FRIX_OPT_TIME_LIMIT);
    const double budget = tl > 0.0 ? std::max(tl - clock.seconds(), kExistenceMinSeconds) : 0.0;
    double margin = NAN;
    info.existence = frix::check_existence(p, budget, &margin);
    info.existence_margin = margin;
}

}  // namespace

namespace frix {

double runaway_bound(double free_velocity_norm) {
    return std::isfinite(free_velocity_norm) ? kRunawayFactor * free_velocity_norm : 0.0;
}

bool runs_away(const frix_problem &p, const double *r, double bound) {
    if (!r || !(bound > 0.0)) return false;
    const int dim = contact_size(p);
    for (int64_t a = 0; a < p.nc; ++a) {
        const double w = p.weight.empty() ? 1.0 : p.weight[(size_t)a];
        const double *ra = r + dim * a;
        for (int i = 0; i < dim; ++i)
            if (!(w * std::fabs(ra[i]) <= bound)) return true;
    }
    return false;
}

std::vector<double> finite_warm_start(double *r, int64_t m) {
    for (int64_t i = 0; i < m; ++i)
        if (!std::isfinite(r[i])) r[i] = 0.0;
    if (vec::all_zero(r, m)) return {};
    std::vector<double> copy;
    copy_advised(copy, r, (size_t)m);
    return copy;
}

bool finite_measures(const Measures &x) {
    return std::isfinite(x.relative) && std::isfinite(x.norm_u) && (!x.global || std::isfinite(x.equilibrium));
}

frix_error fall_back_on_divergence(const frix_problem &p, int64_t measure_kind, const std::vector<double> &warm_start,
                                   bool broken, double bound, const MeasureAnswer &measure, double *r, double *u,
                                   double *v, Measures &meas, frix_info &info, const Agree &agree) {
    const auto agreed = [&agree](bool flag) { return agree ? agree(flag) : flag; };
    broken = agreed(broken);
    if (!broken && info.status == FRIX_STATUS_CONVERGED) return FRIX_OK;
    info.ran_away = agreed(info.ran_away || (!broken && runs_away(p, r, bound)));
    if (!broken && !info.ran_away) return FRIX_OK;
    // The start is returned (r = 0 where the start overflows too: u = q, or the free motion,
    // then), the r of a run that ran away (its last, or the best it kept) only where its error
    // is below half of the start's: an r of 1e150 is no answer to hand a caller, nor one that
    // a diverging run drifted to.
    const int64_t m = contact_size(p) * p.nc, n = is_local_form(p) ? 0 : p.n;
    std::vector<double> start = warm_start.empty() ? std::vector<double>((size_t)m, 0.0) : warm_start;
    std::vector<double> u_start((size_t)m), v_start((size_t)n);
    Measures at_start;
    if (frix_error e = measure(start.data(), u_start.data(), v_start.data(), at_start)) return e;
    if (broken && !finite_measures(at_start)) {
        std::fill(start.begin(), start.end(), 0.0);
        if (frix_error e = measure(start.data(), u_start.data(), v_start.data(), at_start)) return e;
    }
    const bool keep_start = finite_measures(at_start) &&
                            selected_error(at_start, measure_kind) <= 2.0 * selected_error(meas, measure_kind);
    if (broken || keep_start) {
        std::copy(start.begin(), start.end(), r);
        std::copy(u_start.begin(), u_start.end(), u);
        if (v) std::copy(v_start.begin(), v_start.end(), v);
        meas = at_start;
    }
    info.status = FRIX_STATUS_DIVERGED;
    return FRIX_OK;
}

frix_error solve_local_problem(const frix_problem &p, const frix_options &opts,
                               const SolverEntry &entry, double *r, double *u, frix_info &info,
                               const Stopwatch &clock, SolveCache *cache, Measures *measures, bool return_best,
                               bool accept_start, const Measures *measured_start) {
    const int64_t m = contact_size(p) * p.nc;
    std::vector<double> warm_start;  // finite_warm_start, for a problem a solver ran on
    bool ran = false, has_measured = false, non_finite = false;
    double bound = 0.0;  // runaway_bound, for a problem a solver ran on
    frix::Measures measured, start;  // start: the warm start's, where measured here
    const bool separates = separates_at_zero(p);
    if (separates) {
        for (int64_t i = 0; i < m; ++i) r[i] = 0.0;
        info.status = FRIX_STATUS_CONVERGED;
        info.iterations = 0;
    } else {
        if (!(is_rolling(p) ? entry.solves_rolling : entry.solves_local))
            return fail(FRIX_ERR_UNSUPPORTED, "frix_solve: solver %s does not solve %s local problems", entry.name,
                        is_rolling(p) ? "rolling-friction" : "three-component");
        warm_start = finite_warm_start(r, m);
        // A start that already solves the problem to the tolerance is the answer: a time step
        // at rest, whose last answer still holds, costs one product with W instead of a sweep.
        if (accept_start && !warm_start.empty()) {
            if (!measured_start) {
                start = frix::local_measures(p, r, u);
                measured_start = &start;
            }
            const double error = selected_error(*measured_start, opts.i(FRIX_OPT_ERROR_MEASURE));
            has_measured = finite_measures(*measured_start) && error <= opts.d(FRIX_OPT_TOLERANCE);
            if (has_measured) {
                measured = *measured_start;
                info.status = FRIX_STATUS_CONVERGED;
                info.iterations = 0;
            }
        }
    }
    if (!separates && !has_measured) {
        ran = true;
        frix::SolveContext ctx = frix::SolveContext::local(p, opts, r, u, info, clock).with_cache(cache);
        ctx.runaway_bound = bound = runaway_bound(norm2(p.q, m));
        ctx.return_best = return_best;
        if (!warm_start.empty()) ctx.measured_start = measured_start;
        if (frix_error e = entry.solve(ctx)) return e;
        // A solver whose iterates ran away past the doubles (no solution to approach) has
        // diverged: the fallback below answers with a finite r.
        non_finite = !vec::all_finite(r, m);
        has_measured = ctx.has_measured && !non_finite;
        measured = ctx.measured;
    }
    frix::Measures meas = has_measured ? measured : (non_finite ? frix::Measures{} : frix::local_measures(p, r, u));
    if (ran) {
        // Diverged: an r that left the doubles or overflows u, or a finite runaway.
        const MeasureAnswer at = [&p](const double *x, double *ux, double *, Measures &out) {
            out = local_measures(p, x, ux);
            return FRIX_OK;
        };
        if (frix_error e = fall_back_on_divergence(p, opts.i(FRIX_OPT_ERROR_MEASURE), warm_start,
                                                   non_finite || !finite_measures(meas), bound, at, r, u, nullptr,
                                                   meas, info))
            return e;
    }
    frix::record_measures(info, meas, opts.i(FRIX_OPT_ERROR_MEASURE));
    if (measures) *measures = meas;
    // The status must agree with the final, independent measure.
    if (info.status == FRIX_STATUS_CONVERGED && !(info.error <= info.tolerance))
        info.status = FRIX_STATUS_STAGNATED;
    return FRIX_OK;
}

frix_error check_solver_takes(const char *caller, const SolverEntry &entry, const frix_problem &p) {
    if (is_rolling(p)) {
        if (entry.solves_rolling) return FRIX_OK;
        std::string which;  // the registry's solvers of rolling problems, for the message
        for (int64_t k = 0; k < solver_count(); ++k)
            if (solver_at(k).solves_rolling) which += (which.empty() ? "" : ", ") + std::string(solver_at(k).name);
        return fail(FRIX_ERR_UNSUPPORTED, "%s: solver %s does not solve rolling-friction problems (%s do)", caller,
                    entry.name, which.c_str());
    }
    if (!entry.solves_local && !entry.solves_global)
        return fail(FRIX_ERR_UNSUPPORTED, "%s: solver %s solves rolling-friction problems only", caller, entry.name);
    if (p.kind == FRIX_PROBLEM_LOCAL && !entry.solves_local)
        return fail(FRIX_ERR_UNSUPPORTED, "%s: solver %s solves global problems only", caller, entry.name);
    return FRIX_OK;
}

frix_error solve_problem(const char *caller, const frix_problem *problem, const frix_options *options,
                         double *r, double *u, double *v, frix_info *info, SolveCache *cache) {
    Stopwatch clock;
    if (!problem) return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: problem is NULL", caller);
    const int64_t m = contact_size(*problem) * problem->nc;
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

    // The solver runs within all but the existence check's share of a time limit.
    frix_options run = *options;
    const double tl = options->d(FRIX_OPT_TIME_LIMIT);
    if (tl > 0.0 && options->i(FRIX_OPT_EXISTENCE_CHECK)) run.dvalue[FRIX_OPT_TIME_LIMIT] = tl * (1.0 - kExistenceShare);
    if (frix_error e = check_solver_takes(caller, *entry, *problem)) {
        out.solve_time = clock.seconds();
        return e;
    }
    const bool global = !is_local_form(*problem);
    if (global && problem->n > 0 && !v)
        return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: v is required for a global problem (%lld entries)", caller,
                    (long long)problem->n);
    frix_error err;
    if (global)
        err = solve_global_problem(*problem, run, *entry, r, u, v, out, clock, cache);
    else
        err = solve_local_problem(*problem, run, *entry, r, u, out, clock, cache, nullptr, true, true);
    if (!err) check_existence_after_failure(*problem, *options, clock, out);
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
