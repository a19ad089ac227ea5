// The rolling-friction law for one contact (rolling.hpp).
#include "rolling.hpp"

#include <algorithm>
#include <cmath>

namespace frix::rolling {

int project_on_cone(double *r, double mu, double mu_r) {
    const double nt = std::sqrt(r[1] * r[1] + r[2] * r[2]);
    const double nm = std::sqrt(r[3] * r[3] + r[4] * r[4]);
    if (mu * nt + mu_r * nm <= -r[0]) {
        for (int i = 0; i < 5; ++i) r[i] = 0.0;
        return 0;
    }
    if (nt <= mu * r[0] && nm <= mu_r * r[0]) return 1;
    // The normal part t minimises (t - r_N)^2 + (|r_T| - mu t)_+^2 + (|m_R| - mu_r t)_+^2, a
    // strictly convex function: exactly one set of active cones fits its minimiser.
    const double both = (mu * nt + mu_r * nm + r[0]) / (mu_r * mu_r + mu * mu + 1.0);
    if (nt > mu * both && nm > mu_r * both) {
        r[0] = both;
        r[1] = mu * both * r[1] / nt;
        r[2] = mu * both * r[2] / nt;
        r[3] = mu_r * both * r[3] / nm;
        r[4] = mu_r * both * r[4] / nm;
        return 4;
    }
    const double friction = (mu * nt + r[0]) / (mu * mu + 1.0);
    if (nt > mu * friction && nm <= mu_r * friction) {
        r[0] = friction;
        r[1] = mu * friction * r[1] / nt;
        r[2] = mu * friction * r[2] / nt;
        return 2;
    }
    const double rolling = (mu_r * nm + r[0]) / (mu_r * mu_r + 1.0);
    if (nt <= mu * rolling && nm > mu_r * rolling) {
        r[0] = rolling;
        r[3] = mu_r * rolling * r[3] / nm;
        r[4] = mu_r * rolling * r[4] / nm;
        return 3;
    }
    // Rounding at a kink between two cases (Siconos leaves r unprojected there): of the
    // cases' normal parts, the one that minimises the distance function, and each tangential
    // part cut back to its cone: a point of K next to the projection.
    const auto distance = [&](double t) {
        const double a = std::max(nt - mu * t, 0.0), b = std::max(nm - mu_r * t, 0.0);
        return (t - r[0]) * (t - r[0]) + a * a + b * b;
    };
    double t = r[0] > 0.0 ? r[0] : 0.0;
    for (const double c : {both, friction, rolling})
        if (c >= 0.0 && distance(c) < distance(t)) t = c;
    const double ct = nt > mu * t ? mu * t / nt : 1.0, cm = nm > mu_r * t ? mu_r * t / nm : 1.0;
    r[0] = t;
    r[1] *= ct, r[2] *= ct, r[3] *= cm, r[4] *= cm;
    return ct < 1.0 ? (cm < 1.0 ? 4 : 2) : (cm < 1.0 ? 3 : 1);
}

void shifted_velocity(const double *u, double mu, double mu_r, double *uh) {
    uh[0] = u[0] + mu * std::sqrt(u[1] * u[1] + u[2] * u[2]) + mu_r * std::sqrt(u[3] * u[3] + u[4] * u[4]);
    for (int i = 1; i < 5; ++i) uh[i] = u[i];
}

double residual(const double *r, const double *u, double mu, double mu_r) {
    double c = 0.0;
    for (int i = 0; i < 5; ++i) c = std::max({c, std::fabs(r[i]), std::fabs(u[i])});
    if (c == 0.0) return 0.0;
    if (!std::isfinite(c)) return INFINITY;
    // Unscaled where every square is in range (the same numbers as Siconos's).
    const double s = c > 1e-150 && c < 1e150 ? 1.0 : c;
    double rs[5], us[5], uh[5], x[5];
    for (int i = 0; i < 5; ++i) rs[i] = r[i] / s, us[i] = u[i] / s;
    shifted_velocity(us, mu, mu_r, uh);
    for (int i = 0; i < 5; ++i) x[i] = rs[i] - uh[i];
    project_on_cone(x, mu, mu_r);
    double sum = 0.0;
    for (int i = 0; i < 5; ++i) sum += (rs[i] - x[i]) * (rs[i] - x[i]);
    return s * std::sqrt(sum);
}

double cone_distance(const double *r, double mu, double mu_r) {
    double p[5] = {r[0], r[1], r[2], r[3], r[4]};
    project_on_cone(p, mu, mu_r);
    double sum = 0.0;
    for (int i = 0; i < 5; ++i) sum += (r[i] - p[i]) * (r[i] - p[i]);
    return std::sqrt(sum);
}

}  // namespace frix::rolling
