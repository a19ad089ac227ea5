// The rolling one-contact solver: the exact take-off and stick cases, then a semismooth
// Newton on the natural map r - P_K(r - rho u^(r)) (P_K's generalised Jacobian, case by case
// of the projection), globalised by a backtracking search on |F|; Siconos's projected
// iterations with a self-adaptive step finish where Newton stalls.
#include "solvers/kit/local5x5.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>

#include "src/linalg/linalg.hpp"
#include "src/rolling.hpp"

namespace frix::local5 {

namespace {

// u = W r + q.
void velocity(const double *W, const double *q, const double *r, double *u) {
    for (int i = 0; i < 5; ++i) {
        double s = q[i];
        for (int j = 0; j < 5; ++j) s += W[i + 5 * j] * r[j];
        u[i] = s;
    }
}

double norm5(const double *x) {
    double s = 0.0;
    for (int i = 0; i < 5; ++i) s += x[i] * x[i];
    return std::sqrt(s);
}

bool finite5(const double *x) {
    for (int i = 0; i < 5; ++i)
        if (!std::isfinite(x[i])) return false;
    return true;
}

// The unit vector of (x[0], x[1]) into e, 0 where it vanishes.
void unit2(const double *x, double *e) {
    const double n = std::hypot(x[0], x[1]);
    e[0] = n > 0.0 ? x[0] / n : 0.0;
    e[1] = n > 0.0 ? x[1] / n : 0.0;
}

// D = dP_K(x) for the case rolling::project_on_cone reported (5x5, column-major).
void projection_jacobian(const double *x, int which, double mu, double mu_r, double *D) {
    std::fill(D, D + 25, 0.0);
    if (which == 0) return;
    if (which == 1) {
        for (int i = 0; i < 5; ++i) D[i + 5 * i] = 1.0;
        return;
    }
    const bool on_t = which == 2 || which == 4, on_r = which == 3 || which == 4;
    const double nt = std::hypot(x[1], x[2]), nm = std::hypot(x[3], x[4]);
    double et[2], em[2];
    unit2(x + 1, et);
    unit2(x + 3, em);
    const double c = 1.0 + (on_t ? mu * mu : 0.0) + (on_r ? mu_r * mu_r : 0.0);
    double dt[5] = {1.0 / c, 0, 0, 0, 0};  // the gradient of the normal part t
    if (on_t) dt[1] = mu * et[0] / c, dt[2] = mu * et[1] / c;
    if (on_r) dt[3] = mu_r * em[0] / c, dt[4] = mu_r * em[1] / c;
    const double t = (x[0] + (on_t ? mu * nt : 0.0) + (on_r ? mu_r * nm : 0.0)) / c;
    for (int j = 0; j < 5; ++j) D[5 * j] = dt[j];
    // A saturated tangential part: coef t e, whose derivative is coef (e dt + t (I - e e^T) / n).
    const auto saturated = [&](int row, double coef, const double *e, double n) {
        for (int i = 0; i < 2; ++i)
            for (int j = 0; j < 5; ++j) {
                double d = coef * e[i] * dt[j];
                if (j == row || j == row + 1)
                    d += n > 0.0 ? coef * t * ((i == j - row ? 1.0 : 0.0) - e[i] * e[j - row]) / n : 0.0;
                D[row + i + 5 * j] = d;
            }
    };
    if (on_t) saturated(1, mu, et, nt);
    else D[1 + 5] = D[2 + 10] = 1.0;
    if (on_r) saturated(3, mu_r, em, nm);
    else D[3 + 15] = D[4 + 20] = 1.0;
}

// F = r - P_K(r - rho u^), its projection's argument x and case.
void natural_map(const Contact &c, const double *q, const double *r, double rho, double *F, double *x, int &which) {
    double u[5], uh[5], p[5];
    velocity(c.W, q, r, u);
    rolling::shifted_velocity(u, rolling::Cones{c.mu, c.mu_r, 0.0, 5}, uh);
    for (int i = 0; i < 5; ++i) x[i] = p[i] = r[i] - rho * uh[i];
    which = rolling::project_on_cone(p, rolling::Cones{c.mu, c.mu_r, 0.0, 5});
    for (int i = 0; i < 5; ++i) F[i] = r[i] - p[i];
}

// J = I - D (I - rho A), A = du^/dr = W plus the shifts' gradients in the normal row.
void newton_matrix(const Contact &c, const double *q, const double *r, double rho, const double *x, int which,
                   double *J) {
    double u[5], et[2], em[2], D[25], B[25];
    velocity(c.W, q, r, u);
    unit2(u + 1, et);
    unit2(u + 3, em);
    for (int j = 0; j < 5; ++j) {
        const double *w = c.W + 5 * j;
        const double a0 = w[0] + c.mu * (et[0] * w[1] + et[1] * w[2]) + c.mu_r * (em[0] * w[3] + em[1] * w[4]);
        for (int i = 0; i < 5; ++i) B[i + 5 * j] = (i == j ? 1.0 : 0.0) - rho * (i == 0 ? a0 : w[i]);
    }
    projection_jacobian(x, which, c.mu, c.mu_r, D);
    for (int i = 0; i < 5; ++i)
        for (int j = 0; j < 5; ++j) {
            double s = 0.0;
            for (int k = 0; k < 5; ++k) s += D[i + 5 * k] * B[k + 5 * j];
            J[i + 5 * j] = (i == j ? 1.0 : 0.0) - s;
        }
}

}  // namespace

namespace {

// One disk part of Alart-Curnier: phi = x - P_D(R)(x - rho y) for the pair x (reaction) and y
// (velocity) at entries k, k + 1, the disk's radius R = c max(0, xn); its derivatives into A and
// B (5x5, column-major; rows k, k + 1), the radius's through xn = r_N - rho u_N.
void disk_part(int k, const double *r, const double *u, double c, double xn, double rho, double *F, double *A,
               double *B) {
    const double R = c * std::max(xn, 0.0);
    const double t1 = r[k] - rho * u[k], t2 = r[k + 1] - rho * u[k + 1];
    const double nt = std::hypot(t1, t2);
    if (nt <= R) {  // sticking (or rolling without slip): x = P_D(x - rho y) means y = 0
        F[k] = rho * u[k], F[k + 1] = rho * u[k + 1];
        if (B) B[k + 5 * k] = B[k + 1 + 5 * (k + 1)] = rho;
        return;
    }
    const double g1 = t1 / nt, g2 = t2 / nt;
    F[k] = r[k] - R * g1, F[k + 1] = r[k + 1] - R * g2;
    if (!A) return;
    // d(t/|t|)/dt = (I - g g^T)/|t|: dF/dx = I - R G, dF/dy = rho R G.
    const double h = R / nt, G11 = 1.0 - g1 * g1, G22 = 1.0 - g2 * g2, G12 = -g1 * g2;
    A[k + 5 * k] = 1.0 - h * G11, A[k + 1 + 5 * (k + 1)] = 1.0 - h * G22;
    A[k + 5 * (k + 1)] = A[k + 1 + 5 * k] = -h * G12;
    B[k + 5 * k] = rho * h * G11, B[k + 1 + 5 * (k + 1)] = rho * h * G22;
    B[k + 5 * (k + 1)] = B[k + 1 + 5 * k] = rho * h * G12;
    if (xn > 0.0) {  // the radius c (r_N - rho u_N) moves with r_N and u_N
        A[k] = -c * g1, A[k + 1] = -c * g2;
        B[k] = c * rho * g1, B[k + 1] = c * rho * g2;
    }
}

}  // namespace

void alart_curnier(const double *r, const double *u, double mu, double mu_r, double rho, double *F, double *A,
                   double *B) {
    if (A) std::fill(A, A + 25, 0.0), std::fill(B, B + 25, 0.0);
    const double xn = r[0] - rho * u[0];
    if (xn > 0.0) {
        F[0] = rho * u[0];
        if (B) B[0] = rho;
    } else {
        F[0] = r[0];
        if (A) A[0] = 1.0;
    }
    disk_part(1, r, u, mu, xn, rho, F, A, B);
    disk_part(3, r, u, mu_r, xn, rho, F, A, B);
}

namespace {

// Keeps the best r seen (by the relative residual).
struct Best {
    double r[5] = {0, 0, 0, 0, 0};
    double error = INFINITY;
    void offer(const Contact &c, const double *q, const double *x) {
        const double e = relative_residual(c, q, x);
        if (e < error) {
            error = e;
            std::copy(x, x + 5, r);
        }
    }
};

// Backtracking steps of a Newton direction: halved down to this share of the full step.
constexpr double kSmallestStep = 1.0 / 1024.0;
// Siconos's self-adaptive step rule (rolling_fc3d_projectionOnConeWithLocalIteration_solve).
constexpr double kTau = 2.0 / 3.0, kL = 0.9, kLmin = 0.3;
constexpr int kStepSearches = 100;

// solve_contact on the contact in its own units (Contact).
Outcome solve_scaled(Contact &c, const double *q, double *r, const Params &p);

bool newton(Contact &c, const double *q, double *r, const Params &p, Best &best) {
    double F[5], x[5], J[25], inv[25], d[5], Ft[5], xt[5], rt[5];
    int which = 0;
    const double rho = c.rho0;
    natural_map(c, q, r, rho, F, x, which);
    double norm_f = norm5(F);
    for (int it = 0; it < p.max_iter; ++it) {
        if (best.error <= p.tol) return true;
        newton_matrix(c, q, r, rho, x, which, J);
        double scale = 0.0;
        for (double v : J) scale = std::max(scale, std::fabs(v));
        std::fill(inv, inv + 25, 0.0);
        for (int i = 0; i < 5; ++i) inv[i + 5 * i] = 1.0;
        if (!linalg::invert_small(5, J, inv, scale)) return false;
        for (int i = 0; i < 5; ++i) {
            double s = 0.0;
            for (int j = 0; j < 5; ++j) s -= inv[i + 5 * j] * F[j];
            d[i] = s;
        }
        double t = 1.0, norm_t = INFINITY;
        int which_t = 0;
        for (; t >= kSmallestStep; t *= 0.5) {
            for (int i = 0; i < 5; ++i) rt[i] = r[i] + t * d[i];
            natural_map(c, q, rt, rho, Ft, xt, which_t);
            norm_t = norm5(Ft);
            if (norm_t <= (1.0 - 1e-4 * t) * norm_f) break;
        }
        if (!(t >= kSmallestStep) || !finite5(rt)) return false;
        std::copy(rt, rt + 5, r);
        std::copy(Ft, Ft + 5, F);
        std::copy(xt, xt + 5, x);
        which = which_t;
        norm_f = norm_t;
        best.offer(c, q, r);
    }
    return best.error <= p.tol;
}

// Projected iterations r <- P_K(r - rho u^(r)) with Siconos's self-adaptive rho.
bool projected(Contact &c, const double *q, double *r, const Params &p, Best &best) {
    double u_k[5], uh[5], r_k[5], u[5];
    for (int it = 0; it < 10 * p.max_iter; ++it) {
        if (best.error <= p.tol) return true;
        std::copy(r, r + 5, r_k);
        velocity(c.W, q, r_k, u_k);
        rolling::shifted_velocity(u_k, rolling::Cones{c.mu, c.mu_r, 0.0, 5}, uh);
        double rho_k = c.rho / kTau, a1 = 0.0, a2 = 0.0;
        for (int ls = 0; ls < kStepSearches; ++ls) {
            rho_k *= kTau;
            for (int i = 0; i < 5; ++i) r[i] = r_k[i] - rho_k * uh[i];
            rolling::project_on_cone(r, rolling::Cones{c.mu, c.mu_r, 0.0, 5});
            velocity(c.W, q, r, u);
            a1 = a2 = 0.0;
            for (int i = 0; i < 5; ++i) {
                a1 += (u_k[i] - u[i]) * (u_k[i] - u[i]);
                a2 += (r_k[i] - r[i]) * (r_k[i] - r[i]);
            }
            a1 = std::sqrt(a1), a2 = std::sqrt(a2);
            if (rho_k * a1 <= kL * a2) break;
        }
        c.rho = rho_k * a1 < kLmin * a2 ? rho_k / kTau : rho_k;
        if (!(c.rho > 0.0) || !std::isfinite(c.rho)) c.rho = c.rho0;
        if (!finite5(r)) return false;
        best.offer(c, q, r);
    }
    return best.error <= p.tol;
}

}  // namespace

void contact_setup(const double *Waa, double mu, double mu_r, Contact &c) {
    const double tt = Waa[6] + Waa[12], rr = Waa[18] + Waa[24], L = std::sqrt(tt / rr);
    c.length = tt > 0.0 && rr > 0.0 && std::isfinite(L) && L > 0.0 ? L : 1.0;
    // S W S with S = diag(1, 1, 1, L, L).
    for (int j = 0; j < 5; ++j)
        for (int i = 0; i < 5; ++i) c.W[i + 5 * j] = Waa[i + 5 * j] * (i >= 3 ? c.length : 1.0) * (j >= 3 ? c.length : 1.0);
    Waa = c.W;
    c.mu = mu;
    c.mu_r = mu_r / c.length;
    double norm_inf = 0.0, scale = 0.0;
    for (int i = 0; i < 5; ++i) {
        double row = 0.0;
        for (int j = 0; j < 5; ++j) row += std::fabs(Waa[i + 5 * j]);
        norm_inf = std::max(norm_inf, row);
    }
    for (int k = 0; k < 25; ++k) scale = std::max(scale, std::fabs(Waa[k]));
    c.degenerate = !(norm_inf > 0.0) || !std::isfinite(norm_inf);
    c.rho0 = c.degenerate ? 1.0 : 1.0 / norm_inf;
    c.rho = c.rho0;
    double a[25];
    std::copy(Waa, Waa + 25, a);
    std::fill(c.Winv, c.Winv + 25, 0.0);
    for (int i = 0; i < 5; ++i) c.Winv[i + 5 * i] = 1.0;
    c.has_inverse = !c.degenerate && linalg::invert_small(5, a, c.Winv, scale);
}

double relative_residual(const Contact &c, const double *q, const double *r) {
    double u[5];
    velocity(c.W, q, r, u);
    const double res = rolling::residual(r, u, rolling::Cones{c.mu, c.mu_r, 0.0, 5});
    const double scale = std::max({norm5(q), norm5(r), norm5(u)});
    return scale > DBL_EPSILON ? res / scale : res;
}

Outcome solve_contact(Contact &c, const double *q_given, double *r_given, const Params &p) {
    if (q_given[0] >= 0.0) {
        std::fill(r_given, r_given + 5, 0.0);
        return Outcome::TakeOff;
    }
    if (c.degenerate) return Outcome::NoSolution;
    // In the contact's units (Contact): q_R and w_R times L, m_R over L; back at the end.
    const double L = c.length;
    const double q[5] = {q_given[0], q_given[1], q_given[2], L * q_given[3], L * q_given[4]};
    double r[5] = {r_given[0], r_given[1], r_given[2], r_given[3] / L, r_given[4] / L};
    const Outcome out = solve_scaled(c, q, r, p);
    if (out != Outcome::NoSolution) {
        for (int i = 0; i < 3; ++i) r_given[i] = r[i];
        r_given[3] = L * r[3];
        r_given[4] = L * r[4];
    }
    return out;
}

namespace {

Outcome solve_scaled(Contact &c, const double *q, double *r, const Params &p) {
    Best best;
    if (c.has_inverse) {
        // Stick: u = 0, r = -W^-1 q, if it lies in K.
        double s[5];
        for (int i = 0; i < 5; ++i) {
            double v = 0.0;
            for (int j = 0; j < 5; ++j) v -= c.Winv[i + 5 * j] * q[j];
            s[i] = v;
        }
        if (finite5(s) && s[0] >= 0.0 && std::hypot(s[1], s[2]) <= c.mu * s[0] &&
            std::hypot(s[3], s[4]) <= c.mu_r * s[0]) {
            std::copy(s, s + 5, r);
            return Outcome::Stick;
        }
        // Its projection on K: a start that often beats the warm start after a change of regime.
        if (finite5(s)) {
            rolling::project_on_cone(s, rolling::Cones{c.mu, c.mu_r, 0.0, 5});
            best.offer(c, q, s);
        }
    }
    double start[5] = {r[0], r[1], r[2], r[3], r[4]};
    if (!finite5(start)) std::fill(start, start + 5, 0.0);
    rolling::project_on_cone(start, rolling::Cones{c.mu, c.mu_r, 0.0, 5});
    best.offer(c, q, start);
    double x[5];
    std::copy(best.r, best.r + 5, x);
    if (newton(c, q, x, p, best)) {
        std::copy(best.r, best.r + 5, r);
        return Outcome::Newton;
    }
    std::copy(best.r, best.r + 5, x);
    const bool done = projected(c, q, x, p, best);
    if (finite5(best.r)) std::copy(best.r, best.r + 5, r);
    return done ? Outcome::Iterated : Outcome::NotConverged;
}

}  // namespace

}  // namespace frix::local5
