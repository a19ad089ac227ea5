/* Problems: validation at the boundary, zero contacts, all-separating contacts, borrowed
 * data re-checked at solve time, global problem validation. */
#include <frix/frix.h>
#include <math.h>
#include <string.h>

#include "check_main.h"

static const double I6[36] = {2, 0, 0, 0, 0, 0, 0, 2, 0, 0, 0, 0, 0, 0, 2, 0, 0, 0,
                              0, 0, 0, 2, 0, 0, 0, 0, 0, 0, 2, 0, 0, 0, 0, 0, 0, 2};

static frix_matrix *dense(int64_t m, int64_t n, const double *a) {
    frix_matrix *M = NULL;
    ck_assert_int_eq(frix_matrix_from_dense(m, n, a, m, &M), FRIX_OK);
    return M;
}

START_TEST(test_local_validation) {
    frix_matrix *W = dense(6, 6, I6);
    double q[6] = {-1, 0, 0, -1, 0, 0}, mu[2] = {0.3, 0.3};
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_problem_local(W, q, mu, 2, &p), FRIX_OK);
    ck_assert_int_eq(frix_problem_contacts(p), 2);
    ck_assert_int_eq(frix_problem_contact_dofs(p), 6);
    ck_assert_int_eq(frix_problem_dofs(p), 0);
    ck_assert_int_eq(frix_problem_get_kind(p), FRIX_PROBLEM_LOCAL);
    ck_assert_ptr_eq(frix_problem_W(p), W);
    ck_assert_ptr_eq(frix_problem_q(p), q); /* borrowed, not copied */
    ck_assert_ptr_null(frix_problem_M(p));
    ck_assert_int_eq(frix_problem_set_title(p, "two contacts"), FRIX_OK);
    ck_assert_str_eq(frix_problem_title(p), "two contacts");
    frix_problem_free(p);

    frix_problem *bad = (frix_problem *)0x1;
    ck_assert_int_eq(frix_problem_local(W, q, mu, 3, &bad), FRIX_ERR_DIMENSION);
    ck_assert_ptr_null(bad);
    ck_assert(strstr(frix_last_error_message(), "contacts") != NULL);
    double mu_neg[2] = {0.3, -0.1};
    ck_assert_int_eq(frix_problem_local(W, q, mu_neg, 2, &bad), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert(strstr(frix_last_error_message(), "mu[1]") != NULL);
    double mu_nan[2] = {NAN, 0.3};
    ck_assert_int_eq(frix_problem_local(W, q, mu_nan, 2, &bad), FRIX_ERR_NOT_FINITE);
    double q_inf[6] = {-1, 0, INFINITY, -1, 0, 0};
    ck_assert_int_eq(frix_problem_local(W, q_inf, mu, 2, &bad), FRIX_ERR_NOT_FINITE);
    ck_assert(strstr(frix_last_error_message(), "q[2]") != NULL);
    ck_assert_int_eq(frix_problem_local(W, NULL, mu, 2, &bad), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_problem_local(NULL, q, mu, 2, &bad), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_problem_local(W, q, mu, -1, &bad), FRIX_ERR_DIMENSION);
    frix_matrix_free(W);

    /* Non-square W, and square W whose size is not a multiple of 3. */
    double a[24] = {0};
    frix_matrix *R = dense(6, 4, a);
    ck_assert_int_eq(frix_problem_local(R, q, mu, 2, &bad), FRIX_ERR_DIMENSION);
    ck_assert(strstr(frix_last_error_message(), "not square") != NULL);
    frix_matrix_free(R);
    frix_matrix *S = dense(4, 4, a);
    ck_assert_int_eq(frix_problem_local(S, q, mu, 2, &bad), FRIX_ERR_DIMENSION);
    ck_assert(strstr(frix_last_error_message(), "multiple of 3") != NULL);
    frix_matrix_free(S);
    frix_problem_free(NULL); /* NULL-safe */
}
END_TEST

START_TEST(test_zero_contacts) {
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_problem_local(NULL, NULL, NULL, 0, &p), FRIX_OK);
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_solve(p, NULL, NULL, NULL, NULL, info), FRIX_OK);
    ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_CONVERGED);
    ck_assert_int_eq(frix_info_iterations(info), 0);
    ck_assert_double_eq(frix_info_error(info), 0.0);
    frix_info_free(info);
    frix_problem_free(p);
}
END_TEST

START_TEST(test_all_separating) {
    frix_matrix *W = dense(6, 6, I6);
    double q[6] = {0.5, 0.1, 0, 0.0, -3, 2}, mu[2] = {0.3, 0.3};
    double r[6] = {1, 2, 3, 4, 5, 6}, u[6];
    frix_problem *p = NULL;
    frix_info *info = NULL;
    ck_assert_int_eq(frix_problem_local(W, q, mu, 2, &p), FRIX_OK);
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_solve(p, NULL, r, u, NULL, info), FRIX_OK);
    ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_CONVERGED);
    ck_assert_int_eq(frix_info_iterations(info), 0);
    for (int i = 0; i < 6; ++i) {
        ck_assert_double_eq(r[i], 0.0);
        ck_assert_double_eq(u[i], q[i]);
    }
    ck_assert_double_eq(frix_info_error(info), 0.0);
    frix_info_free(info);
    frix_problem_free(p);
    frix_matrix_free(W);
}
END_TEST

/* The problem borrows q: a NaN written into it after creation is caught at solve time. */
START_TEST(test_borrowed_q_rechecked) {
    frix_matrix *W = dense(6, 6, I6);
    double q[6] = {-1, 0, 0, -1, 0, 0}, mu[2] = {0.3, 0.3}, r[6] = {0}, u[6];
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_problem_local(W, q, mu, 2, &p), FRIX_OK);
    q[4] = NAN;
    ck_assert_int_eq(frix_solve(p, NULL, r, u, NULL, NULL), FRIX_ERR_NOT_FINITE);
    ck_assert(strstr(frix_last_error_message(), "q[4]") != NULL);
    q[4] = 0;
    ck_assert_int_eq(frix_solve(p, NULL, NULL, u, NULL, NULL), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_solve(NULL, NULL, r, u, NULL, NULL), FRIX_ERR_INVALID_ARGUMENT);
    frix_problem_free(p);
    frix_matrix_free(W);
}
END_TEST

START_TEST(test_global_validation) {
    /* n = 4 dofs (not a multiple of 3: general storage), 1 contact. */
    const double m4[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    const double h[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    frix_matrix *M = dense(4, 4, m4), *H = dense(4, 3, h);
    double f[4] = {0, 0, -1, 0}, w[3] = {0, 0, 0}, mu = 0.5;
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_problem_global(M, H, f, w, &mu, 1, &p), FRIX_OK);
    ck_assert_int_eq(frix_problem_get_kind(p), FRIX_PROBLEM_GLOBAL);
    ck_assert_int_eq(frix_problem_dofs(p), 4);
    ck_assert_ptr_eq(frix_problem_H(p), H);
    /* Measures of a given (r, v): M v - H r - f = 0 for v = (0,0,-1,0) + H r with r = 0. */
    double r[3] = {0, 0, 0}, v[4] = {0, 0, -1, 0}, u[3];
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_problem_measure(p, r, v, u, info), FRIX_OK);
    double eq;
    ck_assert_int_eq(frix_info_get_double(info, FRIX_INFO_EQUILIBRIUM, &eq), FRIX_OK);
    ck_assert_double_eq_tol(eq, 0.0, 1e-15);
    ck_assert_double_eq(u[0], 0.0); /* u = H^T v + w */
    ck_assert_double_eq(u[2], -1.0);
    ck_assert_int_eq(frix_problem_measure(p, r, NULL, u, info), FRIX_ERR_INVALID_ARGUMENT);
    frix_info_free(info);
    /* Solved through the reduction W = H^T M^-1 H (here q_N = 0: r = 0, v = M^-1 f). */
    v[2] = 5.0;
    ck_assert_int_eq(frix_solve(p, NULL, r, u, v, NULL), FRIX_OK);
    ck_assert_double_eq_tol(v[2], -1.0, 1e-14);
    ck_assert_int_eq(frix_solve(p, NULL, r, u, NULL, NULL), FRIX_ERR_INVALID_ARGUMENT);
    frix_problem_free(p);

    frix_problem *bad = NULL;
    ck_assert_int_eq(frix_problem_global(M, H, f, w, &mu, 2, &bad), FRIX_ERR_DIMENSION);
    ck_assert_int_eq(frix_problem_global(H, H, f, w, &mu, 1, &bad), FRIX_ERR_DIMENSION);
    f[1] = NAN;
    ck_assert_int_eq(frix_problem_global(M, H, f, w, &mu, 1, &bad), FRIX_ERR_NOT_FINITE);
    frix_matrix_free(M);
    frix_matrix_free(H);
}
END_TEST

int main(void) {
    Suite *s = suite_create("problem");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, test_local_validation);
    tcase_add_test(tc, test_zero_contacts);
    tcase_add_test(tc, test_all_separating);
    tcase_add_test(tc, test_borrowed_q_rechecked);
    tcase_add_test(tc, test_global_validation);
    suite_add_tcase(s, tc);
    return frix_run_suite(s);
}
