/* frix — discrete 3D frictional contact with Coulomb friction. The umbrella header.
 *
 *   #include <frix/frix.h>
 *
 * Conventions: every symbol is frix_ / FRIX_; handles are opaque, created by *_create or
 * *_from_* and released by *_free (which accept NULL); functions return a frix_error
 * (FRIX_OK = 0) and a failing call leaves a message in frix_last_error_message().
 * Per-contact vectors are stored normal component first. Nothing prints unless the
 * verbosity option asks for it, and nothing ever exits the process.
 *
 * Threads: the library keeps no global mutable state. Calls on different handles may run at
 * once from any threads; a problem (with its matrices) may be shared by concurrent solves,
 * which only read it; an options or info object serves one call at a time. A progress
 * callback runs in the solving thread (with auto and FRIX_OPT_THREADS > 1, in its worker
 * threads, never two calls at once). frix_last_error_message() is per thread. Results
 * depend neither on FRIX_OPT_THREADS nor on how many threads call the library
 * (tests/test_threads.c, also run under ThreadSanitizer); the interior-point stages can
 * depend on the BLAS library's own thread count (docs/auto.md). The only threads frix
 * starts are auto's workers: CHOLMOD's OpenMP loops run on the solving thread, and the BLAS
 * library threads as it is configured (OPENBLAS_NUM_THREADS). The METIS orderings of sparse
 * factorisations (gnsn-ac's, and CHOLMOD's where it tries METIS on a large M or W + rho I)
 * draw from libc's rand() after reseeding it: a host thread calling rand(), srand() or METIS
 * during such a solve can change its rounding, and the solve leaves rand() reseeded.
 */
#ifndef FRIX_H
#define FRIX_H

#include "frix_export.h"
#include <frix/frix_version.h> /* generated at configure time */
#include "frix_errors.h"
#include "frix_matrix.h"
#include "frix_problem.h"
#include "frix_options.h"
#include "frix_registry.h"
#include "frix_info.h"
#include "frix_solve.h"
#include "frix_persistent.h"
#include "frix_fclib.h"
#include "frix_read.h"
#include "frix_plugin.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The version of the library actually loaded (compare with FRIX_VERSION_*). */
FRIX_API const char *frix_version_string(void);
FRIX_API int frix_version_number(void);

#ifdef __cplusplus
}
#endif

#endif /* FRIX_H */
