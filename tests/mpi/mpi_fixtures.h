/* Shared by the libfrix_mpi test programs (test_mpi_nsgs, test_mpi_global, test_mpi_newton),
 * each run by CTest under mpiexec at np = 1, 2, 3 and 4, and built again as a host that starts
 * PETSc itself (FRIX_TEST_PETSC_HOST) at np = 2 and 3. Every test is collective: each rank runs
 * it, and the verdicts are agreed (all_true) before they are asserted, so that a failure on one
 * rank fails all of them instead of leaving the others waiting. Public API only.
 *
 * Every distributed form reports the serial default measure of its answer (test_mpi_global's
 * every_form_measures_as_the_serial_problem, test_mpi_newton's
 * the_serial_measure_over_the_ranks), and the global forms' tests compare on it. The local
 * forms' tests compare on Siconos's measure (nsgs_options, siconos_error), which their piles'
 * tolerances were set on (on the default one, nsgs does not reach 1e-4 on Spheres-n400 in
 * its 20000 sweeps). */
#ifndef FRIX_TEST_MPI_FIXTURES_H
#define FRIX_TEST_MPI_FIXTURES_H

#include <check.h>
#include <frix/frix.h>
#include <frix/frix_mpi.h>
#ifdef FRIX_TEST_PETSC_HOST
#include <frix/frix_mpi_petsc.h>
#endif

#include "scenes.h"

/* This process's rank in MPI_COMM_WORLD, and the number of ranks (set by mpi_test_start). */
extern int g_rank, g_size;

/* MPI_Init (and PetscInitialize in the host build); sets g_rank and g_size. */
void mpi_test_start(int *argc, char ***argv);

/* Runs the suite on every rank (Check's report on rank 0), then finalises PETSc (host build)
 * and MPI; the exit status of the program. */
int mpi_test_run(Suite *s);

/* Whether `ok` holds on every rank of comm. */
int all_true(MPI_Comm comm, int ok);

/* frix_problem_error on Siconos's measure. */
frix_error siconos_error(const frix_problem *p, const double *r, const double *v, double *error);

/* A problem of ../shared (fclib/ or fclib-large/), read on every rank; NULL with a note when
 * the shared data is absent (the test then passes). */
frix_problem *shared_problem(const char *relative);

/* nsgs at tolerance `tol`, on Siconos's measure. */
frix_options *nsgs_options(double tol);

/* The serial solve and the distributed one on `comm` (the whole problem scattered from rank
 * 0, its contacts dealt as `part` says, or in equal blocks), from the warm start r0 (NULL: 0).
 * The distributed result is gathered to every rank (r, u: 3nc); `keep`, when not NULL, takes
 * the distributed problem. */
typedef struct {
    frix_status status;
    int64_t iterations;
    double error;
    double *r, *u;
} outcome;

void outcome_free(outcome *o);
outcome solve_serial(const frix_problem *p, const frix_options *o, const double *r0);
outcome solve_distributed(MPI_Comm comm, const frix_problem *p, const int *part, const frix_options *o,
                          const double *r0, frix_mpi_problem **keep);
/* frix_mpi_solve on dist, this rank's part of a problem of nc contacts, from r0 (the whole
 * problem's warm start; NULL: 0), its r and u gathered to every rank of comm (3nc). */
outcome solve_part(MPI_Comm comm, frix_mpi_problem *dist, const frix_options *o, const double *r0, int64_t nc);
/* The same status, iterations, error, r and u, bit for bit (m = 3nc). */
int same_bits(const outcome *a, const outcome *b, int64_t m);

/* A chain: contact i coupled to i-1 and i+1 (W block-tridiagonal, diagonally dominant, not
 * symmetric), every contact pressed (q_N < 0) and pushed sideways; its blocks by rows. */
typedef struct {
    int64_t nc, nb;
    int64_t *row_ptr, *rows, *cols;
    double *vals, *q, *mu;
} chain;

chain chain_make(int64_t nc);
void chain_free(chain *c);
/* The chain as a local problem (*W holds its matrix; free both). */
frix_problem *chain_problem(const chain *c, frix_matrix **W);

/* A scene of rigid bodies given as H^T's blocks and M's, each rank its block of contacts and
 * every body (all: a rank may give more bodies than its contacts touch), or only the bodies
 * its contacts touch; *held and *ids: how many and which (free *ids). */
frix_error rigid_part(frix_mpi_context *ctx, const frix_scene *scene, int64_t first, int64_t owned, int all,
                      frix_mpi_problem **out, int64_t *held, int64_t **ids_out);

#endif
