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

#include "solvers/first_order.hpp"
#include "src/error_state.hpp"
#include "src/log.hpp"

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
    fo::project_on_cones(p, z);
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
        fo::project_on_cones(p, out);
        double s = 0.0;
        for (int64_t i = 0; i < m; ++i) s += a[i] * (out[i] - y[i]);
        return s;
    };
    double f_lo = phi(0.0, z);
    if (!(f_lo > 0.0)) return;  // P_K(x) already in H
    const double na2 = fo::dot(a, a, m);
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

frix_error solve(SolveContext &ctx, Method method) {
    const char *name = name_of(method);
    fo::Loop L(ctx, name);
    const frix_problem &p = L.p;
    if (!p.W || !p.W->block) return fail(FRIX_ERR_INTERNAL, "%s: W is not stored as 3x3 blocks", name);
    const bool adaptive = L.o.i(FRIX_OPT_RHO_ADAPTIVE) != 0;
    double wmax, wmean;
    fo::diagonal_scales(p, &wmax, &wmean);
    double rho = L.o.d(FRIX_OPT_RHO) / wmax;
    const int64_t m = L.m;
    frix_info &info = ctx.info;

    // r, u = W r + q, F = F(r) at the current iterate; z, uz, Fz at the trial point;
    // y, uy, Fy the extra point of EG and HP.
    std::vector<double> rv(ctx.r, ctx.r + m), u(m), F(m), z(m), uz(m), Fz(m), y, uy, Fy;
    if (method != Method::FixedPoint) {
        y.resize(m);
        uy.resize(m);
        Fy.resize(m);
    }
    double *r = rv.data();
    fo::de_saxce_map(p, r, u.data(), F.data());

    // A warm start that already solves the problem.
    if (L.warm(r) && L.error_ru(r, u.data()) <= L.tol) {
        info.status = FRIX_STATUS_CONVERGED;
        info.iterations = 0;
        return FRIX_OK;
    }

    double tol_light = L.tol;
    int64_t it = 0;
    frix_status status = FRIX_STATUS_NOT_RUN;
    int64_t backtracks = 0, fallbacks = 0;
    while (status == FRIX_STATUS_NOT_RUN) {
        ++it;
        const double norm_r = fo::norm(r, m), norm_u = fo::norm(u.data(), m);
        // 1. The projected step from r, rho shrunk until the Lipschitz-type test passes.
        double rk = rho, a1 = 0.0, a2 = 0.0;
        bool finite = false;
        if (method == Method::Hyperplane) {
            projected_step(p, r, F.data(), rk, z.data());
            a2 = fo::distance(z.data(), r, m);
            finite = all_finite(z.data(), m);
        } else {
            for (int ls = 0;; ++ls) {
                projected_step(p, r, F.data(), rk, z.data());
                fo::de_saxce_map(p, z.data(), uz.data(), Fz.data());
                a2 = fo::distance(z.data(), r, m);
                a1 = fo::distance(Fz.data(), F.data(), m);
                finite = std::isfinite(a1) && std::isfinite(a2);
                if (!adaptive && finite) break;
                if ((finite && rk * a1 <= kL * a2) || (finite && a2 == 0.0) || ls >= kMaxBacktracks) break;
                rk *= kTau;
                ++backtracks;
            }
        }
        if (!finite) {
            status = FRIX_STATUS_DIVERGED;  // r (finite) is kept
            break;
        }
        // The light bound on the full error at r.
        const double light = std::max(1.0, 1.0 / rk) * a2 / L.scale(norm_r, norm_u);

        // 2. The new iterate.
        if (method == Method::FixedPoint) {
            std::swap(rv, z);
            std::swap(u, uz);
            std::swap(F, Fz);
        } else if (method == Method::ExtraGradient) {
            // Korpelevich's correction r - rho F(z), scaled by He's optimal step length
            // (projection-contraction): gamma <r - z, d> / |d|^2, d = (r - z) - rho (F(r) -
            // F(z)). It halves the iterations of the plain correction on the FCLIB problems.
            double num = 0.0, den = 0.0;
            for (int64_t i = 0; i < m; ++i) {
                const double d = (r[i] - z[i]) - rk * (F[i] - Fz[i]);
                num += (r[i] - z[i]) * d;
                den += d * d;
            }
            const double alpha = den > 0.0 && num > 0.0 ? kGamma * num / den : 1.0;
            for (int64_t i = 0; i < m; ++i) y[i] = r[i] - alpha * rk * Fz[i];
            fo::project_on_cones(p, y.data());
            fo::de_saxce_map(p, y.data(), uy.data(), Fy.data());
            if (!all_finite(Fy.data(), m)) {
                status = FRIX_STATUS_DIVERGED;
                break;
            }
            std::swap(rv, y);
            std::swap(u, uy);
            std::swap(F, Fy);
        } else if (a2 > 0.0) {
            // Hyperplane projection: y = r - t (r - z) with the largest t = 2^-k such that
            // <F(y), r - z> >= sigma / rho |r - z|^2; the halfspace H = {x : <F(y), x - y> <= 0}
            // holds the solutions (F monotone) but not r, and r <- P_{K n H}(r).
            const double need = kSigma / rk * a2 * a2;
            double t = 1.0, lhs = 0.0;
            int halvings = 0;
            for (;; ++halvings) {
                for (int64_t i = 0; i < m; ++i) y[i] = r[i] - t * (r[i] - z[i]);
                fo::de_saxce_map(p, y.data(), uy.data(), Fy.data());
                double s = 0.0;
                for (int64_t i = 0; i < m; ++i) s += Fy[i] * (r[i] - z[i]);
                lhs = s;
                if ((std::isfinite(lhs) && lhs >= need) || halvings >= kMaxHpHalvings) break;
                t *= 0.5;
            }
            backtracks += halvings;
            // Near a solution where F does not vanish (sliding contacts), the cut of the
            // hyperplane shrinks below rounding and the step stalls (at ~1e-9): then the
            // projected step z (kept in uy) is taken instead, which converges locally.
            std::copy(z.begin(), z.end(), uy.begin());
            bool hp_step = lhs > 0.0 && std::isfinite(lhs);
            if (hp_step) {
                project_on_cones_and_halfspace(p, r, Fy.data(), y.data(), z.data(), uz.data());
                hp_step = fo::distance(z.data(), r, m) >= kHpStall * a2;
            }
            if (!hp_step) {
                std::copy(uy.begin(), uy.end(), z.begin());
                ++fallbacks;
            }
            fo::de_saxce_map(p, z.data(), uz.data(), Fz.data());
            if (!all_finite(Fz.data(), m)) {
                status = FRIX_STATUS_DIVERGED;
                break;
            }
            std::swap(rv, z);
            std::swap(u, uz);
            std::swap(F, Fz);
            // The step grows when the first trial passed, shrinks after two halvings or more.
            if (adaptive) {
                if (halvings == 0) rk /= kTau;
                else if (halvings >= 2) rk *= kTau;
            }
        }
        r = rv.data();
        if (adaptive && method != Method::Hyperplane)
            rho = rk * a1 < kLmin * a2 ? rk / kTau : rk;
        else if (adaptive)
            rho = rk;

        // 3. Stopping tests, on the full error of the new iterate.
        double estimate = light;
        bool checked = false;
        if (light <= tol_light || it % kFullCheckPeriod == 0 || a2 == 0.0) {
            const double e = L.error_ru(r, u.data());
            checked = true;
            estimate = e;
            if (e <= L.tol) status = FRIX_STATUS_CONVERGED;
            else if (!std::isfinite(e)) status = FRIX_STATUS_DIVERGED;
            else if (a2 == 0.0) status = FRIX_STATUS_STAGNATED;
            else if (light > 0.0) tol_light = light / e * L.tol;  // as NSGS recalibrates
        }
        if (L.verbosity >= 2 || (L.verbosity >= 1 && checked))
            log_line(&L.o, "%s: iteration %lld rho %.3e light %.3e%s%.3e", name,
                     (long long)it, rk * wmax, light, checked ? " full " : " tol_light ",
                     checked ? estimate : tol_light);
        const frix_status stop = L.limits(it, estimate, r);
        if (status == FRIX_STATUS_NOT_RUN) status = stop;
    }
    std::copy(r, r + m, ctx.r);
    info.status = status;
    info.iterations = it;
    if (L.verbosity >= 1)
        log_line(&L.o, "%s: %s after %lld iterations (%lld backtracks, %lld projected steps)",
                 name, frix_status_string(status), (long long)it, (long long)backtracks,
                 (long long)fallbacks);
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
