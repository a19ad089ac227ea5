// The error measures (../DESIGN.md "Error measures"), and the public entry points that
// evaluate them for a given r.
#include "measures.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <vector>

#include "error_state.hpp"
#include "coulomb.hpp"
#include "rolling.hpp"

namespace {

// Squares of values beyond these bounds overflow or lose all precision; sums inside them are
// exact enough, and they keep the plain arithmetic (the same numbers as Siconos) on every
// physical problem. Problems scaled by 1e+-200 take the rescaled path.
constexpr double kSafeSumMin = 1e-280, kSafeSumMax = 1e280;

}  // namespace

namespace frix {

double max_abs(const double *x, int64_t n) {
    double a = 0.0;
    for (int64_t i = 0; i < n; ++i) a = std::max(a, std::fabs(x[i]));
    return a;
}

bool in_safe_range(double s) { return s > kSafeSumMin && s < kSafeSumMax; }

// Both measures are positively homogeneous, so the caller multiplies the results back.
// Dividing, not multiplying by 1/divisor, which overflows for a subnormal divisor.
void rescaled_residual(const double *r, const double *u, const double *mu, int64_t first, int64_t end,
                       double divisor, double &sum, double &cone) {
    sum = 0.0;
    cone = 0.0;
    for (int64_t a = first; a < end; ++a) {
        const double ra[3] = {r[3 * a] / divisor, r[3 * a + 1] / divisor, r[3 * a + 2] / divisor};
        const double ua[3] = {u[3 * a] / divisor, u[3 * a + 1] / divisor, u[3 * a + 2] / divisor};
        sum += frix::coulomb::residual_sq(ra, ua, mu[a]);
        double p[3] = {ra[0], ra[1], ra[2]};
        frix::coulomb::project_on_cone(p, mu[a]);
        const double d0 = ra[0] - p[0], d1 = ra[1] - p[1], d2 = ra[2] - p[2];
        cone = std::max(cone, std::sqrt(d0 * d0 + d1 * d1 + d2 * d2));
    }
}

double norm2(const double *x, int64_t n) {
    double s = 0.0;
    for (int64_t i = 0; i < n; ++i) s += x[i] * x[i];
    if (in_safe_range(s)) return std::sqrt(s);
    const double a = max_abs(x, n);
    if (a == 0.0) return 0.0;
    s = 0.0;
    for (int64_t i = 0; i < n; ++i) s += (x[i] / a) * (x[i] / a);
    return a * std::sqrt(s);
}

namespace {

// scale^2 * ssq += other_scale^2 * other_ssq, kept without overflow or underflow (LAPACK's
// dnrm2 update; one square x^2 is (|x|, 1)).
void add_scaled_squares(double &scale, double &ssq, double other_scale, double other_ssq) {
    if (other_scale == 0.0) return;  // (a NaN goes on into ssq, as it should)
    if (scale < other_scale) {
        ssq = other_ssq + ssq * (scale / other_scale) * (scale / other_scale);
        scale = other_scale;
    } else {
        ssq += other_ssq * (other_scale / scale) * (other_scale / scale);
    }
}

// |s - P_K(s - u^)| for one contact, written so that no term of s cancels against another:
// with |s| >> |u^| (a runaway r) the plain formula rounds the residual to 0.
double stable_natural_residual(const double *s, const double *u, double mu) {
    const double ut = std::hypot(u[1], u[2]);
    const double uh[3] = {u[0] + mu * ut, u[1], u[2]};
    const double x[3] = {s[0] - uh[0], s[1] - uh[1], s[2] - uh[2]};
    const double xt = std::hypot(x[1], x[2]);
    if (xt <= mu * x[0]) return std::sqrt(uh[0] * uh[0] + uh[1] * uh[1] + uh[2] * uh[2]);  // P_K(x) = x
    if (mu * xt <= -x[0]) return std::sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);    // P_K(x) = 0
    // P_K(x) = a (1, mu x_t / |x_t|), a = (x_n + mu |x_t|) / (1 + mu^2); the differences of
    // norms by |a|^2 - |b|^2 = (a - b)(a + b).
    const double st = std::hypot(s[1], s[2]);
    const double xt_minus_st = xt + st > 0.0
                                   ? (uh[1] * uh[1] + uh[2] * uh[2] - 2.0 * (s[1] * uh[1] + s[2] * uh[2])) / (xt + st)
                                   : 0.0;
    const double gap = st - mu * s[0];                                         // <= 0 inside K
    const double delta = (-uh[0] + mu * xt_minus_st + mu * gap) / (1.0 + mu * mu);  // a - s_n
    const double rn = -delta;
    const double lateral = xt_minus_st + gap;  // |x_t| - mu s_n
    double rt[2];
    for (int i = 0; i < 2; ++i)
        rt[i] = (s[1 + i] * lateral + mu * s[0] * uh[1 + i]) / xt - mu * delta * x[1 + i] / xt;
    return std::sqrt(rn * rn + rt[0] * rt[0] + rt[1] * rt[1]);
}

// |s - P_K(s - u^)| for s = w r (one contact): computed on (s, u) / max|.|, where every
// square is in range, and scaled back (the residual is positively homogeneous).
double scaled_contact_residual(const double *r, const double *u, double mu, double w) {
    const double s[3] = {w * r[0], w * r[1], w * r[2]};
    double c = 0.0;
    for (int i = 0; i < 3; ++i) c = std::max({c, std::fabs(s[i]), std::fabs(u[i])});
    if (c == 0.0 || !std::isfinite(c)) return c;
    const double x[3] = {s[0] / c, s[1] / c, s[2] / c}, y[3] = {u[0] / c, u[1] / c, u[2] / c};
    return c * stable_natural_residual(x, y, mu);
}

}  // namespace

void MeasureParts::add(const MeasureParts &o) {
    add_scaled_squares(scaled_scale, scaled_ssq, o.scaled_scale, o.scaled_ssq);
    residual_sq += o.residual_sq;
    cone = std::max(cone, o.cone);
    penetration = std::max(penetration, o.penetration);
    complementarity = std::max(complementarity, o.complementarity);
    r_sq += o.r_sq;
    u_sq += o.u_sq;
}

MeasureParts measure_parts(const double *r, const double *u, const double *mu, const double *weight, int64_t first,
                           int64_t end) {
    MeasureParts m;
    rescaled_residual(r, u, mu, first, end, 1.0, m.residual_sq, m.cone);
    for (int64_t a = first; a < end; ++a) {
        const double *ra = r + 3 * a, *ua = u + 3 * a;
        add_scaled_squares(m.scaled_scale, m.scaled_ssq,
                           std::fabs(scaled_contact_residual(ra, ua, mu[a], weight ? weight[a] : 1.0)), 1.0);
        m.penetration = std::max(m.penetration, -ua[0]);
        const double uhat_n = ua[0] + mu[a] * std::hypot(ua[1], ua[2]);
        m.complementarity = std::max(m.complementarity, std::fabs(ra[0] * uhat_n + ra[1] * ua[1] + ra[2] * ua[2]));
    }
    for (int64_t i = 3 * first; i < 3 * end; ++i) m.r_sq += r[i] * r[i];
    for (int64_t i = 3 * first; i < 3 * end; ++i) m.u_sq += u[i] * u[i];
    return m;
}

namespace {

// The rescue of the contacts all held here.
class WholeRescue : public MeasureRescue {
   public:
    WholeRescue(const double *r, const double *u, const double *mu, int64_t nc) : r_(r), u_(u), mu_(mu), nc_(nc) {}
    double max_abs_ru() override { return std::max(max_abs(r_, 3 * nc_), max_abs(u_, 3 * nc_)); }
    void residual(double divisor, double &sum, double &cone) override {
        rescaled_residual(r_, u_, mu_, 0, nc_, divisor, sum, cone);
    }
    double norm_r() override { return norm2(r_, 3 * nc_); }
    double norm_u() override { return norm2(u_, 3 * nc_); }

   private:
    const double *r_, *u_, *mu_;
    int64_t nc_;
};

}  // namespace

Measures measures_from_parts(const MeasureParts &all, const double *r, const double *u, const double *mu,
                             int64_t nc, double norm_q, double free) {
    WholeRescue rescue(r, u, mu, nc);
    return measures_from_parts(all, rescue, norm_q, free);
}

Measures measures_from_parts(const MeasureParts &all, MeasureRescue &rescue, double norm_q, double free) {
    Measures m;
    m.residual_absolute = std::sqrt(all.residual_sq);
    m.cone_violation = all.cone;
    if (!in_safe_range(all.residual_sq)) {
        // Squares overflowed or underflowed (e.g. a problem scaled by 1e+-200): redo on
        // (r, u) / max|.|, where every square is in range, and scale the results back.
        const double a = rescue.max_abs_ru();
        if (a > 0.0) {
            double sum, cone;
            rescue.residual(a, sum, cone);
            m.residual_absolute = a * std::sqrt(sum);
            m.cone_violation = cone * a;
        }
    }
    m.residual_scaled = all.scaled_scale * std::sqrt(all.scaled_ssq);
    m.penetration = all.penetration;
    m.complementarity = all.complementarity;
    m.norm_r = in_safe_range(all.r_sq) ? std::sqrt(all.r_sq) : rescue.norm_r();
    m.norm_u = in_safe_range(all.u_sq) ? std::sqrt(all.u_sq) : rescue.norm_u();
    return with_norm_q(m, norm_q, free);
}

Measures measures_from_ru(const double *r, const double *u, const double *mu, const double *weight, int64_t nc,
                          double norm_q, double free) {
    return measures_from_parts(measure_parts(r, u, mu, weight, 0, nc), r, u, mu, nc, norm_q, free);
}

namespace {

// a / b for b > 0, DBL_MAX where that overflows: an error stays finite.
double clamped_ratio(double a, double b) {
    const double x = a / b;
    return std::isfinite(x) ? x : DBL_MAX;
}

}  // namespace

Measures with_norm_q(Measures m, double norm_q, double free) {
    m.norm_q = norm_q;
    m.norm_free = free >= 0.0 ? free : norm_q;
    // Siconos 4.4 divides only when the scale is meaningful (fc3d_compute_error).
    const double scale = std::max({m.norm_q, m.norm_r, m.norm_u});
    m.relative = scale > DBL_EPSILON ? m.residual_absolute / scale : m.residual_absolute;
    // No absolute fallback below DBL_EPSILON: a problem scaled by 1e-17 keeps its relative
    // error. Only q = 0 (then r = 0 solves it) leaves the bare residual.
    m.q_relative = norm_q > 0.0 ? clamped_ratio(m.residual_absolute, norm_q) : m.residual_absolute;
    const double velocity = std::max(m.norm_free, m.norm_u);
    m.scaled = velocity > 0.0 ? clamped_ratio(m.residual_scaled, velocity)
                              : (m.residual_scaled > 0.0 ? DBL_MAX : 0.0);
    return m;
}

namespace {

// The larger of a contact measure and an equilibrium residual; NaN in either stays NaN.
double with_equilibrium(double contact, double equilibrium) {
    return std::isnan(contact) || std::isnan(equilibrium) ? NAN : std::max(contact, equilibrium);
}

}  // namespace

double relative_equilibrium(double res, double norm_f, double norm_mv, double norm_hr) {
    const double scale = std::max({norm_f, norm_mv, norm_hr});
    return scale > DBL_EPSILON ? res / scale : res;
}

double scaled_equilibrium(double scaled_res, double norm_df, double norm_dhr) {
    const double scale = std::max(norm_df, norm_dhr);
    return scale > 0.0 ? clamped_ratio(scaled_res, scale) : (scaled_res > 0.0 ? DBL_MAX : 0.0);
}

double selected_error(const Measures &m, int64_t measure_kind) {
    switch (measure_kind) {
        case FRIX_MEASURE_RELATIVE: return m.global ? with_equilibrium(m.relative, m.equilibrium) : m.relative;
        case FRIX_MEASURE_Q_RELATIVE:
            return m.global ? with_equilibrium(m.q_relative, m.equilibrium) : m.q_relative;
        default: return m.global ? with_equilibrium(m.scaled, m.equilibrium_scaled) : m.scaled;
    }
}

void record_measures(frix_info &info, const Measures &m, int64_t measure_kind) {
    info.error_relative = m.relative;
    info.error_q_relative = m.q_relative;
    info.error_scaled = selected_error(m, FRIX_MEASURE_SCALED);
    info.error_contact = m.scaled;
    info.equilibrium = m.equilibrium;
    info.equilibrium_scaled = m.equilibrium_scaled;
    info.residual_absolute = m.residual_absolute;
    info.cone_violation = m.cone_violation;
    info.penetration = m.penetration;
    info.complementarity = m.complementarity;
    info.error = selected_error(m, measure_kind);
}

}  // namespace frix

namespace {

// How well (v, r) satisfies the dynamics M v = H r + f: m.equilibrium and
// m.equilibrium_scaled (Measures).
void equilibrium_residuals(const frix_problem &p, const double *r, const double *v, frix::Measures &m) {
    const int64_t n = p.n;
    std::vector<double> mv(n), hr(n, 0.0), d(n);
    frix::matrix_gemv(*p.M, 1.0, v, 0.0, mv.data());
    if (p.nc > 0) frix::matrix_gemv(*p.H, 1.0, r, 0.0, hr.data());
    for (int64_t i = 0; i < n; ++i) d[i] = mv[i] - hr[i] - p.f[i];
    double res = 0.0;
    for (int64_t i = 0; i < n; ++i) res += d[i] * d[i];
    m.equilibrium = frix::relative_equilibrium(std::sqrt(res), frix::norm2(p.f, n), frix::norm2(mv.data(), n),
                                               frix::norm2(hr.data(), n));
    // The scaled one: every dof weighted by its own 1 / sqrt(M_ii), hr and d reused for D H r
    // and D d, mv for D f.
    const bool weighted = (int64_t)p.dof_weight.size() == n;
    for (int64_t i = 0; i < n; ++i) {
        const double di = weighted ? p.dof_weight[i] : 1.0;
        d[i] *= di;
        hr[i] *= di;
        mv[i] = di * p.f[i];
    }
    m.equilibrium_scaled =
        frix::scaled_equilibrium(frix::norm2(d.data(), n), frix::norm2(mv.data(), n), frix::norm2(hr.data(), n));
}

}  // namespace

namespace frix {

Measures rolling_measures_from_ru(const frix_problem &p, const double *r, const double *u, double norm_q,
                                  double free) {
    double res_scale = 0.0, res_ssq = 1.0, sc_scale = 0.0, sc_ssq = 1.0;
    Measures m;
    const int size = contact_size(p);
    for (int64_t a = 0; a < p.nc; ++a) {
        const rolling::Cones k = rolling::cones_of(p, a);
        const double *ra = r + size * a, *ua = u + size * a, w = p.weight.empty() ? 1.0 : p.weight[(size_t)a];
        add_scaled_squares(res_scale, res_ssq, std::fabs(rolling::residual(ra, ua, k)), 1.0);
        double sa[6];
        for (int i = 0; i < size; ++i) sa[i] = w * ra[i];
        add_scaled_squares(sc_scale, sc_ssq, std::fabs(rolling::residual(sa, ua, k)), 1.0);
        m.cone_violation = std::max(m.cone_violation, rolling::cone_distance(ra, k));
        m.penetration = std::max(m.penetration, -ua[0]);
        double uh[6];
        rolling::shifted_velocity(ua, k, uh);
        double dot = 0.0;
        for (int i = 0; i < size; ++i) dot += ra[i] * uh[i];
        m.complementarity = std::max(m.complementarity, std::fabs(dot));
    }
    m.residual_absolute = res_scale * std::sqrt(res_ssq);
    m.residual_scaled = sc_scale * std::sqrt(sc_ssq);
    m.norm_r = norm2(r, size * p.nc);
    m.norm_u = norm2(u, size * p.nc);
    return with_norm_q(m, norm_q, free);
}

namespace {

// The contact measures of (r, u) for p's kind of contact (three or five entries).
Measures contact_measures(const frix_problem &p, const double *r, const double *u, double norm_q, double free) {
    return is_rolling(p) ? rolling_measures_from_ru(p, r, u, norm_q, free)
                         : measures_from_ru(r, u, p.mu, p.weight.data(), p.nc, norm_q, free);
}

}  // namespace

Measures local_measures(const frix_problem &p, const double *r, double *u) {
    const int64_t m = contact_size(p) * p.nc;
    if (m == 0) return Measures{};
    matrix_gemv(*p.W, 1.0, r, 0.0, u);
    for (int64_t i = 0; i < m; ++i) u[i] += p.q[i];
    return contact_measures(p, r, u, norm2(p.q, m), -1.0);
}

Measures global_measures(const frix_problem &p, const double *r, const double *v, double *u,
                         double *equilibrium) {
    const int64_t m = contact_size(p) * p.nc;
    if (m > 0) matrix_gemv_transposed(*p.H, 1.0, v, 0.0, u);
    for (int64_t i = 0; i < m; ++i) u[i] += p.w[i];
    Measures meas = contact_measures(p, r, u, norm2(p.w, m), free_velocity(p));
    meas.global = true;
    equilibrium_residuals(p, r, v, meas);
    if (equilibrium) *equilibrium = meas.equilibrium;
    return meas;
}

}  // namespace frix

namespace {

frix_error measure(const char *where, const frix_problem *p, const double *r, const double *v,
                   double *u_out, frix_info &info) {
    using frix::fail;
    if (!p) return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: problem is NULL", where);
    const int64_t m = frix::contact_size(*p) * p->nc;
    if (m > 0 && !r) return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: r is NULL", where);
    if (!frix::is_local_form(*p) && p->n > 0 && !v)
        return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: v is required for a global problem", where);
    if (frix_error e = frix::check_problem_vectors(*p)) return e;
    for (int64_t i = 0; i < m; ++i)
        if (!std::isfinite(r[i]))
            return fail(FRIX_ERR_NOT_FINITE, "%s: r[%lld] is not finite", where, (long long)i);
    std::vector<double> u_work;
    double *u = u_out;
    if (!u) {
        u_work.resize(m);
        u = u_work.data();
    }
    info.contacts = p->nc;
    if (frix::is_local_form(*p)) {
        frix::record_measures(info, frix::local_measures(*p, r, u), FRIX_MEASURE_SCALED);
        return FRIX_OK;
    }
    for (int64_t i = 0; i < p->n; ++i)
        if (!std::isfinite(v[i]))
            return fail(FRIX_ERR_NOT_FINITE, "%s: v[%lld] is not finite", where, (long long)i);
    frix::record_measures(info, frix::global_measures(*p, r, v, u, &info.equilibrium), FRIX_MEASURE_SCALED);
    return FRIX_OK;
}

}  // namespace

extern "C" {

FRIX_API frix_error frix_problem_measure(const frix_problem *problem, const double *r,
                                         const double *v, double *u, frix_info *info) {
    return frix::guard("frix_problem_measure", [&]() -> frix_error {
        if (!info) return frix::fail(FRIX_ERR_INVALID_ARGUMENT, "frix_problem_measure: info is NULL");
        return measure("frix_problem_measure", problem, r, v, u, *info);
    });
}

FRIX_API frix_error frix_problem_error(const frix_problem *problem, const double *r,
                                       const double *v, double *error) {
    return frix::guard("frix_problem_error", [&]() -> frix_error {
        if (!error) return frix::fail(FRIX_ERR_INVALID_ARGUMENT, "frix_problem_error: error is NULL");
        frix_info info;
        if (frix_error e = measure("frix_problem_error", problem, r, v, nullptr, info)) return e;
        *error = info.error_scaled;
        return FRIX_OK;
    });
}

}  // extern "C"
