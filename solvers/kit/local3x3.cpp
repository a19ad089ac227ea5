#include "solvers/kit/local3x3.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>

#include "solvers/kit/local_newton.hpp"
#include "solvers/kit/nsn_functions.hpp"
#include "src/coulomb.hpp"
#include "src/vec.hpp"

namespace frix::local {

namespace {

using vec::gemv3;
using vec::norm2d;
using vec::norm3;

// Largest eigenvalue of a symmetric 3x3 matrix (a00 a11 a22 a01 a02 a12), closed form.
double sym3_max_eigenvalue(double a00, double a11, double a22, double a01, double a02, double a12) {
    const double p1 = a01 * a01 + a02 * a02 + a12 * a12;
    const double m = (a00 + a11 + a22) / 3.0;
    const double d0 = a00 - m, d1 = a11 - m, d2 = a22 - m;
    const double p2 = d0 * d0 + d1 * d1 + d2 * d2 + 2.0 * p1;
    if (!(p2 > 0.0)) return m;
    const double p = std::sqrt(p2 / 6.0);
    const double b00 = d0 / p, b11 = d1 / p, b22 = d2 / p;
    const double b01 = a01 / p, b02 = a02 / p, b12 = a12 / p;
    const double det = b00 * (b11 * b22 - b12 * b12) - b01 * (b01 * b22 - b12 * b02) +
                       b02 * (b01 * b12 - b11 * b02);
    const double half = std::clamp(det / 2.0, -1.0, 1.0);
    return m + 2.0 * p * std::cos(std::acos(half) / 3.0);
}

// |W|_2 = sqrt(lambda_max(W^T W)).
double spectral_norm(const double *W) {
    auto col_dot = [W](int i, int j) {
        return W[3 * i] * W[3 * j] + W[3 * i + 1] * W[3 * j + 1] + W[3 * i + 2] * W[3 * j + 2];
    };
    const double l = sym3_max_eigenvalue(col_dot(0, 0), col_dot(1, 1), col_dot(2, 2), col_dot(0, 1),
                                         col_dot(0, 2), col_dot(1, 2));
    return std::sqrt(std::max(l, 0.0));
}

// F(r) = W r + q + mu|u_T| e_N, with u = W r + q.
inline void de_saxce_map(const Contact &c, const double *q, const double *r, double *u, double *F) {
    gemv3(c.W, r, u);
    u[0] += q[0];
    u[1] += q[1];
    u[2] += q[2];
    F[0] = u[0] + c.mu * norm2d(u[1], u[2]);
    F[1] = u[1];
    F[2] = u[2];
}

// The sliding solution r = r_N (1, mu t), |t| = 1, needs u_N = 0, i.e. r_N = -q_N / a_N with
// a = W (1, mu t), and u_T = r_N a_T + q_T anti-parallel to t. Multiplied by a_N > 0, the
// parallelism condition t_perp . u_T = 0 reads G(theta) = 0 with G a trigonometric
// polynomial of degree 2 (so at most 4 roots): G = A0 + A1 cos + B1 sin + A2 cos2 + B2 sin2.
TrigPoly2 sliding_angle_equation(const double *W, const double *q, double mu) {
    const double wnn = W[0], p1 = W[3], p2 = W[6], v1 = W[1], v2 = W[2];
    const double m11 = W[4], m12 = W[7], m21 = W[5], m22 = W[8];
    const double qn = q[0], q1 = q[1], q2 = q[2];
    TrigPoly2 g;
    g.A0 = 0.5 * mu * (p1 * q2 - p2 * q1) - 0.5 * qn * mu * (m21 - m12);
    g.A1 = wnn * q2 - qn * v2;
    g.B1 = -wnn * q1 + qn * v1;
    g.A2 = 0.5 * mu * (p1 * q2 + p2 * q1) - 0.5 * qn * mu * (m21 + m12);
    g.B2 = 0.5 * mu * (p2 * q2 - p1 * q1) - 0.5 * qn * mu * (m22 - m11);
    g.set_scale();
    return g;
}

// Rotates the unit vector (c, s) by atan(d): the Newton step d in angle, without sin/cos
// (atan(d) = d + O(d^3), so quadratic convergence is kept).
inline void rotate(double &c, double &s, double d) {
    // Late Newton steps are tiny: a series for 1/sqrt(1 + d^2), exact to O(d^6), spares the
    // sqrt and the division on the critical path.
    const double d2 = d * d;
    const double inv = d2 < 1e-6 ? 1.0 - d2 * (0.5 - 0.375 * d2) : 1.0 / std::sqrt(1.0 + d2);
    const double c2 = (c - s * d) * inv, s2 = (s + c * d) * inv;
    c = c2;
    s = s2;
}

bool newton_angle(const TrigPoly2 &g, double &c, double &s) {
    const double tiny = 1e-15 * g.scale;
    for (int k = 0; k < 30; ++k) {
        const double G = g.value(c, s);
        if (std::fabs(G) <= tiny) return true;
        const double dG = g.derivative(c, s);
        if (!(std::fabs(dG) > 0.0)) return false;
        const double d = -G / dG;
        if (!std::isfinite(d)) return false;
        rotate(c, s, d);
        // Quadratic convergence: after a step of 1e-8 the angle is right to ~1e-16.
        if (std::fabs(d) <= 1e-8) return true;
    }
    return false;
}

// Root in the arc from ta to tb (less than pi apart, G of opposite signs at the ends):
// safeguarded Newton on tau, t(tau) = normalize(ta + tau ta_perp), tau in [0, tau_b].
bool bracketed_root(const TrigPoly2 &g, double ca, double sa, double cb, double sb, double &c,
                    double &s) {
    const double dot = ca * cb + sa * sb, cross = ca * sb - sa * cb;
    if (!(dot > 0.0)) return false;
    double lo = 0.0, hi = cross / dot;  // tan of the arc
    const double glo = g.value(ca, sa);
    auto point = [&](double tau, double &pc, double &ps) {
        const double inv = 1.0 / std::sqrt(1.0 + tau * tau);
        pc = (ca - sa * tau) * inv;
        ps = (sa + ca * tau) * inv;
    };
    double tau = 0.5 * (lo + hi);
    for (int k = 0; k < 100; ++k) {
        point(tau, c, s);
        const double G = g.value(c, s);
        if (G == 0.0 || hi - lo <= 1e-15 * (1.0 + std::fabs(hi))) return true;
        if ((G > 0.0) == (glo > 0.0)) lo = tau; else hi = tau;
        const double dG = g.derivative(c, s) / (1.0 + tau * tau);
        const double next = dG != 0.0 ? tau - G / dG : 0.5 * (lo + hi);
        const double step = std::fabs(next - tau);
        tau = (next > lo && next < hi) ? next : 0.5 * (lo + hi);
        if (step <= 1e-16 * (1.0 + std::fabs(tau))) {
            point(tau, c, s);
            return true;
        }
    }
    return true;
}

// A root t of G gives a solution if a_N > 0 (so r_N > 0) and u_T . t <= 0.
bool sliding_reaction(const double *W, const double *q, double mu, double c, double s, double *r) {
    const double aN = W[0] + mu * (W[3] * c + W[6] * s);
    if (!(aN > 0.0)) return false;
    const double rN = -q[0] / aN;
    if (!(rN > 0.0) || !std::isfinite(rN)) return false;
    const double a1 = W[1] + mu * (W[4] * c + W[7] * s), a2 = W[2] + mu * (W[5] * c + W[8] * s);
    const double u1 = rN * a1 + q[1], u2 = rN * a2 + q[2];
    const double h = c * u1 + s * u2;
    const double scale = std::fabs(q[1]) + std::fabs(q[2]) + rN * (std::fabs(a1) + std::fabs(a2));
    if (h > 1e-10 * scale) return false;
    r[0] = rN;
    r[1] = mu * rN * c;
    r[2] = mu * rN * s;
    return true;
}

// Exact take-off and stick cases; true if r was set. Otherwise x holds the rejected stick
// candidate -W^-1 q (zero if W_aa has no inverse).
bool trivial_cases(const Contact &c, const double *q, double *r, double *x, Outcome &out) {
    x[0] = x[1] = x[2] = 0.0;
    if (q[0] >= 0.0) {
        r[0] = r[1] = r[2] = 0.0;
        out = Outcome::TakeOff;
        return true;
    }
    if (!c.has_inverse) return false;
    gemv3(c.Winv, q, x);
    x[0] = -x[0];
    x[1] = -x[1];
    x[2] = -x[2];
    if (x[0] >= 0.0 && x[1] * x[1] + x[2] * x[2] <= c.mu * c.mu * x[0] * x[0]) {
        r[0] = x[0];
        r[1] = x[1];
        r[2] = x[2];
        out = Outcome::Stick;
        return true;
    }
    return false;
}

Outcome projected_iterations(Contact &c, const double *q, double *r, const Params &p) {
    const double start[3] = {r[0], r[1], r[2]};
    double u[3], F[3];
    de_saxce_map(c, q, r, u, F);
    if (std::sqrt(coulomb::residual_sq(r, u, c.mu)) <= p.tol * coulomb::relative_scale(q, r, u))
        return Outcome::Iterated;
    double rho = c.rho;
    const double rho_min = 1e-12 * c.rho0, rho_max = 1e12 * c.rho0;
    for (int it = 0; it < p.max_iter; ++it) {
        double rn[3], un[3], Fn[3], ndr = 0.0, ndF = 0.0;
        // Backtrack until the step is contracting enough (Khobotov-type rule).
        for (int ls = 0; ls < 10; ++ls) {
            for (int i = 0; i < 3; ++i) rn[i] = r[i] - rho * F[i];
            coulomb::project_on_cone(rn, c.mu);
            de_saxce_map(c, q, rn, un, Fn);
            const double dr[3] = {rn[0] - r[0], rn[1] - r[1], rn[2] - r[2]};
            const double dF[3] = {Fn[0] - F[0], Fn[1] - F[1], Fn[2] - F[2]};
            ndr = norm3(dr);
            ndF = norm3(dF);
            if (rho * ndF <= 0.9 * ndr || rho <= rho_min) break;
            rho = std::max(rho * (2.0 / 3.0), rho_min);
        }
        if (!std::isfinite(Fn[0] + Fn[1] + Fn[2] + rn[0] + rn[1] + rn[2])) {
            // Runaway iterates (e.g. W_NN <= 0): give back the warm start, not an overflow.
            std::copy(start, start + 3, r);
            c.rho = c.rho0;
            return Outcome::NotConverged;
        }
        for (int i = 0; i < 3; ++i) {
            r[i] = rn[i];
            u[i] = un[i];
            F[i] = Fn[i];
        }
        if (std::sqrt(coulomb::residual_sq(r, u, c.mu)) <= p.tol * coulomb::relative_scale(q, r, u)) {
            c.rho = rho;
            return Outcome::Iterated;
        }
        if (rho * ndF < 0.3 * ndr) rho = std::min(rho * 1.5, rho_max);
    }
    c.rho = rho;
    return Outcome::NotConverged;
}

}  // namespace

void contact_setup(const double *Waa, double mu, Contact &c) {
    std::copy(Waa, Waa + 9, c.W);
    c.mu = mu;
    const double *W = c.W;
    // Cofactors, stored transposed: Winv = adj(W) / det.
    const double c00 = W[4] * W[8] - W[7] * W[5], c01 = W[7] * W[2] - W[1] * W[8],
                 c02 = W[1] * W[5] - W[4] * W[2];
    const double c10 = W[6] * W[5] - W[3] * W[8], c11 = W[0] * W[8] - W[6] * W[2],
                 c12 = W[3] * W[2] - W[0] * W[5];
    const double c20 = W[3] * W[7] - W[6] * W[4], c21 = W[6] * W[1] - W[0] * W[7],
                 c22 = W[0] * W[4] - W[3] * W[1];
    const double det = W[0] * c00 + W[3] * c01 + W[6] * c02;
    double frob = 0.0;
    for (int i = 0; i < 9; ++i) frob += W[i] * W[i];
    frob = std::sqrt(frob);
    c.degenerate = !(frob > 0.0) || !std::isfinite(frob);
    // cond(W_aa) beyond ~1e13 makes -W^-1 q meaningless; such contacts go the iterative way.
    c.has_inverse = !c.degenerate && std::fabs(det) > 1e-13 * frob * frob * frob;
    if (c.has_inverse) {
        const double inv = 1.0 / det;
        const double adj[9] = {c00, c01, c02, c10, c11, c12, c20, c21, c22};
        for (int i = 0; i < 9; ++i) c.Winv[i] = adj[i] * inv;
    } else {
        std::fill(c.Winv, c.Winv + 9, 0.0);
    }
    const double n2 = c.degenerate ? 0.0 : spectral_norm(W);
    c.has_dir = false;
    c.rho0 = n2 > 0.0 ? 1.0 / n2 : (c.degenerate ? 0.0 : 1.0 / frob);
    c.rho = c.rho0;
}

namespace {

// Unit direction of (x, y), or false if it is zero.
bool unit(double x, double y, double &c, double &s) {
    const double n2 = x * x + y * y;
    if (!(n2 > 0.0)) return false;
    const double inv = 1.0 / std::sqrt(n2);
    c = x * inv;
    s = y * inv;
    return true;
}

// The sliding root nearest the unit direction (hc, hs); dir receives the root's direction.
bool slide_from(const Contact &c, const double *q, double hc, double hs, double *r, double *dir) {
    if (!(q[0] < 0.0)) return false;
    if (c.mu == 0.0) {
        if (!(c.W[0] > 0.0)) return false;
        r[0] = -q[0] / c.W[0];
        r[1] = r[2] = 0.0;
        dir[0] = hc;
        dir[1] = hs;
        return std::isfinite(r[0]);
    }
    return nearest_valid_root(sliding_angle_equation(c.W, q, c.mu), c.W, q, c.mu, sliding_reaction,
                              hc, hs, r, dir);
}

}  // namespace

bool nearest_valid_root(const TrigPoly2 &g, const double *W, const double *q, double mu,
                        ReactionFn reaction, double hc, double hs, double *r, double *dir) {
    if (!(g.scale > 0.0) || !std::isfinite(g.scale)) return false;
    double tc = hc, ts = hs;
    if (newton_angle(g, tc, ts) && reaction(W, q, mu, tc, ts, r)) {
        dir[0] = tc;
        dir[1] = ts;
        return true;
    }

    // Newton went to an invalid root or failed: bracket every root on a 32-point grid and
    // keep the valid one closest to the hint.
    constexpr int kSamples = 32;
    constexpr double kCos = 0.98078528040323043, kSin = 0.19509032201612825;  // pi/16
    double pc[kSamples], ps[kSamples], pg[kSamples];
    pc[0] = 1.0;
    ps[0] = 0.0;
    for (int k = 1; k < kSamples; ++k) {
        pc[k] = pc[k - 1] * kCos - ps[k - 1] * kSin;
        ps[k] = ps[k - 1] * kCos + pc[k - 1] * kSin;
    }
    for (int k = 0; k < kSamples; ++k) pg[k] = g.value(pc[k], ps[k]);
    double best = -2.0;
    for (int k = 0; k < kSamples; ++k) {
        const int j = (k + 1) % kSamples;
        if ((pg[k] > 0.0) == (pg[j] > 0.0) && pg[k] != 0.0) continue;
        double rc, rs, cand[3];
        if (pg[k] == 0.0) {
            rc = pc[k];
            rs = ps[k];
        } else if (!bracketed_root(g, pc[k], ps[k], pc[j], ps[j], rc, rs)) {
            continue;
        }
        if (!reaction(W, q, mu, rc, rs, cand)) continue;
        const double closeness = rc * hc + rs * hs;
        if (closeness > best) {
            best = closeness;
            std::copy(cand, cand + 3, r);
            dir[0] = rc;
            dir[1] = rs;
        }
    }
    return best > -2.0;
}

bool solve_slide(const Contact &c, const double *q, const double *hint, double *r) {
    // Starting direction: the hint's tangential direction, else opposite to q_T.
    double hc = 1.0, hs = 0.0, dir[2];
    if (!(hint && unit(hint[1], hint[2], hc, hs))) unit(-q[1], -q[2], hc, hs);
    return slide_from(c, q, hc, hs, r, dir);
}

// The relative one-contact residual above which the hybrid (565) hands a contact to Newton.
constexpr double kHybridNewtonThreshold = 1e-4;

Outcome solve_contact(Contact &c, const double *q, double *r, const Params &p) {
    if (c.degenerate) {
        if (q[0] >= 0.0) {
            r[0] = r[1] = r[2] = 0.0;
            return Outcome::TakeOff;
        }
        return Outcome::NoSolution;
    }
    if (p.solver == kProjection) {
        double u[3], F[3];
        de_saxce_map(c, q, r, u, F);
        for (int i = 0; i < 3; ++i) r[i] -= c.rho0 * F[i];
        coulomb::project_on_cone(r, c.mu);
        return Outcome::Step;
    }
    Outcome out;
    double stick[3];
    if (trivial_cases(c, q, r, stick, out)) {
        c.has_dir = false;
        return out;
    }
    switch (p.solver) {
        case kNewtonAc:
        case kNewtonAcGp:
        case kNewtonFb:
            return newton_contact(c, q, r, p, p.solver == kNewtonFb ? nsn::kFischerBurmeister : nsn::kAlartCurnier,
                                  p.solver != kNewtonAc)
                       ? Outcome::Newton
                       : Outcome::NotConverged;
        case kHybrid: {
            // The 553 projected iterations first, exactly as 553 runs them; Newton
            // (Alart-Curnier, Goldstein-Price) only where they leave the contact far from
            // solved, its result kept only if it lowers the residual. NSGS then sweeps like
            // NSGS with 553 wherever the projections do their job: exact local solutions
            // lock plain NSGS into limit cycles that the projections' inexactness avoids
            // (OneObject-i100000-316 stalls at 1.7e-3 when Newton finishes every contact
            // left above 1e-6; with the 1e-4 threshold NSGS with 565 solves every FCLIB problem
            // here that NSGS with 553 solves).
            const Outcome proj = projected_iterations(c, q, r, p);
            if (proj == Outcome::Iterated) return proj;
            double rel = 0.0;
            coulomb::contact_residual(c.W, q, c.mu, r, &rel);
            if (rel <= kHybridNewtonThreshold) return proj;
            return newton_contact(c, q, r, p, nsn::kAlartCurnier, true) ? Outcome::Newton : proj;
        }
        default: break;
    }
    if (p.solver == kClosedForm) {
        // The last sliding direction (kept unit, saving a normalisation), else the current
        // r_T's, else the stick candidate's, else opposite to q_T, starts the root search and
        // selects among roots.
        double hc = 1.0, hs = 0.0, cand[3];
        if (c.has_dir) {
            hc = c.dir[0];
            hs = c.dir[1];
        } else if (!unit(r[1], r[2], hc, hs) && !unit(stick[1], stick[2], hc, hs)) {
            unit(-q[1], -q[2], hc, hs);
        }
        c.has_dir = slide_from(c, q, hc, hs, cand, c.dir);
        if (c.has_dir) {
            std::copy(cand, cand + 3, r);
            return Outcome::Slide;
        }
    }
    return projected_iterations(c, q, r, p);
}

}  // namespace frix::local
