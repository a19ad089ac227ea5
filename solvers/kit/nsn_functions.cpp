#include "solvers/kit/nsn_functions.hpp"

#include <algorithm>
#include <cmath>

#include "solvers/kit/local3x3.hpp"

namespace frix::nsn {

namespace {

inline void zero9(double *M) { std::fill(M, M + 9, 0.0); }

// C = X Y (3x3, column-major).
inline void mul3(const double *X, const double *Y, double *C) {
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i)
            C[i + 3 * j] = X[i] * Y[3 * j] + X[i + 3] * Y[3 * j + 1] + X[i + 6] * Y[3 * j + 2];
}

// d u^ / d u with u^ = u + mu |u_T| e_N.
void de_saxce_jacobian(const double *u, double mu, double *D) {
    zero9(D);
    D[0] = D[4] = D[8] = 1.0;
    const double nt = std::sqrt(u[1] * u[1] + u[2] * u[2]);
    if (nt > 0.0) {
        D[3] = mu * u[1] / nt;
        D[6] = mu * u[2] / nt;
    }
}

void alart_curnier(const double *r, const double *u, double mu, double rho_n, double rho_t,
                   double *phi, double *A, double *B) {
    if (A) zero9(A), zero9(B);
    const double xn = r[0] - rho_n * u[0];
    if (xn > 0.0) {
        phi[0] = rho_n * u[0];
        if (B) B[0] = rho_n;
    } else {
        phi[0] = r[0];
        if (A) A[0] = 1.0;
    }
    const double R = mu * std::max(xn, 0.0);
    const double t1 = r[1] - rho_t * u[1], t2 = r[2] - rho_t * u[2];
    const double nt = std::sqrt(t1 * t1 + t2 * t2);
    if (nt <= R) {  // sticking (or r_T = rho_t u_T = 0)
        phi[1] = rho_t * u[1];
        phi[2] = rho_t * u[2];
        if (B) B[4] = B[8] = rho_t;
        return;
    }
    const double g1 = t1 / nt, g2 = t2 / nt;
    phi[1] = r[1] - R * g1;
    phi[2] = r[2] - R * g2;
    if (!A) return;
    // d(t/|t|)/dt = (I - g g^T)/|t| =: G; dPhi_T/dr_T = I - R G, dPhi_T/du_T = rho_t R G.
    const double c = R / nt;
    const double G11 = 1.0 - g1 * g1, G22 = 1.0 - g2 * g2, G12 = -g1 * g2;
    A[4] = 1.0 - c * G11, A[8] = 1.0 - c * G22, A[7] = A[5] = -c * G12;
    B[4] = rho_t * c * G11, B[8] = rho_t * c * G22, B[7] = B[5] = rho_t * c * G12;
    if (xn > 0.0) {  // the disk radius mu (r_N - rho_n u_N) moves with r_N and u_N
        A[1] = -mu * g1, A[2] = -mu * g2;
        B[1] = mu * rho_n * g1, B[2] = mu * rho_n * g2;
    }
}

void natural_map(const double *r, const double *u, double mu, double rho, double *phi, double *A,
                 double *B) {
    const double nt = std::sqrt(u[1] * u[1] + u[2] * u[2]);
    const double z[3] = {r[0] - rho * (u[0] + mu * nt), r[1] - rho * u[1], r[2] - rho * u[2]};
    double P[3], JP[9];
    project_with_jacobian(z, mu, P, JP);
    for (int i = 0; i < 3; ++i) phi[i] = r[i] - P[i];
    if (!A) return;
    // dPhi/dr = I - JP, dPhi/du = rho JP D.
    for (int i = 0; i < 9; ++i) A[i] = -JP[i];
    A[0] += 1.0, A[4] += 1.0, A[8] += 1.0;
    double D[9];
    de_saxce_jacobian(u, mu, D);
    mul3(JP, D, B);
    for (int i = 0; i < 9; ++i) B[i] *= rho;
}

// L_x = [[x0, xb^T], [xb, x0 I]], the Jordan product matrix of x.
inline void arrow(const double *x, double *L) {
    L[0] = x[0], L[1] = x[1], L[2] = x[2];
    L[3] = x[1], L[4] = x[0], L[5] = 0.0;
    L[6] = x[2], L[7] = 0.0, L[8] = x[0];
}

// z = sqrt(w) in the Jordan algebra of the Lorentz cone (w in the cone).
void soc_sqrt(const double *w, double *z) {
    const double nw = std::sqrt(w[1] * w[1] + w[2] * w[2]);
    const double l1 = std::sqrt(std::max(w[0] - nw, 0.0)), l2 = std::sqrt(std::max(w[0] + nw, 0.0));
    z[0] = 0.5 * (l1 + l2);
    if (nw > 0.0) {
        const double k = 0.5 * (l2 - l1) / nw;
        z[1] = k * w[1], z[2] = k * w[2];
    } else {
        z[1] = z[2] = 0.0;
    }
}

// I - L_z^-1 L_x for z in the interior of the Lorentz cone.
void fb_partial(const double *z, const double *x, double *out) {
    const double det = z[0] * z[0] - z[1] * z[1] - z[2] * z[2];
    // L_z^-1 = (1/det) [[z0, -zb^T], [-zb, (det/z0) I + zb zb^T / z0]].
    double Li[9];
    Li[0] = z[0] / det, Li[1] = -z[1] / det, Li[2] = -z[2] / det;
    Li[3] = Li[1], Li[6] = Li[2];
    Li[4] = (det / z[0] + z[1] * z[1] / z[0]) / det;
    Li[8] = (det / z[0] + z[2] * z[2] / z[0]) / det;
    Li[5] = Li[7] = z[1] * z[2] / z[0] / det;
    double L[9];
    arrow(x, L);
    mul3(Li, L, out);
    for (int i = 0; i < 9; ++i) out[i] = -out[i];
    out[0] += 1.0, out[4] += 1.0, out[8] += 1.0;
}

void fischer_burmeister(const double *r, const double *u, double mu, double rho, double *phi,
                        double *A, double *B) {
    if (mu == 0.0) {
        // K = the half-line: 0 <= r_N _|_ u_N >= 0 by scalar FB, and r_T = 0.
        const double a = r[0], b = rho * u[0];
        const double z = std::sqrt(a * a + b * b);
        phi[0] = a + b - z, phi[1] = r[1], phi[2] = r[2];
        if (!A) return;
        zero9(A), zero9(B);
        // At (0, 0) the element (1, 1) of the generalized gradient.
        A[0] = z > 0.0 ? 1.0 - a / z : 1.0;
        B[0] = rho * (z > 0.0 ? 1.0 - b / z : 1.0);
        A[4] = A[8] = 1.0;
        return;
    }
    const double s = std::sqrt(mu);
    const double nt = std::sqrt(u[1] * u[1] + u[2] * u[2]);
    const double x[3] = {s * r[0], r[1] / s, r[2] / s};
    const double y[3] = {rho * (u[0] + mu * nt) / s, rho * s * u[1], rho * s * u[2]};
    double w[3] = {x[0] * x[0] + x[1] * x[1] + x[2] * x[2] + y[0] * y[0] + y[1] * y[1] + y[2] * y[2],
                   2.0 * (x[0] * x[1] + y[0] * y[1]), 2.0 * (x[0] * x[2] + y[0] * y[2])};
    double z[3];
    soc_sqrt(w, z);
    for (int i = 0; i < 3; ++i) phi[i] = x[i] + y[i] - z[i];
    if (!A) return;
    // On the cone's boundary sqrt is not differentiable: the Jacobian of the smoothed
    // function (w + 2 eps^2 e) with a tiny eps gives an element of the generalized Jacobian.
    const double det = z[0] * z[0] - z[1] * z[1] - z[2] * z[2];
    if (!(det > 1e-12 * z[0] * z[0])) {
        w[0] += 2e-12 * std::max(w[0], 1e-300) + 1e-300;
        soc_sqrt(w, z);
    }
    double Jx[9], Jy[9];
    fb_partial(z, x, Jx);
    fb_partial(z, y, Jy);
    // A = Jx S_x, S_x = diag(s, 1/s, 1/s); B = Jy rho S_y D, S_y = diag(1/s, s, s).
    for (int i = 0; i < 3; ++i) {
        A[i] = Jx[i] * s;
        A[i + 3] = Jx[i + 3] / s;
        A[i + 6] = Jx[i + 6] / s;
    }
    double D[9], SD[9];
    de_saxce_jacobian(u, mu, D);
    for (int j = 0; j < 3; ++j) {
        SD[3 * j] = rho * D[3 * j] / s;
        SD[3 * j + 1] = rho * s * D[3 * j + 1];
        SD[3 * j + 2] = rho * s * D[3 * j + 2];
    }
    mul3(Jy, SD, B);
}

// |X|_2 of the 2x2 tangential block of W_aa.
double tangential_norm(const double *W) {
    const double a = W[4], b = W[7], c = W[5], d = W[8];  // [[a, b], [c, d]]
    const double s1 = a * a + c * c, s2 = b * b + d * d, s12 = a * b + c * d;
    const double l = 0.5 * (s1 + s2) + std::sqrt(0.25 * (s1 - s2) * (s1 - s2) + s12 * s12);
    return std::sqrt(std::max(l, 0.0));
}

}  // namespace

void project_with_jacobian(const double *z, double mu, double *P, double *J) {
    zero9(J);
    const double n = std::sqrt(z[1] * z[1] + z[2] * z[2]);
    if (n <= mu * z[0]) {  // inside
        P[0] = z[0], P[1] = z[1], P[2] = z[2];
        J[0] = J[4] = J[8] = 1.0;
        return;
    }
    if (mu * n <= -z[0]) {  // polar cone
        P[0] = P[1] = P[2] = 0.0;
        return;
    }
    if (mu == 0.0) {  // K is the half-line: P = (z_N, 0, 0) with z_N > 0 here
        P[0] = z[0], P[1] = P[2] = 0.0;
        J[0] = 1.0;
        return;
    }
    // Boundary: P = s (1, mu t), s = (z_N + mu n) / (1 + mu^2), t = z_T / n (n > 0 here).
    const double k = 1.0 / (1.0 + mu * mu);
    const double s = (z[0] + mu * n) * k;
    const double t1 = z[1] / n, t2 = z[2] / n;
    P[0] = s, P[1] = mu * s * t1, P[2] = mu * s * t2;
    J[0] = k;
    J[3] = mu * k * t1;  // dP_N / dz_1
    J[6] = mu * k * t2;
    J[1] = mu * k * t1;  // dP_1 / dz_N
    J[2] = mu * k * t2;
    const double a = mu * mu * k, b = mu * s / n;
    J[4] = a * t1 * t1 + b * (1.0 - t1 * t1);
    J[8] = a * t2 * t2 + b * (1.0 - t2 * t2);
    J[7] = J[5] = a * t1 * t2 - b * t1 * t2;
}


void contact_function(int formulation, const double *r, const double *u, double mu,
                      double rho_n, double rho_t, double *phi, double *A, double *B) {
    switch (formulation) {
        case kFischerBurmeister: fischer_burmeister(r, u, mu, rho_n, phi, A, B); return;
        case kNaturalMap: natural_map(r, u, mu, rho_n, phi, A, B); return;
        default: alart_curnier(r, u, mu, rho_n, rho_t, phi, A, B); return;
    }
}

void contact_rho(int strategy, double constant, const double *Waa, double *rho_n, double *rho_t) {
    if (strategy == 0) {  // FRIX_RHO_CONSTANT
        *rho_n = *rho_t = constant;
        return;
    }
    local::Contact c;
    local::contact_setup(Waa, 0.0, c);
    // A zero block (a contact W does not see) has no scale of its own: rho = 1.
    const double spectral = c.rho0 > 0.0 ? c.rho0 : 1.0;
    *rho_n = *rho_t = spectral;
    if (strategy == 2) {  // FRIX_RHO_SPLIT: rho_N = 1/W_NN, rho_T = 1/|W_TT|_2
        if (Waa[0] > 0.0) *rho_n = 1.0 / Waa[0];
        const double nt = tangential_norm(Waa);
        if (nt > 0.0) *rho_t = 1.0 / nt;
    }
}

}  // namespace frix::nsn
