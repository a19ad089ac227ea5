// The rolling-friction law for one contact (frix_problem.h): the projection on the rolling
// cone and the natural-map residual. Vectors are per contact, five entries (r_N, r_T (2),
// m_R (2)); the core's measures and the rolling solvers use these, so that one definition of
// the law decides what "solved" means.
#pragma once

namespace frix::rolling {

// r <- P_K(r), K = {|r_T| <= mu r_N, |m_R| <= mu_r r_N}: Siconos 4.4's projectionOnRollingCone
// (the cases in its order, with its formulas), so that errors compare one to one. Returns the
// case: 0 (the polar cone: r = 0), 1 (inside), 2 (on the friction cone only), 3 (on the
// rolling cone only), 4 (on both).
int project_on_cone(double *r, double mu, double mu_r);

// u^ = u + (mu |u_T| + mu_r |w_R|) e_N, the De Saxcé shift of both cones, into uh (5).
void shifted_velocity(const double *u, double mu, double mu_r, double *uh);

// The natural-map residual of one contact: |r - P_K(r - u^)| (the root of Siconos's
// rolling_fc3d_unitary_compute_and_add_error), computed on (r, u) / max|.| where squares
// would leave the doubles' range, and scaled back (it is positively homogeneous).
double residual(const double *r, const double *u, double mu, double mu_r);

// The distance of r to K.
double cone_distance(const double *r, double mu, double mu_r);

}  // namespace frix::rolling
