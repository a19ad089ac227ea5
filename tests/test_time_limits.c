/* Time and memory limits hold for factorisations: a factorisation cannot be stopped once started, so a
 * solver does not start one that its price (flops from the symbolic analysis, at the
 * machine's measured rate) says would overrun the limit. On the 8-layer pyramid of spheres
 * (960 contacts) with a limit of a millisecond, every registered solver returns "time
 * limit" without a numeric factorisation of its own, where the factorising ones used to
 * make one first (tens of milliseconds each). Under a memory limit below any factor's size,
 * the factorising solvers return "memory limit" without one, the others are not stopped by it,
 * and auto solves the pile without factorising. No time is measured here: the tests assert
 * statuses and counters; the walls are in the benchmark note. */
#include <check.h>
#include <frix/frix.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check_main.h"
#include "scenes.h"

static frix_scene g_scene;
static frix_scene_problems g_problems;

static void setup(void) {
    frix_scene_params sp;
    frix_scene_defaults(FRIX_SCENE_SPHERES, &sp);
    sp.count = 8;
    ck_assert_int_eq(frix_scene_build(&sp, &g_scene, NULL), FRIX_OK);
    ck_assert_int_eq(frix_scene_problems_make(&g_scene, &g_problems), FRIX_OK);
}

static void teardown(void) {
    frix_scene_problems_free(&g_problems);
    frix_scene_free(&g_scene);
}

/* Solves the pile with solver id (gnsn-ac: the global form) under options o: the solve's
 * return, status and factorisation count; r stays finite. */
typedef struct {
    frix_error solved;
    frix_status status;
    int64_t factorizations;
    double error;
} limited_run;

static limited_run solve_pile(int id, const frix_problem *p, const frix_options *o) {
    const int64_t m = 3 * g_scene.nc;
    double *r = calloc((size_t)m, sizeof *r), *u = calloc((size_t)m, sizeof *u);
    double *v = calloc((size_t)g_scene.n, sizeof *v);
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    limited_run run = {frix_solve(p, o, r, u, frix_problem_get_kind(p) == FRIX_PROBLEM_GLOBAL ? v : NULL, info),
                       FRIX_STATUS_NOT_RUN, -1, NAN};
    if (run.solved == FRIX_OK) {
        run.status = frix_info_status(info);
        run.error = frix_info_error(info);
        ck_assert_int_eq(frix_info_get_int(info, FRIX_INFO_FACTORIZATIONS, &run.factorizations), FRIX_OK);
        for (int64_t i = 0; i < m; ++i) ck_assert_msg(isfinite(r[i]), "%s: r not finite", frix_solver_name(id));
    }
    frix_info_free(info);
    free(r);
    free(u);
    free(v);
    return run;
}

/* The solvers of global problems only: they run on the global pile. */
static int global_only(int id) {
    return id == FRIX_SOLVER_GLOBAL_NSN_AC || id == FRIX_SOLVER_GLOBAL_ADMM || id == FRIX_SOLVER_GLOBAL_AL_NEWTON ||
           id == FRIX_SOLVER_GLOBAL_NSGS;
}

START_TEST(test_no_factorisation_past_the_limit) {
    const int id = frix_solver_id_at(_i);
    ck_assert_int_ge(id, 0);
    /* rolling problems only: test_rolling's time limit, test_rolling_newton's memory limit */
    if (id == FRIX_SOLVER_ROLLING_NSGS || id == FRIX_SOLVER_ROLLING_NSN) return;
    const int global = global_only(id);
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(id, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TIME_LIMIT, 1e-3), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_MAX_ITER, 1000000), FRIX_OK);
    const limited_run run = solve_pile(id, global ? g_problems.global : g_problems.local, o);
    ck_assert_int_eq(run.solved, FRIX_OK);
    ck_assert_msg(run.status == FRIX_STATUS_TIME_LIMIT, "%s: %s", frix_solver_name(id),
                  frix_status_string(run.status));
    /* A global problem's M is factorised by the driver before any solver runs, whatever the
     * time limit (the start's velocity needs it; block-diagonal here: cheap); the solver
     * itself makes none. */
    ck_assert_msg(run.factorizations == (global ? 1 : 0), "%s: %lld factorisations under a 1 ms limit",
                  frix_solver_name(id), (long long)run.factorizations);
    frix_options_free(o);
}
END_TEST

/* The solvers that factorise: a memory limit below any factor's size stops them before their first. */
static int factorises(const char *name) {
    static const char *const names[] = {"prox", "nsn-ac", "nsn-fb",  "nsn-nm", "gnsn-ac",
                                        "admm", "ipm",    "ipm-anm", "gadmm",  "gnsn-al"};
    for (size_t k = 0; k < sizeof names / sizeof names[0]; ++k)
        if (strcmp(name, names[k]) == 0) return 1;
    return 0;
}

START_TEST(test_no_factorisation_past_the_memory_limit) {
    const int id = frix_solver_id_at(_i);
    ck_assert_int_ge(id, 0);
    /* rolling problems only: test_rolling_newton's memory limit */
    if (id == FRIX_SOLVER_ROLLING_NSGS || id == FRIX_SOLVER_ROLLING_NSN) return;
    const int global = global_only(id);
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(id, &o), FRIX_OK);
    frix_test_siconos_measure(o);
    /* 64 kB: the smallest factor here (ADMM's Cholesky of W + rho I) takes megabytes. The
     * global problem gets 500 kB: room for M's factor (some 150 kB, the driver's), not for
     * gnsn-ac's LU of the (v, r) system. */
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_MEMORY_LIMIT, global ? 5e5 : 65536.0), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 1e-3), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_MAX_ITER, id == FRIX_SOLVER_AUTO ? 100000 : 50), FRIX_OK);
    const limited_run run = solve_pile(id, global ? g_problems.global : g_problems.local, o);
    ck_assert_int_eq(run.solved, FRIX_OK);
    const char *name = frix_solver_name(id);
    if (factorises(name))
        ck_assert_msg(run.status == FRIX_STATUS_MEMORY_LIMIT, "%s: %s", name, frix_status_string(run.status));
    else
        ck_assert_msg(run.status != FRIX_STATUS_MEMORY_LIMIT, "%s: stopped by the memory limit", name);
    /* M's only (the driver's, before any solver runs). */
    ck_assert_msg(run.factorizations == (global ? 1 : 0), "%s: %lld factorisations under the memory limit", name,
                  (long long)run.factorizations);
    /* auto leaves the factorising stages out and finishes with the first-order ones. */
    if (id == FRIX_SOLVER_AUTO)
        ck_assert_msg(run.status == FRIX_STATUS_CONVERGED, "auto: %s, error %.3e", frix_status_string(run.status),
                      run.error);
    frix_options_free(o);
}
END_TEST

/* A global problem's own memory is held to the limit too. Under 64 kB not even M's
 * factorisation (the driver's, some 150 kB here) is made: nothing is solved, the start comes
 * back with v = 0 and status "memory limit". Under 500 kB M fits but W = H^T M^-1 H (80 bytes
 * a block, over 1 MB here) does not: refused with a message, before W is formed. */
START_TEST(test_global_problem_past_the_memory_limit) {
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_NSGS, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_MEMORY_LIMIT, 65536.0), FRIX_OK);
    limited_run run = solve_pile(FRIX_SOLVER_NSGS, g_problems.global, o);
    ck_assert_int_eq(run.solved, FRIX_OK);
    ck_assert_int_eq(run.status, FRIX_STATUS_MEMORY_LIMIT);
    ck_assert_int_eq(run.factorizations, 0);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_MEMORY_LIMIT, 5e5), FRIX_OK);
    run = solve_pile(FRIX_SOLVER_NSGS, g_problems.global, o);
    ck_assert_int_eq(run.solved, FRIX_ERR_OUT_OF_MEMORY);
    ck_assert_ptr_nonnull(strstr(frix_last_error_message(), "memory"));
    frix_options_free(o);
}
END_TEST

int main(void) {
    Suite *s = suite_create("time_limits");
    TCase *tc = tcase_create("core");
    tcase_add_unchecked_fixture(tc, setup, teardown);
    tcase_add_loop_test(tc, test_no_factorisation_past_the_limit, 0, (int)frix_solver_count());
    tcase_add_loop_test(tc, test_no_factorisation_past_the_memory_limit, 0, (int)frix_solver_count());
    tcase_add_test(tc, test_global_problem_past_the_memory_limit);
    suite_add_tcase(s, tc);
    return frix_run_suite(s);
}
