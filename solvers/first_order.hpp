// What the first-order solvers share: the registry entries of vi.cpp, fixed_points.cpp and
// admm.cpp, the De Saxce map over the whole problem, and the bookkeeping of an iteration
// loop (tolerance, iteration and time limits, callback, verbosity) with the error measured by
// the measures module.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdio>

#include "src/measures.hpp"
#include "src/monitor.hpp"
#include "src/solver_api.hpp"

namespace frix {

extern const SolverEntry kViFppEntry;  // vi.cpp
extern const SolverEntry kViEgEntry;
extern const SolverEntry kHpEntry;
extern const SolverEntry kTfpEntry;    // fixed_points.cpp
extern const SolverEntry kAclmEntry;
extern const SolverEntry kAdmmEntry;   // admm.cpp

namespace fo {

inline double dot(const double *x, const double *y, int64_t n) {
    double s = 0.0;
    for (int64_t i = 0; i < n; ++i) s += x[i] * y[i];
    return s;
}
inline double norm(const double *x, int64_t n) { return std::sqrt(dot(x, x, n)); }
// |x - y|
inline double distance(const double *x, const double *y, int64_t n) {
    double s = 0.0;
    for (int64_t i = 0; i < n; ++i) s += (x[i] - y[i]) * (x[i] - y[i]);
    return std::sqrt(s);
}

// u = W r + q and F = u + mu |u_T| e_N (the De Saxce map of the VI formulation).
void de_saxce_map(const frix_problem &p, const double *r, double *u, double *F);
// r <- P_K(r), contact by contact.
void project_on_cones(const frix_problem &p, double *r);
// |W_aa|_2 (the scale of W seen by contact a); NaN without a usable diagonal block.
double contact_diagonal_norm(const frix_problem &p, int64_t a);
// max_a |W_aa|_2 and mean_a |W_aa|_2 (the scale of W seen by one contact).
void diagonal_scales(const frix_problem &p, double *max_norm, double *mean_norm);

// The common settings and the per-iteration bookkeeping of one solve.
class Loop {
   public:
    Loop(SolveContext &ctx, const char *name);

    const frix_problem &p;
    const frix_options &o;
    SolveContext &ctx;
    const char *name;
    double tol;
    int64_t max_iter;
    int64_t verbosity;
    int64_t measure;
    double norm_q;
    int64_t m;  // 3 nc

    // The selected error of (r, u), u = W r + q already computed (no product).
    double error_ru(const double *r, const double *u) const {
        return selected_error(measures_from_ru(r, u, p.mu, p.weight.data(), p.nc, norm_q), measure);
    }
    // The same, computing u = W r + q into u.
    double error(const double *r, double *u) const {
        return selected_error(local_measures(p, r, u), measure);
    }
    // The scale the selected measure divides by: max(|q|, |u|) (scaled), max(|q|, |r|, |u|)
    // (Siconos's) or |q|; 1 below DBL_EPSILON.
    double scale(double norm_r, double norm_u) const;
    bool out_of_time() const { return Monitor(ctx).out_of_time(); }
    // Calls the callback (if any) with iteration `it` and `estimate`; true if it asks to stop.
    // r: the iterate, when the solver keeps it apart from ctx.r (the Monitor watches it).
    bool report(int64_t it, double estimate, const double *r = nullptr) const {
        return Monitor(ctx).report(it, estimate, r);
    }
    // After iteration `it` (not converged): the status that stops the loop, or
    // FRIX_STATUS_NOT_RUN to go on (callback, time limit, iteration limit, in that order).
    frix_status limits(int64_t it, double estimate, const double *r = nullptr) const {
        if (report(it, estimate, r)) return FRIX_STATUS_STOPPED_BY_CALLBACK;
        if (out_of_time()) return FRIX_STATUS_TIME_LIMIT;
        if (it >= max_iter) return FRIX_STATUS_MAX_ITER;
        return FRIX_STATUS_NOT_RUN;
    }
    // Whether r is not all zeros (a warm start).
    bool warm(const double *r) const {
        for (int64_t i = 0; i < m; ++i)
            if (r[i] != 0.0) return true;
        return false;
    }
};

}  // namespace fo
}  // namespace frix
