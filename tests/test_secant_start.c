/* The persistent solver's secant start (option secant_start, frix_persistent.h): along a line
 * of data it starts from the secant of the last two answers; it leaves the start as given
 * where the caller chose its own, where the data leave the line or jump far along it, where a
 * matrix or mu changed, after a solve that did not converge, for rolling problems, and at
 * secant_start = 0; a refused call hands the caller's r back. */
#include <frix/frix.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check_main.h"
#include "elastic_grid.h"

enum { kContacts = 4, kSteps = 5, kMaxRows = 5 * kContacts };

/* W = 2 I + 0.1 B B^T (rows x rows), B fixed: every contact sticks along the line of data
 * used below, so the answers r = -W^-1 q move linearly with q. */
static frix_matrix *make_w(int rows) {
    double B[kMaxRows * kMaxRows], W[kMaxRows * kMaxRows];
    for (int i = 0; i < rows * rows; ++i) B[i] = sin(1.0 + 0.7 * i);
    for (int i = 0; i < rows; ++i)
        for (int j = 0; j < rows; ++j) {
            double s = 0.0;
            for (int k = 0; k < rows; ++k) s += B[i + rows * k] * B[j + rows * k];
            W[i + rows * j] = 0.1 * s + (i == j ? 2.0 : 0.0);
        }
    frix_matrix *out = NULL;
    ck_assert_int_eq(frix_matrix_from_dense(rows, rows, W, rows, &out), FRIX_OK);
    return out;
}

/* q at point t of the line (dim entries a contact): normals pressing (-1 - 0.1 t), small
 * tangential (and rolling) parts. */
static void q_on_line(double t, int dim, double *q) {
    for (int a = 0; a < kContacts; ++a) {
        q[dim * a] = -1.0 - 0.1 * t;
        for (int j = 1; j < dim; ++j) q[dim * a + j] = 0.01 * (a + j) * (j % 2 ? 1.0 : -1.0) + 0.002 * t / j;
    }
}

/* What step 2 brings (steps 0 and 1 are points 0 and 1 of the line). */
typedef enum {
    kOnLine,     /* point 2 */
    kBack,       /* point 0 again: alpha = -1 */
    kOffLine,    /* point 2, one entry moved off the line */
    kFarAlong,   /* point 4: alpha = 3 */
    kSameData,   /* point 1 again: alpha = 0 */
    kNewW,       /* point 2, a new W with the same values */
    kNewMu,      /* point 2, mu changed in place */
    kStepOneCut, /* point 2; the callback stopped step 1 after one iteration */
    kOwnStart,   /* point 2, from the caller's r = 0 */
    kRolling     /* point 2 of a rolling problem */
} change;

/* The callback stops the solve at its first iteration while *stop is set. */
static int stop_when_asked(void *stop, int64_t iteration, double error, double elapsed) {
    (void)error, (void)elapsed;
    return *(const int *)stop && iteration >= 1;
}

/* Steps 0 .. kSteps-1 (points 0 .. 4, the change at step 2) with `solver` at 1e-10 and
 * secant_start = secant; each step's r and iterations written out. */
static void run_steps(int solver, int secant, change what, double r_out[kSteps][kMaxRows], int64_t its[kSteps]) {
    const int dim = what == kRolling ? 5 : 3, rows = dim * kContacts;
    frix_matrix *W = make_w(rows), *W_again = make_w(rows);
    double q[kMaxRows], mu[kContacts] = {0.5, 0.5, 0.5, 0.5}, mu_r[kContacts] = {0.1, 0.1, 0.1, 0.1};
    double r[kMaxRows] = {0}, u[kMaxRows];
    q_on_line(0.0, dim, q);
    frix_problem *p = NULL;
    if (what == kRolling)
        ck_assert_int_eq(frix_problem_rolling_local(W, q, mu, mu_r, kContacts, &p), FRIX_OK);
    else
        ck_assert_int_eq(frix_problem_local(W, q, mu, kContacts, &p), FRIX_OK);
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(solver, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 1e-10), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_SECANT_START, secant), FRIX_OK);
    int stop = 0;
    ck_assert_int_eq(frix_options_set_callback(o, stop_when_asked, &stop), FRIX_OK);
    frix_persistent *ps = NULL;
    ck_assert_int_eq(frix_persistent_create(p, o, &ps), FRIX_OK);
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    static const double kPoint[] = {0.0, 1.0, 2.0, 3.0, 4.0};
    for (int k = 0; k < kSteps; ++k) {
        double t = kPoint[k];
        if (k == 2 && what == kBack) t = 0.0;
        if (k == 2 && what == kFarAlong) t = 4.0;
        if (k == 2 && what == kSameData) t = 1.0;
        q_on_line(t, dim, q);  /* in place: the persistent solver borrows q */
        if (k == 2 && what == kOffLine) q[0] -= 0.05;
        if (k == 2 && what == kNewW) ck_assert_int_eq(frix_persistent_update_local(ps, W_again, NULL, NULL), FRIX_OK);
        if (k == 2 && what == kNewMu) mu[1] = 0.6;
        if (k == 2 && what == kOwnStart) memset(r, 0, sizeof r);
        stop = k == 1 && what == kStepOneCut;
        ck_assert_int_eq(frix_persistent_solve(ps, r, u, NULL, info), FRIX_OK);
        ck_assert_int_eq(frix_info_status(info), stop ? FRIX_STATUS_STOPPED_BY_CALLBACK : FRIX_STATUS_CONVERGED);
        memcpy(r_out[k], r, sizeof r);
        its[k] = frix_info_iterations(info);
    }
    frix_info_free(info);
    frix_persistent_free(ps);
    frix_options_free(o);
    frix_problem_free(p);
    frix_matrix_free(W);
    frix_matrix_free(W_again);
}

/* The solvers of local problems the sequence is run with. */
static const int kSolvers[] = {FRIX_SOLVER_NSGS, FRIX_SOLVER_NSN_AC, FRIX_SOLVER_PROX, FRIX_SOLVER_ADMM,
                               FRIX_SOLVER_IPM, FRIX_SOLVER_AUTO};

/* Along the line (forward, or back to its first point) the contacts keep sticking: the secant
 * start is step 2's answer up to the last two answers' errors, so step 2 takes fewer
 * iterations than from the last answer, and the next steps no more. Every solver. */
static void on_the_line(int solver, change what) {
    double on[kSteps][kMaxRows], off[kSteps][kMaxRows];
    int64_t its_on[kSteps], its_off[kSteps];
    run_steps(solver, 1, what, on, its_on);
    run_steps(solver, 0, what, off, its_off);
    for (int k = 0; k < 2; ++k) {
        ck_assert_int_eq(its_on[k], its_off[k]);
        ck_assert_mem_eq(on[k], off[k], sizeof on[k]);
    }
    ck_assert_int_gt(its_off[2], 0);
    ck_assert_int_lt(its_on[2], its_off[2]);
    /* NSGS's answers lie far inside the tolerance: their secant meets it as it is. */
    if (solver == FRIX_SOLVER_NSGS) ck_assert_int_eq(its_on[2], 0);
    for (int k = 3; k < kSteps; ++k) ck_assert_int_le(its_on[k], its_off[k]);
    for (int k = 2; k < kSteps; ++k)
        for (int i = 0; i < 3 * kContacts; ++i) ck_assert_double_le(fabs(on[k][i] - off[k][i]), 1e-7);
}

START_TEST(test_on_the_line) { on_the_line(kSolvers[_i], kOnLine); }
END_TEST

START_TEST(test_back_along_the_line) { on_the_line(FRIX_SOLVER_NSGS, kBack); }
END_TEST

/* Where the start is not the secant's to choose, step 2 is solved as with secant_start = 0,
 * to the bit. */
static const change kLeftAlone[] = {kOffLine, kFarAlong, kSameData, kNewW, kNewMu, kStepOneCut, kOwnStart, kRolling};

START_TEST(test_start_left_alone) {
    const int solver = kLeftAlone[_i] == kRolling ? FRIX_SOLVER_ROLLING_NSGS : FRIX_SOLVER_NSGS;
    double on[kSteps][kMaxRows], off[kSteps][kMaxRows];
    int64_t its_on[kSteps], its_off[kSteps];
    run_steps(solver, 1, kLeftAlone[_i], on, its_on);
    run_steps(solver, 0, kLeftAlone[_i], off, its_off);
    if (kLeftAlone[_i] != kSameData) ck_assert_int_gt(its_on[2], 0);
    ck_assert_int_eq(its_on[2], its_off[2]);
    ck_assert_mem_eq(on[2], off[2], sizeof on[2]);
    if (kLeftAlone[_i] == kRolling) ck_assert_mem_eq(on, off, sizeof on);
}
END_TEST

/* A refused call (u NULL) hands the caller's r back and keeps the history: the retry starts
 * from the secant. A solver used without info (NULL) keeps its history too. */
START_TEST(test_refused_call_and_no_info) {
    frix_matrix *W = make_w(3 * kContacts);
    double q[3 * kContacts], mu[kContacts] = {0.5, 0.5, 0.5, 0.5}, r[3 * kContacts] = {0}, u[3 * kContacts];
    q_on_line(0.0, 3, q);
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_problem_local(W, q, mu, kContacts, &p), FRIX_OK);
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_NSGS, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 1e-10), FRIX_OK);
    frix_persistent *ps = NULL;
    ck_assert_int_eq(frix_persistent_create(p, o, &ps), FRIX_OK);
    for (int k = 0; k < 2; ++k) {
        q_on_line(k, 3, q);
        ck_assert_int_eq(frix_persistent_solve(ps, r, u, NULL, NULL), FRIX_OK);
    }
    q_on_line(2.0, 3, q);
    double given[3 * kContacts];
    memcpy(given, r, sizeof r);
    ck_assert_int_eq(frix_persistent_solve(ps, r, NULL, NULL, NULL), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_mem_eq(r, given, sizeof r);
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_persistent_solve(ps, r, u, NULL, info), FRIX_OK);
    ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_CONVERGED);
    ck_assert_int_eq(frix_info_iterations(info), 0);
    frix_info_free(info);
    frix_persistent_free(ps);
    frix_options_free(o);
    frix_problem_free(p);
    frix_matrix_free(W);
}
END_TEST

/* An elastic grid whose nodes stick, slide and separate (global form, auto at 1e-8): its load
 * f raised by 2 % a step and its gaps w widened by 1 % a step. Every step converges with either
 * setting, to answers within the tolerance (frix_problem_error of r and v), the secant start's
 * steps 2-5 in fewer iterations altogether; where w leaves the line at step 2 while f stays on
 * it, step 2 is that of secant_start = 0, to the bit. */
static void grid_steps(int secant, int w_off_line, double *r2, int64_t *its_after) {
    frix_elastic_grid g;
    ck_assert_int_eq(frix_elastic_grid_make(10, 10, 3, 0.5, 1e4, &g), FRIX_OK);
    const int64_t nc = 100, m = 3 * nc, n = 3 * 10 * 10 * 3;
    double *f0 = malloc(sizeof *f0 * (size_t)n), *w0 = malloc(sizeof *w0 * (size_t)m);
    double *r = calloc((size_t)m, sizeof *r), *u = malloc(sizeof *u * (size_t)m), *v = malloc(sizeof *v * (size_t)n);
    memcpy(f0, g.f, sizeof *f0 * (size_t)n);
    memcpy(w0, g.w, sizeof *w0 * (size_t)m);
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_AUTO, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_SECANT_START, secant), FRIX_OK);
    frix_persistent *ps = NULL;
    ck_assert_int_eq(frix_persistent_create(g.problem, o, &ps), FRIX_OK);
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    *its_after = 0;
    for (int k = 0; k < 6; ++k) {
        for (int64_t i = 0; i < n; ++i) g.f[i] = (1.0 + 0.02 * k) * f0[i];
        for (int64_t i = 0; i < m; ++i) g.w[i] = (1.0 + 0.01 * k) * w0[i];
        if (k == 2 && w_off_line) g.w[0] += 0.05;
        ck_assert_int_eq(frix_persistent_solve(ps, r, u, v, info), FRIX_OK);
        ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_CONVERGED);
        double e = 0.0;
        ck_assert_int_eq(frix_problem_error(g.problem, r, v, &e), FRIX_OK);
        ck_assert_double_le(e, 1e-8);
        if (k == 2) memcpy(r2, r, sizeof *r * (size_t)m);
        if (k >= 2) *its_after += frix_info_iterations(info);
    }
    frix_info_free(info);
    frix_persistent_free(ps);
    frix_options_free(o);
    free(f0), free(w0), free(r), free(u), free(v);
    frix_elastic_grid_free(&g);
}

START_TEST(test_load_path_of_a_grid) {
    double on[300], off[300];
    int64_t its_on = 0, its_off = 0;
    grid_steps(1, 0, on, &its_on);
    grid_steps(0, 0, off, &its_off);
    ck_assert_int_lt(its_on, its_off);
    grid_steps(1, 1, on, &its_on);
    grid_steps(0, 1, off, &its_off);
    ck_assert_mem_eq(on, off, sizeof on);
}
END_TEST

/* M scaled by `scale`: a new matrix of the same pattern. */
static frix_matrix *scaled_matrix(const frix_matrix *M, int64_t n, double scale) {
    int64_t nnz = 0;
    ck_assert_int_eq(frix_matrix_to_csc(M, &nnz, NULL, NULL, NULL), FRIX_OK);
    int64_t *colptr = malloc(sizeof *colptr * (size_t)(n + 1)), *rowind = malloc(sizeof *rowind * (size_t)nnz);
    double *val = malloc(sizeof *val * (size_t)nnz);
    ck_assert_int_eq(frix_matrix_to_csc(M, &nnz, colptr, rowind, val), FRIX_OK);
    for (int64_t e = 0; e < nnz; ++e) val[e] *= scale;
    frix_matrix *out = NULL;
    ck_assert_int_eq(frix_matrix_from_csc(n, n, colptr, rowind, val, &out), FRIX_OK);
    free(colptr), free(rowind), free(val);
    return out;
}

/* A persistent solver on a deformable body answers a load that combines earlier ones from
 * their answers (M's factor keeps them). At step 1 M is replaced by 2 M and f raised 10 %: the
 * load solved with the old M is forgotten, and the step's (r, v) are a one-shot solve's, to its
 * tolerance. */
START_TEST(test_loads_forgotten_with_m) {
    frix_elastic_grid g;
    ck_assert_int_eq(frix_elastic_grid_make(10, 10, 3, 0.5, 1e4, &g), FRIX_OK);
    const int64_t nc = 100, m = 3 * nc, n = 3 * 10 * 10 * 3;
    double *f0 = malloc(sizeof *f0 * (size_t)n), *r = calloc((size_t)m, sizeof *r), *u = malloc(sizeof *u * (size_t)m);
    double *v = malloc(sizeof *v * (size_t)n), *r1 = calloc((size_t)m, sizeof *r1), *v1 = malloc(sizeof *v1 * (size_t)n);
    memcpy(f0, g.f, sizeof *f0 * (size_t)n);
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_AUTO, &o), FRIX_OK);
    frix_persistent *ps = NULL;
    ck_assert_int_eq(frix_persistent_create(g.problem, o, &ps), FRIX_OK);
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    frix_matrix *M2 = scaled_matrix(g.M, n, 2.0);
    for (int k = 0; k < 2; ++k) {
        for (int64_t i = 0; i < n; ++i) g.f[i] = (1.0 + 0.1 * k) * f0[i];
        if (k == 1) ck_assert_int_eq(frix_persistent_update_global(ps, M2, NULL, NULL, NULL, NULL), FRIX_OK);
        ck_assert_int_eq(frix_persistent_solve(ps, r, u, v, info), FRIX_OK);
        ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_CONVERGED);
    }
    frix_problem *p2 = NULL;
    ck_assert_int_eq(frix_problem_global(M2, g.H, g.f, g.w, g.mu, nc, &p2), FRIX_OK);
    ck_assert_int_eq(frix_solve(p2, o, r1, u, v1, info), FRIX_OK);
    ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_CONVERGED);
    double dv = 0.0, size = 0.0;
    for (int64_t i = 0; i < n; ++i) dv = fmax(dv, fabs(v[i] - v1[i])), size = fmax(size, fabs(v1[i]));
    ck_assert_double_le(dv, 1e-6 * size);
    double e = 0.0;
    ck_assert_int_eq(frix_problem_error(p2, r, v, &e), FRIX_OK);
    ck_assert_double_le(e, 1e-8);
    frix_problem_free(p2);
    frix_matrix_free(M2);
    frix_info_free(info);
    frix_persistent_free(ps);
    frix_options_free(o);
    free(f0), free(r), free(u), free(v), free(r1), free(v1);
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
    tcase_add_loop_test(tc, test_on_the_line, 0, (int)(sizeof kSolvers / sizeof *kSolvers));
    tcase_add_test(tc, test_back_along_the_line);
    tcase_add_loop_test(tc, test_start_left_alone, 0, (int)(sizeof kLeftAlone / sizeof *kLeftAlone));
    tcase_add_test(tc, test_refused_call_and_no_info);
    tcase_add_test(tc, test_load_path_of_a_grid);
    tcase_add_test(tc, test_loads_forgotten_with_m);
    tcase_add_test(tc, test_option);
    suite_add_tcase(s, tc);
    return frix_run_suite(s);
}
