// frix_mpi_solve: the driver of a distributed solve (as solve_local_problem is for one
// process: the all-separating case, the warm start, the solver, the final measures and the
// status check against them), and the solvers it runs: nsgs's iteration (run_sweeps) on a
// distributed form, or the distributed Newtons (distributed_newton.cpp, and
// distributed_global_newton.cpp for global problems with the host's M).
#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "mpi/distributed_forms.hpp"
#include "solvers/kit/sweeps.hpp"
#include "src/error_state.hpp"
#include "src/measures.hpp"
#include "src/solver_api.hpp"

namespace frix {
namespace mpi {
namespace {

// The driver (as solve_local_problem for one process): the all-separating case, the warm
// start, the solver watched for a runaway (its bound: the serial problem's, runaway_bound of
// the free velocity over all ranks; each rank watches its contacts, the stop agreed), the final
// measures, the serial fallback of a diverged run (fall_back_on_divergence, decided over the
// ranks) and the status check against the measures.
frix_error solve(frix_mpi_problem &p, const frix_options &opts, double *r_out, double *u_out, frix_info &info,
                 const Stopwatch &clock) {
    const MPI_Comm comm = p.ctx->comm;
    const int64_t m = 3 * p.owned;
    // (A non-finite entry would poison every iterate: 0 instead.)
    const std::vector<double> warm_start = finite_warm_start(r_out, m);
    if (p.global) return run_global_newton(p, opts, warm_start, r_out, u_out, info, clock);  // (v, r)
    std::vector<double> r((size_t)(3 * (p.owned + (int64_t)p.ghosts.size())), 0.0);
    std::copy(r_out, r_out + m, r.begin());
    // The form of the problem's kind (bodies: set for rigid bodies only).
    DistributedBodies *bodies = p.rigid ? new DistributedBodies(p) : nullptr;
    const std::unique_ptr<DistributedForm> owner(bodies ? (DistributedForm *)bodies : new DistributedRows(p));
    DistributedForm &form = *owner;
    // r = 0 answers when every contact separates at rest (u = q, or H^T M^-1 f + w).
    bool approaching = false;
    for (int64_t a = 0; a < p.owned && !approaching; ++a) {
        double u[3] = {p.q[3 * (size_t)a], 0.0, 0.0};
        if (p.rigid) bodies->free_velocity(a, u);
        approaching = u[0] < 0.0;
    }
    const bool separating = or_all(comm, approaching ? 1u : 0u) == 0;
    const double bound = runaway_bound(form.norm_free());
    bool ran = false;
    if (p.total == 0 || separating) {
        std::fill(r.begin(), r.end(), 0.0);
        info.status = FRIX_STATUS_CONVERGED;
        info.iterations = 0;
    } else {
        ran = true;
        form.exchange(r.data());
        SolveContext ctx = SolveContext::local(p.view, opts, r.data(), u_out, info, clock);
        ctx.runaway_bound = bound;
        if (opts.solver_id == FRIX_SOLVER_NSN_AC) {
            if (frix_error e = run_newton(p, ctx, form)) return e;
        } else {
            const nsgs::Settings settings = nsgs::settings_from(opts);
            std::unique_ptr<nsgs::Workspace> ws(p.rigid ? new nsgs::Workspace(p.diag.data(), p.mu.data(), p.owned, settings)
                                                        : new nsgs::Workspace(p.view, settings));
            if (frix_error e = nsgs::run_sweeps(ctx, *ws, form, "nsgs")) return e;
        }
    }
    Measures meas = form.exact(r.data(), u_out);
    if (ran) {
        // An answer x of this rank's contacts, measured over the ranks (collective).
        const MeasureAnswer at = [&](const double *x, double *ux, double *, Measures &out) {
            std::vector<double> held(r.size(), 0.0);
            std::copy(x, x + m, held.begin());
            form.exchange(held.data());
            out = form.exact(held.data(), ux);
            return FRIX_OK;
        };
        if (frix_error e = fall_back_on_divergence(p.view, opts.i(FRIX_OPT_ERROR_MEASURE), warm_start,
                                                   !finite_measures(meas), bound, at, r.data(), u_out, nullptr, meas,
                                                   info, over_ranks(comm)))
            return e;
        if (p.rigid && info.status == FRIX_STATUS_DIVERGED) {  // the bodies' velocities at the answer returned
            form.exchange(r.data());
            meas = form.exact(r.data(), u_out);
        }
    }
    std::copy(r.begin(), r.begin() + m, r_out);
    if (p.rigid) {
        p.v = bodies->velocities();  // at the final r: exact() above recomputed them
        p.solved = true;
    }
    record_measures(info, meas, opts.i(FRIX_OPT_ERROR_MEASURE));
    if (info.status == FRIX_STATUS_CONVERGED && !(info.error <= info.tolerance)) info.status = FRIX_STATUS_STAGNATED;
    return FRIX_OK;
}

// The options a distributed solve runs with: nsgs's or nsn-ac's, checked alike on every rank;
// only rank 0 logs.
frix_error check_options(const frix_options *given, const frix_mpi_problem &p, frix_options &out) {
    const char *where = "frix_mpi_solve";
    if (frix_error e = given ? check_release(*given, where, "options") : FRIX_OK) return e;
    if (!given) {
        frix_options *o = nullptr;
        if (frix_error e = frix_options_create(p.global ? FRIX_SOLVER_GLOBAL_NSN_AC : FRIX_SOLVER_NSGS, &o)) return e;
        out = *o;
        frix_options_free(o);
    } else {
        const int id = given->solver_id;
        if (id != FRIX_SOLVER_NSGS && id != FRIX_SOLVER_NSN_AC && id != FRIX_SOLVER_GLOBAL_NSN_AC)
            return fail(FRIX_ERR_UNSUPPORTED,
                        "%s: solver %d is not distributed (nsgs, %d, nsn-ac, %d, and gnsn-ac, %d, are)", where, id,
                        (int)FRIX_SOLVER_NSGS, (int)FRIX_SOLVER_NSN_AC, (int)FRIX_SOLVER_GLOBAL_NSN_AC);
        if (p.global && id != FRIX_SOLVER_GLOBAL_NSN_AC)
            return fail(FRIX_ERR_UNSUPPORTED,
                        "%s: a global problem with the host's M runs gnsn-ac (%d): W = H^T M^-1 H is not formed", where,
                        (int)FRIX_SOLVER_GLOBAL_NSN_AC);
        if (!p.global && id == FRIX_SOLVER_GLOBAL_NSN_AC)
            return fail(FRIX_ERR_UNSUPPORTED, "%s: gnsn-ac runs on global problems with the host's M (frix_mpi_problem_global)",
                        where);
        if (id == FRIX_SOLVER_NSN_AC && p.rigid)
            return fail(FRIX_ERR_UNSUPPORTED, "%s: nsn-ac needs W's rows; a problem of rigid bodies runs nsgs", where);
        out = *given;
    }
    if (out.solver_id == FRIX_SOLVER_NSGS &&
        (out.i(FRIX_OPT_DRIFT_WINDOW) != 0 || out.i(FRIX_OPT_ACCELERATION) != 0 || out.i(FRIX_OPT_ANDERSON) != 0 ||
         out.i(FRIX_OPT_SHUFFLE) != FRIX_SHUFFLE_NONE))
        return fail(FRIX_ERR_UNSUPPORTED,
                    "%s: drift_window, acceleration, anderson and shuffle are not distributed (set them to 0)", where);
    if (p.ctx->rank != 0) out.ivalue[FRIX_OPT_VERBOSITY] = 0;
    return FRIX_OK;
}

}  // namespace
}  // namespace mpi
}  // namespace frix

extern "C" {

FRIX_API frix_error frix_mpi_solve(frix_mpi_problem *p, const frix_options *options, double *r, double *u,
                                   frix_info *info) {
    frix::Stopwatch clock;
    return frix::guard("frix_mpi_solve", [&]() -> frix_error {
        using frix::fail;
        if (!p) return fail(FRIX_ERR_INVALID_ARGUMENT, "frix_mpi_solve: p is NULL");
        const MPI_Comm comm = p->ctx->comm;
        frix_options opts;
        frix_error e = frix::mpi::check_options(options, *p, opts);
        if (!e && info) e = frix::mpi::check_release(*info, "frix_mpi_solve", "info");
        if (!e && p->owned > 0 && (!r || !u))
            e = fail(FRIX_ERR_INVALID_ARGUMENT, "frix_mpi_solve: r and u are required (%lld entries each)",
                     (long long)(3 * p->owned));
        if (frix_error agreed = frix::mpi::agree(comm, e, "frix_mpi_solve")) return agreed;
        frix_info local_info;
        frix_info &out = info ? *info : local_info;
        out = frix_info();
        out.solver_id = opts.solver_id;
        out.contacts = p->total;
        out.tolerance = opts.d(FRIX_OPT_TOLERANCE);
        e = frix::mpi::solve(*p, opts, r, u, out, clock);
        out.solve_time = clock.seconds();
        return e;
    });
}

}  // extern "C"
