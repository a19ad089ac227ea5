/* Time limits hold for factorisations: a factorisation cannot be stopped once started, so a
 * solver does not start one that its price (flops from the symbolic analysis, at the
 * machine's measured rate) says would overrun the limit. On the 8-layer pyramid of spheres
 * (960 contacts) with a limit of a millisecond, every registered solver returns "time
 * limit" without a numeric factorisation of its own, where the factorising ones used to
 * make one first (tens of milliseconds each). No time is measured here: the tests assert statuses and
 * counters; the walls are in the benchmark note. */
#include <check.h>
#include <frix/frix.h>
#include <math.h>
#include <stdlib.h>

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

START_TEST(test_no_factorisation_past_the_limit) {
    const int id = frix_solver_id_at(_i);
    ck_assert_int_ge(id, 0);
    const int global = id == FRIX_SOLVER_GLOBAL_NSN_AC;
    const frix_problem *p = global ? g_problems.global : g_problems.local;
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(id, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TIME_LIMIT, 1e-3), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_MAX_ITER, 1000000), FRIX_OK);
    const int64_t m = 3 * g_scene.nc;
    double *r = calloc((size_t)m, sizeof *r), *u = calloc((size_t)m, sizeof *u);
    double *v = calloc((size_t)g_scene.n, sizeof *v);
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_solve(p, o, r, u, global ? v : NULL, info), FRIX_OK);
    ck_assert_msg(frix_info_status(info) == FRIX_STATUS_TIME_LIMIT, "%s: %s", frix_solver_name(id),
                  frix_status_string(frix_info_status(info)));
    int64_t factorizations = -1;
    ck_assert_int_eq(frix_info_get_int(info, FRIX_INFO_FACTORIZATIONS, &factorizations), FRIX_OK);
    /* A global problem's M is factorised by the driver before any solver runs (block-diagonal
     * here: cheap); the solver itself makes none. */
    ck_assert_msg(factorizations == (global ? 1 : 0), "%s: %lld factorisations under a 1 ms limit",
                  frix_solver_name(id), (long long)factorizations);
    for (int64_t i = 0; i < m; ++i) ck_assert(isfinite(r[i]));
    frix_info_free(info);
    free(r);
    free(u);
    free(v);
    frix_options_free(o);
}
END_TEST

int main(void) {
    Suite *s = suite_create("time_limits");
    TCase *tc = tcase_create("core");
    tcase_add_unchecked_fixture(tc, setup, teardown);
    tcase_add_loop_test(tc, test_no_factorisation_past_the_limit, 0, (int)frix_solver_count());
    suite_add_tcase(s, tc);
    return frix_run_suite(s);
}
