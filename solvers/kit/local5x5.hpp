// The one-contact solver of rolling friction (five entries a contact, frix_problem.h), which
// the rolling NSGS sweeps call for each contact: u = W_aa r + q, K ∋ r ⟂ u^ ∈ K*, with K the
// rolling cone and u^ both De Saxcé shifts (src/rolling.hpp). 5x5 matrices are column-major.
#pragma once

#include <cstdint>

namespace frix::local5 {

// Per-contact data computed once per solve from the diagonal block W_aa. The solver works on
// the contact with its moments in units of force: m_R = L m', w' = L w_R, for the length L =
// sqrt(tr W_TT / tr W_RR) (|W_RR| / |W_TT| is about one over a radius squared, and W_aa in
// the given units is that ill-conditioned); the law is the same with mu_r / L for mu_r.
struct Contact {
    double W[25];     // W_aa in those units
    double Winv[25];  // its inverse, valid only if has_inverse
    double length;    // L
    double mu, mu_r;  // mu_r / L
    double rho;       // step of the projected iterations, adapted across sweeps
    double rho0;      // 1 / |W_aa|_inf: the Newton map's step and rho's reset value
    bool has_inverse;
    bool degenerate;  // W_aa is (numerically) zero: no local solution exists when q_N < 0
};

void contact_setup(const double *Waa, double mu, double mu_r, Contact &c);

enum class Outcome : int {
    TakeOff = 1,       // q_N >= 0: r = 0
    Stick = 2,         // r = -W^-1 q inside K: u = 0
    Newton = 3,        // the semismooth Newton on the natural map reached the local tolerance
    Iterated = 4,      // projected iterations reached it
    NotConverged = 5,  // neither did: the best r found is returned
    NoSolution = 6     // degenerate W_aa with q_N < 0: r left unchanged
};

struct Params {
    double tol = 1e-12;  // on the one-contact residual, relative to max(|q|, |r|, |u|)
    int max_iter = 20;   // Newton steps; the projected iterations' limit is ten times this
};

// Solves the one-contact problem; r holds the current reaction on entry (warm start) and the
// new one on return (unchanged when the outcome is NoSolution).
Outcome solve_contact(Contact &c, const double *q, double *r, const Params &p);

// |r - P_K(r - u^)| / max(|q|, |r|, |u|) (the bare residual where that max is below DBL_EPSILON),
// u = W r + q, with q and r in the contact's units: the local tolerance's measure.
double relative_residual(const Contact &c, const double *q, const double *r);

// The Alart-Curnier function of one contact, F = (r_N - max(0, r_N - rho u_N), r_T - P_D(mu
// x)(r_T - rho u_T), m_R - P_D(mu_r x)(m_R - rho w_R)), x = max(0, r_N - rho u_N) and P_D(R) the
// projection on the disk of radius R: zero exactly where the rolling law holds (Signorini,
// Coulomb's maximal dissipation in each disk); the five-entry nsn::contact_function of
// Alart-Curnier. The blocks A = dF/dr, B = dF/du of a generalized Jacobian (may be null) make
// the Jacobian of r -> F(r, W r + q) A + B W.
void alart_curnier(const double *r, const double *u, double mu, double mu_r, double rho, double *F, double *A,
                   double *B);

}  // namespace frix::local5
