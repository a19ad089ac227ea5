/* Shared by the FCLIB test programs (test_fclib_read, test_fclib_write, test_fclib_bad_input):
 * the shared files they read, temporary paths, reads that must pass or fail, bit-for-bit
 * comparisons of problems, a small problem built in memory, and FCLIB files crafted field by
 * field with the HDF5 C API (valid or malformed). */
#ifndef FRIX_TEST_FCLIB_FIXTURES_H
#define FRIX_TEST_FCLIB_FIXTURES_H

#include <frix/frix.h>

#include <stddef.h>
#include <stdio.h>

#define FCLIB_DIR FRIX_SHARED_DIR "/fclib"
#define LARGE_DIR FRIX_SHARED_DIR "/fclib-large"
#define LOCAL_TEST FCLIB_DIR "/local/local_problem_test.hdf5"
#define CAPSULES FCLIB_DIR "/local/Capsules-i125-1213.hdf5"
#define BOX_GLOBAL FCLIB_DIR "/global/Box_Stacks-i0035-31-0.hdf5"
#define BOX_REDUCED FCLIB_DIR "/converted/Box_Stacks-i0035-31-0.reduced.hdf5"
#define ROLLING FCLIB_DIR "/other/Chute-ndof-768-nc-4-3.hdf5"

/* Whether the shared collection is there. */
int have_shared(void);

/* Tests that need the shared collection skip (with a note) rather than fail without it. */
#define REQUIRE_SHARED()                                                                 \
    do {                                                                                 \
        if (!have_shared()) {                                                            \
            printf("note: %s skipped: no shared FCLIB data under %s\n", __func__,        \
                   FRIX_SHARED_DIR);                                                     \
            return;                                                                      \
        }                                                                                \
    } while (0)

/* FRIX_TEST_TMPDIR/fclib_<name>; the last 8 results stay valid. */
const char *tmp_path(const char *name);

/* Reads `path`, which must succeed. */
frix_problem *read_ok(const char *path);

/* Reading `path` fails with `code`, and the message names the file and contains `needle`. */
void expect_read_error(const char *path, frix_error code, const char *needle);

/* A matrix as CSC arrays, for entry-by-entry checks. */
typedef struct {
    int64_t rows, cols, nnz;
    int64_t *p, *i;
    double *x;
} csc;

csc to_csc(const frix_matrix *A);
void csc_free(csc *c);
double csc_entry(const csc *c, int64_t row, int64_t col);

/* Bit for bit: the same pattern and values, the same arrays, the same problem. */
void assert_same_matrix(const frix_matrix *A, const frix_matrix *B);
void assert_same_vector(const double *a, const double *b, int64_t n);
void assert_same_problem(const frix_problem *a, const frix_problem *b);

/* A 2-contact local problem built in memory (no shared data needed). */
typedef struct {
    frix_matrix *W;
    double q[6], mu[2];
    frix_problem *p;
} small_local;

void small_local_make(small_local *s, const char *title);
void small_local_free(small_local *s);

/* An FCLIB local problem written field by field, so that a test can break any one field. */
typedef struct {
    int int64; /* integers stored as int64 instead of FCLIB's int32 */
    long long spacedim, m, n, nz, nzmax;
    const long long *p, *i;
    size_t np, ni;
    const double *x, *q, *mu;
    size_t nx, nq, nmu;
    const char *vlen_title; /* title as a variable-length string, NULL for none */
} crafted;

/* A valid base: W = 6x6 CSR with diagonal 2..7 and W(0,3) = 0.5, two contacts. */
crafted crafted_base(void);
/* The base's W as CSC (column pointers, row indices, values; 7 entries). */
extern const long long csc_p[7], csc_i[7];
extern const double csc_x[7];

void write_crafted(const char *path, const crafted *c);

#endif
