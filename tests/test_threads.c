/* Concurrency: many problems solved at once from several threads, on shared (const) problems,
 * each thread with its own options and info, give bit-identical results to serial runs;
 * FCLIB reads and writes from several threads at once; error messages stay per thread.
 * Built for ThreadSanitizer with -DFRIX_TSAN=ON (no data race may be reported).
 * No time limits here: a time limit makes the iteration count depend on the machine's load,
 * and these runs must be deterministic. */
#define _POSIX_C_SOURCE 200809L
#include <frix/frix.h>

#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check_main.h"
#include "scenes.h"

#define THREADS 3
#define MAX_ITER 40
#define MAX_CONTACTS 16 /* keep the set small: it runs under TSan, ASan and valgrind too */

typedef struct {
    const frix_problem *problem;
    int solver;
    frix_error err;
    frix_status status;
    int64_t iterations;
    double error;
    double *r, *u, *v; /* the serial result */
} job;

static frix_hard_case cases[64];
static int ncases = 0;
static job *jobs = NULL;
static int njobs = 0;

/* Solves job j into the given arrays (from r = 0, v = 0). */
static frix_error solve_job(const job *jb, double *r, double *u, double *v, frix_status *status,
                            int64_t *iterations, double *error) {
    const int64_t m = frix_problem_contact_dofs(jb->problem), n = frix_problem_dofs(jb->problem);
    memset(r, 0, sizeof(double) * (size_t)(m + 1));
    memset(v, 0, sizeof(double) * (size_t)(n + 1));
    frix_options *o = NULL;
    frix_info *info = NULL;
    frix_error err = frix_options_create(jb->solver, &o);
    if (!err) err = frix_options_set_int(o, FRIX_OPT_MAX_ITER, MAX_ITER);
    if (!err) err = frix_info_create(&info);
    if (!err)
        err = frix_solve(jb->problem, o, r, u,
                         frix_problem_get_kind(jb->problem) == FRIX_PROBLEM_GLOBAL ? v : NULL, info);
    *status = frix_info_status(info);
    *iterations = frix_info_iterations(info);
    *error = frix_info_error(info);
    frix_info_free(info);
    frix_options_free(o);
    return err;
}

static void setup(void) {
    for (int i = 0; i < frix_hard_case_count() && ncases < 64; ++i) {
        frix_hard_case *c = &cases[ncases];
        ck_assert_int_eq(frix_hard_case_make(i, c), FRIX_OK);
        if (frix_problem_contacts(c->problem) > MAX_CONTACTS) {
            frix_hard_case_free(c);
            continue;
        }
        ++ncases;
    }
    jobs = calloc((size_t)(ncases * frix_solver_count()), sizeof *jobs);
    for (int i = 0; i < ncases; ++i)
        for (int64_t k = 0; k < frix_solver_count(); ++k) {
            job *jb = &jobs[njobs];
            jb->problem = cases[i].problem;
            jb->solver = frix_solver_id_at(k);
            const int64_t m = frix_problem_contact_dofs(jb->problem), n = frix_problem_dofs(jb->problem);
            jb->r = calloc((size_t)m + 1, sizeof(double));
            jb->u = calloc((size_t)m + 1, sizeof(double));
            jb->v = calloc((size_t)n + 1, sizeof(double));
            jb->err = solve_job(jb, jb->r, jb->u, jb->v, &jb->status, &jb->iterations, &jb->error);
            if (jb->err == FRIX_ERR_UNSUPPORTED) {
                free(jb->r);
                free(jb->u);
                free(jb->v);
                continue;
            }
            ck_assert_msg(jb->err == FRIX_OK, "%s, solver %d: %s", cases[i].name, jb->solver,
                          frix_last_error_message());
            ++njobs;
        }
}

static void teardown(void) {
    for (int j = 0; j < njobs; ++j) {
        free(jobs[j].r);
        free(jobs[j].u);
        free(jobs[j].v);
    }
    free(jobs);
    jobs = NULL;
    njobs = 0;
    for (int i = 0; i < ncases; ++i) frix_hard_case_free(&cases[i]);
    ncases = 0;
}

typedef struct {
    int index;
    int only_solver, rounds; /* 0: every job; rounds over the job list */
    int runs, mismatches, failures;
    char first[256];
} worker;

static int same(const double *a, const double *b, int64_t n) {
    return n == 0 || memcmp(a, b, sizeof(double) * (size_t)n) == 0;
}

static void *solve_all(void *arg) {
    worker *w = arg;
    double *r = NULL, *u = NULL, *v = NULL;
    size_t cap_m = 0, cap_n = 0;
    for (int step = 0; step < njobs * w->rounds; ++step) {
        const job *jb = &jobs[(step + w->index * 7) % njobs]; /* each thread its own order */
        if (w->only_solver && jb->solver != w->only_solver) continue;
        const int64_t m = frix_problem_contact_dofs(jb->problem), n = frix_problem_dofs(jb->problem);
        if ((size_t)m + 1 > cap_m) {
            cap_m = (size_t)m + 1;
            free(r);
            free(u);
            r = malloc(cap_m * sizeof *r);
            u = malloc(cap_m * sizeof *u);
        }
        if ((size_t)n + 1 > cap_n) {
            cap_n = (size_t)n + 1;
            free(v);
            v = malloc(cap_n * sizeof *v);
        }
        frix_status status;
        int64_t iterations;
        double error;
        frix_error err = solve_job(jb, r, u, v, &status, &iterations, &error);
        ++w->runs;
        if (err != FRIX_OK) {
            if (!w->failures++)
                snprintf(w->first, sizeof w->first, "solver %d: error %d", jb->solver, err);
            continue;
        }
        const int global = frix_problem_get_kind(jb->problem) == FRIX_PROBLEM_GLOBAL;
        if (status != jb->status || iterations != jb->iterations ||
            memcmp(&error, &jb->error, sizeof error) != 0 || !same(r, jb->r, m) || !same(u, jb->u, m) ||
            (global && !same(v, jb->v, n))) {
            if (!w->mismatches++)
                snprintf(w->first, sizeof w->first,
                         "solver %d on '%s': status %d/%d, iterations %lld/%lld, error %.17g/%.17g",
                         jb->solver, frix_problem_title(jb->problem), status, jb->status,
                         (long long)iterations, (long long)jb->iterations, error, jb->error);
        }
    }
    free(r);
    free(u);
    free(v);
    return NULL;
}

/* Every job once per thread, or `rounds` times over the jobs of one solver. */
static void run_concurrently(int only_solver, int rounds) {
    setup();
    ck_assert_int_ge(njobs, 10);
    pthread_t t[THREADS];
    worker w[THREADS];
    memset(w, 0, sizeof w);
    for (int i = 0; i < THREADS; ++i) {
        w[i].index = i;
        w[i].only_solver = only_solver;
        w[i].rounds = rounds;
        ck_assert_int_eq(pthread_create(&t[i], NULL, solve_all, &w[i]), 0);
    }
    for (int i = 0; i < THREADS; ++i) ck_assert_int_eq(pthread_join(t[i], NULL), 0);
    int runs = 0;
    for (int i = 0; i < THREADS; ++i) {
        runs += w[i].runs;
        ck_assert_msg(w[i].failures == 0 && w[i].mismatches == 0,
                      "thread %d: %d failures, %d results differing from the serial run; first: %s", i,
                      w[i].failures, w[i].mismatches, w[i].first);
    }
    ck_assert_int_ge(runs, THREADS);
    printf("%d concurrent solves (%s, %d threads) bit-identical to serial\n", runs,
           only_solver ? frix_solver_name(only_solver) : "every problem x solver", THREADS);
    teardown();
}

START_TEST(test_concurrent_solves_match_serial) { run_concurrently(0, 1); }
END_TEST

/* gnsn-ac orders its Jacobian with METIS, which draws from libc's process-wide rand() after
 * srand(): two orderings at once would interleave their draws and pivot differently (seen
 * in about 1 of 30 runs of the test above). Many rounds of that solver alone make it show. */
START_TEST(test_concurrent_orderings_match_serial) { run_concurrently(FRIX_SOLVER_GLOBAL_NSN_AC, 40); }
END_TEST

/* ---- FCLIB from several threads (the library serialises HDF5 internally) -------------- */

typedef struct {
    int index;
    int failures;
    char first[256];
} io_worker;

static void *write_and_read(void *arg) {
    io_worker *w = arg;
    char path[512];
    for (int round = 0; round < 6; ++round) {
        const frix_hard_case *c = &cases[(w->index + round) % ncases];
        snprintf(path, sizeof path, "%s/threads_%d.hdf5", FRIX_TEST_TMPDIR, w->index);
        frix_problem *back = NULL;
        frix_error err = frix_fclib_write(path, c->problem, NULL, NULL, NULL, 0, NULL, NULL, NULL);
        if (!err) err = frix_fclib_read(path, &back);
        if (!err && (frix_problem_contacts(back) != frix_problem_contacts(c->problem) ||
                     strcmp(frix_problem_title(back), frix_problem_title(c->problem)) != 0))
            err = FRIX_ERR_INTERNAL;
        /* A failing read: the message is this thread's own. */
        char missing[512];
        snprintf(missing, sizeof missing, "%s/threads_missing_%d.hdf5", FRIX_TEST_TMPDIR, w->index);
        frix_problem *none = NULL;
        if (!err && (frix_fclib_read(missing, &none) != FRIX_ERR_IO ||
                     strstr(frix_last_error_message(), missing) == NULL))
            err = FRIX_ERR_INTERNAL;
        if (err && !w->failures++)
            snprintf(w->first, sizeof w->first, "%s: %d %s", c->name, err, frix_last_error_message());
        frix_problem_free(back);
    }
    return NULL;
}

START_TEST(test_concurrent_fclib_io) {
    setup();
    pthread_t t[THREADS];
    io_worker w[THREADS];
    memset(w, 0, sizeof w);
    for (int i = 0; i < THREADS; ++i) {
        w[i].index = i;
        ck_assert_int_eq(pthread_create(&t[i], NULL, write_and_read, &w[i]), 0);
    }
    for (int i = 0; i < THREADS; ++i) ck_assert_int_eq(pthread_join(t[i], NULL), 0);
    for (int i = 0; i < THREADS; ++i)
        ck_assert_msg(w[i].failures == 0, "thread %d: %s", i, w[i].first);
    teardown();
}
END_TEST

/* gnsgs sweeps domains of contacts, those of one colour at once on the threads: r, v, the
 * sweeps and the error are the same bit for bit with 1, 2 and 3 threads, with and without
 * acceleration (the loop's index). The pyramid of spheres (3312 contacts, bodies with many
 * contacts each) has 13 domains of 3 colours, so that every colour is shared among the
 * threads. */
START_TEST(test_domain_sweeps_bit_identical) {
    frix_scene_params prm;
    frix_scene_defaults(FRIX_SCENE_SPHERES, &prm);
    prm.count = 12;
    frix_scene scene;
    frix_scene_problems forms;
    ck_assert_int_eq(frix_scene_build(&prm, &scene, NULL), FRIX_OK);
    ck_assert_int_eq(frix_scene_problems_make(&scene, &forms), FRIX_OK);
    const int64_t m = 3 * scene.nc, n = scene.n;
    double *r[3], *v[3], *u = malloc(sizeof *u * (size_t)m);
    int64_t iterations[3];
    double error[3];
    for (int t = 0; t < 3; ++t) {
        r[t] = calloc((size_t)m, sizeof *r[t]);
        v[t] = calloc((size_t)n, sizeof *v[t]);
        frix_options *o = NULL;
        frix_info *info = NULL;
        ck_assert_int_eq(frix_options_create(FRIX_SOLVER_GLOBAL_NSGS, &o), FRIX_OK);
        ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_THREADS, t + 1), FRIX_OK);
        ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 1e-6), FRIX_OK);
        ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_MAX_ITER, 1500), FRIX_OK);
        ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_ACCELERATION, _i), FRIX_OK);
        ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
        ck_assert_int_eq(frix_solve(forms.global, o, r[t], u, v[t], info), FRIX_OK);
        iterations[t] = frix_info_iterations(info);
        error[t] = frix_info_error(info);
        ck_assert_int_gt(iterations[t], 10); /* the sweeps, not the start, decide the answer */
        frix_info_free(info);
        frix_options_free(o);
    }
    for (int t = 1; t < 3; ++t) {
        ck_assert_int_eq(iterations[t], iterations[0]);
        ck_assert(error[t] == error[0]);
        ck_assert_mem_eq(r[t], r[0], sizeof(double) * (size_t)m);
        ck_assert_mem_eq(v[t], v[0], sizeof(double) * (size_t)n);
    }
    for (int t = 0; t < 3; ++t) free(r[t]), free(v[t]);
    free(u);
    frix_scene_problems_free(&forms);
    frix_scene_free(&scene);
}
END_TEST

int main(void) {
    Suite *s = suite_create("threads");
    TCase *tc = tcase_create("core");
    tcase_set_timeout(tc, 600);
    tcase_add_test(tc, test_concurrent_solves_match_serial);
    tcase_add_test(tc, test_concurrent_orderings_match_serial);
    tcase_add_test(tc, test_concurrent_fclib_io);
    tcase_add_loop_test(tc, test_domain_sweeps_bit_identical, 0, 2);
    suite_add_tcase(s, tc);
    return frix_run_suite(s);
}
