// The driver's global path: M factorised once (or analysed, and factorised where the solver
// asks for it); the all-separating case; a solver of global problems run natively, any other
// through the reduction to W (route (a)); the final measures of (r, v) and the status checked
// against them.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <vector>

#include "error_state.hpp"
#include "floating.hpp"
#include "log.hpp"
#include "measures.hpp"
#include "monitor.hpp"
#include "pressed_reduction.hpp"
#include "reduction.hpp"
#include "vec.hpp"
#include "solver_api.hpp"

namespace frix {

namespace {

// What a persistent solver keeps for a global problem: M's factorisation while M's values
// stay, and W = H^T M^-1 H while M's and H's values stay, with the states of the local
// solvers that run on that W (their own cache, whose W versions follow W's).
struct GlobalState : CachedState {
    uint64_t m_values = 0;  // the M of ms (0: none)
    MassSolver ms;
    uint64_t w_from_m = 0, w_from_h = 0;  // the M and H that W was formed from (0: none)
    std::unique_ptr<frix_matrix> W;
    SolveCache local;
    // A singular M (floating.hpp): its free_motion_quotient, and the solves on M + eps diag(M)
    // with their own states (its factorisation, W).
    bool singular = false;
    double quotient = NAN;
    std::unique_ptr<frix_matrix> shifted;
    SolveCache shifted_cache;
};
constexpr int kGlobalStateKey = 0;  // no solver has id 0

// The local measure's scale is max(|q|, |r|, |u|), the global one's max(|w|, |r|, |u|)
// (Siconos's): where q = H^T M^-1 f + w outweighs w (bodies falling onto their contacts), a
// local answer at the tolerance can miss it by the global measure. The local solver goes on
// from its answer to the tolerance tightened by the ratio of the two errors, at most twice.
constexpr int kTightenedPasses = 2;

// `measures`: the local solve's final measures, which go on with it.
// `scale`: the problem whose global measure's scale (|w|, the free velocity) applies.
frix_error tighten_to_global_measure(const frix_problem &scale, const frix_problem &local, const frix_options &opts,
                                     const SolverEntry &entry, double *r, double *u, frix_info &info,
                                     const Stopwatch &clock, SolveCache *local_cache, Measures &measures) {
    const double tol = opts.d(FRIX_OPT_TOLERANCE), norm_w = norm2(scale.w, 3 * scale.nc);
    const double free = free_velocity(scale);
    const int64_t measure = opts.i(FRIX_OPT_ERROR_MEASURE), max_iter = opts.i(FRIX_OPT_MAX_ITER);
    for (int pass = 0; pass < kTightenedPasses && info.status == FRIX_STATUS_CONVERGED; ++pass) {
        // The global measure of (r, M^-1 (H r + f)) up to rounding: u = W r + q = H^T v + w.
        const double global = selected_error(with_norm_q(measures, norm_w, free), measure);
        if (!(global > tol) || !(info.error > 0.0) || !(global > info.error) || info.iterations >= max_iter) break;
        frix_options tighter = opts;
        tighter.dvalue[FRIX_OPT_TOLERANCE] = 0.5 * tol * info.error / global;
        tighter.ivalue[FRIX_OPT_MAX_ITER] = max_iter - info.iterations;
        // The pass's callback reports are numbered on from the iterations before it.
        ForwardedReports forward{&opts, &clock, info.iterations, false};
        tighter = forward.applied_to(tighter);
        frix_info more = info.next_run();
        more.tolerance = tighter.dvalue[FRIX_OPT_TOLERANCE];
        const Measures start = measures;  // of the r the pass starts from, u holding W r + q
        if (frix_error e = solve_local_problem(local, tighter, entry, r, u, more, clock, local_cache, &measures, false,
                                               false, &start))
            return e;
        more.absorb(info);
        more.tolerance = info.tolerance;  // the caller's, not the tightened pass's
        info = std::move(more);
    }
    return FRIX_OK;
}

// Route (a): reduce with the factorised M, solve the local problem with any local solver,
// recover v. W has at most w_blocks blocks (room is reserved for them: memory only counts once
// written). scale: the problem whose global measure's scale the answer is held to (p, or the
// whole problem p is a part of; null: p).
frix_error solve_reduced(const frix_problem &p, const frix_options &opts, const SolverEntry &entry,
                         MassSolver &ms, double w_blocks, const double *q0, double *r, double *u, double *v,
                         frix_info &info, const Stopwatch &clock, const SolveCache *cache, GlobalState *kept,
                         const frix_problem *scale = nullptr) {
    const Stopwatch setup;
    std::unique_ptr<frix_matrix> W;
    const bool w_current = kept && kept->W && kept->w_from_m == cache->m_values && kept->w_from_h == cache->h_values;
    if (w_current) W = std::move(kept->W);
    // Where W is dense (a deformable body) forming it can take minutes: the time limit and
    // the caller's callback (told iteration 0 and the start's error) can end it as they end
    // an iteration, with the caller's start returned. A W kept from the last solve is not
    // formed: the callback hears from the solver's first iteration on.
    double start_error = NAN;
    if (opts.has_callback() && !w_current) {
        if (frix_error e = recover_velocity(p, ms, r, v)) return e;
        start_error = selected_error(global_measures(p, r, v, u, nullptr), opts.i(FRIX_OPT_ERROR_MEASURE));
    }
    frix_status stop_status = FRIX_STATUS_NOT_RUN;
    const std::function<bool()> stop = [&]() {
        const Monitor monitor(opts, clock);
        if (monitor.out_of_time()) stop_status = FRIX_STATUS_TIME_LIMIT;
        else if (monitor.report(0, start_error))
            stop_status = FRIX_STATUS_STOPPED_BY_CALLBACK;
        return stop_status != FRIX_STATUS_NOT_RUN;
    };
    bool stopped = false;
    double reduction_time = 0.0;  // recorded with the setup, after the local solver's own
    if (!w_current) {
        const Stopwatch reduction;
        if (frix_error e = ms.congruence(*p.H, w_blocks, W, stop, stopped)) return e;
        reduction_time = reduction.seconds();
    }
    if (stopped) {
        info.status = stop_status;
        info.iterations = 0;
        info.setup_time += setup.seconds();
        info.reduction_time += reduction_time;
        return recover_velocity(p, ms, r, v);
    }
    std::vector<double> q(q0, q0 + 3 * p.nc);
    frix_problem *local = nullptr;
    if (frix_error e = make_local_problem(W.get(), q.data(), p.mu, p.nc, &local)) return e;
    std::unique_ptr<frix_problem> local_owner(local);
    // The global problem's weights: the reduced answer is measured as the global one is.
    local->weight = p.weight;
    const double setup_time = setup.seconds();
    SolveCache *local_cache = nullptr;
    if (kept) {
        // The local solvers' states hold while W's pattern does; its values are new unless W
        // was kept.
        if (!w_current) {
            ++kept->local.w_values;
            if (!kept->W || !same_pattern(*kept->W, *W)) ++kept->local.w_pattern;
        }
        local_cache = &kept->local;
    }
    Measures measures;
    // The local solve's errors are on the reduced problem's scale (max(|q|, |u|), not the
    // global measure's): the caller's callback takes them as estimates.
    ForwardedReports forward{&opts, &clock, 0, true};
    const frix_options local_opts = forward.applied_to(opts);
    frix_error err = solve_local_problem(*local, local_opts, entry, r, u, info, clock, local_cache, &measures);
    if (!err)
        err = tighten_to_global_measure(scale ? *scale : p, *local, local_opts, entry, r, u, info, clock, local_cache,
                                        measures);
    if (kept) {
        kept->W = std::move(W);
        kept->w_from_m = cache->m_values;
        kept->w_from_h = cache->h_values;
    }
    if (err) return err;
    info.setup_time += setup_time;
    info.reduction_time += reduction_time;
    return recover_velocity(p, ms, r, v);
}

frix_error solve_global(const frix_problem &p, const frix_options &opts, const SolverEntry &entry, double *r,
                        double *u, double *v, frix_info &info, const Stopwatch &clock, SolveCache *cache,
                        MassSolver *enclosing, bool regularise);

// solve_reduced, where a one-shot solve's W would be large on the contacts pressed at the start
// first (pressed_reduction.hpp), then on all of them where those grew past their share; a
// persistent solver keeps the whole W for its next steps.
frix_error solve_reduced_pressed_first(const frix_problem &p, const frix_options &opts, const SolverEntry &entry,
                                       MassSolver &ms, const ReductionSize &bound, const double *q, double *r,
                                       double *u, double *v, frix_info &info, const Stopwatch &clock,
                                       const SolveCache *cache, GlobalState *kept) {
    const ReducedRoute reduce_part = [&](const frix_problem &part, const frix_options &o, double blocks,
                                         const double *part_q, double *part_r, double *part_u, double *whole_v,
                                         frix_info &run) {
        return solve_reduced(part, o, entry, ms, blocks, part_q, part_r, part_u, whole_v, run, clock, nullptr, nullptr,
                             &p);
    };
    frix_info rounds = info;
    PressedFirst outcome = PressedFirst::kNotApplied;
    if (!cache)
        if (frix_error e = solve_pressed_first(p, opts, q, bound, r, u, v, rounds, clock, reduce_part, &outcome))
            return e;
    if (outcome == PressedFirst::kAnswered) {
        rounds.absorb(info);  // the record so far
        info = std::move(rounds);
        return FRIX_OK;
    }
    frix_options whole = opts;
    ForwardedReports forward{&opts, &clock, rounds.iterations, false};
    if (outcome == PressedFirst::kWholeNext) {
        whole.ivalue[FRIX_OPT_MAX_ITER] = opts.i(FRIX_OPT_MAX_ITER) - rounds.iterations;  // > 0: the rounds checked
        whole = forward.applied_to(whole);
    }
    if (frix_error e = solve_reduced(p, whole, entry, ms, bound.w_blocks, q, r, u, v, info, clock, cache, kept))
        return e;
    if (outcome == PressedFirst::kWholeNext) info.absorb(rounds);
    return FRIX_OK;
}

// Proximal passes on a singular M: (M + eps D) v_k = H r_k + f + eps D v_(k-1), each pass a
// solve of that problem from the last (r, v). Their fixed point is M v = H r + f; where the
// contacts hold the free motion they take the load the shift carried within a pass or two.
// Where they do not (a load no contact reaction balances) the equilibrium residual does not
// halve from pass to pass, and the solve is refused with the reason.
constexpr int kFloatingPasses = 8;

frix_error solve_floating(const frix_problem &p, const frix_options &opts, const SolverEntry &entry, double *r,
                          double *u, double *v, frix_info &info, const Stopwatch &clock, const SolveCache *cache,
                          GlobalState &state, bool m_changed) {
    const int64_t n = p.n;
    if (!state.shifted || m_changed) {
        state.shifted = shifted_mass(p, kFloatingShift);
        ++state.shifted_cache.m_values;
    }
    if (cache) state.shifted_cache.h_values = cache->h_values;
    const std::vector<double> shift = mass_shift(p, kFloatingShift);
    std::vector<double> f(p.f, p.f + n);
    frix_problem view;
    view.kind = FRIX_PROBLEM_GLOBAL;
    view.nc = p.nc;
    view.n = n;
    view.M = state.shifted.get();
    view.H = p.H;
    view.f = f.data();
    view.w = p.w;
    view.mu = p.mu;
    view.weight = p.weight;
    view.dof_weight = p.dof_weight;
    view.load_weight = p.load_weight;
    const double tol = opts.d(FRIX_OPT_TOLERANCE);
    const int64_t kind = opts.i(FRIX_OPT_ERROR_MEASURE), max_iter = opts.i(FRIX_OPT_MAX_ITER);
    frix_info done = info;  // the passes' work so far
    Measures meas;
    double previous = INFINITY;
    int passes = 0;
    for (;;) {
        frix_options o = opts;
        o.ivalue[FRIX_OPT_MAX_ITER] = std::max<int64_t>(1, max_iter - done.iterations);
        frix_info pass = info.next_run();
        if (frix_error e = solve_global(view, o, entry, r, u, v, pass, clock, &state.shifted_cache, nullptr, false))
            return e;
        pass.absorb(done);
        done = std::move(pass);
        ++passes;
        meas = global_measures(p, r, v, u, nullptr);
        const double equilibrium = kind == FRIX_MEASURE_SCALED ? meas.equilibrium_scaled : meas.equilibrium;
        if (opts.i(FRIX_OPT_VERBOSITY) > 0)
            log_line(&opts, "singular M: pass %d on M + %.0e diag(M), error %.3e, equilibrium %.3e", passes,
                     kFloatingShift, selected_error(meas, kind), equilibrium);
        if (selected_error(meas, kind) <= tol || done.status != FRIX_STATUS_CONVERGED || passes == kFloatingPasses ||
            done.iterations >= max_iter || !(equilibrium < 0.5 * previous))
            break;
        previous = equilibrium;
        for (int64_t i = 0; i < n; ++i) f[i] = p.f[i] + shift[i] * v[i];
    }
    info = std::move(done);
    record_measures(info, meas, kind);
    const double equilibrium = kind == FRIX_MEASURE_SCALED ? meas.equilibrium_scaled : meas.equilibrium;
    if (info.error <= tol) {
        info.status = FRIX_STATUS_CONVERGED;
    } else if (info.status == FRIX_STATUS_CONVERGED && equilibrium > tol) {
        char why[96];
        if (std::isnan(state.quotient)) std::snprintf(why, sizeof why, "no factorisation of it succeeds");
        else std::snprintf(why, sizeof why, "x.Mx / x.diag(M)x = %.1e along it", state.quotient);
        return fail(FRIX_ERR_NUMERICAL,
                    "frix_solve: M is singular (it lets the bodies move freely, %s: a body held only by its "
                    "contacts) and the contacts do not hold that motion: solved on M + %.0e diag(M), the "
                    "equilibrium residual stays at %.3g after %d passes (a load that no contact reaction "
                    "balances, or contacts that open or slide)",
                    why, kFloatingShift, equilibrium, passes);
    } else if (info.status == FRIX_STATUS_CONVERGED) {
        info.status = FRIX_STATUS_STAGNATED;
    }
    return FRIX_OK;
}

// The end of a global solve (either kind of contact) that ran from warm_start
// (finite_warm_start): the final measures of (r, v), the fallback of a diverged run (its start's
// v recovered with ms, M's factorisation; null: factorised here if the fallback needs it) and
// the status checked against the measures.
frix_error settle_global(const frix_problem &p, const frix_options &opts, const std::vector<double> &warm_start,
                         const MassSolver *ms, double *r, double *u, double *v, frix_info &info) {
    const int64_t m = contact_size(p) * p.nc, kind = opts.i(FRIX_OPT_ERROR_MEASURE);
    Measures meas = global_measures(p, r, v, u, nullptr);
    const bool broken = !finite_measures(meas) || !vec::all_finite(r, m) || !vec::all_finite(v, p.n);
    MassSolver own;
    const MeasureAnswer at = [&](const double *x, double *ux, double *vx, Measures &out) {
        if (!ms || !ms->factored()) {
            if (frix_error e = own.factor(*p.M)) return e;
            ms = &own;
        }
        if (frix_error e = recover_velocity(p, *ms, x, vx)) return e;
        out = global_measures(p, x, vx, ux, nullptr);
        return FRIX_OK;
    };
    if (frix_error e = fall_back_on_divergence(p, kind, warm_start, broken, runaway_bound(meas.norm_free), at, r, u, v,
                                               meas, info))
        return e;
    if (!finite_measures(meas))  // the start, r = 0, overflows too
        return fail(FRIX_ERR_NUMERICAL, "frix_solve: M^-1 f overflows: M is too ill-conditioned");
    record_measures(info, meas, kind);
    if (info.status == FRIX_STATUS_CONVERGED && !meets_global_tolerance(info, info.tolerance))
        info.status = FRIX_STATUS_STAGNATED;
    return FRIX_OK;
}

// A rolling-friction problem goes to its solver as it is (the rolling solvers take M body by
// body, solvers/kit/rolling_forms.hpp), watched for a runaway as the native route is.
frix_error solve_rolling_global(const frix_problem &p, const frix_options &opts, const SolverEntry &entry, double *r,
                                double *u, double *v, frix_info &info, const Stopwatch &clock, SolveCache *cache) {
    if (!entry.solves_rolling)
        return fail(FRIX_ERR_UNSUPPORTED, "frix_solve: solver %s does not solve rolling-friction problems", entry.name);
    const std::vector<double> warm_start = finite_warm_start(r, contact_size(p) * p.nc);
    SolveContext ctx = SolveContext::global(p, opts, r, u, v, info, clock, nullptr).with_cache(cache);
    ctx.runaway_bound = runaway_bound(free_velocity(p));
    if (frix_error e = entry.solve(ctx)) return e;
    return settle_global(p, opts, warm_start, nullptr, r, u, v, info);
}

}  // namespace

frix_error solve_global_problem(const frix_problem &p, const frix_options &opts, const SolverEntry &entry,
                                double *r, double *u, double *v, frix_info &info, const Stopwatch &clock,
                                SolveCache *cache, MassSolver *enclosing) {
    if (is_rolling(p)) return solve_rolling_global(p, opts, entry, r, u, v, info, clock, cache);
    return solve_global(p, opts, entry, r, u, v, info, clock, cache, enclosing, true);
}

namespace {

// The end of a factorisation of M into ms (`factored`: what it returned): over, the limit one not
// started would have overrun; whether M is singular, into state (regularise: a symmetric M that
// no factorisation takes may be). Fails where neither holds.
frix_error judge_mass(const frix_problem &p, const MassSolver &ms, frix_error factored, GlobalState &state,
                      bool regularise, frix_status &over) {
    state.singular = false;
    if (frix_error e = factored) {
        over = ms.refused();
        if (!over && !(regularise && ms.symmetric())) return e;
        clear_error();
        state.singular = !over;
        state.quotient = NAN;
    } else if (regularise && ms.factored()) {
        state.quotient = free_motion_quotient(p, ms);
        state.singular = std::fabs(state.quotient) <= kSingularQuotient;
    }
    return FRIX_OK;
}

// What became of M (verbosity 1): factorised, or analysed alone for a route that may never solve
// with it.
void log_mass(const frix_options &opts, const MassSolver &ms, frix_error factored) {
    if (opts.i(FRIX_OPT_VERBOSITY) < 1 || factored) return;
    log_line(&opts, ms.factored() ? "M factorised (%s), %.3g s" : "M analysed (%s), %.3g s: its factorisation left to "
                                                                  "the routes that solve with it",
             ms.cholesky() ? "Cholesky" : "LU", ms.last_stats().seconds);
}

// What factor_mass does with M: its whole factorisation, its analysis alone (where M is
// symmetric; a route that never solves with M needs no more), or the numeric part on the
// analysis ms holds.
enum class MassStep { Factor, Analyse, CompleteAnalysis };

// M into ms by `step`, priced against the memory limit only: every answer's velocity needs
// M^-1, and the start returned at a time limit must come with its own (M v = H r + f).
frix_error factor_mass(const frix_problem &p, const frix_options &opts, const Stopwatch &clock, MassSolver &ms,
                       GlobalState &state, bool regularise, MassStep step, frix_status &over) {
    ms.set_budget(Monitor(opts, clock).memory_budget());
    const frix_error factored = step == MassStep::Factor    ? ms.factor(*p.M)
                                : step == MassStep::Analyse ? ms.analyse(*p.M)
                                                            : ms.factor_analysed();
    ms.set_budget(nullptr);  // it refers to this solve's options and clock
    log_mass(opts, ms, factored);
    return judge_mass(p, ms, factored, state, regularise, over);
}

// A solver of global problems run on (v, r) from the caller's r, its work added to info. M's
// factorisation where it asks for it (on_demand: ms holds the analysis alone), its work into
// `completed`: singular_later where that found M singular, info then left as it was (the
// caller's passes take over).
frix_error run_native(const frix_problem &p, const frix_options &opts, const SolverEntry &entry, double *r, double *u,
                      double *v, frix_info &info, const Stopwatch &clock, SolveCache *cache, MassSolver &ms,
                      GlobalState &state, bool regularise, bool on_demand, frix_info &completed,
                      bool &singular_later) {
    const int64_t m = 3 * p.nc;
    // Newton on (v, r) from the caller's r, with the velocity that r gives (not M^-1 f:
    // a warm-started (v, r) must satisfy the equilibrium M v = H r + f to start with);
    // a solver that starts from r alone recovers it where it needs it.
    if (!entry.starts_from_r && std::any_of(r, r + m, [](double x) { return x != 0.0; }))
        if (frix_error e = recover_velocity(p, ms, r, v)) return e;
    // The solver's own setup (auto's reduction route) adds to the driver's.
    frix_info native = info;
    native.setup_time = native.reduction_time = 0.0;
    native.factorizations = native.symbolic_analyses = 0;  // the solver's own, M's added below
    native.factorization_time = 0.0;
    // M's factorisation where the solver asks for it, judged as the caller's own: a singular M
    // ends the solver's run.
    const std::function<frix_error(bool *)> complete = [&](bool *ready) -> frix_error {
        *ready = true;
        if (ms.factored()) return FRIX_OK;
        frix_status over = FRIX_STATUS_NOT_RUN;
        const frix_error e = factor_mass(p, opts, clock, ms, state, true, MassStep::CompleteAnalysis, over);
        Monitor::record_factorizations(completed, ms.last_stats());
        singular_later = state.singular;
        *ready = !e && ms.factored() && !singular_later;
        return e;
    };
    SolveContext ctx = SolveContext::global(p, opts, r, u, v, native, clock, &ms).with_cache(cache);
    ctx.runaway_bound = runaway_bound(free_velocity(p));
    ctx.mass_shifted = !regularise;  // (only solve_floating's passes do not regularise)
    if (on_demand) ctx.factor_mass = &complete;
    if (frix_error e = entry.solve(ctx)) return e;
    // A run that missed the tolerance without solving with M: whether M is singular (the
    // passes then say whether the contacts hold it) is known only from its factorisation.
    if (on_demand && !ms.factored() && !ms.refused() && native.status != FRIX_STATUS_CONVERGED &&
        native.status != FRIX_STATUS_STOPPED_BY_CALLBACK && !Monitor(opts, clock).out_of_time()) {
        bool ready = true;
        if (frix_error e = complete(&ready)) return e;
    }
    if (singular_later) return FRIX_OK;
    native.setup_time += info.setup_time;
    Monitor::add_factorizations(native, info);
    Monitor::add_factorizations(native, completed);
    info = native;
    return FRIX_OK;
}

// solve_global_problem; regularise: a singular M goes to solve_floating (not on its own
// shifted problem).
frix_error solve_global(const frix_problem &p, const frix_options &opts, const SolverEntry &entry, double *r,
                        double *u, double *v, frix_info &info, const Stopwatch &clock, SolveCache *cache,
                        MassSolver *enclosing, bool regularise) {
    const int64_t m = 3 * p.nc;
    if (!entry.solves_global && !entry.solves_local)
        return fail(FRIX_ERR_UNSUPPORTED, "frix_solve: solver %s solves no global problem", entry.name);
    const std::vector<double> warm_start = finite_warm_start(r, m);
    // v0 = M^-1 f and q = H^T v0 + w, the velocity without contact forces: if every contact
    // separates there (q_N >= 0), r = 0 and v = v0 is the exact solution, for every solver.
    const Stopwatch setup;
    Kept<GlobalState> state(cache, kGlobalStateKey);
    MassSolver &ms = enclosing ? *enclosing : state->ms;
    const bool m_current = enclosing || (cache && state->m_values == cache->m_values);
    // A one-shot solve from r = 0 by a solver that asks for M's factorisation where it needs it
    // analyses M alone: auto's route without W never solves with M. (A persistent solver's next
    // steps start from r, whose velocity needs M^-1: it factorises M at its first step.)
    const bool on_demand = regularise && !enclosing && !cache && entry.solves_global &&
                           entry.mass_factor_on_demand && vec::all_zero(r, m);
    if (!m_current) {
        state->m_values = 0;  // until factorised
        frix_status over = FRIX_STATUS_NOT_RUN;
        if (frix_error e = factor_mass(p, opts, clock, ms, *state, regularise,
                                       on_demand ? MassStep::Analyse : MassStep::Factor, over))
            return e;
        if (over) {
            // One that would exceed the memory limit is not started: nothing is solved, r
            // stays as given and v = 0.
            Monitor::record_factorizations(info, ms.last_stats());
            std::fill(v, v + p.n, 0.0);
            info.status = over;
            info.iterations = 0;
            record_measures(info, global_measures(p, r, v, u, &info.equilibrium), opts.i(FRIX_OPT_ERROR_MEASURE));
            return FRIX_OK;
        }
        state->m_values = cache ? cache->m_values : 0;
    }
    frix_info factorised;  // M's factorisation, this solve's part
    if (!m_current) Monitor::record_factorizations(factorised, ms.last_stats());
    // A singular M: the passes on M + eps diag(M) (`factorised` before theirs).
    const auto floating = [&]() {
        const frix_error e = solve_floating(p, opts, entry, r, u, v, info, clock, cache, *state, !m_current);
        Monitor::add_factorizations(info, factorised);
        state.keep();
        return e;
    };
    if (regularise && state->singular) return floating();
    std::vector<double> q(m);
    bool separating = false;
    if (ms.factored()) {
        if (frix_error e = ms.solve_load(p.f, p.n, v, cache != nullptr)) return e;
        if (m > 0) matrix_gemv_transposed(*p.H, 1.0, v, 0.0, q.data());
        separating = true;
        for (int64_t i = 0; i < m; ++i) {
            q[i] += p.w[i];
            if (i % 3 == 0 && q[i] < 0.0) separating = false;
        }
    } else {
        std::fill(v, v + p.n, 0.0);  // the solver's own first solves give v (r = 0)
    }
    info.setup_time = setup.seconds();
    Monitor::add_factorizations(info, factorised);
    if (separating) {
        for (int64_t i = 0; i < m; ++i) r[i] = 0.0;
        info.status = FRIX_STATUS_CONVERGED;
        info.iterations = 0;
    } else if (entry.solves_global) {
        frix_info completed;  // M's factorisation where the solver asked for it
        bool singular_later = false;
        if (frix_error e = run_native(p, opts, entry, r, u, v, info, clock, cache, ms, *state, regularise, on_demand,
                                      completed, singular_later))
            return e;
        if (singular_later) {
            info.factorizations = info.symbolic_analyses = 0;  // M's, counted in `factorised`
            info.factorization_time = 0.0;
            Monitor::add_factorizations(factorised, completed);
            return floating();
        }
    } else {
        const ReductionSize size = reduction_bound(p);
        const ReductionMemory memory = reduction_memory(size, Monitor(opts, clock));
        if (!memory.fits)
            return fail(FRIX_ERR_OUT_OF_MEMORY,
                        "frix_solve: %s reduces the global problem to W = H^T M^-1 H, which would have up to "
                        "%.3g entries in %.3g blocks (at least %.3g GB, more than the %.3g GB of memory it may still "
                        "take); gnsgs (rigid bodies), gnsn-ac (607) and auto solve it without W",
                        entry.name, size.w_entries, size.w_blocks, memory.needed / 1e9,
                        std::max(memory.available, 0.0) / 1e9);
        const frix_info before = info;
        info.factorizations = info.symbolic_analyses = 0;
        info.factorization_time = info.setup_time = info.reduction_time = 0.0;
        if (frix_error e = solve_reduced_pressed_first(p, opts, entry, ms, size, q.data(), r, u, v, info,
                                                       clock, cache, cache ? &*state : nullptr))
            return e;
        // The local solver reported its own work: add the factorisation of M.
        Monitor::add_factorizations(info, before);
        info.setup_time += before.setup_time;
    }
    if (frix_error e = settle_global(p, opts, warm_start, &ms, r, u, v, info)) return e;
    state.keep();
    return FRIX_OK;
}

}  // namespace

bool meets_global_tolerance(const frix_info &info, double tol) { return info.error <= tol; }

}  // namespace frix
