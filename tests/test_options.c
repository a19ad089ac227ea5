/* Options by key (defaults, bounds, refusals), the solver registry, version and error strings. */
#define _POSIX_C_SOURCE 200809L /* dup, dup2, fileno */
#include <frix/frix.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "check_main.h"

START_TEST(test_defaults_and_bounds) {
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_NSGS, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_solver(o), FRIX_SOLVER_NSGS);
    double tol;
    ck_assert_int_eq(frix_options_get_double(o, FRIX_OPT_TOLERANCE, &tol), FRIX_OK);
    ck_assert_double_eq(tol, 1e-8);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 1e-10), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, -1.0), FRIX_ERR_OPTION_RANGE);
    ck_assert(strstr(frix_last_error_message(), "tolerance") != NULL);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, NAN), FRIX_ERR_OPTION_RANGE);
    ck_assert_int_eq(frix_options_get_double(o, FRIX_OPT_TOLERANCE, &tol), FRIX_OK);
    ck_assert_double_eq(tol, 1e-10); /* a refused value leaves the previous one */

    int64_t it;
    ck_assert_int_eq(frix_options_get_int(o, FRIX_OPT_LOCAL_SOLVER, &it), FRIX_OK);
    ck_assert_int_eq(it, FRIX_LOCAL_CLOSED_FORM); /* NSGS's own default */
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_MAX_ITER, 0), FRIX_ERR_OPTION_RANGE);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_MAX_ITER, 50), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_MAX_ITER, 2.5), FRIX_ERR_OPTION_RANGE);
    ck_assert_int_eq(frix_options_get_int(o, FRIX_OPT_MAX_ITER, &it), FRIX_OK);
    ck_assert_int_eq(it, 50);
    double itd;
    ck_assert_int_eq(frix_options_get_double(o, FRIX_OPT_MAX_ITER, &itd), FRIX_OK);
    ck_assert_double_eq(itd, 50.0);
    ck_assert_int_eq(frix_options_get_int(o, FRIX_OPT_TOLERANCE, &it), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_RELAXATION, 2.5), FRIX_ERR_OPTION_RANGE);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_VERBOSITY, 4), FRIX_ERR_OPTION_RANGE);
    /* A choice key takes only its defined values, not everything between its bounds. */
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_LOCAL_SOLVER, 555), FRIX_ERR_OPTION_RANGE);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_LOCAL_SOLVER, FRIX_LOCAL_PROJECTION), FRIX_OK);
    ck_assert_int_eq(frix_options_get_int(o, FRIX_OPT_LOCAL_SOLVER, &it), FRIX_OK);
    ck_assert_int_eq(it, 552);
    ck_assert_int_eq(frix_options_set_int(o, (frix_option_key)999, 1), FRIX_ERR_UNKNOWN_OPTION);

    double lo, hi;
    int is_int;
    ck_assert_int_eq(frix_options_bounds(o, FRIX_OPT_SHUFFLE, &lo, &hi, &is_int), FRIX_OK);
    ck_assert_double_eq(lo, 0);
    ck_assert_double_eq(hi, 2);
    ck_assert_int_eq(is_int, 1);

    frix_options *c = NULL;
    ck_assert_int_eq(frix_options_copy(o, &c), FRIX_OK);
    ck_assert_int_eq(frix_options_get_int(c, FRIX_OPT_MAX_ITER, &it), FRIX_OK);
    ck_assert_int_eq(it, 50);
    frix_options_free(c);
    frix_options_free(o);
    frix_options_free(NULL);

    ck_assert_int_eq(frix_options_create(12345, &o), FRIX_ERR_UNKNOWN_SOLVER);
    ck_assert_ptr_null(o);
}
END_TEST

START_TEST(test_option_names) {
    frix_option_key k;
    ck_assert_int_eq(frix_option_by_name("max_iter", &k), FRIX_OK);
    ck_assert_int_eq(k, FRIX_OPT_MAX_ITER);
    ck_assert_str_eq(frix_option_name(FRIX_OPT_TIME_LIMIT), "time_limit");
    ck_assert_int_eq(frix_option_by_name("maxiter", &k), FRIX_ERR_UNKNOWN_OPTION);
    ck_assert_ptr_null(frix_option_name((frix_option_key)0));
}
END_TEST

START_TEST(test_registry) {
    ck_assert_int_ge(frix_solver_count(), 1);
    int found = 0;
    for (int64_t i = 0; i < frix_solver_count(); ++i) {
        int id = frix_solver_id_at(i);
        ck_assert_ptr_nonnull(frix_solver_name(id));
        ck_assert_ptr_nonnull(frix_solver_describe(id));
        if (id == FRIX_SOLVER_NSGS) found = 1;
    }
    ck_assert(found);
    ck_assert_int_eq(frix_solver_id_at(-1), -1);
    ck_assert_int_eq(frix_solver_id_at(frix_solver_count()), -1);
    ck_assert_str_eq(frix_solver_name(FRIX_SOLVER_NSGS), "nsgs");
    ck_assert_ptr_null(frix_solver_name(499));
    const char *names[] = {"nsgs", "NSGS", "FRICTION_3D_NSGS", "fc3d_nsgs", "SICONOS_FRICTION_3D_NSGS", "500"};
    for (int i = 0; i < 6; ++i) {
        int id = 0;
        ck_assert_int_eq(frix_solver_by_name(names[i], &id), FRIX_OK);
        ck_assert_int_eq(id, 500);
    }
    int id = 0;
    ck_assert_int_eq(frix_solver_by_name("newton", &id), FRIX_ERR_UNKNOWN_SOLVER);
    ck_assert_int_eq(frix_solver_by_name("499", &id), FRIX_ERR_UNKNOWN_SOLVER);
    ck_assert_int_eq(frix_solver_by_name("", &id), FRIX_ERR_UNKNOWN_SOLVER);
}
END_TEST

START_TEST(test_strings_and_version) {
    ck_assert_str_eq(frix_version_string(), FRIX_VERSION_STRING);
    ck_assert_int_eq(frix_version_number(), FRIX_VERSION_NUMBER);
    ck_assert_str_eq(frix_error_string(FRIX_OK), "no error");
    ck_assert_str_eq(frix_error_string((frix_error)-999), "unknown error code");
    for (int e = FRIX_ERR_INTERNAL; e <= FRIX_OK; ++e)
        ck_assert_str_ne(frix_error_string((frix_error)e), "unknown error code");
    ck_assert_str_eq(frix_status_string(FRIX_STATUS_CONVERGED), "converged");
    ck_assert_str_eq(frix_status_string((frix_status)99), "unknown status");
}
END_TEST

/* ---- The log sink: every solver's progress lines reach it, one line a call, and nothing
 * goes to stderr; without a sink they go to stderr as before. */

typedef struct {
    int lines, bad;
} line_count;

static void count_line(void *data, const char *line) {
    line_count *c = data;
    ++c->lines;
    if (line == NULL || line[0] == '\0' || strchr(line, '\n') != NULL) ++c->bad;
}

/* Solves p with `solver` at verbosity 2 into the sink (or stderr when count is NULL); 0 if a
 * call failed (no assertion here: stderr may be redirected). */
static int solve_logged(const frix_problem *p, int solver, line_count *count) {
    frix_options *o = NULL;
    if (frix_options_create(solver, &o) != FRIX_OK) return 0;
    int ok = frix_options_set_int(o, FRIX_OPT_VERBOSITY, 2) == FRIX_OK;
    if (count) ok = ok && frix_options_set_log(o, count_line, count) == FRIX_OK;
    double r[6] = {0}, u[6], v[6];
    const frix_problem_kind kind = frix_problem_get_kind(p);
    const int global = kind == FRIX_PROBLEM_GLOBAL || kind == FRIX_PROBLEM_ROLLING_GLOBAL;
    const frix_error e = frix_solve(p, o, r, u, global ? v : NULL, NULL);
    frix_options_free(o);
    return ok && (e == FRIX_OK || e == FRIX_ERR_UNSUPPORTED);
}

static long file_size(const char *path) {
    FILE *f = fopen(path, "rb");
    ck_assert_ptr_nonnull(f);
    fseek(f, 0, SEEK_END);
    const long n = ftell(f);
    fclose(f);
    return n;
}

START_TEST(test_log_sink) {
    /* Two coupled contacts, one sticking and one sliding; the same as a global problem with
     * M = I, H = I (so W = I) and f = q. */
    double W[36] = {0};
    static const double d[6] = {4, 3, 3, 5, 3.5, 3.5};
    for (int i = 0; i < 6; ++i) W[i + 6 * i] = d[i];
    W[0 + 6 * 3] = W[3 + 6 * 0] = 1.0;
    double q[6] = {-1, 0.7, -0.2, -2, 3, 0.4}, mu[2] = {0.5, 0.3}, I[36] = {0}, w[6] = {0};
    for (int i = 0; i < 6; ++i) I[i + 6 * i] = 1.0;
    frix_matrix *Wm = NULL, *Im = NULL;
    frix_problem *local = NULL, *global = NULL;
    ck_assert_int_eq(frix_matrix_from_dense(6, 6, W, 6, &Wm), FRIX_OK);
    ck_assert_int_eq(frix_matrix_from_dense(6, 6, I, 6, &Im), FRIX_OK);
    ck_assert_int_eq(frix_problem_local(Wm, q, mu, 2, &local), FRIX_OK);
    ck_assert_int_eq(frix_problem_global(Im, Im, q, w, mu, 2, &global), FRIX_OK);
    /* The same for the solvers of rolling-friction problems only: one rolling contact, W = I. */
    double I5[25] = {0}, q5[5] = {-1, 0.7, -0.2, 0.05, 0}, w5[5] = {0}, mu_r = 0.01;
    for (int i = 0; i < 5; ++i) I5[i + 5 * i] = 1.0;
    frix_matrix *I5m = NULL;
    frix_problem *rolling_local = NULL, *rolling_global = NULL;
    ck_assert_int_eq(frix_matrix_from_dense(5, 5, I5, 5, &I5m), FRIX_OK);
    ck_assert_int_eq(frix_problem_rolling_local(I5m, q5, mu, &mu_r, 1, &rolling_local), FRIX_OK);
    ck_assert_int_eq(frix_problem_rolling_global(I5m, I5m, q5, w5, mu, &mu_r, 1, &rolling_global), FRIX_OK);

    char path[512];
    snprintf(path, sizeof path, "%s/log_sink_stderr.txt", FRIX_TEST_TMPDIR);
    fflush(stderr);
    const int saved = dup(fileno(stderr));
    ck_assert(saved >= 0);
    ck_assert_ptr_nonnull(freopen(path, "w", stderr));
    /* Nothing is asserted while stderr is redirected: a failure must be seen. */
    line_count counts[64];
    const int64_t solvers = frix_solver_count();
    for (int64_t k = 0; k < solvers && k < 64; ++k) {
        counts[k].lines = counts[k].bad = 0;
        const int id = frix_solver_id_at(k), rolling = id == FRIX_SOLVER_ROLLING_NSGS || id == FRIX_SOLVER_ROLLING_NSN;
        counts[k].bad += !solve_logged(rolling ? rolling_local : local, id, &counts[k]);
        counts[k].bad += !solve_logged(rolling ? rolling_global : global, id, &counts[k]);
    }
    fflush(stderr);
    const long quiet = file_size(path);
    /* Without a sink: stderr, as before. */
    const int loud_ok = solve_logged(local, FRIX_SOLVER_NSN_AC, NULL);
    fflush(stderr);
    const long loud = file_size(path);
    ck_assert(dup2(saved, fileno(stderr)) >= 0);
    close(saved);
    ck_assert_int_le(solvers, 64);
    for (int64_t k = 0; k < solvers; ++k)
        ck_assert_msg(counts[k].lines > 0 && counts[k].bad == 0, "%s: %d lines to the sink, %d malformed or failed",
                      frix_solver_name(frix_solver_id_at(k)), counts[k].lines, counts[k].bad);
    ck_assert_msg(quiet == 0, "%ld bytes reached stderr with a log sink set", quiet);
    ck_assert_msg(loud > 0 && loud_ok, "nothing reached stderr without a log sink");
    ck_assert_int_eq(frix_options_set_log(NULL, count_line, NULL), FRIX_ERR_INVALID_ARGUMENT);

    frix_problem_free(global);
    frix_problem_free(local);
    frix_problem_free(rolling_global);
    frix_problem_free(rolling_local);
    frix_matrix_free(I5m);
    frix_matrix_free(Im);
    frix_matrix_free(Wm);
}
END_TEST

/* Every option whose values are choices names them, both ways; frix_options_set_by_name takes
 * a name or a number; refusals state the value given and the real bounds. */
START_TEST(test_choice_names) {
    static const struct {
        frix_option_key key;
        int64_t value;
        const char *name;
    } named[] = {
        {FRIX_OPT_SHUFFLE, FRIX_SHUFFLE_NONE, "none"},
        {FRIX_OPT_SHUFFLE, FRIX_SHUFFLE_ONCE, "once"},
        {FRIX_OPT_SHUFFLE, FRIX_SHUFFLE_EACH_SWEEP, "each_sweep"},
        {FRIX_OPT_RHO_STRATEGY, FRIX_RHO_CONSTANT, "constant"},
        {FRIX_OPT_RHO_STRATEGY, FRIX_RHO_SPECTRAL, "spectral"},
        {FRIX_OPT_RHO_STRATEGY, FRIX_RHO_SPLIT, "split"},
        {FRIX_OPT_LINE_SEARCH, FRIX_LINE_SEARCH_NONE, "none"},
        {FRIX_OPT_LINE_SEARCH, FRIX_LINE_SEARCH_GOLDSTEIN_PRICE, "goldstein_price"},
        {FRIX_OPT_LINE_SEARCH, FRIX_LINE_SEARCH_ARMIJO, "armijo"},
        {FRIX_OPT_LINE_SEARCH, FRIX_LINE_SEARCH_NONMONOTONE, "nonmonotone"},
        {FRIX_OPT_HYBRID, FRIX_HYBRID_NONE, "none"},
        {FRIX_OPT_HYBRID, FRIX_HYBRID_NSGS, "nsgs"},
        {FRIX_OPT_ERROR_MEASURE, FRIX_MEASURE_RELATIVE, "siconos"},
        {FRIX_OPT_ERROR_MEASURE, FRIX_MEASURE_Q_RELATIVE, "q_relative"},
        {FRIX_OPT_ERROR_MEASURE, FRIX_MEASURE_SCALED, "scaled"},
        {FRIX_OPT_LOCAL_SOLVER, FRIX_LOCAL_PROJECTION, "projection"},
        {FRIX_OPT_LOCAL_SOLVER, FRIX_LOCAL_PROJECTION_ITERATED, "projection_iterated"},
        {FRIX_OPT_LOCAL_SOLVER, FRIX_LOCAL_CLOSED_FORM, "closed_form"},
        {FRIX_OPT_LOCAL_SOLVER, FRIX_LOCAL_NEWTON_AC, "newton_ac"},
        {FRIX_OPT_LOCAL_SOLVER, FRIX_LOCAL_NEWTON_AC_GP, "newton_ac_gp"},
        {FRIX_OPT_LOCAL_SOLVER, FRIX_LOCAL_NEWTON_FB, "newton_fb"},
        {FRIX_OPT_LOCAL_SOLVER, FRIX_LOCAL_HYBRID, "hybrid"},
        {FRIX_OPT_INNER_SOLVER, FRIX_SOLVER_NSN_AC, "nsn-ac"},
        {FRIX_OPT_INNER_SOLVER, FRIX_SOLVER_NSN_FB, "nsn-fb"},
        {FRIX_OPT_INNER_SOLVER, FRIX_SOLVER_NSN_NM, "nsn-nm"},
    };
    for (size_t k = 0; k < sizeof named / sizeof named[0]; ++k) {
        const char *n = frix_option_choice_name(named[k].key, named[k].value);
        ck_assert_msg(n && strcmp(n, named[k].name) == 0, "%s %lld: %s", frix_option_name(named[k].key),
                      (long long)named[k].value, n ? n : "NULL");
        int64_t v = -1;
        ck_assert_int_eq(frix_option_choice_by_name(named[k].key, named[k].name, &v), FRIX_OK);
        ck_assert_int_eq(v, named[k].value);
    }
    int64_t v = -1;
    ck_assert_int_eq(frix_option_choice_by_name(FRIX_OPT_SHUFFLE, "Each-Sweep", &v), FRIX_OK);
    ck_assert_int_eq(v, FRIX_SHUFFLE_EACH_SWEEP);
    ck_assert_int_eq(frix_option_choice_by_name(FRIX_OPT_ERROR_MEASURE, "relative", &v), FRIX_OK);
    ck_assert_int_eq(v, FRIX_MEASURE_RELATIVE);
    ck_assert_int_eq(frix_option_choice_by_name(FRIX_OPT_SHUFFLE, "sometimes", &v), FRIX_ERR_OPTION_RANGE);
    ck_assert_msg(strstr(frix_last_error_message(), "once = 1"), "%s", frix_last_error_message());
    ck_assert_int_eq(frix_option_choice_by_name(FRIX_OPT_TOLERANCE, "once", &v), FRIX_ERR_OPTION_RANGE);
    ck_assert_int_eq(frix_option_choice_by_name((frix_option_key)999, "once", &v), FRIX_ERR_UNKNOWN_OPTION);
    ck_assert_int_eq(frix_option_choice_by_name(FRIX_OPT_SHUFFLE, NULL, &v), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_ptr_null(frix_option_choice_name(FRIX_OPT_TOLERANCE, 0));
    ck_assert_ptr_null(frix_option_choice_name(FRIX_OPT_SHUFFLE, 3));
    ck_assert_ptr_null(frix_option_choice_name(FRIX_OPT_INNER_SOLVER, FRIX_SOLVER_NSGS));

    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_NSGS, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_by_name(o, "shuffle", "once"), FRIX_OK);
    ck_assert_int_eq(frix_options_get_int(o, FRIX_OPT_SHUFFLE, &v), FRIX_OK);
    ck_assert_int_eq(v, FRIX_SHUFFLE_ONCE);
    ck_assert_int_eq(frix_options_set_by_name(o, "shuffle", "2"), FRIX_OK); /* numbers still */
    ck_assert_int_eq(frix_options_get_int(o, FRIX_OPT_SHUFFLE, &v), FRIX_OK);
    ck_assert_int_eq(v, FRIX_SHUFFLE_EACH_SWEEP);
    ck_assert_int_eq(frix_options_set_by_name(o, "error_measure", "siconos"), FRIX_OK);
    ck_assert_int_eq(frix_options_get_int(o, FRIX_OPT_ERROR_MEASURE, &v), FRIX_OK);
    ck_assert_int_eq(v, FRIX_MEASURE_RELATIVE);
    ck_assert_int_eq(frix_options_set_by_name(o, "max_iter", "77"), FRIX_OK);
    ck_assert_int_eq(frix_options_get_int(o, FRIX_OPT_MAX_ITER, &v), FRIX_OK);
    ck_assert_int_eq(v, 77);
    ck_assert_int_eq(frix_options_set_by_name(o, "relaxation", "0.5"), FRIX_OK);
    double d = 0;
    ck_assert_int_eq(frix_options_get_double(o, FRIX_OPT_RELAXATION, &d), FRIX_OK);
    ck_assert_double_eq(d, 0.5);
    ck_assert_int_eq(frix_options_set_by_name(o, "tolerance", "1e-310"), FRIX_OK); /* a number */
    ck_assert_int_eq(frix_options_set_by_name(o, "shuffle", "sometimes"), FRIX_ERR_OPTION_RANGE);
    ck_assert_msg(strstr(frix_last_error_message(), "each_sweep"), "%s", frix_last_error_message());
    ck_assert_int_eq(frix_options_set_by_name(o, "shuffle", " 1"), FRIX_ERR_OPTION_RANGE);
    ck_assert_int_eq(frix_options_set_by_name(o, "max_iter", "12abc"), FRIX_ERR_OPTION_RANGE);
    ck_assert_int_eq(frix_options_set_by_name(o, "rho", "1"), FRIX_ERR_UNKNOWN_OPTION); /* not nsgs's */
    ck_assert_int_eq(frix_options_set_by_name(o, "nosuch", "1"), FRIX_ERR_UNKNOWN_OPTION);
    ck_assert_int_eq(frix_options_set_by_name(o, "inner_solver", "nsn-ac"), FRIX_ERR_UNKNOWN_OPTION);

    /* Refusals: the value as given, the bounds as integers for int keys. */
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_MAX_ITER, 1000000001), FRIX_ERR_OPTION_RANGE);
    ck_assert_msg(strstr(frix_last_error_message(), "max_iter = 1000000001 is outside [1, 1000000000]"),
                  "%s", frix_last_error_message());
    ck_assert_int_eq(frix_options_set_by_name(o, "max_iter", "99999999999999999999"), FRIX_ERR_OPTION_RANGE);
    ck_assert_msg(strstr(frix_last_error_message(), "max_iter = 99999999999999999999 is outside [1, 1000000000]"),
                  "%s", frix_last_error_message());
    ck_assert_int_eq(frix_options_set_by_name(o, "tolerance", "1e400"), FRIX_ERR_OPTION_RANGE);
    ck_assert_msg(strstr(frix_last_error_message(), "tolerance = 1e400 is outside [0, 1]"), "%s",
                  frix_last_error_message());
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_SEED, 9007199254740993LL), FRIX_ERR_OPTION_RANGE);
    ck_assert_msg(strstr(frix_last_error_message(), "seed = 9007199254740993 is outside [0, 9007199254740992]"),
                  "%s", frix_last_error_message());
    ck_assert_int_eq(frix_options_get_int(o, FRIX_OPT_MAX_ITER, &v), FRIX_OK);
    ck_assert_int_eq(v, 77); /* refused values leave the previous one */
    frix_options_free(o);

    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_ADMM, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_RHO, 1e-310), FRIX_ERR_OPTION_RANGE);
    ck_assert_msg(strstr(frix_last_error_message(), "rho = 1e-310 is outside [1e-300, 1e+300]"), "%s",
                  frix_last_error_message());
    frix_options_free(o);
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_PROX, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_by_name(o, "inner_solver", "nsn-fb"), FRIX_OK);
    ck_assert_int_eq(frix_options_get_int(o, FRIX_OPT_INNER_SOLVER, &v), FRIX_OK);
    ck_assert_int_eq(v, FRIX_SOLVER_NSN_FB);
    ck_assert_int_eq(frix_options_set_by_name(o, "inner_solver", "nsgs"), FRIX_ERR_OPTION_RANGE);
    frix_options_free(o);
}
END_TEST

int main(void) {
    Suite *s = suite_create("options");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, test_defaults_and_bounds);
    tcase_add_test(tc, test_option_names);
    tcase_add_test(tc, test_registry);
    tcase_add_test(tc, test_strings_and_version);
    tcase_add_test(tc, test_log_sink);
    tcase_add_test(tc, test_choice_names);
    suite_add_tcase(s, tc);
    return frix_run_suite(s);
}
