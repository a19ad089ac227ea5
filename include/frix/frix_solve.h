/* frix — the solver registry, solving, the result record and the error measures. */
#ifndef FRIX_SOLVE_H
#define FRIX_SOLVE_H

#include <stdint.h>
#include "frix_export.h"
#include "frix_errors.h"
#include "frix_problem.h"
#include "frix_options.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- Registry. Ids are stable and never renumbered; where an algorithm is the one of a
 * Siconos 4.4 FC3D solver it has that solver's number. Only solvers that really solve are
 * listed. */
enum {
    FRIX_SOLVER_NSGS = 500,
    FRIX_SOLVER_PROX = 502,        /* proximal point, a Newton solver inside */
    FRIX_SOLVER_NSN_AC = 504,      /* semismooth Newton, Alart-Curnier */
    FRIX_SOLVER_NSN_FB = 513,      /* semismooth Newton, Fischer-Burmeister */
    FRIX_SOLVER_NSN_NM = 520,      /* semismooth Newton, natural map */
    FRIX_SOLVER_GLOBAL_NSN_AC = 607, /* global (M, H) problems: Newton on (v, r), W never formed */
    FRIX_SOLVER_NSGS_VELOCITY = 501, /* NSGS keeping u = W r + q up to date */
    FRIX_SOLVER_TFP = 503,         /* Tresca fixed point, NSGS inside */
    FRIX_SOLVER_VI_FPP = 506,      /* VI fixed-point projection, self-adaptive step */
    FRIX_SOLVER_VI_EG = 507,       /* VI extragradient, self-adaptive step */
    FRIX_SOLVER_HP = 508,          /* hyperplane projection */
    FRIX_SOLVER_ACLM = 516,        /* Acary-Cadoux-Lemarechal-Malick fixed point on s = |u_T| */
    FRIX_SOLVER_ADMM = 523         /* ADMM on r = xi, W + rho I factorised */
};

FRIX_API int64_t frix_solver_count(void);
/* Id of the index-th registered solver (0 <= index < count), -1 if out of range. */
FRIX_API int frix_solver_id_at(int64_t index);
/* Short lower-case name ("nsgs"), NULL if the id is unknown. */
FRIX_API const char *frix_solver_name(int solver_id);
/* One paragraph: the algorithm, what it is good for, its options. NULL if unknown. */
FRIX_API const char *frix_solver_describe(int solver_id);
/* Accepts the frix name ("nsgs"), the Siconos spelling ("FRICTION_3D_NSGS" or "FC3D_NSGS",
 * any case) or the id as a decimal string. */
FRIX_API frix_error frix_solver_by_name(const char *name, int *solver_id);

/* ---- The result record of a solve, read by key. */
typedef struct frix_info frix_info;

typedef enum frix_info_key FRIX_ENUM_BASE {
    /* int keys */
    FRIX_INFO_STATUS = 1,          /* frix_status */
    FRIX_INFO_ITERATIONS = 2,
    FRIX_INFO_SOLVER_ID = 3,
    FRIX_INFO_CONTACTS = 4,
    FRIX_INFO_NEWTON_ITERATIONS = 5, /* Newton steps (PROX: summed over its inner solves) */
    FRIX_INFO_LINE_SEARCH_STEPS = 6, /* merit evaluations of the line searches */
    FRIX_INFO_FACTORIZATIONS = 7,    /* numeric factorisations (LU, Cholesky) */
    FRIX_INFO_SYMBOLIC_ANALYSES = 8, /* symbolic analyses (orderings); reused while the
                                        sparsity pattern is unchanged */
    FRIX_INFO_HYBRID_SWEEPS = 9,     /* NSGS sweeps run by a hybrid Newton's fallback */
    FRIX_INFO_INNER_ITERATIONS = 10, /* fixed points (503, 516): inner sweeps, summed over the
                                        outer iterations */
    /* double keys */
    FRIX_INFO_ERROR = 100,          /* the measure compared with the tolerance (FRIX_OPT_ERROR_MEASURE) */
    FRIX_INFO_ERROR_RELATIVE = 101, /* natural-map residual / max(|q|,|r|,|u|) (Siconos 4.4) */
    FRIX_INFO_ERROR_Q_RELATIVE = 102, /* natural-map residual / |q| */
    FRIX_INFO_RESIDUAL_ABSOLUTE = 103, /* the natural-map residual itself */
    FRIX_INFO_CONE_VIOLATION = 104, /* max over contacts of the distance of r_a to K_a */
    FRIX_INFO_PENETRATION = 105,    /* max over contacts of max(0, -u_N) */
    FRIX_INFO_COMPLEMENTARITY = 106, /* max over contacts of |r_a . u^_a| */
    FRIX_INFO_EQUILIBRIUM = 107,    /* global: |Mv - Hr - f| / max(|f|, |Mv|, |Hr|); NaN for local */
    FRIX_INFO_SOLVE_TIME = 120,     /* seconds, wall clock, whole frix_solve call */
    FRIX_INFO_TOLERANCE = 121,      /* the tolerance the solve was asked for */
    FRIX_INFO_FACTORIZATION_TIME = 122, /* seconds in symbolic analyses and factorisations */
    FRIX_INFO_SETUP_TIME = 123      /* global problems: seconds forming W = H^T M^-1 H and q
                                       (reduction route), 0 otherwise */
} frix_info_key;

FRIX_API frix_error frix_info_create(frix_info **out);
FRIX_API void frix_info_free(frix_info *info);
FRIX_API frix_error frix_info_get_int(const frix_info *info, frix_info_key key, int64_t *value);
FRIX_API frix_error frix_info_get_double(const frix_info *info, frix_info_key key, double *value);
/* Shortcuts for the four figures every caller reads. */
FRIX_API frix_status frix_info_status(const frix_info *info);
FRIX_API int64_t frix_info_iterations(const frix_info *info);
FRIX_API double frix_info_error(const frix_info *info);
FRIX_API double frix_info_solve_time(const frix_info *info);

/* ---- Solving.
 * r (3nc) is read as the initial guess (warm start) and holds the result; u (3nc) receives
 * W r + q (or H^T v + w); v (n) is used only for global problems (NULL for local ones).
 * options may be NULL (the default solver with its defaults); info may be NULL.
 * Returns FRIX_OK when the solve ran, whatever its status; the status is in info. r and u
 * are always finite on return. A problem with no contacts, or whose contacts all separate
 * (every q_N >= 0 for a local problem), returns r = 0 at once with status CONVERGED. */
FRIX_API frix_error frix_solve(const frix_problem *problem, const frix_options *options,
                               double *r, double *u, double *v, frix_info *info);

/* ---- Error measures of a given (r[, v]) without solving: fills the measure keys of info
 * (FRIX_INFO_ERROR* , _CONE_VIOLATION, _PENETRATION, _COMPLEMENTARITY, _EQUILIBRIUM), and
 * FRIX_INFO_ERROR with the relative measure. u (optional, 3nc) receives W r + q. */
FRIX_API frix_error frix_problem_measure(const frix_problem *problem, const double *r,
                                         const double *v, double *u, frix_info *info);
/* Just the default measure (FRIX_INFO_ERROR_RELATIVE). */
FRIX_API frix_error frix_problem_error(const frix_problem *problem, const double *r,
                                       const double *v, double *error);

#ifdef __cplusplus
}
#endif

#endif /* FRIX_SOLVE_H */
