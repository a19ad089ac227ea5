/* Rolling friction (frix_problem.h): the problem class and its validation, the refusal of the
 * three-component solvers and services, the measure on hand-checked contacts (stick, rolling,
 * sliding and rolling), rolling-nsgs (local and product forms, and auto's route) on
 * generated sphere piles, checked against the independent measure, and every rolling solver
 * on a problem without a solution (diverged, never the runaway r); the product form's sweeps
 * the same bit for bit on any number of threads. */
#include <frix/frix.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check_main.h"
#include "frix_testing.h"
#include "support/rolling_pile.h"

static frix_matrix *dense(int64_t m, int64_t n, const double *a) {
    frix_matrix *M = NULL;
    ck_assert_int_eq(frix_matrix_from_dense(m, n, a, m, &M), FRIX_OK);
    return M;
}

static frix_matrix *identity(int64_t m) {
    double *a = calloc((size_t)(m * m), sizeof(double));
    for (int64_t i = 0; i < m; ++i) a[i + m * i] = 1.0;
    frix_matrix *I = dense(m, m, a);
    free(a);
    return I;
}

START_TEST(test_validation) {
    frix_matrix *W = identity(10);
    double q[10] = {-1, 0, 0, 0, 0, -1, 0, 0, 0, 0}, mu[2] = {0.3, 0.3}, mu_r[2] = {0.01, 0.02};
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_problem_rolling_local(W, q, mu, mu_r, 2, &p), FRIX_OK);
    ck_assert_int_eq(frix_problem_get_kind(p), FRIX_PROBLEM_ROLLING_LOCAL);
    ck_assert_int_eq(frix_problem_contacts(p), 2);
    ck_assert_int_eq(frix_problem_contact_dofs(p), 10);
    ck_assert_ptr_eq(frix_problem_mu_r(p), mu_r);
    ck_assert_ptr_eq(frix_problem_W(p), W);
    frix_problem_free(p);

    frix_problem *bad = (frix_problem *)0x1;
    ck_assert_int_eq(frix_problem_rolling_local(W, q, mu, NULL, 2, &bad), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_ptr_null(bad);
    ck_assert(strstr(frix_last_error_message(), "mu_r") != NULL);
    double neg[2] = {0.01, -1e-3};
    ck_assert_int_eq(frix_problem_rolling_local(W, q, mu, neg, 2, &bad), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert(strstr(frix_last_error_message(), "mu_r[1]") != NULL);
    double nan_r[2] = {NAN, 0.01};
    ck_assert_int_eq(frix_problem_rolling_local(W, q, mu, nan_r, 2, &bad), FRIX_ERR_NOT_FINITE);
    /* Sizes: 10 rows are 2 rolling contacts, not 3; 9 rows are no number of them. */
    ck_assert_int_eq(frix_problem_rolling_local(W, q, mu, mu_r, 3, &bad), FRIX_ERR_DIMENSION);
    frix_matrix *W9 = identity(9);
    ck_assert_int_eq(frix_problem_rolling_local(W9, q, mu, mu_r, 2, &bad), FRIX_ERR_DIMENSION);
    ck_assert(strstr(frix_last_error_message(), "multiple of 5") != NULL);

    /* Global form: H is n x 5nc. */
    frix_matrix *M = identity(6), *H6 = dense(6, 9, (double[54]){0});
    double f[6] = {0}, w[10] = {0};
    ck_assert_int_eq(frix_problem_rolling_global(M, H6, f, w, mu, mu_r, 2, &bad), FRIX_ERR_DIMENSION);
    ck_assert(strstr(frix_last_error_message(), "5*contacts") != NULL);
    frix_matrix *H = dense(6, 10, (double[60]){0});
    ck_assert_int_eq(frix_problem_rolling_global(M, H, f, w, mu, mu_r, 2, &p), FRIX_OK);
    ck_assert_int_eq(frix_problem_get_kind(p), FRIX_PROBLEM_ROLLING_GLOBAL);
    ck_assert_int_eq(frix_problem_contact_dofs(p), 10);
    ck_assert_int_eq(frix_problem_dofs(p), 6);
    frix_problem_free(p);

    frix_matrix_free(W9);
    frix_matrix_free(W);
    frix_matrix_free(M);
    frix_matrix_free(H6);
    frix_matrix_free(H);
}
END_TEST

START_TEST(test_classic_has_no_mu_r) {
    frix_matrix *W = identity(3);
    double q[3] = {-1, 0, 0}, mu = 0.3;
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_problem_local(W, q, &mu, 1, &p), FRIX_OK);
    ck_assert_ptr_null(frix_problem_mu_r(p));
    ck_assert_int_eq(frix_problem_contact_dofs(p), 3);
    frix_problem_free(p);
    frix_matrix_free(W);
}
END_TEST

/* Every three-component solver and service says no, clearly, instead of misreading r. */
START_TEST(test_refused) {
    frix_matrix *W = identity(5);
    double q[5] = {-1, 0.1, 0, 0.001, 0}, mu = 0.5, mu_r = 0.01, r[5] = {0}, u[5];
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_problem_rolling_local(W, q, &mu, &mu_r, 1, &p), FRIX_OK);
    for (int64_t k = 0; k < frix_solver_count(); ++k) {
        const int id = frix_solver_id_at(k);
        if (id == FRIX_SOLVER_ROLLING_NSGS || id == FRIX_SOLVER_ROLLING_NSN || id == FRIX_SOLVER_AUTO) continue;
        frix_options *o = NULL;
        ck_assert_int_eq(frix_options_create(id, &o), FRIX_OK);
        ck_assert_int_eq(frix_solve(p, o, r, u, NULL, NULL), FRIX_ERR_UNSUPPORTED);
        ck_assert(strstr(frix_last_error_message(), "rolling") != NULL);
        frix_options_free(o);
    }
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    /* The existence check cannot decide this one (q_N < 0), and says so. */
    ck_assert_int_eq(frix_problem_check_existence(p, 0.0, info), FRIX_OK);
    int64_t verdict = -1;
    ck_assert_int_eq(frix_info_get_int(info, FRIX_INFO_EXISTENCE, &verdict), FRIX_OK);
    ck_assert_int_eq(verdict, FRIX_EXISTENCE_UNDETERMINED);
    frix_info_free(info);
    frix_problem_free(p);
    frix_matrix_free(W);
}
END_TEST

/* One contact, W = I, solved by hand: r* and the measure at r* and at r = 0. */
typedef struct {
    double q[5], r[5], residual_at_zero;
} hand_case;

static void check_case(const hand_case *c, double mu, double mu_r) {
    frix_matrix *W = identity(5);
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_problem_rolling_local(W, c->q, &mu, &mu_r, 1, &p), FRIX_OK);
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    double u[5], zero[5] = {0};
    ck_assert_int_eq(frix_problem_measure(p, c->r, NULL, u, info), FRIX_OK);
    double e = NAN;
    ck_assert_int_eq(frix_info_get_double(info, FRIX_INFO_ERROR_RELATIVE, &e), FRIX_OK);
    ck_assert_double_le(e, 1e-15);
    for (int i = 0; i < 5; ++i) ck_assert_double_eq_tol(u[i], c->r[i] + c->q[i], 1e-15);
    ck_assert_int_eq(frix_problem_measure(p, zero, NULL, u, info), FRIX_OK);
    double abs_res = NAN, qn = 0.0;
    for (int i = 0; i < 5; ++i) qn += c->q[i] * c->q[i];
    ck_assert_int_eq(frix_info_get_double(info, FRIX_INFO_RESIDUAL_ABSOLUTE, &abs_res), FRIX_OK);
    ck_assert_double_eq_tol(abs_res, c->residual_at_zero, 1e-14);
    /* Siconos's normalisation: max(|q|, |r|, |u|), here |q|. */
    ck_assert_int_eq(frix_info_get_double(info, FRIX_INFO_ERROR_RELATIVE, &e), FRIX_OK);
    ck_assert_double_eq_tol(e, c->residual_at_zero / sqrt(qn), 1e-14);
    /* The solver finds r*. */
    double r[5] = {0};
    ck_assert_int_eq(frix_solve(p, NULL, r, u, NULL, info), FRIX_OK);
    ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_CONVERGED);
    for (int i = 0; i < 5; ++i) ck_assert_double_eq_tol(r[i], c->r[i], 1e-12);
    frix_info_free(info);
    frix_problem_free(p);
    frix_matrix_free(W);
}

START_TEST(test_measure_by_hand) {
    const double mu = 0.5, mu_r = 0.01;
    /* Stick: r = -q inside both cones. At r = 0, x = -q^ lies inside K: the residual is |q^|. */
    const double qn_hat = -1.0 + mu * 0.1 + mu_r * 0.001;
    hand_case stick = {{-1, 0.1, 0, 0.001, 0}, {1, -0.1, 0, -0.001, 0}, 0};
    stick.residual_at_zero = sqrt(qn_hat * qn_hat + 0.01 + 1e-6);
    check_case(&stick, mu, mu_r);
    /* Rolling, not sliding: r_N = 1, m_R = -mu_r r_N on the rolling cone, w_R = 0.04. At r = 0,
     * x = -q^ = (0.9995, 0, 0, -0.05, 0) projects on the rolling cone alone, t = 1 / (1 +
     * mu_r^2), and the residual is t sqrt(1 + mu_r^2) = 1 / sqrt(1.0001). */
    hand_case roll = {{-1, 0, 0, 0.05, 0}, {1, 0, 0, -0.01, 0}, 1.0 / sqrt(1.0001)};
    check_case(&roll, mu, mu_r);
    /* Sliding and rolling: r = (1, -mu, 0, 0, -mu_r), u = (0, 0.3, 0, 0, 0.04). At r = 0,
     * x = -(-1 + 0.4 + 0.0005, 0.8, 0, 0, 0.05) lies on both cones' outside: t = (x_N + mu
     * |x_T| + mu_r |x_R|) / (1 + mu^2 + mu_r^2), residual t sqrt(1 + mu^2 + mu_r^2). */
    const double c = 1.0 + mu * mu + mu_r * mu_r, t = (0.5995 + mu * 0.8 + mu_r * 0.05) / c;
    hand_case both = {{-1, 0.8, 0, 0, 0.05}, {1, -0.5, 0, 0, -0.01}, t * sqrt(c)};
    check_case(&both, mu, mu_r);
}
END_TEST

/* A coupled 5x5 block (a sphere on the ground): Newton's case, to the local tolerance. */
START_TEST(test_one_sphere_on_ground) {
    rolling_pile pile;
    ck_assert_int_eq(rolling_pile_make(1, 1, 0.3, 0.05, 3, &pile), 0);
    ck_assert_int_eq(pile.nc, 1);
    double r[5] = {0}, u[5];
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_ROLLING_NSGS, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 1e-12), FRIX_OK);
    ck_assert_int_eq(frix_solve(pile.local, o, r, u, NULL, info), FRIX_OK);
    double e = NAN;
    ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_CONVERGED);
    ck_assert_int_eq(frix_info_get_double(info, FRIX_INFO_ERROR, &e), FRIX_OK);
    ck_assert_double_le(e, 1e-12);
    ck_assert_double_gt(r[0], 0.0); /* the sphere weighs on the ground */
    frix_options_free(o);
    frix_info_free(info);
    rolling_pile_free(&pile);
}
END_TEST

/* The same sphere with q (so r and u) scaled by 1e-150 and 1e150, where the squares of the
 * one-contact solver's norms leave the range of doubles: the same r, scaled. */
START_TEST(test_one_sphere_at_extreme_scales) {
    rolling_pile pile;
    ck_assert_int_eq(rolling_pile_make(1, 1, 0.3, 0.05, 3, &pile), 0);
    double W[25], e[5];
    for (int j = 0; j < 5; ++j) {
        for (int i = 0; i < 5; ++i) e[i] = i == j ? 1.0 : 0.0;
        ck_assert_int_eq(frix_matrix_gemv(pile.W, 1.0, e, 0.0, W + 5 * j), FRIX_OK);
    }
    frix_matrix *Wm = dense(5, 5, W);
    const double scales[3] = {1.0, 1e-150, 1e150};
    double reference[5] = {0};
    for (int k = 0; k < 3; ++k) {
        double q[5], r[5] = {0}, u[5];
        for (int i = 0; i < 5; ++i) q[i] = scales[k] * pile.q[i];
        frix_problem *p = NULL;
        ck_assert_int_eq(frix_problem_rolling_local(Wm, q, pile.mu, pile.mu_r, 1, &p), FRIX_OK);
        frix_options *o = NULL;
        ck_assert_int_eq(frix_options_create(FRIX_SOLVER_ROLLING_NSGS, &o), FRIX_OK);
        ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 1e-12), FRIX_OK);
        frix_info *info = NULL;
        ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
        ck_assert_int_eq(frix_solve(p, o, r, u, NULL, info), FRIX_OK);
        ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_CONVERGED);
        double size = 0.0;
        for (int i = 0; i < 5; ++i) {
            if (k == 0) reference[i] = r[i];
            size = fmax(size, fabs(reference[i]));
        }
        ck_assert_double_gt(reference[0], 0.0);
        ck_assert_double_gt(fabs(reference[3]) + fabs(reference[4]), 0.0); /* a rolling moment */
        for (int i = 0; i < 5; ++i) ck_assert_double_eq_tol(r[i] / scales[k], reference[i], 1e-9 * size);
        frix_info_free(info);
        frix_options_free(o);
        frix_problem_free(p);
    }
    frix_matrix_free(Wm);
    rolling_pile_free(&pile);
}
END_TEST

/* Solves `p` with `solver` to 1e-8 and checks the status against frix_problem_measure. */
static void solve_to(frix_problem *p, int solver, int64_t nc, int64_t n, int64_t *iterations) {
    const int64_t m = 5 * nc;
    double *r = calloc((size_t)m, sizeof(double)), *u = calloc((size_t)m, sizeof(double));
    double *v = n > 0 ? calloc((size_t)n, sizeof(double)) : NULL;
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(solver, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 1e-8), FRIX_OK);
    frix_info *info = NULL, *check = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_info_create(&check), FRIX_OK);
    ck_assert_int_eq(frix_solve(p, o, r, u, v, info), FRIX_OK);
    double e = NAN, again = NAN, rel = NAN;
    ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_CONVERGED);
    ck_assert_int_eq(frix_info_get_double(info, FRIX_INFO_ERROR, &e), FRIX_OK);
    ck_assert_double_le(e, 1e-8);
    ck_assert_int_eq(frix_info_get_int(info, FRIX_INFO_ITERATIONS, iterations), FRIX_OK);
    ck_assert_int_gt(*iterations, 0);
    ck_assert_int_eq(frix_problem_measure(p, r, v, NULL, check), FRIX_OK);
    ck_assert_int_eq(frix_info_get_double(check, FRIX_INFO_ERROR_SCALED, &again), FRIX_OK);
    ck_assert_double_eq_tol(again, e, 1e-12);
    ck_assert_int_eq(frix_info_get_double(check, FRIX_INFO_ERROR_RELATIVE, &rel), FRIX_OK);
    ck_assert(isfinite(rel));
    /* The rolling moments are used (the pile does not settle on friction alone). */
    double moment = 0.0;
    for (int64_t a = 0; a < nc; ++a) moment = fmax(moment, hypot(r[5 * a + 3], r[5 * a + 4]));
    ck_assert_double_gt(moment, 0.0);
    frix_info_free(info);
    frix_info_free(check);
    frix_options_free(o);
    free(r);
    free(u);
    free(v);
}

START_TEST(test_nsgs_on_piles) {
    for (uint64_t seed = 1; seed <= 3; ++seed) {
        rolling_pile pile;
        ck_assert_int_eq(rolling_pile_make(3, 2, 0.3, 0.02, seed, &pile), 0);
        int64_t local_it = 0, global_it = 0, auto_it = 0;
        solve_to(pile.local, FRIX_SOLVER_ROLLING_NSGS, pile.nc, 0, &local_it);
        solve_to(pile.global, FRIX_SOLVER_ROLLING_NSGS, pile.nc, pile.n, &global_it);
        solve_to(pile.local, FRIX_SOLVER_AUTO, pile.nc, 0, &auto_it);
        solve_to(pile.global, FRIX_SOLVER_AUTO, pile.nc, pile.n, &auto_it);
        /* The pile is one domain: the product form sweeps the same contacts in the same
         * order as the local form, the same iterates. */
        ck_assert_int_eq(local_it, global_it);
        rolling_pile_free(&pile);
    }
}
END_TEST

/* The local form a sweep reads, from rolling-nsgs's log ("local form, W's ..."). */
static void read_form(void *data, const char *line) {
    const char *at = strstr(line, "local form, ");
    if (strncmp(line, "rolling-nsgs: ", 14) == 0 && at)
        snprintf((char *)data, 64, "%.*s", (int)strcspn(at + 12, ","), at + 12);
}

/* The pile's W as frix_matrix_from_csc stores it, an entry of contact 0's columns multiplied by
 * 1 + eps (eps = -1: left out), off the diagonal, in the rows of contact 0 (own = 1: W_00) or
 * of another: the local problem on it. */
static frix_problem *with_entry_scaled(const rolling_pile *pile, double eps, int own, frix_matrix **W) {
    int64_t nnz = 0, m = 5 * pile->nc;
    ck_assert_int_eq(frix_matrix_to_csc(pile->W, &nnz, NULL, NULL, NULL), FRIX_OK);
    int64_t *colptr = malloc((size_t)(m + 1) * sizeof(int64_t)), *rowind = malloc((size_t)nnz * sizeof(int64_t));
    double *val = malloc((size_t)nnz * sizeof(double));
    ck_assert_int_eq(frix_matrix_to_csc(pile->W, &nnz, colptr, rowind, val), FRIX_OK);
    int64_t k = -1;
    for (int64_t j = 0; j < 5 && k < 0; ++j)
        for (int64_t e = colptr[j]; e < colptr[j + 1] && k < 0; ++e)
            if ((rowind[e] / 5 == 0) == own && rowind[e] != j && val[e] != 0.0) k = e;
    ck_assert_int_ge(k, 0);
    val[k] *= 1.0 + eps;
    if (eps == -1.0) { /* its mirror stays: the pattern is not symmetric */
        memmove(rowind + k, rowind + k + 1, (size_t)(nnz - k - 1) * sizeof(int64_t));
        memmove(val + k, val + k + 1, (size_t)(nnz - k - 1) * sizeof(double));
        for (int64_t c = 1; c <= m; ++c) --colptr[c];
    }
    ck_assert_int_eq(frix_matrix_from_csc(m, m, colptr, rowind, val, W), FRIX_OK);
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_problem_rolling_local(*W, pile->q, pile->mu, pile->mu_r, pile->nc, &p), FRIX_OK);
    free(colptr), free(rowind), free(val);
    return p;
}

/* The local form's sweeps read W where it lies, with no copy: by its 3x3 block rows where W is
 * stored so (5 nc a multiple of 3), else by its columns read as its rows where W is symmetric:
 * the same iterates as on a copy of its block rows, to round-off (40 sweeps on two piles, one
 * of each storage). A W symmetric to round-off (an entry off by 1e-15 of itself) is read so; one
 * stored by columns with an entry off by 1e-6, or left out while its mirror stays, is not (its
 * transpose is another problem), and rolling-nsgs solves it on a copy of W's block rows, as the
 * log says. Stored by blocks, W's rows are read as they are, symmetric or not (an entry of W_00,
 * then one off it, off by 1e-3); and with six entries a contact. */
/* 40 sweeps from r = 0 on W where it lies and on a copy of its block rows: the same iterates to
 * round-off. */
static void check_forms_agree(const frix_problem *p, int64_t m) {
    double *stored = calloc((size_t)m, sizeof(double)), *copied = calloc((size_t)m, sizeof(double));
    ck_assert_int_eq(frix_testing_rolling_local_sweeps(p, 1, 40, stored), FRIX_OK);
    ck_assert_int_eq(frix_testing_rolling_local_sweeps(p, 0, 40, copied), FRIX_OK);
    double diff = 0.0, size = 0.0;
    for (int64_t i = 0; i < m; ++i)
        diff = fmax(diff, fabs(stored[i] - copied[i])), size = fmax(size, fabs(copied[i]));
    ck_assert_double_gt(size, 0.0);
    ck_assert_double_le(diff, 1e-10 * size);
    free(stored), free(copied);
}

START_TEST(test_local_forms) {
    int storages = 0; /* bit 0: by blocks, bit 1: by columns */
    const int sides[2][2] = {{3, 2}, {4, 2}};
    for (int t = 0; t < 2; ++t) {
        rolling_pile pile;
        ck_assert_int_eq(rolling_pile_make(sides[t][0], sides[t][1], 0.3, 0.02, 7, &pile), 0);
        const int64_t m = 5 * pile.nc;
        const int by_blocks = m % 3 == 0;
        storages |= by_blocks ? 1 : 2;
        check_forms_agree(pile.local, m);
        if (by_blocks) /* rows read as stored, symmetric or not: W_00 and an entry off it made uneven */
            for (int own = 0; own < 2; ++own) {
                frix_matrix *W = NULL;
                frix_problem *p = with_entry_scaled(&pile, 1e-3, own, &W);
                check_forms_agree(p, m);
                frix_problem_free(p);
                frix_matrix_free(W);
            }

        const double eps[3] = {1e-15, 1e-6, -1.0};
        for (int c = 0; c < 3; ++c) {
            frix_matrix *W = NULL;
            frix_problem *p = with_entry_scaled(&pile, eps[c], 0, &W);
            double *r = calloc((size_t)m, sizeof(double)), *u = calloc((size_t)m, sizeof(double));
            const int served = by_blocks || c == 0;
            ck_assert_int_eq(frix_testing_rolling_local_sweeps(p, 1, 1, r), served ? FRIX_OK : FRIX_ERR_UNSUPPORTED);
            char form[64] = "";
            frix_options *o = NULL;
            frix_info *info = NULL;
            ck_assert_int_eq(frix_options_create(FRIX_SOLVER_ROLLING_NSGS, &o), FRIX_OK);
            ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 1e-8), FRIX_OK);
            ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_VERBOSITY, 1), FRIX_OK);
            ck_assert_int_eq(frix_options_set_log(o, read_form, form), FRIX_OK);
            ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
            memset(r, 0, (size_t)m * sizeof(double));
            ck_assert_int_eq(frix_solve(p, o, r, u, NULL, info), FRIX_OK);
            ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_CONVERGED);
            ck_assert_str_eq(form, by_blocks ? "W's stored rows"
                                   : c == 0  ? "W's columns as its rows"
                                             : "W's block rows copied");
            frix_info_free(info);
            frix_options_free(o);
            frix_problem_free(p);
            frix_matrix_free(W);
            free(r), free(u);
        }
        rolling_pile_free(&pile);
    }
    ck_assert_int_eq(storages, 3);
    /* Six entries a contact (spinning friction): W by 3x3 blocks, two to a contact's row. */
    rolling_pile spin;
    ck_assert_int_eq(rolling_pile_make_spinning(3, 2, 0.3, 0.02, 0.01, 7, &spin), 0);
    check_forms_agree(spin.local, 6 * spin.nc);
    rolling_pile_free(&spin);
}
END_TEST

/* The pile's W stored by columns in other units for contact 0 (D W D, D = `scale` on contact
 * 0's five entries, 1 elsewhere), the first non-zero entry of its column 0 in another
 * contact's rows then multiplied by 1 + eps: the local problem on it. */
static frix_problem *with_contact_rescaled(const rolling_pile *pile, double scale, double eps, frix_matrix **W,
                                           double **q_out) {
    int64_t nnz = 0, m = 5 * pile->nc;
    ck_assert_int_eq(frix_matrix_to_csc(pile->W, &nnz, NULL, NULL, NULL), FRIX_OK);
    int64_t *colptr = malloc((size_t)(m + 1) * sizeof(int64_t)), *rowind = malloc((size_t)nnz * sizeof(int64_t));
    double *val = malloc((size_t)nnz * sizeof(double)), *q = malloc((size_t)m * sizeof(double));
    ck_assert_int_eq(frix_matrix_to_csc(pile->W, &nnz, colptr, rowind, val), FRIX_OK);
    int perturbed = 0;
    for (int64_t j = 0; j < m; ++j)
        for (int64_t e = colptr[j]; e < colptr[j + 1]; ++e) {
            val[e] *= (rowind[e] < 5 ? scale : 1.0) * (j < 5 ? scale : 1.0);
            if (j == 0 && rowind[e] >= 5 && val[e] != 0.0 && !perturbed) val[e] *= 1.0 + eps, perturbed = 1;
        }
    ck_assert(perturbed);
    for (int64_t i = 0; i < m; ++i) q[i] = pile->q[i] * (i < 5 ? scale : 1.0);
    ck_assert_int_eq(frix_matrix_from_csc(m, m, colptr, rowind, val, W), FRIX_OK);
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_problem_rolling_local(*W, q, pile->mu, pile->mu_r, pile->nc, &p), FRIX_OK);
    free(colptr), free(rowind), free(val);
    *q_out = q; /* the problem borrows it */
    return p;
}

/* W is read by its columns where it equals its transpose to round-off at every scale: a
 * contact in other units (its rows and columns scaled by 1e-8, its entries against the others
 * 1e-8 of theirs and its own 1e-16) with an entry against another contact off its mirror by
 * 1e-6 of itself is not read so (its transpose is another problem, however small the entries
 * are against the largest), nor off by 1e-9; in those units without it, and with every entry
 * scaled by 1e150 or 1e-150, it is. */
START_TEST(test_symmetry_at_every_scale) {
    rolling_pile pile;
    ck_assert_int_eq(rolling_pile_make(4, 2, 0.3, 0.02, 7, &pile), 0);
    const int64_t m = 5 * pile.nc;
    ck_assert_int_ne(m % 3, 0); /* stored by columns */
    const struct {
        double scale, eps;
        int served;
    } cases[] = {{1e-8, 1e-6, 0}, {1e-8, 1e-9, 0}, {1e-8, 0.0, 1}, {1.0, 1e-6, 0}, {1.0, 1e-15, 1}};
    double *r = calloc((size_t)m, sizeof(double));
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
        frix_matrix *W = NULL;
        double *q = NULL;
        frix_problem *p = with_contact_rescaled(&pile, cases[c].scale, cases[c].eps, &W, &q);
        memset(r, 0, (size_t)m * sizeof(double));
        ck_assert_int_eq(frix_testing_rolling_local_sweeps(p, 1, 1, r),
                         cases[c].served ? FRIX_OK : FRIX_ERR_UNSUPPORTED);
        frix_problem_free(p);
        frix_matrix_free(W);
        free(q);
    }
    /* All of W in other units: the same verdict. A pair of mirrored entries made 1e3 times the
     * largest entry (past sqrt(W_ii W_jj): W no longer positive semidefinite, where the one-pass
     * test's tolerance would have no bound): the pairwise test decides, read by columns where
     * the pair agrees, not where one of them is off by 1e-6 of itself. */
    for (int k = 0; k < 4; ++k) {
        const double scale = k == 0 ? 1e75 : k == 1 ? 1e-75 : 1.0; /* W scaled by its square */
        int64_t nnz = 0;
        ck_assert_int_eq(frix_matrix_to_csc(pile.W, &nnz, NULL, NULL, NULL), FRIX_OK);
        int64_t *colptr = malloc((size_t)(m + 1) * sizeof(int64_t)), *rowind = malloc((size_t)nnz * sizeof(int64_t));
        double *val = malloc((size_t)nnz * sizeof(double));
        ck_assert_int_eq(frix_matrix_to_csc(pile.W, &nnz, colptr, rowind, val), FRIX_OK);
        for (int64_t e = 0; e < nnz; ++e) val[e] *= scale * scale;
        if (k >= 2) {
            int64_t at = -1, mirror = -1;
            for (int64_t e = colptr[0]; e < colptr[1] && at < 0; ++e)
                if (rowind[e] >= 5 && val[e] != 0.0) at = e;
            ck_assert_int_ge(at, 0);
            for (int64_t e = colptr[rowind[at]]; e < colptr[rowind[at] + 1]; ++e)
                if (rowind[e] == 0) mirror = e;
            ck_assert_int_ge(mirror, 0);
            double largest = 0.0;
            for (int64_t e = 0; e < nnz; ++e) largest = fmax(largest, fabs(val[e]));
            val[at] = val[mirror] = 1e3 * largest; /* past sqrt(W_ii W_jj) <= max |W| */
            if (k == 3) val[at] *= 1.0 + 1e-6;
        }
        frix_matrix *W = NULL;
        ck_assert_int_eq(frix_matrix_from_csc(m, m, colptr, rowind, val, &W), FRIX_OK);
        frix_problem *p = NULL;
        ck_assert_int_eq(frix_problem_rolling_local(W, pile.q, pile.mu, pile.mu_r, pile.nc, &p), FRIX_OK);
        memset(r, 0, (size_t)m * sizeof(double));
        ck_assert_int_eq(frix_testing_rolling_local_sweeps(p, 1, 1, r), k == 3 ? FRIX_ERR_UNSUPPORTED : FRIX_OK);
        frix_problem_free(p);
        frix_matrix_free(W);
        free(colptr), free(rowind), free(val);
    }
    free(r);
    rolling_pile_free(&pile);
}
END_TEST

/* A pile of 8 x 8 spheres in 6 layers (1,056 contacts) at 1e-8 in the product form: its error
 * stalls for hundreds of sweeps, after which momentum restarts only where a sweep's step grows
 * by more than a quarter of its square: 5,776 sweeps (20,704 with the restart rule of the local
 * form, which keeps it). */
START_TEST(test_product_form_loosens_momentum_after_a_stall) {
    rolling_pile pile;
    ck_assert_int_eq(rolling_pile_make(8, 6, 0.3, 0.02, 1, &pile), 0);
    const int64_t m = 5 * pile.nc;
    double *r = calloc((size_t)m, sizeof(double)), *u = calloc((size_t)m, sizeof(double));
    double *v = calloc((size_t)pile.n, sizeof(double));
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_ROLLING_NSGS, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 1e-8), FRIX_OK);
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_solve(pile.global, o, r, u, v, info), FRIX_OK);
    ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_CONVERGED);
    ck_assert_double_le(frix_info_error(info), 1e-8);
    ck_assert_int_lt(frix_info_iterations(info), 10000);
    frix_info_free(info);
    frix_options_free(o);
    free(r), free(u), free(v);
    rolling_pile_free(&pile);
}
END_TEST

/* The global form answers v = M^-1 (H r + f) and u = H^T v + w. */
START_TEST(test_global_velocity) {
    rolling_pile pile;
    ck_assert_int_eq(rolling_pile_make(2, 2, 0.4, 0.01, 7, &pile), 0);
    const int64_t m = 5 * pile.nc, n = pile.n;
    double *r = calloc((size_t)m, sizeof(double)), *u = calloc((size_t)m, sizeof(double));
    double *v = calloc((size_t)n, sizeof(double)), *b = calloc((size_t)n, sizeof(double));
    double *mv = calloc((size_t)n, sizeof(double)), *hv = calloc((size_t)m, sizeof(double));
    ck_assert_int_eq(frix_solve(pile.global, NULL, r, u, v, NULL), FRIX_OK);
    ck_assert_int_eq(frix_matrix_gemv(pile.H, 1.0, r, 0.0, b), FRIX_OK);
    ck_assert_int_eq(frix_matrix_gemv(pile.M, 1.0, v, 0.0, mv), FRIX_OK);
    for (int64_t i = 0; i < n; ++i) ck_assert_double_eq_tol(mv[i], b[i] + pile.f[i], 1e-12);
    ck_assert_int_eq(frix_matrix_gemv_transposed(pile.H, 1.0, v, 0.0, hv), FRIX_OK);
    for (int64_t i = 0; i < m; ++i) ck_assert_double_eq_tol(u[i], hv[i] + pile.w[i], 1e-12);
    ck_assert_int_eq(frix_solve(pile.global, NULL, r, u, NULL, NULL), FRIX_ERR_INVALID_ARGUMENT);
    free(r), free(u), free(v), free(b), free(mv), free(hv);
    rolling_pile_free(&pile);
}
END_TEST

/* rolling-nsgs's log of its domains: the most domains of one colour, and the threads. */
typedef struct {
    long long widest;
    int threads;
} domain_log;

static void read_domains(void *data, const char *line) {
    domain_log *d = data;
    long long domains = 0, colours = 0, widest = 0;
    int threads = 0;
    if (sscanf(line, "rolling-nsgs: %lld domains of %lld colours, at most %lld a colour, %d threads", &domains,
               &colours, &widest, &threads) == 4)
        d->widest = widest, d->threads = threads;
}

/* The product form sweeps domains of contacts, those of one colour at once on the threads:
 * rolling-nsgs and auto (whose sweeps get the caller's threads) answer the same r, u, v, the
 * same iterations and error bit for bit on 1, 2 and 3 threads, five and six entries a contact
 * (the loop's index: solver, then spinning). The 4 x 4 x 4 pile (160 contacts) has two domains
 * of one colour, which the log shows swept on the threads asked for. */
/* A global problem's warm start that already meets the tolerance is the answer after no sweep
 * (rolling-nsgs's product form measures it first; auto runs rolling-nsgs first): r unchanged to
 * the bit. Five and six entries. */
START_TEST(test_global_start_that_solves) {
    const int solver = _i % 2 ? FRIX_SOLVER_AUTO : FRIX_SOLVER_ROLLING_NSGS, spinning = _i / 2;
    rolling_pile pile;
    ck_assert_int_eq(spinning ? rolling_pile_make_spinning(3, 2, 0.3, 0.02, 0.01, 5, &pile)
                              : rolling_pile_make(3, 2, 0.3, 0.02, 5, &pile),
                     0);
    const int64_t m = pile.size * pile.nc, n = pile.n;
    double *star = calloc((size_t)m, sizeof(double)), *r = calloc((size_t)m, sizeof(double));
    double *u = calloc((size_t)m, sizeof(double)), *v = calloc((size_t)n, sizeof(double));
    frix_options *o = NULL;
    frix_info *info = NULL;
    ck_assert_int_eq(frix_options_create(solver, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 1e-8), FRIX_OK);
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_solve(pile.global, o, star, u, v, info), FRIX_OK);
    ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_CONVERGED);
    ck_assert_int_gt(frix_info_iterations(info), 0);
    memcpy(r, star, sizeof(double) * (size_t)m);
    ck_assert_int_eq(frix_solve(pile.global, o, r, u, v, info), FRIX_OK);
    ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_CONVERGED);
    ck_assert_int_eq(frix_info_iterations(info), 0);
    ck_assert_double_le(frix_info_error(info), 1e-8);
    ck_assert_mem_eq(r, star, sizeof(double) * (size_t)m);
    /* Half of it misses: swept. */
    for (int64_t i = 0; i < m; ++i) r[i] = 0.5 * star[i];
    ck_assert_int_eq(frix_solve(pile.global, o, r, u, v, info), FRIX_OK);
    ck_assert_int_gt(frix_info_iterations(info), 0);
    frix_info_free(info);
    frix_options_free(o);
    free(star), free(r), free(u), free(v);
    rolling_pile_free(&pile);
}
END_TEST

START_TEST(test_threads_bit_identical) {
    const int solver = _i % 2 ? FRIX_SOLVER_AUTO : FRIX_SOLVER_ROLLING_NSGS, spinning = _i / 2;
    rolling_pile pile;
    ck_assert_int_eq(spinning ? rolling_pile_make_spinning(4, 4, 0.3, 0.02, 0.01, 5, &pile)
                              : rolling_pile_make(4, 4, 0.3, 0.02, 5, &pile),
                     0);
    const int64_t m = pile.size * pile.nc, n = pile.n;
    double *r[3], *u[3], *v[3], error[3];
    int64_t iterations[3];
    for (int t = 0; t < 3; ++t) {
        r[t] = calloc((size_t)m, sizeof(double));
        u[t] = calloc((size_t)m, sizeof(double));
        v[t] = calloc((size_t)n, sizeof(double));
        frix_options *o = NULL;
        frix_info *info = NULL;
        domain_log log = {0, 0};
        ck_assert_int_eq(frix_options_create(solver, &o), FRIX_OK);
        ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_THREADS, t + 1), FRIX_OK);
        ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 1e-8), FRIX_OK);
        ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_VERBOSITY, 1), FRIX_OK);
        ck_assert_int_eq(frix_options_set_log(o, read_domains, &log), FRIX_OK);
        ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
        ck_assert_int_eq(frix_solve(pile.global, o, r[t], u[t], v[t], info), FRIX_OK);
        ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_CONVERGED);
        error[t] = frix_info_error(info);
        ck_assert_double_le(error[t], 1e-8);
        iterations[t] = frix_info_iterations(info);
        ck_assert_int_gt(iterations[t], 10); /* the sweeps, not the start, decide the answer */
        if (solver == FRIX_SOLVER_ROLLING_NSGS) {
            ck_assert_int_ge(log.widest, 2);
            ck_assert_int_eq(log.threads, t + 1);
        }
        frix_info_free(info);
        frix_options_free(o);
    }
    for (int t = 1; t < 3; ++t) {
        ck_assert_int_eq(iterations[t], iterations[0]);
        ck_assert(error[t] == error[0]);
        ck_assert_mem_eq(r[t], r[0], sizeof(double) * (size_t)m);
        ck_assert_mem_eq(u[t], u[0], sizeof(double) * (size_t)m);
        ck_assert_mem_eq(v[t], v[0], sizeof(double) * (size_t)n);
    }
    for (int t = 0; t < 3; ++t) free(r[t]), free(u[t]), free(v[t]);
    rolling_pile_free(&pile);
}
END_TEST

/* The time limit and the iteration limit stop rolling-nsgs (through the Monitor), with the
 * answer measured and finite. */
START_TEST(test_limits) {
    rolling_pile pile;
    ck_assert_int_eq(rolling_pile_make(4, 4, 0.3, 0.02, 11, &pile), 0);
    const int64_t m = 5 * pile.nc;
    double *r = calloc((size_t)m, sizeof(double)), *u = calloc((size_t)m, sizeof(double));
    frix_options *o = NULL;
    frix_info *info = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_ROLLING_NSGS, &o), FRIX_OK);
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 1e-300), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TIME_LIMIT, 1e-3), FRIX_OK);
    ck_assert_int_eq(frix_solve(pile.local, o, r, u, NULL, info), FRIX_OK);
    ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_TIME_LIMIT);
    ck_assert(isfinite(frix_info_error(info)));
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TIME_LIMIT, 0.0), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_MAX_ITER, 3), FRIX_OK);
    memset(r, 0, sizeof(double) * (size_t)m);
    ck_assert_int_eq(frix_solve(pile.local, o, r, u, NULL, info), FRIX_OK);
    ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_MAX_ITER);
    ck_assert_int_eq(frix_info_iterations(info), 3);
    frix_options_free(o);
    frix_info_free(info);
    free(r), free(u);
    rolling_pile_free(&pile);
}
END_TEST

/* All separating: r = 0 at once. */
START_TEST(test_separating) {
    frix_matrix *W = identity(5);
    double q[5] = {0.5, 1, 0, 1, 0}, mu = 0.5, mu_r = 0.01, r[5] = {1, 1, 1, 1, 1}, u[5];
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_problem_rolling_local(W, q, &mu, &mu_r, 1, &p), FRIX_OK);
    ck_assert_int_eq(frix_solve(p, NULL, r, u, NULL, NULL), FRIX_OK);
    for (int i = 0; i < 5; ++i) ck_assert_double_eq(r[i], 0.0);
    frix_problem_free(p);
    frix_matrix_free(W);
}
END_TEST

/* One contact that nothing holds in the normal direction, pressed: no solution
 * (rolling_check_no_solution). */
START_TEST(test_no_solution_diverges) { rolling_check_no_solution(5); }
END_TEST

int main(void) {
    Suite *s = suite_create("rolling");
    TCase *tc = tcase_create("core");
    tcase_set_timeout(tc, 120);
    tcase_add_test(tc, test_validation);
    tcase_add_test(tc, test_classic_has_no_mu_r);
    tcase_add_test(tc, test_refused);
    tcase_add_test(tc, test_measure_by_hand);
    tcase_add_test(tc, test_one_sphere_on_ground);
    tcase_add_test(tc, test_one_sphere_at_extreme_scales);
    tcase_add_test(tc, test_product_form_loosens_momentum_after_a_stall);
    tcase_add_test(tc, test_nsgs_on_piles);
    tcase_add_test(tc, test_local_forms);
    tcase_add_test(tc, test_symmetry_at_every_scale);
    tcase_add_test(tc, test_global_velocity);
    tcase_add_loop_test(tc, test_global_start_that_solves, 0, 4);
    tcase_add_loop_test(tc, test_threads_bit_identical, 0, 4);
    tcase_add_test(tc, test_separating);
    tcase_add_test(tc, test_limits);
    tcase_add_test(tc, test_no_solution_diverges);
    suite_add_tcase(s, tc);
    return frix_run_suite(s);
}
