/* Shared by the Check test programs: run one suite and turn failures into the exit code. */
#ifndef FRIX_CHECK_MAIN_H
#define FRIX_CHECK_MAIN_H

#include <check.h>
#include <stdlib.h>

static int frix_run_suite(Suite *s) {
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}

#endif
