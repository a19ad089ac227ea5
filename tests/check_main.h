/* Shared by the Check test programs: run one suite and turn failures into the exit code. */
#ifndef FRIX_CHECK_MAIN_H
#define FRIX_CHECK_MAIN_H

#include <check.h>
#include <stdlib.h>

/* For a test whose scenario (iteration counts, stages, a verdict at a tolerance) was built and
 * measured on Siconos's measure, the default until the trust issue: it keeps testing what it
 * was written for. Returns o. */
#ifdef FRIX_H
static inline frix_options *frix_test_siconos_measure(frix_options *o) {
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_ERROR_MEASURE, FRIX_MEASURE_RELATIVE), FRIX_OK);
    return o;
}
#endif

#ifdef FRIX_H
/* For a test of auto whose scenario (which stages run, and why) was built on plain sweeps, the
 * default until auto's sweeps took momentum: it keeps testing what it was written for. Returns o. */
static inline frix_options *frix_test_plain_sweeps(frix_options *o) {
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_ACCELERATION, 0), FRIX_OK);
    return o;
}
#endif

#ifdef FRIX_H
/* The info key of the measure options o compare with the tolerance. */
static inline frix_info_key frix_test_error_key(const frix_options *o) {
    int64_t measure = FRIX_MEASURE_SCALED;
    ck_assert_int_eq(frix_options_get_int(o, FRIX_OPT_ERROR_MEASURE, &measure), FRIX_OK);
    return measure == FRIX_MEASURE_RELATIVE     ? FRIX_INFO_ERROR_RELATIVE
           : measure == FRIX_MEASURE_Q_RELATIVE ? FRIX_INFO_ERROR_Q_RELATIVE
                                                : FRIX_INFO_ERROR_SCALED;
}

/* The measure of (r, v) that options o compare with the tolerance, measured independently. */
static inline double frix_test_error_of(const frix_problem *p, const double *r, const double *v, const frix_options *o) {
    frix_info *check = NULL;
    double e = NAN;
    ck_assert_int_eq(frix_info_create(&check), FRIX_OK);
    ck_assert_int_eq(frix_problem_measure(p, r, v, NULL, check), FRIX_OK);
    ck_assert_int_eq(frix_info_get_double(check, frix_test_error_key(o), &e), FRIX_OK);
    frix_info_free(check);
    return e;
}
#endif

static inline int frix_run_suite(Suite *s) {
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}

#endif
