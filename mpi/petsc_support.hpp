// What the PETSc users of libfrix_mpi share: PETSc's errors as frix's, and the sparse LU by
// MUMPS that the distributed Newtons solve with.
#pragma once

#include <petscksp.h>

#include "mpi/distributed.hpp"

namespace frix {
namespace mpi {

// FRIX_OK for rc == 0; else fails with `code` and "where: what failed" with PETSc's message.
frix_error petsc_call(PetscErrorCode rc, frix_error code, const char *where, const char *what);

// MUMPS's orderings (ICNTL(7)): AMD; METIS's nested dissection, far less fill on a mesh.
enum MumpsOrdering { kMumpsAmd = 0, kMumpsMetis = 5 };

// ksp (destroyed first if set): KSP PREONLY with MUMPS's LU of A, a sequential analysis
// (ICNTL(28) = 1) with the ordering given, whose result does not depend on the run.
frix_error mumps_lu(MPI_Comm comm, Mat A, KSP &ksp, const char *where, MumpsOrdering ordering);

// x = A^-1 b by ksp (made by mumps_lu for A with `ordering`); solved: false when A did not
// factorise (ksp is then made again: MUMPS keeps a failure) or x is not finite, the same on
// every rank.
frix_error mumps_solve(MPI_Comm comm, Mat A, KSP &ksp, Vec b, Vec x, bool &solved, const char *where,
                       MumpsOrdering ordering);

}  // namespace mpi
}  // namespace frix
