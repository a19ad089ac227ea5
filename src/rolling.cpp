// The rolling-friction law for one contact (rolling.hpp).
#include "rolling.hpp"

#include <algorithm>
#include <cmath>

namespace frix::rolling {

namespace {

// Six entries: the exact projection. Its normal part t minimises the strictly convex
// phi(t) = (t - r_N)^2 + sum_k (n_k - c_k t)_+^2 over the three parts k (n_k = |part k|, c_k its
// coefficient); on the minimiser's set S of parts cut back, t = (r_N + sum_S c_k n_k) /
// (1 + sum_S c_k^2). Of the eight candidates, the minimiser is the one where phi'/2 = t - r_N -
// sum_k c_k (n_k - c_k t)_+ vanishes: its slope is at least 1, so |phi'| bounds the distance to
// the minimiser (phi's own values would only fix t to the square root of the rounding).
int project_with_spin(double *r, double mu, double mu_r, double mu_s) {
    const double n[3] = {std::sqrt(r[1] * r[1] + r[2] * r[2]), std::sqrt(r[3] * r[3] + r[4] * r[4]), std::fabs(r[5])};
    const double c[3] = {mu, mu_r, mu_s};
    if (c[0] * n[0] + c[1] * n[1] + c[2] * n[2] <= -r[0]) {
        for (int i = 0; i < 6; ++i) r[i] = 0.0;
        return 0;
    }
    if (n[0] <= c[0] * r[0] && n[1] <= c[1] * r[0] && n[2] <= c[2] * r[0]) return 1;
    const auto slope = [&](double t) {
        double s = t - r[0];
        for (int k = 0; k < 3; ++k) s -= c[k] * std::max(n[k] - c[k] * t, 0.0);
        return std::fabs(s);
    };
    double t = std::max(r[0], 0.0), best = slope(t);
    for (int set = 1; set < 8; ++set) {
        double num = r[0], den = 1.0;
        for (int k = 0; k < 3; ++k)
            if (set & (1 << k)) num += c[k] * n[k], den += c[k] * c[k];
        const double candidate = num / den;
        if (candidate < 0.0) continue;
        const double value = slope(candidate);
        if (value < best) best = value, t = candidate;
    }
    r[0] = t;
    int cut = 0;
    const int first[3] = {1, 3, 5}, count[3] = {2, 2, 1};
    for (int k = 0; k < 3; ++k) {
        if (n[k] <= c[k] * t) continue;
        const double scale = c[k] * t / n[k];
        for (int i = first[k]; i < first[k] + count[k]; ++i) r[i] *= scale;
        cut |= 1 << k;
    }
    return 1 + cut;
}

}  // namespace

int project_on_cone(double *r, const Cones &k) {
    if (k.size == 6) return project_with_spin(r, k.mu, k.mu_r, k.mu_s);
    const double mu = k.mu, mu_r = k.mu_r;
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

void shifted_velocity(const double *u, const Cones &k, double *uh) {
    uh[0] = u[0] + k.mu * std::sqrt(u[1] * u[1] + u[2] * u[2]) + k.mu_r * std::sqrt(u[3] * u[3] + u[4] * u[4]);
    if (k.size == 6) uh[0] += k.mu_s * std::fabs(u[5]);
    for (int i = 1; i < k.size; ++i) uh[i] = u[i];
}

double residual(const double *r, const double *u, const Cones &k) {
    const int size = k.size;
    double c = 0.0;
    for (int i = 0; i < size; ++i) c = std::max({c, std::fabs(r[i]), std::fabs(u[i])});
    if (c == 0.0) return 0.0;
    if (!std::isfinite(c)) return INFINITY;
    // Unscaled where every square is in range (the same numbers as Siconos's).
    const double s = c > 1e-150 && c < 1e150 ? 1.0 : c;
    double rs[6], us[6], uh[6], x[6];
    for (int i = 0; i < size; ++i) rs[i] = r[i] / s, us[i] = u[i] / s;
    shifted_velocity(us, k, uh);
    for (int i = 0; i < size; ++i) x[i] = rs[i] - uh[i];
    project_on_cone(x, k);
    double sum = 0.0;
    for (int i = 0; i < size; ++i) sum += (rs[i] - x[i]) * (rs[i] - x[i]);
    return s * std::sqrt(sum);
}

double cone_distance(const double *r, const Cones &k) {
    double p[6] = {};
    for (int i = 0; i < k.size; ++i) p[i] = r[i];
    project_on_cone(p, k);
    double sum = 0.0;
    for (int i = 0; i < k.size; ++i) sum += (r[i] - p[i]) * (r[i] - p[i]);
    return std::sqrt(sum);
}

}  // namespace frix::rolling
