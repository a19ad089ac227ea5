/* Compiled, never run, by the public_headers_mpi_* tests: frix_mpi.h is valid C89, C99 and
 * C++ under -pedantic with every warning an error (mpi.h itself is a system header). */
#include <frix/frix.h>
#include <frix/frix_mpi.h>

int frix_public_mpi_header_probe(const frix_mpi_problem *p);
int frix_public_mpi_header_probe(const frix_mpi_problem *p) {
    int64_t v = 0;
    return frix_mpi_problem_get_int(p, FRIX_MPI_CONTACTS, &v) == FRIX_OK && (int)sizeof(MPI_Comm) > 0;
}
