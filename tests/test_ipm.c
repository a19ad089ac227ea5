/* The interior-point solver (524 ipm): the FCLIB problems it solves to 1e-8 (error
 * recomputed), frictionless and mixed-mu contacts, determinism, the iteration limit and the
 * callback, and the hand-over to Newton when the interior iterates stall. */
#include <frix/frix.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check_main.h"
#include "scenes.h"
#include "shared_data.h"

static frix_options *ipm_options(void) {
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_IPM, &o), FRIX_OK);
    return o;
}

/* Solves p from r = 0 (r must hold 3nc entries); checks r finite and returns the recomputed
 * error. */
static double solve_and_check(const frix_problem *p, const frix_options *o, double *r, frix_info *info) {
    const int64_t m = frix_problem_contact_dofs(p);
    double *u = calloc((size_t)m + 1, sizeof *u);
    memset(r, 0, (size_t)m * sizeof *r);
    ck_assert_int_eq(frix_solve(p, o, r, u, NULL, info), FRIX_OK);
    for (int64_t i = 0; i < m; ++i) ck_assert(isfinite(r[i]));
    double err = NAN;
    ck_assert_int_eq(frix_problem_error(p, r, NULL, &err), FRIX_OK);
    free(u);
    return err;
}

START_TEST(ipm_is_registered) {
    int id = 0;
    ck_assert_int_eq(frix_solver_by_name("ipm", &id), FRIX_OK);
    ck_assert_int_eq(id, FRIX_SOLVER_IPM);
    ck_assert_int_eq(frix_solver_by_name("FRICTION_3D_IPM", &id), FRIX_OK);
    ck_assert_int_eq(id, 524);
    ck_assert_str_eq(frix_solver_name(FRIX_SOLVER_IPM), "ipm");
}
END_TEST

/* Every local FCLIB problem but RockPile (which it leaves at ~2e-4), within 200 iterations. */
START_TEST(ipm_solves_the_fclib_problems) {
    const char *file = kFclibLocalProblems[_i];
    if (strstr(file, "RockPile")) return;
    frix_problem *p = load(file);
    if (!p) return;
    frix_options *o = ipm_options();
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    double *r = calloc((size_t)frix_problem_contact_dofs(p) + 1, sizeof *r);
    const double err = solve_and_check(p, o, r, info);
    ck_assert_msg(frix_info_status(info) == FRIX_STATUS_CONVERGED && err <= 1e-8,
                  "%s: %s, error %g after %lld iterations", file,
                  frix_status_string(frix_info_status(info)), err, (long long)frix_info_iterations(info));
    ck_assert_int_le(frix_info_iterations(info), 200);
    free(r);
    frix_info_free(info);
    frix_options_free(o);
    frix_problem_free(p);
}
END_TEST

/* mu = 0 contacts have no Lorentz pair (r_T stays 0); mixed mu in one problem. */
START_TEST(ipm_solves_frictionless_and_mixed_mu) {
    static const char *const names[] = {"spheres_mu0", "stack_mixed_mu", "spheres_mu1e-3",
                                        "single_cone_boundary", "slope_at_threshold"};
    for (size_t k = 0; k < sizeof names / sizeof names[0]; ++k) {
        int index = -1;
        for (int i = 0; i < frix_hard_case_count(); ++i)
            if (strcmp(frix_hard_case_name(i), names[k]) == 0) index = i;
        ck_assert_int_ge(index, 0);
        frix_hard_case c;
        ck_assert_int_eq(frix_hard_case_make(index, &c), FRIX_OK);
        frix_options *o = ipm_options();
        frix_info *info = NULL;
        ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
        double *r = calloc((size_t)frix_problem_contact_dofs(c.problem) + 1, sizeof *r);
        const double err = solve_and_check(c.problem, o, r, info);
        ck_assert_msg(frix_info_status(info) == FRIX_STATUS_CONVERGED && err <= 1e-8, "%s: %s, error %g",
                      names[k], frix_status_string(frix_info_status(info)), err);
        if (strcmp(names[k], "spheres_mu0") == 0)
            for (int64_t a = 0; a < frix_problem_contacts(c.problem); ++a)
                ck_assert(r[3 * a + 1] == 0.0 && r[3 * a + 2] == 0.0);
        free(r);
        frix_info_free(info);
        frix_options_free(o);
        frix_hard_case_free(&c);
    }
}
END_TEST

START_TEST(ipm_is_deterministic) {
    frix_problem *p = load("converted/Capsules-i101-404.from_dat.hdf5");
    if (!p) return;
    const int64_t m = frix_problem_contact_dofs(p);
    double *r1 = calloc((size_t)m, sizeof *r1), *r2 = calloc((size_t)m, sizeof *r2);
    frix_options *o = ipm_options();
    frix_info *i1 = NULL, *i2 = NULL;
    ck_assert_int_eq(frix_info_create(&i1), FRIX_OK);
    ck_assert_int_eq(frix_info_create(&i2), FRIX_OK);
    solve_and_check(p, o, r1, i1);
    /* A warm start that misses the tolerance does not change the result. */
    for (int64_t i = 0; i < m; ++i) r2[i] = 1.0;
    double *u = calloc((size_t)m, sizeof *u);
    ck_assert_int_eq(frix_solve(p, o, r2, u, NULL, i2), FRIX_OK);
    ck_assert_int_eq(frix_info_iterations(i1), frix_info_iterations(i2));
    ck_assert(memcmp(r1, r2, (size_t)m * sizeof *r1) == 0);
    free(u);
    free(r1);
    free(r2);
    frix_info_free(i1);
    frix_info_free(i2);
    frix_options_free(o);
    frix_problem_free(p);
}
END_TEST

static int stop_at_three(void *data, int64_t iteration, double error, double elapsed) {
    (void)error, (void)elapsed;
    int *calls = data;
    ++*calls;
    return iteration >= 3;
}

START_TEST(ipm_limits_and_callback) {
    frix_problem *p = load("local/Capsules-i125-1213.hdf5");
    if (!p) return;
    const int64_t m = frix_problem_contact_dofs(p);
    double *r = calloc((size_t)m, sizeof *r);
    frix_options *o = ipm_options();
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_MAX_ITER, 2), FRIX_OK);
    double err = solve_and_check(p, o, r, info);
    ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_MAX_ITER);
    ck_assert_int_eq(frix_info_iterations(info), 2);
    ck_assert(isfinite(err) && err > 1e-8);

    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_MAX_ITER, 500), FRIX_OK);
    int calls = 0;
    ck_assert_int_eq(frix_options_set_callback(o, stop_at_three, &calls), FRIX_OK);
    err = solve_and_check(p, o, r, info);
    ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_STOPPED_BY_CALLBACK);
    ck_assert_int_le(frix_info_iterations(info), 4);
    ck_assert_int_ge(calls, 3);
    ck_assert(isfinite(err));
    free(r);
    frix_info_free(info);
    frix_options_free(o);
    frix_problem_free(p);
}
END_TEST

/* Where the interior iterates stall (RockPile's rank-deficient, non-symmetric W), Newton
 * takes over from the best of them: Newton steps are reported and r is no worse than the
 * interior-point stage's best (~2e-4). */
START_TEST(ipm_hands_over_to_newton) {
    frix_problem *p = load("converted/RockPile_tob1.from_dat.hdf5");
    if (!p) return;
    const int64_t m = frix_problem_contact_dofs(p);
    double *r = calloc((size_t)m, sizeof *r);
    frix_options *o = ipm_options();
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    const double err = solve_and_check(p, o, r, info);
    int64_t newton = 0;
    ck_assert_int_eq(frix_info_get_int(info, FRIX_INFO_NEWTON_ITERATIONS, &newton), FRIX_OK);
    ck_assert_int_gt(newton, 0);
    ck_assert_msg(err < 1e-3, "error %g", err);
    ck_assert(fabs(err - frix_info_error(info)) <= 1e-12 * err);
    free(r);
    frix_info_free(info);
    frix_options_free(o);
    frix_problem_free(p);
}
END_TEST

int main(void) {
    Suite *s = suite_create("ipm");
    TCase *tc = tcase_create("core");
    tcase_set_timeout(tc, 120);
    tcase_add_test(tc, ipm_is_registered);
    tcase_add_loop_test(tc, ipm_solves_the_fclib_problems, 0, FRIX_FCLIB_LOCAL_COUNT);
    tcase_add_test(tc, ipm_solves_frictionless_and_mixed_mu);
    tcase_add_test(tc, ipm_is_deterministic);
    tcase_add_test(tc, ipm_limits_and_callback);
    tcase_add_test(tc, ipm_hands_over_to_newton);
    suite_add_tcase(s, tc);
    return frix_run_suite(s);
}
