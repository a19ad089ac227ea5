// Solver 901 (gnsn-al): the augmented Lagrangian method on the global problem, each of its
// steps a minimisation in v alone by semismooth Newton, whose linear systems are
// M + rho H J H^T: symmetric positive definite, factorised by CHOLMOD in one pattern (one
// symbolic analysis per solve). W = H^T M^-1 H is never formed.
//
// With s = mu |u_T| e_N held (the De Saxce term, updated after every outer step) the problem
// is  min_v 1/2 v'M v - f'v  subject to  g(v) = H^T v + w + s in K*, r in K the multiplier of
// the constraint. The augmented Lagrangian step from r_k:
//   v_k+1 = argmin phi(v),  phi(v) = 1/2 v'M v - f'v + 1/(2 rho) |P_K(r_k - rho g(v))|^2,
//   r_k+1 = P_K(r_k - rho g(v_k+1)).
// phi is convex, its gradient M v - f - H P_K(r_k - rho g(v)) (zero: M v = H r_k+1 + f, the
// equilibrium), its generalized Hessian M + rho H J H^T with J = dP_K block-diagonal, symmetric
// and 0 <= J <= I: Newton with Armijo's line search converges from any v, and every system is
// at least as well posed as M. A fixed point r = P_K(r - rho g) is r in K, g in K*, r'g = 0.
// A persistent solver keeps the pattern and its analysis while M and H stay.
// rho grows while the outer steps gain little: the outer rate improves with rho, and Newton
// refactorises every step anyway, so a new rho costs nothing more.
#include <algorithm>
#include <cmath>
#include <vector>

#include "solvers/kit/first_order.hpp"
#include "solvers/kit/global_newton.hpp"
#include "solvers/kit/line_search.hpp"
#include "solvers/kit/mass_plus_contacts.hpp"
#include "solvers/kit/nsn_functions.hpp"
#include "src/error_state.hpp"
#include "src/log.hpp"
#include "src/matrix.hpp"
#include "src/measures.hpp"
#include "src/monitor.hpp"
#include "src/reduction.hpp"
#include "solvers/entries.hpp"

namespace frix {
namespace gnsn_al {

namespace {

constexpr int kScaleSamples = 8;      // contacts whose W_aa set rho's unit
constexpr int kLineSearchSteps = 40;  // halvings of the Newton step at most
constexpr int kInnerSteps = 30;       // Newton steps per outer step at most
// An outer step's minimisation ends when the gradient (the equilibrium residual) is below
// this share of the force the step moved, |H (r_k+1 - r_k)|: the next multiplier is then as
// good as an exact minimiser's to first order.
constexpr double kInnerShare = 0.1;
constexpr double kSlowOuter = 0.5;    // an outer step gaining less than this ...
constexpr double kRhoGrowth = 5.0;    // ... multiplies rho by this
constexpr double kRhoMax = 1e8;       // rho at most, in units of 1 / scale
constexpr int kStallOuter = 8;        // outer steps without halving the best error: stagnated

using vec::dot;

// One solve: the outer steps (multiplier updates) and the inner Newton on v that each makes.
class AlRun {
   public:
    AlRun(SolveContext &ctx, MassPlusContacts &system, double scale)
        : ctx_(ctx), p_(ctx.problem), monitor_(ctx), system_(system), n_(p_.n), nc_(p_.nc), m_(3 * p_.nc),
          r_(ctx.r), u_(ctx.u), v_(ctx.v), tol_(monitor_.tolerance()), measure_(ctx.options.i(FRIX_OPT_ERROR_MEASURE)),
          verbosity_(ctx.options.i(FRIX_OPT_VERBOSITY)),
          scale_(scale), rho_(ctx.options.d(FRIX_OPT_RHO) / scale), rk_(r_, r_ + m_), shift_(m_, 0.0), y_(m_), z_(m_),
          J_(9 * nc_), S_(9 * nc_), Mv_(n_), Hz_(n_), grad_(n_), d_(n_), Md_(n_), Htd_(m_), ut_(m_), zt_(m_),
          best_r_(r_, r_ + m_), best_v_(v_, v_ + n_), fk_(p_.f, p_.f + n_), Kd_(n_), skew_work_(n_) {
        norm_f_ = std::sqrt(dot(p_.f, p_.f, n_));
    }

    // The outer steps until the status; then the best iterate into ctx and the counters into info.
    frix_error run() {
        velocities(v_, u_);
        de_saxce_shift(p_, u_, shift_.data());
        double err = global_error(p_, measure_, r_, v_, u_, &equilibrium_), best_err = err, ref_err = err;
        int since_progress = 0;
        frix_status status = FRIX_STATUS_NOT_RUN;
        while ((status = monitor_.verdict_after_report(outer_, err, false)) == FRIX_STATUS_NOT_RUN) {
            if (frix_error e = minimise(status)) return e;  // the outer step: minimise phi from the current v
            if (status != FRIX_STATUS_NOT_RUN) break;
            ++outer_;
            const double previous = err;
            std::copy(z_.begin(), z_.end(), r_);
            err = global_error_or_recovered(p_, ctx_.mass, measure_, tol_, r_, v_, u_, &equilibrium_);
            if (verbosity_ >= 2)
                log_line(&ctx_.options, "gnsn-al: outer %lld rho %.3e newton %lld error %.3e equilibrium %.3e",
                         (long long)outer_, rho_ * scale_, (long long)newton_steps_, err, equilibrium_);
            if (err < best_err) {
                best_err = err;
                std::copy(r_, r_ + m_, best_r_.begin());
                std::copy(v_, v_ + n_, best_v_.begin());
            }
            if (monitor_.report(outer_, err)) {  // the callback's stop, at once
                status = FRIX_STATUS_STOPPED_BY_CALLBACK;
                break;
            }
            if (err <= tol_) continue;
            if (best_err < 0.5 * ref_err) {
                ref_err = best_err;
                since_progress = 0;
            } else if (++since_progress >= kStallOuter) {
                status = FRIX_STATUS_STAGNATED;
                break;
            }
            if (err > kSlowOuter * previous && rho_ < kRhoMax / scale_) rho_ = std::min(rho_ * kRhoGrowth, kRhoMax / scale_);
            std::copy(r_, r_ + m_, rk_.begin());
            de_saxce_shift(p_, u_, shift_.data());
        }
        if (!(err <= best_err)) {  // also when the last iterate is not finite
            std::copy(best_r_.begin(), best_r_.end(), r_);
            std::copy(best_v_.begin(), best_v_.end(), v_);
        }
        ctx_.info.status = status;
        ctx_.info.iterations = outer_;
        ctx_.info.newton_iterations = newton_steps_;
        ctx_.info.line_search_steps = ls_steps_;
        if (verbosity_ >= 1)
            log_line(&ctx_.options, "gnsn-al: %s after %lld outer steps, %lld Newton steps (rho %.3g / scale)",
                     frix_status_string(status), (long long)outer_, (long long)newton_steps_, rho_ * scale_);
        return FRIX_OK;
    }

   private:
    // out = (M + M^T) / 2 x: M x, less M's skew part where M is not exactly symmetric.
    void symmetric_mass(const double *x, double *out) {
        matrix_gemv(*p_.M, 1.0, x, 0.0, out);
        if (!system_.skewed()) return;
        matrix_skew_gemv(*p_.M, x, Kd_.data(), skew_work_.data());
        for (int64_t j = 0; j < n_; ++j) out[j] -= Kd_[j];
    }
    // u = H^T v + w, the De Saxce term from it.
    void velocities(const double *vv, double *uu) const {
        if (m_ > 0) matrix_gemv_transposed(*p_.H, 1.0, vv, 0.0, uu);
        for (int64_t i = 0; i < m_; ++i) uu[i] += p_.w[i];
    }
    // z = P_K(r_k - rho (uu + s)) into zz, with J's blocks when asked; returns |z|^2.
    double multiplier(const double *uu, double *zz, bool jacobian) {
        double sq = 0.0;
        for (int64_t a = 0; a < nc_; ++a) {
            double yy[3];
            for (int i = 0; i < 3; ++i) yy[i] = rk_[3 * a + i] - rho_ * (uu[3 * a + i] + shift_[3 * a + i]);
            double Ja[9];
            nsn::project_with_jacobian(yy, p_.mu[a], zz + 3 * a, Ja);
            if (jacobian) std::copy(Ja, Ja + 9, &J_[9 * a]);
            for (int i = 0; i < 3; ++i) sq += zz[3 * a + i] * zz[3 * a + i];
        }
        return sq;
    }

    // Newton on phi from v; status: what ends the solve inside (the time limit, a factorisation).
    frix_error minimise(frix_status &status) {
        velocities(v_, u_);
        // M's skew part K, if any, at this step's start: the step minimises phi with M's
        // symmetric part and f - K v_k, which at a fixed point is M v = f + H r.
        if (system_.skewed()) {
            matrix_skew_gemv(*p_.M, v_, fk_.data(), Kd_.data());
            for (int64_t j = 0; j < n_; ++j) fk_[j] = p_.f[j] - fk_[j];
        }
        symmetric_mass(v_, Mv_.data());
        double zsq = multiplier(u_, z_.data(), true);
        for (int step = 0; step < kInnerSteps && !minimised(); ++step) {
            if ((status = monitor_.limits_after_report(outer_, false)) != FRIX_STATUS_NOT_RUN) break;
            for (int64_t k = 0; k < 9 * nc_; ++k) S_[k] = rho_ * J_[k];
            if (system_.factor(S_.data(), monitor_.budget()) != FRIX_OK) {
                status = system_.refused() ? system_.refused() : FRIX_STATUS_NUMERICAL_FAILURE;
                clear_error();
                break;
            }
            if (frix_error e = system_.solve(grad_.data(), d_.data())) return e;
            for (int64_t j = 0; j < n_; ++j) d_[j] = -d_[j];
            ++newton_steps_;
            if (!move(zsq)) break;
        }
        return FRIX_OK;
    }
    // The gradient M v - f - H z (the equilibrium residual) is below kInnerShare of the force
    // this step moved, |H (z - r_k)|, or the tolerance.
    bool minimised() {
        if (m_ > 0) matrix_gemv(*p_.H, 1.0, z_.data(), 0.0, Hz_.data());
        for (int64_t j = 0; j < n_; ++j) grad_[j] = Mv_[j] - fk_[j] - Hz_[j];
        for (int64_t i = 0; i < m_; ++i) y_[i] = z_[i] - rk_[i];
        std::vector<double> &moved = d_;  // scratch until the Newton direction is solved
        if (m_ > 0) matrix_gemv(*p_.H, 1.0, y_.data(), 0.0, moved.data());
        const double gnorm = std::sqrt(dot(grad_.data(), grad_.data(), n_));
        const double eq_scale =
            std::max({norm_f_, std::sqrt(dot(Mv_.data(), Mv_.data(), n_)), std::sqrt(dot(Hz_.data(), Hz_.data(), n_))});
        return gnorm <= std::max(0.5 * tol_ * eq_scale, kInnerShare * std::sqrt(dot(moved.data(), moved.data(), n_)));
    }
    // v along the Newton direction d, by Armijo's backtracking on phi (from products computed
    // once); false where d does not descend or no step is accepted (the minimiser to rounding).
    bool move(double &zsq) {
        symmetric_mass(d_.data(), Md_.data());
        if (m_ > 0) matrix_gemv_transposed(*p_.H, 1.0, d_.data(), 0.0, Htd_.data());
        const double vMv = dot(v_, Mv_.data(), n_), dMv = dot(d_.data(), Mv_.data(), n_);
        const double dMd = dot(d_.data(), Md_.data(), n_);
        const double fv = dot(fk_.data(), v_, n_), fd = dot(fk_.data(), d_.data(), n_);
        const double phi0 = 0.5 * vMv - fv + zsq / (2.0 * rho_);
        const double slope = dot(grad_.data(), d_.data(), n_);
        if (!(slope < 0.0)) return false;
        const auto phi_along = [&](double t) {  // (ut and zt: the last trial's)
            for (int64_t i = 0; i < m_; ++i) ut_[i] = u_[i] + t * Htd_[i];
            const double zsq_t = multiplier(ut_.data(), zt_.data(), false);
            return 0.5 * (vMv + 2.0 * t * dMv + t * t * dMd) - fv - t * fd + zsq_t / (2.0 * rho_);
        };
        const kit::SearchResult search =
            kit::backtrack(phi_along, phi0, kit::Decrease{phi0, kit::kArmijoSigma, slope}, kLineSearchSteps, ls_steps_);
        if (!search.accepted) return false;
        for (int64_t j = 0; j < n_; ++j) {
            v_[j] += search.t * d_[j];
            Mv_[j] += search.t * Md_[j];
        }
        for (int64_t i = 0; i < m_; ++i) u_[i] = ut_[i];
        zsq = multiplier(u_, z_.data(), true);
        return true;
    }

    SolveContext &ctx_;
    const frix_problem &p_;
    const Monitor monitor_;
    MassPlusContacts &system_;
    const int64_t n_, nc_, m_;
    double *r_, *u_, *v_;
    const double tol_;
    const int64_t measure_, verbosity_;
    const double scale_;
    double rho_, norm_f_ = 0.0, equilibrium_ = 0.0;
    int64_t outer_ = 0, newton_steps_ = 0, ls_steps_ = 0;
    std::vector<double> rk_, shift_, y_, z_, J_, S_, Mv_, Hz_, grad_, d_, Md_, Htd_, ut_, zt_;
    std::vector<double> best_r_, best_v_, fk_, Kd_, skew_work_;
};

frix_error solve(SolveContext &ctx) {
    // A persistent solver's next step with the same M and H keeps the pattern, its symbolic
    // analysis and rho's unit.
    Kept<KeptMassPlusContacts> kept(ctx.cache, FRIX_SOLVER_GLOBAL_AL_NEWTON);
    linalg::FactorStats before;
    const ContactBlocks blocks = ContactBlocks::kAny;  // rho J, J the projection's Jacobian
    if (frix_error e = prepare_mass_plus_contacts(ctx, *kept, "gnsn-al", kScaleSamples, blocks, &before)) return e;
    kept.keep();
    AlRun run(ctx, kept->system, kept->scale);
    if (frix_error e = run.run()) return e;
    Monitor::record_factorizations(ctx.info, kept->system.stats() - before);
    return FRIX_OK;
}

const frix_option_key kExtraKeys[] = {FRIX_OPT_RHO, (frix_option_key)0};
const OptionDefault kDefaults[] = {{FRIX_OPT_MAX_ITER, 500}, {FRIX_OPT_RHO, 10.0}, {(frix_option_key)0, 0}};

}  // namespace
}  // namespace gnsn_al

const SolverEntry kGnsnAlEntry = {
    FRIX_SOLVER_GLOBAL_AL_NEWTON, "gnsn-al", nullptr,
    "Augmented Lagrangian method on the global problem itself, each outer step a minimisation "
    "in v by semismooth Newton with Armijo's line search: its linear systems are M + rho H J H^T "
    "(J the Jacobian of the projection on the cones), symmetric positive definite, factorised "
    "by CHOLMOD in one fixed pattern (one symbolic analysis per solve). W = H^T M^-1 H is never "
    "formed: for deformable bodies whose W would be dense and too large. The De Saxce term is "
    "updated after every outer step; rho, in units of the mean normal entry of W_aa over 8 sampled contacts (from M's "
    "factorisation), grows 5-fold while an outer step does not halve the "
    "error. Converged means both the error and the equilibrium residual are below the "
    "tolerance. Global problems with a symmetric positive definite M only. Options: rho "
    "(the initial penalty, in units of 1 / that mean; default 10); max_iter counts outer steps.",
    gnsn_al::solve, false, true, gnsn_al::kExtraKeys, gnsn_al::kDefaults};

}  // namespace frix
