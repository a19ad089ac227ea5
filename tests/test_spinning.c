/* Rolling and spinning friction (frix_problem.h, frix_problem_spinning_*): the problem class and
 * its validation, the measure of the six-entry law on hand-checked contacts (spinning friction
 * sliding, every cone cut back at once); the one-contact kernels' Jacobians against finite
 * differences; every rolling solver (rolling-nsgs, rolling-nsn, auto) on hand-solved contacts,
 * on sphere piles (both forms) and on a full-rank chain, each answer checked by the
 * independent measure and against the spin-free problem; a problem without a solution. */
#include <frix/frix.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check_main.h"
#include "frix_testing.h"
#include "support/lcg.h"
#include "support/rolling_pile.h"

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

/* dP_K (six entries, and five) against central differences of the projection, at points of
 * every case of the projection (the polar cone, inside, and each of the seven sets of parts cut
 * back), away from the cases' boundaries (where both one-sided differences agree). */
START_TEST(test_projection_jacobian) {
    uint64_t s = 42;
    const double h = 1e-7;
    for (int size = 5; size <= 6; ++size) {
        int seen[9] = {0};
        for (int trial = 0; trial < 4000; ++trial) {
            double x[6], c[3];
            for (int k = 0; k < 3; ++k) c[k] = 0.05 + lcg_uniform(&s);
            x[0] = 2.0 * lcg_uniform(&s) - 1.0;
            for (int i = 1; i < size; ++i) x[i] = (2.0 * lcg_uniform(&s) - 1.0) * (i >= 3 ? 0.3 * lcg_uniform(&s) : 1.0);
            double D[36], p[6];
            memcpy(p, x, sizeof p);
            const int which = frix_testing_rolling_projection(size, p, c[0], c[1], c[2], D);
            ck_assert_int_ge(which, 0);
            ck_assert_int_le(which, size == 6 ? 8 : 4);
            int smooth = 1;
            double fd[36];
            for (int j = 0; j < size && smooth; ++j) {
                double xp[6], xm[6], xc[6];
                memcpy(xp, x, sizeof xp), memcpy(xm, x, sizeof xm), memcpy(xc, x, sizeof xc);
                xp[j] += h, xm[j] -= h;
                const int wp = frix_testing_rolling_projection(size, xp, c[0], c[1], c[2], NULL);
                const int wm = frix_testing_rolling_projection(size, xm, c[0], c[1], c[2], NULL);
                frix_testing_rolling_projection(size, xc, c[0], c[1], c[2], NULL);
                smooth = wp == which && wm == which;
                for (int i = 0; i < size; ++i) {
                    const double fwd = (xp[i] - xc[i]) / h, bwd = (xc[i] - xm[i]) / h;
                    smooth = smooth && fabs(fwd - bwd) < 1e-4;
                    fd[i + size * j] = (xp[i] - xm[i]) / (2.0 * h);
                }
            }
            if (!smooth) continue;
            seen[which] = 1;
            for (int e = 0; e < size * size; ++e)
                ck_assert_msg(fabs(D[e] - fd[e]) <= 1e-6, "size %d case %d entry %d: %g, differences %g", size, which,
                              e, D[e], fd[e]);
        }
        for (int w = 0; w <= (size == 6 ? 8 : 4); ++w) ck_assert_msg(seen[w], "size %d: case %d not reached", size, w);
    }
}
END_TEST

/* The Alart-Curnier function's blocks A = dF/dr and B = dF/du (six entries) against central
 * differences, where F is smooth (both one-sided differences agree). */
START_TEST(test_alart_curnier_jacobian) {
    uint64_t s = 7;
    const double h = 1e-7, mu = 0.4, mu_r = 0.2, mu_s = 0.1, rho = 0.7;
    int compared = 0, spin_slides = 0;
    for (int trial = 0; trial < 2000; ++trial) {
        double r[6], u[6], F[6], A[36], B[36];
        for (int i = 0; i < 6; ++i) r[i] = 2.0 * lcg_uniform(&s) - 0.5, u[i] = 2.0 * lcg_uniform(&s) - 1.0;
        frix_testing_rolling_alart_curnier(6, r, u, mu, mu_r, mu_s, rho, F, A, B);
        int smooth = 1;
        double fa[36], fb[36];
        for (int which = 0; which < 2 && smooth; ++which)
            for (int j = 0; j < 6 && smooth; ++j) {
                double rp[6], rm[6], up[6], um[6], Fp[6], Fm[6];
                memcpy(rp, r, sizeof rp), memcpy(rm, r, sizeof rm), memcpy(up, u, sizeof up), memcpy(um, u, sizeof um);
                if (which == 0) rp[j] += h, rm[j] -= h;
                else up[j] += h, um[j] -= h;
                frix_testing_rolling_alart_curnier(6, rp, up, mu, mu_r, mu_s, rho, Fp, NULL, NULL);
                frix_testing_rolling_alart_curnier(6, rm, um, mu, mu_r, mu_s, rho, Fm, NULL, NULL);
                for (int i = 0; i < 6; ++i) {
                    smooth = smooth && fabs((Fp[i] - F[i]) / h - (F[i] - Fm[i]) / h) < 1e-4;
                    (which == 0 ? fa : fb)[i + 6 * j] = (Fp[i] - Fm[i]) / (2.0 * h);
                }
            }
        if (!smooth) continue;
        ++compared;
        /* the spin slides: m_S - rho w_S outside the interval, which then moves with r_N */
        if (fabs(r[5] - rho * u[5]) > mu_s * (r[0] - rho * u[0]) && r[0] - rho * u[0] > 0.0) ++spin_slides;
        for (int e = 0; e < 36; ++e) {
            ck_assert_msg(fabs(A[e] - fa[e]) <= 1e-6, "A[%d] = %g, differences %g", e, A[e], fa[e]);
            ck_assert_msg(fabs(B[e] - fb[e]) <= 1e-6, "B[%d] = %g, differences %g", e, B[e], fb[e]);
        }
    }
    ck_assert_int_ge(compared, 1500);
    ck_assert_int_ge(spin_slides, 100);
}
END_TEST

/* Solves p (n dofs; 0 for the local form) with solver to tol from r (updated), the status and
 * error checked against frix_problem_measure; returns the iterations. */
static int64_t solve_checked(frix_problem *p, int solver, double tol, int64_t n, double *r) {
    const int64_t m = frix_problem_contact_dofs(p);
    double *u = calloc((size_t)m, sizeof(double)), *v = n > 0 ? calloc((size_t)n, sizeof(double)) : NULL;
    frix_options *o = NULL;
    frix_info *info = NULL, *check = NULL;
    ck_assert_int_eq(frix_options_create(solver, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, tol), FRIX_OK);
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_info_create(&check), FRIX_OK);
    ck_assert_int_eq(frix_solve(p, o, r, u, v, info), FRIX_OK);
    ck_assert_msg(frix_info_status(info) == FRIX_STATUS_CONVERGED, "solver %d: %s, error %g", solver,
                  frix_status_string(frix_info_status(info)), frix_info_error(info));
    double e = NAN, again = NAN;
    ck_assert_int_eq(frix_info_get_double(info, FRIX_INFO_ERROR, &e), FRIX_OK);
    ck_assert_double_le(e, tol);
    ck_assert_int_eq(frix_problem_measure(p, r, v, NULL, check), FRIX_OK);
    ck_assert_int_eq(frix_info_get_double(check, FRIX_INFO_ERROR_SCALED, &again), FRIX_OK);
    ck_assert_double_eq_tol(again, e, 1e-12 + 1e-9 * e);
    const int64_t iterations = frix_info_iterations(info);
    frix_info_free(check);
    frix_info_free(info);
    frix_options_free(o);
    free(u), free(v);
    return iterations;
}

/* One contact, W = I, solved by hand (K ∋ r ⟂ u^ ∈ K*, u = r + q), found by every solver of
 * rolling problems to 1e-12. */
static void solve_by_hand(const double q[6], const double r_star[6], double mu, double mu_r, double mu_s) {
    frix_matrix *W = identity(6);
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_problem_spinning_local(W, q, &mu, &mu_r, &mu_s, 1, &p), FRIX_OK);
    const int solvers[3] = {FRIX_SOLVER_ROLLING_NSGS, FRIX_SOLVER_ROLLING_NSN, FRIX_SOLVER_AUTO};
    for (int k = 0; k < 3; ++k) {
        double r[6] = {0};
        solve_checked(p, solvers[k], 1e-14, 0, r);
        for (int i = 0; i < 6; ++i)
            ck_assert_msg(fabs(r[i] - r_star[i]) <= 1e-12, "solver %d: r[%d] = %.17g, not %.17g", solvers[k], i, r[i],
                          r_star[i]);
    }
    frix_problem_free(p);
    frix_matrix_free(W);
}

START_TEST(test_one_contact_solved) {
    /* test_measure_by_hand's cases: spinning while pressed, and sticking with every part loaded. */
    const double q_spin[6] = {-1, 0, 0, 0, 0, 0.05}, r_spin[6] = {1, 0, 0, 0, 0, -0.02};
    solve_by_hand(q_spin, r_spin, 0.5, 0.01, 0.02);
    const double q_all[6] = {-3, -1, 0, -1, 0, -1}, r_all[6] = {3, 1, 0, 1, 0, 1};
    solve_by_hand(q_all, r_all, 1.0, 1.0, 1.0);
    /* Sliding, rolling and spinning at once: r = (1, -mu e_T, -mu_r e_R, -mu_s sign(w_S)) with
     * u = (0, 0.2 e_T, 0.1 e_R, w_S), e_T = (0.6, 0.8), e_R = (1, 0), w_S = -0.3 (u^_N = mu 0.2 +
     * mu_r 0.1 + mu_s 0.3 makes r . u^ = 0), q = u - r. */
    const double q_slide[6] = {-1, 0.42, 0.56, 0.2, 0, -0.35}, r_slide[6] = {1, -0.3, -0.4, -0.1, 0, 0.05};
    solve_by_hand(q_slide, r_slide, 0.5, 0.1, 0.05);
}
END_TEST

/* A sphere on the ground (a coupled 6x6 block): the one-contact kernel reaches 1e-14 without
 * the projected iterations (the semismooth Newton's Jacobian right), with the spin sliding (m_S
 * on its bound; Newton's case) for a small mu_s and held (u_S = 0) for a large one. */
START_TEST(test_newton_on_a_sphere) {
    const double mu_s[2] = {1e-3, 1.0};
    for (int k = 0; k < 2; ++k) {
        rolling_pile pile;
        ck_assert_int_eq(rolling_pile_make_spinning(1, 1, 0.3, 0.02, mu_s[k], 3, &pile), 0);
        ck_assert_int_eq(pile.nc, 1);
        double W[36], r[6] = {0}, u[6];
        for (int j = 0; j < 6; ++j) { /* W's columns W e_j */
            double e[6] = {0};
            e[j] = 1.0;
            ck_assert_int_eq(frix_matrix_gemv(pile.W, 1.0, e, 0.0, W + 6 * j), FRIX_OK);
        }
        const int out = frix_testing_rolling_solve_contact(6, W, pile.q, 0.3, 0.02, mu_s[k], r, 1e-14, 20);
        ck_assert_msg(out == FRIX_TESTING_ROLLING_NEWTON || out == FRIX_TESTING_ROLLING_STICK, "outcome %d", out);
        for (int i = 0; i < 6; ++i) {
            u[i] = pile.q[i];
            for (int j = 0; j < 6; ++j) u[i] += W[i + 6 * j] * r[j];
        }
        ck_assert_double_gt(r[0], 0.0);
        if (k == 0) {
            ck_assert_int_eq(out, FRIX_TESTING_ROLLING_NEWTON);
            ck_assert_double_eq_tol(fabs(r[5]), mu_s[k] * r[0], 1e-14);
        } else {
            ck_assert_double_lt(fabs(r[5]), mu_s[k] * r[0]);
            ck_assert_double_le(fabs(u[5]), 1e-12);
        }
        rolling_pile_free(&pile);
    }
}
END_TEST

/* m_S within its bound at every contact, and on it (and pressed) at some: the spin entry acts. */
static void check_spin(const double *r, int64_t nc, double mu_s) {
    int on_bound = 0;
    for (int64_t a = 0; a < nc; ++a) {
        const double rn = r[6 * a], ms = fabs(r[6 * a + 5]);
        ck_assert_double_le(ms, mu_s * rn * (1.0 + 1e-9) + 1e-15);
        if (rn > 0.0 && ms >= mu_s * rn * (1.0 - 1e-9)) ++on_bound;
    }
    ck_assert_int_gt(on_bound, 0);
}

/* The relative error of the five-entry pile at the five-entry part of a six-entry r. */
static double five_entry_error(const rolling_pile *five, const double *r6) {
    double *r5 = calloc((size_t)(5 * five->nc), sizeof(double));
    for (int64_t a = 0; a < five->nc; ++a) memcpy(r5 + 5 * a, r6 + 6 * a, 5 * sizeof(double));
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_problem_measure(five->local, r5, NULL, NULL, info), FRIX_OK);
    double e = NAN;
    ck_assert_int_eq(frix_info_get_double(info, FRIX_INFO_ERROR_SCALED, &e), FRIX_OK);
    frix_info_free(info);
    free(r5);
    return e;
}

/* Sphere piles with spinning friction, both forms, solved by rolling-nsgs and auto to 1e-8:
 * the same sweeps in both forms, the spin on its bound at some contacts, and an answer that
 * does not solve the same pile without spinning friction; with mu_s = 0 the answer is the
 * spin-free pile's (m_S = 0). */
START_TEST(test_piles) {
    for (uint64_t seed = 1; seed <= 3; ++seed) {
        rolling_pile pile, free_pile, five;
        ck_assert_int_eq(rolling_pile_make_spinning(3, 2, 0.3, 0.02, 0.01, seed, &pile), 0);
        ck_assert_int_eq(rolling_pile_make_spinning(3, 2, 0.3, 0.02, 0.0, seed, &free_pile), 0);
        ck_assert_int_eq(rolling_pile_make(3, 2, 0.3, 0.02, seed, &five), 0);
        const int64_t m = 6 * pile.nc;
        double *r = calloc((size_t)m, sizeof(double));
        int64_t local_it = 0, global_it = 0;
        const int solvers[2] = {FRIX_SOLVER_ROLLING_NSGS, FRIX_SOLVER_AUTO};
        for (int k = 0; k < 2; ++k)
            for (int form = 0; form < 2; ++form) {
                memset(r, 0, (size_t)m * sizeof(double));
                const int64_t it = solve_checked(form ? pile.global : pile.local, solvers[k], 1e-8,
                                                 form ? pile.n : 0, r);
                if (k == 0) *(form ? &global_it : &local_it) = it;
                check_spin(r, pile.nc, 0.01);
                ck_assert_double_gt(five_entry_error(&five, r), 1e-6);
            }
        /* The pile is one domain: the product form sweeps the same contacts in the same
         * order as the local form, the same iterates. */
        ck_assert_int_eq(local_it, global_it);
        memset(r, 0, (size_t)m * sizeof(double));
        solve_checked(free_pile.local, FRIX_SOLVER_ROLLING_NSGS, 1e-8, 0, r);
        for (int64_t a = 0; a < pile.nc; ++a) ck_assert_double_eq(r[6 * a + 5], 0.0);
        ck_assert_double_le(five_entry_error(&five, r), 1e-7);
        free(r);
        rolling_pile_free(&pile);
        rolling_pile_free(&free_pile);
        rolling_pile_free(&five);
    }
}
END_TEST

/* A chain of nc contacts, W = (tridiag(-1, 2, -1) (x) I_6) + eps I (full rank: one solution),
 * each pressed (q_N = -1), pushed, turned and spun a little: rolling-nsn converges in a few
 * steps to rolling-nsgs's answer, with the spin sliding at some contacts. */
START_TEST(test_nsn_on_a_chain) {
    const int64_t nc = 30, m = 6 * nc;
    int64_t nnz = 0, *ri = malloc((size_t)(3 * m) * sizeof(int64_t)), *ci = malloc((size_t)(3 * m) * sizeof(int64_t));
    double *x = malloc((size_t)(3 * m) * sizeof(double)), *q = malloc((size_t)m * sizeof(double));
    double mu[30], mu_r[30], mu_s[30];
    for (int64_t i = 0; i < m; ++i) {
        ri[nnz] = i, ci[nnz] = i, x[nnz++] = 2.0 + 1e-2;
        if (i + 6 < m) ri[nnz] = i, ci[nnz] = i + 6, x[nnz++] = -1.0;
        if (i >= 6) ri[nnz] = i, ci[nnz] = i - 6, x[nnz++] = -1.0;
    }
    frix_matrix *W = NULL;
    ck_assert_int_eq(frix_matrix_from_triplets(m, m, nnz, ri, ci, x, &W), FRIX_OK);
    uint64_t s = 12345;
    for (int64_t i = 0; i < m; ++i) q[i] = i % 6 == 0 ? -1.0 : 0.1 * (lcg_uniform(&s) - 0.5);
    for (int64_t a = 0; a < nc; ++a) mu[a] = 0.3, mu_r[a] = 0.05, mu_s[a] = 1e-3;
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_problem_spinning_local(W, q, mu, mu_r, mu_s, nc, &p), FRIX_OK);
    double *rn = calloc((size_t)m, sizeof(double)), *rg = calloc((size_t)m, sizeof(double));
    ck_assert_int_le(solve_checked(p, FRIX_SOLVER_ROLLING_NSN, 1e-10, 0, rn), 30);
    solve_checked(p, FRIX_SOLVER_ROLLING_NSGS, 1e-10, 0, rg);
    double d2 = 0.0, r2 = 0.0;
    for (int64_t i = 0; i < m; ++i) d2 += (rn[i] - rg[i]) * (rn[i] - rg[i]), r2 += rg[i] * rg[i];
    ck_assert_double_le(sqrt(d2), 1e-7 * sqrt(r2));
    check_spin(rn, nc, 1e-3);
    frix_problem_free(p);
    frix_matrix_free(W);
    free(ri), free(ci), free(x), free(q), free(rn), free(rg);
}
END_TEST

/* One contact that nothing holds in the normal direction, pressed: no solution
 * (rolling_check_no_solution). */
START_TEST(test_no_solution_diverges) { rolling_check_no_solution(6); }
END_TEST

/* The existence check decides a spinning problem where r = 0 solves it (every contact separates
 * in the local form), which the solvers answer at once, and is undetermined otherwise. */
START_TEST(test_existence) {
    frix_matrix *W = identity(6);
    double q[6] = {0.5, 1, 0, 1, 0, 1}, mu = 0.5, mu_r = 0.01, mu_s = 0.01, r[6] = {1, 1, 1, 1, 1, 1}, u[6];
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    for (int pressed = 0; pressed < 2; ++pressed) {
        q[0] = pressed ? -0.5 : 0.5;
        frix_problem *p = NULL;
        ck_assert_int_eq(frix_problem_spinning_local(W, q, &mu, &mu_r, &mu_s, 1, &p), FRIX_OK);
        ck_assert_int_eq(frix_problem_check_existence(p, 0.0, info), FRIX_OK);
        int64_t verdict = -1;
        ck_assert_int_eq(frix_info_get_int(info, FRIX_INFO_EXISTENCE, &verdict), FRIX_OK);
        ck_assert_int_eq(verdict, pressed ? FRIX_EXISTENCE_UNDETERMINED : FRIX_EXISTENCE_GUARANTEED);
        if (!pressed) {
            ck_assert_int_eq(frix_solve(p, NULL, r, u, NULL, NULL), FRIX_OK);
            for (int i = 0; i < 6; ++i) ck_assert_double_eq(r[i], 0.0);
        }
        frix_problem_free(p);
    }
    frix_info_free(info);
    frix_matrix_free(W);
}
END_TEST

int main(void) {
    Suite *s = suite_create("spinning");
    TCase *tc = tcase_create("core");
    tcase_set_timeout(tc, 120);
    tcase_add_test(tc, test_validation);
    tcase_add_test(tc, test_measure_by_hand);
    tcase_add_test(tc, test_persistent_calls);
    tcase_add_test(tc, test_projection_jacobian);
    tcase_add_test(tc, test_alart_curnier_jacobian);
    tcase_add_test(tc, test_one_contact_solved);
    tcase_add_test(tc, test_newton_on_a_sphere);
    tcase_add_test(tc, test_piles);
    tcase_add_test(tc, test_nsn_on_a_chain);
    tcase_add_test(tc, test_no_solution_diverges);
    tcase_add_test(tc, test_existence);
    suite_add_tcase(s, tc);
    return frix_run_suite(s);
}
