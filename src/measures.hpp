// The error measures of ../DESIGN.md, in one place: every solver, the CLI (through the public
// API) and the tests use these functions and nothing else.
#pragma once

#include <cstdint>

#include "info.hpp"
#include "problem.hpp"

namespace frix {

struct Measures {
    double residual_absolute = 0;  // sqrt(sum_a |r_a - P_K(r_a - u^_a)|^2)
    double relative = 0;           // residual / max(|q|, |r|, |u|), if that max > DBL_EPSILON
    double q_relative = 0;         // residual / |q|, if |q| > 0 (else the residual)
    // The default measure (FRIX_MEASURE_SCALED): each contact's reaction in velocity units,
    // s_a = w_a r_a (w_a = frix_problem::weight), residual_scaled = sqrt(sum_a |s_a - P_K(s_a -
    // u^_a)|^2), and scaled = residual_scaled / max(|q|, |u|) (|q|: the free velocity's norm,
    // for a global problem free_velocity(p)). Unit-consistent (length, mass
    // and time units cancel) and, having no |r| below the line, out of reach of a runaway r.
    double residual_scaled = 0;
    double scaled = 0;
    double cone_violation = 0;     // max_a dist(r_a, K_a)
    double penetration = 0;        // max_a max(0, -u_N,a)
    double complementarity = 0;    // max_a |r_a . u^_a|
    double norm_q = 0, norm_r = 0, norm_u = 0;
    double norm_free = 0;  // the scaled measure's velocity floor (see measures_from_ru)
    // A global problem's equilibrium residual d = M v - H r - f (global_measures; NaN and
    // global = false for a local problem): equilibrium = |d| / max(|f|, |M v|, |H r|) goes
    // with the Siconos and |q| measures; equilibrium_scaled = |D d| / max(|D f|, |D H r|),
    // D = diag(M)^-1/2 (frix_problem::dof_weight), with the default one: each dof's force in
    // the same unit (sqrt of energy), so that a change of units, rotations' included, leaves
    // it, and no |M v| below the line, so that a runaway v cannot satisfy it.
    bool global = false;
    double equilibrium = NAN, equilibrium_scaled = NAN;
};

// |x|_2, without overflow or underflow for values far from 1 (problems scaled by 1e+-200).
double norm2(const double *x, int64_t n);

// All measures of (r, u), with u = W r + q (or H^T v + w) already computed by the caller,
// norm_q = |q|_2 (|w|_2 for a global problem) and weight the problem's contact weights.
// free: the norm of the velocity without contact forces, the scaled measure's floor (|q| for
// a local problem, free_velocity(p)); negative: norm_q.
Measures measures_from_ru(const double *r, const double *u, const double *mu, const double *weight, int64_t nc,
                          double norm_q, double free = -1.0);

// measures_from_ru's sums and maxima over contacts [first, end): threads may measure ranges
// apart and combine them (add) in a fixed order, so that the result does not depend on how
// many there are.
struct MeasureParts {
    double residual_sq = 0, cone = 0, penetration = 0, complementarity = 0, r_sq = 0, u_sq = 0;
    // The scaled residual's sum of squares as scale^2 * ssq (LAPACK's dnrm2): never overflows.
    double scaled_scale = 0, scaled_ssq = 1;
    void add(const MeasureParts &o);
};
MeasureParts measure_parts(const double *r, const double *u, const double *mu, const double *weight, int64_t first,
                           int64_t end);
// The measures from the parts of all nc contacts (sums out of the safe range are redone on
// r and u rescaled).
Measures measures_from_parts(const MeasureParts &all, const double *r, const double *u, const double *mu,
                             int64_t nc, double norm_q, double free = -1.0);

// What measures_from_parts redoes over all contacts when a sum of the parts left the safe
// range (a problem scaled by 1e+-200): for contacts held apart (by the processes of a
// distributed solve), which must combine their shares in a fixed order.
class MeasureRescue {
   public:
    virtual ~MeasureRescue() = default;
    // The largest |r_i| and |u_i|.
    virtual double max_abs_ru() = 0;
    // rescaled_residual's sum and maximum over all contacts, for the divisor given.
    virtual void residual(double divisor, double &sum, double &cone) = 0;
    // |r|_2 and |u|_2 (norm2 over all contacts).
    virtual double norm_r() = 0;
    virtual double norm_u() = 0;
};
Measures measures_from_parts(const MeasureParts &all, MeasureRescue &rescue, double norm_q, double free = -1.0);

// The sum over contacts [first, end) of the squared natural-map residual of (r, u) / divisor,
// and the largest distance of r_a / divisor to its cone.
void rescaled_residual(const double *r, const double *u, const double *mu, int64_t first, int64_t end,
                       double divisor, double &sum, double &cone);
// max_i |x_i|.
double max_abs(const double *x, int64_t n);
// Whether a sum of squares lies where the plain sums are exact enough (kSafeSumMin..Max).
bool in_safe_range(double sum_of_squares);

// m's errors on another scale: norm_q replaced (a reduced problem's answer measured as the
// global problem's, |w| for |q|: the residual, r and u are the same).
// free as in measures_from_ru (negative: norm_q).
Measures with_norm_q(Measures m, double norm_q, double free = -1.0);

// Computes u = W r + q (into u) and the measures of a local problem (of either kind of
// contact: three entries, or five for rolling friction).
Measures local_measures(const frix_problem &p, const double *r, double *u);

// Computes u = H^T v + w (into u) and the measures of a global problem (either kind of
// contact), equilibrium included; *equilibrium (may be null) receives m.equilibrium.
Measures global_measures(const frix_problem &p, const double *r, const double *v, double *u,
                         double *equilibrium);

// The measures of a rolling problem (5 entries a contact, 6 with spinning friction; rolling.hpp's
// residual): the same fields with the same normalisations, Measures::relative being Siconos
// 4.4's rolling_fc3d_compute_error (its norm = |q|). The scaled residual weighs every entry of
// r_a by the contact's weight (p.weight; empty: 1).
Measures rolling_measures_from_ru(const frix_problem &p, const double *r, const double *u, double norm_q,
                                  double free = -1.0);

// The two equilibrium residuals (Measures) from their norms, for a problem held whole or by
// ranks (mpi/): res = |d| over max(|f|, |M v|, |H r|), and scaled_res = |D d| over
// max(|D f|, |D H r|).
double relative_equilibrium(double res, double norm_f, double norm_mv, double norm_hr);
double scaled_equilibrium(double scaled_res, double norm_df, double norm_dhr);

// The value compared with the tolerance for a given frix_error_measure: for a global problem
// the larger of the contact measure and the matching equilibrium residual (equilibrium_scaled
// with the default measure), so that no answer out of equilibrium meets a tolerance.
double selected_error(const Measures &m, int64_t measure_kind);

// Copies the measures into info, and info.error = selected_error(m, measure_kind).
void record_measures(frix_info &info, const Measures &m, int64_t measure_kind);

}  // namespace frix
