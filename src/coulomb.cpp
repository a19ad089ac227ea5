#include "coulomb.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>

#include "vec.hpp"

namespace frix::coulomb {

using vec::norm2d;
using vec::norm3;

void project_on_cone(double *r, double mu) {
    const double nT = norm2d(r[1], r[2]);
    if (nT <= mu * r[0]) return;  // inside (this also keeps r_N >= 0 with r_T = 0 when mu = 0)
    if (mu * nT <= -r[0]) {       // polar cone
        r[0] = r[1] = r[2] = 0.0;
        return;
    }
    const double rN = (mu * nT + r[0]) / (1.0 + mu * mu);
    const double k = mu * rN / nT;  // nT > 0 here: nT = 0 is inside or polar
    r[0] = rN;
    r[1] *= k;
    r[2] *= k;
}

void project_on_cones(double *r, const double *mu, int64_t nc) {
    for (int64_t a = 0; a < nc; ++a) project_on_cone(r + 3 * a, mu[a]);
}

void project_on_disk(double *r, double R) {
    if (r[0] < 0.0) r[0] = 0.0;
    R = std::max(R, 0.0);
    const double nT = norm2d(r[1], r[2]);
    if (nT > R) {
        const double k = R / nT;
        r[1] *= k;
        r[2] *= k;
    }
}

double residual_sq(const double *r, const double *u, double mu) {
    const double ut = std::hypot(u[1], u[2]);
    double z[3] = {r[0] - (u[0] + mu * ut), r[1] - u[1], r[2] - u[2]};
    project_on_cone(z, mu);
    const double d0 = r[0] - z[0], d1 = r[1] - z[1], d2 = r[2] - z[2];
    return d0 * d0 + d1 * d1 + d2 * d2;
}

double relative_scale(const double *q, const double *r, const double *u) {
    const double s = std::max({norm3(q), norm3(r), norm3(u)});
    return s > DBL_EPSILON ? s : 1.0;
}

double contact_residual(const double *W, const double *q, double mu, const double *r,
                        double *relative) {
    double u[3];
    for (int i = 0; i < 3; ++i) u[i] = W[i] * r[0] + W[3 + i] * r[1] + W[6 + i] * r[2] + q[i];
    const double res = std::sqrt(residual_sq(r, u, mu));
    if (relative) *relative = res / relative_scale(q, r, u);
    return res;
}

}  // namespace frix::coulomb
