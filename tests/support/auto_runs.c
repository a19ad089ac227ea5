/* The auto test fixtures of auto_runs.h. */
#include "auto_runs.h"

#include <check.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check_main.h"
#include "shared_data.h"

frix_options *auto_options(double tol) {
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_AUTO, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, tol), FRIX_OK);
    return o;
}

int file_run_open(file_run *f, const char *relative, double tol) {
    memset(f, 0, sizeof *f);
    f->p = load(relative);
    if (!f->p) return 0;
    f->m = frix_problem_contact_dofs(f->p);
    f->r = calloc((size_t)f->m + 1, sizeof *f->r);
    f->u = calloc((size_t)f->m + 1, sizeof *f->u);
    f->v = calloc((size_t)frix_problem_dofs(f->p) + 1, sizeof *f->v);
    ck_assert_int_eq(frix_info_create(&f->info), FRIX_OK);
    f->o = auto_options(tol);
    return 1;
}

void file_run_solve(file_run *f) {
    memset(f->r, 0, (size_t)f->m * sizeof *f->r);
    memset(f->v, 0, (size_t)frix_problem_dofs(f->p) * sizeof *f->v);
    ck_assert_int_eq(frix_solve(f->p, f->o, f->r, f->u, f->v, f->info), FRIX_OK);
    if (frix_problem_get_kind(f->p) != FRIX_PROBLEM_LOCAL) return;
    double *u = calloc((size_t)f->m + 1, sizeof *u);
    frix_info *measured = NULL;
    ck_assert_int_eq(frix_info_create(&measured), FRIX_OK);
    ck_assert_int_eq(frix_problem_measure(f->p, f->r, NULL, u, measured), FRIX_OK);
    for (int64_t i = 0; i < f->m; ++i)
        ck_assert_double_eq_tol(f->u[i], u[i], 1e-12 * (1.0 + fabs(u[i])));
    double independent = NAN;
    ck_assert_int_eq(frix_info_get_double(measured, frix_test_error_key(f->o), &independent), FRIX_OK);
    ck_assert_double_eq(frix_info_error(f->info), independent);
    frix_info_free(measured);
    free(u);
}

void file_run_close(file_run *f) {
    frix_options_free(f->o);
    frix_info_free(f->info);
    free(f->r);
    free(f->u);
    free(f->v);
    frix_problem_free(f->p);
}
