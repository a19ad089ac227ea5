/* frix — distributed problems from PETSc objects (libfrix_mpi, built with -DFRIX_WITH_MPI=ON).
 *
 * For host codes that already hold their contact operator in PETSc: W as an assembled
 * parallel matrix whose rows are laid out 3 to a contact (a block size of 3), q as a vector
 * with W's row layout; or a global problem's M, f, H^T and w. Each rank's rows are its
 * contacts (and dofs): PETSc's ownership ranges are contiguous in rank order, as
 * frix_mpi_problem_local asks. The host has initialised PETSc; the matrices' communicator
 * must be congruent with the context's. The rest is frix_mpi.h's.
 */
#ifndef FRIX_MPI_PETSC_H
#define FRIX_MPI_PETSC_H

#include <petscmat.h>
#include "frix_mpi.h"

#ifdef __cplusplus
extern "C" {
#endif

/* This rank's part of the local problem u = W r + q (collective): its rows of W (any
 * assembled matrix type whose local rows are a multiple of 3; entries stored are grouped in
 * 3 x 3 blocks), its entries of q and its mu (one value a contact). The values are copied;
 * W and q may be destroyed after the call. */
FRIX_API frix_error frix_mpi_problem_petsc(frix_mpi_context *ctx, Mat W, Vec q, const double *mu,
                                           frix_mpi_problem **out);

/* This rank's part of a global problem M v = H r + f, u = H^T v + w with the host's M
 * (collective; as frix_mpi_problem_global): its rows of M (square, any assembled type) with
 * f in M's row layout, and its contacts' rows of Ht = H^T (3 rows a contact, M's columns) with
 * w in Ht's row layout, and mu (one value a contact). The values are copied. */
FRIX_API frix_error frix_mpi_problem_petsc_global(frix_mpi_context *ctx, Mat M, Vec f, Mat Ht, Vec w,
                                                  const double *mu, frix_mpi_problem **out);

#ifdef __cplusplus
}
#endif

#endif /* FRIX_MPI_PETSC_H */
