/* auto (900): registered and the default, islands found and combined exactly, results
 * independent of the thread count, the trace and the switch count, the caller's callback,
 * and convergence to 1e-8 on every local and global problem of ../shared/fclib. */
#include <check.h>
#include <frix/frix.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check_main.h"
#include "stage_records.h"
#include "shared_data.h"
#include "scenes.h"

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

static frix_options *auto_options(double tol) {
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_AUTO, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, tol), FRIX_OK);
    return o;
}

/* One shared problem with what a solve of it needs: r, u, v (all zero), an info and auto's
 * options at `tol`. open() returns 0 when the shared data is absent (the test then passes). */
typedef struct {
    frix_problem *p;
    int64_t m;
    double *r, *u, *v;
    frix_info *info;
    frix_options *o;
} file_run;

static int file_run_open(file_run *f, const char *relative, double tol) {
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

/* Solves from r = 0 (v = 0). On a local problem, the u and the error returned must be those
 * of the r returned (measured again here). */
static void file_run_solve(file_run *f) {
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

static void file_run_close(file_run *f) {
    frix_options_free(f->o);
    frix_info_free(f->info);
    free(f->r);
    free(f->u);
    free(f->v);
    frix_problem_free(f->p);
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
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_LOCAL_SOLVER, 562), FRIX_ERR_UNKNOWN_OPTION);
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

/* The connected component of the contact graph (contacts a, b linked when W_ab != 0) that
 * has exactly `size` contacts, as a local problem of its own in island->p; returns 0 if there
 * is none. The problem borrows the arrays of `island`, freed by island_free. */
typedef struct {
    frix_matrix *W;
    double *q, *mu;
    int64_t *colptr, *rowind;
    double *values;
    frix_problem *p;
} island_part;

static int island_of_size(const frix_problem *whole, int64_t size, island_part *island) {
    memset(island, 0, sizeof *island);
    const int64_t nc = frix_problem_contacts(whole), m = 3 * nc;
    int64_t nnz = 0;
    ck_assert_int_eq(frix_matrix_to_csc(frix_problem_W(whole), &nnz, NULL, NULL, NULL), FRIX_OK);
    int64_t *cp = malloc((size_t)(m + 1) * sizeof *cp), *ri = malloc((size_t)nnz * sizeof *ri);
    double *vx = malloc((size_t)nnz * sizeof *vx);
    ck_assert_int_eq(frix_matrix_to_csc(frix_problem_W(whole), &nnz, cp, ri, vx), FRIX_OK);
    /* Components by repeated labelling over the (symmetric) block pattern. */
    int64_t *label = malloc((size_t)nc * sizeof *label), *stack = malloc((size_t)nc * sizeof *stack);
    int64_t *index = malloc((size_t)nc * sizeof *index);
    for (int64_t a = 0; a < nc; ++a) label[a] = -1;
    int64_t found = -1;
    for (int64_t seed = 0; seed < nc && found < 0; ++seed) {
        if (label[seed] >= 0) continue;
        int64_t top = 0, count = 0;
        label[seed] = seed;
        stack[top++] = seed;
        while (top > 0) {
            const int64_t a = stack[--top];
            ++count;
            for (int64_t j = 3 * a; j < 3 * a + 3; ++j)
                for (int64_t k = cp[j]; k < cp[j + 1]; ++k) {
                    const int64_t b = ri[k] / 3;
                    if (label[b] < 0) label[b] = seed, stack[top++] = b;
                }
        }
        if (count == size) found = seed;
    }
    if (found >= 0) {
        int64_t n = 0;
        for (int64_t a = 0; a < nc; ++a) index[a] = label[a] == found ? n++ : -1;
        island->colptr = calloc((size_t)(3 * n + 1), sizeof *island->colptr);
        island->rowind = malloc((size_t)nnz * sizeof *island->rowind);
        island->values = malloc((size_t)nnz * sizeof *island->values);
        island->q = malloc((size_t)(3 * n) * sizeof *island->q);
        island->mu = malloc((size_t)n * sizeof *island->mu);
        int64_t e = 0;
        for (int64_t a = 0; a < nc; ++a) {
            if (index[a] < 0) continue;
            island->mu[index[a]] = frix_problem_mu(whole)[a];
            for (int d = 0; d < 3; ++d) {
                const int64_t j = 3 * a + d;
                island->q[3 * index[a] + d] = frix_problem_q(whole)[j];
                for (int64_t k = cp[j]; k < cp[j + 1]; ++k) {
                    island->rowind[e] = 3 * index[ri[k] / 3] + ri[k] % 3;
                    island->values[e++] = vx[k];
                }
                island->colptr[3 * index[a] + d + 1] = e;
            }
        }
        ck_assert_int_eq(frix_matrix_from_csc(3 * n, 3 * n, island->colptr, island->rowind, island->values, &island->W),
                         FRIX_OK);
        ck_assert_int_eq(frix_problem_local(island->W, island->q, island->mu, n, &island->p), FRIX_OK);
    }
    free(cp), free(ri), free(vx), free(label), free(stack), free(index);
    return found >= 0;
}

static void island_free(island_part *island) {
    frix_problem_free(island->p);
    frix_matrix_free(island->W);
    free(island->q), free(island->mu), free(island->colptr), free(island->rowind), free(island->values);
}

/* RockPile's 25-contact island: Newton from r = 0 and from the best iterate stops at a
 * stationary point of its merit function (error ~5e-8) that is not a solution, NSGS needs
 * ~1.6 million sweeps. The random restarts of Newton solve it within a few thousand
 * iterations; before them auto had not converged after 10 s (2.2 million iterations). */
START_TEST(test_random_restarts_solve_rockpile_small_island) {
    frix_problem *whole = load("converted/RockPile_tob1.from_dat.hdf5");
    if (!whole) return;
    island_part island;
    ck_assert_msg(island_of_size(whole, 25, &island), "RockPile has a 25-contact island");
    const int64_t m = frix_problem_contact_dofs(island.p);
    double *r = calloc((size_t)m, sizeof *r), *u = calloc((size_t)m, sizeof *u);
    frix_options *o = NULL;
    frix_info *info = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_AUTO, &o), FRIX_OK);
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 1e-8), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_MAX_ITER, 20000), FRIX_OK);
    ck_assert_int_eq(frix_solve(island.p, o, r, u, NULL, info), FRIX_OK);
    ck_assert_msg(frix_info_status(info) == FRIX_STATUS_CONVERGED, "%s, error %.3e\n%s",
                  frix_status_string(frix_info_status(info)), frix_info_error(info), frix_info_trace(info));
    double e = NAN;
    ck_assert_int_eq(frix_problem_error(island.p, r, NULL, &e), FRIX_OK);
    ck_assert_double_le(e, 1e-8);
    int random_start_converged = 0;
    for (int64_t k = 0; k < frix_info_stage_count(info); ++k)
        random_start_converged |= stage_int(info, k, FRIX_STAGE_SOLVER_ID) == FRIX_SOLVER_NSN_AC &&
                                  stage_int(info, k, FRIX_STAGE_RANDOM_STARTS) == 1 &&
                                  stage_int(info, k, FRIX_STAGE_STATUS) == FRIX_STATUS_CONVERGED;
    ck_assert_msg(random_start_converged, "%s", frix_info_trace(info));

    /* Deterministic: the same draws, the same iterations and reactions. */
    double *r2 = calloc((size_t)m, sizeof *r2);
    const int64_t iterations = frix_info_iterations(info);
    ck_assert_int_eq(frix_solve(island.p, o, r2, u, NULL, info), FRIX_OK);
    ck_assert_int_eq(frix_info_iterations(info), iterations);
    ck_assert_mem_eq(r, r2, (size_t)m * sizeof *r);

    free(r), free(r2), free(u);
    frix_info_free(info);
    frix_options_free(o);
    island_free(&island);
    frix_problem_free(whole);
}
END_TEST

/* Two contacts pressing one body from opposite sides (u_0N = r_0N - r_1N - 1, u_1N = r_1N - r_0N
 * - 1): no solution, and with the |q| measure no run can pass, so auto goes round after round
 * until its iteration limit, Newton stalling every time on this small part. Round k makes 2^k
 * random starts; the trace must give each round's starts one line (2^k of them). (An
 * iteration limit, not a time limit: under valgrind 0.5 s gave one round only.) */
START_TEST(test_random_restarts_one_trace_line_per_round) {
    double Wd[36] = {0};
    Wd[0] = Wd[3 * 6 + 3] = 1.0, Wd[3] = Wd[3 * 6] = -1.0;
    Wd[1 * 6 + 1] = Wd[2 * 6 + 2] = Wd[4 * 6 + 4] = Wd[5 * 6 + 5] = 1.0;
    const double q[6] = {-1, 0.1, 0, -1, 0.1, 0}, mu[2] = {0.3, 0.3};
    double r[6] = {0}, u[6];
    frix_matrix *W = NULL;
    frix_problem *p = NULL;
    frix_options *o = NULL;
    frix_info *info = NULL;
    ck_assert_int_eq(frix_matrix_from_dense(6, 6, Wd, 6, &W), FRIX_OK);
    ck_assert_int_eq(frix_problem_local(W, q, mu, 2, &p), FRIX_OK);
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_AUTO, &o), FRIX_OK);
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_ERROR_MEASURE, FRIX_MEASURE_Q_RELATIVE), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_MAX_ITER, 100000), FRIX_OK);
    ck_assert_int_eq(frix_solve(p, o, r, u, NULL, info), FRIX_OK);
    ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_MAX_ITER);
    ck_assert_int_eq(frix_info_iterations(info), 100000);
    const int64_t lines = frix_info_stage_count(info);
    int64_t restart_lines = 0, newton_lines = 0;
    long long starts_of[64] = {0};
    for (int64_t k = 0; k < lines; ++k) {
        const int64_t starts = stage_int(info, k, FRIX_STAGE_RANDOM_STARTS);
        if (starts > 0) {
            ck_assert_int_lt(restart_lines, 64);
            ck_assert_int_eq(stage_int(info, k, FRIX_STAGE_SOLVER_ID), FRIX_SOLVER_NSN_AC);
            starts_of[restart_lines++] = starts;
        } else if (stage_int(info, k, FRIX_STAGE_SOLVER_ID) == FRIX_SOLVER_NSN_AC) {
            ++newton_lines;
        }
    }
    ck_assert_int_ge(restart_lines, 2);
    /* Round k: 2^k starts; the iteration limit may cut the last round's short. */
    for (int64_t k = 0; k < restart_lines; ++k) {
        const long long expected = 1LL << k;
        if (k + 1 < restart_lines)
            ck_assert_msg(starts_of[k] == expected, "round %lld: %lld starts", (long long)k, starts_of[k]);
        else
            ck_assert(starts_of[k] >= 1 && starts_of[k] <= expected);
    }
    /* Newton from r = 0 and from the best iterate: one or two lines a round, never more. */
    ck_assert_int_le(restart_lines, newton_lines);
    ck_assert_int_le(lines, 8 * restart_lines + 8);
    frix_info_free(info);
    frix_options_free(o);
    frix_problem_free(p);
    frix_matrix_free(W);
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

static void solve_to_1e8(const char *relative) {
    file_run f;
    if (!file_run_open(&f, relative, 1e-8)) return;
    file_run_solve(&f);
    if (frix_info_status(f.info) != FRIX_STATUS_CONVERGED) fprintf(stderr, "%s\n%s", relative, frix_info_trace(f.info));
    ck_assert_msg(frix_info_status(f.info) == FRIX_STATUS_CONVERGED, "%s: %s, error %.3e (trace above)", relative,
                  frix_status_string(frix_info_status(f.info)), frix_info_error(f.info));
    double e = NAN;
    ck_assert_int_eq(frix_problem_error(f.p, f.r, f.v, &e), FRIX_OK);
    ck_assert_msg(e <= 1e-8, "%s: recomputed error %.3e", relative, e);
    file_run_close(&f);
}



/* Every local problem of ../shared/fclib (RockPile_tob1 in its own test, below). */
START_TEST(test_every_local_fclib_problem) {
    if (strstr(kFclibLocalProblems[_i], "RockPile")) return;
    solve_to_1e8(kFclibLocalProblems[_i]);
}
END_TEST

/* RockPile_tob1: its 295-contact island is solved by NSGS's stages, one chain across the rounds
 * that carries the steady drifts of r ahead (about 540000 iterations in all, 13 s). Restarted
 * from the best iterate every round and without the drift jumps, auto needed 9.2 million
 * iterations (220 s). */
START_TEST(test_rockpile_by_the_nsgs_chain) {
    file_run f;
    if (!file_run_open(&f, "converted/RockPile_tob1.from_dat.hdf5", 1e-8)) return;
    ck_assert_int_eq(frix_options_set_int(f.o, FRIX_OPT_MAX_ITER, 2000000), FRIX_OK);
    file_run_solve(&f);
    ck_assert_msg(frix_info_status(f.info) == FRIX_STATUS_CONVERGED, "%s after %lld iterations, error %.3e",
                  frix_status_string(frix_info_status(f.info)), (long long)frix_info_iterations(f.info),
                  frix_info_error(f.info));
    double e = NAN;
    ck_assert_int_eq(frix_problem_error(f.p, f.r, NULL, &e), FRIX_OK);
    ck_assert_double_le(e, 1e-8);
    file_run_close(&f);
}
END_TEST

/* The first NSGS stage (plain on a part of fewer than 64 contacts, velocity form on a
 * larger one), or -1. */
static int64_t first_nsgs_stage(const frix_info *info) {
    const int64_t plain = find_stage(info, FRIX_SOLVER_NSGS, 0), velocity = find_stage(info, FRIX_SOLVER_NSGS_VELOCITY, 0);
    return plain < 0 ? velocity : velocity < 0 ? plain : plain < velocity ? plain : velocity;
}

/* The sweeps of the first NSGS stage from r = 0 on a problem (-1 without one), and whether
 * that stage converged. */
static int64_t first_nsgs_sweeps(const frix_info *info, int *converged) {
    const int64_t k = first_nsgs_stage(info);
    *converged = k >= 0 && stage_int(info, k, FRIX_STAGE_STATUS) == FRIX_STATUS_CONVERGED;
    return k >= 0 ? stage_int(info, k, FRIX_STAGE_ITERATIONS) : -1;
}

/* The first NSGS stage is judged by its rate once it has done 1e5 block operations (sweeps x
 * W blocks): on OneObject-i100000 (25 contacts, 207 blocks) it is slow and is stopped after
 * 483 sweeps, where Newton finishes in a few steps (966 sweeps with 2e5); on
 * LMGC_100_PR_PerioBox (60 contacts) it converges after 35 sweeps, which a judgement after 3e4
 * operations or less would cut short, handing the problem to the costlier stages. */
START_TEST(test_first_nsgs_judged_after_its_work) {
    file_run f;
    if (!file_run_open(&f, "converted/OneObject-i100000-316.from_dat.hdf5", 1e-8)) return;
    file_run_solve(&f);
    int converged = 0;
    int64_t sweeps = first_nsgs_sweeps(f.info, &converged);
    ck_assert_msg(frix_info_status(f.info) == FRIX_STATUS_CONVERGED && !converged && sweeps >= 30 &&
                      sweeps <= 600,
                  "%s\n", frix_info_trace(f.info));
    file_run_close(&f);
    if (!file_run_open(&f, "local/LMGC_100_PR_PerioBox-i00361-60-03000.hdf5", 1e-8)) return;
    frix_test_siconos_measure(f.o);
    file_run_solve(&f);
    sweeps = first_nsgs_sweeps(f.info, &converged);
    ck_assert_msg(frix_info_status(f.info) == FRIX_STATUS_CONVERGED && converged && sweeps > 0,
                  "%s\n", frix_info_trace(f.info));
    file_run_close(&f);
}
END_TEST

/* Contacts in units that differ by decades (OneObject-i100000 rescaled per contact by
 * 10^[-2, 2]): auto sees the spread of |W_aa| and gives ADMM per-contact penalties; it
 * converges in 1277 iterations where, with one penalty for all contacts, it needed 18386. */
START_TEST(test_contacts_in_different_units) {
    scaled_problem sp;
    if (!scaled_problem_load(&sp, "converted/OneObject-i100000-316.from_dat.hdf5", 2.0)) return;
    const int64_t m = frix_problem_contact_dofs(sp.p);
    double *r = calloc((size_t)m, sizeof *r), *u = calloc((size_t)m, sizeof *u);
    frix_options *o = auto_options(1e-8);
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_solve(sp.p, o, r, u, NULL, info), FRIX_OK);
    double err = NAN;
    ck_assert_int_eq(frix_problem_error(sp.p, r, NULL, &err), FRIX_OK);
    ck_assert_msg(frix_info_status(info) == FRIX_STATUS_CONVERGED && err <= 1e-8, "%s, error %g",
                  frix_status_string(frix_info_status(info)), err);
    ck_assert_msg(frix_info_iterations(info) < 3000, "%lld iterations",
                  (long long)frix_info_iterations(info));
    frix_info_free(info);
    frix_options_free(o);
    scaled_problem_free(&sp);
    free(r);
    free(u);
}
END_TEST

/* At a loose tolerance on a large pile where NSGS stalls (the 8-layer pyramid of spheres, 960
 * contacts), ADMM is weighed against the interior-point stage by their prices and comes
 * first: auto converges by ADMM, and no factorising stage runs. */
START_TEST(test_loose_tolerance_pile_solved_by_admm_first) {
    frix_scene_params sp;
    frix_scene_defaults(FRIX_SCENE_SPHERES, &sp);
    sp.count = 8;
    frix_scene scene;
    ck_assert_int_eq(frix_scene_build(&sp, &scene, NULL), FRIX_OK);
    frix_scene_problems pr;
    ck_assert_int_eq(frix_scene_problems_make(&scene, &pr), FRIX_OK);
    ck_assert_int_eq(scene.nc, 960);
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_AUTO, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 1e-4), FRIX_OK);
    double *r = calloc((size_t)(3 * scene.nc), sizeof *r), *u = calloc((size_t)(3 * scene.nc), sizeof *u);
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_solve(pr.local, o, r, u, NULL, info), FRIX_OK);
    const char *trace = frix_info_trace(info);
    ck_assert_msg(frix_info_status(info) == FRIX_STATUS_CONVERGED, "%s\n%s",
                  frix_status_string(frix_info_status(info)), trace);
    const int64_t admm = find_stage(info, FRIX_SOLVER_ADMM, 0);
    ck_assert_msg(admm >= 0 && stage_int(info, admm, FRIX_STAGE_STATUS) == FRIX_STATUS_CONVERGED,
                  "no converged ADMM stage:\n%s", trace);
    ck_assert_msg(find_stage(info, FRIX_SOLVER_IPM, 0) < 0 && find_stage(info, FRIX_SOLVER_NSN_AC, 0) < 0,
                  "a factorising stage ran:\n%s", trace);
    double e = NAN;
    ck_assert_int_eq(frix_problem_error(pr.local, r, NULL, &e), FRIX_OK);
    ck_assert_double_le(e, 1e-4);
    frix_info_free(info);
    free(r);
    free(u);
    frix_options_free(o);
    frix_scene_problems_free(&pr);
    frix_scene_free(&scene);
}
END_TEST

/* Kapla-4x2x25-ball s100 (fclib-large): the interior-point run on its 941-contact island
 * stalls (at 1.8e-7 with OpenBLAS on one thread, 5.6e-7 on two), Newton from that iterate
 * lowers the error further (converges, or ends within 100 x the tolerance, and its point is
 * kept), and auto converges in a few hundred iterations, where the rounds from NSGS's iterate
 * needed about 30000 (10 s). */
START_TEST(test_newton_from_stalled_interior_point) {
    file_run f;
    if (!file_run_open(&f, "../fclib-large/Kapla-4x2x25-ball-seed2-s00100-nc2895.hdf5", 1e-8)) return;
    file_run_solve(&f);
    const char *trace = frix_info_trace(f.info);
    ck_assert_msg(frix_info_status(f.info) == FRIX_STATUS_CONVERGED, "%s, error %.3e\n%s",
                  frix_status_string(frix_info_status(f.info)), frix_info_error(f.info), trace);
    double e = NAN;
    ck_assert_int_eq(frix_problem_error(f.p, f.r, NULL, &e), FRIX_OK);
    ck_assert_double_le(e, 1e-8);
    const int64_t ipm = find_stage(f.info, FRIX_SOLVER_IPM, 0);
    ck_assert_msg(ipm >= 0 && stage_int(f.info, ipm, FRIX_STAGE_STATUS) == FRIX_STATUS_STAGNATED,
                  "no stalled interior-point stage:\n%s", trace);
    ck_assert_msg(ipm + 1 < frix_info_stage_count(f.info) &&
                      stage_int(f.info, ipm + 1, FRIX_STAGE_SOLVER_ID) == FRIX_SOLVER_NSN_AC,
                  "no Newton stage right after the interior-point stage:\n%s", trace);
    ck_assert_msg(stage_double(f.info, ipm + 1, FRIX_STAGE_ERROR) < stage_double(f.info, ipm, FRIX_STAGE_ERROR),
                  "Newton did not improve on the interior point:\n%s", trace);
    /* And by a decade at least, within its first budget (100 steps): the interior point is
     * within Newton's reach. */
    ck_assert_msg(stage_double(f.info, ipm + 1, FRIX_STAGE_ERROR) <= 0.1 * stage_double(f.info, ipm, FRIX_STAGE_ERROR) &&
                      stage_int(f.info, ipm + 1, FRIX_STAGE_ITERATIONS) <= 100,
                  "Newton did not take the interior point a decade down:\n%s", trace);
    file_run_close(&f);
}
END_TEST

/* Spheres-n400 s140 (fclib-large) capped at 170 iterations: the interior-point stage and
 * Newton after it reach about 1.7e-3, far above 100 x the tolerance, so the rounds start from
 * NSGS's 2.2e-2 instead, and the cap ends them above the interior point's result (1.3e-2).
 * That result is returned, not the rounds' best: the answer is the best of every stage. */
START_TEST(test_set_aside_interior_point_returned) {
    file_run f;
    if (!file_run_open(&f, "../fclib-large/Spheres-n400-seed2-s00140-nc1165.hdf5", 1e-8)) return;
    ck_assert_int_eq(frix_options_set_int(frix_test_siconos_measure(f.o), FRIX_OPT_MAX_ITER, 170), FRIX_OK);
    file_run_solve(&f);
    const char *trace = frix_info_trace(f.info);
    ck_assert_int_eq(frix_info_status(f.info), FRIX_STATUS_MAX_ITER);
    double best = INFINITY, last = NAN;
    int after_ipm = 0, rounds_above = 0;
    for (int64_t k = 0; k < frix_info_stage_count(f.info); ++k) {
        if (stage_int(f.info, k, FRIX_STAGE_PART) != 1 || stage_int(f.info, k, FRIX_STAGE_SOLVER_ID) == 0) continue;
        const double e = stage_double(f.info, k, FRIX_STAGE_ERROR);
        if (e < best) best = e;
        last = e;
        if (after_ipm && e > best) rounds_above = 1;
        if (stage_int(f.info, k, FRIX_STAGE_SOLVER_ID) == FRIX_SOLVER_IPM) after_ipm = 1;
    }
    ck_assert_msg(after_ipm && rounds_above && last > best, "not the case meant:\n%s", trace);
    const double e = frix_test_error_of(f.p, f.r, NULL, f.o);
    /* (the part's own measure against the whole problem's: the same up to rounding) */
    ck_assert_msg(e <= 1.001 * best, "returned %.4e, best stage %.4e\n%s", e, best, trace);
    file_run_close(&f);
}
END_TEST

/* Kapla-3x3x20 s30 (fclib-large, nine towers of blocks of about 311 contacts) at 1e-6: on each
 * tower NSGS's rate predicts more than ADMM's probe costs, ADMM from r = 0 then converges
 * within the probe (about 50 iterations, where NSGS alone sweeps about 3500 times: its
 * primal residual is exactly 0 at first, the contacts inside their cones, and rho must fall
 * for it to converge), and no other stage runs. */
START_TEST(test_towers_at_simulation_tolerance_by_admm_probe) {
    file_run f;
    if (!file_run_open(&f, "../fclib-large/Kapla-3x3x20-seed1-s00030-nc2799.hdf5", 1e-6)) return;
    file_run_solve(&f);
    const char *trace = frix_info_trace(f.info);
    ck_assert_msg(frix_info_status(f.info) == FRIX_STATUS_CONVERGED, "%s\n%s",
                  frix_status_string(frix_info_status(f.info)), trace);
    int64_t parts = 0;
    ck_assert_int_eq(frix_info_get_int(f.info, FRIX_INFO_ISLANDS, &parts), FRIX_OK);
    ck_assert_int_eq(parts, 9);
    for (int64_t part = 1; part <= parts; ++part) {
        int64_t nsgs = -1, admm = -1, stages = 0;
        for (int64_t k = 0; k < frix_info_stage_count(f.info); ++k) {
            if (stage_int(f.info, k, FRIX_STAGE_PART) != part || stage_int(f.info, k, FRIX_STAGE_SOLVER_ID) == 0) continue;
            ++stages;
            if (stage_int(f.info, k, FRIX_STAGE_SOLVER_ID) == FRIX_SOLVER_NSGS_VELOCITY) nsgs = k;
            if (stage_int(f.info, k, FRIX_STAGE_SOLVER_ID) == FRIX_SOLVER_ADMM) admm = k;
        }
        ck_assert_msg(stages == 2 && nsgs >= 0 && admm == nsgs + 1, "part %lld: not NSGS then ADMM:\n%s",
                      (long long)part, trace);
        ck_assert_msg(stage_int(f.info, nsgs, FRIX_STAGE_STOPPED_BY_AUTO) == 1 &&
                          stage_int(f.info, nsgs, FRIX_STAGE_ITERATIONS) < 1000,
                      "part %lld: NSGS not stopped early:\n%s", (long long)part, trace);
        ck_assert_msg(stage_int(f.info, admm, FRIX_STAGE_STATUS) == FRIX_STATUS_CONVERGED &&
                          stage_int(f.info, admm, FRIX_STAGE_ITERATIONS) <= 100,
                      "part %lld: ADMM did not converge within its probe:\n%s", (long long)part, trace);
    }
    double e = NAN;
    ck_assert_int_eq(frix_problem_error(f.p, f.r, NULL, &e), FRIX_OK);
    ck_assert_double_le(e, 1e-6);
    file_run_close(&f);
}
END_TEST

/* Capsules-i125 (36 islands, the largest 57 contacts) at 1e-4: the small parts, whose |q| is
 * a small share of the whole problem's, stop at errors of their own up to 100 x the
 * tolerance, and the whole problem still meets it: one NSGS stage per part, no Newton (which
 * a part of 17 contacts needed when held to 1e-4 of its own size). */
START_TEST(test_small_parts_held_to_their_share) {
    const double tol = 1e-5;
    file_run f;
    if (!file_run_open(&f, "local/Capsules-i125-1213.hdf5", tol)) return;
    file_run_solve(&f);
    const char *trace = frix_info_trace(f.info);
    ck_assert_msg(frix_info_status(f.info) == FRIX_STATUS_CONVERGED, "%s\n%s",
                  frix_status_string(frix_info_status(f.info)), trace);
    /* The sweeps on the whole problem first (part 0), then one converged NSGS per part. */
    ck_assert_msg(stage_int(f.info, 1, FRIX_STAGE_SOLVER_ID) == FRIX_SOLVER_NSGS &&
                      stage_int(f.info, 1, FRIX_STAGE_PART) == 0 &&
                      stage_int(f.info, 1, FRIX_STAGE_STATUS) == FRIX_STATUS_MAX_ITER,
                  "%s", trace);
    int loosened = 0;
    for (int64_t k = 2; k < frix_info_stage_count(f.info); ++k) {
        const int64_t id = stage_int(f.info, k, FRIX_STAGE_SOLVER_ID);
        ck_assert_msg((id == FRIX_SOLVER_NSGS_VELOCITY || id == FRIX_SOLVER_NSGS) &&
                          stage_int(f.info, k, FRIX_STAGE_STATUS) == FRIX_STATUS_CONVERGED,
                      "a stage other than one converged NSGS per part:\n%s", trace);
        loosened += stage_double(f.info, k, FRIX_STAGE_ERROR) > tol;
    }
    ck_assert_msg(loosened > 0, "no part stopped above the tolerance:\n%s", trace);
    double e = NAN;
    ck_assert_int_eq(frix_problem_error(f.p, f.r, NULL, &e), FRIX_OK);
    ck_assert_double_le(e, tol);
    file_run_close(&f);
}
END_TEST

/* NSGS near the tolerance on a plateau of its error (spheres-in-a-box at 1e-4: 1.7e-4 from
 * about sweep 100 to 750): stopped by its rate within 3 times the tolerance, it goes on for
 * the work of ADMM's probe before the probe, and crosses the plateau: no ADMM stage runs. */
START_TEST(test_nsgs_crosses_a_plateau_before_the_probe) {
    file_run f;
    if (!file_run_open(&f, "converted/spheres-in-a-box-98-i10000-256-10.reduced.hdf5", 1e-4)) return;
    frix_test_siconos_measure(f.o);
    file_run_solve(&f);
    const char *trace = frix_info_trace(f.info);
    ck_assert_msg(frix_info_status(f.info) == FRIX_STATUS_CONVERGED, "%s", trace);
    ck_assert_msg(find_stage(f.info, FRIX_SOLVER_ADMM, 0) < 0, "%s", trace);
    const int64_t first = find_stage(f.info, FRIX_SOLVER_NSGS_VELOCITY, 0);
    ck_assert_msg(first >= 0 && stage_int(f.info, first, FRIX_STAGE_STATUS) != FRIX_STATUS_CONVERGED, "%s", trace);
    const int64_t after = find_stage(f.info, FRIX_SOLVER_NSGS_VELOCITY, first + 1);
    ck_assert_msg(after >= 0 && stage_int(f.info, after, FRIX_STAGE_STATUS) == FRIX_STATUS_CONVERGED, "%s", trace);
    file_run_close(&f);
}
END_TEST

/* A priced part whose NSGS rate promises the tolerance within three times its sweeps but
 * not within twice, while the factorising alternative is priced lower (Spheres-n400 s200 at
 * 1e-6, one part of 1171 contacts): NSGS is stopped after ADMM's probe and ADMM from r = 0
 * finishes the part. Under the patience of unpriced parts (three times) NSGS went on to the
 * tolerance at about twice the cost. */
START_TEST(test_priced_part_stops_a_late_promise) {
    file_run f;
    if (!file_run_open(&f, "../fclib-large/Spheres-n400-seed2-s00200-nc1186.hdf5", 1e-6)) return;
    frix_test_siconos_measure(f.o);
    file_run_solve(&f);
    const char *trace = frix_info_trace(f.info);
    ck_assert_msg(frix_info_status(f.info) == FRIX_STATUS_CONVERGED, "%s", trace);
    const int64_t probe = find_stage(f.info, FRIX_SOLVER_ADMM, 0);
    const int64_t nsgs = probe < 0 ? -1 : find_stage(f.info, FRIX_SOLVER_NSGS_VELOCITY, probe + 1);
    ck_assert_msg(nsgs > probe && stage_int(f.info, nsgs, FRIX_STAGE_STOPPED_BY_AUTO) == 1, "%s", trace);
    const int64_t admm = find_stage(f.info, FRIX_SOLVER_ADMM, nsgs + 1);
    ck_assert_msg(admm > nsgs && stage_int(f.info, admm, FRIX_STAGE_STATUS) == FRIX_STATUS_CONVERGED, "%s", trace);
    file_run_close(&f);
}
END_TEST

/* A small part that NSGS does not finish, at a loose tolerance: Newton from r = 0 for a few
 * steps, then the interior point, whose solution is not polished (local_problem_test at 1e-4:
 * NSGS stalls at 8e-3, Newton alone takes 67 line-searched steps, the IPM 8). At 1e-8 the
 * rounds run as before: no interior-point stage. */
START_TEST(test_small_part_at_loose_tolerance_by_interior_point) {
    file_run f;
    if (!file_run_open(&f, "local/local_problem_test.hdf5", 1e-4)) return;
    file_run_solve(&f);
    const char *trace = frix_info_trace(f.info);
    ck_assert_msg(frix_info_status(f.info) == FRIX_STATUS_CONVERGED, "%s", trace);
    const int64_t newton = find_stage(f.info, FRIX_SOLVER_NSN_AC, 0), ipm = find_stage(f.info, FRIX_SOLVER_IPM, 0);
    ck_assert_msg(newton >= 0 && stage_int(f.info, newton, FRIX_STAGE_ITERATIONS) <= 10 && ipm > newton &&
                      stage_int(f.info, ipm, FRIX_STAGE_STATUS) == FRIX_STATUS_CONVERGED &&
                      ipm == frix_info_stage_count(f.info) - 1,
                  "%s", trace);
    file_run_close(&f);
    if (!file_run_open(&f, "local/local_problem_test.hdf5", 1e-8)) return;
    file_run_solve(&f);
    trace = frix_info_trace(f.info);
    ck_assert_msg(frix_info_status(f.info) == FRIX_STATUS_CONVERGED && find_stage(f.info, FRIX_SOLVER_IPM, 0) < 0,
                  "%s", trace);
    file_run_close(&f);
}
END_TEST

/* Before any part is set up: a problem of several parts that NSGS solves in a few sweeps ends
 * in the sweeps on the whole of it, and a small problem that is one part runs its first
 * stage at once, the same NSGS as the nsgs solver's (same iterations, same r). */
START_TEST(test_easy_problems_before_the_parts) {
    file_run f;
    if (!file_run_open(&f, "local/Capsules-i125-1213.hdf5", 1e-4)) return;
    file_run_solve(&f);
    const char *trace = frix_info_trace(f.info);
    ck_assert_msg(frix_info_status(f.info) == FRIX_STATUS_CONVERGED && frix_info_stage_count(f.info) == 2 &&
                      stage_int(f.info, 1, FRIX_STAGE_SOLVER_ID) == FRIX_SOLVER_NSGS &&
                      stage_int(f.info, 1, FRIX_STAGE_PART) == 0,
                  "%s", trace);
    int64_t islands = 0;
    ck_assert_int_eq(frix_info_get_int(f.info, FRIX_INFO_ISLANDS, &islands), FRIX_OK);
    ck_assert_int_eq(islands, 36);
    file_run_close(&f);

    if (!file_run_open(&f, "converted/FC3D_Example1.from_dat.hdf5", 1e-8)) return;
    file_run_solve(&f);
    ck_assert_msg(frix_info_status(f.info) == FRIX_STATUS_CONVERGED && frix_info_stage_count(f.info) == 2 &&
                      stage_int(f.info, 1, FRIX_STAGE_SOLVER_ID) == FRIX_SOLVER_NSGS,
                  "%s", frix_info_trace(f.info));
    double *r = calloc((size_t)f.m + 1, sizeof *r), *u = calloc((size_t)f.m + 1, sizeof *u);
    frix_options *o = NULL;
    frix_info *info = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_NSGS, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 1e-8), FRIX_OK);
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_solve(f.p, o, r, u, NULL, info), FRIX_OK);
    ck_assert_int_eq(frix_info_iterations(info), frix_info_iterations(f.info));
    ck_assert_mem_eq(r, f.r, (size_t)f.m * sizeof *r);
    frix_options_free(o);
    frix_info_free(info);
    free(r);
    free(u);
    file_run_close(&f);
}
END_TEST

static const char *const kGlobalFiles[] = {
    "global/Box_Stacks-i0035-31-0.hdf5",
    "global/CubeH8.hdf5",
    "global/LMGC_GFC3D-i00501-4-00000.hdf5",
    "global/spheres-in-a-box-98-i10000-256-10.hdf5",
};

START_TEST(test_global_fclib_problems) { solve_to_1e8(kGlobalFiles[_i]); }
END_TEST

int main(void) {
    Suite *s = suite_create("auto");
    TCase *tc = tcase_create("auto");
    tcase_set_timeout(tc, 300);
    tcase_add_test(tc, test_registered_and_default);
    tcase_add_test(tc, test_option_keys);
    tcase_add_test(tc, test_islands_and_threads);
    tcase_add_test(tc, test_switches_recorded);
    tcase_add_test(tc, test_callback_sees_progress_and_stops);
    tcase_add_test(tc, test_limits);
    tcase_add_test(tc, test_random_restarts_solve_rockpile_small_island);
    tcase_add_test(tc, test_random_restarts_one_trace_line_per_round);
    tcase_add_test(tc, test_set_aside_interior_point_returned);
    tcase_add_test(tc, test_towers_at_simulation_tolerance_by_admm_probe);
    tcase_add_test(tc, test_small_parts_held_to_their_share);
    tcase_add_test(tc, test_easy_problems_before_the_parts);
    tcase_add_test(tc, test_nsgs_crosses_a_plateau_before_the_probe);
    tcase_add_test(tc, test_small_part_at_loose_tolerance_by_interior_point);
    tcase_add_test(tc, test_priced_part_stops_a_late_promise);
    tcase_add_test(tc, test_contacts_in_different_units);
    tcase_add_test(tc, test_newton_from_stalled_interior_point);
    tcase_add_test(tc, test_rockpile_by_the_nsgs_chain);
    tcase_add_test(tc, test_first_nsgs_judged_after_its_work);
    tcase_add_test(tc, test_loose_tolerance_pile_solved_by_admm_first);
    tcase_add_loop_test(tc, test_every_local_fclib_problem, 0, FRIX_FCLIB_LOCAL_COUNT);
    tcase_add_loop_test(tc, test_global_fclib_problems, 0, (int)(sizeof kGlobalFiles / sizeof kGlobalFiles[0]));
    suite_add_tcase(s, tc);
    return frix_run_suite(s);
}
