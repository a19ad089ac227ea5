// Solver 607 (gnsn-ac): semismooth Newton (Alart-Curnier) on the global problem's (v, r),
// with UMFPACK; W = H^T M^-1 H is never formed.
#pragma once

#include "src/solver_api.hpp"

namespace frix {

extern const SolverEntry kGlobalNsnAcEntry;

}  // namespace frix
