/* The persistent solver's secant start (option secant_start, frix_persistent.h): along a line
 * of data it starts from the secant of the last two answers; it leaves the start as given
 * where the caller chose its own, where the data leave the line, where a matrix or mu
 * changed and after a solve that did not converge; it is off at secant_start = 0. */
#include <frix/frix.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check_main.h"
#include "elastic_grid.h"

enum { kContacts = 4, kRows = 3 * kContacts, kSteps = 5 };

/* A small local problem whose contacts all stick along the line of data used below, so that
 * its answers r = -W^-1 q move linearly with q: W = 2 I + 0.1 B B^T, B fixed. */
static frix_matrix *make_w(void) {
    double B[kRows * kRows], W[kRows * kRows];
    for (int i = 0; i < kRows * kRows; ++i) B[i] = sin(1.0 + 0.7 * i);
    for (int i = 0; i < kRows; ++i)
        for (int j = 0; j < kRows; ++j) {
            double s = 0.0;
            for (int k = 0; k < kRows; ++k) s += B[i + kRows * k] * B[j + kRows * k];
            W[i + kRows * j] = 0.1 * s + (i == j ? 2.0 : 0.0);
        }
    frix_matrix *out = NULL;
    ck_assert_int_eq(frix_matrix_from_dense(kRows, kRows, W, kRows, &out), FRIX_OK);
    return out;
}

/* q at step k of the line: normals pressing (-1 - 0.1 k), small tangents. */
static void q_on_line(int k, double *q) {
    for (int a = 0; a < kContacts; ++a) {
        q[3 * a] = -1.0 - 0.1 * k;
        q[3 * a + 1] = 0.01 * (a + 1) + 0.002 * k;
        q[3 * a + 2] = -0.01 * a + 0.001 * k;
    }
}

/* Changes a step may bring besides q moving along the line. */
typedef enum { kOnLine, kOffLine, kNewW, kNewMu, kStepOneCut, kOwnStart } change;

/* The callback stops the solve at its first iteration while *stop is set. */
static int stop_when_asked(void *stop, int64_t iteration, double error, double elapsed) {
    (void)error, (void)elapsed;
    return *(const int *)stop && iteration >= 1;
}

/* Steps 0 .. kSteps-1 of a persistent NSGS at 1e-10 with secant_start = secant; the `what`
 * change comes at step 2 (kStepOneCut: the callback stops step 1 after one sweep). Each step's r and
 * sweeps are written out. */
static void run_steps(int secant, change what, double r_out[kSteps][kRows], int64_t sweeps[kSteps]) {
    frix_matrix *W = make_w(), *W_again = make_w();
    double q[kRows], mu[kContacts] = {0.5, 0.5, 0.5, 0.5}, r[kRows] = {0}, u[kRows];
    q_on_line(0, q);
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_problem_local(W, q, mu, kContacts, &p), FRIX_OK);
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_NSGS, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 1e-10), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_SECANT_START, secant), FRIX_OK);
    int stop = 0;
    ck_assert_int_eq(frix_options_set_callback(o, stop_when_asked, &stop), FRIX_OK);
    frix_persistent *ps = NULL;
    ck_assert_int_eq(frix_persistent_create(p, o, &ps), FRIX_OK);
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    for (int k = 0; k < kSteps; ++k) {
        q_on_line(k, q);  /* in place: the persistent solver borrows q */
        if (k == 2 && what == kOffLine) q[0] -= 0.05;
        if (k == 2 && what == kNewW) ck_assert_int_eq(frix_persistent_update_local(ps, W_again, NULL, NULL), FRIX_OK);
        if (k == 2 && what == kNewMu) mu[1] = 0.6;
        if (k == 2 && what == kOwnStart) memset(r, 0, sizeof r);
        stop = k == 1 && what == kStepOneCut;
        ck_assert_int_eq(frix_persistent_solve(ps, r, u, NULL, info), FRIX_OK);
        ck_assert_int_eq(frix_info_status(info), stop ? FRIX_STATUS_STOPPED_BY_CALLBACK : FRIX_STATUS_CONVERGED);
        memcpy(r_out[k], r, sizeof r);
        sweeps[k] = frix_info_iterations(info);
    }
    frix_info_free(info);
    frix_persistent_free(ps);
    frix_options_free(o);
    frix_problem_free(p);
    frix_matrix_free(W);
    frix_matrix_free(W_again);
}

/* Along the line the contacts keep sticking: the secant start is the answer from step 2 on
 * (no sweep), where the last answer alone needs sweeps. */
START_TEST(test_on_the_line) {
    double on[kSteps][kRows], off[kSteps][kRows];
    int64_t sweeps_on[kSteps], sweeps_off[kSteps];
    run_steps(1, kOnLine, on, sweeps_on);
    run_steps(0, kOnLine, off, sweeps_off);
    for (int k = 0; k < 2; ++k) {
        ck_assert_int_eq(sweeps_on[k], sweeps_off[k]);
        ck_assert_mem_eq(on[k], off[k], sizeof on[k]);
    }
    for (int k = 2; k < kSteps; ++k) {
        ck_assert_int_gt(sweeps_off[k], 0);
        ck_assert_int_eq(sweeps_on[k], 0);
        for (int i = 0; i < kRows; ++i) ck_assert_double_le(fabs(on[k][i] - off[k][i]), 1e-8);
    }
}
END_TEST

/* Where the start is not the secant's to choose, the solves are those of secant_start = 0,
 * to the bit: the data off the line, a new W (even with the same values), a new mu, a step
 * that stopped short (the history is forgotten), the caller's own start. */
static const change kLeftAlone[] = {kOffLine, kNewW, kNewMu, kStepOneCut, kOwnStart};

START_TEST(test_start_left_alone) {
    double on[kSteps][kRows], off[kSteps][kRows];
    int64_t sweeps_on[kSteps], sweeps_off[kSteps];
    run_steps(1, kLeftAlone[_i], on, sweeps_on);
    run_steps(0, kLeftAlone[_i], off, sweeps_off);
    ck_assert_int_gt(sweeps_on[2], 0);
    ck_assert_int_eq(sweeps_on[2], sweeps_off[2]);
    ck_assert_mem_eq(on[2], off[2], sizeof on[2]);
}
END_TEST

/* An elastic grid whose nodes stick, slide and separate (global form, auto at 1e-8), its load
 * raised by 2 % a step: every step converges in either setting, the secant start's from step
 * 2 on in fewer iterations altogether, with answers that meet the tolerance (frix_problem_error
 * of the returned r and v). */
START_TEST(test_load_path_of_a_grid) {
    frix_elastic_grid g;
    ck_assert_int_eq(frix_elastic_grid_make(10, 10, 3, 0.5, 1e4, &g), FRIX_OK);
    const int64_t nc = 100, m = 3 * nc, n = 3 * 10 * 10 * 3;
    double *f0 = malloc(sizeof *f0 * (size_t)n), *r = malloc(sizeof *r * (size_t)m);
    double *u = malloc(sizeof *u * (size_t)m), *v = malloc(sizeof *v * (size_t)n);
    memcpy(f0, g.f, sizeof *f0 * (size_t)n);
    int64_t total[2] = {0, 0};
    for (int secant = 0; secant < 2; ++secant) {
        frix_options *o = NULL;
        ck_assert_int_eq(frix_options_create(FRIX_SOLVER_AUTO, &o), FRIX_OK);
        ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_SECANT_START, secant), FRIX_OK);
        memcpy(g.f, f0, sizeof *f0 * (size_t)n);
        frix_persistent *ps = NULL;
        ck_assert_int_eq(frix_persistent_create(g.problem, o, &ps), FRIX_OK);
        frix_info *info = NULL;
        ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
        memset(r, 0, sizeof *r * (size_t)m);
        for (int k = 0; k < 6; ++k) {
            for (int64_t i = 0; i < n; ++i) g.f[i] = (1.0 + 0.02 * k) * f0[i];
            ck_assert_int_eq(frix_persistent_solve(ps, r, u, v, info), FRIX_OK);
            ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_CONVERGED);
            double e = 0.0;
            ck_assert_int_eq(frix_problem_error(g.problem, r, v, &e), FRIX_OK);
            ck_assert_double_le(e, 1e-8);
            if (k >= 2) total[secant] += frix_info_iterations(info);
        }
        frix_info_free(info);
        frix_persistent_free(ps);
        frix_options_free(o);
    }
    ck_assert_int_lt(total[1], total[0]);
    free(f0), free(r), free(u), free(v);
    frix_elastic_grid_free(&g);
}
END_TEST

START_TEST(test_option) {
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_AUTO, &o), FRIX_OK);
    int64_t value = -1;
    ck_assert_int_eq(frix_options_get_int(o, FRIX_OPT_SECANT_START, &value), FRIX_OK);
    ck_assert_int_eq(value, 1);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_SECANT_START, 2), FRIX_ERR_OPTION_RANGE);
    ck_assert_int_eq(frix_options_set_by_name(o, "secant_start", "0"), FRIX_OK);
    ck_assert_int_eq(frix_options_get_int(o, FRIX_OPT_SECANT_START, &value), FRIX_OK);
    ck_assert_int_eq(value, 0);
    frix_options_free(o);
}
END_TEST

int main(void) {
    Suite *s = suite_create("secant_start");
    TCase *tc = tcase_create("secant_start");
    tcase_set_timeout(tc, 300);
    tcase_add_test(tc, test_on_the_line);
    tcase_add_loop_test(tc, test_start_left_alone, 0, (int)(sizeof kLeftAlone / sizeof *kLeftAlone));
    tcase_add_test(tc, test_load_path_of_a_grid);
    tcase_add_test(tc, test_option);
    suite_add_tcase(s, tc);
    return frix_run_suite(s);
}
