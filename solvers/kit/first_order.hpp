// What the first-order solvers share: the registry entries of vi.cpp, fixed_points.cpp and
// admm.cpp, the De Saxce map over the whole problem, the bookkeeping of an iteration loop
// (tolerance, iteration and time limits, callback, verbosity) with the error measured by the
// measures module, and the restarted Nesterov momentum of the two ADMMs.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "src/measures.hpp"
#include "src/monitor.hpp"
#include "src/solver_api.hpp"
#include "src/vec.hpp"

namespace frix {


namespace first_order {

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
    bool out_of_time() const { return monitor().out_of_time(); }
    // The Monitor on this loop's tolerance and iteration limit.
    Monitor monitor() const { return Monitor(ctx).with_limits(tol, max_iter); }
    // After iteration `it` whose full error is `error`: Monitor::verdict (converged, diverged,
    // callback, time limit, iteration limit), FRIX_STATUS_NOT_RUN to go on. r: the iterate,
    // when the solver keeps it apart from ctx.r (the Monitor watches it).
    frix_status verdict(int64_t it, double error, const double *r = nullptr) const {
        return monitor().verdict(it, error, r);
    }
    // The same after an iteration with an estimate only: Monitor::limits (callback, time
    // limit, iteration limit, in that order).
    frix_status limits(int64_t it, double estimate, const double *r = nullptr) const {
        return monitor().limits(it, estimate, r);
    }
    // The same after an iteration whose full error `error` was measured, without the error test.
    frix_status limits_measured(int64_t it, double error, const double *r = nullptr) const {
        const Monitor run = monitor();
        return run.limits_after_report(it, run.report(it, error, r));
    }
    // Whether r is not all zeros (a warm start).
    bool warm(const double *r) const {
        for (int64_t i = 0; i < m; ++i)
            if (r[i] != 0.0) return true;
        return false;
    }
};

// Nesterov's extrapolation of the ADMM pair (x, y) (admm.cpp: (z, y), gadmm.cpp:
// (r, xi)), restarted whenever the combined residual does not fall below kRestartEta times its
// last value (Goldstein, O'Donoghue, Setzer, Baraniuk 2014). Off, the next iteration starts
// from (x, y) itself.
class RestartedNesterov {
   public:
    RestartedNesterov(bool on, int64_t m) : on_(on), xh_(m), yh_(m), x_old_(m), y_old_(m) {}
    // Starts again from (x, y) without momentum: at the start, and after rho changed.
    void reset(const double *x, const double *y);
    // After an iteration that reached (x, y) with the combined residual `comb`.
    void advance(double comb, const double *x, const double *y);
    // The points the next iteration starts from.
    const double *x_hat() const { return xh_.data(); }
    const double *y_hat() const { return yh_.data(); }
    int64_t restarts() const { return restarts_; }

   private:
    static constexpr double kRestartEta = 0.999;
    bool on_;
    double alpha_ = 1.0, c_prev_ = INFINITY;
    int64_t restarts_ = 0;
    std::vector<double> xh_, yh_, x_old_, y_old_;
};

}  // namespace first_order
}  // namespace frix
