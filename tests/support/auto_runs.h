/* Shared by the auto test programs (test_auto, test_auto_fclib, test_auto_stages): auto's
 * options at a tolerance, and one problem of ../shared/fclib with what a solve of it needs. */
#ifndef FRIX_TEST_AUTO_RUNS_H
#define FRIX_TEST_AUTO_RUNS_H

#include <frix/frix.h>

/* Auto's options at tolerance `tol`. */
frix_options *auto_options(double tol);

/* One shared problem with what a solve of it needs: r, u, v (all zero), an info and auto's
 * options at `tol`. open() returns 0 when the shared data is absent (the test then passes). */
typedef struct {
    frix_problem *p;
    int64_t m;
    double *r, *u, *v;
    frix_info *info;
    frix_options *o;
} file_run;

int file_run_open(file_run *f, const char *relative, double tol);
/* Solves from r = 0 (v = 0). On a local problem, the u and the error returned must be those
 * of the r returned (measured again here). */
void file_run_solve(file_run *f);
void file_run_close(file_run *f);

#endif
