/* Siconos/Numerics 4.4 as a comparator: solve a frix local problem with one of Siconos's
 * FC3D solvers (fc3d_driver) and measure the returned r with frix's own error measure, so
 * that frix and Siconos are compared with one measure.
 *
 * The problem is read by frix (Debian's Siconos is built without its FCLIB reader) and
 * Siconos gets copies of the same W (as its sparse-block matrix, the storage its own FCLIB
 * reader builds), q and mu. Uses frix's public API and Siconos's only. Built only when
 * libsiconos-numerics-dev is installed; nothing in frix depends on it.
 *
 * Siconos calls abort() or exit() on some errors (and its solvers may not stop), so run
 * untrusted solves in a child process: `frix bench` does, through the `frix-siconos`
 * executable. */
#ifndef FRIX_SICONOS_ADAPTER_H
#define FRIX_SICONOS_ADAPTER_H

#include <frix/frix.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The FC3D local solvers offered, by Siconos id (500..523) and short Siconos name
 * ("NSGS", "NSN_AC", ...). */
int frix_siconos_solver_count(void);
int frix_siconos_solver_id_at(int index);
/* Short name, or NULL if the id is not offered. */
const char *frix_siconos_solver_name(int id);
/* Accepts the short name, "FC3D_NSGS", "FRICTION_3D_NSGS", "SICONOS_FRICTION_3D_NSGS" (any
 * case) or the id as a decimal string. Returns the id, or -1. */
int frix_siconos_solver_by_name(const char *name);

/* Called by the solvers that support Siconos's iteration callback (collectStatsIteration),
 * after each of their iterations: the iteration count so far, seconds since fc3d_driver was
 * entered, and the solver's own error estimate. */
typedef void (*frix_siconos_trace_fn)(void *user_data, int64_t iteration, double elapsed,
                                      double error);

typedef struct frix_siconos_result {
    int ran;              /* 1 if fc3d_driver ran to its end (0: refused or numerics_error) */
    int info;             /* fc3d_driver's return: 0 when Siconos considers it converged */
    int64_t iterations;   /* iparam[SICONOS_IPARAM_ITER_DONE] */
    double siconos_error; /* dparam[SICONOS_DPARAM_RESIDU]: Siconos's own error */
    double error;         /* frix_problem_error of the returned r (frix's relative measure) */
    double time;          /* seconds of wall clock around fc3d_driver only */
    int64_t callbacks;    /* how many times the iteration callback was called */
    char message[256];    /* why it did not run, or Siconos's fatal error message */
} frix_siconos_result;

/* Solves `problem` (a local one) with Siconos solver `solver_id` from r (the initial guess,
 * 3nc entries; the result on return) and writes u = W r + q (3nc). tolerance and max_iter
 * go to dparam[TOL] and iparam[MAX_ITER]; max_iter <= 0 keeps Siconos's default. trace may
 * be NULL. Returns 0 when fc3d_driver ran (whatever it says), -1 otherwise (see message). */
int frix_siconos_solve(const frix_problem *problem, int solver_id, double tolerance,
                       int64_t max_iter, double *r, double *u, frix_siconos_trace_fn trace,
                       void *trace_data, frix_siconos_result *result);

#ifdef __cplusplus
}
#endif

#endif /* FRIX_SICONOS_ADAPTER_H */
