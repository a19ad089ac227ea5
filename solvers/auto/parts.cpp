// auto on a local problem (routes.hpp): the analysis, NSGS on the whole problem first, then
// the parts (each island of at least kMinIslandContacts contacts, the smaller ones together),
// on several threads when the caller allows them, until the whole problem's error meets the
// tolerance, and the status.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "solvers/auto/analysis.hpp"
#include "solvers/auto/part.hpp"
#include "solvers/auto/routes.hpp"
#include "src/error_state.hpp"

namespace frix::autosolve {

namespace {

// A part of a local problem, with its sub-problem (none when the problem is one part) and its
// solver.
struct Island {
    std::vector<int64_t> contacts;
    std::unique_ptr<frix_problem, void (*)(frix_problem *)> sub{nullptr, frix_problem_free};
    std::unique_ptr<IslandSolver> solver;
    std::vector<double> r;
    double error = INFINITY;
    double loosening = 1.0;  // its tolerance over the whole problem's (part_loosening)
    frix_error status = FRIX_OK;
    std::string message;  // the error message of a failed solve, from its thread
};

struct Parts {
    std::vector<Island> islands;
    bool whole = false;          // one part: the whole problem itself
    std::vector<size_t> copied;  // each part's records copied into the trace so far
};

// How much looser than the whole problem's tolerance a part's may be: the whole problem's
// residual is the parts' in quadrature, and each part's error is relative to its own size, so
// a part whose |q_part| is small next to |q| may stop at a larger error of its own:
// |q| / (|q_part| sqrt(2 parts)), between 1 and kMaxPartLoosening. Where the whole problem
// then misses, the parts are solved again with their loosening shrunk, and then tighter.
double part_loosening(double norm_q, double part_norm_q, size_t parts) {
    const double share = part_norm_q * std::sqrt(2.0 * (double)parts);
    if (!(share > 0.0)) return kMaxPartLoosening;
    return std::clamp(norm_q / share, 1.0, kMaxPartLoosening);
}

// The cache of each part for this solve: the kept ones when the parts are those of the last
// solve on the same pattern, new ones otherwise; their W versions are the problem's.
void part_caches(KeptAuto &kept, const SolveCache &cache, const std::vector<std::vector<int64_t>> &parts) {
    if (kept.w_pattern != cache.w_pattern || kept.parts != parts) {
        kept.part_caches.clear();
        for (size_t k = 0; k < parts.size(); ++k) kept.part_caches.push_back(std::make_unique<SolveCache>());
        kept.parts = parts;
        kept.w_pattern = cache.w_pattern;
    }
    for (std::unique_ptr<SolveCache> &c : kept.part_caches) {
        c->w_values = cache.w_values;
        c->w_pattern = cache.w_pattern;
    }
}

// Plain NSGS on ctx's problem from ctx.r, before any part is set up: with sweeps = 0 the first
// stage of a problem that is one part of fewer than kPlainNsgsMaxContacts contacts (the rate
// watch, as IslandSolver::first_stage runs it), otherwise that many sweeps (the stall watch
// then only counts). Its sweeps are counted in `shared`, its record goes into the trace. Sets
// *converged; ctx holds its iterate, counters and measures either way, and *measured the
// measures of that iterate (ctx.u holds W r + q).
frix_error direct_nsgs(SolveContext &ctx, Shared &shared, double tol, int64_t sweeps, bool *converged,
                       Measures *measured) {
    const frix_problem &p = ctx.problem;
    const SolverEntry &nsgs = *find_solver(FRIX_SOLVER_NSGS);
    const StageRequest req = sweeps > 0 ? stall_request(FRIX_SOLVER_NSGS, sweeps + 1, sweeps, tol)
                                        : rate_request(FRIX_SOLVER_NSGS, kFirstNsgsSweeps, tol);
    bool cut_short = false;
    frix_options o = stage_options(nsgs, ctx.options, tol, stage_iterations(shared, req.budget, &cut_short), &shared);
    Watchdog dog(shared, req.watch, tol, req.patience, nsgs_min_sweeps(p.W->nblocks()));
    dog.install(o);

    frix_info &info = ctx.info;
    info.status = FRIX_STATUS_NOT_RUN;
    info.iterations = 0;
    const double t0 = ctx.clock.seconds();
    SolveContext sub = SolveContext::local(p, o, ctx.r, ctx.u, info, ctx.clock);
    sub.runaway_bound = ctx.runaway_bound;  // the whole problem's, as the driver set it: a runaway stops the solve
    sub.measured_start = ctx.measured_start;
    if (frix_error e = nsgs.solve(sub)) return e;
    ctx.has_measured = sub.has_measured;
    ctx.measured = sub.measured;
    *measured = sub.has_measured ? sub.measured : local_measures(p, ctx.r, ctx.u);
    const double err = selected_error(*measured, ctx.options.i(FRIX_OPT_ERROR_MEASURE));
    const TraceEvent ev = close_stage(FRIX_SOLVER_NSGS, info, dog, ctx.clock.seconds() - t0, err);
    info.trace.push_back(ev);
    log_event(shared, ev);
    *converged = err <= tol;
    if (info.status == FRIX_STATUS_STOPPED_BY_CALLBACK && !dog.stopped_by_watchdog) shared.stop_requested = true;
    return FRIX_OK;
}

// A small problem that is one part gets its first stage at once (direct); a problem of several
// parts first gets kWholeNsgsSweeps sweeps of plain NSGS on the whole of it, which end many easy
// problems before the parts cost their setup (the parts go on from there). *done: they ended
// the solve, whose status is set. *measured: the measures of the r they left (ctx.u holds W r + q).
frix_error first_sweeps(SolveContext &ctx, Shared &shared, double tol, bool several_parts, bool *done,
                        Measures *measured) {
    bool converged = false;
    if (frix_error e = direct_nsgs(ctx, shared, tol, several_parts ? kWholeNsgsSweeps : 0, &converged, measured))
        return e;
    const frix_status status = shared.ending(converged, shared.stop_requested.load());
    *done = status != FRIX_STATUS_NOT_RUN;
    if (*done) {
        ctx.info.iterations = shared.iterations.load();
        ctx.info.status = status;
    } else {
        ctx.has_measured = false;
    }
    return FRIX_OK;
}

// The parts: every island of at least kMinIslandContacts contacts on its own, the smaller ones
// together (one sub-problem, still block-diagonal), each from its share of ctx.r. `kept`: a
// persistent solver's state (null: none); `direct`: the first stage already ran on the whole;
// `measured`: the measures of ctx.r, ctx.u holding W r + q (null: not known), which a part that
// is the whole problem takes.
frix_error set_up_parts(SolveContext &ctx, Shared &shared, const Analysis &a, KeptAuto *kept, bool direct,
                        const Measures *measured, Parts &parts) {
    const frix_problem &p = ctx.problem;
    std::vector<std::vector<int64_t>> units = solve_units(a, kMinIslandContacts);
    if (kept) part_caches(*kept, *ctx.cache, units);
    if (direct && units.size() != 1) return fail(FRIX_ERR_INTERNAL, "auto: a direct first stage on %zu parts", units.size());
    parts.islands.resize(units.size());
    parts.copied.assign(units.size(), 0);
    parts.whole = units.size() == 1;
    for (size_t k = 0; k < units.size(); ++k) {
        Island &is = parts.islands[k];
        is.contacts = std::move(units[k]);
        const frix_problem *sub = &p;
        if (!parts.whole) {
            if (frix_error e = extract_island(p, is.contacts, is.sub)) return e;
            sub = is.sub.get();
            is.r.resize(3 * is.contacts.size());
            for (size_t c = 0; c < is.contacts.size(); ++c)
                for (int d = 0; d < 3; ++d) is.r[3 * c + (size_t)d] = ctx.r[3 * is.contacts[c] + d];
        }
        is.solver = std::make_unique<IslandSolver>(*sub, shared, parts.whole ? 0 : (int64_t)k + 1,
                                                   kept ? kept->part_caches[k].get() : nullptr);
        if (direct) is.solver->first_stage_ran(FRIX_SOLVER_NSGS);
        if (parts.whole && measured) is.solver->know_start(ctx.r, ctx.u, *measured);
    }
    if (!parts.whole) {
        const double norm_q = norm2(p.q, 3 * p.nc);
        for (Island &is : parts.islands)
            is.loosening = part_loosening(norm_q, norm2(is.sub->q, 3 * is.sub->nc), parts.islands.size());
    }
    return FRIX_OK;
}

// One pass of `phase` over the parts, on `threads` threads; each part's failure is kept with
// its message (which lives in its thread's error state).
void pass_over_parts(Parts &parts, IslandSolver::Phase phase, double *whole_r, double island_tol, int64_t threads) {
    std::atomic<size_t> next{0};
    auto work = [&]() {
        for (size_t k = next++; k < parts.islands.size(); k = next++) {
            Island &is = parts.islands[k];
            double *r = parts.whole ? whole_r : is.r.data();
            is.status = guard("frix_solve (auto)", [&] {
                return is.solver->solve(phase, r, island_tol * is.loosening, &is.error);
            });
            if (is.status != FRIX_OK) is.message = frix_last_error_message();
        }
    };
    if (threads <= 1) {
        work();
        return;
    }
    std::vector<std::thread> pool;
    for (int64_t t = 1; t < threads; ++t) pool.emplace_back(work);
    work();
    for (std::thread &t : pool) t.join();
}

// Every part to `island_tol` (times its loosening): the first stages, then rounds while a part
// is active.
frix_error solve_parts(const frix_options &user, Parts &parts, double *whole_r, double island_tol) {
    const int64_t threads = std::min<int64_t>(user.i(FRIX_OPT_THREADS), (int64_t)parts.islands.size());
    for (int pass = 0;; ++pass) {
        const IslandSolver::Phase phase = pass == 0 ? IslandSolver::kFirst : IslandSolver::kRest;
        if (phase == IslandSolver::kRest && std::none_of(parts.islands.begin(), parts.islands.end(),
                                                         [](const Island &is) { return is.solver->active(); }))
            break;
        pass_over_parts(parts, phase, whole_r, island_tol, threads);
        for (const Island &is : parts.islands)
            if (is.status != FRIX_OK) return fail(is.status, "%s", is.message.c_str());
    }
    return FRIX_OK;
}

// The parts' records, in part order, as far as they have not been copied into `trace`.
void copy_records(Parts &parts, std::vector<TraceEvent> &trace) {
    for (size_t k = 0; k < parts.islands.size(); ++k) {
        const std::vector<TraceEvent> &ev = parts.islands[k].solver->events();
        trace.insert(trace.end(), ev.begin() + (std::ptrdiff_t)parts.copied[k], ev.end());
        parts.copied[k] = ev.size();
    }
}

// After the whole problem's error `error` missed `tol`: the parts' tolerance for another pass
// (*island_tol), false where another pass would not help (a part missed its own). Where the
// parts' shares misjudged the whole (their errors are relative to |r| and |u| too, which |q|
// does not tell), first their loosening shrinks by the observed ratio (and a margin), at least
// halving, down to the tolerance itself; then their tolerance tightens by that ratio (counted).
bool tighten(Parts &parts, double tol, double error, double *island_tol, int *tightenings) {
    bool all_met = true, loosened = false;
    for (const Island &is : parts.islands) {
        all_met = all_met && is.error <= *island_tol * is.loosening;
        loosened = loosened || is.loosening > 1.0;
    }
    if (!all_met) return false;
    if (loosened) {
        for (Island &is : parts.islands) is.loosening = std::max(1.0, is.loosening * 0.5 * tol / error);
    } else {
        *island_tol *= std::max(1e-3, 0.5 * tol / error);
        ++*tightenings;
    }
    return true;
}

// The whole problem's error, measured on the parts' answers put together, to the caller's
// callback (the parts' own errors reach it as estimates); a stop it asks for stops the parts.
void report_whole(Shared &shared, double error) {
    if (!shared.user.has_callback() || shared.stop_requested.load()) return;
    std::lock_guard<std::mutex> guard(shared.lock);
    if (Monitor(shared.user, shared.clock).report(shared.iterations.load(), error)) shared.stop_requested = true;
}

// The parts, solved and combined until the whole problem's error (*error) meets `tol`: each
// part's r goes back into ctx.r and the whole problem is measured; the parts go on from where
// they stopped, tightened, at most kMaxTightenings times.
frix_error solve_combined(SolveContext &ctx, Shared &shared, Parts &parts, double tol, double *error) {
    const frix_problem &p = ctx.problem;
    double island_tol = tol;
    for (int tightenings = 0;;) {
        if (frix_error e = solve_parts(ctx.options, parts, ctx.r, island_tol)) return e;
        if (parts.whole) {  // the part's own measure is the whole problem's
            *error = parts.islands[0].error;
            ctx.has_measured = parts.islands[0].solver->final_measures(&ctx.measured, ctx.u);
            return FRIX_OK;
        }
        for (const Island &is : parts.islands)
            for (size_t c = 0; c < is.contacts.size(); ++c)
                for (int d = 0; d < 3; ++d) ctx.r[3 * is.contacts[c] + d] = is.r[3 * c + (size_t)d];
        *error = selected_error(local_measures(p, ctx.r, ctx.u), ctx.options.i(FRIX_OPT_ERROR_MEASURE));
        report_whole(shared, *error);
        if (*error <= tol || tightenings >= kMaxTightenings || shared.out_of_time() || shared.stop_requested.load() ||
            !tighten(parts, tol, *error, &island_tol, &tightenings))
            return FRIX_OK;
        copy_records(parts, ctx.info.trace);
        TraceEvent e = trace_event(kTighten);
        e.error = *error;
        e.value = island_tol;
        ctx.info.trace.push_back(e);
    }
}

// The parts' records and work into ctx.info, and the status.
void close_parts(SolveContext &ctx, Shared &shared, Parts &parts, double tol, double error) {
    frix_info &info = ctx.info;
    copy_records(parts, info.trace);
    for (const Island &is : parts.islands) info.absorb(is.solver->ledger());
    info.iterations = shared.iterations.load();
    bool stopped = shared.stop_requested.load();
    for (const Island &is : parts.islands) stopped = stopped || is.solver->stopped();
    const frix_status status = shared.ending(error <= tol, stopped);
    info.status = status == FRIX_STATUS_NOT_RUN ? FRIX_STATUS_STAGNATED : status;
    if (shared.ran_away.load()) info.ran_away = true;  // stopped: the driver reports it as diverged
}

}  // namespace

frix_error solve_local(SolveContext &ctx) {
    const frix_problem &p = ctx.problem;
    const double tol = Monitor(ctx).tolerance();
    Shared shared(ctx.options, ctx.clock);
    shared.contacts = p.nc;

    const Analysis a = analyse_local(p);
    ctx.info.islands = a.islands;
    ctx.info.trace.push_back(analysis_event(a));
    shared.scaled_penalty = !(a.diag_max <= kScaledPenaltySpread * a.diag_min);
    const bool several_parts = a.islands > 1 && a.largest_island >= kMinIslandContacts;
    const bool direct = p.nc < kPlainNsgsMaxContacts && !several_parts;
    Measures first;  // of the first sweeps' iterate
    const Measures *measured = ctx.measured_start;
    if (direct || several_parts) {
        bool done = false;
        if (frix_error e = first_sweeps(ctx, shared, tol, several_parts, &done, &first)) return e;
        if (done) return FRIX_OK;
        measured = &first;
    }
    // Taken after the first sweeps: a problem that they solve leaves the kept state in the
    // cache as it was.
    Kept<KeptAuto> kept(ctx.cache, FRIX_SOLVER_AUTO);
    Parts parts;
    if (frix_error e = set_up_parts(ctx, shared, a, ctx.cache ? &*kept : nullptr, direct, measured, parts)) return e;
    if (parts.islands.size() == 1) shared.part_threads = ctx.options.i(FRIX_OPT_THREADS);
    double error = INFINITY;
    if (frix_error e = solve_combined(ctx, shared, parts, tol, &error)) return e;
    close_parts(ctx, shared, parts, tol, error);
    kept.keep();
    return FRIX_OK;
}

}  // namespace frix::autosolve
