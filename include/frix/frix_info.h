/* frix — the result record of a solve (frix_info), the existence verdict and the stage records. */
#ifndef FRIX_INFO_H
#define FRIX_INFO_H

#include <stdint.h>
#include "frix_export.h"
#include "frix_errors.h"

#ifdef __cplusplus
extern "C" {
#endif

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
    FRIX_INFO_ISLANDS = 11,          /* auto: independent groups of contacts (connected
                                        components of W's block graph) solved separately */
    FRIX_INFO_SWITCHES = 12,         /* auto: solver changes made by its watchdog, all islands */
    FRIX_INFO_EXISTENCE = 13,        /* frix_existence: verdict of the existence check, when
                                        one ran (auto on failure, frix_problem_check_existence) */
    /* double keys */
    FRIX_INFO_ERROR = 100,          /* the measure compared with the tolerance (FRIX_OPT_ERROR_MEASURE) */
    FRIX_INFO_ERROR_RELATIVE = 101, /* natural-map residual / max(|q|,|r|,|u|) (Siconos 4.4) */
    FRIX_INFO_ERROR_Q_RELATIVE = 102, /* natural-map residual / |q| */
    FRIX_INFO_RESIDUAL_ABSOLUTE = 103, /* the natural-map residual itself */
    FRIX_INFO_CONE_VIOLATION = 104, /* max over contacts of the distance of r_a to K_a */
    FRIX_INFO_PENETRATION = 105,    /* max over contacts of max(0, -u_N) */
    FRIX_INFO_COMPLEMENTARITY = 106, /* max over contacts of |r_a . u^_a| */
    FRIX_INFO_EQUILIBRIUM = 107,    /* global: |Mv - Hr - f| / max(|f|, |Mv|, |Hr|); NaN for local */
    FRIX_INFO_ERROR_SCALED = 108,   /* the default measure, FRIX_MEASURE_SCALED: natural-map residual
                                       of (w_a r_a, u^_a) / max(|q|, |u|); for a global problem the
                                       larger of that and FRIX_INFO_EQUILIBRIUM_SCALED */
    FRIX_INFO_ERROR_CONTACT = 109,  /* the default measure's contact part alone (the natural-map
                                       residual above; = FRIX_INFO_ERROR_SCALED for local) */
    FRIX_INFO_EQUILIBRIUM_SCALED = 110, /* global: the default measure's equilibrium part,
                                       |D (Mv - Hr - f)| / max(|D f|, |D Hr|), D = diag(M)^-1/2;
                                       NaN for local */
    FRIX_INFO_SOLVE_TIME = 120,     /* seconds, wall clock, whole frix_solve call */
    FRIX_INFO_TOLERANCE = 121,      /* the tolerance the solve was asked for */
    FRIX_INFO_FACTORIZATION_TIME = 122, /* seconds in symbolic analyses and factorisations */
    FRIX_INFO_SETUP_TIME = 123,     /* global problems: seconds factorising M and forming q,
                                       and W = H^T M^-1 H on the reduction route; 0 for local */
    FRIX_INFO_EXISTENCE_MARGIN = 124, /* existence check: the best margin t* / |q|_rms, bounded
                                        from below (> 0, a solution exists) or from above
                                        (<= 0, no solution may exist); NaN when not checked
                                        or undetermined. See frix_existence */
    FRIX_INFO_REDUCTION_TIME = 125  /* global problems: of the setup time, the seconds forming
                                       W = H^T M^-1 H (0 when not formed, or kept by a
                                       persistent solver from an earlier solve) */
} frix_info_key;

/* Verdict of the existence check (frix_problem_check_existence). A solution exists when
 * some z puts W z + q strictly inside the dual cone K* at every contact (for a global
 * problem: some v with H^T v + w in int K*; Klarbring-Pang, Cadoux). When no such z exists
 * there is a certificate y in K, y != 0, with W y = 0 (H y = 0) and q.y <= 0 (w.y <= 0):
 * a self-equilibrated reaction in the friction cones that does no work, and a solution
 * may not exist.
 *
 * FRIX_INFO_EXISTENCE_MARGIN tells how far the problem is from the boundary between the
 * two: with e = (1, 0, 0) at every contact, t* = sup{t : some z has W z + q - t e in K* at
 * every contact}, divided by |q|_rms = sqrt(sum_a |q_a|^2 / nc) (|w|_rms for a global
 * problem). t* > 0 exactly when a strictly feasible z exists, and is often +inf (bodies
 * that can all move apart). The margin is
 *   GUARANTEED:  > 0, a lower bound: the margin of the z the check found, min_a (u_N,a -
 *                mu_a |u_T,a|) / |q|_rms with u = W z + q (+inf without contacts or with
 *                q = 0); 0 for a local problem without a strictly feasible z found but whose
 *                contacts all separate (q_N >= 0: r = 0 is a solution);
 *   DOUBTFUL:    <= 0, the bound of the certificate, q.y / (sum_a y_N,a |q|_rms), an upper
 *                bound of the margin where W y = 0 exactly; 0 means on the boundary (within
 *                1e-9: no strictly feasible z, though a solution may still exist);
 *   otherwise:   NaN.
 * y counts as W y = 0 when it does (almost) no work: y.W y <= 1e-12 lambda_max(W) |y|^2
 * and |W y|, |W^T y| <= 3e-6 lambda_max(W) |y|, W Jacobi-scaled (H^T diag(M)^-1 H for a
 * global problem). */
typedef enum frix_existence FRIX_ENUM_BASE {
    FRIX_EXISTENCE_NOT_CHECKED = 0,
    FRIX_EXISTENCE_GUARANTEED = 1,     /* a strictly feasible z was found: a solution exists,
                                          a failed solve is the solver's failure */
    FRIX_EXISTENCE_DOUBTFUL = 2,       /* a certificate y was found: no solution may exist,
                                          a failed solve may be the problem's fault */
    FRIX_EXISTENCE_UNDETERMINED = 3    /* the check ran out of its budget without either, or
                                          cannot decide (a rolling-friction problem: the check
                                          knows the three-component cones; it decides only
                                          a local one whose contacts all separate, GUARANTEED
                                          with margin 0) */
} frix_existence;
/* "not checked", "a solution exists", "no solution may exist", "undetermined". */
FRIX_API const char *frix_existence_describe(frix_existence verdict);

FRIX_API frix_error frix_info_create(frix_info **out);
FRIX_API void frix_info_free(frix_info *info);
FRIX_API frix_error frix_info_get_int(const frix_info *info, frix_info_key key, int64_t *value);
FRIX_API frix_error frix_info_get_double(const frix_info *info, frix_info_key key, double *value);
/* Shortcuts for the four figures every caller reads. */
FRIX_API frix_status frix_info_status(const frix_info *info);
FRIX_API int64_t frix_info_iterations(const frix_info *info);
FRIX_API double frix_info_error(const frix_info *info);
FRIX_API double frix_info_solve_time(const frix_info *info);
/* What the solve did, one line per step, for people: auto lists its analysis, its islands,
 * every solver it ran and why it switched. "" for a solver that has nothing to add. The
 * string belongs to info and lives until the next solve with it or frix_info_free. */
FRIX_API const char *frix_info_trace(const frix_info *info);

/* Stage records: the lines of frix_info_trace as data, in the same order (none for a solver
 * whose trace is empty). A record of a solver's run (auto's stages) has its solver id,
 * status, iterations, error and time; the others (auto's analysis and decisions) have
 * solver id 0, status FRIX_STATUS_NOT_RUN, 0 iterations and a NaN error. */
typedef enum frix_stage_key FRIX_ENUM_BASE {
    FRIX_STAGE_SOLVER_ID = 1,       /* int: the solver run, 0 for a record of another kind */
    FRIX_STAGE_STATUS = 2,          /* int: the run's frix_status */
    FRIX_STAGE_ITERATIONS = 3,      /* int */
    FRIX_STAGE_PART = 4,            /* int: the part (island) solved, from 1; 0: the whole problem */
    FRIX_STAGE_PART_CONTACTS = 5,   /* int: the part's contacts; 0 for the whole problem */
    FRIX_STAGE_RANDOM_STARTS = 6,   /* int: > 0 when the run went from that many random starts */
    FRIX_STAGE_STOPPED_BY_AUTO = 7, /* int: 1 when auto stopped the run (slow progress, its
                                       share of max_iter, a non-finite error: the note says) */
    FRIX_STAGE_ERROR = 100,         /* double: the run's error at its end */
    FRIX_STAGE_SECONDS = 101        /* double: the run's time */
} frix_stage_key;
FRIX_API int64_t frix_info_stage_count(const frix_info *info);
/* FRIX_ERR_DIMENSION for an index outside [0, count), FRIX_ERR_INVALID_ARGUMENT for a NULL
 * argument or a key of the other type. */
FRIX_API frix_error frix_info_stage_get_int(const frix_info *info, int64_t index, frix_stage_key key,
                                            int64_t *value);
FRIX_API frix_error frix_info_stage_get_double(const frix_info *info, int64_t index,
                                               frix_stage_key key, double *value);
/* The record's line of the trace, without its newline ("" for an index out of range); it
 * belongs to info and lives until the next call of this function with info, the next solve
 * with it or frix_info_free. */
FRIX_API const char *frix_info_stage_note(const frix_info *info, int64_t index);

#ifdef __cplusplus
}
#endif

#endif /* FRIX_INFO_H */
