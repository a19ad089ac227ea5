/* Options by key (defaults, bounds, refusals), the solver registry, version and error strings. */
#include <frix/frix.h>
#include <math.h>
#include <string.h>

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
    ck_assert_str_eq(frix_solver_name(500), "nsgs");
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

int main(void) {
    Suite *s = suite_create("options");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, test_defaults_and_bounds);
    tcase_add_test(tc, test_option_names);
    tcase_add_test(tc, test_registry);
    tcase_add_test(tc, test_strings_and_version);
    suite_add_tcase(s, tc);
    return frix_run_suite(s);
}
