// rolling-nsgs (3000, Siconos 4.4's ROLLING_FRICTION_3D_NSGS): nonsmooth Gauss-Seidel on
// rolling-friction problems (five entries a contact, six with spinning friction). Each sweep
// solves every contact with the others held fixed (kit/local_rolling.hpp); the local form reads
// W's stored 3x3 block rows, or its columns where W is symmetric (else a copy of its block
// rows), the global form of rigid
// bodies keeps v = M^-1 (H r + f) and never forms W, its domains of contacts of one colour swept
// at once on the threads (kit/rolling_forms.hpp).
// Stops as Siconos's LIGHT_WITH_FULL_FINAL: on the light error |dr| / |r| confirmed by the full
// measure (and full checks on a schedule: kFullEvery, early_check_due).
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "solvers/entries.hpp"
#include "solvers/kit/local_rolling.hpp"
#include "solvers/kit/rolling_forms.hpp"
#include "solvers/kit/sweeps.hpp"
#include "src/error_state.hpp"
#include "src/log.hpp"
#include "src/memory.hpp"
#include "src/monitor.hpp"
#include "src/rolling.hpp"
#include "src/vec.hpp"

namespace frix {
namespace rolling_nsgs {
namespace {

// A full check (the measures at r, a product) every kFullEvery sweeps besides those the light
// error asks for: a sweep that converges while its light error stays large still stops.
constexpr int64_t kFullEvery = 16;
// Also after sweeps 1, 2, 4 and 8 where the light error is within kEarlyLight times its
// tolerance: on piles r drifts, and |dr| / |r| stays up to about 100 times above an error that
// already meets a loose tolerance; where it is further off, a check (about two sweeps' work)
// would fail.
constexpr double kEarlyLight = 100.0;
bool early_check_due(int64_t sweep, double light, double light_tol) {
    return sweep < kFullEvery && (sweep & (sweep - 1)) == 0 && light <= kEarlyLight * light_tol;
}

// The product form (global problems): once the best full error has not halved within
// kStallSweeps sweeps, a sweep restarts momentum only where |dr|^2 grows beyond kStalledGrowth
// times the last two sweeps'. While r drifts on a plateau its steps lengthen as momentum builds
// up, and the plain rule restarted at most sweeps. On the local form's sweeps (one order on W's
// rows) the same rule took up to 7 times more sweeps, and from the first sweep it slows small
// piles (notes/2026-11-29-rolling-sweeps-and-w-free-finish.md).
constexpr int64_t kStallSweeps = 200;
constexpr double kStalledGrowth = 1.25;

// Momentum on the sweeps (option acceleration; kit/sweeps.hpp's MomentumSchedule, nsgs's
// weights): after a sweep, r = x moves to P_K(x + beta (x - x_prev)). It stays on for the whole
// run: these sweeps have no freezing to hand a plateau back to, and on the sphere piles
// measured the plain sweeps held the same plateaus longer. A stall loosens its restarts in the
// product form only (a patience no local run reaches).
class Momentum {
   public:
    Momentum(bool on, bool product_form, int64_t m, const double *r)
        : schedule_(on, {product_form ? kStallSweeps : std::numeric_limits<int64_t>::max(), kStalledGrowth}) {
        if (on) copy_advised(last_, r, (size_t)m);
    }
    // A full check's error e after `sweep` sweeps.
    void judge(int64_t sweep, double e) { schedule_.judge(sweep, e); }
    void after_sweep(double dr2, double *r, const frix_problem &p, rolling::SweepForm &form) {
        if (!schedule_.on()) return;
        const double beta = schedule_.next(dr2, false);
        for (size_t i = 0; i < last_.size(); ++i) {
            const double x = r[i];
            r[i] = x + beta * (x - last_[i]);
            last_[i] = x;
        }
        if (beta == 0.0) return;
        const int n = contact_size(p);
        for (int64_t a = 0; a < p.nc; ++a) rolling::project_on_cone(r + n * a, rolling::cones_of(p, a));
        form.restart(r);
    }

   private:
    nsgs::MomentumSchedule schedule_;
    std::vector<double> last_;  // x_{k-1}
};

// *at_r_out: whether the last form.exact() was at the r returned, into ctx.u (rolling::solve_on_form).
frix_error run(SolveContext &ctx, rolling::SweepForm &form, bool *at_r_out) {
    const frix_problem &p = ctx.problem;
    const frix_options &o = ctx.options;
    local_rolling::Params lp;
    lp.tol = o.d(FRIX_OPT_LOCAL_TOLERANCE);
    lp.max_iter = (int)o.i(FRIX_OPT_LOCAL_MAX_ITER);
    std::vector<local_rolling::Contact> contacts = rolling::contacts_of(form, p);
    const Monitor monitor(ctx);
    const double tol = monitor.tolerance();
    if (o.i(FRIX_OPT_VERBOSITY) >= 1) {
        log_line(&o, "rolling-nsgs: %lld contacts, %s, momentum %s", (long long)p.nc, form.name(),
                 o.i(FRIX_OPT_ACCELERATION) ? "on" : "off");
        if (const nsgs::Domains *d = form.domains()) {
            int64_t widest = 0;  // the most domains of one colour: what the threads share
            for (int64_t k = 0; k < d->colours(); ++k)
                widest = std::max(widest, d->colour_ptr[(size_t)k + 1] - d->colour_ptr[(size_t)k]);
            log_line(&o, "rolling-nsgs: %lld domains of %lld colours, at most %lld a colour, %d threads",
                     (long long)d->domains(), (long long)d->colours(), (long long)widest, form.team()->size());
        }
    }
    const int64_t measure = o.i(FRIX_OPT_ERROR_MEASURE);
    double light_tol = tol;  // tightened when a light convergence is not confirmed
    frix_status status = FRIX_STATUS_NOT_RUN;
    int64_t it = 0;
    Momentum momentum(o.i(FRIX_OPT_ACCELERATION) != 0, p.kind == FRIX_PROBLEM_ROLLING_GLOBAL, contact_size(p) * p.nc,
                      ctx.r);
    Measures last;       // the last full check's measures,
    bool at_r = false;   // taken at the r returned
    // The product form measures a warm start by one pass over the contacts (a local problem's
    // is measured by the driver): one that already meets the tolerance is the answer.
    if (p.kind == FRIX_PROBLEM_ROLLING_GLOBAL && !vec::all_zero(ctx.r, contact_size(p) * p.nc)) {
        last = form.exact(ctx.r, ctx.u);
        at_r = true;
        ctx.info.error = selected_error(last, measure);
        if (ctx.info.error <= tol) status = FRIX_STATUS_CONVERGED;
    }
    while (status == FRIX_STATUS_NOT_RUN) {
        ++it;
        const rolling::SweepStats st = rolling::sweep(form, contacts, lp, ctx.r);
        momentum.after_sweep(st.dr2, ctx.r, p, form);
        at_r = false;
        const double light = std::sqrt(st.dr2) / (st.r2 > 0.0 ? std::sqrt(st.r2) : 1.0);
        const bool regular = light <= light_tol || it % kFullEvery == 0;  // the checks before the early ones
        if (regular || early_check_due(it, light, light_tol) || monitor.out_of_iterations(it)) {
            last = form.exact(ctx.r, ctx.u);
            at_r = true;
            const double error = selected_error(last, measure);
            ctx.info.error = error;
            // The stall's patience counts from the regular checks: the early ones, taken or not by
            // the light error, would move where it starts.
            if (regular) momentum.judge(it, error);
            if (o.i(FRIX_OPT_VERBOSITY) >= 2)
                log_line(&o, "rolling-nsgs: sweep %lld, light %.3e, error %.3e", (long long)it, light, error);
            // Siconos's rule: the light tolerance scaled by how far the full error missed.
            if (light <= light_tol && error > tol && error > 0.0) light_tol = std::max(light * tol / error, 1e-300);
            status = monitor.verdict(it, error);
        } else {
            status = monitor.limits(it, light);
        }
    }
    ctx.info.iterations = it;
    ctx.info.status = status;
    // The local form measures as the driver does (local_measures): it need not measure again.
    ctx.has_measured = at_r && p.kind == FRIX_PROBLEM_ROLLING_LOCAL;
    ctx.measured = last;
    *at_r_out = at_r;
    return FRIX_OK;
}

frix_error solve(SolveContext &ctx) {
    bool at_r = false;
    return rolling::solve_on_form(
        ctx, "rolling-nsgs", [&](rolling::SweepForm &form) { return run(ctx, form, &at_r); },
        (int)ctx.options.i(FRIX_OPT_THREADS), &at_r);
}

const frix_option_key kExtraKeys[] = {FRIX_OPT_LOCAL_TOLERANCE, FRIX_OPT_LOCAL_MAX_ITER, FRIX_OPT_ACCELERATION,
                                      FRIX_OPT_THREADS, (frix_option_key)0};

const OptionDefault kDefaults[] = {{FRIX_OPT_MAX_ITER, 20000},
                                   {FRIX_OPT_LOCAL_TOLERANCE, 1e-12},
                                   {FRIX_OPT_LOCAL_MAX_ITER, 20},
                                   {FRIX_OPT_ACCELERATION, 1},
                                   {(frix_option_key)0, 0}};

}  // namespace
}  // namespace rolling_nsgs

const SolverEntry kRollingNsgsEntry = {
    FRIX_SOLVER_ROLLING_NSGS,
    "rolling-nsgs",
    "ROLLING_FRICTION_3D_NSGS",
    "Nonsmooth Gauss-Seidel for rolling-friction problems (five entries a contact: r_N, r_T, "
    "m_R, and with spinning friction a sixth, m_S; frix_problem.h): sweeps over the contacts, "
    "each solved with the others held fixed. "
    "The one-contact solver is exact for take-off and for stick (r = -W_aa^-1 q inside the "
    "rolling cone), and otherwise runs a semismooth Newton on the natural map (the projection "
    "on the rolling cone, every De Saxce shift) from the better of the warm start and the "
    "projected stick reaction, finished where it stalls by Siconos's projected iterations with "
    "a self-adaptive step. Local problems: W as it is stored, its 3x3 block rows, or its "
    "columns read as its rows where W is symmetric (else a copy of its 5x5 or 6x6 block rows). "
    "Global problems whose M is block-diagonal with small blocks (rigid bodies, at most 64 dofs "
    "a block): the product "
    "form, v = M^-1 (H r + f) kept up to date, W never formed, the contacts cut into domains "
    "coloured by body as gnsgs's, the domains of a colour swept at once on `threads` threads (r "
    "does not depend on their number); the local form sweeps on one thread. A deformable M is refused "
    "(FRIX_ERR_UNSUPPORTED). Stops on the light error |dr|/|r| confirmed by the full error "
    "(Siconos LIGHT_WITH_FULL_FINAL), with full checks every 16 sweeps, and after sweeps 1, 2, 4 "
    "and 8 where the light error is within 100 times the tolerance. Options: threads, "
    "local_tolerance, local_max_iter (Newton steps; the projected iterations take ten times "
    "as many), acceleration (1, the default: after each sweep r moves on along its last step, "
    "Nesterov's momentum restarted whenever a sweep moves r more than each of the two before "
    "(in the product form more than 1.12 times them once the error has not halved in 200 "
    "sweeps), on for the whole run; on sphere piles it takes several times fewer sweeps; 0 = "
    "plain sweeps).",
    rolling_nsgs::solve,
    false,  // no three-component problem: rolling ones only, in both forms
    false,
    rolling_nsgs::kExtraKeys,
    rolling_nsgs::kDefaults,
    true,
};

}  // namespace frix
