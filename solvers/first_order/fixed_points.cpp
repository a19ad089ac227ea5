// Fixed points on a convex inner problem, solved by NSGS sweeps (nsgs::Workspace::sweep_with)
// with a local step of their own:
//   503 tfp   Tresca fixed point: the friction threshold s_a = mu_a r_N,a of the last outer
//             iterate is fixed and the Tresca problem (r_N >= 0 _|_ u_N >= 0, r_T in the disk
//             of radius s_a, -u_T in its normal cone) is solved; s is updated, and so on.
//   516 aclm  Acary-Cadoux-Lemarechal-Malick fixed point: s_a = |u_T,a| of the last outer
//             iterate is fixed and the second-order cone complementarity problem
//             K ∋ r _|_ W r + q + mu s e_N ∈ K* (the optimality conditions of a convex
//             second-order-cone QP when W is symmetric) is solved; s is updated, and so on.
// At the fixed point the inner solution solves the Coulomb problem. The inner tolerance is
// tied to the outer error (inner_tolerance_ratio times it): early outer iterations are cheap,
// the last ones exact enough not to slow the outer convergence.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "solvers/kit/first_order.hpp"
#include "solvers/kit/local3x3.hpp"
#include "solvers/kit/sweeps.hpp"
#include "src/coulomb.hpp"
#include "src/error_state.hpp"
#include "src/log.hpp"
#include "src/matrix.hpp"
#include "src/vec.hpp"
#include "solvers/entries.hpp"

namespace frix {
namespace fixed_points {

namespace {

using local::Contact;
using local::Outcome;

using vec::gemv3;
using vec::norm2d;

// The r_T with (A + nu I) r_T = -g, nu >= 0, |r_T| = s, for the 2x2 matrix A = [a b; c d]
// (row-major) with det A > 0 and trace A > 0, so that det(A + nu I) > 0 for every nu >= 0:
// the smallest such nu, by Newton on 1/|x(nu)| - 1/s (exact for symmetric A, where it is
// the trust-region equation) safeguarded by a bracket. false if |A^-1 g| <= s (the
// unconstrained solution is inside the disk) or A does not qualify.
bool circle_solve(double a, double b, double c, double d, double g1, double g2, double s,
                  double *x) {
    const double det0 = a * d - b * c, tr = a + d;
    const double scale = std::fabs(a) + std::fabs(b) + std::fabs(c) + std::fabs(d);
    if (!(det0 > 1e-14 * scale * scale) || !(tr > 0.0)) return false;
    // x(nu) = -(A + nu I)^-1 g and w = (A + nu I)^-1 x.
    auto solve = [&](double nu, double *xv, double *w) {
        const double aa = a + nu, dd = d + nu, det = aa * dd - b * c;
        xv[0] = -(dd * g1 - b * g2) / det;
        xv[1] = -(aa * g2 - c * g1) / det;
        if (w) {
            w[0] = (dd * xv[0] - b * xv[1]) / det;
            w[1] = (aa * xv[1] - c * xv[0]) / det;
        }
        return norm2d(xv[0], xv[1]);
    };
    double xv[2], w[2];
    if (!(solve(0.0, xv, nullptr) > s)) return false;
    double lo = 0.0, hi = norm2d(g1, g2) / s + scale;
    for (int k = 0; k < 200 && solve(hi, xv, nullptr) > s; ++k) {
        lo = hi;
        hi *= 2.0;
    }
    double nu = lo;
    for (int k = 0; k < 100; ++k) {
        const double n = solve(nu, xv, w);
        if (std::fabs(n - s) <= 1e-15 * s) break;
        if (n > s) lo = nu;
        else hi = nu;
        const double xw = xv[0] * w[0] + xv[1] * w[1];  // = -x' d x / d nu
        double next = xw > 0.0 ? nu + (n - s) / s * n * n / xw : 0.5 * (lo + hi);
        if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
        if (hi - lo <= 1e-16 * hi) break;
        nu = next;
    }
    const double n = solve(nu, xv, nullptr);
    if (!(n > 0.0) || !std::isfinite(n)) return false;
    x[0] = xv[0] * (s / n);
    x[1] = xv[1] * (s / n);
    return true;
}

// The exact solution of one contact's Tresca problem, u = W r + q, r_N >= 0 _|_ u_N >= 0,
// r_T in the disk of radius s, -u_T in its normal cone (for symmetric positive definite W_aa,
// the minimiser of 1/2 r'W r + q'r over that set), by the four cases of the conditions:
// interior (u = 0); on the circle with u_N = 0 (a trust-region-like equation on the Schur
// complement); r_N = 0 inside; r_N = 0 on the circle. The first case that holds is taken.
// false if none does (W_aa far from positive definite, or rounding at a case boundary).
bool tresca_exact(const Contact &c, const double *q, double s, double *r, Outcome &out) {
    const double *W = c.W;
    const double wnn = W[0];
    if (!(wnn > 0.0)) return false;
    if (!(s > 0.0)) {  // no friction: a one-dimensional complementarity problem
        r[0] = std::max(0.0, -q[0] / wnn);
        r[1] = r[2] = 0.0;
        out = r[0] > 0.0 ? Outcome::Stick : Outcome::TakeOff;
        return true;
    }
    const double tol_in = 1e-14;
    // Interior: u = 0.
    if (c.has_inverse) {
        double x[3];
        gemv3(c.Winv, q, x);
        if (-x[0] >= 0.0 && norm2d(x[1], x[2]) <= s * (1.0 + tol_in)) {
            r[0] = -x[0];
            r[1] = -x[1];
            r[2] = -x[2];
            out = Outcome::Stick;
            return true;
        }
    }
    // On the circle with u_N = 0: r_N = -(q_N + w_NT r_T) / W_NN, the Schur complement
    // S = W_TT - w_TN w_NT / W_NN and g = q_T - w_TN q_N / W_NN.
    const double wn1 = W[3], wn2 = W[6];  // row N, tangential columns
    {
        const double w1n = W[1], w2n = W[2];  // column N, tangential rows
        const double a = W[4] - w1n * wn1 / wnn, b = W[7] - w1n * wn2 / wnn;
        const double c2 = W[5] - w2n * wn1 / wnn, d = W[8] - w2n * wn2 / wnn;
        const double g1 = q[1] - w1n * q[0] / wnn, g2 = q[2] - w2n * q[0] / wnn;
        double t[2];
        if (circle_solve(a, b, c2, d, g1, g2, s, t)) {
            const double rn = -(q[0] + wn1 * t[0] + wn2 * t[1]) / wnn;
            if (rn >= 0.0) {
                r[0] = rn;
                r[1] = t[0];
                r[2] = t[1];
                out = Outcome::Slide;
                return true;
            }
        }
    }
    // r_N = 0, u_N >= 0: inside the disk, then on the circle.
    const double a = W[4], b = W[7], c2 = W[5], d = W[8];
    const double det = a * d - b * c2;
    if (det > 1e-14 * (std::fabs(a * d) + std::fabs(b * c2))) {
        const double t1 = -(d * q[1] - b * q[2]) / det, t2 = -(a * q[2] - c2 * q[1]) / det;
        if (norm2d(t1, t2) <= s * (1.0 + tol_in) && q[0] + wn1 * t1 + wn2 * t2 >= 0.0) {
            r[0] = 0.0;
            r[1] = t1;
            r[2] = t2;
            out = Outcome::TakeOff;
            return true;
        }
    }
    double t[2];
    if (circle_solve(a, b, c2, d, q[1], q[2], s, t) && q[0] + wn1 * t[0] + wn2 * t[1] >= 0.0) {
        r[0] = 0.0;
        r[1] = t[0];
        r[2] = t[1];
        out = Outcome::TakeOff;
        return true;
    }
    return false;
}

// Projected iterations r <- P_C(r - rho (W r + q)) on one contact with Siconos' self-adaptive
// rho (kept in c.rho across sweeps), until the natural-map residual |r - P_C(r - u)| is below
// p.tol relative to max(|q|, |r|, |u|). C is the disk {r_N >= 0, |r_T| <= s} (s >= 0) or, for
// s < 0, the Coulomb cone of c.mu. The inner problems' map is linear: no De Saxce term.
Outcome projected(Contact &c, const double *q, double s, double *r, const local::Params &p) {
    auto project = [&](double *x) {
        if (s >= 0.0) coulomb::project_on_disk(x, s);
        else coulomb::project_on_cone(x, c.mu);
    };
    auto residual_ok = [&](const double *x, const double *u) {
        double z[3] = {x[0] - u[0], x[1] - u[1], x[2] - u[2]};
        project(z);
        const double res = norm2d(norm2d(x[0] - z[0], x[1] - z[1]), x[2] - z[2]);
        const double scale = std::max({norm2d(norm2d(q[0], q[1]), q[2]), norm2d(norm2d(x[0], x[1]), x[2]),
                                       norm2d(norm2d(u[0], u[1]), u[2]), 1e-300});
        return res <= p.tol * scale;
    };
    const double start[3] = {r[0], r[1], r[2]};
    project(r);
    double u[3];
    gemv3(c.W, r, u);
    for (int i = 0; i < 3; ++i) u[i] += q[i];
    if (residual_ok(r, u)) return Outcome::Iterated;
    double rho = c.rho > 0.0 ? c.rho : c.rho0;
    const double rho_min = 1e-12 * c.rho0, rho_max = 1e12 * c.rho0;
    for (int it = 0; it < p.max_iter; ++it) {
        double rn[3], un[3], ndr = 0.0, ndu = 0.0;
        for (int ls = 0; ls < 20; ++ls) {
            for (int i = 0; i < 3; ++i) rn[i] = r[i] - rho * u[i];
            project(rn);
            gemv3(c.W, rn, un);
            for (int i = 0; i < 3; ++i) un[i] += q[i];
            ndr = norm2d(norm2d(rn[0] - r[0], rn[1] - r[1]), rn[2] - r[2]);
            ndu = norm2d(norm2d(un[0] - u[0], un[1] - u[1]), un[2] - u[2]);
            if (rho * ndu <= 0.9 * ndr || rho <= rho_min) break;
            rho = std::max(rho * (2.0 / 3.0), rho_min);
        }
        if (!std::isfinite(rn[0] + rn[1] + rn[2] + un[0] + un[1] + un[2])) {
            std::copy(start, start + 3, r);
            c.rho = c.rho0;
            return Outcome::NotConverged;
        }
        std::copy(rn, rn + 3, r);
        std::copy(un, un + 3, u);
        if (residual_ok(r, u)) {
            c.rho = rho;
            return Outcome::Iterated;
        }
        if (rho * ndu < 0.3 * ndr) rho = std::min(rho * 1.5, rho_max);
    }
    c.rho = rho;
    return Outcome::NotConverged;
}

// The boundary solution of one contact's second-order cone complementarity problem
// K ∋ r _|_ u = W r + q ∈ K*: r = t a(th), a = (1, mu cos th, mu sin th), t > 0, and
// u = l b(th), b = (mu, -cos th, -sin th), l >= 0 (the ray of K* orthogonal to a). The three
// vectors W a, b and q are then coplanar: G(th) = det[W a(th), b(th), q] = 0, a trigonometric
// polynomial of degree 2 (at most four roots), and (t, l) solve W a t - b l = -q.
local::TrigPoly2 cone_angle_equation(const double *W, const double *q, double mu) {
    // D(x, y) = det[x, y, q] for columns x of W and unit vectors y.
    auto det = [q](const double *x, int e) {
        // det[x, e_k, q] = x . (e_k x q)
        const double ex[3] = {e == 0 ? 1.0 : 0.0, e == 1 ? 1.0 : 0.0, e == 2 ? 1.0 : 0.0};
        const double c[3] = {ex[1] * q[2] - ex[2] * q[1], ex[2] * q[0] - ex[0] * q[2],
                             ex[0] * q[1] - ex[1] * q[0]};
        return x[0] * c[0] + x[1] * c[1] + x[2] * c[2];
    };
    const double *w0 = W, *w1 = W + 3, *w2 = W + 6;
    const double d11 = det(w1, 1), d22 = det(w2, 2), d12 = det(w1, 2), d21 = det(w2, 1);
    local::TrigPoly2 g;
    g.A0 = mu * det(w0, 0) - 0.5 * mu * (d11 + d22);
    g.A1 = -det(w0, 1) + mu * mu * det(w1, 0);
    g.B1 = -det(w0, 2) + mu * mu * det(w2, 0);
    g.A2 = -0.5 * mu * (d11 - d22);
    g.B2 = -0.5 * mu * (d12 + d21);
    g.set_scale();
    return g;
}

// (t, l) of the root direction (c, s), if t > 0 and l >= 0: r = t a.
bool cone_reaction(const double *W, const double *q, double mu, double c, double s, double *r) {
    const double a[3] = {1.0, mu * c, mu * s}, b[3] = {mu, -c, -s};
    double wa[3];
    gemv3(W, a, wa);
    // Least squares on [wa, -b] (t, l) = -q (consistent at a root).
    const double m11 = wa[0] * wa[0] + wa[1] * wa[1] + wa[2] * wa[2];
    const double m12 = -(wa[0] * b[0] + wa[1] * b[1] + wa[2] * b[2]);
    const double m22 = b[0] * b[0] + b[1] * b[1] + b[2] * b[2];
    const double r1 = -(wa[0] * q[0] + wa[1] * q[1] + wa[2] * q[2]);
    const double r2 = b[0] * q[0] + b[1] * q[1] + b[2] * q[2];
    const double det = m11 * m22 - m12 * m12;
    if (!(det > 1e-14 * m11 * m22)) return false;
    const double t = (r1 * m22 - m12 * r2) / det, l = (m11 * r2 - m12 * r1) / det;
    if (!(t > 0.0) || !(l >= 0.0) || !std::isfinite(t)) return false;
    r[0] = t;
    r[1] = t * a[1];
    r[2] = t * a[2];
    return true;
}

// The boundary solution nearest the unit direction (hc, hs): Newton on G from it, else every
// root bracketed on a 32-point grid. dir receives the root's direction.
bool cone_slide(const double *W, const double *q, double mu, double hc, double hs, double *r,
                double *dir) {
    return local::nearest_valid_root(cone_angle_equation(W, q, mu), W, q, mu, cone_reaction, hc, hs,
                                     r, dir);
}

// One contact of the second-order cone complementarity problem K ∋ r _|_ W r + q ∈ K*
// (q already holds the mu s e_N shift): exact take-off (q ∈ K*), stick (-W^-1 q ∈ K) and
// boundary (root of the angle equation, from the last direction dir) cases; projected
// iterations where no valid root exists.
Outcome cone_contact(Contact &c, const double *q, double *r, double *dir, const local::Params &p) {
    if (q[0] >= c.mu * norm2d(q[1], q[2])) {
        r[0] = r[1] = r[2] = 0.0;
        return Outcome::TakeOff;
    }
    if (c.has_inverse) {
        double x[3];
        gemv3(c.Winv, q, x);
        if (-x[0] >= 0.0 && norm2d(x[1], x[2]) <= -c.mu * x[0]) {
            r[0] = -x[0];
            r[1] = -x[1];
            r[2] = -x[2];
            return Outcome::Stick;
        }
    }
    if (c.degenerate) return Outcome::NoSolution;
    if (c.mu == 0.0) {  // K is the normal half-line
        if (!(c.W[0] > 0.0)) return projected(c, q, -1.0, r, p);
        r[0] = std::max(0.0, -q[0] / c.W[0]);
        r[1] = r[2] = 0.0;
        return Outcome::Slide;
    }
    double hc = dir[0], hs = dir[1];
    if (!(hc * hc + hs * hs > 0.5)) {
        const double n = norm2d(r[1], r[2]);
        if (n > 0.0) {
            hc = r[1] / n;
            hs = r[2] / n;
        } else {
            const double nq = norm2d(q[1], q[2]);
            hc = nq > 0.0 ? -q[1] / nq : 1.0;
            hs = nq > 0.0 ? -q[2] / nq : 0.0;
        }
    }
    if (cone_slide(c.W, q, c.mu, hc, hs, r, dir)) return Outcome::Slide;
    return projected(c, q, -1.0, r, p);
}

enum class Kind { Tresca, Cadoux };

// Bounds of the relaxation factor of the threshold update.
constexpr double kMinDamping = 1.0 / 64.0;
constexpr double kMaxDamping = 1.0;

// One solve: the outer iterate r (ctx.r) with u = W r + q, the thresholds s, and the NSGS
// sweeps of the inner problems.
class Solver {
   public:
    Solver(SolveContext &ctx, Kind kind);
    // Runs the solve into ctx.r and ctx.info.
    void run();

   private:
    void update_thresholds(int64_t outer);
    int64_t inner_sweeps(double inner_tol);
    double inner_error(const double *x);
    nsgs::SweepStats sweep();
    static nsgs::Settings sweep_settings(const local::Params &lp) {
        nsgs::Settings gs;
        gs.local = lp;
        return gs;
    }

    const Kind kind_;
    const char *name_;
    const first_order::Loop L_;
    const frix_problem &p_;
    const int64_t nc_, m_, inner_max_;
    const double ratio_;
    local::Params lp_;
    nsgs::Workspace ws_;
    std::vector<double> u_, s_, ui_;
    std::vector<double> dirs_;   // aclm: each contact's last sliding direction
    std::vector<double> delta_;  // T(s) - s of the last outer iteration
    double theta_ = 1.0, err_ = 0.0;
    int64_t sweeps_ = 0;
};

local::Params local_params(const frix_options &o) {
    local::Params lp;
    lp.tol = o.d(FRIX_OPT_LOCAL_TOLERANCE);
    lp.max_iter = (int)o.i(FRIX_OPT_LOCAL_MAX_ITER);
    return lp;
}

Solver::Solver(SolveContext &ctx, Kind kind)
    : kind_(kind),
      name_(kind == Kind::Tresca ? "tfp" : "aclm"),
      L_(ctx, name_),
      p_(ctx.problem),
      nc_(ctx.problem.nc),
      m_(L_.m),
      inner_max_(L_.o.i(FRIX_OPT_INNER_MAX_ITER)),
      ratio_(L_.o.d(FRIX_OPT_INNER_TOLERANCE_RATIO)),
      lp_(local_params(L_.o)),
      ws_(p_, sweep_settings(lp_)),
      u_(m_), s_(nc_), ui_(m_), dirs_(kind == Kind::Cadoux ? 2 * nc_ : 0, 0.0), delta_(nc_, 0.0) {}

void Solver::run() {
    double *r = L_.ctx.r;
    frix_info &info = L_.ctx.info;
    err_ = L_.error(r, u_.data());
    if (L_.warm(r) && err_ <= L_.tol) {
        info.status = FRIX_STATUS_CONVERGED;
        info.iterations = 0;
        return;
    }
    int64_t outer = 0;
    frix_status status = FRIX_STATUS_NOT_RUN;
    while (status == FRIX_STATUS_NOT_RUN) {
        ++outer;
        update_thresholds(outer);
        const double inner_tol = ratio_ * err_;
        const int64_t k = inner_sweeps(inner_tol);
        err_ = L_.error(r, u_.data());
        if (L_.verbosity >= 1)
            log_line(&L_.o, "%s: outer %lld, %lld sweeps (inner tolerance %.2e), error %.3e", name_, (long long)outer,
                     (long long)k, inner_tol, err_);
        // (Sweeps cut short by the time limit stop here too: the clock only goes on.)
        status = L_.verdict(outer, err_, r);
    }
    info.status = status;
    info.iterations = outer;
    info.inner_iterations = sweeps_;
    if (L_.verbosity >= 1)
        log_line(&L_.o, "%s: %s after %lld outer iterations (%lld sweeps)", name_, frix_status_string(status),
                 (long long)outer, (long long)sweeps_);
}

// The threshold of this outer iteration, from the last iterate (u = W r + q is up to date:
// the last error computed it): s <- s + theta (T(s) - s), with theta from Aitken's dynamic
// relaxation (Irons-Tuck): 1 while the update converges by itself, about 1/2 where it
// oscillates with period two (the Capsules problems, on which the plain update of Siconos'
// TFP never settles).
void Solver::update_thresholds(int64_t outer) {
    const double *r = L_.ctx.r;
    double num = 0.0, den = 0.0;
    for (int64_t a = 0; a < nc_; ++a) {
        const double *ra = r + 3 * a, *ua = u_.data() + 3 * a;
        const double target = kind_ == Kind::Tresca ? p_.mu[a] * std::max(0.0, ra[0]) : vec::norm2d(ua[1], ua[2]);
        const double d = target - s_[a];
        num += delta_[a] * (d - delta_[a]);
        den += (d - delta_[a]) * (d - delta_[a]);
        delta_[a] = d;
    }
    if (outer > 1 && den > 0.0 && std::isfinite(num / den))
        theta_ = std::clamp(-theta_ * num / den, kMinDamping, kMaxDamping);
    for (int64_t a = 0; a < nc_; ++a) s_[a] = outer == 1 ? s_[a] + delta_[a] : s_[a] + theta_ * delta_[a];
}

// NSGS sweeps on the inner problem until its own error is below inner_tol (the light error
// first, its tolerance recalibrated on each inner full check, as NSGS does), inner_max_
// sweeps, or the time limit; returns the sweeps made.
int64_t Solver::inner_sweeps(double inner_tol) {
    double *r = L_.ctx.r;
    double light_tol = inner_tol;
    int64_t k = 0;
    while (k < inner_max_) {
        const nsgs::SweepStats st = sweep();
        ++sweeps_;
        ++k;
        if (!std::isfinite(st.r2)) break;
        const double light = st.r2 > 0.0 ? std::sqrt(st.dr2 / st.r2) : std::sqrt(st.dr2);
        if (L_.verbosity >= 2)
            log_line(&L_.o, "%s:   sweep %lld light %.3e unsolved %lld rejected %lld", name_, (long long)k, light,
                     (long long)st.unsolved, (long long)st.rejected);
        if (light <= light_tol) {
            const double e_in = inner_error(r);
            if (e_in <= inner_tol) break;
            light_tol = light > 0.0 ? light / e_in * inner_tol : light_tol;
            if (st.dr2 == 0.0) break;  // a fixed point of the sweep: nothing more to gain
        }
        if (L_.out_of_time()) break;
    }
    return k;
}

// One sweep with the local step of the inner problem: the exact Tresca solution, else
// projected steps on the disk; or the exact cone solution on the shifted cone.
nsgs::SweepStats Solver::sweep() {
    double *r = L_.ctx.r;
    if (kind_ == Kind::Tresca)
        return ws_.sweep_with(r, [this](int64_t a, Contact &c, const double *ql, double *ra) {
            Outcome out;
            if (tresca_exact(c, ql, s_[a], ra, out)) return out;
            return projected(c, ql, s_[a], ra, lp_);
        });
    return ws_.sweep_with(r, [this](int64_t a, Contact &c, const double *ql, double *ra) {
        const double shifted[3] = {ql[0] + c.mu * s_[a], ql[1], ql[2]};
        return cone_contact(c, shifted, ra, dirs_.data() + 2 * a, lp_);
    });
}

// The inner problem's own error: its natural-map residual relative to max(|q|, |r|, |u|),
// with the Tresca disk or the shifted cone (u + mu s e_N) of this outer iteration.
double Solver::inner_error(const double *x) {
    matrix_gemv(*p_.W, 1.0, x, 0.0, ui_.data());
    double sum = 0.0, nr = 0.0, nu = 0.0;
    for (int64_t a = 0; a < nc_; ++a) {
        const double *xa = x + 3 * a;
        double *ua = ui_.data() + 3 * a;
        for (int i = 0; i < 3; ++i) ua[i] += p_.q[3 * a + i];
        double z[3] = {xa[0] - ua[0], xa[1] - ua[1], xa[2] - ua[2]};
        if (kind_ == Kind::Tresca) {
            coulomb::project_on_disk(z, s_[a]);
        } else {
            z[0] -= p_.mu[a] * s_[a];
            coulomb::project_on_cone(z, p_.mu[a]);
        }
        for (int i = 0; i < 3; ++i) {
            sum += (xa[i] - z[i]) * (xa[i] - z[i]);
            nr += xa[i] * xa[i];
            nu += ua[i] * ua[i];
        }
    }
    return std::sqrt(sum) / L_.scale(std::sqrt(nr), std::sqrt(nu));
}

frix_error solve(SolveContext &ctx, Kind kind) {
    if (!ctx.problem.W || !ctx.problem.W->block)
        return fail(FRIX_ERR_INTERNAL, "%s: W is not stored as 3x3 blocks", kind == Kind::Tresca ? "tfp" : "aclm");
    Solver(ctx, kind).run();
    return FRIX_OK;
}

frix_error solve_tfp(SolveContext &ctx) { return solve(ctx, Kind::Tresca); }
frix_error solve_aclm(SolveContext &ctx) { return solve(ctx, Kind::Cadoux); }

const frix_option_key kExtraKeys[] = {FRIX_OPT_INNER_MAX_ITER, FRIX_OPT_INNER_TOLERANCE_RATIO,
                                      FRIX_OPT_LOCAL_TOLERANCE, FRIX_OPT_LOCAL_MAX_ITER,
                                      (frix_option_key)0};

const OptionDefault kDefaults[] = {{FRIX_OPT_MAX_ITER, 10000},
                                   {FRIX_OPT_INNER_MAX_ITER, 100},
                                   {FRIX_OPT_INNER_TOLERANCE_RATIO, 0.1},
                                   {FRIX_OPT_LOCAL_TOLERANCE, 1e-12},
                                   {FRIX_OPT_LOCAL_MAX_ITER, 50},
                                   {(frix_option_key)0, 0}};

}  // namespace
}  // namespace fixed_points

const SolverEntry kTfpEntry = {
    FRIX_SOLVER_TFP, "tfp", "FRICTION_3D_TFP",
    "Tresca fixed point: the friction threshold s_a = mu_a r_N,a is frozen, the Tresca "
    "problem (normal half-lines times tangential disks of radius s; a convex QP when W is "
    "symmetric) is solved by NSGS sweeps, and s moves towards mu r_N, until it stops moving. "
    "The one-contact Tresca problem is solved exactly (interior, or on the circle through a "
    "one-dimensional equation on the Schur complement, for any W_aa with a positive definite "
    "tangential part), by projected steps with a self-adaptive step where that fails. The "
    "update of s is relaxed by Aitken's factor (Irons-Tuck, in [1/64, 1]): it damps the "
    "oscillation of the plain update. The inner tolerance is inner_tolerance_ratio times the "
    "outer error (light "
    "error confirmed by the inner problem's own residual). Iterations count outer steps; "
    "FRIX_INFO_INNER_ITERATIONS the sweeps. Options: inner_max_iter (sweeps per outer step, "
    "default "
    "100), inner_tolerance_ratio (0.1), local_tolerance and local_max_iter (the fallback "
    "projected steps).",
    fixed_points::solve_tfp, true, false, fixed_points::kExtraKeys, fixed_points::kDefaults};

const SolverEntry kAclmEntry = {
    FRIX_SOLVER_ACLM, "aclm", "FRICTION_3D_ACLMFP",
    "Acary-Cadoux-Lemarechal-Malick fixed point: s_a = |u_T,a| is frozen and the "
    "second-order cone complementarity problem K contains r _|_ W r + q + mu s e_N in K* (the "
    "optimality conditions of a convex second-order-cone QP when W is symmetric) is solved "
    "by NSGS sweeps, then s moves towards |u_T| (Aitken-relaxed, as in tfp), until it stops "
    "moving. The one-contact cone problem is solved exactly: take-off, stick, or the "
    "boundary solution through the root of a degree-2 trigonometric equation in the sliding "
    "angle (Newton from the last angle, all roots bracketed otherwise); projected steps with "
    "a self-adaptive step only where no valid root exists. The inner tolerance is "
    "inner_tolerance_ratio times the outer error. Iterations count outer steps; "
    "FRIX_INFO_INNER_ITERATIONS the sweeps. Options: inner_max_iter (default 100), "
    "inner_tolerance_ratio (0.1), local_tolerance and local_max_iter (the fallback projected "
    "steps).",
    fixed_points::solve_aclm, true, false, fixed_points::kExtraKeys, fixed_points::kDefaults};

}  // namespace frix
