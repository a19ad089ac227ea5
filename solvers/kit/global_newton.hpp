// The solvers of global problems that never form W = H^T M^-1 H: 607 (gnsn-ac), semismooth
// Newton (Alart-Curnier) on (v, r) with UMFPACK; 613 (gadmm, gadmm.cpp), ADMM with
// M + rho H H^T factorised; 901 (gnsn-al, gnsn_al.cpp), the augmented Lagrangian
// method with semismooth Newton on v and M + rho H J H^T factorised.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "solvers/kit/newton_engine.hpp"
#include "src/solver_api.hpp"

namespace frix {


// gnsn-ac's constants and rules, shared with its distributed run (libfrix_mpi).
namespace gnsn_ac {
// After a step that no line search accepts, rho is cut by kRhoCut, at most kMaxRhoCuts times.
constexpr double kRhoCut = 0.1;
constexpr int kMaxRhoCuts = 4;
// Contacts whose exact Delassus blocks calibrate the lumped ones, and the underrating below
// which the lumped blocks are taken as they are (rigid bodies: the rho of before).
constexpr int kRhoSamples = 8;
constexpr double kUnderrateToCorrect = 2.0;

// gnsn-ac's Newton rules (kit/newton_engine.hpp) from its settings: delta from 0, the
// factorisation tried kit::kMaxFactorAttempts times whatever delta, Goldstein-Price taken as
// Armijo with m1, the callback's stop at once. Where W = H^T M^-1 H may be regular (3 nc <= n:
// a deformable body), the first step is full where it lowers the error; where it is singular
// (a rigid pile, whose r is not unique) a full first step can lead Newton along W's null space
// to a stall (spheres-in-a-box), and the merit's search decides.
inline kit::Rules rules_of(int line_search, int max_trials, bool w_may_be_regular) {
    kit::Rules rules;
    rules.search = kit::armijo_search_of(line_search, max_trials);
    rules.delta_start = 0.0;
    rules.delta_cap = INFINITY;
    rules.stop_at_once = true;
    rules.full_first_step_by_error = w_may_be_regular && rules.search.kind != kit::Search::kNone;
    return rules;
}

// The cuts of rho: rho can be far too large (a calibration missed by the samples, or a
// constant rho), and no step lowers the merit then. Until a step is accepted, a rejected step
// cuts it (later, a failed step is a kink, not a scale: notes/2026-11-28-newton-kit.md), at
// most kMaxRhoCuts times.
class RhoCuts {
   public:
    // After a rejected step, `taken` steps taken: whether to cut rho by kRhoCut now.
    bool cut(int64_t taken) {
        if (cuts_ >= kMaxRhoCuts || taken > 0) return false;
        ++cuts_;
        return true;
    }

   private:
    int cuts_ = 0;
};
}  // namespace gnsn_ac

}  // namespace frix
