// auto on a global problem (routes.hpp). The reduction route runs the local strategy on
// W = H^T M^-1 H and, where the global measure (error and equilibrium) is not met, Newton on
// (v, r) from its result; the two share the caller's max_iter (the reduction half of it). Where
// W would be large, rigid bodies first get NSGS without W (gnsgs); where a dense W (a
// deformable body) is priced above the route without it, or would overrun the time or memory
// limit, that route goes first (613, then 901; 607 alone where M has no Cholesky factor).
// Every route keeps one ledger in ctx.info: each run adds its work to the earlier ones'.
#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "solvers/entries.hpp"
#include "solvers/auto/routes.hpp"
#include "solvers/auto/stage.hpp"
#include "solvers/kit/global_newton.hpp"
#include "solvers/kit/mass_plus_contacts.hpp"
#include "solvers/kit/sweeps.hpp"
#include "src/log.hpp"
#include "src/reduction.hpp"

namespace frix::autosolve {

namespace {

// A global answer (r, v) set aside while another route runs from elsewhere: the caller gets
// the better of the two by the global measure (its error, equilibrium included), as auto's
// local stages keep their best iterate.
struct GlobalAnswer {
    std::vector<double> r, v;
    double error, equilibrium;
    GlobalAnswer(const SolveContext &ctx, const frix_info &info)
        : r(ctx.r, ctx.r + 3 * ctx.problem.nc), v(ctx.v, ctx.v + ctx.problem.n), error(info.error),
          equilibrium(info.equilibrium) {}
    static double score(double error) { return std::isfinite(error) ? error : INFINITY; }
    // Puts the set-aside (r, v) back, whatever the caller holds.
    void put_back(SolveContext &ctx) const {
        std::copy(r.begin(), r.end(), ctx.r);
        std::copy(v.begin(), v.end(), ctx.v);
    }
    // Puts the set-aside answer back where it is better than the one the route left, with its
    // error and equilibrium (the driver measures the answer returned again in full).
    void restore_if_better(SolveContext &ctx, frix_info &info) const {
        if (info.status == FRIX_STATUS_CONVERGED || !(score(error) < score(info.error)))
            return;
        put_back(ctx);
        info.error = error;
        info.equilibrium = equilibrium;
    }
};

// The route a global problem takes, from its sizes and (where W would be large) its prices.
struct RouteChoice {
    frix_status refused = FRIX_STATUS_NOT_RUN;  // the limit forming W would overrun, as asked up front
    // Forming W's price, where the route without W goes first for being cheaper: the time limit
    // is asked only before W would be formed after that route (see choose_route).
    const linalg::FactorPrice *forming_w_later = nullptr;
    bool w_free = false;   // the route without W is priced below forming W, and fits
    bool product = false;  // rigid bodies with a large W: NSGS without W first
    bool rigid = false;    // rigid bodies: NSGS without W (gnsgs) can solve the problem
    RoutePrices prices;
    // M + H S H^T as the pricing built and analysed it, for the route without W (null: not priced).
    std::unique_ptr<KeptMassPlusContacts> w_free_system;
};

// Forming W and the route without it priced, or their prices kept from the step before
// (`kept`, where a persistent solver's M and H are the same).
void price_routes(const SolveContext &ctx, const ReductionSize &size, KeptAuto::Prices &kept, RouteChoice &c) {
    const frix_problem &p = ctx.problem;
    if (ctx.cache && kept.m_values == ctx.cache->m_values && kept.h_values == ctx.cache->h_values) return;
    kept = KeptAuto::Prices{};
    kept.forming_w_priced = ctx.mass && ctx.mass->congruence_price(*p.H, &kept.forming_w);
    if (kept.forming_w_priced) {
        c.w_free_system = std::make_unique<KeptMassPlusContacts>();
        kept.w_free_priced =
            price_w_free_route(p, *ctx.mass, kept.forming_w, size.w_blocks, &kept.routes, c.w_free_system->system);
    }
    if (ctx.cache) kept.m_values = ctx.cache->m_values, kept.h_values = ctx.cache->h_values;
}

RouteChoice choose_route(const SolveContext &ctx, const ReductionSize &size, KeptAuto::Prices &kept) {
    RouteChoice c;
    bool priced = false;
    if (size.w_entries > kReductionMaxEntries && size.w_entries > kReductionMaxGrowth * size.input_entries) {
        price_routes(ctx, size, kept, c);
        priced = kept.forming_w_priced;
        if (kept.forming_w_priced) {
            c.prices = kept.routes;
            const bool w_free_fits = kept.w_free_priced && Monitor(ctx).fits_memory(c.prices.without_w_bytes);
            const bool cheaper = w_free_fits && c.prices.without_w < c.prices.with_w;
            // Where the route without W is cheaper, the time limit is asked only before W would
            // be formed after it: a question may time the machine, tens of milliseconds.
            if (!cheaper)
                c.refused = Monitor(ctx).affords(kept.forming_w);
            else if (!Monitor(ctx).fits_memory(kept.forming_w.bytes))
                c.refused = FRIX_STATUS_MEMORY_LIMIT;
            else
                c.forming_w_later = &kept.forming_w;
            c.w_free = w_free_fits && (cheaper || c.refused);
            if (ctx.options.i(FRIX_OPT_VERBOSITY) >= 1)
                log_line(&ctx.options, "auto: forming W priced %.3g flops, the route without W %.3g", c.prices.with_w,
                         c.prices.without_w);
        }
    }
    // Not priced (W small beside M and H, or M factorised by LU): W's blocks against the memory.
    if (!priced && !reduction_memory(size, Monitor(ctx)).fits) c.refused = FRIX_STATUS_MEMORY_LIMIT;
    // Rigid bodies with a large W: W's entries against M^-1 H's.
    c.rigid = size.largest_component <= nsgs::kMaxRigidBodyDofs;
    c.product = !c.w_free && c.rigid && size.w_entries > kReductionMaxEntries && size.w_entries > size.product_entries;
    return c;
}

// The figures of a global problem that auto's records show.
AnalysisSummary global_figures(const frix_problem &p, const ReductionSize &size) {
    AnalysisSummary s;
    s.dofs = p.n;
    s.contacts = p.nc;
    s.rank_ratio = p.n > 0 ? 3.0 * (double)p.nc / (double)p.n : 0.0;
    s.reduced_entries = size.w_entries;
    s.input_entries = size.input_entries;
    return s;
}

// The caller's options for the routes' solvers. auto's option acceleration steers the sweeps
// by W's rank: momentum where W = H^T M^-1 H is singular (3nc > n), carrying the drift along
// W's null space that holds the plain sweeps for thousands of sweeps; Anderson's mix of the
// last sweeps where W may be regular (a deformable body, few contacts for its dofs), whose
// sweeps contract at a steady rate that momentum only overshoots.
frix_options route_options(const frix_options &user, const AnalysisSummary &figures) {
    frix_options o = user;
    if (figures.w_may_be_regular()) {
        o.ivalue[FRIX_OPT_ANDERSON] = user.i(FRIX_OPT_ACCELERATION) != 0 ? kRegularWAndersonDepth : 0;
        o.ivalue[FRIX_OPT_ACCELERATION] = 0;
    }
    return o;
}

class GlobalRoutes {
   public:
    GlobalRoutes(SolveContext &ctx, SolveCache *reduction, const AnalysisSummary &figures)
        : ctx_(ctx),
          info_(ctx.info),
          reduction_(reduction),
          figures_(figures),
          options_(route_options(ctx.options, figures)) {}

    frix_error ensure_mass_factorised(bool *go_on);
    frix_error product_then_reduce(int64_t max_iter, bool may_reduce);
    frix_error reduce_then_newton(int64_t max_iter, int64_t reduction_iter);
    frix_error without_w(int64_t max_iter, RouteChoice &choice);

   private:
    frix_error run(const SolverEntry &entry, int64_t max_iter, Watchdog *dog = nullptr, SolveCache *cache = nullptr);
    frix_error reduced_solve(const frix_info &like, int64_t max_iter);
    frix_error w_free_route(int64_t max_iter, std::unique_ptr<KeptMassPlusContacts> system);
    frix_error reduce_after(int64_t left, const GlobalAnswer *from);
    // Whether a route may go on after a run that did not converge: not stopped, not run away
    // (no solution: no route finds one), time and `left` iterations left.
    bool may_go_on(bool stopped, int64_t left) const {
        return info_.status != FRIX_STATUS_CONVERGED && !stopped && !info_.ran_away && !Monitor(ctx_).out_of_time() &&
               left > 0;
    }

    SolveContext &ctx_;
    frix_info &info_;  // the ledger of the routes run so far
    SolveCache *reduction_;
    const AnalysisSummary figures_;
    const frix_options options_;  // route_options
};

// M's factorisation, before a route that solves with M, where the driver left it to the routes
// (SolveContext::factor_mass: a one-shot solve from r = 0). *go_on false: the run ends here, M
// singular (the driver's passes take over) or its factorisation refused by a limit (the
// ledger's status).
frix_error GlobalRoutes::ensure_mass_factorised(bool *go_on) {
    *go_on = true;
    if (!ctx_.mass || ctx_.mass->factored() || !ctx_.factor_mass) return FRIX_OK;
    bool ready = true;
    if (frix_error e = (*ctx_.factor_mass)(&ready)) return e;
    if (!ready) {
        info_.status = ctx_.mass->refused() ? ctx_.mass->refused() : FRIX_STATUS_NOT_RUN;
        *go_on = false;
    }
    return FRIX_OK;
}

// A solver of global problems (`entry`: 607, 613, 901, gnsgs) from ctx's (r, v), for at most
// max_iter iterations (and its own limit), on the caller's clock, tolerance, measure and
// callback (`dog`, when given, watches it and passes the callback on), on `cache` where given
// (else the routes' own: the persistent solver's, or none). Its run joins the
// ledger, its record the trace. Converged is the driver's verdict on the returned (r, v)
// (error and equilibrium), whatever the solver's own stopping test said.
frix_error GlobalRoutes::run(const SolverEntry &entry, int64_t max_iter, Watchdog *dog, SolveCache *cache) {
    const double tol = Monitor(ctx_).tolerance();
    frix_options o = stage_options(entry, options_, tol, max_iter, nullptr);
    if (dog) dog->install(o);
    frix_info run = info_.next_run();
    const double t0 = ctx_.clock.seconds();
    if (frix_error e = solve_global_problem(ctx_.problem, o, entry, ctx_.r, ctx_.u, ctx_.v, run, ctx_.clock,
                                            cache ? cache : reduction_, ctx_.mass))
        return e;
    if (meets_global_tolerance(run, tol)) run.status = FRIX_STATUS_CONVERGED;
    TraceEvent stage = stage_event(entry.id, run, ctx_.clock.seconds() - t0, run.error);
    stage.why = dog && dog->stopped_by_watchdog ? dog->why : nullptr;
    run.absorb(info_);
    run.trace.push_back(stage);
    info_ = std::move(run);
    return FRIX_OK;
}

// The local strategy on W = H^T M^-1 H for at most max_iter iterations: the ledger becomes its
// run (`like`'s solver, contacts and tolerance), whose analysis records get the global
// problem's figures. The reduced problem's own tolerance test is not the global one: the
// global measure of (r, v) decides, both ways.
frix_error GlobalRoutes::reduced_solve(const frix_info &like, int64_t max_iter) {
    frix_options reduction = options_;
    reduction.ivalue[FRIX_OPT_MAX_ITER] = std::max<int64_t>(1, max_iter);
    frix_info reduced = like.next_run();
    if (frix_error e = solve_global_problem(ctx_.problem, reduction, kAutoReductionEntry, ctx_.r, ctx_.u, ctx_.v,
                                            reduced, ctx_.clock, reduction_, ctx_.mass))
        return e;
    info_ = std::move(reduced);
    add_global_figures(info_.trace, figures_);
    if (meets_global_tolerance(info_, Monitor(ctx_).tolerance())) info_.status = FRIX_STATUS_CONVERGED;
    return FRIX_OK;
}

// The reduction route with `reduction_iter` of its `max_iter` iterations, then, where the
// global measure is not met, Newton on (v, r) (607) from its result with what is left; the
// better of the two answers is kept. The existence check is the caller's.
frix_error GlobalRoutes::reduce_then_newton(int64_t max_iter, int64_t reduction_iter) {
    const frix_info earlier = std::move(info_);
    if (frix_error e = reduced_solve(earlier, reduction_iter)) return e;
    const int64_t left = max_iter - info_.iterations;
    if (may_go_on(info_.status == FRIX_STATUS_STOPPED_BY_CALLBACK, left)) {
        TraceEvent fallback = trace_event(kGlobalFallback);
        fallback.status = info_.status;
        fallback.error = info_.error;
        fallback.value = info_.equilibrium;
        fallback.solver_id = FRIX_SOLVER_GLOBAL_NSN_AC;
        info_.trace.push_back(fallback);
        const GlobalAnswer reduced(ctx_, info_);
        if (frix_error e = run(kGnsnAcEntry, left)) return e;
        reduced.restore_if_better(ctx_, info_);
        info_.switches += 1;
    }
    info_.absorb(earlier);
    return FRIX_OK;
}

// After a route that missed the tolerance: the reduction route with `left` iterations, from
// `from` (null: from the route's answer), the better of the two answers kept.
frix_error GlobalRoutes::reduce_after(int64_t left, const GlobalAnswer *from) {
    const GlobalAnswer answer(ctx_, info_);
    if (from) from->put_back(ctx_);
    if (frix_error e = reduce_then_newton(left, left / 2)) return e;
    answer.restore_if_better(ctx_, info_);
    info_.switches += 1;
    return FRIX_OK;
}

// Rigid bodies whose W would be large and hold more entries than M^-1 H: NSGS without W
// (gnsgs, the caller's threads) with half the iterations, under the NSGS rate watch from
// kProductPatience sweeps on; where it misses the tolerance, the reduction route from its
// answer with what is left. Where forming W would overrun the limits (not `may_reduce`),
// gnsgs alone with all the iterations: there is nothing to hand over to.
frix_error GlobalRoutes::product_then_reduce(int64_t max_iter, bool may_reduce) {
    if (!may_reduce) return run(kGnsgsEntry, max_iter, nullptr);
    Shared shared(ctx_.options, ctx_.clock);
    const bool momentum = options_.i(FRIX_OPT_ACCELERATION) != 0;
    Watchdog dog(shared, Watch::Rate, Monitor(ctx_).tolerance(), 0,
                 momentum ? nsgs::kMomentumPatience : kProductPatience);
    if (frix_error e = run(kGnsgsEntry, std::max<int64_t>(1, max_iter / 2), &dog)) return e;
    const int64_t left = max_iter - info_.iterations;
    if (!may_go_on(shared.stop_requested.load(), left)) {
        if (info_.status == FRIX_STATUS_STOPPED_BY_CALLBACK && dog.stopped_by_watchdog)
            info_.status = FRIX_STATUS_STAGNATED;
        return FRIX_OK;
    }
    return reduce_after(left, nullptr);
}

// The route without W: ADMM on (v, r) (613) with at most half of max_iter, then, where it
// misses the tolerance, the augmented Lagrangian Newton (901) from its result with the rest.
// ADMM takes `system` (the pricing's M + H S H^T and its analysis) on the routes' cache, or on
// one of its own for a one-shot solve.
frix_error GlobalRoutes::w_free_route(int64_t max_iter, std::unique_ptr<KeptMassPlusContacts> system) {
    SolveCache own;
    SolveCache *cache = reduction_ ? reduction_ : &own;
    if (system) offer_mass_plus_contacts(*cache, FRIX_SOLVER_GLOBAL_ADMM, std::move(system));
    // Where W may be regular (3 nc <= n: a deformable body), gnsn-ac finishes from a short
    // ADMM's answer in a few steps, where ADMM's linear rate on a stiff body takes thousands.
    const bool newton_finishes = figures_.w_may_be_regular();
    const int64_t admm_cap = newton_finishes ? kWFreeAdmmBeforeNewton : kWFreeAdmmIterations;
    const int64_t admm_iter = std::clamp<int64_t>(max_iter / 2, 1, admm_cap);
    if (frix_error e = run(kGadmmEntry, admm_iter, nullptr, cache)) return e;
    int64_t left = max_iter - info_.iterations;
    if (!may_go_on(info_.status == FRIX_STATUS_STOPPED_BY_CALLBACK, left)) return FRIX_OK;
    const GlobalAnswer admm(ctx_, info_);
    bool go_on = true;
    if (frix_error e = ensure_mass_factorised(&go_on)) return e;
    if (!go_on) return FRIX_OK;
    if (newton_finishes) {
        if (frix_error e = run(kGnsnAcEntry, std::min(left, kWFreeNewtonSteps))) return e;
        admm.restore_if_better(ctx_, info_);
        info_.switches += 1;
        left = max_iter - info_.iterations;
        if (!may_go_on(info_.status == FRIX_STATUS_STOPPED_BY_CALLBACK, left)) return FRIX_OK;
    }
    const GlobalAnswer before(ctx_, info_);
    if (frix_error e = run(kGnsnAlEntry, std::min(left, kWFreeNewtonSteps))) return e;
    before.restore_if_better(ctx_, info_);
    info_.switches += 1;
    return FRIX_OK;
}

// Where W is not formed: the route without it, both stages on M + H S H^T. Where they miss the
// tolerance (a body so stiff that M's rounding bounds the equilibrium of their answer) and
// forming W fits the limits, the reduction from the caller's start, not from their answer: on
// such a body r is far from unique, and the reduction's own path leads where the equilibrium's
// rounding is smaller relative to H r. Where forming W would overrun a limit and M + H H^T has
// no Cholesky factor or would not fit either: Newton on (v, r) alone.
frix_error GlobalRoutes::without_w(int64_t max_iter, RouteChoice &choice) {
    TraceEvent direct = summary_event(kGlobalDirect, figures_);
    direct.status = choice.refused;
    direct.value = choice.prices.with_w / choice.prices.without_w;
    direct.solver_id = choice.w_free ? FRIX_SOLVER_GLOBAL_ADMM : FRIX_SOLVER_GLOBAL_NSN_AC;
    info_.trace.push_back(direct);
    if (!choice.w_free) return run(kGnsnAcEntry, max_iter);
    const GlobalAnswer start(ctx_, info_);
    if (frix_error e = w_free_route(max_iter, std::move(choice.w_free_system))) return e;
    const int64_t left = max_iter - info_.iterations;
    // Its factorisations refused although the price fitted (the memory left shrank before
    // their turn, at the start or at a change of rho): on rigid bodies the sweeps without W,
    // which factorise nothing, from the route's answer, kept where they end worse.
    if (info_.status == FRIX_STATUS_MEMORY_LIMIT && choice.rigid && left > 0) {
        const GlobalAnswer route(ctx_, info_);
        info_.switches += 1;
        if (frix_error e = product_then_reduce(left, false)) return e;
        route.restore_if_better(ctx_, info_);
        return FRIX_OK;
    }
    if (choice.refused || !may_go_on(info_.status == FRIX_STATUS_STOPPED_BY_CALLBACK, left)) return FRIX_OK;
    // The record of the route's answer (its error and equilibrium) where W is formed after it,
    // or refused.
    const auto record_route_end = [&](TraceKind kind, frix_status status) {
        TraceEvent e = trace_event(kind);
        e.status = status;
        e.error = info_.error;
        e.value = info_.equilibrium;
        info_.trace.push_back(e);
    };
    if (choice.forming_w_later) {
        if (const frix_status refused = Monitor(ctx_).affords(*choice.forming_w_later)) {
            record_route_end(kGlobalReduceRefused, refused);
            return FRIX_OK;
        }
    }
    bool go_on = true;
    if (frix_error e = ensure_mass_factorised(&go_on)) return e;
    if (!go_on) return FRIX_OK;
    record_route_end(kGlobalReduceAfter, info_.status);
    return reduce_after(left, &start);
}

}  // namespace

frix_error solve_global(SolveContext &ctx) {
    const frix_problem &p = ctx.problem;
    // A persistent solver keeps the driver's states of the reductions below (their own cache,
    // which follows the versions of the caller's M and H).
    Kept<KeptAuto> kept(ctx.cache, FRIX_SOLVER_AUTO);
    kept.keep();
    SolveCache *reduction = nullptr;
    if (ctx.cache) {
        reduction = &kept->reduction;
        reduction->m_values = ctx.cache->m_values;
        reduction->h_values = ctx.cache->h_values;
    }
    KeptAuto::Size &kept_size = kept->size;
    if (!ctx.cache || !kept_size.known || kept_size.m_values != ctx.cache->m_values ||
        kept_size.h_values != ctx.cache->h_values) {
        kept_size.figures = reduction_size(p);
        kept_size.known = ctx.cache != nullptr;
        if (ctx.cache) kept_size.m_values = ctx.cache->m_values, kept_size.h_values = ctx.cache->h_values;
    }
    const ReductionSize size = kept_size.figures;
    const int64_t max_iter = Monitor(ctx).max_iterations();
    RouteChoice choice = choose_route(ctx, size, kept->prices);
    GlobalRoutes routes(ctx, reduction, global_figures(p, size));
    if (!choice.w_free) {  // every route but the one without W solves with M from its start
        bool go_on = true;
        if (frix_error e = routes.ensure_mass_factorised(&go_on)) return e;
        if (!go_on) return FRIX_OK;
    }
    if (choice.product) return routes.product_then_reduce(max_iter, !choice.refused);
    if (!choice.refused && !choice.w_free) return routes.reduce_then_newton(max_iter, max_iter / 2);
    return routes.without_w(max_iter, choice);
}

}  // namespace frix::autosolve
