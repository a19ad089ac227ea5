/* auto (900): registered and the default, its option keys, islands found and combined
 * exactly, results independent of the thread count, the trace and its records, the switch
 * count, the caller's callback, and the limits. Which stages auto runs where: test_auto_stages;
 * convergence on every problem of ../shared/fclib: test_auto_fclib. */
#include <check.h>
#include <frix/frix.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "auto_runs.h"
#include "check_main.h"
#include "stage_records.h"

/* A local problem of `groups` independent chains of `size` contacts (each coupled to the
 * next: islands of `size`), plus `singles` contacts coupled to nothing. Every contact is
 * pressed (q_N < 0) and pushed sideways, some enough to slide. */
typedef struct {
    frix_matrix *W;
    double *q, *mu;
    frix_problem *p;
    int64_t nc;
} islands_problem;

static void islands_make(islands_problem *ip, int64_t groups, int64_t size, int64_t singles) {
    const int64_t nc = groups * size + singles;
    const int64_t nblocks = groups * (3 * size - 2) + singles;
    int64_t *brow = calloc((size_t)nblocks, sizeof *brow), *bcol = calloc((size_t)nblocks, sizeof *bcol);
    double *vals = calloc((size_t)(9 * nblocks), sizeof *vals);
    int64_t b = 0;
    for (int64_t g = 0; g < groups; ++g) {
        const double s = 1.0 + 0.1 * (double)g;
        for (int64_t i = 0; i < size; ++i)
            for (int64_t j = i - 1; j <= i + 1; ++j) {
                if (j < 0 || j >= size) continue;
                brow[b] = g * size + i, bcol[b] = g * size + j;
                double *B = &vals[9 * b];
                if (i == j) {
                    B[0] = 2.0 * s, B[4] = 1.5 * s, B[8] = 1.5 * s;
                    B[3] = B[1] = 0.2 * s;
                } else {
                    B[0] = 0.9 * s, B[4] = 0.3 * s, B[8] = 0.3 * s;
                }
                ++b;
            }
    }
    for (int64_t k = 0; k < singles; ++k) {
        brow[b] = bcol[b] = groups * size + k;
        double *B = &vals[9 * b];
        B[0] = 1.0 + 0.01 * (double)k, B[4] = B[8] = 0.8;
        ++b;
    }
    ck_assert_int_eq(frix_matrix_from_blocks(nc, nc, nblocks, brow, bcol, vals, &ip->W), FRIX_OK);
    ip->q = calloc((size_t)(3 * nc), sizeof *ip->q);
    ip->mu = calloc((size_t)nc, sizeof *ip->mu);
    for (int64_t a = 0; a < nc; ++a) {
        ip->q[3 * a] = -1.0 - 0.05 * (double)(a % 7);
        ip->q[3 * a + 1] = 0.3 * (double)((a % 5) - 2);
        ip->q[3 * a + 2] = 0.2 * (double)((a % 3) - 1);
        ip->mu[a] = 0.2 + 0.1 * (double)(a % 4);
    }
    ip->nc = nc;
    ck_assert_int_eq(frix_problem_local(ip->W, ip->q, ip->mu, nc, &ip->p), FRIX_OK);
    free(brow);
    free(bcol);
    free(vals);
}

static void islands_free(islands_problem *ip) {
    frix_problem_free(ip->p);
    frix_matrix_free(ip->W);
    free(ip->q);
    free(ip->mu);
}

START_TEST(test_registered_and_default) {
    int id = 0;
    ck_assert_int_eq(frix_solver_by_name("auto", &id), FRIX_OK);
    ck_assert_int_eq(id, FRIX_SOLVER_AUTO);
    ck_assert_str_eq(frix_solver_name(FRIX_SOLVER_AUTO), "auto");
    ck_assert_ptr_nonnull(strstr(frix_solver_describe(FRIX_SOLVER_AUTO), "island"));
    /* NULL options: the default solver is auto. */
    islands_problem ip;
    islands_make(&ip, 2, 2, 1);
    double r[15] = {0}, u[15];
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_solve(ip.p, NULL, r, u, NULL, info), FRIX_OK);
    int64_t solver = 0;
    ck_assert_int_eq(frix_info_get_int(info, FRIX_INFO_SOLVER_ID, &solver), FRIX_OK);
    ck_assert_int_eq(solver, FRIX_SOLVER_AUTO);
    ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_CONVERGED);
    frix_info_free(info);
    islands_free(&ip);
}
END_TEST

START_TEST(test_option_keys) {
    frix_options *o = auto_options(1e-8);
    int64_t threads = 0;
    ck_assert_int_eq(frix_options_get_int(o, FRIX_OPT_THREADS, &threads), FRIX_OK);
    ck_assert_int_eq(threads, 1);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_THREADS, 0), FRIX_ERR_OPTION_RANGE);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_EXISTENCE_CHECK, 2), FRIX_ERR_OPTION_RANGE);
    /* auto runs other solvers' options itself: their keys are not auto's. */
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_LOCAL_SOLVER, FRIX_LOCAL_CLOSED_FORM), FRIX_ERR_UNKNOWN_OPTION);
    frix_options_free(o);
    /* threads is auto's key only. */
    frix_options *n = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_NSGS, &n), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(n, FRIX_OPT_THREADS, 2), FRIX_ERR_UNKNOWN_OPTION);
    frix_options_free(n);
}
END_TEST

/* Islands: counted, the large ones solved as parts of their own and the small ones together,
 * the result meets the tolerance on the whole problem, and the same bits with 1 and with 3
 * threads. */
START_TEST(test_islands_and_threads) {
    islands_problem ip;
    islands_make(&ip, 4, 40, 5);
    const int64_t m = 3 * ip.nc;
    double *r1 = calloc((size_t)m, sizeof *r1), *r3 = calloc((size_t)m, sizeof *r3);
    double *u = calloc((size_t)m, sizeof *u);
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    frix_options *o = auto_options(1e-10);
    ck_assert_int_eq(frix_solve(ip.p, o, r1, u, NULL, info), FRIX_OK);
    ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_CONVERGED);
    ck_assert(frix_info_error(info) <= 1e-10);
    int64_t islands = 0;
    ck_assert_int_eq(frix_info_get_int(info, FRIX_INFO_ISLANDS, &islands), FRIX_OK);
    ck_assert_int_eq(islands, 4 + 5);
    /* First NSGS on the whole problem (record 1, part 0), then parts 1-4 the chains (40 contacts
     * each) and part 5 the singles together, no part 6; the singles are solved by the sweeps
     * on the whole problem, so that their part has nothing left to run. */
    ck_assert_int_eq(stage_int(info, 1, FRIX_STAGE_SOLVER_ID), FRIX_SOLVER_NSGS);
    ck_assert_int_eq(stage_int(info, 1, FRIX_STAGE_PART), 0);
    int64_t largest_part = 0, part5 = 0;
    for (int64_t k = 2; k < frix_info_stage_count(info); ++k) {
        const int64_t part = stage_int(info, k, FRIX_STAGE_PART), n = stage_int(info, k, FRIX_STAGE_PART_CONTACTS);
        ck_assert_int_ge(part, 1);
        ck_assert_int_le(part, 5);
        if (part == 4) ck_assert_int_eq(n, 40);
        if (part == 5) part5 = n;
        if (part > largest_part) largest_part = part;
    }
    ck_assert_int_eq(largest_part, 4);
    ck_assert_int_eq(part5, 0);
    /* The whole problem's own measure agrees. */
    double e = NAN;
    ck_assert_int_eq(frix_problem_error(ip.p, r1, NULL, &e), FRIX_OK);
    ck_assert(e <= 1e-10);

    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_THREADS, 3), FRIX_OK);
    ck_assert_int_eq(frix_solve(ip.p, o, r3, u, NULL, info), FRIX_OK);
    ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_CONVERGED);
    ck_assert_mem_eq(r1, r3, (size_t)m * sizeof *r1);
    frix_options_free(o);
    frix_info_free(info);
    free(r1);
    free(r3);
    free(u);
    islands_free(&ip);
}
END_TEST

/* A problem where NSGS alone is a limit cycle (Siconos' NSGS fails too): auto switches and
 * converges, and says so in the trace and the switch count. */
START_TEST(test_switches_recorded) {
    file_run f;
    if (!file_run_open(&f, "converted/OneObject-i100000-316.from_dat.hdf5", 1e-8)) return;
    frix_test_siconos_measure(f.o);
    file_run_solve(&f);
    ck_assert_int_eq(frix_info_status(f.info), FRIX_STATUS_CONVERGED);
    int64_t switches = -1;
    ck_assert_int_eq(frix_info_get_int(f.info, FRIX_INFO_SWITCHES, &switches), FRIX_OK);
    ck_assert_int_ge(switches, 1);
    /* (25 contacts: the first stage is plain NSGS) */
    const int64_t nsgs = find_stage(f.info, FRIX_SOLVER_NSGS, 0);
    ck_assert_msg(nsgs >= 0 && stage_int(f.info, nsgs, FRIX_STAGE_STOPPED_BY_AUTO) == 1, "%s",
                  frix_info_trace(f.info));
    /* The records are the trace's lines: as many, each note one of its lines; the analysis
     * (record 0) is not a run. */
    const int64_t count = frix_info_stage_count(f.info);
    const char *trace = frix_info_trace(f.info);
    int64_t lines = 0;
    for (const char *c = trace; *c; ++c) lines += *c == '\n';
    ck_assert_int_eq(count, lines);
    for (int64_t k = 0; k < count; ++k) {
        const char *note = frix_info_stage_note(f.info, k);
        ck_assert_msg(note[0] != '\0' && strchr(note, '\n') == NULL && strstr(trace, note) != NULL, "%s", note);
    }
    ck_assert_int_eq(stage_int(f.info, 0, FRIX_STAGE_SOLVER_ID), 0);
    ck_assert(isnan(stage_double(f.info, 0, FRIX_STAGE_ERROR)));
    ck_assert(stage_double(f.info, nsgs, FRIX_STAGE_ERROR) > 0.0);
    int64_t value = 0;
    double x = 0.0;
    ck_assert_int_eq(frix_info_stage_get_int(f.info, count, FRIX_STAGE_STATUS, &value), FRIX_ERR_DIMENSION);
    ck_assert_int_eq(frix_info_stage_get_int(f.info, -1, FRIX_STAGE_STATUS, &value), FRIX_ERR_DIMENSION);
    ck_assert_int_eq(frix_info_stage_get_int(f.info, 0, FRIX_STAGE_ERROR, &value), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_info_stage_get_double(f.info, 0, FRIX_STAGE_STATUS, &x), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_info_stage_get_int(NULL, 0, FRIX_STAGE_STATUS, &value), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_str_eq(frix_info_stage_note(f.info, count), "");
    ck_assert_int_eq(frix_info_stage_count(NULL), 0);
    file_run_close(&f);
}
END_TEST

typedef struct {
    int64_t calls, last_iteration, stop_after;
    int monotone;
} progress_log;

static int on_progress(void *data, int64_t iteration, double error, double elapsed) {
    progress_log *log = data;
    (void)error;
    (void)elapsed;
    if (iteration < log->last_iteration) log->monotone = 0;
    log->last_iteration = iteration;
    ++log->calls;
    return log->stop_after > 0 && log->calls >= log->stop_after;
}

START_TEST(test_callback_sees_progress_and_stops) {
    file_run f;
    if (!file_run_open(&f, "local/Capsules-i125-1213.hdf5", 1e-8)) return;
    progress_log log = {0, 0, 0, 1};
    ck_assert_int_eq(frix_options_set_callback(f.o, on_progress, &log), FRIX_OK);
    file_run_solve(&f);
    ck_assert_int_eq(frix_info_status(f.info), FRIX_STATUS_CONVERGED);
    ck_assert_int_gt(log.calls, 10);
    ck_assert(log.monotone);
    ck_assert_int_le(log.last_iteration, frix_info_iterations(f.info));

    progress_log stop = {0, 0, 5, 1};
    ck_assert_int_eq(frix_options_set_callback(f.o, on_progress, &stop), FRIX_OK);
    file_run_solve(&f);
    ck_assert_int_eq(frix_info_status(f.info), FRIX_STATUS_STOPPED_BY_CALLBACK);
    ck_assert_int_eq(stop.calls, 5);
    file_run_close(&f);
}
END_TEST

/* The iteration limit and the time limit bound the whole sequence. */
START_TEST(test_limits) {
    file_run f;
    if (!file_run_open(&f, "converted/RockPile_tob1.from_dat.hdf5", 1e-12)) return;
    ck_assert_int_eq(frix_options_set_int(f.o, FRIX_OPT_MAX_ITER, 50), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(f.o, FRIX_OPT_EXISTENCE_CHECK, 0), FRIX_OK);
    file_run_solve(&f);
    ck_assert_int_eq(frix_info_status(f.info), FRIX_STATUS_MAX_ITER);
    ck_assert(isfinite(frix_info_error(f.info)));
    int64_t existence = -1;
    ck_assert_int_eq(frix_info_get_int(f.info, FRIX_INFO_EXISTENCE, &existence), FRIX_OK);
    ck_assert_int_eq(existence, FRIX_EXISTENCE_NOT_CHECKED);

    /* max_iter bounds the sum of the stages' iterations exactly (one thread), PROX's inner
     * Newton steps included: with every stage limited to half of what is left, PROX stages
     * of one outer step came late and overran 2000 by 45 until the watchdog enforced it. */
    ck_assert_int_eq(frix_options_set_int(f.o, FRIX_OPT_MAX_ITER, 2000), FRIX_OK);
    file_run_solve(&f);
    ck_assert_int_eq(frix_info_status(f.info), FRIX_STATUS_MAX_ITER);
    ck_assert_int_eq(frix_info_iterations(f.info), 2000);

    /* A run ended by its time limit still says whether a solution exists: frix_solve keeps
     * a share of the limit for the check. */
    ck_assert_int_eq(frix_options_set_int(f.o, FRIX_OPT_MAX_ITER, 1000000000), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(f.o, FRIX_OPT_EXISTENCE_CHECK, 1), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(f.o, FRIX_OPT_TIME_LIMIT, 0.2), FRIX_OK);
    file_run_solve(&f);
    ck_assert_int_eq(frix_info_status(f.info), FRIX_STATUS_TIME_LIMIT);
    ck_assert(isfinite(frix_info_error(f.info)));
    ck_assert_int_eq(frix_info_get_int(f.info, FRIX_INFO_EXISTENCE, &existence), FRIX_OK);
    ck_assert_int_ne(existence, FRIX_EXISTENCE_NOT_CHECKED);
    ck_assert_double_le(frix_info_solve_time(f.info), 0.2 * 1.5);

    /* Without a limit, a failure is followed by the check: RockPile has a solution. */
    ck_assert_int_eq(frix_options_set_double(f.o, FRIX_OPT_TIME_LIMIT, 0.0), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(f.o, FRIX_OPT_MAX_ITER, 50), FRIX_OK);
    file_run_solve(&f);
    ck_assert_int_eq(frix_info_status(f.info), FRIX_STATUS_MAX_ITER);
    ck_assert_int_eq(frix_info_get_int(f.info, FRIX_INFO_EXISTENCE, &existence), FRIX_OK);
    ck_assert_int_eq(existence, FRIX_EXISTENCE_GUARANTEED);
    /* The check is a record of the trace too (a note, not a run): the last one. */
    const int64_t last = frix_info_stage_count(f.info) - 1;
    ck_assert_int_eq(stage_int(f.info, last, FRIX_STAGE_SOLVER_ID), 0);
    ck_assert_ptr_nonnull(strstr(frix_info_stage_note(f.info, last), "existence"));
    file_run_close(&f);
}
END_TEST

int main(void) {
    Suite *s = suite_create("auto");
    TCase *tc = tcase_create("contract");
    tcase_set_timeout(tc, 300);
    tcase_add_test(tc, test_registered_and_default);
    tcase_add_test(tc, test_option_keys);
    tcase_add_test(tc, test_islands_and_threads);
    tcase_add_test(tc, test_switches_recorded);
    tcase_add_test(tc, test_callback_sees_progress_and_stops);
    tcase_add_test(tc, test_limits);
    suite_add_tcase(s, tc);
    return frix_run_suite(s);
}
