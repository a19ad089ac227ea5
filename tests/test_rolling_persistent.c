/* The persistent solver on rolling-friction problems (frix_persistent.h): its answers are
 * frix_solve's, in the local and the global form; a warm-started next step costs fewer sweeps
 * than a cold one; the contacts and mu_r change through the rolling calls; bad input and the
 * calls of the other law are refused with a message. Problems: tests/support/rolling_pile.h. */
#include <frix/frix.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check_main.h"
#include "support/rolling_pile.h"

/* A solve's answer and counters. */
typedef struct {
    double *r, *u, *v;
    int64_t iterations;
    frix_status status;
} answer;

static answer answer_make(int64_t nc, int64_t n) {
    answer a = {calloc((size_t)(5 * nc + 1), sizeof(double)), calloc((size_t)(5 * nc + 1), sizeof(double)),
                calloc((size_t)(n + 1), sizeof(double)), 0, FRIX_STATUS_NOT_RUN};
    ck_assert(a.r && a.u && a.v);
    return a;
}

static void answer_free(answer *a) { free(a->r), free(a->u), free(a->v); }

static void record(answer *a, const frix_info *info) {
    a->iterations = frix_info_iterations(info);
    a->status = frix_info_status(info);
}

/* frix_solve of p from the warm start r0 (NULL: 0), with options o. */
static answer one_shot(const frix_problem *p, const frix_options *o, const double *r0) {
    const int64_t nc = frix_problem_contacts(p), n = frix_problem_dofs(p);
    answer a = answer_make(nc, n);
    if (r0) memcpy(a.r, r0, sizeof(double) * 5 * (size_t)nc);
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_solve(p, o, a.r, a.u, n ? a.v : NULL, info), FRIX_OK);
    record(&a, info);
    frix_info_free(info);
    return a;
}

/* The persistent solver's solve from r0 (NULL: 0). */
static answer persistent_solve(frix_persistent *ps, int64_t nc, int64_t n, const double *r0) {
    answer a = answer_make(nc, n);
    if (r0) memcpy(a.r, r0, sizeof(double) * 5 * (size_t)nc);
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_persistent_solve(ps, a.r, a.u, n ? a.v : NULL, info), FRIX_OK);
    record(&a, info);
    frix_info_free(info);
    return a;
}

/* The same answer, to the bit: the persistent solver of a rolling problem keeps no state that
 * would change it. */
static void assert_same(const answer *x, const answer *y, int64_t nc, int64_t n) {
    ck_assert_int_eq(x->status, y->status);
    ck_assert_int_eq(x->iterations, y->iterations);
    ck_assert_int_eq(memcmp(x->r, y->r, sizeof(double) * 5 * (size_t)nc), 0);
    ck_assert_int_eq(memcmp(x->u, y->u, sizeof(double) * 5 * (size_t)nc), 0);
    ck_assert_int_eq(memcmp(x->v, y->v, sizeof(double) * (size_t)n), 0);
}

static frix_options *options_for(int solver) {
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(solver, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 1e-8), FRIX_OK);
    return o;
}

/* Two steps in each form, with auto and rolling-nsgs: the first from r = 0, the second (a new
 * q, or a new f: the pile pushed a little more) from the first's r. Each answer is
 * frix_solve's from the same start; the warm second step takes fewer sweeps than a cold one
 * (rolling-nsgs). */
START_TEST(test_steps_match_frix_solve) {
    rolling_pile pile;
    ck_assert_int_eq(rolling_pile_make(3, 3, 0.4, 0.02, 5, &pile), 0);
    const int64_t nc = pile.nc, n = pile.n;
    double *q2 = malloc(sizeof(double) * 5 * (size_t)nc), *f2 = malloc(sizeof(double) * (size_t)n);
    /* The next step: every normal free velocity 2 % further into contact, every body's
     * momentum 2 % larger. */
    for (int64_t i = 0; i < 5 * nc; ++i) q2[i] = pile.q[i] * (i % 5 == 0 ? 1.02 : 1.0);
    for (int64_t i = 0; i < n; ++i) f2[i] = 1.02 * pile.f[i];
    const int solvers[2] = {FRIX_SOLVER_AUTO, FRIX_SOLVER_ROLLING_NSGS};
    for (int s = 0; s < 2; ++s)
        for (int global = 0; global < 2; ++global) {
            frix_options *o = options_for(solvers[s]);
            const frix_problem *first = global ? pile.global : pile.local;
            const int64_t dofs = global ? n : 0;
            frix_persistent *ps = NULL;
            ck_assert_int_eq(frix_persistent_create(first, o, &ps), FRIX_OK);
            answer a1 = persistent_solve(ps, nc, dofs, NULL), b1 = one_shot(first, o, NULL);
            ck_assert_int_eq(a1.status, FRIX_STATUS_CONVERGED);
            assert_same(&a1, &b1, nc, dofs);

            frix_problem *second = NULL;
            if (global) {
                ck_assert_int_eq(frix_persistent_update_global(ps, NULL, NULL, f2, NULL, NULL), FRIX_OK);
                ck_assert_int_eq(
                    frix_problem_rolling_global(pile.M, pile.H, f2, pile.w, pile.mu, pile.mu_r, nc, &second), FRIX_OK);
            } else {
                ck_assert_int_eq(frix_persistent_update_local(ps, NULL, q2, NULL), FRIX_OK);
                ck_assert_int_eq(frix_problem_rolling_local(pile.W, q2, pile.mu, pile.mu_r, nc, &second), FRIX_OK);
            }
            answer a2 = persistent_solve(ps, nc, dofs, a1.r), b2 = one_shot(second, o, a1.r);
            answer cold = one_shot(second, o, NULL);
            ck_assert_int_eq(a2.status, FRIX_STATUS_CONVERGED);
            assert_same(&a2, &b2, nc, dofs);
            ck_assert_int_eq(cold.status, FRIX_STATUS_CONVERGED);
            /* auto's count adds Newton steps to sweeps (its polish after 1e-4): the sweeps alone say
             * what the warm start saves. */
            if (solvers[s] == FRIX_SOLVER_ROLLING_NSGS) ck_assert_int_lt(a2.iterations, cold.iterations);
            answer_free(&a1), answer_free(&b1), answer_free(&a2), answer_free(&b2), answer_free(&cold);
            frix_problem_free(second);
            frix_persistent_free(ps);
            frix_options_free(o);
        }
    free(q2), free(f2);
    rolling_pile_free(&pile);
}
END_TEST

/* The leading rows x cols of A (a new matrix). */
static frix_matrix *leading(const frix_matrix *A, int64_t rows, int64_t cols) {
    int64_t nnz = 0;
    ck_assert_int_eq(frix_matrix_to_csc(A, &nnz, NULL, NULL, NULL), FRIX_OK);
    int64_t *colptr = malloc(sizeof(int64_t) * (size_t)(frix_matrix_cols(A) + 1));
    int64_t *rowind = malloc(sizeof(int64_t) * (size_t)(nnz + 1)), *ti = malloc(sizeof(int64_t) * (size_t)(nnz + 1));
    int64_t *tj = malloc(sizeof(int64_t) * (size_t)(nnz + 1));
    double *val = malloc(sizeof(double) * (size_t)(nnz + 1)), *tv = malloc(sizeof(double) * (size_t)(nnz + 1));
    ck_assert_int_eq(frix_matrix_to_csc(A, &nnz, colptr, rowind, val), FRIX_OK);
    int64_t k = 0;
    for (int64_t j = 0; j < cols; ++j)
        for (int64_t e = colptr[j]; e < colptr[j + 1]; ++e)
            if (rowind[e] < rows) ti[k] = rowind[e], tj[k] = j, tv[k++] = val[e];
    frix_matrix *B = NULL;
    ck_assert_int_eq(frix_matrix_from_triplets(rows, cols, k, ti, tj, tv, &B), FRIX_OK);
    free(colptr), free(rowind), free(ti), free(tj), free(val), free(tv);
    return B;
}

/* Contacts that go and come back, and a new mu_r: each solve is frix_solve's on the problem
 * the persistent solver was given. */
START_TEST(test_contacts_and_mu_r) {
    rolling_pile pile;
    ck_assert_int_eq(rolling_pile_make(3, 2, 0.4, 0.02, 9, &pile), 0);
    const int64_t nc = pile.nc, n = pile.n, kept = nc - 4;
    frix_matrix *H_kept = leading(pile.H, n, 5 * kept), *W_kept = leading(pile.W, 5 * kept, 5 * kept);
    double *mu_r2 = malloc(sizeof(double) * (size_t)nc);
    for (int64_t a = 0; a < nc; ++a) mu_r2[a] = 0.5 * pile.mu_r[a];
    frix_options *o = options_for(FRIX_SOLVER_AUTO);
    for (int global = 0; global < 2; ++global) {
        const int64_t dofs = global ? n : 0;
        frix_persistent *ps = NULL;
        ck_assert_int_eq(frix_persistent_create(global ? pile.global : pile.local, o, &ps), FRIX_OK);
        answer full = persistent_solve(ps, nc, dofs, NULL);
        /* Fewer contacts. */
        frix_problem *fewer = NULL;
        if (global) {
            ck_assert_int_eq(frix_persistent_set_contacts_rolling_global(ps, H_kept, pile.w, pile.mu, pile.mu_r, kept),
                             FRIX_OK);
            ck_assert_int_eq(
                frix_problem_rolling_global(pile.M, H_kept, pile.f, pile.w, pile.mu, pile.mu_r, kept, &fewer), FRIX_OK);
        } else {
            ck_assert_int_eq(frix_persistent_set_contacts_rolling_local(ps, W_kept, pile.q, pile.mu, pile.mu_r, kept),
                             FRIX_OK);
            ck_assert_int_eq(frix_problem_rolling_local(W_kept, pile.q, pile.mu, pile.mu_r, kept, &fewer), FRIX_OK);
        }
        answer a = persistent_solve(ps, kept, dofs, full.r), b = one_shot(fewer, o, full.r);
        assert_same(&a, &b, kept, dofs);
        /* All of them again, with half the rolling resistance: the moments follow mu_r. */
        if (global)
            ck_assert_int_eq(frix_persistent_set_contacts_rolling_global(ps, pile.H, pile.w, pile.mu, pile.mu_r, nc),
                             FRIX_OK);
        else
            ck_assert_int_eq(frix_persistent_set_contacts_rolling_local(ps, pile.W, pile.q, pile.mu, pile.mu_r, nc),
                             FRIX_OK);
        ck_assert_int_eq(frix_persistent_update_mu_r(ps, mu_r2), FRIX_OK);
        frix_problem *halved = NULL;
        if (global)
            ck_assert_int_eq(frix_problem_rolling_global(pile.M, pile.H, pile.f, pile.w, pile.mu, mu_r2, nc, &halved),
                             FRIX_OK);
        else
            ck_assert_int_eq(frix_problem_rolling_local(pile.W, pile.q, pile.mu, mu_r2, nc, &halved), FRIX_OK);
        answer c = persistent_solve(ps, nc, dofs, full.r), d = one_shot(halved, o, full.r);
        ck_assert_int_eq(c.status, FRIX_STATUS_CONVERGED);
        assert_same(&c, &d, nc, dofs);
        for (int64_t k = 0; k < nc; ++k)
            /* Within the tolerance's share: a Newton answer (auto's polish) meets the cone to it. */
            ck_assert_double_le(hypot(c.r[5 * k + 3], c.r[5 * k + 4]), mu_r2[k] * c.r[5 * k] * (1 + 1e-7) + 1e-12);
        answer_free(&full), answer_free(&a), answer_free(&b), answer_free(&c), answer_free(&d);
        frix_problem_free(fewer);
        frix_problem_free(halved);
        frix_persistent_free(ps);
    }
    frix_options_free(o);
    free(mu_r2);
    frix_matrix_free(H_kept);
    frix_matrix_free(W_kept);
    rolling_pile_free(&pile);
}
END_TEST

/* Refusals with a message that names the fault; nothing of a refused call is taken. */
static void assert_refused(frix_error got, frix_error expected, const char *needle) {
    ck_assert_int_eq(got, expected);
    ck_assert_msg(strstr(frix_last_error_message(), needle) != NULL, "message \"%s\" lacks \"%s\"",
                  frix_last_error_message(), needle);
}

START_TEST(test_bad_input) {
    rolling_pile pile;
    ck_assert_int_eq(rolling_pile_make(2, 2, 0.4, 0.02, 3, &pile), 0);
    const int64_t nc = pile.nc, n = pile.n;
    /* A solver of three-component problems only. */
    frix_options *nsgs = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_NSGS, &nsgs), FRIX_OK);
    frix_persistent *ps = (frix_persistent *)&pile; /* must be overwritten with NULL */
    assert_refused(frix_persistent_create(pile.global, nsgs, &ps), FRIX_ERR_UNSUPPORTED, "rolling");
    ck_assert_ptr_null(ps);
    frix_options_free(nsgs);

    ck_assert_int_eq(frix_persistent_create(pile.global, NULL, &ps), FRIX_OK);
    answer first = persistent_solve(ps, nc, n, NULL);
    /* A negative or non-finite mu_r, and a mu_r without its contacts. */
    double *bad = malloc(sizeof(double) * (size_t)nc);
    memcpy(bad, pile.mu_r, sizeof(double) * (size_t)nc);
    bad[1] = -0.01;
    assert_refused(frix_persistent_update_mu_r(ps, bad), FRIX_ERR_INVALID_ARGUMENT, "mu_r[1]");
    assert_refused(frix_persistent_set_contacts_rolling_global(ps, pile.H, pile.w, pile.mu, bad, nc),
                   FRIX_ERR_INVALID_ARGUMENT, "mu_r[1]");
    bad[1] = NAN;
    assert_refused(frix_persistent_update_mu_r(ps, bad), FRIX_ERR_NOT_FINITE, "mu_r[1]");
    assert_refused(frix_persistent_update_mu_r(ps, NULL), FRIX_ERR_INVALID_ARGUMENT, "mu_r is NULL");
    assert_refused(frix_persistent_update_mu_r(NULL, pile.mu_r), FRIX_ERR_INVALID_ARGUMENT, "NULL");
    assert_refused(frix_persistent_set_contacts_rolling_global(ps, pile.H, pile.w, pile.mu, NULL, nc),
                   FRIX_ERR_INVALID_ARGUMENT, "mu_r is NULL");
    /* One contact more than H has columns for (5 a contact). */
    assert_refused(frix_persistent_set_contacts_rolling_global(ps, pile.H, pile.w, pile.mu, pile.mu_r, nc + 1),
                   FRIX_ERR_DIMENSION, "");
    /* The other law's calls, and the other form's. */
    assert_refused(frix_persistent_set_contacts_global(ps, pile.H, pile.w, pile.mu, nc), FRIX_ERR_INVALID_ARGUMENT,
                   "frix_persistent_set_contacts_rolling_global");
    assert_refused(frix_persistent_set_contacts_rolling_local(ps, pile.W, pile.q, pile.mu, pile.mu_r, nc),
                   FRIX_ERR_INVALID_ARGUMENT, "the problem is global");
    assert_refused(frix_persistent_update_local(ps, NULL, pile.q, NULL), FRIX_ERR_INVALID_ARGUMENT,
                   "the problem is global");
    assert_refused(frix_persistent_set_contacts_spinning_global(ps, pile.H, pile.w, pile.mu, pile.mu_r, pile.mu_r, nc),
                   FRIX_ERR_INVALID_ARGUMENT, "frix_persistent_set_contacts_rolling_global");
    assert_refused(frix_persistent_update_mu_s(ps, pile.mu_r), FRIX_ERR_INVALID_ARGUMENT, "no spinning friction");
    /* Nothing was taken: the next solve is the first's. */
    answer again = persistent_solve(ps, nc, n, NULL);
    assert_same(&first, &again, nc, n);
    frix_persistent_free(ps);

    /* A three-component problem's solver refuses the rolling calls. */
    double W3[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, q3[3] = {-1, 0, 0}, mu = 0.5, mu_r = 0.01;
    frix_matrix *W = NULL;
    frix_problem *classic = NULL;
    ck_assert_int_eq(frix_matrix_from_dense(3, 3, W3, 3, &W), FRIX_OK);
    ck_assert_int_eq(frix_problem_local(W, q3, &mu, 1, &classic), FRIX_OK);
    ck_assert_int_eq(frix_persistent_create(classic, NULL, &ps), FRIX_OK);
    assert_refused(frix_persistent_update_mu_r(ps, &mu_r), FRIX_ERR_INVALID_ARGUMENT, "no rolling friction");
    assert_refused(frix_persistent_set_contacts_rolling_local(ps, W, q3, &mu, &mu_r, 1), FRIX_ERR_INVALID_ARGUMENT,
                   "frix_persistent_set_contacts_local");
    frix_persistent_free(ps);
    frix_problem_free(classic);
    frix_matrix_free(W);
    answer_free(&first), answer_free(&again);
    free(bad);
    rolling_pile_free(&pile);
}
END_TEST

int main(void) {
    Suite *s = suite_create("rolling_persistent");
    TCase *tc = tcase_create("core");
    tcase_set_timeout(tc, 120);
    tcase_add_test(tc, test_steps_match_frix_solve);
    tcase_add_test(tc, test_contacts_and_mu_r);
    tcase_add_test(tc, test_bad_input);
    suite_add_tcase(s, tc);
    return frix_run_suite(s);
}
