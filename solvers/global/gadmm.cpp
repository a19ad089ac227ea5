// Solver 613 (gadmm): ADMM on the global problem itself (Siconos' GFC3D_ADMM), W never formed.
// With s = mu |u_T| e_N (the De Saxce term, updated every iteration) the problem is
//   min_v 1/2 v'M v - f'v  subject to  xi = H^T v + w + s,  xi in K*,
// r in K the multiplier of the splitting. One iteration, with (r^, xi^) Nesterov's
// extrapolations of (r, xi), restarted whenever the combined residual does not decrease:
//   (M + rho H H^T) v = f + H (r^ + rho (xi^ - w - s))
//   g = H^T v + w + s,  r = P_K(r^ - rho g),  xi = g - (r^ - r) / rho  (= P_K*(g - r^ / rho))
// so that M v = f + H r + rho H (xi - xi^): the equilibrium residual is the dual residual (to
// the residual the linear solve leaves; the stopping test measures equilibrium itself).
// M + rho H H^T is symmetric positive definite (M is): CHOLMOD factorises it once per value
// of rho, one symbolic analysis for all; each iteration solves from the last v, through a
// single-precision copy of a supernodal factor (MassPlusContacts::solve_near: half the bytes
// read, and the error it leaves a share of the step, not of v). rho, in units of the mean
// normal entry of W_aa over a few sampled contacts, follows the residual balance (the ratio of
// the relative primal and dual residuals), checked every kBalancePeriod iterations and changed
// only by a factor >= 5, and only where the iterations left at the rate since the last change
// cost more than the factorisation the change takes.
#include <algorithm>
#include <cmath>
#include <vector>

#include "solvers/kit/first_order.hpp"
#include "solvers/kit/global_newton.hpp"
#include "solvers/kit/mass_plus_contacts.hpp"
#include "src/coulomb.hpp"
#include "src/error_state.hpp"
#include "src/log.hpp"
#include "src/matrix.hpp"
#include "src/measures.hpp"
#include "src/monitor.hpp"
#include "src/reduction.hpp"
#include "solvers/entries.hpp"

namespace frix {
namespace gadmm {

namespace {

constexpr int kScaleSamples = 8;          // contacts whose W_aa set rho's unit
constexpr int64_t kBalancePeriod = 25;
constexpr double kBalanceFactor = 5.0;    // rho changes only by this factor or more
constexpr double kRhoMin = 1e-6, kRhoMax = 1e6;  // in units of 1 / scale
constexpr int64_t kFullCheckPeriod = 32;
// While the light error is within the tolerance, a full check at least every kCheckGap
// iterations, whatever the recalibrated light tolerance says: ADMM's light error oscillates,
// so waiting for it to pass a tolerance lowered by a failed check runs past iterates that meet
// the tolerance (a check is two products, and M's solves only where M is factorised).
constexpr int64_t kCheckGap = 2;

using vec::dot;

// The sums of squares over the contacts one iteration's residuals come from (update_r_and_xi).
struct Residuals {
    double prim2 = 0.0, dual_xi2 = 0.0, comb = 0.0, g2 = 0.0, r2 = 0.0;
};

// One solve: the iterates (r, xi) and v, the system M + rho H H^T and the steps of the iteration.
class Solver {
   public:
    // before: the system's factorisation counters before the solve prepared it.
    Solver(SolveContext &ctx, KeptMassPlusContacts &kept, const linalg::FactorStats &before);
    // Runs the solve into ctx.info, (r, u, v); fails only as the linear solves do.
    frix_error run();

   private:
    bool factor();
    void start_xi();
    frix_error update_v();
    Residuals update_r_and_xi();
    frix_status stop_test(double light, double prim, double dual);
    frix_status balance_rho(double prim, double dual);
    bool change_pays(double light) const;
    void finish(frix_status status);

    SolveContext &ctx_;
    const frix_problem &p_;
    const frix_options &o_;
    const Monitor monitor_;
    const double tol_;
    const int64_t verbosity_, measure_;
    const bool adaptive_;
    const int64_t n_, nc_, m_;
    double *r_, *u_, *v_;
    KeptMassPlusContacts &kept_;
    MassPlusContacts &system_;
    const linalg::FactorStats before_;
    const double scale_;
    double rho_;
    std::vector<double> S_;  // the contacts' shifts rho I of the factorised system
    std::vector<double> shift_, xi_, rhs_, Hx_, dxi_, Hdxi_, Hr_, kv_, work_;
    first_order::RestartedNesterov momentum_;
    double equilibrium_ = 0.0, err_ = 0.0, norm_f_ = 0.0, tol_light_ = 0.0;
    double light_after_change_ = NAN;  // the light error of the first iteration on the current rho
    int64_t it_ = 0, changes_ = 0, since_change_ = 0, last_full_ = 0;
    // The system's counts of solves through the single-precision copy, and of those finished in
    // double, when the solve started.
    const int64_t single_solves_before_, finished_in_double_before_;
};

Solver::Solver(SolveContext &ctx, KeptMassPlusContacts &kept, const linalg::FactorStats &before)
    : ctx_(ctx),
      p_(ctx.problem),
      o_(ctx.options),
      monitor_(ctx),
      tol_(monitor_.tolerance()),
      verbosity_(o_.i(FRIX_OPT_VERBOSITY)),
      measure_(o_.i(FRIX_OPT_ERROR_MEASURE)),
      adaptive_(o_.i(FRIX_OPT_RHO_ADAPTIVE) != 0),
      n_(p_.n),
      nc_(p_.nc),
      m_(3 * p_.nc),
      r_(ctx.r),
      u_(ctx.u),
      v_(ctx.v),
      kept_(kept),
      system_(kept.system),
      before_(before),
      scale_(kept.scale),
      rho_(std::isfinite(kept.factored_rho) ? kept.factored_rho : o_.d(FRIX_OPT_RHO) / kept.scale),
      S_(9 * nc_, 0.0),
      shift_(m_, 0.0), xi_(m_), rhs_(n_), Hx_(m_), dxi_(m_), Hdxi_(n_), Hr_(n_), kv_(n_), work_(n_),
      momentum_(o_.i(FRIX_OPT_ACCELERATION) != 0, m_),
      single_solves_before_(system_.single_solves()),
      finished_in_double_before_(system_.solves_finished_in_double()) {}

// Factorises M + rho H H^T unless the system holds that rho already; false if that failed.
// Then keeps the factor's single-precision copy for the iterations' solves, where it can.
bool Solver::factor() {
    if (rho_ != kept_.factored_rho) {
        kept_.factored_rho = NAN;
        for (int64_t a = 0; a < nc_; ++a) S_[9 * a] = S_[9 * a + 4] = S_[9 * a + 8] = rho_;
        if (system_.factor(S_.data(), monitor_.budget()) != FRIX_OK) {
            clear_error();
            return false;
        }
        kept_.factored_rho = rho_;
    }
    system_.keep_single_copy(monitor_.memory_budget());
    return true;
}

// The start: u from the driver's v (M v = H r + f), xi = P_K*(u + s) = x + P_K(-x).
void Solver::start_xi() {
    de_saxce_shift(p_, u_, shift_.data());
    for (int64_t a = 0; a < nc_; ++a) {
        double *x = &xi_[3 * a], neg[3];
        for (int i = 0; i < 3; ++i) x[i] = u_[3 * a + i] + shift_[3 * a + i], neg[i] = -x[i];
        coulomb::project_on_cone(neg, p_.mu[a]);
        for (int i = 0; i < 3; ++i) x[i] += neg[i];
    }
}

frix_error Solver::run() {
    err_ = global_error(p_, measure_, r_, v_, u_, &equilibrium_);
    start_xi();
    momentum_.reset(r_, xi_.data());
    norm_f_ = std::sqrt(dot(p_.f, p_.f, n_));
    frix_status status = err_ <= tol_ ? FRIX_STATUS_CONVERGED : FRIX_STATUS_NOT_RUN;
    if (status == FRIX_STATUS_NOT_RUN && !factor())
        status = system_.refused() ? system_.refused() : FRIX_STATUS_NUMERICAL_FAILURE;
    tol_light_ = tol_;
    while (status == FRIX_STATUS_NOT_RUN) {
        ++it_;
        ++since_change_;
        if (frix_error e = update_v()) return e;
        const Residuals res = update_r_and_xi();
        if (!std::isfinite(res.prim2 + res.dual_xi2 + res.g2 + res.r2)) {
            status = FRIX_STATUS_DIVERGED;
            break;
        }
        // Relative residuals: primal against |g|, dual (the equilibrium residual rho H dxi)
        // against max(|f|, |H r|), as the equilibrium measure.
        if (m_ > 0) {
            matrix_gemv(*p_.H, rho_, dxi_.data(), 0.0, Hdxi_.data());
            matrix_gemv(*p_.H, 1.0, r_, 0.0, Hr_.data());
        }
        const double prim = std::sqrt(res.prim2) / std::max(std::sqrt(res.g2), 1e-300);
        const double dual = std::sqrt(dot(Hdxi_.data(), Hdxi_.data(), n_)) /
                            std::max({norm_f_, std::sqrt(dot(Hr_.data(), Hr_.data(), n_)), 1e-300});
        momentum_.advance(res.comb, r_, xi_.data());
        if (since_change_ == 1) light_after_change_ = std::max(prim, dual);
        status = stop_test(std::max(prim, dual), prim, dual);
        if (status == FRIX_STATUS_NOT_RUN) status = balance_rho(prim, dual);
    }
    finish(status);
    return FRIX_OK;
}

// (M + rho H H^T) v = f + H (r^ + rho (xi^ - w - s)), M's skew part K, if any, at the
// previous v (exact at the fixed point); then u = H^T v (w added in update_r_and_xi).
frix_error Solver::update_v() {
    const double *rh = momentum_.x_hat(), *xih = momentum_.y_hat();
    for (int64_t i = 0; i < m_; ++i) Hx_[i] = rh[i] + rho_ * (xih[i] - p_.w[i] - shift_[i]);
    std::copy(p_.f, p_.f + n_, rhs_.begin());
    if (m_ > 0) matrix_gemv(*p_.H, 1.0, Hx_.data(), 1.0, rhs_.data());
    if (system_.skewed()) {
        matrix_skew_gemv(*p_.M, v_, kv_.data(), work_.data());
        for (int64_t j = 0; j < n_; ++j) rhs_[j] -= kv_[j];
    }
    if (frix_error e = system_.solve_near(rhs_.data(), v_)) return e;
    if (m_ > 0) matrix_gemv_transposed(*p_.H, 1.0, v_, 0.0, u_);
    return FRIX_OK;
}

// g = u + s, r = P_K(r^ - rho g), xi = g - (r^ - r) / rho, then s from the new u.
Residuals Solver::update_r_and_xi() {
    const double *rh = momentum_.x_hat(), *xih = momentum_.y_hat();
    Residuals res;
    for (int64_t a = 0; a < nc_; ++a) {
        double g[3];
        for (int i = 0; i < 3; ++i) {
            const int64_t k = 3 * a + i;
            u_[k] += p_.w[k];
            g[i] = u_[k] + shift_[k];
            r_[k] = rh[k] - rho_ * g[i];
        }
        coulomb::project_on_cone(&r_[3 * a], p_.mu[a]);
        for (int i = 0; i < 3; ++i) {
            const int64_t k = 3 * a + i;
            xi_[k] = g[i] - (rh[k] - r_[k]) / rho_;
            dxi_[k] = xi_[k] - xih[k];
            res.prim2 += (g[i] - xi_[k]) * (g[i] - xi_[k]);
            res.dual_xi2 += dxi_[k] * dxi_[k];
            res.comb += (r_[k] - rh[k]) * (r_[k] - rh[k]) / rho_ + rho_ * dxi_[k] * dxi_[k];
            res.g2 += g[i] * g[i];
            res.r2 += r_[k] * r_[k];
        }
    }
    de_saxce_shift(p_, u_, shift_.data());
    return res;
}

// Stopping: the full error (with v recovered where that helps), when the light error passes
// its tolerance, recalibrated on each full check, every kCheckGap iterations while it is within
// the tolerance itself, or every kFullCheckPeriod iterations.
frix_status Solver::stop_test(double light, double prim, double dual) {
    const bool full = light <= tol_light_ || (light <= tol_ && it_ - last_full_ >= kCheckGap) ||
                      it_ % kFullCheckPeriod == 0;
    if (full) {
        last_full_ = it_;
        err_ = global_error_or_recovered(p_, ctx_.mass, measure_, tol_, r_, v_, u_, &equilibrium_);
        if (!(err_ <= tol_) && std::isfinite(err_) && light > 0.0) tol_light_ = std::min(tol_, light / err_ * tol_);
    }
    if (verbosity_ >= 2 || (verbosity_ >= 1 && full))
        log_line(&o_, "gadmm: iteration %lld rho %.3e primal %.3e dual %.3e%s%.3e", (long long)it_, rho_ * scale_, prim,
                 dual, full ? " full " : " tol_light ", full ? err_ : tol_light_);
    return full ? monitor_.verdict(it_, err_) : monitor_.limits(it_, light);
}

// Residual balancing: rho <- rho sqrt(primal / dual) when that changes it 5-fold and the
// change pays (change_pays).
// FRIX_STATUS_NOT_RUN to go on.
frix_status Solver::balance_rho(double prim, double dual) {
    if (!adaptive_ || since_change_ < kBalancePeriod || !(dual > 0.0) || !(prim > 0.0)) return FRIX_STATUS_NOT_RUN;
    const double target = std::clamp(rho_ * std::sqrt(prim / dual), kRhoMin / scale_, kRhoMax / scale_);
    if (!(target > kBalanceFactor * rho_ || target * kBalanceFactor < rho_)) return FRIX_STATUS_NOT_RUN;
    if (!change_pays(std::max(prim, dual))) return FRIX_STATUS_NOT_RUN;
    rho_ = target;
    momentum_.reset(r_, xi_.data());
    since_change_ = 0;
    ++changes_;
    if (factor()) return FRIX_STATUS_NOT_RUN;
    return system_.refused() ? system_.refused() : FRIX_STATUS_NUMERICAL_FAILURE;
}

// Whether a change of rho may pay for its factorisation: it saves at most the iterations left,
// predicted from the light error's rate since the last change, which must cost more (counted
// in flops, so that the path does not depend on the machine). Near the tolerance a change
// costs more than it can save.
bool Solver::change_pays(double light) const {
    if (!(light > tol_light_)) return false;
    const double gained = std::log(light_after_change_ / light);  // over since_change_ - 1 iterations
    if (!(gained > 0.0)) return true;  // not converging on this rho
    const double left = std::log(light / tol_light_) / gained * (double)(since_change_ - 1);
    const linalg::FactorCost cost = system_.cost();
    const double iteration = 4.0 * cost.factor_entries + 8.0 * system_.contact_entries();
    return left * iteration > cost.flops;
}

// The last (r, v): r is in K, and v the velocity of the last linear solve.
void Solver::finish(frix_status status) {
    frix_info &info = ctx_.info;
    info.status = status;
    info.iterations = it_;
    Monitor::record_factorizations(info, system_.stats() - before_);
    if (verbosity_ >= 1)
        log_line(&o_, "gadmm: %s after %lld iterations (%lld rho changes, %lld restarts; %lld solves in single "
                 "precision, %lld of them finished in double)", frix_status_string(status), (long long)it_,
                 (long long)changes_, (long long)momentum_.restarts(),
                 (long long)(system_.single_solves() - single_solves_before_),
                 (long long)(system_.solves_finished_in_double() - finished_in_double_before_));
}

// A persistent solver's next step with the same M and H starts from the last step's
// factorisation and its rho: a time-stepping host pays the factorisation once.
frix_error solve(SolveContext &ctx) {
    Kept<KeptMassPlusContacts> kept(ctx.cache, FRIX_SOLVER_GLOBAL_ADMM);
    linalg::FactorStats before;
    const ContactBlocks blocks = ContactBlocks::kMultiplesOfIdentity;  // rho I
    if (frix_error e = prepare_mass_plus_contacts(ctx, *kept, "gadmm", kScaleSamples, blocks, &before)) return e;
    kept.keep();
    return Solver(ctx, *kept, before).run();
}

const frix_option_key kExtraKeys[] = {FRIX_OPT_RHO, FRIX_OPT_RHO_ADAPTIVE, FRIX_OPT_ACCELERATION, (frix_option_key)0};
const OptionDefault kDefaults[] = {{FRIX_OPT_MAX_ITER, 100000},
                                   {FRIX_OPT_RHO, 1.0},
                                   {FRIX_OPT_RHO_ADAPTIVE, 1},
                                   {FRIX_OPT_ACCELERATION, 1},
                                   {(frix_option_key)0, 0}};

}  // namespace
}  // namespace gadmm

const SolverEntry kGadmmEntry = {
    FRIX_SOLVER_GLOBAL_ADMM, "gadmm", "GLOBAL_FRICTION_3D_ADMM",
    "ADMM on the global problem itself (Siconos' GFC3D_ADMM): the splitting xi = H^T v + w + s, "
    "xi in the dual cones, r the multiplier; one solve with M + rho H H^T and one projection per "
    "iteration, the De Saxce term s = mu |u_T| e_N updated every iteration, Nesterov "
    "acceleration with restart, rho balanced between the relative primal and dual residuals "
    "(checked every 25 iterations, changed only 5-fold or more, and only where the iterations left "
    "at the rate so far cost more than the factorisation the change takes). "
    "M + rho H H^T is factorised by CHOLMOD (one symbolic analysis per solve; a persistent solver "
    "keeps the factorisation, and its rho, while M and H stay); where its factor is supernodal, "
    "each iteration solves from the last v through a single-precision copy of it, the step checked "
    "and finished in double where it falls short; W = H^T M^-1 H is "
    "never formed: for deformable bodies whose W would be dense and too large. Converged means "
    "both the error and the equilibrium residual are below the tolerance. Global problems with "
    "a symmetric positive definite M only. Options: rho (initial penalty, in units of the mean "
    "normal entry of W_aa over 8 sampled contacts), rho_adaptive (0: keep rho), acceleration (0: plain "
    "ADMM).",
    gadmm::solve, false, true, gadmm::kExtraKeys, gadmm::kDefaults};

}  // namespace frix
