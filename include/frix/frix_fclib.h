/* frix — FCLIB HDF5 files (https://frictionalcontactlibrary.github.io).
 *
 * Reading accepts local (/fclib_local) and global (/fclib_global) problems with matrices in
 * CSC, CSR or triplet form. Every failure is a frix_error with a message naming the file and
 * the dataset at fault; nothing is printed and the process never exits.
 * Writing goes to a temporary file in the target's directory that is renamed into place
 * only when complete, so a failed write never destroys an existing file.
 */
#ifndef FRIX_FCLIB_H
#define FRIX_FCLIB_H

#include <stdint.h>
#include "frix_export.h"
#include "frix_errors.h"
#include "frix_problem.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Reads the problem of an FCLIB file; the problem owns its data. Its info group's title,
 * description and math_info, where present, become the problem's texts (control characters
 * escaped as \xNN, but for line breaks and tabs in the description and math_info); a text
 * over 65536 bytes is refused (FRIX_ERR_FORMAT). */
FRIX_API frix_error frix_fclib_read(const char *path, frix_problem **out);

/* Reads /solution of the file into caller arrays sized from `problem` (which must be the
 * file's problem): r and u (3nc), v (n, global only; may be NULL). Any pointer may be NULL
 * to skip that vector. FRIX_ERR_FORMAT if the file has no /solution. */
FRIX_API frix_error frix_fclib_read_solution(const char *path, const frix_problem *problem,
                                             double *r, double *u, double *v);

/* Number of /guesses in the file (0 if none). */
FRIX_API frix_error frix_fclib_guess_count(const char *path, int64_t *count);
/* Reads guess `index` (0-based; FCLIB numbers them from 1 in the file). */
FRIX_API frix_error frix_fclib_read_guess(const char *path, const frix_problem *problem,
                                          int64_t index, double *r, double *u, double *v);

/* Writes `problem`, and optionally a solution and guesses, to a new FCLIB file (an existing
 * file at `path` is replaced atomically), arrays of 1024 entries or more deflated at level 4
 * (frix_fclib_write_compressed chooses). Pass sol_r = sol_u = sol_v = NULL for no /solution
 * (sol_v is ignored for local problems); an array with no entries may be NULL (r and u
 * without contacts, v without dofs). n_guesses guesses are stored contiguously:
 * guess k is guess_r[k*3nc ...], guess_u[k*3nc ...], guess_v[k*n ...]. */
FRIX_API frix_error frix_fclib_write(const char *path, const frix_problem *problem,
                                     const double *sol_r, const double *sol_u,
                                     const double *sol_v, int64_t n_guesses,
                                     const double *guess_r, const double *guess_u,
                                     const double *guess_v);

/* frix_fclib_write with the compression chosen: arrays of 1024 entries or more are stored
 * shuffled and deflated at `level` (1 fastest .. 9 smallest; frix_fclib_write uses 4), in
 * chunks; level 0 stores every array as it is (contiguous, readable without HDF5's filters).
 * Where the HDF5 library lacks deflate, arrays are stored as they are whatever the level.
 * FRIX_ERR_INVALID_ARGUMENT for a level outside 0..9. The problem's title, description and
 * math info go into the info group (an empty description: "written by frix VERSION"). */
FRIX_API frix_error frix_fclib_write_compressed(const char *path, const frix_problem *problem,
                                                const double *sol_r, const double *sol_u,
                                                const double *sol_v, int64_t n_guesses,
                                                const double *guess_r, const double *guess_u,
                                                const double *guess_v, int level);

#ifdef __cplusplus
}
#endif

#endif /* FRIX_FCLIB_H */
