/* frix — solving, and the error measures of a given answer. Includes the registry
 * (frix_registry.h) and the result record (frix_info.h), which it once held. */
#ifndef FRIX_SOLVE_H
#define FRIX_SOLVE_H

#include <stdint.h>
#include "frix_export.h"
#include "frix_errors.h"
#include "frix_problem.h"
#include "frix_options.h"
#include "frix_registry.h"
#include "frix_info.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- Solving.
 * r (3nc) is read as the initial guess (warm start) and holds the result; u (3nc) receives
 * W r + q (or H^T v + w); v (n) is used only for global problems (NULL for local ones).
 * options may be NULL (the default solver with its defaults); info may be NULL.
 * Returns FRIX_OK when the solve ran, whatever its status; the status is in info. r and u
 * are always finite on return. A problem with no contacts, or whose contacts all separate
 * (every q_N >= 0 for a local problem), returns r = 0 at once with status CONVERGED; a local
 * problem whose warm start already meets the tolerance returns it unchanged, CONVERGED after
 * 0 iterations.
 * A local solver on a global problem works on W = H^T M^-1 H; where W would be larger than
 * the memory (a large deformable body makes it dense), FRIX_ERR_OUT_OF_MEMORY at once, before
 * it is formed: gnsn-ac (607) and auto solve such problems without W. A global problem whose M
 * is singular (a body held only by its contacts) is solved where the contacts hold it, and
 * refused with FRIX_ERR_NUMERICAL and the reason where they do not (docs/solvers.md). */
FRIX_API frix_error frix_solve(const frix_problem *problem, const frix_options *options,
                               double *r, double *u, double *v, frix_info *info);

/* ---- Error measures of a given (r[, v]) without solving: fills the measure keys of info
 * (FRIX_INFO_ERROR* , _CONE_VIOLATION, _PENETRATION, _COMPLEMENTARITY, _EQUILIBRIUM*), and
 * FRIX_INFO_ERROR with the default measure (FRIX_MEASURE_SCALED). u (optional, 3nc) receives
 * W r + q. */
FRIX_API frix_error frix_problem_measure(const frix_problem *problem, const double *r,
                                         const double *v, double *u, frix_info *info);
/* Existence check of a local or global problem: looks for a strictly feasible z (W z + q
 * in int K*) or a certificate that none exists (see frix_existence), by an accelerated
 * projected-gradient search on 1/2 dist^2(W z + q - t e, K*). Sets FRIX_INFO_EXISTENCE and
 * FRIX_INFO_EXISTENCE_MARGIN of info and leaves its other keys alone.
 * time_limit: seconds in [0, 1e9]; 0 = the default budget, about 1e9 multiply-adds (from
 * 10^6 steps for a tiny problem down to 1000 for a huge one, a step costing one or two
 * products with W or H) and never more than 2 s. Deterministic, except where a time limit
 * cuts the search short. FRIX_ERR_INVALID_ARGUMENT for a NULL problem or info or a
 * time_limit out of range; the problem's vectors are checked again as by frix_solve. */
FRIX_API frix_error frix_problem_check_existence(const frix_problem *problem, double time_limit,
                                                 frix_info *info);
/* Just the default measure (FRIX_INFO_ERROR_SCALED). */
FRIX_API frix_error frix_problem_error(const frix_problem *problem, const double *r,
                                       const double *v, double *error);

#ifdef __cplusplus
}
#endif

#endif /* FRIX_SOLVE_H */
