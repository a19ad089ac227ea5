// The local Newton's run on kit::NewtonLoop (newton.hpp's Engine, as its system), and the
// solvers 504/513/520 with their hybrid (NSGS sweeps where Newton stalls).
#include "solvers/kit/newton.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "solvers/kit/sweeps.hpp"
#include "solvers/kit/nsn_functions.hpp"
#include "src/error_state.hpp"
#include "src/log.hpp"
#include "src/matrix.hpp"
#include "src/measures.hpp"
#include "src/monitor.hpp"
#include "src/vec.hpp"
#include "solvers/entries.hpp"

namespace frix {
namespace newton {

namespace {

using vec::dot;

}  // namespace

Engine &engine_for(KeptEngine &kept, const SolveCache *cache, const frix_matrix &W, const double *mu,
                   int64_t nc, const Settings &s) {
    if (kept.engine && cache && kept.w_pattern == cache->w_pattern && kept.nc == nc) {
        kept.engine->rebind(W, mu, s);
    } else {
        kept.engine = std::make_unique<Engine>(W, mu, nc, s);
        kept.nc = nc;
    }
    kept.w_pattern = cache ? cache->w_pattern : 0;
    return *kept.engine;
}

Settings settings_from(const frix_options &o, int solver_id) {
    Settings s;
    s.formulation = solver_id == FRIX_SOLVER_NSN_FB   ? nsn::kFischerBurmeister
                    : solver_id == FRIX_SOLVER_NSN_NM ? nsn::kNaturalMap
                                                      : nsn::kAlartCurnier;
    s.rho_strategy = (int)o.i(FRIX_OPT_RHO_STRATEGY);
    s.rho = o.d(FRIX_OPT_RHO);
    s.line_search = (int)o.i(FRIX_OPT_LINE_SEARCH);
    s.ls_max_iter = (int)o.i(FRIX_OPT_LINE_SEARCH_MAX_ITER);
    s.hybrid = (int)o.i(FRIX_OPT_HYBRID);
    s.hybrid_sweeps = o.i(FRIX_OPT_HYBRID_SWEEPS);
    s.watchdog = (int)o.i(FRIX_OPT_WATCHDOG);
    s.measure = o.i(FRIX_OPT_ERROR_MEASURE);
    s.verbosity = (int)o.i(FRIX_OPT_VERBOSITY);
    s.log = &o;
    return s;
}

// A run of the engine as the Newton loop's system (kit/newton_engine.hpp): Newton on
// u = (W + shift I) r + q from r, in place.
class Engine::Run : public kit::SystemDefaults, public kit::InPlaceIterate {
   public:
    static constexpr bool kWatchable = true;

    Run(Engine &e, double *r, const double *q, double shift, double scale_q)
        : InPlaceIterate(r, e.m_), e_(e), q_(q), shift_(shift), phi_(m_), rhs_(m_), x_(m_), phit_(m_) {
        norm_q_ = scale_q >= 0.0 ? scale_q : std::sqrt(dot(q, q, m_));
    }
    frix_error evaluate(double &psi, double &err) {
        velocity();  // a fresh product: no drift of u = W r + q over many steps
        e_.evaluate(r_, u_.data(), true, phi_.data());
        psi = 0.5 * dot(phi_.data(), phi_.data(), m_);
        err = error_at(r_, u_.data());
        return FRIX_OK;
    }
    // delta in units of the mean |W_aa| (w_scale), on top of the shift.
    frix_error prepare(double delta) { return e_.prepare(shift_ + delta * e_.w_scale_); }
    frix_error factor(double delta, kit::Factorisation &f) { return e_.factor(shift_ + delta * e_.w_scale_, f); }
    frix_error solve(bool &finite) {
        e_.analysed_ = true;
        if (frix_error e = e_.step(phi_.data(), d_.data(), rhs_.data(), x_.data())) return e;
        for (int64_t i = 0; i < m_ && finite; ++i) finite = std::isfinite(d_[i]);
        return FRIX_OK;
    }
    // Slope of the merit along d: Phi . (A d + B du), the exact directional derivative.
    frix_error directional(double &slope) {
        product(d_.data(), du_.data());
        slope = nsn::add_merit_slope(0.0, phi_.data(), e_.A_.data(), e_.B_.data(), d_.data(), du_.data(), e_.nc_);
        return FRIX_OK;
    }
    // 1/2 |Phi(r + t d, u + t du)|^2.
    double merit_at(double t) {
        along(t);
        e_.evaluate(rt_.data(), ut_.data(), false, phit_.data());
        return 0.5 * dot(phit_.data(), phit_.data(), m_);
    }
    frix_error full_step_error(double &err) {
        along(1.0);
        err = error_at(rt_.data(), ut_.data());
        return FRIX_OK;
    }
    void log_step(int64_t step, double t, double err, double psi, double delta) const {
        if (e_.s_.verbosity >= 2)
            log_line(e_.s_.log, "newton: step %lld t %.3g error %.3e merit %.3e delta %.1e", (long long)step, t, err,
                     psi, delta);
    }
    void log_return(int64_t step) const {
        if (e_.s_.verbosity >= 2) log_line(e_.s_.log, "newton: watchdog: back to step %lld", (long long)step);
    }

   private:
    void product(const double *z, double *y) const {  // y = (W + shift I) z
        matrix_gemv(*e_.W_, 1.0, z, 0.0, y);
        if (shift_ != 0.0)
            for (int64_t i = 0; i < m_; ++i) y[i] += shift_ * z[i];
    }
    void velocity() {
        product(r_, u_.data());
        for (int64_t i = 0; i < m_; ++i) u_[i] += q_[i];
    }
    double error_at(const double *r, const double *u) const {
        return selected_error(measures_from_ru(r, u, e_.mu_, e_.s_.weight, e_.nc_, norm_q_), e_.s_.measure);
    }

    Engine &e_;
    const double *q_;
    const double shift_;
    double norm_q_;
    std::vector<double> phi_, rhs_, x_, phit_;
};

frix_error Engine::run(double *r, const double *q, double shift, kit::Steps &steps, RunResult &res, double scale_q) {
    lu_.set_budget(steps.monitor.budget());  // this run's time and memory limits
    Run system(*this, r, q, shift, scale_q);
    kit::Rules rules;
    rules.search = kit::search_of(s_.line_search, s_.ls_max_iter);
    // A proximal shift already regularises J: delta then starts at 0.
    rules.delta_start = shift > 0.0 ? 0.0 : kit::kDeltaStart;
    rules.watchdog = s_.watchdog;
    rules.full_step_on_failure = full_step_on_failure;
    return kit::newton(system, steps, rules, counters, res);
}

namespace {

// The hybrid's rounds (kit::newton_with_sweeps) on the local problem: Newton from ctx.r,
// and NSGS sweeps with the closed-form one-contact solver (made on the first fallback only).
class LocalRounds {
   public:
    LocalRounds(SolveContext &ctx, Engine &engine, kit::Steps &steps, const Settings &s)
        : ctx_(ctx), engine_(engine), steps_(steps), s_(s) {}
    frix_error newton(RunResult &res) { return engine_.run(ctx_.r, ctx_.problem.q, 0.0, steps_, res); }
    void keep() {
        if (!gs_) {
            nsgs::Settings gss;
            gss.local.solver = local::kClosedForm;
            gs_ = std::make_unique<nsgs::Workspace>(ctx_.problem, gss);
        }
        kept_.assign(ctx_.r, ctx_.r + 3 * ctx_.problem.nc);
    }
    void restore() { std::copy(kept_.begin(), kept_.end(), ctx_.r); }
    void sweep() { gs_->sweep(ctx_.r); }
    double error() const { return selected_error(local_measures(ctx_.problem, ctx_.r, ctx_.u), s_.measure); }
    void log_sweeps(double before, double after) const {
        if (s_.verbosity >= 1)
            log_line(s_.log, "newton: stalled at %.3e, %lld NSGS sweeps -> %.3e", before, (long long)s_.hybrid_sweeps,
                     after);
    }
    Monitor::Agree agree() const { return nullptr; }

   private:
    SolveContext &ctx_;
    Engine &engine_;
    kit::Steps &steps_;
    const Settings &s_;
    std::unique_ptr<nsgs::Workspace> gs_;
    std::vector<double> kept_;
};

frix_error solve(SolveContext &ctx, int solver_id) {
    const frix_problem &p = ctx.problem;
    const frix_options &o = ctx.options;
    if (!p.W || !p.W->block) return fail(FRIX_ERR_INTERNAL, "newton: W is not stored as 3x3 blocks");
    Settings s = settings_from(o, solver_id);
    frix_info &info = ctx.info;
    kit::Steps steps{Monitor(ctx)};
    Kept<KeptEngine> kept(ctx.cache, solver_id);
    s.weight = p.weight.data();
    Engine &engine = engine_for(*kept, ctx.cache, *p.W, p.mu, p.nc, s);
    LocalRounds rounds(ctx, engine, steps, s);
    RunResult res;
    if (frix_error e = kit::newton_with_sweeps(rounds, steps, s.hybrid == FRIX_HYBRID_NSGS, s.hybrid_sweeps,
                                               engine.counters, res))
        return e;
    kit::record(info, res, steps, engine.counters);
    Monitor::record_factorizations(info, engine.factor_stats());
    if (s.verbosity >= 1)
        log_line(s.log, "newton: %s after %lld iterations (%lld Newton, %lld sweeps)",
                 frix_status_string(info.status), (long long)steps.done,
                 (long long)engine.counters.newton, (long long)engine.counters.sweeps);
    kept.keep();
    return FRIX_OK;
}

frix_error solve_ac(SolveContext &ctx) { return solve(ctx, FRIX_SOLVER_NSN_AC); }
frix_error solve_fb(SolveContext &ctx) { return solve(ctx, FRIX_SOLVER_NSN_FB); }
frix_error solve_nm(SolveContext &ctx) { return solve(ctx, FRIX_SOLVER_NSN_NM); }

const frix_option_key kExtraKeys[] = {FRIX_OPT_RHO_STRATEGY, FRIX_OPT_RHO, FRIX_OPT_LINE_SEARCH,
                                      FRIX_OPT_LINE_SEARCH_MAX_ITER, FRIX_OPT_HYBRID,
                                      FRIX_OPT_HYBRID_SWEEPS, FRIX_OPT_WATCHDOG, (frix_option_key)0};

// The watchdog (kWatchdogTrigger) with 5 steps for Alart-Curnier and Fischer-Burmeister; not
// for the natural map, whose full steps it cuts short on problems the natural map solves.
const OptionDefault kAcDefaults[] = {{FRIX_OPT_MAX_ITER, 2000},
                                     {FRIX_OPT_RHO_STRATEGY, FRIX_RHO_SPECTRAL},
                                     {FRIX_OPT_WATCHDOG, 5},
                                     {(frix_option_key)0, 0}};
// FB and the natural map take rho = 1/W_NN (the split strategy's rho_N): with the spectral
// rho they stall on three of the rigid FCLIB problems (Capsules, spheres-in-a-box) that
// they solve with this one; Alart-Curnier is the other way round.
const OptionDefault kFbDefaults[] = {{FRIX_OPT_MAX_ITER, 2000},
                                     {FRIX_OPT_RHO_STRATEGY, FRIX_RHO_SPLIT},
                                     {FRIX_OPT_WATCHDOG, 5},
                                     {(frix_option_key)0, 0}};
const OptionDefault kNmDefaults[] = {{FRIX_OPT_MAX_ITER, 2000},
                                     {FRIX_OPT_RHO_STRATEGY, FRIX_RHO_SPLIT},
                                     {(frix_option_key)0, 0}};

#define FRIX_NEWTON_COMMON_DOC                                                                   \
    " The generalized Jacobian A + B W is assembled directly in sparse form from W's 3x3 "      \
    "blocks (pattern fixed for the solve: one UMFPACK symbolic analysis, one numeric "          \
    "factorisation per step); the step is damped by a line search on 1/2 |Phi|^2 "             \
    "(Goldstein-Price by default, Armijo, non-monotone Armijo or none). A singular Jacobian "  \
    "(rank-deficient W) is regularised as A + B (W + delta I) with delta adapted. With "        \
    "hybrid = nsgs (the default), a stalled Newton hands over to NSGS sweeps and resumes. "    \
    "Options: rho_strategy (constant, spectral, split), rho, line_search, "                    \
    "line_search_max_iter, hybrid, hybrid_sweeps, watchdog (where the line search stalls but the " \
    "full step halves the best error: the full step and k - 1 more, full too where the line "  \
    "search would cut them short, undone unless the error fell tenfold). Iterations count "     \
    "Newton steps plus fallback sweeps."

}  // namespace
}  // namespace newton

const SolverEntry kNsnAcEntry = {
    FRIX_SOLVER_NSN_AC, "nsn-ac", "FRICTION_3D_NSN_AC",
    "Semismooth Newton on the Alart-Curnier formulation Phi(r) = 0 (per contact: "
    "r_N - max(0, r_N - rho_N u_N) and r_T minus the projection of r_T - rho_T u_T on the disk "
    "of radius mu max(0, r_N - rho_N u_N))." FRIX_NEWTON_COMMON_DOC,
    newton::solve_ac, true, false, newton::kExtraKeys, newton::kAcDefaults};

const SolverEntry kNsnFbEntry = {
    FRIX_SOLVER_NSN_FB, "nsn-fb", "FRICTION_3D_NSN_FB",
    "Semismooth Newton on the Fischer-Burmeister function of the second-order cone "
    "complementarity K ∋ r ⟂ u^ ∈ K* (u^ the De Saxce velocity), after the sqrt(mu) scaling "
    "that maps K and K* onto the Lorentz cone." FRIX_NEWTON_COMMON_DOC,
    newton::solve_fb, true, false, newton::kExtraKeys, newton::kFbDefaults};

const SolverEntry kNsnNmEntry = {
    FRIX_SOLVER_NSN_NM, "nsn-nm", "FRICTION_3D_NSN_NM",
    "Semismooth Newton on the natural map Phi(r) = r - P_K(r - rho u^), the residual of the "
    "error measure (u^ the De Saxce velocity)." FRIX_NEWTON_COMMON_DOC,
    newton::solve_nm, true, false, newton::kExtraKeys, newton::kNmDefaults};

}  // namespace frix
