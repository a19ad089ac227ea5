/* The linear algebra back-end (src/linalg) through tests/frix_testing.h: UMFPACK with its
 * symbolic analysis reused, CHOLMOD solves and B^T A^-1 B, dense LAPACK LU and Cholesky, and
 * factorisation failures returned as frix_error values. */
#include <frix/frix.h>
#include <math.h>

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
    tcase_add_test(tc, dense_lu_and_cholesky);
    suite_add_tcase(s, tc);
    return frix_run_suite(s);
}
