/* Rolling and spinning friction (frix_problem.h, frix_problem_spinning_*): the problem class and
 * its validation, and the measure of the six-entry law on hand-checked contacts (spinning
 * friction sliding, every cone cut back at once). */
#include <frix/frix.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check_main.h"

static frix_matrix *identity(int64_t m) {
    double *a = calloc((size_t)(m * m), sizeof(double));
    for (int64_t i = 0; i < m; ++i) a[i + m * i] = 1.0;
    frix_matrix *I = NULL;
    ck_assert_int_eq(frix_matrix_from_dense(m, m, a, m, &I), FRIX_OK);
    free(a);
    return I;
}

START_TEST(test_validation) {
    frix_matrix *W = identity(12);
    double q[12] = {-1, 0, 0, 0, 0, 0, -1, 0, 0, 0, 0, 0};
    double mu[2] = {0.3, 0.3}, mu_r[2] = {0.01, 0.02}, mu_s[2] = {0.001, 0.002};
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_problem_spinning_local(W, q, mu, mu_r, mu_s, 2, &p), FRIX_OK);
    ck_assert_int_eq(frix_problem_get_kind(p), FRIX_PROBLEM_ROLLING_LOCAL);
    ck_assert_int_eq(frix_problem_contact_dofs(p), 12);
    ck_assert_ptr_eq(frix_problem_mu_r(p), mu_r);
    ck_assert_ptr_eq(frix_problem_mu_s(p), mu_s);
    frix_problem_free(p);

    /* A rolling problem of five entries has no mu_s. */
    frix_matrix *W10 = identity(10);
    ck_assert_int_eq(frix_problem_rolling_local(W10, q, mu, mu_r, 2, &p), FRIX_OK);
    ck_assert_ptr_null(frix_problem_mu_s(p));
    frix_problem_free(p);

    frix_problem *bad = (frix_problem *)0x1;
    ck_assert_int_eq(frix_problem_spinning_local(W, q, mu, mu_r, NULL, 2, &bad), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_ptr_null(bad);
    ck_assert(strstr(frix_last_error_message(), "mu_s") != NULL);
    double neg[2] = {0.01, -1e-3};
    ck_assert_int_eq(frix_problem_spinning_local(W, q, mu, mu_r, neg, 2, &bad), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert(strstr(frix_last_error_message(), "mu_s[1]") != NULL);
    double nan_s[2] = {NAN, 0.01};
    ck_assert_int_eq(frix_problem_spinning_local(W, q, mu, mu_r, nan_s, 2, &bad), FRIX_ERR_NOT_FINITE);
    /* Sizes: 10 rows are two contacts of five entries, not of six. */
    ck_assert_int_eq(frix_problem_spinning_local(W10, q, mu, mu_r, mu_s, 2, &bad), FRIX_ERR_DIMENSION);
    ck_assert(strstr(frix_last_error_message(), "multiple of 6") != NULL);

    /* Global form: H is n x 6nc. */
    frix_matrix *M = identity(6), *H10 = NULL, *H = NULL;
    double zeros[72] = {0}, f[6] = {0}, w[12] = {0};
    ck_assert_int_eq(frix_matrix_from_dense(6, 10, zeros, 6, &H10), FRIX_OK);
    ck_assert_int_eq(frix_problem_spinning_global(M, H10, f, w, mu, mu_r, mu_s, 2, &bad), FRIX_ERR_DIMENSION);
    ck_assert(strstr(frix_last_error_message(), "6*contacts") != NULL);
    ck_assert_int_eq(frix_matrix_from_dense(6, 12, zeros, 6, &H), FRIX_OK);
    ck_assert_int_eq(frix_problem_spinning_global(M, H, f, w, mu, mu_r, mu_s, 2, &p), FRIX_OK);
    ck_assert_int_eq(frix_problem_get_kind(p), FRIX_PROBLEM_ROLLING_GLOBAL);
    ck_assert_int_eq(frix_problem_contact_dofs(p), 12);
    ck_assert_ptr_eq(frix_problem_mu_s(p), mu_s);
    frix_problem_free(p);
    frix_matrix_free(H);
    frix_matrix_free(H10);
    frix_matrix_free(M);
    frix_matrix_free(W10);
    frix_matrix_free(W);
}
END_TEST

/* W = I: r solves the one contact when its residual is 0, and at r = 0 the residual is |P_K(-q^)|. */
static void check_case(const double q[6], const double r[6], double mu, double mu_r, double mu_s,
                       double residual_at_zero) {
    frix_matrix *W = identity(6);
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_problem_spinning_local(W, q, &mu, &mu_r, &mu_s, 1, &p), FRIX_OK);
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    double u[6], zero[6] = {0}, e = NAN;
    ck_assert_int_eq(frix_problem_measure(p, r, NULL, u, info), FRIX_OK);
    ck_assert_int_eq(frix_info_get_double(info, FRIX_INFO_ERROR_RELATIVE, &e), FRIX_OK);
    ck_assert_double_le(e, 1e-15);
    for (int i = 0; i < 6; ++i) ck_assert_double_eq_tol(u[i], r[i] + q[i], 1e-15);
    ck_assert_int_eq(frix_problem_measure(p, zero, NULL, u, info), FRIX_OK);
    ck_assert_int_eq(frix_info_get_double(info, FRIX_INFO_RESIDUAL_ABSOLUTE, &e), FRIX_OK);
    ck_assert_double_eq_tol(e, residual_at_zero, 1e-14);
    /* An r off the spinning cone is not a solution. */
    double off[6];
    memcpy(off, r, sizeof off);
    off[5] = 2.0 * mu_s * r[0] + 1.0;
    ck_assert_int_eq(frix_problem_measure(p, off, NULL, u, info), FRIX_OK);
    ck_assert_int_eq(frix_info_get_double(info, FRIX_INFO_CONE_VIOLATION, &e), FRIX_OK);
    ck_assert_double_gt(e, 1e-4);
    frix_info_free(info);
    frix_problem_free(p);
    frix_matrix_free(W);
}

START_TEST(test_measure_by_hand) {
    /* Spinning while pressed: r = (1, 0, 0, 0, 0, -mu_s), u = (0, 0, 0, 0, 0, 0.03) (r_S on its
     * bound, opposing w_S; u^_N = mu_s |w_S| makes r . u^ = 0). At r = 0, x = -q^ = (0.999, 0, 0,
     * 0, 0, -0.05) is cut on the spinning interval alone: t = (0.999 + mu_s 0.05) / (1 + mu_s^2)
     * = 1 / 1.0004, and the residual is t sqrt(1 + mu_s^2) = 1 / sqrt(1.0004). */
    const double q_spin[6] = {-1, 0, 0, 0, 0, 0.05}, r_spin[6] = {1, 0, 0, 0, 0, -0.02};
    check_case(q_spin, r_spin, 0.5, 0.01, 0.02, 1.0 / sqrt(1.0004));
    /* Sticking with every part loaded: all coefficients 1, q = (-3, -1, 0, -1, 0, -1), r = -q
     * inside K, u = 0. At r = 0, x = -q^ = (0, 1, 0, 1, 0, 1) is cut on all three parts: t = (0 +
     * 1 + 1 + 1) / (1 + 3) = 0.75, every part cut to 0.75, and the residual is 0.75 * 2. */
    const double q_all[6] = {-3, -1, 0, -1, 0, -1}, r_all[6] = {3, 1, 0, 1, 0, 1};
    check_case(q_all, r_all, 1.0, 1.0, 1.0, 1.5);
}
END_TEST

/* The persistent solver's calls of the six-entry law: they take its contacts and coefficients,
 * and refuse those of another law or form, naming the call to use. */
START_TEST(test_persistent_calls) {
    frix_matrix *W = identity(12), *W10 = identity(10);
    double q[12] = {-1, 0, 0, 0, 0, 0.05, -1, 0, 0, 0, 0, 0};
    double mu[2] = {0.3, 0.3}, mu_r[2] = {0.01, 0.02}, mu_s[2] = {0.001, 0.002}, neg[2] = {0.001, -1.0};
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_problem_spinning_local(W, q, mu, mu_r, mu_s, 2, &p), FRIX_OK);
    frix_persistent *ps = NULL;
    ck_assert_int_eq(frix_persistent_create(p, NULL, &ps), FRIX_OK);
    ck_assert_int_eq(frix_persistent_update_mu_s(ps, mu_s), FRIX_OK);
    ck_assert_int_eq(frix_persistent_update_mu_r(ps, mu_r), FRIX_OK);
    ck_assert_int_eq(frix_persistent_update_mu_s(ps, neg), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert(strstr(frix_last_error_message(), "mu_s[1]") != NULL);
    ck_assert_int_eq(frix_persistent_set_contacts_spinning_local(ps, W, q, mu, mu_r, mu_s, 2), FRIX_OK);
    ck_assert_int_eq(frix_persistent_set_contacts_spinning_local(ps, W, q, mu, mu_r, NULL, 2),
                     FRIX_ERR_INVALID_ARGUMENT);
    ck_assert(strstr(frix_last_error_message(), "mu_s is NULL") != NULL);
    ck_assert_int_eq(frix_persistent_set_contacts_spinning_local(ps, W10, q, mu, mu_r, mu_s, 2), FRIX_ERR_DIMENSION);
    ck_assert_int_eq(frix_persistent_set_contacts_rolling_local(ps, W10, q, mu, mu_r, 2), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert(strstr(frix_last_error_message(), "frix_persistent_set_contacts_spinning_local") != NULL);
    ck_assert_int_eq(frix_persistent_set_contacts_spinning_global(ps, W, q, mu, mu_r, mu_s, 2),
                     FRIX_ERR_INVALID_ARGUMENT);
    ck_assert(strstr(frix_last_error_message(), "the problem is local") != NULL);
    frix_persistent_free(ps);
    frix_problem_free(p);
    frix_matrix_free(W10);
    frix_matrix_free(W);
}
END_TEST

int main(void) {
    Suite *s = suite_create("spinning");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, test_validation);
    tcase_add_test(tc, test_measure_by_hand);
    tcase_add_test(tc, test_persistent_calls);
    suite_add_tcase(s, tc);
    return frix_run_suite(s);
}
