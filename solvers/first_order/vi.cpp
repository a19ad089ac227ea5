// The variational-inequality solvers on the De Saxce formulation: find r in K (the product of
// the Coulomb cones) with <F(r), s - r> >= 0 for all s in K, F(r) = W r + q + mu |u_T| e_N.
//   506 vi-fpp  fixed-point projection  r <- P_K(r - rho F(r))
//   507 vi-eg   extragradient           z = P_K(r - rho F(r)), r <- P_K(r - a rho F(z)), with
//               He's step length a (projection-contraction)
//   508 hp      hyperplane projection   (Solodov-Svaiter) from z = P_K(r - rho F(r))
// The step rho is self-adaptive (Siconos 4.4's Armijo rule with the Khobotov ratio): shrunk
// by tau = 2/3 while rho |F(z) - F(r)| > L |z - r| (L = 0.9), grown by 1/tau when
// rho |F(z) - F(r)| < L_min |z - r| (L_min = 0.3).
//
// Stopping: |r - P_K(r - rho F(r))| is, for rho <= 1, at least rho times the natural-map
// residual |r - P_K(r - F(r))| of the error measure, and at least that residual for rho >= 1;
// so max(1, 1/rho) |z - r| bounds the full error's residual at r without another product.
// That light bound is tested every iteration; when it passes (with the light tolerance
// recalibrated on every full check, as NSGS does) or every kFullCheckPeriod iterations, the
// measures module computes the full error, from u already at hand.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

#include "solvers/kit/first_order.hpp"
#include "src/error_state.hpp"
#include "src/log.hpp"
#include "solvers/entries.hpp"

namespace frix {
namespace vi {

namespace {

constexpr double kTau = 2.0 / 3.0;  // step shrink factor
constexpr double kL = 0.9;          // Lipschitz-type acceptance ratio
constexpr double kLmin = 0.3;       // below this ratio the step grows
constexpr int kMaxBacktracks = 60;  // per iteration; (2/3)^60 ~ 3e-11
constexpr double kSigma = 0.3;      // HP: sufficient-decrease ratio of the line search
constexpr int kMaxHpHalvings = 40;
constexpr double kHpStall = 1e-2;  // HP: a step shorter than this times |r - z| has stalled
constexpr double kGamma = 1.9;     // EG: relaxation of He's step length, in (0, 2)
constexpr int64_t kFullCheckPeriod = 32;

enum class Method { FixedPoint, ExtraGradient, Hyperplane };

const char *name_of(Method m) {
    return m == Method::FixedPoint ? "vi-fpp" : m == Method::ExtraGradient ? "vi-eg" : "hp";
}

inline bool all_finite(const double *x, int64_t n) {
    double s = 0.0;
    for (int64_t i = 0; i < n; ++i) s += x[i] * 0.0;
    return s == 0.0;  // NaN if any entry is NaN or infinite
}

// z = P_K(r - rho F)
void projected_step(const frix_problem &p, const double *r, const double *F, double rho, double *z) {
    const int64_t m = 3 * p.nc;
    for (int64_t i = 0; i < m; ++i) z[i] = r[i] - rho * F[i];
    first_order::project_on_cones(p, z);
}

// z = P_{K n H}(x), H = {z : <a, z - y> <= 0}: z = P_K(x - lambda a) with the lambda >= 0 at
// which phi(lambda) = <a, P_K(x - lambda a) - y> (nonincreasing) vanishes, found by bracketing
// and the Illinois variant of regula falsi. The result is on the feasible side (up to
// rounding; <a, z - y> is formed from the differences, so that it stays accurate when the
// halfspace cuts x off by little, near the solution). work (m) is scratch.
void project_on_cones_and_halfspace(const frix_problem &p, const double *x, const double *a,
                                    const double *y, double *z, double *work) {
    const int64_t m = 3 * p.nc;
    const double b = 0.0;
    auto phi = [&](double lambda, double *out) {
        for (int64_t i = 0; i < m; ++i) out[i] = x[i] - lambda * a[i];
        first_order::project_on_cones(p, out);
        double s = 0.0;
        for (int64_t i = 0; i < m; ++i) s += a[i] * (out[i] - y[i]);
        return s;
    };
    double f_lo = phi(0.0, z);
    if (!(f_lo > 0.0)) return;  // P_K(x) already in H
    const double na2 = vec::dot(a, a, m);
    if (!(na2 > 0.0)) return;
    double lo = 0.0, hi = f_lo / na2, f_hi = phi(hi, work);
    for (int k = 0; k < 200 && f_hi > 0.0; ++k) {
        lo = hi;
        f_lo = f_hi;
        hi *= 2.0;
        f_hi = phi(hi, work);
    }
    int side = 0;
    for (int k = 0; k < 100 && f_hi < 0.0; ++k) {
        if (hi - lo <= 1e-15 * hi || f_lo <= 1e-300 + b) break;
        double mid = (lo * f_hi - hi * f_lo) / (f_hi - f_lo);
        if (!(mid > lo && mid < hi)) mid = 0.5 * (lo + hi);
        const double f_mid = phi(mid, z);
        if (f_mid > 0.0) {
            lo = mid;
            f_lo = f_mid;
            if (side == 1) f_hi *= 0.5;
            side = 1;
        } else {
            hi = mid;
            f_hi = f_mid;
            if (side == -1) f_lo *= 0.5;
            side = -1;
            if (f_mid == 0.0) break;
        }
    }
    phi(hi, z);
}

// One solve: the iterate r (rv, apart from ctx.r), u = W r + q and F = F(r); z, uz, Fz at the
// trial point; y, uy, Fy the extra point of EG and HP.
class Solver {
   public:
    Solver(SolveContext &ctx, Method method);
    // Runs the solve into ctx.r and ctx.info.
    void run();

   private:
    bool trial_step();
    bool next_iterate();
    bool extragradient_step();
    bool hyperplane_step();
    frix_status stop_test(double light);

    const Method method_;
    const char *name_;
    const first_order::Loop L_;
    const frix_problem &p_;
    const int64_t m_;
    const bool adaptive_;
    double wmax_ = 0.0, wmean_ = 0.0, rho_ = 0.0;
    std::vector<double> rv_, u_, F_, z_, uz_, Fz_, y_, uy_, Fy_;
    // The trial's step (rk), |F(z) - F(r)| (a1, not for HP) and |z - r| (a2).
    double rk_ = 0.0, a1_ = 0.0, a2_ = 0.0, tol_light_ = 0.0;
    int64_t it_ = 0, backtracks_ = 0, fallbacks_ = 0;
};

Solver::Solver(SolveContext &ctx, Method method)
    : method_(method),
      name_(name_of(method)),
      L_(ctx, name_),
      p_(ctx.problem),
      m_(L_.m),
      adaptive_(L_.o.i(FRIX_OPT_RHO_ADAPTIVE) != 0),
      rv_(ctx.r, ctx.r + m_), u_(m_), F_(m_), z_(m_), uz_(m_), Fz_(m_) {
    first_order::diagonal_scales(p_, &wmax_, &wmean_);
    rho_ = L_.o.d(FRIX_OPT_RHO) / wmax_;
    if (method != Method::FixedPoint) {
        y_.resize(m_);
        uy_.resize(m_);
        Fy_.resize(m_);
    }
}

void Solver::run() {
    frix_info &info = L_.ctx.info;
    first_order::de_saxce_map(p_, rv_.data(), u_.data(), F_.data());
    // A warm start that already solves the problem.
    if (L_.warm(rv_.data()) && L_.error_ru(rv_.data(), u_.data()) <= L_.tol) {
        info.status = FRIX_STATUS_CONVERGED;
        info.iterations = 0;
        return;
    }
    tol_light_ = L_.tol;
    frix_status status = FRIX_STATUS_NOT_RUN;
    while (status == FRIX_STATUS_NOT_RUN) {
        ++it_;
        const double norm_r = vec::norm(rv_.data(), m_), norm_u = vec::norm(u_.data(), m_);
        if (!trial_step()) {
            status = FRIX_STATUS_DIVERGED;  // r (finite) is kept
            break;
        }
        // The light bound on the full error at r.
        const double light = std::max(1.0, 1.0 / rk_) * a2_ / L_.scale(norm_r, norm_u);
        if (!next_iterate()) {
            status = FRIX_STATUS_DIVERGED;
            break;
        }
        if (adaptive_ && method_ != Method::Hyperplane)
            rho_ = rk_ * a1_ < kLmin * a2_ ? rk_ / kTau : rk_;
        else if (adaptive_)
            rho_ = rk_;
        status = stop_test(light);
    }
    std::copy(rv_.begin(), rv_.end(), L_.ctx.r);
    info.status = status;
    info.iterations = it_;
    if (L_.verbosity >= 1)
        log_line(&L_.o, "%s: %s after %lld iterations (%lld backtracks, %lld projected steps)", name_,
                 frix_status_string(status), (long long)it_, (long long)backtracks_, (long long)fallbacks_);
}

// 1. The projected step z from r, rho shrunk until the Lipschitz-type test passes (HP: one
// step, its test is the line search). False if it is not finite.
bool Solver::trial_step() {
    const double *r = rv_.data();
    rk_ = rho_;
    a1_ = 0.0;
    a2_ = 0.0;
    if (method_ == Method::Hyperplane) {
        projected_step(p_, r, F_.data(), rk_, z_.data());
        a2_ = vec::distance(z_.data(), r, m_);
        return all_finite(z_.data(), m_);
    }
    for (int ls = 0;; ++ls) {
        projected_step(p_, r, F_.data(), rk_, z_.data());
        first_order::de_saxce_map(p_, z_.data(), uz_.data(), Fz_.data());
        a2_ = vec::distance(z_.data(), r, m_);
        a1_ = vec::distance(Fz_.data(), F_.data(), m_);
        const bool finite = std::isfinite(a1_) && std::isfinite(a2_);
        if (!adaptive_ && finite) return true;
        if ((finite && rk_ * a1_ <= kL * a2_) || (finite && a2_ == 0.0) || ls >= kMaxBacktracks) return finite;
        rk_ *= kTau;
        ++backtracks_;
    }
}

// 2. The new iterate, by the method; false if it is not finite (r is then kept).
bool Solver::next_iterate() {
    if (method_ == Method::FixedPoint) {
        std::swap(rv_, z_);
        std::swap(u_, uz_);
        std::swap(F_, Fz_);
        return true;
    }
    if (method_ == Method::ExtraGradient) return extragradient_step();
    return a2_ > 0.0 ? hyperplane_step() : true;
}

// Korpelevich's correction r - rho F(z), scaled by He's optimal step length
// (projection-contraction): gamma <r - z, d> / |d|^2, d = (r - z) - rho (F(r) - F(z)). It
// halves the iterations of the plain correction on the FCLIB problems.
bool Solver::extragradient_step() {
    const double *r = rv_.data();
    double num = 0.0, den = 0.0;
    for (int64_t i = 0; i < m_; ++i) {
        const double d = (r[i] - z_[i]) - rk_ * (F_[i] - Fz_[i]);
        num += (r[i] - z_[i]) * d;
        den += d * d;
    }
    const double alpha = den > 0.0 && num > 0.0 ? kGamma * num / den : 1.0;
    for (int64_t i = 0; i < m_; ++i) y_[i] = r[i] - alpha * rk_ * Fz_[i];
    first_order::project_on_cones(p_, y_.data());
    first_order::de_saxce_map(p_, y_.data(), uy_.data(), Fy_.data());
    if (!all_finite(Fy_.data(), m_)) return false;
    std::swap(rv_, y_);
    std::swap(u_, uy_);
    std::swap(F_, Fy_);
    return true;
}

// Hyperplane projection: y = r - t (r - z) with the largest t = 2^-k such that
// <F(y), r - z> >= sigma / rho |r - z|^2; the halfspace H = {x : <F(y), x - y> <= 0} holds
// the solutions (F monotone) but not r, and r <- P_{K n H}(r).
bool Solver::hyperplane_step() {
    const double *r = rv_.data();
    const double need = kSigma / rk_ * a2_ * a2_;
    double t = 1.0, lhs = 0.0;
    int halvings = 0;
    for (;; ++halvings) {
        for (int64_t i = 0; i < m_; ++i) y_[i] = r[i] - t * (r[i] - z_[i]);
        first_order::de_saxce_map(p_, y_.data(), uy_.data(), Fy_.data());
        double s = 0.0;
        for (int64_t i = 0; i < m_; ++i) s += Fy_[i] * (r[i] - z_[i]);
        lhs = s;
        if ((std::isfinite(lhs) && lhs >= need) || halvings >= kMaxHpHalvings) break;
        t *= 0.5;
    }
    backtracks_ += halvings;
    // Near a solution where F does not vanish (sliding contacts), the cut of the hyperplane
    // shrinks below rounding and the step stalls (at ~1e-9): then the projected step z (kept
    // in uy) is taken instead, which converges locally.
    std::copy(z_.begin(), z_.end(), uy_.begin());
    bool hp_step = lhs > 0.0 && std::isfinite(lhs);
    if (hp_step) {
        project_on_cones_and_halfspace(p_, r, Fy_.data(), y_.data(), z_.data(), uz_.data());
        hp_step = vec::distance(z_.data(), r, m_) >= kHpStall * a2_;
    }
    if (!hp_step) {
        std::copy(uy_.begin(), uy_.end(), z_.begin());
        ++fallbacks_;
    }
    first_order::de_saxce_map(p_, z_.data(), uz_.data(), Fz_.data());
    if (!all_finite(Fz_.data(), m_)) return false;
    std::swap(rv_, z_);
    std::swap(u_, uz_);
    std::swap(F_, Fz_);
    // The step grows when the first trial passed, shrinks after two halvings or more.
    if (adaptive_) {
        if (halvings == 0) rk_ /= kTau;
        else if (halvings >= 2) rk_ *= kTau;
    }
    return true;
}

// 3. Stopping tests, on the full error of the new iterate when the light bound passes its
// tolerance (recalibrated on each full check, as NSGS does), every kFullCheckPeriod
// iterations, or when the step vanished.
frix_status Solver::stop_test(double light) {
    const double *r = rv_.data();
    frix_status status = FRIX_STATUS_NOT_RUN;
    double estimate = light;
    const bool full = light <= tol_light_ || it_ % kFullCheckPeriod == 0 || a2_ == 0.0;
    if (full) {
        const double e = L_.error_ru(r, u_.data());
        estimate = e;
        if (e <= L_.tol) status = FRIX_STATUS_CONVERGED;
        else if (!std::isfinite(e)) status = FRIX_STATUS_DIVERGED;
        else if (a2_ == 0.0) status = FRIX_STATUS_STAGNATED;
        else if (light > 0.0) tol_light_ = light / e * L_.tol;
    }
    if (L_.verbosity >= 2 || (L_.verbosity >= 1 && full))
        log_line(&L_.o, "%s: iteration %lld rho %.3e light %.3e%s%.3e", name_, (long long)it_, rk_ * wmax_, light,
                 full ? " full " : " tol_light ", full ? estimate : tol_light_);
    // The callback sees every iteration, the last one too.
    const frix_status stop = full ? L_.limits_measured(it_, estimate, r) : L_.limits(it_, estimate, r);
    return status == FRIX_STATUS_NOT_RUN ? stop : status;
}

frix_error solve(SolveContext &ctx, Method method) {
    if (!ctx.problem.W || !ctx.problem.W->block)
        return fail(FRIX_ERR_INTERNAL, "%s: W is not stored as 3x3 blocks", name_of(method));
    Solver(ctx, method).run();
    return FRIX_OK;
}

frix_error solve_fpp(SolveContext &ctx) { return solve(ctx, Method::FixedPoint); }
frix_error solve_eg(SolveContext &ctx) { return solve(ctx, Method::ExtraGradient); }
frix_error solve_hp(SolveContext &ctx) { return solve(ctx, Method::Hyperplane); }

const frix_option_key kExtraKeys[] = {FRIX_OPT_RHO, FRIX_OPT_RHO_ADAPTIVE, (frix_option_key)0};

const OptionDefault kDefaults[] = {{FRIX_OPT_MAX_ITER, 1000000},
                                   {FRIX_OPT_RHO, 1.0},
                                   {FRIX_OPT_RHO_ADAPTIVE, 1},
                                   {(frix_option_key)0, 0}};

}  // namespace
}  // namespace vi

const SolverEntry kViFppEntry = {
    FRIX_SOLVER_VI_FPP, "vi-fpp", "FRICTION_3D_VI_FPP",
    "Fixed-point projection on the variational inequality of the De Saxce formulation: "
    "r <- P_K(r - rho F(r)), F(r) = W r + q + mu |u_T| e_N, with the self-adaptive step of "
    "Siconos' VI_FPP (shrunk by 2/3 while rho |dF| > 0.9 |dr|, grown by 3/2 when rho |dF| < "
    "0.3 |dr|). One product with W per iteration (more while the step shrinks), no "
    "factorisation, memory O(nnz): any W, rank-deficient included; linear convergence. Stops on "
    "a light bound of the error taken from the step itself, confirmed by the full error. "
    "Options: rho (initial step, in units of 1 / max_a |W_aa|_2), rho_adaptive (0: keep rho "
    "fixed, Siconos' DSFP).",
    vi::solve_fpp, true, false, vi::kExtraKeys, vi::kDefaults};

const SolverEntry kViEgEntry = {
    FRIX_SOLVER_VI_EG, "vi-eg", "FRICTION_3D_VI_EG",
    "Extragradient on the variational inequality of the De Saxce formulation: the predictor "
    "z = P_K(r - rho F(r)) with the self-adaptive step of vi-fpp, then the corrector "
    "r <- P_K(r - a rho F(z)) with He's step length a = 1.9 <r - z, d> / |d|^2, d = r - z - "
    "rho (F(r) - F(z)) (projection-contraction), which halves the iterations of Korpelevich's "
    "plain corrector. Two products with W per iteration; convergent for monotone F. "
    "(Siconos 4.4's VI_EG takes two "
    "projected steps z = P(r - rho F(r)), r <- P(z - rho F(z)) instead.) Options: rho "
    "(initial step, in units of 1 / max_a |W_aa|_2), rho_adaptive.",
    vi::solve_eg, true, false, vi::kExtraKeys, vi::kDefaults};

const SolverEntry kHpEntry = {
    FRIX_SOLVER_HP, "hp", "FRICTION_3D_HP",
    "Hyperplane projection (Solodov-Svaiter) on the variational inequality of the De Saxce "
    "formulation: from z = P_K(r - rho F(r)), a halving search along r -> z finds y with "
    "<F(y), r - z> >= 0.3 |r - z|^2 / rho; the halfspace {x : <F(y), x - y> <= 0} holds the "
    "solutions (F monotone) but not r, and r moves to the projection on its intersection with "
    "the cones (a scalar root search, no product). Near a solution where F does not vanish "
    "the cut falls below rounding, and the projected step z is taken instead. At least two "
    "products with W per iteration plus the root search. (Siconos' HP projects on the hyperplane, "
    "then on the cones.) Options: rho (in units of 1 / max_a |W_aa|_2), rho_adaptive (grows rho "
    "when the first trial passes, shrinks it after two halvings).",
    vi::solve_hp, true, false, vi::kExtraKeys, vi::kDefaults};

}  // namespace frix
