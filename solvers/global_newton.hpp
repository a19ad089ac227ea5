// The solvers of global problems that never form W = H^T M^-1 H: 607 (gnsn-ac), semismooth
// Newton (Alart-Curnier) on (v, r) with UMFPACK; 613 (gadmm, global_admm.cpp), ADMM with
// M + rho H H^T factorised; 901 (gnsn-al, global_al_newton.cpp), the augmented Lagrangian
// method with semismooth Newton on v and M + rho H J H^T factorised.
#pragma once

#include "src/solver_api.hpp"

namespace frix {

extern const SolverEntry kGlobalNsnAcEntry;
extern const SolverEntry kGlobalAdmmEntry;
extern const SolverEntry kGlobalAlNewtonEntry;

}  // namespace frix
