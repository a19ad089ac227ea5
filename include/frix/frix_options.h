/* frix — solver options, set by key.
 *
 * frix_options_create(solver_id) fills the solver's defaults. Each key has a type (int or
 * double) and bounds (frix_options_bounds); a value outside them is refused with
 * FRIX_ERR_OPTION_RANGE and the options keep their previous value. A key the chosen solver
 * does not use is refused with FRIX_ERR_UNKNOWN_OPTION, so a typo never goes unnoticed.
 * Key values are pinned and only ever added.
 */
#ifndef FRIX_OPTIONS_H
#define FRIX_OPTIONS_H

#include <stdint.h>
#include "frix_export.h"
#include "frix_errors.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct frix_options frix_options;

typedef enum frix_option_key {
    FRIX_OPT_TOLERANCE = 1,       /* double: stop when the error measure <= this (default 1e-8) */
    FRIX_OPT_MAX_ITER = 2,        /* int: iteration limit (sweeps for NSGS) */
    FRIX_OPT_TIME_LIMIT = 3,      /* double: seconds of solve time, 0 = none */
    FRIX_OPT_VERBOSITY = 4,       /* int 0..3: 0 prints nothing; higher levels print to stderr */
    FRIX_OPT_ERROR_MEASURE = 5,   /* int, frix_error_measure: the measure compared with the tolerance */
    FRIX_OPT_LOCAL_SOLVER = 6,    /* int: one-contact solver id (FRIX_LOCAL_*) */
    FRIX_OPT_LOCAL_TOLERANCE = 7, /* double: one-contact solver tolerance */
    FRIX_OPT_LOCAL_MAX_ITER = 8,  /* int: one-contact solver iteration limit */
    FRIX_OPT_RELAXATION = 9,      /* double in (0, 2): r <- w r_new + (1-w) r_old */
    FRIX_OPT_SHUFFLE = 10,        /* int, frix_shuffle: order of the contacts in a sweep */
    FRIX_OPT_SEED = 11            /* int >= 0: seed of the shuffle (deterministic) */
} frix_option_key;

typedef enum frix_error_measure {
    /* The Siconos 4.4 measure: natural-map residual / max(|q|, |r|, |u|). */
    FRIX_MEASURE_RELATIVE = 0,
    /* The same residual / |q| (Acary, Bremond, Huber 2018). */
    FRIX_MEASURE_Q_RELATIVE = 1
} frix_error_measure;

typedef enum frix_shuffle {
    FRIX_SHUFFLE_NONE = 0,
    FRIX_SHUFFLE_ONCE = 1,
    FRIX_SHUFFLE_EACH_SWEEP = 2
} frix_shuffle;

/* One-contact solvers (values match the Siconos 4.4 ids of the same algorithms). */
typedef enum frix_local_solver {
    /* One projected step r <- P_K(r - rho (W_aa r + q_a + mu|u_T| e_N)), rho from W_aa. */
    FRIX_LOCAL_PROJECTION = 552,
    /* Exact stick and take-off cases, otherwise projected steps iterated with a
     * self-adaptive rho until the one-contact residual is below the local tolerance. */
    FRIX_LOCAL_PROJECTION_ITERATED = 553,
    /* The closed-form one-contact solution: exact take-off and stick, and sliding through
     * the root of the sliding-angle equation (Newton from the last sliding direction, roots
     * bracketed otherwise); the 553 iterations only where no valid root exists. */
    FRIX_LOCAL_CLOSED_FORM = 562
} frix_local_solver;

/* Called after each iteration; a non-zero return stops the solve with
 * FRIX_STATUS_STOPPED_BY_CALLBACK. `error` is the solver's current estimate (the light
 * error for NSGS between full checks). */
typedef int (*frix_progress_fn)(void *user_data, int64_t iteration, double error,
                                double elapsed_seconds);

/* solver_id: an id of the registry (frix_solvers.h). */
FRIX_API frix_error frix_options_create(int solver_id, frix_options **out);
FRIX_API frix_error frix_options_copy(const frix_options *src, frix_options **out);
FRIX_API void frix_options_free(frix_options *opts);

FRIX_API int frix_options_solver(const frix_options *opts);

FRIX_API frix_error frix_options_set_int(frix_options *opts, frix_option_key key, int64_t value);
FRIX_API frix_error frix_options_set_double(frix_options *opts, frix_option_key key, double value);
/* Reading an int key as double is allowed (exact for |value| < 2^53). */
FRIX_API frix_error frix_options_get_int(const frix_options *opts, frix_option_key key,
                                         int64_t *value);
FRIX_API frix_error frix_options_get_double(const frix_options *opts, frix_option_key key,
                                            double *value);
/* Inclusive bounds of a key for this solver, and whether the key is an int (1) or double (0). */
FRIX_API frix_error frix_options_bounds(const frix_options *opts, frix_option_key key,
                                        double *lower, double *upper, int *is_int);

/* Names: "tolerance", "max_iter", "time_limit", ... NULL / FRIX_ERR_UNKNOWN_OPTION if unknown. */
FRIX_API const char *frix_option_name(frix_option_key key);
FRIX_API frix_error frix_option_by_name(const char *name, frix_option_key *key);

/* fn may be NULL to remove the callback. */
FRIX_API frix_error frix_options_set_callback(frix_options *opts, frix_progress_fn fn,
                                              void *user_data);

#ifdef __cplusplus
}
#endif

#endif /* FRIX_OPTIONS_H */
