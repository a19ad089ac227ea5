/* The error measures against values computed by hand on one contact with W = I:
 * taking off, sticking inside the cone, sliding on its boundary, r - u^ in the polar cone,
 * and mu = 0. Each case also checks the physical measures. */
#include <frix/frix.h>
#include <math.h>

#include "check_main.h"

typedef struct {
    double rel, qrel, scaled, abs, cone, pen, compl;
} measured;

static measured measure_one(double mu, const double q[3], const double r[3], double u[3]) {
    static const double I3[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    frix_matrix *W = NULL;
    frix_problem *p = NULL;
    frix_info *info = NULL;
    ck_assert_int_eq(frix_matrix_from_dense(3, 3, I3, 3, &W), FRIX_OK);
    ck_assert_int_eq(frix_problem_local(W, q, &mu, 1, &p), FRIX_OK);
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_problem_measure(p, r, NULL, u, info), FRIX_OK);
    measured m;
    frix_info_get_double(info, FRIX_INFO_ERROR_RELATIVE, &m.rel);
    frix_info_get_double(info, FRIX_INFO_ERROR_Q_RELATIVE, &m.qrel);
    frix_info_get_double(info, FRIX_INFO_ERROR_SCALED, &m.scaled);
    frix_info_get_double(info, FRIX_INFO_RESIDUAL_ABSOLUTE, &m.abs);
    frix_info_get_double(info, FRIX_INFO_CONE_VIOLATION, &m.cone);
    frix_info_get_double(info, FRIX_INFO_PENETRATION, &m.pen);
    frix_info_get_double(info, FRIX_INFO_COMPLEMENTARITY, &m.compl);
    double e;
    ck_assert_int_eq(frix_problem_error(p, r, NULL, &e), FRIX_OK);
    ck_assert_double_eq(e, m.scaled); /* the shortcut gives the default measure */
    ck_assert_double_eq(frix_info_error(info), m.scaled);
    /* W = I: each contact's weight is 1, so the scaled residual is the plain one, over
     * max(|q|, |u|). */
    const double nq = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
    const double nu = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    const double floor = nq > nu ? nq : nu;
    if (floor > 1e-300 && floor < 1e300 && m.abs < 1e300)
        ck_assert_double_eq_tol(m.scaled, m.abs / floor, 1e-14 * (1.0 + m.scaled));
    frix_info_free(info);
    frix_problem_free(p);
    frix_matrix_free(W);
    return m;
}

START_TEST(test_taking_off) {
    double q[3] = {1, 0, 0}, r0[3] = {0, 0, 0}, u[3];
    measured m = measure_one(0.5, q, r0, u);
    ck_assert_double_eq(m.abs, 0.0);
    ck_assert_double_eq(u[0], 1.0);
    /* Pushing while separating: u = (2,0,0), r - u^ = (-1,0,0) projects to 0, residual |r| = 1,
     * scale max(|q|=1, |r|=1, |u|=2) = 2. */
    double r1[3] = {1, 0, 0};
    m = measure_one(0.5, q, r1, u);
    ck_assert_double_eq_tol(m.abs, 1.0, 1e-15);
    ck_assert_double_eq_tol(m.rel, 0.5, 1e-15);
    ck_assert_double_eq_tol(m.qrel, 1.0, 1e-15);
    ck_assert_double_eq_tol(m.compl, 2.0, 1e-15); /* r . u^ = 1 * 2 */
    ck_assert_double_eq(m.pen, 0.0);
}
END_TEST

START_TEST(test_sticking_inside) {
    double q[3] = {-1, 0.2, 0}, r[3] = {1, -0.2, 0}, u[3];
    measured m = measure_one(0.5, q, r, u);
    ck_assert_double_eq_tol(m.abs, 0.0, 1e-16);
    /* Perturb q_T2 by 0.1: u = (0,0,0.1), u^ = (0.05,0,0.1); r - u^ = (0.95,-0.2,-0.1) is
     * inside K, so the residual is |u^| = sqrt(0.0125); scale |q| = sqrt(1.05). */
    double q2[3] = {-1, 0.2, 0.1};
    m = measure_one(0.5, q2, r, u);
    ck_assert_double_eq_tol(m.abs, sqrt(0.0125), 1e-15);
    ck_assert_double_eq_tol(m.rel, sqrt(0.0125) / sqrt(1.05), 1e-15);
    ck_assert_double_eq_tol(m.compl, 0.05, 1e-15);
    ck_assert_double_eq(m.cone, 0.0);
}
END_TEST

START_TEST(test_sliding_on_boundary) {
    /* r = (1,-0.5,0) on the cone boundary, u = (0,0.5,0): sliding opposite to r_T. */
    double q[3] = {-1, 1, 0}, r[3] = {1, -0.5, 0}, u[3];
    measured m = measure_one(0.5, q, r, u);
    ck_assert_double_eq_tol(m.abs, 0.0, 1e-15);
    ck_assert_double_eq_tol(m.cone, 0.0, 1e-15);
    ck_assert_double_eq_tol(m.compl, 0.0, 1e-15); /* r . u^ = 1*0.25 - 0.5*0.5 */
    ck_assert_double_eq_tol(u[1], 0.5, 1e-15);
    /* Sliding the wrong way (r_T along u_T): u = (0,1.5,0), u^ = (0.75,1.5,0),
     * r - u^ = (0.25,-1,0) projects to ((0.5+0.25)/1.25, -0.3, 0) = (0.6,-0.3,0),
     * so the residual is |(0.4,0.8,0)| = sqrt(0.8). */
    double r2[3] = {1, 0.5, 0};
    m = measure_one(0.5, q, r2, u);
    ck_assert_double_eq_tol(m.abs, sqrt(0.8), 1e-15);
}
END_TEST

START_TEST(test_polar_cone) {
    /* u = (0.3,0,0), r - u^ = (-0.2,0,0) lies in the polar cone: P = 0, residual |r| = 0.1,
     * scale max(0.2, 0.1, 0.3) = 0.3. */
    double q[3] = {0.2, 0, 0}, r[3] = {0.1, 0, 0}, u[3];
    measured m = measure_one(0.5, q, r, u);
    ck_assert_double_eq_tol(m.abs, 0.1, 1e-15);
    ck_assert_double_eq_tol(m.rel, 0.1 / 0.3, 1e-15);
    ck_assert_double_eq_tol(m.qrel, 0.5, 1e-15);
    /* r = 0 while penetrating: the residual is |P_K(-q)| = 1 and u_N = -1. */
    double q2[3] = {-1, 0, 0}, r0[3] = {0, 0, 0};
    m = measure_one(0.5, q2, r0, u);
    ck_assert_double_eq_tol(m.abs, 1.0, 1e-15);
    ck_assert_double_eq_tol(m.pen, 1.0, 1e-15);
}
END_TEST

START_TEST(test_frictionless) {
    double q[3] = {-1, 0.3, -0.4}, r[3] = {1, 0, 0}, u[3];
    measured m = measure_one(0.0, q, r, u);
    ck_assert_double_eq_tol(m.abs, 0.0, 1e-15);
    /* A tangential reaction is a cone violation when mu = 0: distance 0.1. */
    double r2[3] = {1, 0.1, 0};
    m = measure_one(0.0, q, r2, u);
    ck_assert_double_eq_tol(m.abs, 0.1, 1e-15);
    ck_assert_double_eq_tol(m.cone, 0.1, 1e-15);
}
END_TEST

/* The measures are positively homogeneous: scaling r and q by 1e200 or 1e-200 scales the
 * residual by the same factor, without overflow or underflow to NaN or 0. */
START_TEST(test_extreme_scales) {
    double q[3] = {1e200, 0, 0}, r[3] = {1e200, 0, 0}, u[3];
    measured m = measure_one(0.5, q, r, u);
    ck_assert_double_eq_tol(m.abs / 1e200, 1.0, 1e-15);
    ck_assert_double_eq_tol(m.rel, 0.5, 1e-15);
    ck_assert_double_eq_tol(m.cone, 0.0, 1e-15);
    double qs[3] = {-1e-200, 1e-200, 0}, rs[3] = {1e-200, 0.5e-200, 0};
    m = measure_one(0.5, qs, rs, u); /* the "wrong way" slide of test_sliding_on_boundary */
    ck_assert_double_eq_tol(m.abs / 1e-200, sqrt(0.8), 1e-14);
    ck_assert_double_eq_tol(m.cone / 1e-200, 0.0, 1e-14);
    /* Subnormal data: the rescale must divide by the largest entry, not multiply by its
     * inverse (which overflows). r = 0 with u = q > 0 is an exact solution. */
    double qd[3] = {4.9406564584124654e-324, 4.9406564584124654e-324, 0}, r0[3] = {0, 0, 0};
    m = measure_one(0.0, qd, r0, u);
    ck_assert(isfinite(m.rel) && isfinite(m.abs));
    ck_assert_double_eq(m.abs, 0.0);
}
END_TEST

/* The measure of (W, q, mu, r) in both the default and Siconos's measures. */
static void measure_general(const double *Wd, const double *q, const double *mu, const double *r, int64_t nc,
                            double *scaled, double *siconos) {
    frix_matrix *W = NULL;
    frix_problem *p = NULL;
    frix_info *info = NULL;
    ck_assert_int_eq(frix_matrix_from_dense(3 * nc, 3 * nc, Wd, 3 * nc, &W), FRIX_OK);
    ck_assert_int_eq(frix_problem_local(W, q, mu, nc, &p), FRIX_OK);
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_problem_measure(p, r, NULL, NULL, info), FRIX_OK);
    frix_info_get_double(info, FRIX_INFO_ERROR_SCALED, scaled);
    frix_info_get_double(info, FRIX_INFO_ERROR_RELATIVE, siconos);
    frix_info_free(info);
    frix_problem_free(p);
    frix_matrix_free(W);
}

/* A change of force or length unit changes Siconos's measure, not the default one. */
START_TEST(test_scaled_is_unit_free) {
    const double W[36] = {2, 0.1, 0, 1, 0, 0, 0.1, 2, 0, 0, 0, 0, 0, 0, 2, 0, 0, 0,
                          1, 0, 0, 3, 0, 0.2, 0, 0, 0, 0, 3, 0, 0, 0, 0, 0.2, 0, 3};
    const double q[6] = {-1, 0.3, 0.1, -0.5, 0.2, -0.4}, mu[2] = {0.3, 0.6};
    const double r[6] = {0.4, -0.05, 0.02, 0.1, 0.03, 0.01};
    double base, base_siconos;
    measure_general(W, q, mu, r, 2, &base, &base_siconos);
    ck_assert(base > 1e-3);
    const double k = 1e4, c = 1e-3;
    double Wf[36], rf[6], Wl[36], ql[6];
    for (int i = 0; i < 36; ++i) Wf[i] = W[i] / k, Wl[i] = W[i] * c;
    for (int i = 0; i < 6; ++i) rf[i] = r[i] * k, ql[i] = q[i] * c;
    double forces, forces_siconos, lengths, lengths_siconos;
    measure_general(Wf, q, mu, rf, 2, &forces, &forces_siconos);  /* forces in units 1/k */
    measure_general(Wl, ql, mu, r, 2, &lengths, &lengths_siconos); /* lengths in units 1/c */
    ck_assert_double_eq_tol(forces, base, 1e-12 * base);
    ck_assert_double_eq_tol(lengths, base, 1e-12 * base);
    ck_assert(fabs(forces_siconos - base_siconos) > 0.1 * base_siconos);
}
END_TEST

/* A runaway r on a problem without a solution: W = diag(0, 1, 1), q_N = -1. Siconos's
 * measure falls like 1/|r|; the default one stays at the penetration velocity over |q|. */
START_TEST(test_runaway_does_not_satisfy) {
    const double W[9] = {0, 0, 0, 0, 1, 0, 0, 0, 1}, q[3] = {-1, 0, 0}, mu = 0.5;
    const double r[3] = {1.6e17, 0, 0};
    double scaled, siconos;
    measure_general(W, q, &mu, r, 1, &scaled, &siconos);
    ck_assert_msg(siconos < 1e-16, "siconos %g", siconos);
    ck_assert_msg(scaled > 0.99, "scaled %g", scaled);
    /* Sliding on the cone's boundary, far out: the residual is not lost to rounding. */
    const double rs[3] = {1e17, -0.5e17, 0}, qs[3] = {-1, 0.3, 0};
    measure_general(W, qs, &mu, rs, 1, &scaled, &siconos);
    ck_assert_msg(scaled > 0.5, "scaled %g", scaled);
}
END_TEST

/* Data scaled by 1e-17 keeps its relative errors: no absolute fallback below DBL_EPSILON. */
START_TEST(test_tiny_data_stays_relative) {
    const double W[9] = {1e-17, 0, 0, 0, 1e-17, 0, 0, 0, 1e-17}, q[3] = {-1e-17, 0, 0}, mu = 0.5;
    const double r[3] = {0.93, 0, 0}; /* 7 % short of the solution r_N = 1 */
    double scaled, siconos;
    measure_general(W, q, &mu, r, 1, &scaled, &siconos);
    ck_assert_double_eq_tol(scaled, 0.07, 1e-9);
}
END_TEST

START_TEST(test_bad_arguments) {
    static const double I3[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    double q[3] = {-1, 0, 0}, mu = 0.3, r[3] = {NAN, 0, 0}, e;
    frix_matrix *W = NULL;
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_matrix_from_dense(3, 3, I3, 3, &W), FRIX_OK);
    ck_assert_int_eq(frix_problem_local(W, q, &mu, 1, &p), FRIX_OK);
    ck_assert_int_eq(frix_problem_error(p, r, NULL, &e), FRIX_ERR_NOT_FINITE);
    ck_assert_int_eq(frix_problem_error(p, NULL, NULL, &e), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_problem_error(NULL, r, NULL, &e), FRIX_ERR_INVALID_ARGUMENT);
    frix_problem_free(p);
    frix_matrix_free(W);
}
END_TEST

int main(void) {
    Suite *s = suite_create("measures");
    TCase *tc = tcase_create("one contact");
    tcase_add_test(tc, test_taking_off);
    tcase_add_test(tc, test_sticking_inside);
    tcase_add_test(tc, test_sliding_on_boundary);
    tcase_add_test(tc, test_polar_cone);
    tcase_add_test(tc, test_frictionless);
    tcase_add_test(tc, test_extreme_scales);
    tcase_add_test(tc, test_bad_arguments);
    tcase_add_test(tc, test_scaled_is_unit_free);
    tcase_add_test(tc, test_runaway_does_not_satisfy);
    tcase_add_test(tc, test_tiny_data_stays_relative);
    suite_add_tcase(s, tc);
    return frix_run_suite(s);
}
