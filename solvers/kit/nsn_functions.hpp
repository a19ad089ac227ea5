// The semismooth reformulations of one contact's Coulomb law, Phi(r, u) = 0 with u = W r + q,
// and an element of their generalized Jacobians, shared by the global Newton solvers
// (newton.cpp, prox.cpp, gnsn_ac.cpp) and the one-contact Newton solvers (local_newton.cpp).
// Vectors are per contact, normal first; 3x3 matrices column-major.
#pragma once

#include <cstdint>

namespace frix::nsn {

enum Formulation : int {
    // Alart-Curnier: Phi_N = r_N - max(0, r_N - rho_N u_N),
    // Phi_T = r_T - P_D(mu max(0, r_N - rho_N u_N))(r_T - rho_T u_T).
    kAlartCurnier = 0,
    // Fischer-Burmeister on the second-order cone, with the De Saxce velocity
    // u^ = u + mu|u_T| e_N and the scaling that maps K_mu and its dual onto the Lorentz cone:
    // x = (sqrt(mu) r_N, r_T / sqrt(mu)), y = rho (u^_N / sqrt(mu), sqrt(mu) u^_T),
    // Phi = x + y - (x^2 + y^2)^(1/2) (Jordan algebra). mu = 0: scalar FB on (r_N, rho u_N)
    // and Phi_T = r_T.
    kFischerBurmeister = 1,
    // Natural map: Phi = r - P_K(r - rho u^), the residual of the error measure (rho = 1).
    kNaturalMap = 2
};

// Phi(r, u) and the blocks A = dPhi/dr, B = dPhi/du of a generalized Jacobian, so that the
// Jacobian of r -> Phi(r, W r + q) is A + B W. rho_n, rho_t > 0; the FB and natural-map
// formulations use a single rho (rho_n). A and B may be null to skip the Jacobian.
void contact_function(int formulation, const double *r, const double *u, double mu,
                      double rho_n, double rho_t, double *phi, double *A, double *B);

// P = P_K(z) on K_mu = {|z_T| <= mu z_N} and J = dP/dz (3x3, column-major; an element of the
// B-subdifferential on the kinks; symmetric, 0 <= J <= I).
void project_with_jacobian(const double *z, double mu, double *P, double *J);

// The per-contact rho of the strategies of frix_rho_strategy, from the diagonal block W_aa.
void contact_rho(int strategy, double constant, const double *Waa, double *rho_n, double *rho_t);

// slope plus the contacts' part of the slope of the merit 1/2 |Phi|^2 along (dr, du):
// Phi . (A dr + B du), A and B 9 values a contact; nc contacts.
inline double add_merit_slope(double slope, const double *phi, const double *A, const double *B, const double *dr,
                              const double *du, int64_t nc) {
    for (int64_t a = 0; a < nc; ++a) {
        const double *Aa = A + 9 * a, *Ba = B + 9 * a, *d = dr + 3 * a, *dua = du + 3 * a;
        for (int i = 0; i < 3; ++i)
            slope += phi[3 * a + i] * (Aa[i] * d[0] + Aa[i + 3] * d[1] + Aa[i + 6] * d[2] + Ba[i] * dua[0] +
                                       Ba[i + 3] * dua[1] + Ba[i + 6] * dua[2]);
    }
    return slope;
}

}  // namespace frix::nsn
