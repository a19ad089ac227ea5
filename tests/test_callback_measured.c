/* Option callback_estimates = 0: every error the callback sees is the error of an iterate.
 * Each (iteration k, error) the callback saw is checked against a run of the same solver
 * from the same start stopped after k iterations, whose answer the driver measures: the runs
 * are deterministic, so that answer is the iterate the callback was told about. With the
 * default (1), NSGS's light errors between its full checks fail the same comparison. */
#include <frix/frix.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check_main.h"
#include "shared_data.h"

enum { kMaxCalls = 4096 };

typedef struct {
    int64_t calls;
    int64_t iteration[kMaxCalls];
    double error[kMaxCalls];
} progress_log;

static int record(void *data, int64_t iteration, double error, double elapsed) {
    (void)elapsed;
    progress_log *log = data;
    if (log->calls < kMaxCalls) {
        log->iteration[log->calls] = iteration;
        log->error[log->calls] = error;
    }
    ++log->calls;
    return 0;
}

static frix_options *options_for(int solver, double tol, int64_t max_iter) {
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(solver, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, tol), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_MAX_ITER, max_iter), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_EXISTENCE_CHECK, 0), FRIX_OK);
    return o;
}

/* The error of the answer of `solver` from r = 0 (v = 0) after at most max_iter iterations;
 * with log, the callback's calls under callback_estimates = estimates. *iterations: done. */
static double run(const frix_problem *p, int solver, double tol, int64_t max_iter, progress_log *log, int estimates,
                  int64_t *iterations) {
    frix_options *o = options_for(solver, tol, max_iter);
    if (log) {
        log->calls = 0;
        ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_CALLBACK_ESTIMATES, estimates), FRIX_OK);
        ck_assert_int_eq(frix_options_set_callback(o, record, log), FRIX_OK);
    }
    const int64_t m = frix_problem_contact_dofs(p), n = frix_problem_dofs(p);
    double *r = calloc((size_t)m + 1, sizeof *r), *u = calloc((size_t)m + 1, sizeof *u);
    double *v = calloc((size_t)n + 1, sizeof *v);
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_solve(p, o, r, u, n > 0 ? v : NULL, info), FRIX_OK);
    const double error = frix_info_error(info);
    if (iterations) *iterations = frix_info_iterations(info);
    frix_info_free(info);
    free(r);
    free(u);
    free(v);
    frix_options_free(o);
    return error;
}

static int same(double a, double b) { return fabs(a - b) <= 1e-9 * b; }

/* How many of (at most `checks`, spread over the log) reported errors differ from the error
 * of the answer stopped at their iteration by more than a relative 1e-9: that answer is the
 * iterate told about, or the best one told about so far (a solver that keeps its best). */
static int mismatches(const frix_problem *p, int solver, double tol, const progress_log *log, int checks) {
    int bad = 0;
    const int64_t calls = log->calls < kMaxCalls ? log->calls : kMaxCalls;
    const int64_t stride = calls > checks ? calls / checks : 1;
    double best = INFINITY;
    for (int64_t i = 0; i < calls; ++i) {
        const double told = log->error[i];
        if (told < best) best = told;
        const int64_t k = log->iteration[i];
        if (i % stride != 0 || k < 1) continue; /* k = 0: forming W, at the start */
        const double got = run(p, solver, tol, k, NULL, 1, NULL);
        if (!same(got, told) && !same(got, best)) ++bad;
    }
    return bad;
}

static void check_measured_only(const char *file, int solver, double tol, int64_t max_iter) {
    frix_problem *p = load(file);
    if (!p) return;
    progress_log *measured = calloc(1, sizeof *measured), *all = calloc(1, sizeof *all);
    int64_t iterations = 0;
    run(p, solver, tol, max_iter, all, 1, &iterations);
    run(p, solver, tol, max_iter, measured, 0, NULL);
    ck_assert_int_gt(measured->calls, 1);
    ck_assert_int_lt(measured->calls, all->calls);
    ck_assert_int_le(all->calls, kMaxCalls);
    ck_assert_int_eq(mismatches(p, solver, tol, measured, 8), 0);
    if (solver == FRIX_SOLVER_NSGS) ck_assert_int_gt(mismatches(p, solver, tol, all, 8), 0);
    free(measured);
    free(all);
    frix_problem_free(p);
}

START_TEST(nsgs_reports_its_full_checks) {
    check_measured_only("local/Capsules-i125-1213.hdf5", FRIX_SOLVER_NSGS, 1e-12, 300);
}
END_TEST

START_TEST(admm_reports_its_full_checks) {
    check_measured_only("local/Capsules-i125-1213.hdf5", FRIX_SOLVER_ADMM, 1e-12, 300);
}
END_TEST

START_TEST(gadmm_reports_its_full_checks) {
    check_measured_only("global/LMGC_GFC3D-i00501-4-00000.hdf5", FRIX_SOLVER_GLOBAL_ADMM, 1e-12, 300);
}
END_TEST

/* auto's stages are checked against their own log (verbosity 3: NSGS's full checks, Newton's
 * steps): its budgets depend on max_iter, so a shorter run is another run. */
enum { kMaxLogged = 4096 };

typedef struct {
    int64_t count;
    double value[kMaxLogged];
} logged_errors;

/* Keeps the number after each " full " and " error " of a stage's line (NSGS's sweeps,
 * Newton's steps; printed with 4 digits). */
static void keep_errors(void *data, const char *line) {
    logged_errors *log = data;
    if (strncmp(line, "nsgs", 4) != 0 && strncmp(line, "newton: step", 12) != 0) return;
    const char *const marks[] = {" full ", " error "};
    for (int k = 0; k < 2; ++k)
        for (const char *at = strstr(line, marks[k]); at; at = strstr(at + 1, marks[k])) {
            char *end = NULL;
            const double v = strtod(at + strlen(marks[k]), &end);
            if (end != at + strlen(marks[k]) && log->count < kMaxLogged) log->value[log->count++] = v;
        }
}

/* How many of the callback's errors are none of the errors the stages logged. */
static int64_t unlogged(const frix_problem *p, int estimates) {
    progress_log *calls = calloc(1, sizeof *calls);
    logged_errors *logged = calloc(1, sizeof *logged);
    frix_options *o = options_for(FRIX_SOLVER_AUTO, 1e-12, 300);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_CALLBACK_ESTIMATES, estimates), FRIX_OK);
    ck_assert_int_eq(frix_options_set_callback(o, record, calls), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_VERBOSITY, 3), FRIX_OK);
    ck_assert_int_eq(frix_options_set_log(o, keep_errors, logged), FRIX_OK);
    const int64_t m = frix_problem_contact_dofs(p);
    double *r = calloc((size_t)m + 1, sizeof *r), *u = calloc((size_t)m + 1, sizeof *u);
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_solve(p, o, r, u, NULL, info), FRIX_OK);
    ck_assert_int_gt(calls->calls, 1);
    ck_assert_int_le(calls->calls, kMaxCalls);
    ck_assert_int_lt(logged->count, kMaxLogged);
    int64_t missing = 0;
    for (int64_t i = 0; i < calls->calls; ++i) {
        int found = 0;
        for (int64_t j = 0; j < logged->count && !found; ++j)
            found = fabs(calls->error[i] - logged->value[j]) <= 1e-3 * logged->value[j];
        missing += !found;
    }
    frix_info_free(info);
    free(r);
    free(u);
    frix_options_free(o);
    free(logged);
    free(calls);
    return missing;
}

START_TEST(auto_reports_its_stages_measured_errors) {
    /* One island: on a problem of several, a part's errors are its own, estimates of the whole's. */
    frix_problem *p = load("local/LMGC_100_PR_PerioBox-i00361-60-03000.hdf5");
    if (!p) return;
    ck_assert_int_eq(unlogged(p, 0), 0);
    ck_assert_int_gt(unlogged(p, 1), 0);
    frix_problem_free(p);
}
END_TEST

/* The iteration that converges is told too, with the answer's error. */
static void check_last_told(const char *file, int solver, double tol) {
    frix_problem *p = load(file);
    if (!p) return;
    progress_log *log = calloc(1, sizeof *log);
    int64_t iterations = 0;
    const double error = run(p, solver, tol, 1000, log, 0, &iterations);
    ck_assert_double_le(error, tol);
    ck_assert_int_ge(log->calls, 1);
    ck_assert_int_le(log->calls, kMaxCalls);
    ck_assert_int_eq(log->iteration[log->calls - 1], iterations);
    ck_assert(same(log->error[log->calls - 1], error));
    free(log);
    frix_problem_free(p);
}

START_TEST(converged_iteration_is_told) {
    check_last_told("local/Capsules-i125-1213.hdf5", FRIX_SOLVER_ADMM, 1e-6);
    check_last_told("global/LMGC_GFC3D-i00501-4-00000.hdf5", FRIX_SOLVER_GLOBAL_ADMM, 1e-6);
}
END_TEST

START_TEST(option_is_common_and_checked) {
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_NSGS, &o), FRIX_OK);
    int64_t value = -1;
    ck_assert_int_eq(frix_options_get_int(o, FRIX_OPT_CALLBACK_ESTIMATES, &value), FRIX_OK);
    ck_assert_int_eq(value, 1);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_CALLBACK_ESTIMATES, 2), FRIX_ERR_OPTION_RANGE);
    ck_assert_int_eq(frix_options_set_by_name(o, "callback_estimates", "0"), FRIX_OK);
    ck_assert_int_eq(frix_options_get_int(o, FRIX_OPT_CALLBACK_ESTIMATES, &value), FRIX_OK);
    ck_assert_int_eq(value, 0);
    frix_options_free(o);
}
END_TEST

static Suite *suite(void) {
    Suite *s = suite_create("callback_measured");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, option_is_common_and_checked);
    tcase_add_test(tc, nsgs_reports_its_full_checks);
    tcase_add_test(tc, admm_reports_its_full_checks);
    tcase_add_test(tc, gadmm_reports_its_full_checks);
    tcase_add_test(tc, auto_reports_its_stages_measured_errors);
    tcase_add_test(tc, converged_iteration_is_told);
    suite_add_tcase(s, tc);
    return s;
}

int main(void) { return frix_run_suite(suite()); }
