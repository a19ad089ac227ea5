// The existence check behind frix_problem_check_existence, for the solvers that want it
// without going through the C entry point (auto calls it when its solve fails).
#pragma once

#include <frix/frix_solve.h>

#include "problem.hpp"

namespace frix {

// The verdict of frix_existence for a validated problem (local or global), within
// time_limit seconds (0: the default budget of frix_problem_check_existence). *margin (may
// be null) receives the value documented for FRIX_INFO_EXISTENCE_MARGIN in frix_solve.h.
// Deterministic apart from where a time limit cuts the search; throws only std::bad_alloc.
frix_existence check_existence(const frix_problem &p, double time_limit, double *margin);

enum class Psd { Yes, No, Unknown };
// Whether a local problem's W has a positive semidefinite symmetric part, within `tolerance`
// (relative to its Gershgorin bound after Jacobi scaling): the Cholesky factorisation of
// S = D (W + W^T)/2 D + delta I, D = diag(S)^-1/2, delta = tolerance times that bound, exists
// exactly when S's least eigenvalue is above -delta (a congruence keeps the signs). Unknown
// where the factorisation would cost too much (existence_psd.cpp) or cannot be built.
Psd symmetric_part_psd(const frix_problem &p, double tolerance);

}  // namespace frix
