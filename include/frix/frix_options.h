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

typedef enum frix_option_key FRIX_ENUM_BASE {
    FRIX_OPT_TOLERANCE = 1,       /* double: stop when the error measure <= this (default 1e-8) */
    FRIX_OPT_MAX_ITER = 2,        /* int: iteration limit (sweeps for NSGS) */
    FRIX_OPT_TIME_LIMIT = 3,      /* double: seconds of solve time, 0 = none; also ends the
                                     forming of W = H^T M^-1 H for a global problem; a
                                     factorisation that would overrun it (priced from its
                                     symbolic analysis) is not started */
    FRIX_OPT_VERBOSITY = 4,       /* int 0..3: 0 prints nothing; higher levels print to stderr */
    FRIX_OPT_ERROR_MEASURE = 5,   /* int, frix_error_measure: the measure compared with the tolerance
                                     (default FRIX_MEASURE_SCALED; by name: scaled, siconos,
                                     q_relative) */
    FRIX_OPT_LOCAL_SOLVER = 6,    /* int: one-contact solver id (FRIX_LOCAL_*) */
    FRIX_OPT_LOCAL_TOLERANCE = 7, /* double: one-contact solver tolerance */
    FRIX_OPT_LOCAL_MAX_ITER = 8,  /* int: one-contact solver iteration limit */
    FRIX_OPT_RELAXATION = 9,      /* double in (0, 2): r <- w r_new + (1-w) r_old */
    FRIX_OPT_SHUFFLE = 10,        /* int, frix_shuffle: order of the contacts in a sweep */
    FRIX_OPT_SEED = 11,           /* int >= 0: seed of the shuffle (deterministic) */
    /* Newton-type solvers (504, 513, 520, 502, 607) */
    FRIX_OPT_RHO_STRATEGY = 12,   /* int, frix_rho_strategy: the per-contact rho of Phi */
    FRIX_OPT_RHO = 13,            /* double > 0: rho of FRIX_RHO_CONSTANT; VI, HP (506-508): the
                                     initial (or fixed) step in units of 1 / max_a |W_aa|_2;
                                     ADMM (523): the penalty in units of mean_a |W_aa|_2 */
    FRIX_OPT_LINE_SEARCH = 14,    /* int, frix_line_search: on the merit 1/2 |Phi|^2 */
    FRIX_OPT_LINE_SEARCH_MAX_ITER = 15, /* int: trial steps per line search */
    FRIX_OPT_HYBRID = 16,         /* int, frix_hybrid: what to do when Newton stalls */
    FRIX_OPT_HYBRID_SWEEPS = 17,  /* int: NSGS sweeps per fallback of FRIX_HYBRID_NSGS */
    /* PROX (502) */
    FRIX_OPT_PROX_ALPHA = 18,     /* double >= 0: fixed proximal alpha, 0 = adapted to the error */
    FRIX_OPT_PROX_SIGMA = 19,     /* double > 0: adapted alpha = sigma * error^nu * scale(W) */
    FRIX_OPT_PROX_NU = 20,        /* double > 0: see FRIX_OPT_PROX_SIGMA */
    FRIX_OPT_INNER_SOLVER = 21,   /* int: PROX's inner Newton solver id (504, 513 or 520) */
    /* NSGS (500, 501) */
    FRIX_OPT_FREEZING = 22,       /* int >= 0: sweeps a settled contact is skipped, 0 = never */
    FRIX_OPT_ERROR_FREQUENCY = 23, /* int >= 1: the stopping test runs every k sweeps */
    /* First-order solvers (506, 507, 508, 523) */
    FRIX_OPT_RHO_ADAPTIVE = 24,   /* int 0/1: adapt rho (VI: self-adaptive step; ADMM: residual
                                     balancing) or keep FRIX_OPT_RHO fixed */
    /* Fixed points (503, 516) */
    FRIX_OPT_INNER_MAX_ITER = 25, /* int: inner sweeps per outer iteration */
    FRIX_OPT_INNER_TOLERANCE_RATIO = 26, /* double in (0, 1]: inner tolerance = ratio * outer error */
    /* ADMM (523), NSGS (500, 501, 902), auto (900) */
    FRIX_OPT_ACCELERATION = 27,   /* int 0/1: Nesterov acceleration with restart (default 1 for
                                     523 and for auto's NSGS stages (900), 0 for the NSGS ones,
                                     where it turns freezing off until it stalls) */
    /* auto (900) */
    FRIX_OPT_THREADS = 28,        /* int >= 1: threads auto may use to solve independent islands
                                     at once, and gnsgs (902) and auto's route through it to
                                     sweep domains of contacts at once (default 1; results do
                                     not depend on it) */
    FRIX_OPT_EXISTENCE_CHECK = 29, /* int 0/1, every solver: when the solve fails (not stopped
                                     by the callback), check whether a solution exists
                                     (frix_problem_check_existence; default 1), within 5 % of
                                     a time limit kept for it */
    /* NSGS (500, 501) */
    FRIX_OPT_DRIFT_WINDOW = 30,   /* int >= 0: every k sweeps, a steady drift of r is carried
                                     ahead to the next loss of contact; 0 = never (default) */
    /* Semismooth Newton (504, 513, 520) */
    FRIX_OPT_WATCHDOG = 31,       /* int >= 0: where the line search stalls but the full step
                                     halves the best error, take it and k - 1 more steps (full
                                     where the line search would cut them short), and go back
                                     unless the error fell tenfold; 0 = never. Default 5 for
                                     504 and 513, 0 for 520 */
    FRIX_OPT_MEMORY_LIMIT = 32,   /* double: bytes the solve may add to the process's memory;
                                     0 = what the process may use (the machine's or its
                                     control group's memory) less what it holds (default). A
                                     factorisation whose peak (priced from its symbolic
                                     analysis) would exceed what is left is not started:
                                     status FRIX_STATUS_MEMORY_LIMIT; auto leaves out the
                                     stages that would */
    /* NSGS (500, 501, 902) */
    FRIX_OPT_ANDERSON = 33        /* int 0..50: Anderson acceleration of the sweeps over the
                                     last k of them, 0 = off (default); in place of
                                     acceleration, freezing then off. auto takes it (depth 10)
                                     on global problems whose W may be regular (3 nc <= n) when
                                     its acceleration is on */,
    FRIX_OPT_CALLBACK_ESTIMATES = 34 /* int 0/1, every solver: 1 (default): the callback is
                                     called after every iteration, with the solver's current
                                     estimate; 0: only after iterations whose error was
                                     measured on the iterate by the option error_measure (the
                                     full checks of NSGS, not its light error; the outer steps
                                     of PROX, not its inner solves; for a global problem solved
                                     through W, none but the start's), so that every error it
                                     sees is the error of an iterate; a stop it asks for then
                                     waits for such an iteration */,
    FRIX_OPT_SECANT_START = 35    /* int 0/1, every solver, persistent solvers: 1 (default):
                                     a solve that continues from the last answer (r passed
                                     back unchanged), with the matrices and mu of the last two
                                     solves and data (q, or f and w) that moved along a line
                                     over them, starts from the secant prediction of the last
                                     two answers (frix_persistent.h); 0: from r as given */
} frix_option_key;

typedef enum frix_rho_strategy FRIX_ENUM_BASE {
    FRIX_RHO_CONSTANT = 0,   /* rho_N = rho_T = FRIX_OPT_RHO */
    FRIX_RHO_SPECTRAL = 1,   /* rho = 1 / |W_aa|_2 per contact */
    FRIX_RHO_SPLIT = 2       /* rho_N = 1 / W_aa,NN, rho_T = 1 / |W_aa,TT|_2 (AC); FB and the
                                natural map, which take one rho, use rho_N */
} frix_rho_strategy;

typedef enum frix_line_search FRIX_ENUM_BASE {
    FRIX_LINE_SEARCH_NONE = 0,            /* full Newton steps */
    FRIX_LINE_SEARCH_GOLDSTEIN_PRICE = 1, /* Goldstein-Price, m1 = 0.01, m2 = 0.99 (Siconos) */
    FRIX_LINE_SEARCH_ARMIJO = 2,          /* Armijo backtracking, sigma = 1e-4 */
    FRIX_LINE_SEARCH_NONMONOTONE = 3      /* Armijo against the max of the last 8 merits */
} frix_line_search;

typedef enum frix_hybrid FRIX_ENUM_BASE {
    FRIX_HYBRID_NONE = 0,  /* Newton only */
    FRIX_HYBRID_NSGS = 1   /* when Newton stalls, NSGS sweeps, then Newton again */
} frix_hybrid;

typedef enum frix_error_measure FRIX_ENUM_BASE {
    /* The Siconos 4.4 measure: natural-map residual / max(|q|, |r|, |u|). */
    FRIX_MEASURE_RELATIVE = 0,
    /* The same residual / |q| (Acary, Bremond, Huber 2018). */
    FRIX_MEASURE_Q_RELATIVE = 1,
    /* The default: the natural-map residual with each contact's reaction in velocity units,
     * s_a = w_a r_a (w_a its normal self-compliance W_aa[0][0]; for a global problem
     * sum_i H_i,a^2 / M_ii), divided by max(|q|, |u|); for a global problem, the larger of that
     * and the equilibrium residual |D (M v - H r - f)| / max(|D f|, |D H r|), D = diag(M)^-1/2.
     * A change of units does not change it, and a runaway r or v cannot satisfy it. On a global
     * problem the other two measures are also taken with the equilibrium residual
     * FRIX_INFO_EQUILIBRIUM (the larger of the two). */
    FRIX_MEASURE_SCALED = 2
} frix_error_measure;

typedef enum frix_shuffle FRIX_ENUM_BASE {
    FRIX_SHUFFLE_NONE = 0,
    FRIX_SHUFFLE_ONCE = 1,
    FRIX_SHUFFLE_EACH_SWEEP = 2
} frix_shuffle;

/* One-contact solvers (values match the Siconos 4.4 ids of the same algorithms). */
typedef enum frix_local_solver FRIX_ENUM_BASE {
    /* One projected step r <- P_K(r - rho (W_aa r + q_a + mu|u_T| e_N)), rho from W_aa. */
    FRIX_LOCAL_PROJECTION = 552,
    /* Exact stick and take-off cases, otherwise projected steps iterated with a
     * self-adaptive rho until the one-contact residual is below the local tolerance. */
    FRIX_LOCAL_PROJECTION_ITERATED = 553,
    /* The closed-form one-contact solution: exact take-off and stick, and sliding through
     * the root of the sliding-angle equation (Newton from the last sliding direction, roots
     * bracketed otherwise); the 553 iterations only where no valid root exists. */
    FRIX_LOCAL_CLOSED_FORM = 562,
    /* Alart-Curnier semismooth Newton on the 3 unknowns, full steps. */
    FRIX_LOCAL_NEWTON_AC = 550,
    /* Alart-Curnier semismooth Newton with the Goldstein-Price line search. */
    FRIX_LOCAL_NEWTON_AC_GP = 551,
    /* Fischer-Burmeister semismooth Newton (De Saxce form) with the Goldstein-Price line
     * search. Siconos' 561 is an FB Newton too, on Glocker's NCP reformulation. */
    FRIX_LOCAL_NEWTON_FB = 561,
    /* Hybrid of projection and Newton: exactly 553 (exact take-off and stick, projected
     * iterations); where those stop short of the local tolerance, Alart-Curnier Newton with
     * Goldstein-Price from their iterate, kept only if it lowers the residual. */
    FRIX_LOCAL_HYBRID = 565
} frix_local_solver;

/* Called after each iteration; a non-zero return stops the solve with
 * FRIX_STATUS_STOPPED_BY_CALLBACK. `error` is the solver's current estimate (the light
 * error for NSGS between full checks; with FRIX_OPT_CALLBACK_ESTIMATES 0, only measured
 * errors). A global problem solved through W = H^T M^-1 H
 * also calls it while W is formed (after each block of 128 contacts), with iteration 0 and
 * the error of the start, which a stop then returns. */
typedef int (*frix_progress_fn)(void *user_data, int64_t iteration, double error,
                                double elapsed_seconds);

/* solver_id: an id of the registry (frix_registry.h). */
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

/* Options whose values are choices (error_measure, local_solver, shuffle, rho_strategy,
 * line_search, hybrid, inner_solver) name them: frix_option_choice_name(FRIX_OPT_SHUFFLE,
 * FRIX_SHUFFLE_ONCE) is "once"; the names are the enumerators' in lower case without their
 * prefix ("each_sweep", "goldstein_price", "newton_ac"; error_measure: "scaled", "siconos"
 * (also "relative"), "q_relative"), and inner_solver's are the registry's solver names. NULL
 * if the key has no named values or value is none of them. */
FRIX_API const char *frix_option_choice_name(frix_option_key key, int64_t value);
/* The value named `name` (case and '-' / '_' ignored), or FRIX_ERR_OPTION_RANGE naming the
 * choices; FRIX_ERR_UNKNOWN_OPTION for an unknown key. */
FRIX_API frix_error frix_option_choice_by_name(frix_option_key key, const char *name,
                                               int64_t *value);
/* Sets the option named `key` (frix_option_name) from text, for command lines and
 * configuration files: a choice name (frix_option_choice_by_name), an integer (exact for int
 * keys) or a number, with the checks of frix_options_set_int / _set_double. A number beyond
 * the doubles (1e400) is FRIX_ERR_OPTION_RANGE, as is text that is none of these. */
FRIX_API frix_error frix_options_set_by_name(frix_options *opts, const char *key,
                                             const char *value);

/* fn may be NULL to remove the callback. */
FRIX_API frix_error frix_options_set_callback(frix_options *opts, frix_progress_fn fn,
                                              void *user_data);

/* Where the progress lines of the option verbosity (> 0) go: fn(user_data, line) once per
 * line, without its newline, from the solving thread or (auto with threads > 1) one of its
 * workers, never two calls at once. fn NULL (the default) writes them to stderr. At
 * verbosity 0 nothing is logged. The copy of frix_options_copy keeps the sink. */
typedef void (*frix_log_fn)(void *user_data, const char *line);
FRIX_API frix_error frix_options_set_log(frix_options *opts, frix_log_fn fn, void *user_data);

#ifdef __cplusplus
}
#endif

#endif /* FRIX_OPTIONS_H */
