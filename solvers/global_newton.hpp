// The solvers of global problems that never form W = H^T M^-1 H: 607 (gnsn-ac), semismooth
// Newton (Alart-Curnier) on (v, r) with UMFPACK; 613 (gadmm, global_admm.cpp), ADMM with
// M + rho H H^T factorised; 901 (gnsn-al, global_al_newton.cpp), the augmented Lagrangian
// method with semismooth Newton on v and M + rho H J H^T factorised.
#pragma once

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
}  // namespace gnewton
extern const SolverEntry kGlobalAdmmEntry;
extern const SolverEntry kGlobalAlNewtonEntry;

}  // namespace frix
