/* One-contact kernels: cone and disk projections, and the one-contact solvers (552, 553, 562). */
#include <math.h>
#include <stdint.h>

#include "check_main.h"
#include "frix_testing.h"
#include "support/lcg.h"

static const double kIdentity[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};

/* |got - want| <= tol componentwise (tol = 0 asks for exact equality). */
static void assert_vec(const double *got, double x, double y, double z, double tol) {
    const double want[3] = {x, y, z};
    for (int i = 0; i < 3; ++i)
        ck_assert_msg(fabs(got[i] - want[i]) <= tol, "component %d: got %.17g, want %.17g (tol %g)",
                      i, got[i], want[i], tol);
}

static int finite3(const double *x) { return isfinite(x[0]) && isfinite(x[1]) && isfinite(x[2]); }

/* A small deterministic generator, so failures reproduce. */
static uint64_t rng_state = 12345;
static double uniform(double lo, double hi) { return lo + (hi - lo) * lcg_uniform(&rng_state); }

/* W = A A^T + shift I (column-major), plus a non-symmetric part of relative size skew. */
static void random_W(double *W, double shift, double skew) {
    double A[9];
    for (int i = 0; i < 9; ++i) A[i] = uniform(-1, 1);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            double s = 0;
            for (int k = 0; k < 3; ++k) s += A[i + 3 * k] * A[j + 3 * k];
            W[i + 3 * j] = s + (i == j ? shift : 0.0) + (i != j ? skew * uniform(-1, 1) : 0.0);
        }
}

/* ---- projection on the cone */

START_TEST(cone_inside_and_boundary_unchanged) {
    double r[3] = {1.0, 0.3, 0.4};
    frix_testing_project_on_cone(r, 0.7);
    assert_vec(r, 1.0, 0.3, 0.4, 0.0);
    double b[3] = {1.0, 0.6, 0.8}; /* |r_T| = mu r_N exactly */
    frix_testing_project_on_cone(b, 1.0);
    assert_vec(b, 1.0, 0.6, 0.8, 0.0);
}
END_TEST

START_TEST(cone_polar_goes_to_zero) {
    double r[3] = {-1.0, 0.3, 0.4}; /* mu|r_T| = 0.35 <= -r_N */
    frix_testing_project_on_cone(r, 0.7);
    assert_vec(r, 0.0, 0.0, 0.0, 0.0);
    double n[3] = {-2.0, 0.0, 0.0};
    frix_testing_project_on_cone(n, 0.5);
    assert_vec(n, 0.0, 0.0, 0.0, 0.0);
}
END_TEST

START_TEST(cone_general_case) {
    /* |r_T| = 5: r_N = (0.5*5 + 1)/1.25 = 2.8, r_T = 0.5*2.8*(3,4)/5. */
    double r[3] = {1.0, 3.0, 4.0};
    frix_testing_project_on_cone(r, 0.5);
    assert_vec(r, 2.8, 0.84, 1.12, 1e-15);
    /* A projection: idempotent, and r - P(r) is orthogonal to P(r). */
    for (int k = 0; k < 200; ++k) {
        double x[3] = {uniform(-3, 3), uniform(-3, 3), uniform(-3, 3)}, p[3] = {x[0], x[1], x[2]};
        const double mu = uniform(0.05, 2.0);
        frix_testing_project_on_cone(p, mu);
        ck_assert(hypot(p[1], p[2]) <= mu * p[0] * (1 + 1e-14) + 1e-15);
        const double dot = (x[0] - p[0]) * p[0] + (x[1] - p[1]) * p[1] + (x[2] - p[2]) * p[2];
        ck_assert_double_eq_tol(dot, 0.0, 1e-12);
        double pp[3] = {p[0], p[1], p[2]};
        frix_testing_project_on_cone(pp, mu);
        assert_vec(pp, p[0], p[1], p[2], 1e-14);
    }
}
END_TEST

START_TEST(cone_mu_zero_is_half_line) {
    double r[3] = {2.0, 1.0, -1.0};
    frix_testing_project_on_cone(r, 0.0);
    assert_vec(r, 2.0, 0.0, 0.0, 0.0);
    double n[3] = {-2.0, 1.0, 1.0};
    frix_testing_project_on_cone(n, 0.0);
    assert_vec(n, 0.0, 0.0, 0.0, 0.0);
}
END_TEST

/* ---- projection on the Tresca disk */

START_TEST(disk_projection) {
    double r[3] = {-1.0, 3.0, 4.0};
    frix_testing_project_on_disk(r, 2.5);
    assert_vec(r, 0.0, 1.5, 2.0, 1e-15);
    double in[3] = {1.0, 0.1, 0.2};
    frix_testing_project_on_disk(in, 1.0);
    assert_vec(in, 1.0, 0.1, 0.2, 0.0);
    double z[3] = {1.0, 0.1, 0.2};
    frix_testing_project_on_disk(z, 0.0);
    assert_vec(z, 1.0, 0.0, 0.0, 0.0);
}
END_TEST

/* ---- one-contact solver */

START_TEST(contact_take_off) {
    const double q[3] = {0.3, 5.0, -2.0};
    double r[3] = {1.0, 0.1, 0.1};
    ck_assert_int_eq(frix_testing_solve_contact(kIdentity, q, 0.5, r, 562, 1e-12, 20),
                     FRIX_TESTING_TAKE_OFF);
    assert_vec(r, 0.0, 0.0, 0.0, 0.0);
}
END_TEST

START_TEST(contact_stick) {
    const double q[3] = {-1.0, 0.2, 0.1};
    double r[3] = {0, 0, 0};
    ck_assert_int_eq(frix_testing_solve_contact(kIdentity, q, 0.5, r, 562, 1e-12, 20),
                     FRIX_TESTING_STICK);
    assert_vec(r, 1.0, -0.2, -0.1, 1e-15);
    /* A general W: r* inside the cone and q = -W r* give back r*, with u = 0. */
    for (int k = 0; k < 50; ++k) {
        double W[9], rs[3], qq[3], x[3] = {0, 0, 0};
        random_W(W, 0.5, 0.1);
        const double mu = uniform(0.2, 1.0), rn = uniform(0.5, 2.0), ang = uniform(0, 6.283);
        const double t = uniform(0.0, 0.9) * mu * rn;
        rs[0] = rn;
        rs[1] = t * cos(ang);
        rs[2] = t * sin(ang);
        for (int i = 0; i < 3; ++i) qq[i] = -(W[i] * rs[0] + W[i + 3] * rs[1] + W[i + 6] * rs[2]);
        if (qq[0] >= 0) continue; /* that would be take-off */
        ck_assert_int_eq(frix_testing_solve_contact(W, qq, mu, x, 562, 1e-12, 20),
                         FRIX_TESTING_STICK);
        assert_vec(x, rs[0], rs[1], rs[2], 1e-10);
    }
}
END_TEST

/* Checks that r is a sliding solution: on the cone boundary, u_N = 0, u_T opposite to r_T. */
static void assert_sliding(const double *W, const double *q, double mu, const double *r) {
    double u[3], rel;
    for (int i = 0; i < 3; ++i) u[i] = W[i] * r[0] + W[i + 3] * r[1] + W[i + 6] * r[2] + q[i];
    const double scale = fabs(q[0]) + hypot(q[1], q[2]);
    ck_assert(r[0] > 0);
    ck_assert_double_eq_tol(hypot(r[1], r[2]), mu * r[0], 1e-12 * r[0]);
    ck_assert_double_eq_tol(u[0], 0.0, 1e-12 * scale);
    ck_assert(u[1] * r[1] + u[2] * r[2] <= 1e-12 * scale * r[0]);
    ck_assert_double_eq_tol(u[1] * r[2] - u[2] * r[1], 0.0, 1e-11 * scale * r[0]);
    frix_testing_contact_residual(W, q, mu, r, &rel);
    ck_assert(rel <= 1e-12);
}

START_TEST(contact_slide_by_hand) {
    /* W = I, mu = 0.5, q = (-1, 2, 0): r = (1, -0.5, 0), u = (0, 1.5, 0). */
    const double q[3] = {-1.0, 2.0, 0.0};
    double r[3] = {0, 0, 0};
    ck_assert_int_eq(frix_testing_solve_contact(kIdentity, q, 0.5, r, 562, 1e-12, 20),
                     FRIX_TESTING_SLIDE);
    assert_vec(r, 1.0, -0.5, 0.0, 1e-14);
    assert_sliding(kIdentity, q, 0.5, r);
}
END_TEST

START_TEST(contact_slide_random) {
    int slides = 0;
    for (int k = 0; k < 400; ++k) {
        double W[9], q[3], r[3] = {0, 0, 0};
        random_W(W, 0.2, k % 2 ? 0.05 : 0.0);
        const double mu = uniform(0.05, 1.0);
        q[0] = -uniform(0.1, 1.0);
        q[1] = uniform(-3, 3);
        q[2] = uniform(-3, 3);
        const int out = frix_testing_solve_contact(W, q, mu, r, 562, 1e-12, 200);
        ck_assert(finite3(r));
        double rel;
        frix_testing_contact_residual(W, q, mu, r, &rel);
        ck_assert_msg(rel <= 1e-12, "case %d: outcome %d, relative residual %g", k, out, rel);
        if (out == FRIX_TESTING_SLIDE) {
            assert_sliding(W, q, mu, r);
            ++slides;
        }
    }
    ck_assert_int_ge(slides, 200); /* the test really exercises the sliding root */
}
END_TEST

START_TEST(contact_slide_root_from_any_hint) {
    /* Whatever the hint, the root found is a solution. */
    const double W[9] = {2.0, 0.3, -0.2, 0.3, 1.0, 0.1, -0.2, 0.1, 0.8};
    const double q[3] = {-1.0, 1.5, -2.0};
    for (int k = 0; k < 16; ++k) {
        const double hint[3] = {1.0, cos(0.4 * k), sin(0.4 * k)};
        double r[3];
        ck_assert_int_eq(frix_testing_solve_slide(W, q, 0.6, hint, r), 1);
        assert_sliding(W, q, 0.6, r);
    }
}
END_TEST

START_TEST(contact_projection_iterations_converge) {
    /* 553 without the sliding root: projected iterations alone reach the local tolerance. */
    for (int k = 0; k < 100; ++k) {
        double W[9], q[3] = {-uniform(0.1, 1.0), uniform(-2, 2), uniform(-2, 2)}, r[3] = {0, 0, 0};
        random_W(W, 1.0, 0.0);
        const double mu = uniform(0.1, 0.8);
        const int out = frix_testing_solve_contact(W, q, mu, r, 553, 1e-10, 5000);
        ck_assert(out == FRIX_TESTING_STICK || out == FRIX_TESTING_ITERATED);
        double rel;
        frix_testing_contact_residual(W, q, mu, r, &rel);
        ck_assert(rel <= 1e-10);
    }
}
END_TEST

START_TEST(contact_single_projected_step) {
    /* 552 from r = 0 with W = I: F = (-1 + 0.5*2, 2, 0) and rho = 1/|W| = 1, so
     * r = P_K((0, -2, 0)) = (0.8, -0.4, 0). Repeated steps converge to (1, -0.5, 0). */
    const double q[3] = {-1.0, 2.0, 0.0};
    double r[3] = {0, 0, 0};
    ck_assert_int_eq(frix_testing_solve_contact(kIdentity, q, 0.5, r, 552, 1e-12, 20),
                     FRIX_TESTING_STEP);
    assert_vec(r, 0.8, -0.4, 0.0, 1e-15);
    for (int k = 0; k < 200; ++k) frix_testing_solve_contact(kIdentity, q, 0.5, r, 552, 0, 1);
    assert_vec(r, 1.0, -0.5, 0.0, 1e-10);
}
END_TEST

START_TEST(contact_mu_zero) {
    const double W[9] = {2.0, 0.1, 0.0, 0.1, 1.0, 0.0, 0.0, 0.0, 1.0};
    const double q[3] = {-1.0, 0.5, 0.2};
    double r[3] = {0, 0, 0};
    frix_testing_solve_contact(W, q, 0.0, r, 562, 1e-12, 20);
    assert_vec(r, 0.5, 0.0, 0.0, 1e-15);
}
END_TEST

START_TEST(contact_degenerate_W_is_finite) {
    const double zero[9] = {0};
    const double q[3] = {-1.0, 0.3, 0.0};
    double r[3] = {0.5, 0.1, 0.0};
    /* W_aa = 0 with q_N < 0 has no local solution: r is left as it was. */
    ck_assert_int_eq(frix_testing_solve_contact(zero, q, 0.5, r, 562, 1e-12, 20),
                     FRIX_TESTING_NO_SOLUTION);
    assert_vec(r, 0.5, 0.1, 0.0, 0.0);
    ck_assert_int_eq(frix_testing_solve_contact(zero, q, 0.5, r, 552, 1e-12, 20),
                     FRIX_TESTING_NO_SOLUTION);
    const double up[3] = {1.0, 0.3, 0.0};
    ck_assert_int_eq(frix_testing_solve_contact(zero, up, 0.5, r, 562, 1e-12, 20),
                     FRIX_TESTING_TAKE_OFF);

    /* Singular W = diag(1, 0, 0): u_T = q_T whatever r, so r = (1, -0.3, 0) slides. */
    const double rank1[9] = {1, 0, 0, 0, 0, 0, 0, 0, 0};
    const double q1[3] = {-1.0, 0.5, 0.0};
    double r1[3] = {0, 0, 0};
    frix_testing_solve_contact(rank1, q1, 0.3, r1, 562, 1e-12, 20);
    assert_vec(r1, 1.0, -0.3, 0.0, 1e-14);

    /* W_NN <= 0 (here W = -I) and a tiny W: whatever the outcome, r stays finite. */
    const double neg[9] = {-1, 0, 0, 0, -1, 0, 0, 0, -1};
    const double tiny[9] = {1e-300, 0, 0, 0, 1e-300, 0, 0, 0, 0};
    const double *cases[2] = {neg, tiny};
    const int solvers[3] = {552, 553, 562};
    for (int c = 0; c < 2; ++c)
        for (int k = 0; k < 3; ++k) {
            double x[3] = {0.2, 0.0, 0.1};
            frix_testing_solve_contact(cases[c], q, 0.5, x, solvers[k], 1e-12, 100000);
            ck_assert(finite3(x));
        }
}
END_TEST

static Suite *local3x3_suite(void) {
    Suite *s = suite_create("local3x3");
    TCase *proj = tcase_create("projections");
    tcase_add_test(proj, cone_inside_and_boundary_unchanged);
    tcase_add_test(proj, cone_polar_goes_to_zero);
    tcase_add_test(proj, cone_general_case);
    tcase_add_test(proj, cone_mu_zero_is_half_line);
    tcase_add_test(proj, disk_projection);
    suite_add_tcase(s, proj);
    TCase *one = tcase_create("one_contact");
    tcase_add_test(one, contact_take_off);
    tcase_add_test(one, contact_stick);
    tcase_add_test(one, contact_slide_by_hand);
    tcase_add_test(one, contact_slide_random);
    tcase_add_test(one, contact_slide_root_from_any_hint);
    tcase_add_test(one, contact_projection_iterations_converge);
    tcase_add_test(one, contact_single_projected_step);
    tcase_add_test(one, contact_mu_zero);
    tcase_add_test(one, contact_degenerate_W_is_finite);
    suite_add_tcase(s, one);
    return s;
}

int main(void) { return frix_run_suite(local3x3_suite()); }
