/* The sparse(-block) matrix: every constructor gives the same matrix, products match a dense
 * reference, export to CSC round-trips, and bad input is refused with the right code. */
#include <frix/frix.h>
#include <math.h>
#include <string.h>

#include "check_main.h"
#include "frix_testing.h"

/* A 6x6 test matrix (two block rows/cols) with an empty off-diagonal block, column-major. */
static const double A6[36] = {
    4, 1, 0, 0, 0, 0,   /* col 0 */
    1, 5, 2, 0, 0, 0,   /* col 1 */
    0, 2, 6, 0, 0, 0,   /* col 2 */
    0.5, 0, 0, 7, 1, 0, /* col 3 */
    0, 0, 0, 1, 8, 3,   /* col 4 */
    0, 0, -1, 0, 3, 9   /* col 5 */
};

static void dense_gemv(const double *A, int m, int n, const double *x, double *y) {
    for (int i = 0; i < m; ++i) {
        y[i] = 0;
        for (int j = 0; j < n; ++j) y[i] += A[i + j * m] * x[j];
    }
}

/* Dense column-major copy of any matrix through the CSC export. */
static void to_dense(const frix_matrix *M, double *out) {
    int64_t m = frix_matrix_rows(M), n = frix_matrix_cols(M), nnz = 0;
    ck_assert_int_eq(frix_matrix_to_csc(M, &nnz, NULL, NULL, NULL), FRIX_OK);
    int64_t *cp = malloc(sizeof(int64_t) * (size_t)(n + 1));
    int64_t *ri = malloc(sizeof(int64_t) * (size_t)(nnz > 0 ? nnz : 1));
    double *v = malloc(sizeof(double) * (size_t)(nnz > 0 ? nnz : 1));
    ck_assert_int_eq(frix_matrix_to_csc(M, &nnz, cp, ri, v), FRIX_OK);
    memset(out, 0, sizeof(double) * (size_t)(m * n));
    for (int64_t j = 0; j < n; ++j)
        for (int64_t e = cp[j]; e < cp[j + 1]; ++e) {
            if (e > cp[j]) ck_assert_int_lt(ri[e - 1], ri[e]); /* sorted, no duplicates */
            out[ri[e] + j * m] = v[e];
        }
    free(cp);
    free(ri);
    free(v);
}

static void dense_to_csc(const double *A, int m, int n, int64_t *cp, int64_t *ri, double *v) {
    int64_t k = 0;
    cp[0] = 0;
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < m; ++i)
            if (A[i + j * m] != 0.0) {
                ri[k] = i;
                v[k++] = A[i + j * m];
            }
        cp[j + 1] = k;
    }
}

/* Duplicates are summed; a sum that overflows is refused, in both storages. */
/* The large arrays' helpers: any size, growing (new storage, advised) and shrinking (the same
 * storage), keep the values asked for. */
START_TEST(test_advised_arrays) {
    const int64_t sizes[] = {0, 1, 1000, 3 << 20, 1 << 20, 5 << 20, 0, 7};
    const double values[8] = {1.5, -2.0, 0.0, 3.25, 4.0, 5.0, 6.0, 7.0};
    ck_assert_int_eq(frix_testing_advised_arrays(sizes, 8, values), 0);
}
END_TEST

START_TEST(test_duplicates_summing_past_the_doubles) {
    const int64_t rows[2] = {0, 0}, cols[2] = {0, 0};
    const double big[2] = {1.7e308, 1.7e308}, fine[2] = {1.0, 2.0};
    frix_matrix *A = NULL;
    ck_assert_int_eq(frix_matrix_from_triplets(3, 3, 2, rows, cols, big, &A), FRIX_ERR_NOT_FINITE);
    ck_assert_ptr_null(A);
    ck_assert_int_eq(frix_matrix_from_triplets(2, 2, 2, rows, cols, big, &A), FRIX_ERR_NOT_FINITE);
    ck_assert_ptr_null(A);
    ck_assert_int_eq(frix_matrix_from_triplets(3, 3, 2, rows, cols, fine, &A), FRIX_OK);
    frix_matrix_free(A);
}
END_TEST

START_TEST(test_all_constructors_agree) {
    int64_t cp[7], ri[36];
    double v[36];
    dense_to_csc(A6, 6, 6, cp, ri, v);
    int64_t nnz = cp[6];

    /* CSR of A is the CSC of A^T. */
    double At[36];
    for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 6; ++j) At[j + i * 6] = A6[i + j * 6];
    int64_t rp[7], ci[36];
    double rv[36];
    dense_to_csc(At, 6, 6, rp, ci, rv);

    /* Triplets in reverse order, with one entry split in two duplicates (4 = 3 + 1). */
    int64_t tr[37], tc[37];
    double tv[37];
    int64_t t = 0;
    for (int64_t j = 5; j >= 0; --j)
        for (int64_t e = cp[j + 1] - 1; e >= cp[j]; --e) {
            tr[t] = ri[e];
            tc[t] = j;
            tv[t++] = v[e];
        }
    for (int64_t k = 0; k < t; ++k)
        if (tr[k] == 0 && tc[k] == 0) tv[k] = 3;
    tr[t] = 0;
    tc[t] = 0;
    tv[t++] = 1;

    /* Blocks: (0,0), (0,1), (1,1), with (1,0) empty and left out. */
    int64_t br[3] = {0, 0, 1}, bc[3] = {0, 1, 1};
    double bv[27];
    for (int b = 0; b < 3; ++b)
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 3; ++i) bv[9 * b + 3 * j + i] = A6[(3 * br[b] + i) + (3 * bc[b] + j) * 6];

    frix_matrix *M[5] = {0};
    ck_assert_int_eq(frix_matrix_from_dense(6, 6, A6, 6, &M[0]), FRIX_OK);
    ck_assert_int_eq(frix_matrix_from_csc(6, 6, cp, ri, v, &M[1]), FRIX_OK);
    ck_assert_int_eq(frix_matrix_from_csr(6, 6, rp, ci, rv, &M[2]), FRIX_OK);
    ck_assert_int_eq(frix_matrix_from_triplets(6, 6, t, tr, tc, tv, &M[3]), FRIX_OK);
    ck_assert_int_eq(frix_matrix_from_blocks(2, 2, 3, br, bc, bv, &M[4]), FRIX_OK);
    for (int k = 0; k < 5; ++k) {
        double D[36];
        ck_assert(frix_matrix_is_block(M[k]));
        ck_assert_int_eq(frix_matrix_block_count(M[k]), 3);
        ck_assert_int_eq(frix_matrix_nnz(M[k]), 27);
        to_dense(M[k], D);
        for (int i = 0; i < 36; ++i) ck_assert_double_eq(D[i], A6[i]);
        int64_t enz;
        ck_assert_int_eq(frix_matrix_to_csc(M[k], &enz, NULL, NULL, NULL), FRIX_OK);
        ck_assert_int_eq(enz, nnz);
        frix_matrix_free(M[k]);
    }
}
END_TEST

START_TEST(test_products_and_diagonal) {
    frix_matrix *M = NULL;
    ck_assert_int_eq(frix_matrix_from_dense(6, 6, A6, 6, &M), FRIX_OK);
    double x[6] = {1, -2, 3, 0.5, -1, 2}, y[6], yref[6], At[36];
    dense_gemv(A6, 6, 6, x, yref);
    for (int i = 0; i < 6; ++i) y[i] = 1.0;
    ck_assert_int_eq(frix_matrix_gemv(M, 2.0, x, 3.0, y), FRIX_OK);
    for (int i = 0; i < 6; ++i) ck_assert_double_eq_tol(y[i], 2 * yref[i] + 3, 1e-14);
    for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 6; ++j) At[j + i * 6] = A6[i + j * 6];
    dense_gemv(At, 6, 6, x, yref);
    for (int i = 0; i < 6; ++i) y[i] = NAN; /* beta = 0 must ignore y */
    ck_assert_int_eq(frix_matrix_gemv_transposed(M, 1.0, x, 0.0, y), FRIX_OK);
    for (int i = 0; i < 6; ++i) ck_assert_double_eq_tol(y[i], yref[i], 1e-14);
    double D[9];
    ck_assert_int_eq(frix_matrix_diagonal_block(M, 1, D), FRIX_OK);
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) ck_assert_double_eq(D[3 * j + i], A6[(3 + i) + (3 + j) * 6]);
    ck_assert_int_eq(frix_matrix_diagonal_block(M, 2, D), FRIX_ERR_DIMENSION);
    frix_matrix_free(M);
}
END_TEST

/* A 4x5 matrix (not block-shaped) is stored as general CSC and still works. */
START_TEST(test_general_sparse) {
    const double B[20] = {1, 0, 0, 2, 0, 3, 0, 0, 0, 0, 0, 0, 4, 0, 5, 0, 0, 0, 0, 6};
    frix_matrix *M = NULL;
    ck_assert_int_eq(frix_matrix_from_dense(4, 5, B, 4, &M), FRIX_OK);
    ck_assert(!frix_matrix_is_block(M));
    ck_assert_int_eq(frix_matrix_nnz(M), 6);
    ck_assert_int_eq(frix_matrix_block_count(M), 0);
    double x[5] = {1, 2, 3, 4, 5}, y[4], yref[4];
    dense_gemv(B, 4, 5, x, yref);
    ck_assert_int_eq(frix_matrix_gemv(M, 1.0, x, 0.0, y), FRIX_OK);
    for (int i = 0; i < 4; ++i) ck_assert_double_eq(y[i], yref[i]);
    double D[20];
    to_dense(M, D);
    for (int i = 0; i < 20; ++i) ck_assert_double_eq(D[i], B[i]);
    double Dblk[9];
    ck_assert_int_eq(frix_matrix_diagonal_block(M, 0, Dblk), FRIX_ERR_UNSUPPORTED);
    frix_matrix_free(M);
}
END_TEST

/* A matrix stored by columns (5 columns: not 3x3 blocks) is taken as given where every column's
 * rows strictly increase, and sorted and merged where they do not: the same matrix either way,
 * and the same refusals (a row out of range, a value not finite) with the same messages. */
START_TEST(test_columns_as_given) {
    int64_t cp[6] = {0, 2, 2, 5, 6, 7}, ri[7] = {0, 3, 0, 1, 3, 2, 1};
    double v[7] = {1, 2, 3, 4, 5, 6, 7}, D[20];
    frix_matrix *M = NULL;
    ck_assert_int_eq(frix_matrix_from_csc(4, 5, cp, ri, v, &M), FRIX_OK);
    int64_t nnz = 0, cp_out[6], ri_out[7];
    double v_out[7];
    ck_assert_int_eq(frix_matrix_to_csc(M, &nnz, cp_out, ri_out, v_out), FRIX_OK);
    ck_assert_int_eq(nnz, 7);
    ck_assert_mem_eq(cp_out, cp, sizeof cp);
    ck_assert_mem_eq(ri_out, ri, sizeof ri);
    ck_assert_mem_eq(v_out, v, sizeof v);
    frix_matrix_free(M);
    /* Column 2 unsorted with a duplicate: rows 3, 1, 3 (5 and 7 summed to 12 at row 3). */
    int64_t cp2[6] = {0, 2, 2, 5, 6, 6}, ri2[6] = {0, 3, 3, 1, 3, 2};
    double v2[6] = {1, 2, 5, 4, 7, 6}, ref2[20] = {0};
    for (int j = 0; j < 5; ++j)
        for (int64_t e = cp2[j]; e < cp2[j + 1]; ++e) ref2[ri2[e] + 4 * j] += v2[e];
    ck_assert_int_eq(frix_matrix_from_csc(4, 5, cp2, ri2, v2, &M), FRIX_OK);
    to_dense(M, D);
    for (int i = 0; i < 20; ++i) ck_assert_double_eq(D[i], ref2[i]);
    ck_assert_double_eq(D[3 + 4 * 2], 12.0);
    frix_matrix_free(M);
    /* Refusals on columns that are sorted. */
    int64_t far[7] = {0, 3, 0, 1, 4, 2, 1}; /* row 4 of a 4-row matrix */
    M = (frix_matrix *)0x1;
    ck_assert_int_eq(frix_matrix_from_csc(4, 5, cp, far, v, &M), FRIX_ERR_DIMENSION);
    ck_assert_ptr_null(M);
    ck_assert(strstr(frix_last_error_message(), "entry 4 at (4, 2) is outside the 4 x 5 matrix") != NULL);
    double inf[7] = {1, 2, 3, 4, 5, INFINITY, 7};
    ck_assert_int_eq(frix_matrix_from_csc(4, 5, cp, ri, inf, &M), FRIX_ERR_NOT_FINITE);
    ck_assert(strstr(frix_last_error_message(), "entry (2, 3) is not finite") != NULL);
}
END_TEST

/* The 4 x 5 matrix of (cp, ri, v) (nnz entries) by the reader's path is frix_matrix_from_csc's,
 * the vectors taken (1) or left as given (0) as `want_taken` says. */
static void taken_as_given(int64_t *cp, int64_t *ri, double *v, int64_t nnz, int want_taken) {
    double D[20], E[20];
    frix_matrix *M = NULL, *R = NULL;
    int taken = -2;
    ck_assert_int_eq(frix_testing_matrix_from_csc_taking(4, 5, cp, ri, v, nnz, &M, &taken), FRIX_OK);
    ck_assert_int_eq(taken, want_taken);
    ck_assert_int_eq(frix_matrix_from_csc(4, 5, cp, ri, v, &R), FRIX_OK);
    to_dense(M, D);
    to_dense(R, E);
    ck_assert_mem_eq(D, E, sizeof D);
    frix_matrix_free(M), frix_matrix_free(R);
}

/* The reader's path: sorted columns are taken into the matrix (the caller's vectors left
 * empty); unsorted ones are read and left as given; a bad entry is refused with
 * frix_matrix_from_csc's message, nothing taken. */
START_TEST(test_columns_taken) {
    int64_t cp[6] = {0, 2, 2, 5, 6, 7}, ri[7] = {0, 3, 0, 1, 3, 2, 1};
    double v[7] = {1, 2, 3, 4, 5, 6, 7};
    taken_as_given(cp, ri, v, 7, 1);
    int64_t cp2[6] = {0, 2, 2, 5, 6, 6}, ri2[6] = {0, 3, 3, 1, 3, 2};
    double v2[6] = {1, 2, 5, 4, 7, 6};
    taken_as_given(cp2, ri2, v2, 6, 0);
    int64_t far[7] = {0, 3, 0, 1, 4, 2, 1};
    frix_matrix *M = NULL;
    int taken = -2;
    ck_assert_int_eq(frix_testing_matrix_from_csc_taking(4, 5, cp, far, v, 7, &M, &taken), FRIX_ERR_DIMENSION);
    ck_assert_ptr_null(M);
    ck_assert_int_eq(taken, 0);
    ck_assert(strstr(frix_last_error_message(), "frix_matrix_from_csc: entry 4 at (4, 2) is outside the 4 x 5 matrix") !=
              NULL);
}
END_TEST

START_TEST(test_bad_input) {
    frix_matrix *M = (frix_matrix *)0x1;
    int64_t cp[4] = {0, 1, 1, 2}, ri[2] = {0, 5};
    double v[2] = {1, 2};
    ck_assert_int_eq(frix_matrix_from_csc(3, 3, cp, ri, v, &M), FRIX_ERR_DIMENSION); /* row 5 */
    ck_assert_ptr_null(M);
    ck_assert(strstr(frix_last_error_message(), "outside") != NULL);
    int64_t bad_cp[4] = {0, 2, 1, 2}, ri2[2] = {0, 1};
    ck_assert_int_eq(frix_matrix_from_csc(3, 3, bad_cp, ri2, v, &M), FRIX_ERR_DIMENSION);
    double nanv[2] = {1, NAN};
    int64_t cp2[4] = {0, 1, 1, 2};
    ck_assert_int_eq(frix_matrix_from_csc(3, 3, cp2, ri2, nanv, &M), FRIX_ERR_NOT_FINITE);
    ck_assert_int_eq(frix_matrix_from_csc(-1, 3, cp2, ri2, v, &M), FRIX_ERR_DIMENSION);
    ck_assert_int_eq(frix_matrix_from_csc(3, 3, NULL, ri2, v, &M), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_matrix_from_csc(3, 3, cp2, ri2, v, NULL), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_matrix_from_triplets(3, 3, -1, ri2, ri2, v, &M), FRIX_ERR_DIMENSION);
    ck_assert_int_eq(frix_matrix_from_dense(3, 3, v, 2, &M), FRIX_ERR_DIMENSION); /* ld < rows */
    int64_t br = 1, bc = 0;
    double bv[9] = {0};
    ck_assert_int_eq(frix_matrix_from_blocks(1, 1, 1, &br, &bc, bv, &M), FRIX_ERR_DIMENSION);
    /* A declared size far beyond any real problem is refused, not attempted. */
    ck_assert_int_eq(frix_matrix_from_triplets((int64_t)1 << 50, 3, 0, NULL, NULL, NULL, &M),
                     FRIX_ERR_DIMENSION);
    frix_matrix_free(NULL); /* NULL-safe */
}
END_TEST

/* A symmetric 9x9 matrix (3 block rows): dense diagonal blocks, blocks (0, 2) and (2, 0) with
 * three entries each (one a stored zero), and no block (0, 1) or (1, 0). `stored` marks the
 * entries given; the CSC arrays are built from both. */
enum { kS = 9 };
static void symmetric_case(double D[kS * kS], int stored[kS * kS]) {
    memset(D, 0, sizeof(double) * kS * kS);
    memset(stored, 0, sizeof(int) * kS * kS);
    for (int b = 0; b < 3; ++b)
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) {
                const int r = 3 * b + i, c = 3 * b + j;
                D[r + kS * c] = i == j ? 4.0 + b : 1.0 / (3.0 + i + j); /* symmetric */
                stored[r + kS * c] = 1;
            }
    D[1 + kS * 7] = D[7 + kS * 1] = 0.0; /* stored zeros */
    stored[1 + kS * 7] = stored[7 + kS * 1] = 1;
    D[0 + kS * 6] = D[6 + kS * 0] = 0.25; /* (0, 2) is not a symmetric block itself */
    D[1 + kS * 8] = D[8 + kS * 1] = 0.5;
    stored[0 + kS * 6] = stored[6 + kS * 0] = stored[1 + kS * 8] = stored[8 + kS * 1] = 1;
}
static int64_t to_csc(const double D[kS * kS], const int stored[kS * kS], int64_t cp[kS + 1], int64_t ri[kS * kS],
                      double v[kS * kS]) {
    int64_t e = 0;
    for (int j = 0; j < kS; ++j) {
        cp[j] = e;
        for (int i = 0; i < kS; ++i)
            if (stored[i + kS * j]) ri[e] = i, v[e++] = D[i + kS * j];
    }
    cp[kS] = e;
    return e;
}

/* The reduction assembles W column by column: a symmetric W (as CHOLMOD's are) has its column
 * storage turned into its row storage, anything else is copied into rows; both give the
 * matrix as given, to the bit, with frix_matrix_from_csc's blocks. */
START_TEST(test_matrix_from_columns) {
    double D[kS * kS], out[kS * kS], v[kS * kS];
    int stored[kS * kS], in_place = -1;
    int64_t cp[kS + 1], ri[kS * kS], blocks = -1;
    for (int t = 0; t < 5; ++t) {
        symmetric_case(D, stored);
        int symmetric = 1;
        int64_t expected_blocks = 5;
        if (t == 2) { /* one entry off by one unit in the last place */
            D[0 + kS * 1] = nextafter(D[0 + kS * 1], 1.0);
            symmetric = 0;
        } else if (t == 3) { /* block (2, 0) not stored */
            for (int i = 6; i < 9; ++i)
                for (int j = 0; j < 3; ++j) stored[i + kS * j] = 0, D[i + kS * j] = 0.0;
            symmetric = 0;
            expected_blocks = 4;
        } else if (t == 4) { /* -0 against +0: equal, not the same bits */
            D[7 + kS * 1] = -0.0;
            symmetric = 0;
        }
        to_csc(D, stored, cp, ri, v);
        /* Without room reserved (t = 0), with more than needed (t > 0). */
        ck_assert_int_eq(frix_testing_matrix_from_columns(kS, cp, ri, v, t == 0 ? 0.0 : 100.0, out, &blocks, &in_place),
                         FRIX_OK);
        ck_assert_msg(in_place == symmetric, "case %d: in_place %d", t, in_place);
        ck_assert(memcmp(out, D, sizeof D) == 0);
        ck_assert_int_eq(blocks, expected_blocks);
        frix_matrix *M = NULL;
        ck_assert_int_eq(frix_matrix_from_csc(kS, kS, cp, ri, v, &M), FRIX_OK);
        ck_assert_int_eq(frix_matrix_block_count(M), blocks);
        frix_matrix_free(M);
    }
    /* A non-finite entry is refused. */
    symmetric_case(D, stored);
    D[4 + kS * 4] = NAN;
    to_csc(D, stored, cp, ri, v);
    ck_assert_int_eq(frix_testing_matrix_from_columns(kS, cp, ri, v, 0.0, out, &blocks, &in_place),
                     FRIX_ERR_NOT_FINITE);
}
END_TEST

START_TEST(test_empty_matrix) {
    frix_matrix *M = NULL;
    ck_assert_int_eq(frix_matrix_from_triplets(0, 0, 0, NULL, NULL, NULL, &M), FRIX_OK);
    ck_assert_int_eq(frix_matrix_rows(M), 0);
    ck_assert_int_eq(frix_matrix_nnz(M), 0);
    int64_t nnz = -1, cp[1] = {-1};
    ck_assert_int_eq(frix_matrix_to_csc(M, &nnz, NULL, NULL, NULL), FRIX_OK);
    ck_assert_int_eq(nnz, 0);
    /* No entries: the index and value arrays have length 0 and may be NULL; colptr may not. */
    ck_assert_int_eq(frix_matrix_to_csc(M, &nnz, cp, NULL, NULL), FRIX_OK);
    ck_assert_int_eq(cp[0], 0);
    int64_t ri[1];
    double x[1];
    ck_assert_int_eq(frix_matrix_to_csc(M, &nnz, NULL, ri, x), FRIX_ERR_INVALID_ARGUMENT);
    frix_matrix_free(M);
}
END_TEST

int main(void) {
    Suite *s = suite_create("matrix");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, test_all_constructors_agree);
    tcase_add_test(tc, test_products_and_diagonal);
    tcase_add_test(tc, test_general_sparse);
    tcase_add_test(tc, test_bad_input);
    tcase_add_test(tc, test_columns_as_given);
    tcase_add_test(tc, test_empty_matrix);
    tcase_add_test(tc, test_matrix_from_columns);
    tcase_add_test(tc, test_duplicates_summing_past_the_doubles);
    tcase_add_test(tc, test_advised_arrays);
    tcase_add_test(tc, test_columns_taken);
    suite_add_tcase(s, tc);
    return frix_run_suite(s);
}
