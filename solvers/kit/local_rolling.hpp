// The one-contact solver of rolling friction (five entries a contact, six with spinning
// friction; frix_problem.h), which the rolling NSGS sweeps call for each contact: u = W_aa r +
// q, K ∋ r ⟂ u^ ∈ K*, with K the rolling cone (and the spinning interval) and u^ every De
// Saxcé shift (src/rolling.hpp). Matrices are column-major, size x size.
#pragma once

#include <cstdint>
#include <type_traits>

#include "src/rolling.hpp"

namespace frix::local_rolling {

// Entries of a contact at most.
constexpr int kMaxSize = 6;

// f(std::integral_constant<int, N>{}) for a contact size N of 5 or 6: the per-contact loops
// run on a size the compiler knows (five-entry contacts as fast as before spinning friction).
template <class F>
decltype(auto) with_size(int size, F &&f) {
    if (size == 6) return f(std::integral_constant<int, 6>{});
    return f(std::integral_constant<int, 5>{});
}

// Per-contact data computed once per solve from the diagonal block W_aa. The solver works on
// the contact with its moments in units of force: m = L m', w' = L w for the rolling and the
// spinning entries alike, for the length L = sqrt(tr W_TT / tr W_RR) (|W_RR| / |W_TT| is about
// one over a radius squared, and W_aa in the given units is that ill-conditioned; the spin row
// of a sphere's contact scales as the rolling rows do; where W_RR vanishes, tr W_RR is taken
// as 2 W_SS); the law is the same with mu_r / L and mu_s / L.
struct Contact {
    int size = 5;                      // entries: 5, or 6 with spinning friction
    double W[kMaxSize * kMaxSize];     // W_aa in those units (size x size)
    double Winv[kMaxSize * kMaxSize];  // its inverse, valid only if has_inverse
    double length;                     // L
    double mu, mu_r, mu_s;             // mu_r / L, mu_s / L
    double rho;                        // step of the projected iterations, adapted across sweeps
    double rho0;                       // 1 / |W_aa|_inf: the Newton map's step and rho's reset value
    bool has_inverse;
    bool degenerate;  // W_aa is (numerically) zero: no local solution exists when q_N < 0
    // The cones in the contact's units.
    rolling::Cones cones() const { return rolling::Cones{mu, mu_r, mu_s, size}; }
};

// Sets c up from W_aa (k.size x k.size) and the contact's cones k (in the given units).
void contact_setup(const double *Waa, const rolling::Cones &k, Contact &c);

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

// Solves the one-contact problem (c.size entries); r holds the current reaction on entry (warm
// start) and the new one on return (unchanged when the outcome is NoSolution).
Outcome solve_contact(Contact &c, const double *q, double *r, const Params &p);

// |r - P_K(r - u^)| / max(|q|, |r|, |u|) (the bare residual where that max is 0), u = W r + q,
// with q and r in the contact's units: the local tolerance's measure. Relative at every scale:
// a problem in units where q is 1e-20 is solved as the same problem in units where it is 1.
double relative_residual(const Contact &c, const double *q, const double *r);

// D = dP_K(x) (k.size x k.size), a generalized Jacobian of the projection at x, for the case
// rolling::project_on_cone(x) reported: 0 the polar cone, otherwise 1 plus the parts cut back
// (1 friction, 2 rolling, 4 spin).
void projection_jacobian(const double *x, int which, const rolling::Cones &k, double *D);

// The Alart-Curnier function of one contact (k.size entries), F = (r_N - max(0, r_N - rho u_N),
// r_T - P_D(mu x)(r_T - rho u_T), m_R - P_D(mu_r x)(m_R - rho w_R)[, m_S - clamp(m_S - rho w_S,
// ±mu_s x)]), x = max(0, r_N - rho u_N) and P_D(R) the projection on the disk of radius R: zero
// exactly where the law holds (Signorini, maximal dissipation in each disk and on the spinning
// interval); the rolling nsn::contact_function of Alart-Curnier. The blocks A = dF/dr, B = dF/du
// of a generalized Jacobian (may be null; k.size^2 values each) make the Jacobian of r -> F(r,
// W r + q) A + B W.
void alart_curnier(const double *r, const double *u, const rolling::Cones &k, double rho, double *F, double *A,
                   double *B);

}  // namespace frix::local_rolling
