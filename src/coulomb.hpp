// Coulomb's law for one contact: the projections on the friction cone and the Tresca disk,
// and the contact's natural-map residual. Vectors are per contact, normal first; 3x3
// matrices are column-major. The core's measures and every solver use these, so that one
// definition of the law decides what "solved" means.
#pragma once

#include <cstdint>

namespace frix::coulomb {

// r <- P_K(r), K = {|r_T| <= mu r_N}; mu = 0 is the half-line r_T = 0, r_N >= 0.
void project_on_cone(double *r, double mu);

// project_on_cone for each of nc contacts: r_a = r[3a .. 3a+3) on its mu[a].
void project_on_cones(double *r, const double *mu, int64_t nc);

// r <- the projection on {r_N >= 0, |r_T| <= R} (Tresca); R < 0 is taken as 0.
void project_on_disk(double *r, double R);

// Squared natural-map residual of one contact: |r - P_K(r - (u + mu|u_T| e_N))|^2.
double residual_sq(const double *r, const double *u, double mu);

// max(|q|, |r|, |u|), or 1 where that is below DBL_EPSILON: the scale of a relative residual.
double relative_scale(const double *q, const double *r, const double *u);

// The one-contact natural-map residual of r, |r - P_K(r - u^)| with u = W r + q, and the
// same divided by relative_scale(q, r, u) (the measure of the local tolerance).
double contact_residual(const double *W, const double *q, double mu, const double *r,
                        double *relative = nullptr);

}  // namespace frix::coulomb
