/* The linear algebra back-end (src/linalg) through tests/frix_testing.h: UMFPACK with its
 * symbolic analysis reused, CHOLMOD solves and B^T A^-1 B, dense LAPACK LU and Cholesky, and
 * factorisation failures returned as frix_error values. */
#include <frix/frix.h>
#include <math.h>
#include <string.h>

#include "check_main.h"
#include "frix_testing.h"

/* A = [[4, 1, 0], [1, 3, 1], [0, 1, 2]] (SPD), CSC. */
static const int64_t kP[4] = {0, 2, 5, 7};
static const int64_t kI[7] = {0, 1, 0, 1, 2, 1, 2};
static const double kX[7] = {4, 1, 1, 3, 1, 1, 2};
static const double kDense[9] = {4, 1, 0, 1, 3, 1, 0, 1, 2};

static void check_solution(const double *x, double factor) {
    /* A (1, 2, 3) = (6, 10, 8). */
    const double want[3] = {1, 2, 3};
    for (int i = 0; i < 3; ++i) ck_assert_double_eq_tol(x[i], want[i] * factor, 1e-13);
}

START_TEST(sparse_lu_reuses_symbolic) {
    const double b[3] = {6, 10, 8};
    double x[3];
    int64_t sym = 0, num = 0;
    ck_assert_int_eq(frix_testing_sparse_lu(3, kP, kI, kX, b, x, &sym, &num), FRIX_OK);
    check_solution(x, 0.5); /* the second factorisation is of 2A */
    ck_assert_int_eq(sym, 1);
    ck_assert_int_eq(num, 2);
}
END_TEST

START_TEST(sparse_lu_singular_is_an_error) {
    /* [[1, 1], [1, 1]]: the factorisation fails cleanly. */
    const int64_t p[3] = {0, 2, 4}, i[4] = {0, 1, 0, 1};
    const double v[4] = {1, 1, 1, 1}, b[2] = {1, 1};
    double x[2];
    int64_t sym = 0, num = 0;
    ck_assert_int_eq(frix_testing_sparse_lu(2, p, i, v, b, x, &sym, &num), FRIX_ERR_NUMERICAL);
    ck_assert(frix_last_error_message()[0] != '\0');
}
END_TEST

START_TEST(sparse_cholesky_and_congruence) {
    const double b[3] = {6, 10, 8};
    double x[3], C[4];
    /* B = [[1, 0], [0, 0], [0, 1]]: C = B^T A^-1 B = the (0, 2) corner of A^-1. */
    const int64_t bp[3] = {0, 1, 2}, bi[2] = {0, 2};
    const double bx[2] = {1, 1};
    ck_assert_int_eq(frix_testing_sparse_cholesky(3, kP, kI, kX, b, x, 2, bp, bi, bx, C), FRIX_OK);
    check_solution(x, 1.0);
    /* det A = 18; A^-1(0,0) = 5/18, A^-1(2,2) = 11/18, A^-1(0,2) = 1/18. */
    ck_assert_double_eq_tol(C[0], 5.0 / 18.0, 1e-14);
    ck_assert_double_eq_tol(C[3], 11.0 / 18.0, 1e-14);
    ck_assert_double_eq_tol(C[1], 1.0 / 18.0, 1e-14);
    ck_assert_double_eq_tol(C[2], 1.0 / 18.0, 1e-14);
    /* Not positive definite: an error, not a crash. */
    const double neg[7] = {-4, 1, 1, 3, 1, 1, 2};
    ck_assert_int_eq(frix_testing_sparse_cholesky(3, kP, kI, neg, b, x, 0, NULL, NULL, NULL, NULL),
                     FRIX_ERR_NUMERICAL);
}
END_TEST

/* A = tridiag(-1, 4, -1) of size 16, CSC (both triangles); B (16 x 13) with column j holding
 * j + 1 at row j and 1 at row j + 3. */
enum { kN = 16, kK = 13 };
static void build_congruence_case(int64_t ap[kN + 1], int64_t ai[3 * kN], double ax[3 * kN],
                                  int64_t bp[kK + 1], int64_t bi[2 * kK], double bx[2 * kK]) {
    int64_t e = 0;
    for (int j = 0; j < kN; ++j) {
        ap[j] = e;
        for (int i = j - 1; i <= j + 1; ++i)
            if (i >= 0 && i < kN) {
                ai[e] = i;
                ax[e++] = i == j ? 4.0 : -1.0;
            }
    }
    ap[kN] = e;
    for (int j = 0; j < kK; ++j) {
        bp[j] = 2 * j;
        bi[2 * j] = j;
        bx[2 * j] = j + 1.0;
        bi[2 * j + 1] = j + 3;
        bx[2 * j + 1] = 1.0;
    }
    bp[kK] = 2 * kK;
}

/* The price of a factorisation before it is paid: L of a tridiagonal matrix of size 10 has
 * 19 entries, of a dense one of size 6 has 21; the dense one costs more flops per entry. */
START_TEST(cholesky_cost_from_the_pattern) {
    int64_t tp[11], ti[30], e = 0;
    for (int j = 0; j < 10; ++j) {
        tp[j] = e;
        for (int i = j - 1; i <= j + 1; ++i)
            if (i >= 0 && i < 10) ti[e++] = i;
    }
    tp[10] = e;
    double flops = 0.0, entries = 0.0;
    ck_assert_int_eq(frix_testing_cholesky_cost(10, tp, ti, &flops, &entries), FRIX_OK);
    ck_assert_double_eq(entries, 19.0);
    ck_assert_double_gt(flops, 0.0);
    const double tridiagonal_ratio = flops / entries;
    int64_t dp[7], di[21];
    e = 0;
    for (int j = 0; j < 6; ++j) {  /* the upper triangle only */
        dp[j] = e;
        for (int i = 0; i <= j; ++i) di[e++] = i;
    }
    dp[6] = e;
    ck_assert_int_eq(frix_testing_cholesky_cost(6, dp, di, &flops, &entries), FRIX_OK);
    ck_assert_double_eq(entries, 21.0);
    ck_assert_double_gt(flops / entries, tridiagonal_ratio);
    /* No rows: nothing to pay. */
    const int64_t zp[1] = {0};
    ck_assert_int_eq(frix_testing_cholesky_cost(0, zp, NULL, &flops, &entries), FRIX_OK);
    ck_assert_double_eq(flops, 0.0);
}
END_TEST

START_TEST(congruence_in_blocks_is_the_same_and_stops_when_asked) {
    int64_t ap[kN + 1], ai[3 * kN], bp[kK + 1], bi[2 * kK], nnz = -1;
    double ax[3 * kN], bx[2 * kK], whole[kK * kK], blocked[kK * kK];
    build_congruence_case(ap, ai, ax, bp, bi, bx);
    int questions = -1, stopped = -1;
    /* One block of 16 columns: asked once, after Z (not after C's last block). */
    ck_assert_int_eq(frix_testing_congruence_in_blocks(kN, ap, ai, ax, kK, bp, bi, bx, 16, 0, whole,
                                                       &questions, &stopped, &nnz),
                     FRIX_OK);
    ck_assert_int_eq(questions, 1);
    ck_assert_int_eq(stopped, 0);
    ck_assert_int_eq(nnz, kK * kK); /* A^-1 is dense: so is C */
    /* C = B^T A^-1 B: symmetric to the bit (the reduction hands W's columns over as its rows
     * when it is), positive diagonal. */
    for (int i = 0; i < kK; ++i) {
        ck_assert(whole[i + kK * i] > 0.0);
        for (int j = 0; j < kK; ++j) ck_assert(memcmp(&whole[i + kK * j], &whole[j + kK * i], sizeof(double)) == 0);
    }
    /* Blocks of 8 and of 4 columns (1 is taken as 4): the same bits, one question per block of
     * Z and per block of C but the last. */
    const int cols[3] = {8, 4, 1}, blocks[3] = {2, 4, 4};
    for (int t = 0; t < 3; ++t) {
        ck_assert_int_eq(frix_testing_congruence_in_blocks(kN, ap, ai, ax, kK, bp, bi, bx, cols[t], 0,
                                                           blocked, &questions, &stopped, &nnz),
                         FRIX_OK);
        ck_assert_int_eq(questions, 2 * blocks[t] - 1);
        ck_assert_int_eq(stopped, 0);
        ck_assert(memcmp(whole, blocked, sizeof whole) == 0);
    }
    /* Told to stop while forming Z (2nd question of 4) and while forming C (6th): it stops
     * there, with nothing returned. */
    const int stop_at[2] = {2, 6};
    for (int t = 0; t < 2; ++t) {
        ck_assert_int_eq(frix_testing_congruence_in_blocks(kN, ap, ai, ax, kK, bp, bi, bx, 4, stop_at[t],
                                                           blocked, &questions, &stopped, &nnz),
                         FRIX_OK);
        ck_assert_int_eq(questions, stop_at[t]);
        ck_assert_int_eq(stopped, 1);
        ck_assert_int_eq(nnz, 0);
    }
}
END_TEST

START_TEST(dense_lu_and_cholesky) {
    const double b[3] = {6, 10, 8};
    double x[3];
    ck_assert_int_eq(frix_testing_dense_solve(0, 3, kDense, b, x), FRIX_OK);
    check_solution(x, 1.0);
    ck_assert_int_eq(frix_testing_dense_solve(1, 3, kDense, b, x), FRIX_OK);
    check_solution(x, 1.0);
    const double singular[4] = {1, 2, 2, 4}, b2[2] = {1, 1};
    ck_assert_int_eq(frix_testing_dense_solve(0, 2, singular, b2, x), FRIX_ERR_NUMERICAL);
    ck_assert_int_eq(frix_testing_dense_solve(1, 2, singular, b2, x), FRIX_ERR_NUMERICAL);
}
END_TEST

int main(void) {
    Suite *s = suite_create("linalg");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, sparse_lu_reuses_symbolic);
    tcase_add_test(tc, sparse_lu_singular_is_an_error);
    tcase_add_test(tc, sparse_cholesky_and_congruence);
    tcase_add_test(tc, congruence_in_blocks_is_the_same_and_stops_when_asked);
    tcase_add_test(tc, dense_lu_and_cholesky);
    tcase_add_test(tc, cholesky_cost_from_the_pattern);
    suite_add_tcase(s, tc);
    return frix_run_suite(s);
}
