// The distributed global Newton (gnsn-ac, 607) on a global problem with the host's M: the
// serial gnsn-ac's Newton (solvers/global/gnsn_ac.cpp, on solvers/kit/newton_engine.hpp's
// loop) over the ranks' rows of (v, r), each
// rank holding its dofs' rows of M v - H r - f = 0 and its contacts' rows of
// Phi(r, H^T v + w) = 0. The Jacobian [[M, -H], [B H^T, A]] is one PETSc matrix over the
// ranks' rows (rank k's dofs, then its contacts' 3 rows each), solved by MUMPS's LU.
#include <petscksp.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "mpi/distributed_forms.hpp"
#include "mpi/global_newton_system.hpp"
#include "mpi/petsc_support.hpp"
#include "solvers/kit/global_newton.hpp"
#include "solvers/kit/newton.hpp"
#include "solvers/kit/nsn_functions.hpp"
#include "src/error_state.hpp"
#include "src/log.hpp"
#include "src/monitor.hpp"
#include "src/vec.hpp"

namespace frix {
namespace mpi {
namespace {

using namespace gnsn_ac;

using global_newton::dot_all;
using global_newton::GlobalSystem;

// The contacts' rho from the lumped blocks, corrected where they underrate W's (as the serial
// gnsn-ac), and their scale (mean |W_aa| over all contacts), delta's unit.
struct RanksRho {
    std::vector<double> rho_n, rho_t;
    double scale = 1.0;
};
frix_error lumped_rho(frix_mpi_problem &p, const newton::Settings &s, GlobalSystem &sys, const frix_options &o,
                      RanksRho &out) {
    const MPI_Comm comm = p.ctx->comm;
    const int64_t nc = p.owned;
    std::vector<double> lumped;
    if (frix_error e = agree(comm, sys.lumped_blocks(lumped), "frix_mpi_solve")) return e;
    double underrate = 1.0;
    if (s.rho_strategy != FRIX_RHO_CONSTANT && p.total > 0) {
        const int count = (int)std::min<int64_t>(kRhoSamples, p.total);
        std::vector<double> ratios;
        for (int k = 0; k < count; ++k) {
            const int64_t a = (int64_t)k * p.total / count;
            double exact = 0.0, lumped_trace = 0.0;
            if (frix_error e = agree(comm, sys.exact_trace(a, exact), "frix_mpi_solve")) return e;
            if (a >= p.first && a < p.first + nc) {
                const double *Wd = &lumped[9 * (size_t)(a - p.first)];
                lumped_trace = Wd[0] + Wd[4] + Wd[8];
            }
            reduce_all(comm, &lumped_trace, 1, "s");
            if (lumped_trace > 0.0 && std::isfinite(exact)) ratios.push_back(exact / lumped_trace);
        }
        if (!ratios.empty()) {
            std::nth_element(ratios.begin(), ratios.begin() + ratios.size() / 2, ratios.end());
            underrate = ratios[ratios.size() / 2];
        }
    }
    const double correction = underrate > kUnderrateToCorrect ? underrate : 1.0;
    if (s.verbosity >= 1 && underrate != 1.0)
        log_line(&o, "global newton (distributed): the lumped blocks underrate W's by %.3g%s", underrate,
                 correction != 1.0 ? ": rho corrected" : "");
    out.rho_n.resize((size_t)nc), out.rho_t.resize((size_t)nc);
    double wscale = 0.0;
    for (int64_t a = 0; a < nc; ++a) {
        double Wd[9], fro = 0.0;
        for (int k = 0; k < 9; ++k) Wd[k] = correction * lumped[9 * (size_t)a + (size_t)k], fro += Wd[k] * Wd[k];
        nsn::contact_rho(s.rho_strategy, s.rho, Wd, &out.rho_n[(size_t)a], &out.rho_t[(size_t)a]);
        wscale += std::sqrt(fro);
    }
    reduce_all(comm, &wscale, 1, "s");
    out.scale = p.total > 0 && wscale > 0.0 ? wscale / (double)p.total : 1.0;
    return FRIX_OK;
}

// The newton's iterate (v, r) with what the steps and measures read.
struct State {
    std::vector<double> v, r, u, res, mv, hr, phi, A, B;
};

// The distributed gnsn-ac as kit::NewtonLoop's system: the serial gnsn-ac's (v, r) over the
// ranks' rows, the products and the Jacobian's solves by PETSc.
class RanksVrSystem : public kit::SystemDefaults {
   public:
    struct Point {
        std::vector<double> v, r;
    };
    RanksVrSystem(frix_mpi_problem &p, GlobalSystem &sys, RanksRho rho, const newton::Settings &s, const frix_options &o,
                  const RanksWeights &weights, const double *r)
        : p_(p), g_(*p.global), sys_(sys), comm_(p.ctx->comm), n_(g_.dofs), nc_(p.owned), m_(3 * p.owned),
          rho_(std::move(rho)), s_(s), o_(o), weights_(weights), norm_w_(norm2_all(comm_, p.w.data(), m_)),
          norm_f_(norm2_all(comm_, g_.f.data(), n_)), rhs_((size_t)(n_ + m_)), dx_((size_t)(n_ + m_)), Mdv_((size_t)n_),
          Hdr_((size_t)n_), Htdv_((size_t)m_), scaled_res_((size_t)n_), scaled_hr_((size_t)n_) {
        for (int64_t j = 0; j < n_; ++j) scaled_res_[(size_t)j] = weights_.dof[(size_t)j] * g_.f[(size_t)j];
        norm_df_ = norm2_all(comm_, scaled_res_.data(), n_);
        x_.v.assign((size_t)n_, 0.0);  // v from 0 (run_global_newton: or from a warm r)
        x_.r.assign(r, r + m_);
        x_.u.resize((size_t)m_);
        x_.res.resize((size_t)n_);
        x_.mv.resize((size_t)n_);
        x_.hr.resize((size_t)n_);
        x_.phi.resize((size_t)m_);
        x_.A.resize(9 * (size_t)nc_);
        x_.B.resize(9 * (size_t)nc_);
        trial_ = x_;
    }
    frix_error evaluate(double &psi, double &err) {
        psi = merit(x_, true);
        if (frix_error e = stopped()) return e;
        err = error_of(x_);
        return FRIX_OK;
    }
    frix_error factor(double delta, kit::Factorisation &f) {
        if (frix_error e = mpi::agree(comm_, sys_.assemble(x_.A, x_.B, delta * rho_.scale), "frix_mpi_solve")) return e;
        for (int64_t j = 0; j < n_; ++j) rhs_[(size_t)j] = -x_.res[(size_t)j];
        for (int64_t i = 0; i < m_; ++i) rhs_[(size_t)(n_ + i)] = -x_.phi[(size_t)i];
        return mpi::agree(comm_, sys_.solve(rhs_.data(), dx_.data(), f.factored), "frix_mpi_solve");
    }
    frix_error solve(bool &finite) {
        bool mine = true;
        for (size_t i = 0; i < dx_.size() && mine; ++i) mine = std::isfinite(dx_[i]);
        finite = or_all(comm_, mine ? 0u : 1u) == 0;
        return FRIX_OK;
    }
    // Slope of the merit: res . (M dv - H dr) + Phi . (A dr + B H^T dv), over the ranks.
    frix_error directional(double &slope) {
        const double *dv = dx_.data(), *dr = dx_.data() + n_;
        failed_ = sys_.mult_M(dv, Mdv_.data());
        if (!failed_) failed_ = sys_.mult_H(dr, Hdr_.data());
        if (!failed_) failed_ = sys_.mult_Ht(dv, Htdv_.data());
        if (frix_error e = stopped()) return e;
        slope = 0.0;
        for (int64_t j = 0; j < n_; ++j) slope += x_.res[(size_t)j] * (Mdv_[(size_t)j] - Hdr_[(size_t)j]);
        slope = nsn::add_merit_slope(slope, x_.phi.data(), x_.A.data(), x_.B.data(), dr, Htdv_.data(), nc_);
        reduce_all(comm_, &slope, 1, "s");
        return FRIX_OK;
    }
    // The merit over the ranks at (v, r) + t (dv, dr); the equilibrium rows are linear.
    double merit_at(double t) {
        const double *dr = dx_.data() + n_;
        double both[2] = {0.0, 0.0};
        for (int64_t j = 0; j < n_; ++j) {
            const double d = x_.res[(size_t)j] + t * (Mdv_[(size_t)j] - Hdr_[(size_t)j]);
            both[0] += d * d;
        }
        for (int64_t i = 0; i < m_; ++i) {
            trial_.r[(size_t)i] = x_.r[(size_t)i] + t * dr[i];
            trial_.u[(size_t)i] = x_.u[(size_t)i] + t * Htdv_[(size_t)i];
        }
        contacts(trial_, false);
        for (const double d : trial_.phi) both[1] += d * d;
        reduce_all(comm_, both, 2, "ss");
        return 0.5 * (both[0] + both[1]);
    }
    static constexpr bool kWatchable = true;
    // The error over the ranks at (v, r) + (dv, dr), in the trial state; the iterate's
    // measures stay those handed over.
    frix_error full_step_error(double &err) {
        for (int64_t j = 0; j < n_; ++j) trial_.v[(size_t)j] = x_.v[(size_t)j] + dx_[(size_t)j];
        for (int64_t i = 0; i < m_; ++i) trial_.r[(size_t)i] = x_.r[(size_t)i] + dx_[(size_t)(n_ + i)];
        const Measures kept = measures_;
        const double kept_equilibrium = equilibrium_;
        merit(trial_, false);
        if (frix_error e = stopped()) return e;
        err = error_of(trial_);
        measures_ = kept, equilibrium_ = kept_equilibrium;
        return FRIX_OK;
    }
    void move(double t) {
        for (int64_t j = 0; j < n_; ++j) x_.v[(size_t)j] += t * dx_[(size_t)j];
        for (int64_t i = 0; i < m_; ++i) x_.r[(size_t)i] += t * dx_[(size_t)(n_ + i)];
    }
    void save(Point &x) const {
        x.v = x_.v;
        x.r = x_.r;
    }
    void load(const Point &x) {  // in place: reactions() stays where it points
        std::copy(x.v.begin(), x.v.end(), x_.v.begin());
        std::copy(x.r.begin(), x.r.end(), x_.r.begin());
    }
    // This rank's reactions of the iterate (3 a contact), where they stay during the run.
    double *reactions() { return x_.r.data(); }
    // v = M^-1 (H r + f) at the start's r (collective), as the serial gnsn-ac keeps it from a
    // warm r on a deformable body; v stays 0 where M does not factorise.
    frix_error start_from_warm_velocity() {
        std::vector<double> b((size_t)n_), v((size_t)n_);
        bool solved = false;
        if (frix_error e = mpi::agree(comm_, velocity_of(x_.r.data(), b.data(), v.data(), solved), "frix_mpi_solve"))
            return e;
        if (solved && or_all(comm_, vec::all_finite(v.data(), n_) ? 0u : 1u) == 0) x_.v = std::move(v);
        return FRIX_OK;
    }
    // The best iterate's measures, for the driver.
    frix_error restored_best() {
        merit(x_, false);
        if (frix_error e = stopped()) return e;
        error_of(x_);
        return FRIX_OK;
    }
    frix_error rejected(int64_t taken, bool &changed, double &psi) {  // gnsn_ac::RhoCuts
        if (!(changed = cuts_.cut(taken))) return FRIX_OK;
        for (int64_t a = 0; a < nc_; ++a) rho_.rho_n[(size_t)a] *= kRhoCut, rho_.rho_t[(size_t)a] *= kRhoCut;
        psi = merit(x_, true);
        return stopped();
    }
    Monitor::Agree agree() const { return over_ranks(comm_); }
    void log_step(int64_t step, double t, double err, double, double delta) const {
        if (s_.verbosity >= 2)
            log_line(&o_, "global newton (distributed): step %lld t %.3g error %.3e equilibrium %.3e delta %.1e",
                     (long long)step, t, err, equilibrium_, delta);
    }
    // The iterate into the caller's r, u and p.v; its measures.
    Measures hand_over(double *r, double *u) {
        std::copy(x_.r.begin(), x_.r.end(), r);
        std::copy(x_.u.begin(), x_.u.end(), u);
        p_.v = x_.v;
        p_.solved = true;
        return measures_;
    }
    // The measures of the answer r (this rank's reactions) with v = M^-1 (H r + f) (collective):
    // into u, v and out (not finite where M does not factorise).
    frix_error measure_answer(const double *r, double *u, double *v, Measures &out) {
        State st = x_;
        st.r.assign(r, r + m_);
        bool solved = false;
        failed_ = velocity_of(st.r.data(), st.hr.data(), st.v.data(), solved);
        merit(st, false);  // (no product once one failed)
        if (frix_error e = stopped()) return e;
        error_of(st);
        out = measures_;
        if (!solved) out.relative = out.scaled = NAN;
        std::copy(st.u.begin(), st.u.end(), u);
        std::copy(st.v.begin(), st.v.end(), v);
        return FRIX_OK;
    }

   private:
    // v = M^-1 (H r + f) over this rank's dofs, hr receiving H r + f (collective); solved as
    // GlobalSystem::solve_mass's.
    frix_error velocity_of(const double *r, double *hr, double *v, bool &solved) {
        if (frix_error e = sys_.mult_H(r, hr)) return e;
        for (int64_t j = 0; j < n_; ++j) hr[j] += g_.f[(size_t)j];
        return sys_.solve_mass(hr, v, solved);
    }
    // res = M v - H r - f, u = H^T v + w, Phi (A and B when asked); the merit over the ranks.
    double merit(State &st, bool jacobian) {
        if (!failed_) failed_ = sys_.mult_M(st.v.data(), st.mv.data());
        if (!failed_) failed_ = sys_.mult_H(st.r.data(), st.hr.data());
        if (!failed_) failed_ = sys_.mult_Ht(st.v.data(), st.u.data());
        for (int64_t j = 0; j < n_; ++j) st.res[(size_t)j] = st.mv[(size_t)j] - st.hr[(size_t)j] - g_.f[(size_t)j];
        for (int64_t i = 0; i < m_; ++i) st.u[(size_t)i] += p_.w[(size_t)i];
        contacts(st, jacobian);
        double both[2] = {0.0, 0.0};
        for (const double d : st.res) both[0] += d * d;
        for (const double d : st.phi) both[1] += d * d;
        reduce_all(comm_, both, 2, "ss");
        return 0.5 * (both[0] + both[1]);
    }
    void contacts(State &st, bool jacobian) {
        for (int64_t a = 0; a < nc_; ++a)
            nsn::contact_function(nsn::kAlartCurnier, &st.r[3 * (size_t)a], &st.u[3 * (size_t)a], p_.mu[(size_t)a],
                                  rho_.rho_n[(size_t)a], rho_.rho_t[(size_t)a], &st.phi[3 * (size_t)a],
                                  jacobian ? &st.A[9 * (size_t)a] : nullptr, jacobian ? &st.B[9 * (size_t)a] : nullptr);
    }
    // The measures of (r, v) over all ranks, as global_measures takes them on the whole
    // problem (the same weights: RanksWeights), and the error selected_error takes of them.
    double error_of(const State &st) {
        measures_ = measures_over_ranks(comm_, st.r.data(), st.u.data(), p_.mu.data(), weights_.contact, nc_, norm_w_,
                                        weights_.free);
        for (int64_t j = 0; j < n_; ++j) {
            scaled_res_[(size_t)j] = weights_.dof[(size_t)j] * st.res[(size_t)j];
            scaled_hr_[(size_t)j] = weights_.dof[(size_t)j] * st.hr[(size_t)j];
        }
        measures_.global = true;
        const double norm_mv = norm2_all(comm_, st.mv.data(), n_), norm_hr = norm2_all(comm_, st.hr.data(), n_);
        measures_.equilibrium = relative_equilibrium(norm2_all(comm_, st.res.data(), n_), norm_f_, norm_mv, norm_hr);
        measures_.equilibrium_scaled = scaled_equilibrium(norm2_all(comm_, scaled_res_.data(), n_), norm_df_,
                                                          norm2_all(comm_, scaled_hr_.data(), n_));
        equilibrium_ = measures_.equilibrium;
        return selected_error(measures_, s_.measure);
    }
    frix_error stopped() { return mpi::agree(comm_, failed_, "frix_mpi_solve"); }

    frix_mpi_problem &p_;
    const frix_mpi_global_rows &g_;
    GlobalSystem &sys_;
    const MPI_Comm comm_;
    const int64_t n_, nc_, m_;
    RanksRho rho_;
    const newton::Settings &s_;
    const frix_options &o_;
    const RanksWeights weights_;
    const double norm_w_, norm_f_;
    double norm_df_ = 0.0;  // |D f|
    State x_, trial_;
    std::vector<double> rhs_, dx_, Mdv_, Hdr_, Htdv_;
    std::vector<double> scaled_res_, scaled_hr_;  // D (M v - H r - f) and D H r
    frix_error failed_ = FRIX_OK;
    RhoCuts cuts_;
    Measures measures_;
    double equilibrium_ = 0.0;
};

}  // namespace

frix_error run_global_newton(frix_mpi_problem &p, const frix_options &o, const std::vector<double> &warm_start,
                             double *r_io, double *u_out, frix_info &info, const Stopwatch &clock) {
    const MPI_Comm comm = p.ctx->comm;
    const newton::Settings s = newton::settings_from(o, FRIX_SOLVER_NSN_AC);
    if (frix_error e = agree(comm, use_petsc(*p.ctx), "frix_mpi_solve")) return e;
    GlobalSystem sys(p);
    if (frix_error e = agree(comm, sys.setup(), "frix_mpi_solve")) return e;
    RanksRho rho;
    if (frix_error e = lumped_rho(p, s, sys, o, rho)) return e;
    const RanksWeights weights = ranks_weights(p);
    RanksVrSystem system(p, sys, std::move(rho), s, o, weights, r_io);
    // v starts from 0 but from a warm r on a deformable body (the serial gnsn-ac's rule; a
    // distributed M is not shifted).
    const bool w_may_be_regular = 3 * p.total <= p.global->dof_total;
    if (w_may_be_regular && or_all(comm, vec::all_zero(r_io, 3 * p.owned) ? 0u : 1u) != 0)
        if (frix_error e = system.start_from_warm_velocity()) return e;
    // Watched for a runaway past the serial bound (of free_velocity) on this rank's contacts.
    const frix_problem watched = watched_contacts(p, weights);
    const double bound = runaway_bound(weights.free);
    SolveContext ctx = SolveContext::global(watched, o, system.reactions(), u_out, nullptr, info, clock, nullptr);
    ctx.runaway_bound = bound;
    kit::Steps steps{Monitor(ctx)};
    kit::Counters counters;
    kit::RunResult res;
    const kit::Rules rules = rules_of(s.line_search, s.ls_max_iter, w_may_be_regular);
    if (frix_error e = kit::newton(system, steps, rules, counters, res)) return e;
    Measures meas = system.hand_over(r_io, u_out);
    kit::record(info, res, steps, counters);
    const bool broken = !finite_measures(meas) || !vec::all_finite(r_io, 3 * p.owned) ||
                        !vec::all_finite(p.v.data(), p.global->dofs);
    const MeasureAnswer at = [&system](const double *x, double *ux, double *vx, Measures &out) {
        return system.measure_answer(x, ux, vx, out);
    };
    if (frix_error e = fall_back_on_divergence(watched, s.measure, warm_start, broken, bound, at, r_io, u_out,
                                               p.v.data(), meas, info, over_ranks(comm)))
        return e;
    if (!finite_measures(meas))  // the start, r = 0, has no finite velocity either
        return fail(FRIX_ERR_NUMERICAL, "frix_mpi_solve: gnsn-ac diverged, and M^-1 f is not finite: M is singular "
                                        "or too ill-conditioned");
    record_measures(info, meas, s.measure);
    if (info.status == FRIX_STATUS_CONVERGED && !(res.error <= steps.monitor.tolerance()))
        info.status = FRIX_STATUS_STAGNATED;
    if (s.verbosity >= 1)
        log_line(&o, "global newton (distributed): %s after %lld steps", frix_status_string(info.status),
                 (long long)steps.done);
    return FRIX_OK;
}

}  // namespace mpi
}  // namespace frix
