// The rolling-friction law for one contact (frix_problem.h): the projection on the rolling
// cone and the natural-map residual. Vectors are per contact, five entries (r_N, r_T (2),
// m_R (2)), or six with spinning friction (and m_S); the core's measures and the rolling
// solvers use these, so that one definition of the law decides what "solved" means.
#pragma once

#include <cstdint>

#include "problem.hpp"

namespace frix::rolling {

// One contact's cones: |r_T| <= mu r_N, |m_R| <= mu_r r_N and, where size is 6, |m_S| <= mu_s r_N.
struct Cones {
    double mu = 0.0, mu_r = 0.0, mu_s = 0.0;
    int size = 5;  // entries of the contact: 5, or 6 with spinning friction
};

// Contact a's cones in a rolling problem.
inline Cones cones_of(const frix_problem &p, int64_t a) {
    return p.spinning ? Cones{p.mu[a], p.mu_r[a], p.mu_s[a], 6} : Cones{p.mu[a], p.mu_r[a], 0.0, 5};
}

// r <- P_K(r), K = {|r_T| <= mu r_N, |m_R| <= mu_r r_N (, |m_S| <= mu_s r_N)}. Five entries:
// Siconos 4.4's projectionOnRollingCone (the cases in its order, with its formulas), so that
// errors compare one to one. Returns the case: 0 (the polar cone: r = 0), otherwise 1 plus the
// parts cut back to their cone's boundary (1 the friction disk, 2 the rolling disk, 4 the
// spinning interval): 1 inside, 2 the friction cone only, 3 the rolling cone only, 4 both, ...
int project_on_cone(double *r, const Cones &k);

// u^ = u + (mu |u_T| + mu_r |w_R| (+ mu_s |w_S|)) e_N, the De Saxcé shift of every cone, into
// uh (k.size entries).
void shifted_velocity(const double *u, const Cones &k, double *uh);

// The natural-map residual of one contact: |r - P_K(r - u^)| (the root of Siconos's
// rolling_fc3d_unitary_compute_and_add_error), computed on (r, u) / max|.| where squares
// would leave the doubles' range, and scaled back (it is positively homogeneous).
double residual(const double *r, const double *u, const Cones &k);

// The distance of r to K.
double cone_distance(const double *r, const Cones &k);

}  // namespace frix::rolling
