/* rolling-nsn (the semismooth Newton of rolling friction) and auto's rolling route: Newton's
 * answer against rolling-nsgs's on a problem with a unique solution, both forms of a sphere
 * stack, auto reaching a tolerance the sweeps alone miss within the same iterations, statuses
 * that never claim a convergence the measure denies, the memory limit, and the existence
 * check's verdicts on rolling problems. */
#include <frix/frix.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check_main.h"
#include "frix_testing.h"
#include "support/lcg.h"
#include "support/rolling_pile.h"

/* A chain of nc contacts, W = (tridiag(-1, 2, -1) (x) I_5) + eps I (symmetric positive
 * definite: one solution), every contact pressed (q_N = -1) and pushed a little sideways and
 * turned (pseudo-random q_T, q_R): the sweeps need of the order of nc^2 sweeps, Newton about
 * ten steps. */
typedef struct {
    int64_t nc;
    frix_matrix *W;
    double *q, *mu, *mu_r;
    frix_problem *p;
} chain;

static void chain_make(int64_t nc, double eps, chain *c) {
    const int64_t m = 5 * nc;
    c->nc = nc;
    int64_t nnz = 0, *ri = malloc((size_t)(15 * nc) * sizeof(int64_t));
    int64_t *ci = malloc((size_t)(15 * nc) * sizeof(int64_t));
    double *x = malloc((size_t)(15 * nc) * sizeof(double));
    for (int64_t i = 0; i < m; ++i) {
        ri[nnz] = i, ci[nnz] = i, x[nnz++] = 2.0 + eps;
        if (i + 5 < m) ri[nnz] = i, ci[nnz] = i + 5, x[nnz++] = -1.0;
        if (i >= 5) ri[nnz] = i, ci[nnz] = i - 5, x[nnz++] = -1.0;
    }
    ck_assert_int_eq(frix_matrix_from_triplets(m, m, nnz, ri, ci, x, &c->W), FRIX_OK);
    free(ri), free(ci), free(x);
    c->q = malloc((size_t)m * sizeof(double));
    c->mu = malloc((size_t)nc * sizeof(double));
    c->mu_r = malloc((size_t)nc * sizeof(double));
    uint64_t s = 12345;
    for (int64_t i = 0; i < m; ++i) c->q[i] = i % 5 == 0 ? -1.0 : 0.1 * (lcg_uniform(&s) - 0.5);
    for (int64_t a = 0; a < nc; ++a) c->mu[a] = 0.3, c->mu_r[a] = 0.05;
    ck_assert_int_eq(frix_problem_rolling_local(c->W, c->q, c->mu, c->mu_r, nc, &c->p), FRIX_OK);
}

static void chain_free(chain *c) {
    frix_problem_free(c->p);
    frix_matrix_free(c->W);
    free(c->q), free(c->mu), free(c->mu_r);
}

typedef struct {
    frix_status status;
    int64_t iterations;
    double error;
} run;

/* Solves p with solver from r (5 nc entries; updated), the status checked against the
 * measure: converged never above the tolerance. */
static run solve(frix_problem *p, int solver, double tol, int64_t max_iter, double *r, int64_t nc, int64_t n,
                 frix_info *info) {
    double *u = calloc((size_t)(5 * nc), sizeof(double)), *v = n > 0 ? calloc((size_t)n, sizeof(double)) : NULL;
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(solver, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, tol), FRIX_OK);
    if (max_iter > 0) ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_MAX_ITER, max_iter), FRIX_OK);
    ck_assert_int_eq(frix_solve(p, o, r, u, v, info), FRIX_OK);
    run out = {frix_info_status(info), frix_info_iterations(info), frix_info_error(info)};
    frix_info *check = NULL;
    ck_assert_int_eq(frix_info_create(&check), FRIX_OK);
    ck_assert_int_eq(frix_problem_measure(p, r, v, NULL, check), FRIX_OK);
    double again = NAN;
    ck_assert_int_eq(frix_info_get_double(check, FRIX_INFO_ERROR_SCALED, &again), FRIX_OK);
    ck_assert_double_eq_tol(again, out.error, 1e-12 + 1e-9 * out.error);
    if (out.status == FRIX_STATUS_CONVERGED) ck_assert_double_le(out.error, tol);
    else ck_assert_double_gt(out.error, tol);
    frix_info_free(check);
    frix_options_free(o);
    free(u), free(v);
    return out;
}

START_TEST(test_newton_agrees_with_nsgs) {
    chain c;
    chain_make(30, 1e-2, &c);
    const int64_t m = 5 * c.nc;
    double *rn = calloc((size_t)m, sizeof(double)), *rg = calloc((size_t)m, sizeof(double));
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    const run newton = solve(c.p, FRIX_SOLVER_ROLLING_NSN, 1e-10, 0, rn, c.nc, 0, info);
    ck_assert_int_eq(newton.status, FRIX_STATUS_CONVERGED);
    ck_assert_int_le(newton.iterations, 30);
    const run gs = solve(c.p, FRIX_SOLVER_ROLLING_NSGS, 1e-12, 100000, rg, c.nc, 0, info);
    ck_assert_int_eq(gs.status, FRIX_STATUS_CONVERGED);
    /* W is positive definite: one solution, which both found. */
    double d2 = 0.0, r2 = 0.0, moment = 0.0;
    for (int64_t i = 0; i < m; ++i) d2 += (rn[i] - rg[i]) * (rn[i] - rg[i]), r2 += rg[i] * rg[i];
    for (int64_t a = 0; a < c.nc; ++a) moment = fmax(moment, hypot(rn[5 * a + 3], rn[5 * a + 4]));
    ck_assert_double_le(sqrt(d2), 1e-7 * sqrt(r2));
    ck_assert_double_gt(moment, 0.0);  /* the rolling moments take part */
    frix_info_free(info);
    free(rn), free(rg);
    chain_free(&c);
}
END_TEST

/* A sphere stack in both forms (the global one reduced body by body), and the same answer. */
START_TEST(test_newton_on_a_stack) {
    rolling_pile pile;
    ck_assert_int_eq(rolling_pile_make(2, 2, 0.3, 0.02, 5, &pile), 0);
    const int64_t m = 5 * pile.nc;
    double *rl = calloc((size_t)m, sizeof(double)), *rg = calloc((size_t)m, sizeof(double));
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    const run local = solve(pile.local, FRIX_SOLVER_ROLLING_NSN, 1e-8, 0, rl, pile.nc, 0, info);
    const run global = solve(pile.global, FRIX_SOLVER_ROLLING_NSN, 1e-8, 0, rg, pile.nc, pile.n, info);
    ck_assert_int_eq(local.status, FRIX_STATUS_CONVERGED);
    ck_assert_int_eq(global.status, FRIX_STATUS_CONVERGED);
    frix_info_free(info);
    free(rl), free(rg);
    rolling_pile_free(&pile);
}
END_TEST

/* Within the same iterations, the sweeps alone stop short of 1e-8 and auto (sweeps, then the
 * Newton polish) gets there, its trace showing both. */
START_TEST(test_auto_polishes) {
    chain c;
    chain_make(400, 1e-5, &c);
    const int64_t m = 5 * c.nc, budget = 600;
    double *r = calloc((size_t)m, sizeof(double));
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    const run gs = solve(c.p, FRIX_SOLVER_ROLLING_NSGS, 1e-8, budget, r, c.nc, 0, info);
    ck_assert_int_eq(gs.status, FRIX_STATUS_MAX_ITER);
    memset(r, 0, (size_t)m * sizeof(double));
    const run au = solve(c.p, FRIX_SOLVER_AUTO, 1e-8, budget, r, c.nc, 0, info);
    ck_assert_int_eq(au.status, FRIX_STATUS_CONVERGED);
    ck_assert_int_le(au.iterations, budget);
    ck_assert_ptr_nonnull(strstr(frix_info_trace(info), "rolling-nsgs"));
    ck_assert_ptr_nonnull(strstr(frix_info_trace(info), "rolling-nsn"));
    frix_info_free(info);
    free(r);
    chain_free(&c);
}
END_TEST

/* auto's watch over the rolling polish (Watch::Newton): steps that creep (each lowering the best
 * error by less than a tenth: damped steps on a settled pile, about 1 % each) end it after the
 * patience, and so do errors that are not finite; steps that gain do not, nor do a stage's
 * estimates (an inner problem's errors) once it reports measured ones. */
START_TEST(test_newton_watch_stops_a_creeping_polish) {
    const double creep[6] = {6.24e-5, 6.23e-5, 6.16e-5, 6.10e-5, 5.98e-5, 5.92e-5};
    const int estimates[6] = {0, 0, 0, 0, 0, 0};
    ck_assert_int_eq(frix_testing_newton_watch(creep, estimates, 6, 3), 3);
    ck_assert_int_eq(frix_testing_newton_watch(creep, estimates, 6, 6), -1);
    const double gains[6] = {3.4e-1, 8.8e-2, 4.0e-3, 1.9e-5, 9.0e-9, 1.0e-12};
    ck_assert_int_eq(frix_testing_newton_watch(gains, estimates, 6, 1), -1);
    /* measured errors that gain, tiny estimates between them */
    const double mixed[8] = {2.6e-12, 3.4e-1, 1.8e-12, 1.5e-1, 1.7e-12, 6.0e-2, 1.6e-12, 1.0e-2};
    const int kinds[8] = {0, 1, 0, 1, 0, 1, 0, 1};
    ck_assert_int_eq(frix_testing_newton_watch(mixed, kinds, 8, 2), -1);
    /* a restart that undoes the progress counts as slow */
    const double undone[5] = {1e-4, 4e-5, 4.1e-5, 4.05e-5, 3.99e-5};
    const int measured[5] = {1, 1, 1, 1, 1};
    ck_assert_int_eq(frix_testing_newton_watch(undone, measured, 5, 3), 4);
    /* errors that are not finite are slow steps too */
    const double nans[3] = {NAN, NAN, NAN};
    ck_assert_int_eq(frix_testing_newton_watch(nans, measured, 3, 2), 1);
}
END_TEST

/* Cut short (iterations), each solver says so, never converged above the tolerance (solve()
 * checks the status against the measure), and within the iterations it was given. */
START_TEST(test_status_follows_the_measure) {
    chain c;
    chain_make(100, 1e-4, &c);
    const int64_t m = 5 * c.nc;
    double *r = calloc((size_t)m, sizeof(double));
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    const int solvers[3] = {FRIX_SOLVER_ROLLING_NSN, FRIX_SOLVER_ROLLING_NSGS, FRIX_SOLVER_AUTO};
    const int64_t limits[4] = {1, 2, 5, 0};
    for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 4; ++j) {
            memset(r, 0, (size_t)m * sizeof(double));
            const run out = solve(c.p, solvers[k], 1e-12, limits[j], r, c.nc, 0, info);
            if (limits[j] == 1) ck_assert_int_ne(out.status, FRIX_STATUS_CONVERGED);
            if (limits[j] > 0) ck_assert_int_le(out.iterations, limits[j]);  /* auto's stages share them */
        }
    frix_info_free(info);
    free(r);
    chain_free(&c);
}
END_TEST

/* A memory limit the factorisation would exceed stops Newton before it, with its status. */
START_TEST(test_memory_limit) {
    chain c;
    chain_make(200, 1e-3, &c);
    const int64_t m = 5 * c.nc;
    double *r = calloc((size_t)m, sizeof(double)), *u = calloc((size_t)m, sizeof(double));
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_ROLLING_NSN, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_MEMORY_LIMIT, 1.0), FRIX_OK);
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_solve(c.p, o, r, u, NULL, info), FRIX_OK);
    ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_MEMORY_LIMIT);
    for (int64_t i = 0; i < m; ++i) ck_assert(isfinite(r[i]));
    frix_info_free(info);
    frix_options_free(o);
    free(r), free(u);
    chain_free(&c);
}
END_TEST

static void collect_line(void *data, const char *line) {
    char *log = data;
    strncat(log, line, 4095 - strlen(log));
    strncat(log, "\n", 4095 - strlen(log));
}

/* rolling-nsn under the limit `key` = `limit` that its first factorisation would overrun, on the
 * global form (W's pattern from the bodies) and on the local one (W given): it stops before it
 * allocates W's values or the Jacobian (status `status`, no step, r untouched, its log line
 * naming the limit in `says`). */
static void check_refused_before_w(frix_option_key key, double limit, frix_status status, const char *says) {
    rolling_pile pile;
    ck_assert_int_eq(rolling_pile_make(4, 3, 0.3, 0.02, 5, &pile), 0);
    chain c;
    chain_make(200, 1e-3, &c);
    const frix_problem *problems[2] = {pile.global, c.p};
    for (int k = 0; k < 2; ++k) {
        const int64_t m = frix_problem_contact_dofs(problems[k]);
        double *r = calloc((size_t)m, sizeof(double)), *u = calloc((size_t)m, sizeof(double));
        double *v = calloc((size_t)(k == 0 ? frix_problem_dofs(problems[k]) : 1), sizeof(double));
        char log[4096] = "";
        frix_options *o = NULL;
        ck_assert_int_eq(frix_options_create(FRIX_SOLVER_ROLLING_NSN, &o), FRIX_OK);
        ck_assert_int_eq(frix_options_set_double(o, key, limit), FRIX_OK);
        ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_VERBOSITY, 1), FRIX_OK);
        ck_assert_int_eq(frix_options_set_log(o, collect_line, log), FRIX_OK);
        frix_info *info = NULL;
        ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
        ck_assert_int_eq(frix_solve(problems[k], o, r, u, k == 0 ? v : NULL, info), FRIX_OK);
        ck_assert_int_eq(frix_info_status(info), status);
        ck_assert_int_eq(frix_info_iterations(info), 0);
        ck_assert_msg(strstr(log, "rolling-nsn: W and its Newton system need at least"), "%s", log);
        ck_assert_msg(strstr(log, says), "%s", log);
        for (int64_t i = 0; i < m; ++i) ck_assert(r[i] == 0.0);
        ck_assert(isfinite(frix_info_error(info)));
        frix_info_free(info);
        frix_options_free(o);
        free(r), free(u), free(v);
    }
    chain_free(&c);
    rolling_pile_free(&pile);
}

/* Where the memory left cannot hold even the Newton system on W's pattern (a limit of 1 byte). */
START_TEST(test_memory_limit_before_w) {
    check_refused_before_w(FRIX_OPT_MEMORY_LIMIT, 1.0, FRIX_STATUS_MEMORY_LIMIT, "more than the memory left");
}
END_TEST

/* Past the time limit (1 ns), by the price of the first factorisation: as under a memory limit. */
START_TEST(test_time_limit_before_w) {
    check_refused_before_w(FRIX_OPT_TIME_LIMIT, 1e-9, FRIX_STATUS_TIME_LIMIT, "more than the time left");
}
END_TEST

/* On a pile of spheres the LU of the Newton system fills in far beyond W's pattern, and the
 * price counts that fill: a limit above the Jacobian's size but below the counted fill (8 MB on
 * the 704-contact pile) stops the run before W and the Jacobian are formed; a limit that holds
 * the LU (512 MB) lets it run. */
START_TEST(test_memory_price_counts_the_fill) {
    rolling_pile pile;
    ck_assert_int_eq(rolling_pile_make(8, 4, 0.3, 0.02, 5, &pile), 0);
    ck_assert_int_eq(pile.nc, 704);
    const double limits[2] = {8e6, 512e6};
    for (int k = 0; k < 2; ++k) {
        double *r = calloc((size_t)(5 * pile.nc), sizeof(double)), *u = calloc((size_t)(5 * pile.nc), sizeof(double));
        double *v = calloc((size_t)pile.n, sizeof(double));
        char log[4096] = "";
        frix_options *o = NULL;
        ck_assert_int_eq(frix_options_create(FRIX_SOLVER_ROLLING_NSN, &o), FRIX_OK);
        ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_MEMORY_LIMIT, limits[k]), FRIX_OK);
        ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_VERBOSITY, 1), FRIX_OK);
        ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_MAX_ITER, 1), FRIX_OK);
        ck_assert_int_eq(frix_options_set_log(o, collect_line, log), FRIX_OK);
        frix_info *info = NULL;
        ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
        ck_assert_int_eq(frix_solve(pile.global, o, r, u, v, info), FRIX_OK);
        const int refused_before_w = strstr(log, "rolling-nsn: W and its Newton system need at least") != NULL;
        if (k == 0) {
            ck_assert_msg(refused_before_w, "%s", log);
            ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_MEMORY_LIMIT);
            ck_assert_int_eq(frix_info_iterations(info), 0);
        } else {
            ck_assert_msg(!refused_before_w && frix_info_iterations(info) > 0, "%s", log);
        }
        frix_info_free(info);
        frix_options_free(o);
        free(r), free(u), free(v);
    }
    rolling_pile_free(&pile);
}
END_TEST

/* Where the Newton polish may not factorise (a memory limit of 1 byte), auto goes on with the
 * sweeps, which factorise nothing, and converges (it stopped with "memory limit reached"). */
START_TEST(test_auto_sweeps_on_when_newton_is_refused) {
    chain c;
    chain_make(400, 1e-5, &c);
    const int64_t m = 5 * c.nc;
    double *r = calloc((size_t)m, sizeof(double)), *u = calloc((size_t)m, sizeof(double));
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_AUTO, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 1e-8), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_MEMORY_LIMIT, 1.0), FRIX_OK);
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_solve(c.p, o, r, u, NULL, info), FRIX_OK);
    const char *trace = frix_info_trace(info);
    ck_assert_msg(strstr(trace, "rolling-nsn: memory limit reached"), "%s", trace);
    ck_assert_msg(frix_info_status(info) == FRIX_STATUS_CONVERGED && frix_info_error(info) <= 1e-8, "%s, %g\n%s",
                  frix_status_string(frix_info_status(info)), frix_info_error(info), trace);
    frix_info_free(info);
    frix_options_free(o);
    free(r), free(u);
    chain_free(&c);
}
END_TEST

/* The existence check decides a rolling problem only where r = 0 solves it, and otherwise
 * says that it cannot decide (undetermined), in both forms. */
START_TEST(test_existence_verdicts) {
    double W[25] = {0}, q[5] = {0.5, 0.1, 0, 0.01, 0}, mu = 0.3, mu_r = 0.01;
    for (int i = 0; i < 5; ++i) W[i + 5 * i] = 1.0;
    frix_matrix *Wm = NULL;
    ck_assert_int_eq(frix_matrix_from_dense(5, 5, W, 5, &Wm), FRIX_OK);
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_problem_rolling_local(Wm, q, &mu, &mu_r, 1, &p), FRIX_OK);
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    int64_t verdict = -1;
    double margin = NAN;
    ck_assert_int_eq(frix_problem_check_existence(p, 0.0, info), FRIX_OK);
    ck_assert_int_eq(frix_info_get_int(info, FRIX_INFO_EXISTENCE, &verdict), FRIX_OK);
    ck_assert_int_eq(verdict, FRIX_EXISTENCE_GUARANTEED);
    ck_assert_int_eq(frix_info_get_double(info, FRIX_INFO_EXISTENCE_MARGIN, &margin), FRIX_OK);
    ck_assert_double_eq(margin, 0.0);
    rolling_pile pile;
    ck_assert_int_eq(rolling_pile_make(2, 1, 0.3, 0.02, 3, &pile), 0);
    ck_assert_int_eq(frix_problem_check_existence(pile.global, 0.0, info), FRIX_OK);
    ck_assert_int_eq(frix_info_get_int(info, FRIX_INFO_EXISTENCE, &verdict), FRIX_OK);
    ck_assert_int_eq(verdict, FRIX_EXISTENCE_UNDETERMINED);
    /* A failed solve says so too, instead of "not checked". */
    const int64_t m = 5 * pile.nc;
    double *r = calloc((size_t)m, sizeof(double)), *u = calloc((size_t)m, sizeof(double));
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_ROLLING_NSGS, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_MAX_ITER, 1), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 1e-14), FRIX_OK);
    ck_assert_int_eq(frix_solve(pile.local, o, r, u, NULL, info), FRIX_OK);
    ck_assert_int_ne(frix_info_status(info), FRIX_STATUS_CONVERGED);
    ck_assert_int_eq(frix_info_get_int(info, FRIX_INFO_EXISTENCE, &verdict), FRIX_OK);
    ck_assert_int_eq(verdict, FRIX_EXISTENCE_UNDETERMINED);
    frix_options_free(o);
    free(r), free(u);
    rolling_pile_free(&pile);
    frix_info_free(info);
    frix_problem_free(p);
    frix_matrix_free(Wm);
}
END_TEST

int main(void) {
    Suite *s = suite_create("rolling_newton");
    TCase *tc = tcase_create("core");
    tcase_set_timeout(tc, 120);
    tcase_add_test(tc, test_newton_agrees_with_nsgs);
    tcase_add_test(tc, test_newton_on_a_stack);
    tcase_add_test(tc, test_auto_polishes);
    tcase_add_test(tc, test_newton_watch_stops_a_creeping_polish);
    tcase_add_test(tc, test_status_follows_the_measure);
    tcase_add_test(tc, test_memory_limit);
    tcase_add_test(tc, test_auto_sweeps_on_when_newton_is_refused);
    tcase_add_test(tc, test_memory_limit_before_w);
    tcase_add_test(tc, test_memory_price_counts_the_fill);
    tcase_add_test(tc, test_time_limit_before_w);
    tcase_add_test(tc, test_existence_verdicts);
    suite_add_tcase(s, tc);
    return frix_run_suite(s);
}
