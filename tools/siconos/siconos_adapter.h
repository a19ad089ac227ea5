/* Siconos/Numerics 4.4 as a comparator: solve a frix problem with one of Siconos's solvers
 * (a local one with an FC3D solver through fc3d_driver, a global one with a GFC3D solver
 * through gfc3d_driver) and measure the returned r (and v) with frix's own error measure,
 * so that frix and Siconos are compared with one measure.
 *
 * The problem is read by frix (Debian's Siconos is built without its FCLIB reader) and
 * Siconos gets copies of the same data in the storage its own FCLIB reader builds: W as
 * its sparse-block matrix, q and mu for a local problem; M and H as its sparse (CSC)
 * matrices, f, w and mu for a global one (Siconos's q and b: M v = H r + q, u = H^T v + b,
 * FCLIB's convention). Uses frix's public API and Siconos's only. Built only when
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

/* The solvers offered, by Siconos id and name: the FC3D local ones (500..523) by their
 * short Siconos name ("NSGS", "NSN_AC", ...), then the GFC3D global ones (600..615) by
 * Siconos's own name for them ("GFC3D_NSN_AC", ...), whose prefix tells them apart, then
 * the rolling-friction ones (3000, 3003: "RFC3D_NSGS", "RFC3D_ADMM"). */
int frix_siconos_solver_count(void);
int frix_siconos_solver_id_at(int index);
/* Name, or NULL if the id is not offered. */
const char *frix_siconos_solver_name(int id);
/* 1 for a global solver (gfc3d_driver, global problems only), 0 for a local one
 * (fc3d_driver, local problems only), -1 if the id is not offered. */
int frix_siconos_solver_is_global(int id);
/* 1 for a rolling-friction solver (rolling_fc3d_driver: the local form of rolling problems
 * only), 0 for any other, -1 if the id is not offered. */
int frix_siconos_solver_is_rolling(int id);
/* Accepts, any case: a local solver's short name, "FC3D_NSGS", "FRICTION_3D_NSGS",
 * "SICONOS_FRICTION_3D_NSGS"; a global one's "GFC3D_NSN_AC", "GLOBAL_FRICTION_3D_NSN_AC",
 * "SICONOS_GLOBAL_FRICTION_3D_NSN_AC"; or the id as a decimal string. Returns the id, or -1.
 * A bare short name ("NSGS") is the local solver: the global ones always carry a prefix. */
int frix_siconos_solver_by_name(const char *name);

/* Called by the solvers that support Siconos's iteration callback (collectStatsIteration),
 * after each of their iterations: the iteration count so far, seconds since the driver was
 * entered, and the error: for a local problem frix's default measure (FRIX_MEASURE_SCALED) of
 * the iterate, whose seconds are left out of elapsed and of the result's time; for a global
 * one (whose callback does not carry v) the solver's own error estimate. */
typedef void (*frix_siconos_trace_fn)(void *user_data, int64_t iteration, double elapsed,
                                      double error);

typedef struct frix_siconos_result {
    int ran;              /* 1 if the driver ran to its end (0: refused or numerics_error) */
    int refused_kind;     /* 1 if refused because the solver is for the other kind of problem */
    int info;             /* the driver's return: 0 when Siconos considers it converged */
    int64_t iterations;   /* iparam[SICONOS_IPARAM_ITER_DONE] */
    double siconos_error; /* dparam[SICONOS_DPARAM_RESIDU]: Siconos's own error */
    double error;         /* frix's measure of Siconos's kind (relative) of the returned r (and v) */
    double error_scaled;  /* frix's default measure (FRIX_MEASURE_SCALED) of the same */
    double equilibrium;   /* global: frix's |M v - H r - f| / max(|f|, |M v|, |H r|); NaN local */
    double time;          /* seconds of wall clock around the driver only */
    int64_t callbacks;    /* how many times the iteration callback was called */
    char message[256];    /* why it did not run, or Siconos's fatal error message */
} frix_siconos_result;

/* Solves `problem` with Siconos solver `solver_id`, a local solver for a local problem and a
 * global one for a global problem (the other pairs are refused, refused_kind set), from r
 * (the initial guess, 3nc entries; the result on return) and, for a global problem, v (n
 * entries, the same; NULL for a local one). Writes u (3nc): W r + q, or H^T v + w. tolerance
 * and max_iter go to dparam[TOL] and iparam[MAX_ITER]; max_iter <= 0 keeps Siconos's
 * default. trace may be NULL. Returns 0 when the driver ran (whatever it says), -1
 * otherwise (see message). */
int frix_siconos_solve(const frix_problem *problem, int solver_id, double tolerance,
                       int64_t max_iter, double *r, double *u, double *v,
                       frix_siconos_trace_fn trace, void *trace_data, frix_siconos_result *result);

#ifdef __cplusplus
}
#endif

#endif /* FRIX_SICONOS_ADAPTER_H */
