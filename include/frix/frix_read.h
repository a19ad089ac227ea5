/* frix — reading a problem from a file of any format frix knows.
 *
 * Two formats are read: FCLIB HDF5 files (frix_fclib.h) and the text format of Siconos
 * (the .dat files of its test collection, written by frictionContact_printInFile and
 * globalFrictionContact_printInFile). A problem read from a file owns its data.
 * Nothing is printed and the process never exits; a malformed file is FRIX_ERR_FORMAT with
 * a message naming the file, the line and what was expected there.
 */
#ifndef FRIX_READ_H
#define FRIX_READ_H

#include "frix_export.h"
#include "frix_errors.h"
#include "frix_problem.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Reads `path` whatever its format: an HDF5 file is read as FCLIB (frix_fclib_read), any
 * other file as Siconos text (frix_dat_read). */
FRIX_API frix_error frix_read_problem(const char *path, frix_problem **out);

/* Reads a Siconos text problem: a local one (dimension, contacts, W, q, mu) or a global one
 * (dimension, contacts, M, H, f, w, mu), told apart by the file's content, not its name.
 * Matrices may be stored dense (storage 0) or sparse-block (storage 1); dimension must be 3.
 * The mapping onto frix is exact: Siconos q and b of a global problem are frix f and w. */
FRIX_API frix_error frix_dat_read(const char *path, frix_problem **out);

#ifdef __cplusplus
}
#endif

#endif /* FRIX_READ_H */
