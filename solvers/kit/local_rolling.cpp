// The rolling one-contact solver: the exact take-off and stick cases, then a semismooth
// Newton on the natural map r - P_K(r - rho u^(r)) (P_K's generalised Jacobian, case by case
// of the projection), globalised by a backtracking search on |F|; Siconos's projected
// iterations with a self-adaptive step finish where Newton stalls. Templates on the contact's
// size N (5, or 6 with spinning friction).
#include "solvers/kit/local_rolling.hpp"

#include <algorithm>
#include <cmath>

#include "src/linalg/linalg.hpp"

namespace frix::local_rolling {

namespace {

// u = W r + q.
template <int N>
void velocity(const double *W, const double *q, const double *r, double *u) {
    for (int i = 0; i < N; ++i) {
        double s = q[i];
        for (int j = 0; j < N; ++j) s += W[i + N * j] * r[j];
        u[i] = s;
    }
}

template <int N>
double norm_of(const double *x) {
    double s = 0.0;
    for (int i = 0; i < N; ++i) s += x[i] * x[i];
    return std::sqrt(s);
}

template <int N>
bool all_finite(const double *x) {
    for (int i = 0; i < N; ++i)
        if (!std::isfinite(x[i])) return false;
    return true;
}

// |(a, b)|: the plain square root where the squares stay in range (std::hypot, which guards
// against their overflow and underflow, costs several times as much on this hot path).
double pair_norm(double a, double b) {
    const double s = a * a + b * b;
    return s > 1e-290 && s < 1e290 ? std::sqrt(s) : std::hypot(a, b);
}

// The unit vector of (x[0], x[1]) into e, 0 where it vanishes.
void unit2(const double *x, double *e) {
    const double n = pair_norm(x[0], x[1]);
    e[0] = n > 0.0 ? x[0] / n : 0.0;
    e[1] = n > 0.0 ? x[1] / n : 0.0;
}

double sign_of(double x) { return x > 0.0 ? 1.0 : (x < 0.0 ? -1.0 : 0.0); }

// projection_jacobian for a size N. On the set S of parts cut back, the normal part is t =
// (x_N + sum_S c_k |x_k|) / (1 + sum_S c_k^2) and part k is c_k t x_k / |x_k|.
template <int N>
void projection_jacobian_n(const double *x, int which, const rolling::Cones &k, double *D) {
    std::fill(D, D + N * N, 0.0);
    if (which == 0) return;
    if (which == 1) {
        for (int i = 0; i < N; ++i) D[i + N * i] = 1.0;
        return;
    }
    const double mu = k.mu, mu_r = k.mu_r;
    const int cut = which - 1;
    const bool on_t = (cut & 1) != 0, on_r = (cut & 2) != 0, on_s = N == 6 && (cut & 4) != 0;
    const double nt = pair_norm(x[1], x[2]), nm = pair_norm(x[3], x[4]);
    double et[2], em[2];
    unit2(x + 1, et);
    unit2(x + 3, em);
    double c = 1.0 + (on_t ? mu * mu : 0.0) + (on_r ? mu_r * mu_r : 0.0);
    double sum = x[0] + (on_t ? mu * nt : 0.0) + (on_r ? mu_r * nm : 0.0);
    if constexpr (N == 6) {
        if (on_s) c += k.mu_s * k.mu_s, sum += k.mu_s * std::fabs(x[5]);
    }
    double dt[N] = {1.0 / c};  // the gradient of the normal part t
    if (on_t) dt[1] = mu * et[0] / c, dt[2] = mu * et[1] / c;
    if (on_r) dt[3] = mu_r * em[0] / c, dt[4] = mu_r * em[1] / c;
    const double es = N == 6 ? sign_of(x[N - 1]) : 0.0;
    if (on_s) dt[N - 1] = k.mu_s * es / c;
    const double t = sum / c;
    for (int j = 0; j < N; ++j) D[N * j] = dt[j];
    // A saturated disk part: coef t e, whose derivative is coef (e dt + t (I - e e^T) / n).
    const auto saturated = [&](int row, double coef, const double *e, double n) {
        for (int i = 0; i < 2; ++i)
            for (int j = 0; j < N; ++j) {
                double d = coef * e[i] * dt[j];
                if (j == row || j == row + 1)
                    d += n > 0.0 ? coef * t * ((i == j - row ? 1.0 : 0.0) - e[i] * e[j - row]) / n : 0.0;
                D[row + i + N * j] = d;
            }
    };
    if (on_t) saturated(1, mu, et, nt);
    else D[1 + N] = D[2 + 2 * N] = 1.0;
    if (on_r) saturated(3, mu_r, em, nm);
    else D[3 + 3 * N] = D[4 + 4 * N] = 1.0;
    if constexpr (N == 6) {  // the spinning part: mu_s t sign(x_S), or x_S itself
        if (on_s)
            for (int j = 0; j < N; ++j) D[5 + N * j] = k.mu_s * es * dt[j];
        else
            D[5 + N * 5] = 1.0;
    }
}

// F = r - P_K(r - rho u^), its projection's argument x and case, and u = W r + q.
template <int N>
void natural_map(const Contact &c, const double *q, const double *r, double rho, double *F, double *x, int &which,
                 double *u) {
    double uh[N], p[N];
    velocity<N>(c.W, q, r, u);
    rolling::shifted_velocity(u, c.cones(), uh);
    for (int i = 0; i < N; ++i) x[i] = p[i] = r[i] - rho * uh[i];
    which = rolling::project_on_cone(p, c.cones());
    for (int i = 0; i < N; ++i) F[i] = r[i] - p[i];
}

// J = I - D (I - rho A), A = du^/dr = W plus the shifts' gradients in the normal row; u = W r + q.
template <int N>
void newton_matrix(const Contact &c, const double *u, double rho, const double *x, int which, double *J) {
    double et[2], em[2], D[N * N], B[N * N];
    unit2(u + 1, et);
    unit2(u + 3, em);
    const double es = N == 6 ? sign_of(u[N - 1]) : 0.0;
    for (int j = 0; j < N; ++j) {
        const double *w = c.W + N * j;
        double a0 = w[0] + c.mu * (et[0] * w[1] + et[1] * w[2]) + c.mu_r * (em[0] * w[3] + em[1] * w[4]);
        if constexpr (N == 6) a0 += c.mu_s * es * w[5];
        for (int i = 0; i < N; ++i) B[i + N * j] = (i == j ? 1.0 : 0.0) - rho * (i == 0 ? a0 : w[i]);
    }
    projection_jacobian_n<N>(x, which, c.cones(), D);
    for (int i = 0; i < N; ++i)
        for (int j = 0; j < N; ++j) {
            double s = 0.0;
            for (int k = 0; k < N; ++k) s += D[i + N * k] * B[k + N * j];
            J[i + N * j] = (i == j ? 1.0 : 0.0) - s;
        }
}

// One disk part of Alart-Curnier: phi = x - P_D(R)(x - rho y) for the pair x (reaction) and y
// (velocity) at entries k, k + 1, the disk's radius R = c max(0, xn); its derivatives into A and
// B (n x n, column-major; rows k, k + 1), the radius's through xn = r_N - rho u_N.
void disk_part(int n, int k, const double *r, const double *u, double c, double xn, double rho, double *F, double *A,
               double *B) {
    const double R = c * std::max(xn, 0.0);
    const double t1 = r[k] - rho * u[k], t2 = r[k + 1] - rho * u[k + 1];
    const double nt = pair_norm(t1, t2);
    if (nt <= R) {  // sticking (or rolling without slip): x = P_D(x - rho y) means y = 0
        F[k] = rho * u[k], F[k + 1] = rho * u[k + 1];
        if (B) B[k + n * k] = B[k + 1 + n * (k + 1)] = rho;
        return;
    }
    const double g1 = t1 / nt, g2 = t2 / nt;
    F[k] = r[k] - R * g1, F[k + 1] = r[k + 1] - R * g2;
    if (!A) return;
    // d(t/|t|)/dt = (I - g g^T)/|t|: dF/dx = I - R G, dF/dy = rho R G.
    const double h = R / nt, G11 = 1.0 - g1 * g1, G22 = 1.0 - g2 * g2, G12 = -g1 * g2;
    A[k + n * k] = 1.0 - h * G11, A[k + 1 + n * (k + 1)] = 1.0 - h * G22;
    A[k + n * (k + 1)] = A[k + 1 + n * k] = -h * G12;
    B[k + n * k] = rho * h * G11, B[k + 1 + n * (k + 1)] = rho * h * G22;
    B[k + n * (k + 1)] = B[k + 1 + n * k] = rho * h * G12;
    if (xn > 0.0) {  // the radius c (r_N - rho u_N) moves with r_N and u_N
        A[k] = -c * g1, A[k + 1] = -c * g2;
        B[k] = c * rho * g1, B[k + 1] = c * rho * g2;
    }
}

// The spinning part of Alart-Curnier (entry 5 of 6): m_S - clamp(m_S - rho w_S, ±c x), the
// interval's half-width c max(0, xn); the one-dimensional disk_part (its I - g g^T vanishes).
void spin_part(const double *r, const double *u, double c, double xn, double rho, double *F, double *A, double *B) {
    constexpr int n = 6, k = 5;
    const double R = c * std::max(xn, 0.0), s = r[k] - rho * u[k];
    if (std::fabs(s) <= R) {  // no spin: w_S = 0
        F[k] = rho * u[k];
        if (B) B[k + n * k] = rho;
        return;
    }
    const double g = s > 0.0 ? 1.0 : -1.0;
    F[k] = r[k] - R * g;
    if (!A) return;
    A[k + n * k] = 1.0;
    if (xn > 0.0) A[k] = -c * g, B[k] = c * rho * g;
}

}  // namespace

void projection_jacobian(const double *x, int which, const rolling::Cones &k, double *D) {
    with_size(k.size, [&](auto n) { projection_jacobian_n<decltype(n)::value>(x, which, k, D); });
}

void alart_curnier(const double *r, const double *u, const rolling::Cones &k, double rho, double *F, double *A,
                   double *B) {
    const int n = k.size;
    if (A) std::fill(A, A + n * n, 0.0), std::fill(B, B + n * n, 0.0);
    const double xn = r[0] - rho * u[0];
    if (xn > 0.0) {
        F[0] = rho * u[0];
        if (B) B[0] = rho;
    } else {
        F[0] = r[0];
        if (A) A[0] = 1.0;
    }
    disk_part(n, 1, r, u, k.mu, xn, rho, F, A, B);
    disk_part(n, 3, r, u, k.mu_r, xn, rho, F, A, B);
    if (n == 6) spin_part(r, u, k.mu_s, xn, rho, F, A, B);
}

namespace {

// The relative residual at r, whose velocity W r + q is u.
template <int N>
double residual_at(const double *q, const double *r, const double *u, const rolling::Cones &k) {
    const double res = rolling::residual(r, u, k);
    const double scale = std::max({norm_of<N>(q), norm_of<N>(r), norm_of<N>(u)});
    return scale > 0.0 ? res / scale : res;
}

template <int N>
double residual_n(const Contact &c, const double *q, const double *r) {
    double u[N];
    velocity<N>(c.W, q, r, u);
    return residual_at<N>(q, r, u, c.cones());
}

// Keeps the best r seen (by the relative residual).
template <int N>
struct Best {
    double r[N] = {};
    double error = INFINITY;
    void offer(const Contact &c, const double *q, const double *x) {
        double u[N];
        velocity<N>(c.W, q, x, u);
        offer_at(q, x, u, c.cones());
    }
    // x, whose velocity W x + q is u.
    void offer_at(const double *q, const double *x, const double *u, const rolling::Cones &k) {
        const double e = residual_at<N>(q, x, u, k);
        if (e < error) {
            error = e;
            std::copy(x, x + N, r);
        }
    }
};

// Backtracking steps of a Newton direction: halved down to this share of the full step.
constexpr double kSmallestStep = 1.0 / 1024.0;
// Siconos's self-adaptive step rule (rolling_fc3d_projectionOnConeWithLocalIteration_solve).
constexpr double kTau = 2.0 / 3.0, kL = 0.9, kLmin = 0.3;
constexpr int kStepSearches = 100;

template <int N>
bool newton(Contact &c, const double *q, double *r, const Params &p, Best<N> &best) {
    double F[N], x[N], u[N], J[N * N], d[N], Ft[N], xt[N], rt[N], ut[N];
    int which = 0;
    const double rho = c.rho0;
    natural_map<N>(c, q, r, rho, F, x, which, u);
    double norm_f = norm_of<N>(F);
    for (int it = 0; it < p.max_iter; ++it) {
        if (best.error <= p.tol) return true;
        newton_matrix<N>(c, u, rho, x, which, J);
        double scale = 0.0;
        for (double v : J) scale = std::max(scale, std::fabs(v));
        for (int i = 0; i < N; ++i) d[i] = -F[i];
        if (!linalg::solve_small<N>(J, d, scale)) return false;
        double t = 1.0, norm_t = INFINITY;
        int which_t = 0;
        for (; t >= kSmallestStep; t *= 0.5) {
            for (int i = 0; i < N; ++i) rt[i] = r[i] + t * d[i];
            natural_map<N>(c, q, rt, rho, Ft, xt, which_t, ut);
            norm_t = norm_of<N>(Ft);
            if (norm_t <= (1.0 - 1e-4 * t) * norm_f) break;
        }
        if (!(t >= kSmallestStep) || !all_finite<N>(rt)) return false;
        std::copy(rt, rt + N, r);
        std::copy(Ft, Ft + N, F);
        std::copy(xt, xt + N, x);
        std::copy(ut, ut + N, u);
        which = which_t;
        norm_f = norm_t;
        best.offer_at(q, r, u, c.cones());
    }
    return best.error <= p.tol;
}

// Projected iterations r <- P_K(r - rho u^(r)) with Siconos's self-adaptive rho.
template <int N>
bool projected(Contact &c, const double *q, double *r, const Params &p, Best<N> &best) {
    double u_k[N], uh[N], r_k[N], u[N];
    for (int it = 0; it < 10 * p.max_iter; ++it) {
        if (best.error <= p.tol) return true;
        std::copy(r, r + N, r_k);
        velocity<N>(c.W, q, r_k, u_k);
        rolling::shifted_velocity(u_k, c.cones(), uh);
        double rho_k = c.rho / kTau, a1 = 0.0, a2 = 0.0;
        for (int ls = 0; ls < kStepSearches; ++ls) {
            rho_k *= kTau;
            for (int i = 0; i < N; ++i) r[i] = r_k[i] - rho_k * uh[i];
            rolling::project_on_cone(r, c.cones());
            velocity<N>(c.W, q, r, u);
            a1 = a2 = 0.0;
            for (int i = 0; i < N; ++i) {
                a1 += (u_k[i] - u[i]) * (u_k[i] - u[i]);
                a2 += (r_k[i] - r[i]) * (r_k[i] - r[i]);
            }
            a1 = std::sqrt(a1), a2 = std::sqrt(a2);
            if (rho_k * a1 <= kL * a2) break;
        }
        c.rho = rho_k * a1 < kLmin * a2 ? rho_k / kTau : rho_k;
        if (!(c.rho > 0.0) || !std::isfinite(c.rho)) c.rho = c.rho0;
        if (!all_finite<N>(r)) return false;
        best.offer(c, q, r);
    }
    return best.error <= p.tol;
}

// r = -W^-1 q inside K (the stick case)?
template <int N>
bool inside(const Contact &c, const double *s) {
    if (!(s[0] >= 0.0 && pair_norm(s[1], s[2]) <= c.mu * s[0] && pair_norm(s[3], s[4]) <= c.mu_r * s[0]))
        return false;
    return N == 5 || std::fabs(s[N - 1]) <= c.mu_s * s[0];
}

// solve_contact on the contact in its own units (Contact).
template <int N>
Outcome solve_scaled(Contact &c, const double *q, double *r, const Params &p) {
    Best<N> best;
    if (c.has_inverse) {
        // Stick: u = 0, r = -W^-1 q, if it lies in K.
        double s[N];
        for (int i = 0; i < N; ++i) {
            double v = 0.0;
            for (int j = 0; j < N; ++j) v -= c.Winv[i + N * j] * q[j];
            s[i] = v;
        }
        if (all_finite<N>(s) && inside<N>(c, s)) {
            std::copy(s, s + N, r);
            return Outcome::Stick;
        }
        // Its projection on K: a start that often beats the warm start after a change of regime.
        if (all_finite<N>(s)) {
            rolling::project_on_cone(s, c.cones());
            best.offer(c, q, s);
        }
    }
    double start[N];
    std::copy(r, r + N, start);
    if (!all_finite<N>(start)) std::fill(start, start + N, 0.0);
    rolling::project_on_cone(start, c.cones());
    best.offer(c, q, start);
    double x[N];
    std::copy(best.r, best.r + N, x);
    if (newton<N>(c, q, x, p, best)) {
        std::copy(best.r, best.r + N, r);
        return Outcome::Newton;
    }
    std::copy(best.r, best.r + N, x);
    const bool done = projected<N>(c, q, x, p, best);
    if (all_finite<N>(best.r)) std::copy(best.r, best.r + N, r);
    return done ? Outcome::Iterated : Outcome::NotConverged;
}

// solve_contact for a size N: in the contact's units (Contact), q_R, w_R (and q_S, w_S) times
// L, m_R (and m_S) over L; back at the end.
template <int N>
Outcome solve_sized(Contact &c, const double *q_given, double *r_given, const Params &p) {
    if (q_given[0] >= 0.0) {
        std::fill(r_given, r_given + N, 0.0);
        return Outcome::TakeOff;
    }
    if (c.degenerate) return Outcome::NoSolution;
    const double L = c.length;
    double q[N], r[N];
    for (int i = 0; i < N; ++i) {
        q[i] = i >= 3 ? L * q_given[i] : q_given[i];
        r[i] = i >= 3 ? r_given[i] / L : r_given[i];
    }
    const Outcome out = solve_scaled<N>(c, q, r, p);
    if (out != Outcome::NoSolution)
        for (int i = 0; i < N; ++i) r_given[i] = i >= 3 ? L * r[i] : r[i];
    return out;
}

template <int N>
void setup_sized(const double *Waa, const rolling::Cones &k, Contact &c) {
    const double tt = Waa[1 + N] + Waa[2 + 2 * N];
    double rr = Waa[3 + 3 * N] + Waa[4 + 4 * N];
    if constexpr (N == 6) {
        if (!(rr > 0.0)) rr = 2.0 * Waa[5 + 5 * N];
    }
    const double L = std::sqrt(tt / rr);
    c.size = N;
    c.length = tt > 0.0 && rr > 0.0 && std::isfinite(L) && L > 0.0 ? L : 1.0;
    // S W S with S = diag(1, 1, 1, L, L[, L]).
    for (int j = 0; j < N; ++j)
        for (int i = 0; i < N; ++i)
            c.W[i + N * j] = Waa[i + N * j] * (i >= 3 ? c.length : 1.0) * (j >= 3 ? c.length : 1.0);
    Waa = c.W;
    c.mu = k.mu;
    c.mu_r = k.mu_r / c.length;
    c.mu_s = N == 6 ? k.mu_s / c.length : 0.0;
    double norm_inf = 0.0, scale = 0.0;
    for (int i = 0; i < N; ++i) {
        double row = 0.0;
        for (int j = 0; j < N; ++j) row += std::fabs(Waa[i + N * j]);
        norm_inf = std::max(norm_inf, row);
    }
    for (int e = 0; e < N * N; ++e) scale = std::max(scale, std::fabs(Waa[e]));
    c.degenerate = !(norm_inf > 0.0) || !std::isfinite(norm_inf);
    c.rho0 = c.degenerate ? 1.0 : 1.0 / norm_inf;
    c.rho = c.rho0;
    double a[N * N];
    std::copy(Waa, Waa + N * N, a);
    std::fill(c.Winv, c.Winv + N * N, 0.0);
    for (int i = 0; i < N; ++i) c.Winv[i + N * i] = 1.0;
    c.has_inverse = !c.degenerate && linalg::invert_small(N, a, c.Winv, scale);
}

}  // namespace

void contact_setup(const double *Waa, const rolling::Cones &k, Contact &c) {
    with_size(k.size, [&](auto n) { setup_sized<decltype(n)::value>(Waa, k, c); });
}

double relative_residual(const Contact &c, const double *q, const double *r) {
    return with_size(c.size, [&](auto n) { return residual_n<decltype(n)::value>(c, q, r); });
}

Outcome solve_contact(Contact &c, const double *q, double *r, const Params &p) {
    return with_size(c.size, [&](auto n) { return solve_sized<decltype(n)::value>(c, q, r, p); });
}

}  // namespace frix::local_rolling
