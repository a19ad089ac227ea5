/* frix — error codes (what went wrong with a call) and solver status (how a solve ended).
 *
 * Every function that can fail returns a frix_error. FRIX_OK is 0, failures are negative.
 * A failing call also leaves a message naming the precise cause, readable with
 * frix_last_error_message() from the same thread until the next failing call.
 * The solver status is not an error: a solve that stops at its iteration limit returns
 * FRIX_OK, and the status in the frix_info says FRIX_STATUS_MAX_ITER.
 * Values are pinned: new codes are only ever added at the end.
 */
#ifndef FRIX_ERRORS_H
#define FRIX_ERRORS_H

#include "frix_export.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum frix_error FRIX_ENUM_BASE {
    FRIX_OK = 0,
    FRIX_ERR_INVALID_ARGUMENT = -1, /* NULL where a value is required, or a bad value */
    FRIX_ERR_DIMENSION = -2,        /* sizes that do not match or are out of range */
    FRIX_ERR_NOT_FINITE = -3,       /* NaN or Inf in input data */
    FRIX_ERR_OUT_OF_MEMORY = -4,
    FRIX_ERR_IO = -5,               /* a file cannot be opened, read or written */
    FRIX_ERR_FORMAT = -6,           /* a file is readable but its content is malformed */
    FRIX_ERR_UNKNOWN_SOLVER = -7,
    FRIX_ERR_UNKNOWN_OPTION = -8,   /* the key does not exist, or the solver does not use it */
    FRIX_ERR_OPTION_RANGE = -9,     /* the value is outside the option's bounds */
    FRIX_ERR_UNSUPPORTED = -10,     /* valid request this build or solver cannot do */
    FRIX_ERR_NUMERICAL = -11,       /* e.g. a factorisation failed */
    FRIX_ERR_INTERNAL = -12         /* a bug in frix: please report it */
} frix_error;

typedef enum frix_status FRIX_ENUM_BASE {
    FRIX_STATUS_NOT_RUN = 0,
    FRIX_STATUS_CONVERGED = 1,       /* error <= tolerance, checked with the full error measure */
    FRIX_STATUS_MAX_ITER = 2,
    FRIX_STATUS_TIME_LIMIT = 3,
    FRIX_STATUS_STAGNATED = 4,       /* no progress possible; r is the best iterate found */
    FRIX_STATUS_DIVERGED = 5,
    FRIX_STATUS_NUMERICAL_FAILURE = 6,
    FRIX_STATUS_STOPPED_BY_CALLBACK = 7,
    FRIX_STATUS_MEMORY_LIMIT = 8     /* a factorisation would have exceeded the memory limit
                                        (option memory_limit); r is the best iterate found (a
                                        global problem whose M itself did not fit: the start,
                                        with v = 0) */
} frix_status;

/* Static, never NULL: "unknown error code" for values frix does not define. */
FRIX_API const char *frix_error_string(frix_error code);
FRIX_API const char *frix_status_string(frix_status status);

/* The message of the last failing frix call in this thread ("" if none). Valid until
 * the next frix call in this thread. */
FRIX_API const char *frix_last_error_message(void);

#ifdef __cplusplus
}
#endif

#endif /* FRIX_ERRORS_H */
