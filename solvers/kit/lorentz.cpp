#include "solvers/kit/lorentz.hpp"

#include "solvers/kit/nsn_functions.hpp"
#include "src/measures.hpp"
#include "src/monitor.hpp"

namespace frix {
namespace lorentz {

StartScales start_scales(const frix_problem &p) {
    const frix_matrix &W = *p.W;
    double qinf = 0.0, wnn = 0.0;
    for (int64_t i = 0; i < 3 * p.nc; ++i) qinf = std::max(qinf, std::fabs(p.q[i]));
    for (int64_t a = 0; a < p.nc; ++a)
        if (W.diag_index[a] >= 0) wnn += std::fabs(W.block_val[9 * W.diag_index[a]]);
    wnn = wnn > 0.0 ? wnn / (double)p.nc : 1.0;
    StartScales s;
    s.velocity = qinf > 0.0 ? qinf : 1.0;
    s.force = s.velocity / wnn;
    return s;
}

Run::Run(SolveContext &ctx, KeptSystem &kept, int stall_after)
    : ctx_(ctx),
      kept_(kept),
      stall_after_(stall_after),
      tol_(Monitor(ctx).tolerance()),
      measure_(ctx.options.i(FRIX_OPT_ERROR_MEASURE)),
      steps_(Monitor(ctx)),
      best_(ctx.r, ctx.r + 3 * ctx.problem.nc) {
    const frix_problem &p = ctx.problem;
    kept_.refresh(ctx.cache, *p.W, p.mu, p.nc);
    stats_before_ = kept_.lu.stats();
    kept_.lu.set_budget(Monitor(ctx).budget());
    best_err_ = selected_error(local_measures(p, ctx.r, ctx.u), measure_);
    if (!std::isfinite(best_err_)) best_err_ = INFINITY;
    ctx.info.status = FRIX_STATUS_MAX_ITER;
}

Run::Next Run::check(const double *r) {
    if (best_err_ <= tol_) return kStop;
    const double err = last_err_ = selected_error(local_measures(ctx_.problem, r, ctx_.u), measure_);
    if (err < best_err_) {
        best_err_ = err;
        std::copy(r, r + best_.size(), best_.begin());
    }
    if (err <= tol_) return kStop;
    if (steps_.done > 0) steps_.report(err, r);  // the interior point's own iterate, watched for a runaway
    const frix_status stop = steps_.limits();
    if (stop != FRIX_STATUS_NOT_RUN) {
        ctx_.info.status = stop;
        return kStop;
    }
    if (best_err_ < 0.5 * ref_err_) {
        ref_err_ = best_err_;
        since_progress_ = 0;
    } else if (++since_progress_ >= stall_after_) {
        return kHandOver;
    }
    return kIterate;
}

frix_error Run::end(bool hand_over) {
    frix_info &info = ctx_.info;
    const frix_problem &p = ctx_.problem;
    if (best_err_ <= tol_) info.status = FRIX_STATUS_CONVERGED;
    std::copy(best_.begin(), best_.end(), ctx_.r);
    linalg::FactorStats fs = kept_.lu.stats() - stats_before_;
    int64_t line_search = 0;
    if (hand_over) {
        const frix_options &o = ctx_.options;
        newton::Settings s;
        s.formulation = nsn::kAlartCurnier;
        s.rho_strategy = FRIX_RHO_SPECTRAL;
        s.measure = measure_;
        s.verbosity = (int)o.i(FRIX_OPT_VERBOSITY);
        s.log = &o;
        s.weight = p.weight.data();
        newton::Engine &engine = newton::engine_for(kept_.polish, ctx_.cache, *p.W, p.mu, p.nc, s);
        newton::RunResult res;
        if (frix_error e = engine.run(ctx_.r, p.q, 0.0, steps_, res)) return e;
        info.status = res.status;
        newton_steps_ = engine.counters.newton;
        line_search = engine.counters.line_search;
        fs = fs + engine.factor_stats();
    }
    info.iterations = steps_.done;
    info.newton_iterations = newton_steps_;
    info.line_search_steps = line_search;
    Monitor::record_factorizations(info, fs);
    return FRIX_OK;
}

}  // namespace lorentz
}  // namespace frix
