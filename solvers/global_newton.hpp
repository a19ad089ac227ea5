// The solvers of global problems that never form W = H^T M^-1 H: 607 (gnsn-ac), semismooth
// Newton (Alart-Curnier) on (v, r) with UMFPACK; 613 (gadmm, global_admm.cpp), ADMM with
// M + rho H H^T factorised; 901 (gnsn-al, global_al_newton.cpp), the augmented Lagrangian
// method with semismooth Newton on v and M + rho H J H^T factorised.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "src/solver_api.hpp"

namespace frix {

extern const SolverEntry kGlobalNsnAcEntry;

// gnsn-ac's constants, shared with its distributed run (libfrix_mpi).
namespace gnewton {
// Line search: Goldstein-Price's m1 and Armijo's sigma.
constexpr double kM1 = 0.01, kArmijo = 1e-4;
// Steps without halving the best error, after which the run stagnates.
constexpr int kStallSteps = 25;
// The Jacobian's regularisation delta (times the blocks' scale): its first value, and the
// value below which a full step drops it to 0.
constexpr double kDeltaStart = 1e-6, kDeltaFloor = 1e-8;
// After a step that no line search accepts, rho is cut by kRhoCut, at most kMaxRhoCuts times.
constexpr double kRhoCut = 0.1;
constexpr int kMaxRhoCuts = 4;
// Contacts whose exact Delassus blocks calibrate the lumped ones, and the underrating below
// which the lumped blocks are taken as they are (rigid bodies: the rho of before).
constexpr int kRhoSamples = 8;
constexpr double kUnderrateToCorrect = 2.0;

// The status that ends a run before its next step (err: the current error, it: steps taken),
// or FRIX_STATUS_NOT_RUN to take it. out_of_time() is asked last, when nothing else ends
// the run (it may be collective: every rank reaches it alike).
template <class OutOfTime>
frix_status status_before_step(double err, double tol, int64_t it, int64_t max_iter, const OutOfTime &out_of_time) {
    if (err <= tol) return FRIX_STATUS_CONVERGED;
    if (!std::isfinite(err)) return FRIX_STATUS_DIVERGED;
    if (it >= max_iter) return FRIX_STATUS_MAX_ITER;
    if (out_of_time()) return FRIX_STATUS_TIME_LIMIT;
    return FRIX_STATUS_NOT_RUN;
}

// What the steps decide for the next ones: the Jacobian's regularisation delta (times the
// blocks' scale), the cuts of rho, the best error and whether the run has stalled.
class Progress {
   public:
    explicit Progress(double error) : best_(error), reference_(error) {}
    double delta() const { return delta_; }
    // The Jacobian did not factorise: delta from kDeltaStart, a hundredfold each time.
    void factorisation_failed() { delta_ = delta_ == 0.0 ? kDeltaStart : delta_ * 100.0; }
    // A step of length t was taken: a full one lowers delta tenfold (to 0 below kDeltaFloor).
    void step_taken(double t) {
        failures_ = 0;
        ++taken_;
        if (t == 1.0) delta_ = delta_ < kDeltaFloor ? 0.0 : delta_ * 0.1;
    }
    // No line search accepted the step: delta rises tenfold. True when rho is to be cut by
    // kRhoCut: while no step has been taken, at most kMaxRhoCuts times (later a failed step
    // is a kink, not a scale).
    bool step_rejected() {
        ++failures_;
        delta_ = std::max(delta_ * 10.0, kDeltaStart);
        if (rho_cuts_ >= kMaxRhoCuts || taken_ > 0) return false;
        ++rho_cuts_;
        failures_ = 0;
        return true;
    }
    // Whether error is the best yet (the caller keeps its iterate).
    bool improved(double error) {
        if (!(error < best_)) return false;
        best_ = error;
        return true;
    }
    // kStallSteps steps without halving the best error, or 3 rejected steps in a row.
    bool stalled() {
        if (best_ < 0.5 * reference_) {
            reference_ = best_;
            since_ = 0;
            return false;
        }
        return ++since_ >= kStallSteps || failures_ >= 3;
    }
    double best() const { return best_; }

   private:
    double delta_ = 0.0, best_, reference_;
    int since_ = 0, failures_ = 0, rho_cuts_ = 0;
    int64_t taken_ = 0;
};

// slope plus the contacts' part of the merit's slope along (dr, H^T dv): Phi . (A dr + B H^T dv),
// A and B 9 values a contact (column-major).
inline double add_contacts_slope(double slope, const double *phi, const double *A, const double *B, const double *dr,
                                 const double *Htdv, int64_t nc) {
    for (int64_t a = 0; a < nc; ++a) {
        const double *Aa = A + 9 * a, *Ba = B + 9 * a, *d = dr + 3 * a, *du = Htdv + 3 * a;
        for (int i = 0; i < 3; ++i)
            slope += phi[3 * a + i] * (Aa[i] * d[0] + Aa[i + 3] * d[1] + Aa[i + 6] * d[2] + Ba[i] * du[0] +
                                       Ba[i + 3] * du[1] + Ba[i + 6] * du[2]);
    }
    return slope;
}

// Backtracking from t = 1, halved after each of at most max_trials trials: the first t with
// merit(t) <= ref + c t slope, else the t of the lowest merit below psi, else 0 (no step).
// trials counts the merits taken.
template <class Merit>
double backtrack(const Merit &merit, double psi, double ref, double c, double slope, int max_trials,
                 int64_t &trials) {
    double t = 1.0, best_t = 0.0, best_psi = psi;
    for (int k = 0; k < max_trials; ++k, t *= 0.5) {
        const double pt = merit(t);
        ++trials;
        if (pt < best_psi) best_psi = pt, best_t = t;
        if (pt <= ref + c * t * slope) return t;
    }
    return best_t;
}
}  // namespace gnewton
extern const SolverEntry kGlobalAdmmEntry;
extern const SolverEntry kGlobalAlNewtonEntry;

}  // namespace frix
