/* nsgs-v's pushes through a single-precision copy of a large dense W (solvers/kit/
 * single_columns.hpp): forced on problems small enough for the suite (frix_testing.h), the run
 * still meets tight tolerances by the double measure and agrees with the double pushes'
 * answer; below the size that takes them, frix_solve's nsgs-v is the double path to the bit.
 * On a grid past that size, a persistent nsgs-v sweeps its active part. */
#include <frix/frix.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check_main.h"
#include "elastic_grid.h"
#include "frix_testing.h"
#include "shared_data.h"

/* The log sink: whether a line told of the single-precision pushes. */
static void note_single(void *data, const char *line) {
    if (strstr(line, "single precision")) *(int *)data = 1;
}

enum route { PUBLIC, SINGLE, DOUBLE };

typedef struct {
    frix_status status;
    int64_t iterations;
    double error;  /* frix_problem_error of (r, v): the double measure, recomputed */
    int logged_single;
    double *r, *u, *v;
} run;

/* A run's arrays for p, zero. */
static run run_make(const frix_problem *p) {
    const int64_t m = frix_problem_contact_dofs(p), n = frix_problem_dofs(p);
    run out = {0, 0, NAN, 0, calloc((size_t)m, sizeof(double)), calloc((size_t)m, sizeof(double)),
               calloc((size_t)(n > 0 ? n : 1), sizeof(double))};
    ck_assert(out.r && out.u && out.v);
    return out;
}

/* nsgs-v with options o from r = 0 into out, by frix_solve (PUBLIC) or with the pushes forced
 * into single (SINGLE) or double (DOUBLE) precision where W suits them; o is freed. */
static void run_solve(const frix_problem *p, enum route route, frix_options *o, run *out) {
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    double *v = frix_problem_dofs(p) > 0 ? out->v : NULL;
    const int e = route == PUBLIC ? frix_solve(p, o, out->r, out->u, v, info)
                                  : frix_testing_nsgs_velocity(route == SINGLE, p, o, out->r, out->u, v, info);
    ck_assert_msg(e == FRIX_OK, "%s", frix_last_error_message());
    out->status = frix_info_status(info);
    out->iterations = frix_info_iterations(info);
    ck_assert_int_eq(frix_problem_error(p, out->r, v, &out->error), FRIX_OK);
    frix_info_free(info);
    frix_options_free(o);
}

/* nsgs-v at `tol` by `route` under the option memory_limit (0: none). */
static run solve_limited(const frix_problem *p, enum route route, double tol, double memory_limit) {
    run out = run_make(p);
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_NSGS_VELOCITY, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, tol), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_VERBOSITY, 1), FRIX_OK);
    ck_assert_int_eq(frix_options_set_log(o, note_single, &out.logged_single), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_MEMORY_LIMIT, memory_limit), FRIX_OK);
    run_solve(p, route, o, &out);
    return out;
}

static run solve(const frix_problem *p, enum route route, double tol) { return solve_limited(p, route, tol, 0.0); }

static void run_free(run *x) { free(x->r), free(x->u), free(x->v); }

static double distance(const double *a, const double *b, int64_t m) {
    double d = 0.0, s = 0.0;
    for (int64_t i = 0; i < m; ++i) d += (a[i] - b[i]) * (a[i] - b[i]), s += b[i] * b[i];
    return sqrt(d / (s > 0.0 ? s : 1.0));
}

/* A local problem with a dense W given by its caller (not formed by the reduction: W's
 * columns are then read through its rows' index): W = I + G G^T / (3 nc), G pseudo-random,
 * q pseudo-random with most normal parts negative, so that contacts stick, slide and
 * separate. */
typedef struct {
    frix_matrix *W;
    frix_problem *p;
    double *q, *mu; /* borrowed by p */
} dense_local;

static dense_local dense_local_make(int64_t nc) {
    const int64_t k = 3 * nc;
    double *G = malloc((size_t)(k * k) * sizeof(double)), *D = malloc((size_t)(k * k) * sizeof(double));
    double *q = malloc((size_t)k * sizeof(double)), *mu = malloc((size_t)nc * sizeof(double));
    ck_assert(G && D && q && mu);
    uint64_t s = 12345;
    for (int64_t i = 0; i < k * k; ++i) {
        s = s * 6364136223846793005ull + 1442695040888963407ull;
        G[i] = (double)(s >> 11) / 9007199254740992.0 - 0.5;
    }
    for (int64_t i = 0; i < k; ++i)
        for (int64_t j = 0; j < k; ++j) {
            double g = 0.0;
            for (int64_t t = 0; t < k; ++t) g += G[i + k * t] * G[j + k * t];
            D[i + k * j] = (i == j ? 1.0 : 0.0) + g / (double)k;
        }
    for (int64_t a = 0; a < nc; ++a) {
        q[3 * a] = a % 4 == 3 ? 0.3 : -1.0 + 0.01 * (double)a;
        q[3 * a + 1] = G[3 * a] * 2.0;
        q[3 * a + 2] = G[3 * a + 1] * 2.0;
        mu[a] = 0.3;
    }
    dense_local out = {NULL, NULL, q, mu};
    ck_assert_int_eq(frix_matrix_from_dense(k, k, D, k, &out.W), FRIX_OK);
    ck_assert_int_eq(frix_matrix_block_count(out.W), nc * nc);
    ck_assert_int_eq(frix_problem_local(out.W, q, mu, nc, &out.p), FRIX_OK);
    free(G), free(D);
    return out;
}

static void dense_local_free(dense_local *d) {
    frix_problem_free(d->p);
    frix_matrix_free(d->W);
    free(d->q), free(d->mu);
}

/* The single pushes meet `tol` by the double measure, told in the log, and their answer is
 * the double pushes' within what the tolerance leaves (both are within tol of the solution,
 * in the error's scale; W is well conditioned here). */
static void single_meets(const frix_problem *p, double tol) {
    run single = solve(p, SINGLE, tol), twin = solve(p, DOUBLE, tol);
    ck_assert_msg(single.status == FRIX_STATUS_CONVERGED && single.error <= tol, "single: %s after %lld, error %g",
                  frix_status_string(single.status), (long long)single.iterations, single.error);
    ck_assert(single.logged_single);
    ck_assert(twin.status == FRIX_STATUS_CONVERGED && twin.error <= tol && !twin.logged_single);
    const int64_t m = frix_problem_contact_dofs(p);
    const double d = distance(single.r, twin.r, m);
    ck_assert_msg(d <= 100.0 * tol, "|r_single - r_double| / |r_double| = %g at tolerance %g", d, tol);
    /* The runs differ (the test sees the path), by rounding only. */
    ck_assert(memcmp(single.r, twin.r, (size_t)m * sizeof(double)) != 0);
    run_free(&single);
    run_free(&twin);
}

/* A deformable body pressed on a plane, reduced to its dense W by the driver (symmetric:
 * columns read from rows). */
START_TEST(single_pushes_meet_tight_tolerances_on_a_reduced_body) {
    frix_elastic_grid g;
    ck_assert_int_eq(frix_elastic_grid_make(10, 10, 2, 0.5, 1e4, &g), FRIX_OK);
    const double tol[] = {1e-8, 1e-10, 1e-12};
    single_meets(g.problem, tol[_i]);
    frix_elastic_grid_free(&g);
}
END_TEST

START_TEST(single_pushes_meet_tight_tolerances_on_a_given_dense_w) {
    dense_local d = dense_local_make(60);
    const double tol[] = {1e-8, 1e-10, 1e-12};
    single_meets(d.p, tol[_i]);
    dense_local_free(&d);
}
END_TEST

/* `pub` ran the double pushes: the same bits as `twin`, the double path forced, and nothing
 * told. */
static void same_as_double(run pub, run twin, const frix_problem *p) {
    const int64_t m = frix_problem_contact_dofs(p), n = frix_problem_dofs(p);
    ck_assert(!pub.logged_single && !twin.logged_single);
    ck_assert_int_eq(pub.status, twin.status);
    ck_assert_int_eq(pub.iterations, twin.iterations);
    ck_assert(memcmp(pub.r, twin.r, (size_t)m * sizeof(double)) == 0);
    ck_assert(memcmp(pub.u, twin.u, (size_t)m * sizeof(double)) == 0);
    if (n > 0) ck_assert(memcmp(pub.v, twin.v, (size_t)n * sizeof(double)) == 0);
    ck_assert(memcmp(&pub.error, &twin.error, sizeof(double)) == 0);
    run_free(&pub);
    run_free(&twin);
}

/* Below the size that takes single pushes, frix_solve's nsgs-v runs the double ones. */
static void public_is_double(const frix_problem *p) {
    same_as_double(solve(p, PUBLIC, 1e-8), solve(p, DOUBLE, 1e-8), p);
}

START_TEST(below_the_size_frix_solve_pushes_in_double) {
    frix_elastic_grid g;
    ck_assert_int_eq(frix_elastic_grid_make(10, 10, 2, 0.5, 1e4, &g), FRIX_OK);
    public_is_double(g.problem);
    frix_elastic_grid_free(&g);
    dense_local d = dense_local_make(60);
    public_is_double(d.p);
    dense_local_free(&d);
    frix_problem *p = load("converted/Rover4396.from_dat.hdf5"); /* a sparse W */
    if (!p) return;
    public_is_double(p);
    frix_problem_free(p);
}
END_TEST

/* Where the memory limit leaves no room for the copy, the pushes stay in double precision. */
START_TEST(single_pushes_need_room_in_the_memory_limit) {
    dense_local d = dense_local_make(60);
    same_as_double(solve_limited(d.p, SINGLE, 1e-8, 1000.0), solve_limited(d.p, DOUBLE, 1e-8, 1000.0), d.p);
    dense_local_free(&d);
}
END_TEST

/* A push through the single-precision columns is W's column times dr up to single rounding,
 * read by columns (any W) or from the rows (a symmetric W); a W with a block missing does not
 * suit. */
START_TEST(single_push_is_the_column_times_dr) {
    const int64_t nc = 7, k = 3 * nc; /* 21 rows: the last chunk of four rows is partial */
    double *A = malloc((size_t)(k * k) * sizeof(double)), *S = malloc((size_t)(k * k) * sizeof(double));
    ck_assert(A && S);
    for (int64_t i = 0; i < k; ++i)
        for (int64_t j = 0; j < k; ++j) A[i + k * j] = 1.0 + sin(1.3 * (double)i + 0.7 * (double)(j * j));
    for (int64_t i = 0; i < k; ++i)
        for (int64_t j = 0; j < k; ++j) S[i + k * j] = A[i + k * j] + A[j + k * i];
    const double dr[3] = {0.3, -1.7, 2.1};
    for (int symmetric = 0; symmetric < 2; ++symmetric) {
        const double *D = symmetric ? S : A;
        frix_matrix *W = NULL;
        ck_assert_int_eq(frix_matrix_from_dense(k, k, D, k, &W), FRIX_OK);
        for (int64_t a = 0; a < nc; ++a) {
            double u[21], x[21] = {0}, want[21] = {0};
            for (int64_t i = 0; i < k; ++i) u[i] = 0.5 * (double)i;
            for (int t = 0; t < 3; ++t) x[3 * a + t] = dr[t];
            ck_assert_int_eq(frix_matrix_gemv(W, 1.0, x, 0.0, want), FRIX_OK);
            ck_assert_int_eq(frix_testing_single_push(W, symmetric, a, dr, u), FRIX_OK);
            for (int64_t i = 0; i < k; ++i)
                ck_assert_msg(fabs(u[i] - 0.5 * (double)i - want[i]) <= 1e-6 * (1.0 + fabs(want[i])),
                              "symmetric %d column %lld row %lld: %g, want %g", symmetric, (long long)a,
                              (long long)i, u[i] - 0.5 * (double)i, want[i]);
        }
        frix_matrix_free(W);
    }
    /* Block (0, 1) zero: not stored, and W no longer suits. */
    for (int64_t i = 0; i < 3; ++i)
        for (int64_t j = 3; j < 6; ++j) A[i + k * j] = 0.0;
    frix_matrix *W = NULL;
    ck_assert_int_eq(frix_matrix_from_dense(k, k, A, k, &W), FRIX_OK);
    double u[21] = {0};
    ck_assert_int_eq(frix_testing_single_push(W, 0, 0, dr, u), FRIX_ERR_INVALID_ARGUMENT);
    frix_matrix_free(W);
    free(A), free(S);
}
END_TEST

/* The log sink: the thread count the single-precision pushes ran on (0: not told). */
static void note_threads(void *data, const char *line) {
    const char *on = strstr(line, "single precision");
    if (on && (on = strstr(on, " on "))) *(int *)data = atoi(on + 4);
}

/* nsgs-v with single pushes forced, on `threads` threads, each sweep in a new order (shuffle)
 * or in order, a fixed number of sweeps where `sweeps` > 0 (else to 1e-10). */
static run solve_threads(const frix_problem *p, int64_t threads, int shuffle, int64_t sweeps, int *told) {
    run out = run_make(p);
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_NSGS_VELOCITY, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, sweeps > 0 ? 1e-300 : 1e-10), FRIX_OK);
    if (sweeps > 0) ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_MAX_ITER, sweeps), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_THREADS, threads), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_SHUFFLE, shuffle ? FRIX_SHUFFLE_EACH_SWEEP : FRIX_SHUFFLE_NONE),
                     FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_EXISTENCE_CHECK, 0), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_VERBOSITY, 1), FRIX_OK);
    ck_assert_int_eq(frix_options_set_log(o, note_threads, told), FRIX_OK);
    run_solve(p, SINGLE, o, &out);
    return out;
}

/* Threads split u's rows among them and the pushes keep the sweep's order: the iterates are
 * those of one thread to the bit, in order or shuffled, with frozen contacts (nsgs-v's
 * default) and with every contact in play (a fixed number of sweeps from r = 0). */
static void same_on_any_threads(const frix_problem *p, int64_t sweeps) {
    const int64_t m = frix_problem_contact_dofs(p), nc = m / 3;
    for (int shuffle = 0; shuffle < 2; ++shuffle) {
        int told = 0;
        run one = solve_threads(p, 1, shuffle, sweeps, &told);
        ck_assert_int_eq(told, 1);
        if (sweeps == 0) ck_assert_msg(one.status == FRIX_STATUS_CONVERGED, "%s", frix_status_string(one.status));
        const int64_t threads[] = {2, 3, 64};
        for (int k = 0; k < 3; ++k) {
            told = 0;
            run many = solve_threads(p, threads[k], shuffle, sweeps, &told);
            /* One thread a run of at least 4 contacts. */
            ck_assert_int_eq(told, threads[k] <= nc / 4 ? threads[k] : nc / 4);
            ck_assert_int_eq(many.status, one.status);
            ck_assert_int_eq(many.iterations, one.iterations);
            ck_assert_msg(memcmp(many.r, one.r, (size_t)m * sizeof(double)) == 0,
                          "threads %lld shuffle %d: r differs by %g", (long long)threads[k], shuffle,
                          distance(many.r, one.r, m));
            ck_assert(memcmp(many.u, one.u, (size_t)m * sizeof(double)) == 0);
            run_free(&many);
        }
        run_free(&one);
    }
}

START_TEST(single_pushes_on_threads_are_one_threads_to_the_bit) {
    dense_local d = dense_local_make(62); /* 62 contacts: the last run's last chunk is partial */
    same_on_any_threads(d.p, 0);
    same_on_any_threads(d.p, 7);
    dense_local_free(&d);
    frix_elastic_grid g;
    ck_assert_int_eq(frix_elastic_grid_make(10, 10, 2, 0.5, 1e4, &g), FRIX_OK);
    same_on_any_threads(g.problem, 0);
    frix_elastic_grid_free(&g);
}
END_TEST

/* ---- The active part (a persistent nsgs-v on a large dense W): from step 1 on, the sweeps
 * run on the contacts closed at the warm start and those nearest to closing, built once and
 * kept; the whole problem's run then measures that answer and sweeps on only where an open
 * contact closed. */

typedef struct {
    int built, kept, stopped_at_3, whole_runs, whole_sweeps;
} part_lines;

static void note_part(void *data, const char *line) {
    part_lines *c = data;
    if (strstr(line, "nsgs-v: active part")) {
        if (strstr(line, "(built)")) ++c->built;
        if (strstr(line, "(kept)")) ++c->kept;
        if (strstr(line, "stopped by callback after 3 sweeps")) ++c->stopped_at_3;
    }
    const char *after = strstr(line, "nsgs-v: converged after ");
    if (after) {
        ++c->whole_runs;
        c->whole_sweeps += atoi(after + strlen("nsgs-v: converged after "));
    }
}

/* nsgs-v at 1e-8, its progress lines (verbosity 1) counted into *lines. */
static frix_options *logged_nsgs_v(part_lines *lines) {
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_NSGS_VELOCITY, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 1e-8), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_VERBOSITY, 1), FRIX_OK);
    ck_assert_int_eq(frix_options_set_log(o, note_part, lines), FRIX_OK);
    return o;
}

/* The callback stops a solve at iteration *stop_at (0: never). */
static int stop_at_iteration(void *stop_at, int64_t iteration, double error, double elapsed) {
    (void)error, (void)elapsed;
    const int at = *(const int *)stop_at;
    return at > 0 && iteration >= at;
}

/* A 27x27x2 grid (729 contacts: W dense, 38 MB, past the single-precision size) whose gaps
 * leave a share of its contacts open, its load raised by 2 % a step and by half at step 4:
 * every persistent step converges, meets the tolerance by the double measure and agrees with
 * frix_solve's nsgs-v from the same start; step 2 once more, stopped by the callback within
 * the part, ends stopped after that many sweeps, and the next steps go on. */
START_TEST(persistent_steps_sweep_the_active_part) {
    frix_elastic_grid g;
    ck_assert_int_eq(frix_elastic_grid_make(27, 27, 2, 2.0, 1e4, &g), FRIX_OK);
    const frix_problem *p = g.problem;
    const int64_t m = frix_problem_contact_dofs(p), n = frix_problem_dofs(p);
    double *f0 = malloc(sizeof *f0 * (size_t)n), *start = malloc(sizeof *start * (size_t)m);
    memcpy(f0, g.f, sizeof *f0 * (size_t)n);
    run pers = run_make(p), one = run_make(p);
    part_lines lines = {0, 0, 0, 0, 0};
    frix_options *o = logged_nsgs_v(&lines);
    int stop_at = 0;
    ck_assert_int_eq(frix_options_set_callback(o, stop_at_iteration, &stop_at), FRIX_OK);
    frix_persistent *ps = NULL;
    ck_assert_int_eq(frix_persistent_create(p, o, &ps), FRIX_OK);
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    int kept_steps_whole_sweeps = 0;
    for (int k = 0; k < 6; ++k) {
        const double scale = k == 4 ? 1.5 : 1.0 + 0.02 * k;
        for (int64_t i = 0; i < n; ++i) g.f[i] = scale * f0[i];
        memcpy(start, pers.r, sizeof *start * (size_t)m);
        if (k == 2) {
            stop_at = 3;
            const part_lines stopped = lines;
            ck_assert_int_eq(frix_persistent_solve(ps, pers.r, pers.u, pers.v, info), FRIX_OK);
            ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_STOPPED_BY_CALLBACK);
            ck_assert_int_eq(frix_info_iterations(info), 3);
            ck_assert_int_eq(lines.kept, stopped.kept + 1);
            ck_assert_int_eq(lines.stopped_at_3, stopped.stopped_at_3 + 1);
            stop_at = 0;
            memcpy(pers.r, start, sizeof *start * (size_t)m);
        }
        const part_lines before = lines;
        ck_assert_int_eq(frix_persistent_solve(ps, pers.r, pers.u, pers.v, info), FRIX_OK);
        ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_CONVERGED);
        ck_assert_int_eq(frix_problem_error(p, pers.r, pers.v, &pers.error), FRIX_OK);
        ck_assert_double_le(pers.error, 1e-8);
        if (lines.kept > before.kept && k != 4) kept_steps_whole_sweeps += lines.whole_sweeps - before.whole_sweeps;
        memcpy(one.r, start, sizeof *start * (size_t)m);
        frix_options *o1 = NULL;
        ck_assert_int_eq(frix_options_copy(o, &o1), FRIX_OK);
        ck_assert_int_eq(frix_options_set_int(o1, FRIX_OPT_VERBOSITY, 0), FRIX_OK);
        run_solve(p, PUBLIC, o1, &one);
        ck_assert_int_eq(one.status, FRIX_STATUS_CONVERGED);
        ck_assert_double_le(distance(pers.r, one.r, m), 1e-6);
    }
    ck_assert_int_ge(lines.built, 1);
    ck_assert_int_ge(lines.kept, 2);
    /* Where the part was kept along the path, its answer solved the whole problem. */
    ck_assert_int_eq(kept_steps_whole_sweeps, 0);
    frix_info_free(info);
    frix_persistent_free(ps);
    frix_options_free(o);
    run_free(&pers), run_free(&one);
    free(f0), free(start);
    frix_elastic_grid_free(&g);
}
END_TEST

/* The callback's iterations, which must rise through a solve. */
typedef struct {
    int64_t last, reports, out_of_order;
} numbering;

static int note_numbering(void *data, int64_t iteration, double error, double elapsed) {
    numbering *c = data;
    (void)error, (void)elapsed;
    if (iteration <= c->last) ++c->out_of_order;
    c->last = iteration, ++c->reports;
    return 0;
}

/* A local dense W = 2 I - c e e^T on the normal rows (e: ones on them; 700 contacts, 35 MB,
 * past the single-precision size): a contact's normal velocity falls as the others press
 * harder. Half the contacts press; of the others, those with a small gap close only once the
 * pressing ones' reactions have grown, so they lie outside the part and the whole problem's
 * run sweeps on after it: the step converges within the tolerance, and the callback's
 * iterations rise across the part and the whole run. */
START_TEST(persistent_step_sweeps_on_after_the_active_part) {
    enum { nc = 700, rows = 3 * nc };
    const double c = 5.7e-4;
    double *W = calloc((size_t)rows * rows, sizeof *W), q[rows], mu[nc], r[rows] = {0}, u[rows];
    for (int64_t i = 0; i < rows; ++i) W[i + rows * i] = 2.0;
    for (int64_t a = 0; a < nc; ++a)
        for (int64_t b = 0; b < nc; ++b) W[3 * a + rows * 3 * b] -= c;
    frix_matrix *Wm = NULL;
    ck_assert_int_eq(frix_matrix_from_dense(rows, rows, W, rows, &Wm), FRIX_OK);
    free(W);
    for (int64_t a = 0; a < nc; ++a) {
        mu[a] = 0.5;
        q[3 * a] = a % 2 ? -1.0 : 0.2 + 1.0 * (double)a / nc;  /* pressing, or open by a gap */
        q[3 * a + 1] = q[3 * a + 2] = 0.0;
    }
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_problem_local(Wm, q, mu, nc, &p), FRIX_OK);
    part_lines lines = {0, 0, 0, 0, 0};
    frix_options *o = logged_nsgs_v(&lines);
    numbering calls = {0, 0, 0};
    ck_assert_int_eq(frix_options_set_callback(o, note_numbering, &calls), FRIX_OK);
    frix_persistent *ps = NULL;
    ck_assert_int_eq(frix_persistent_create(p, o, &ps), FRIX_OK);
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_persistent_solve(ps, r, u, NULL, info), FRIX_OK);
    ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_CONVERGED);
    /* The pressing contacts press six times as hard: those open by less than about 0.6 close. */
    for (int64_t a = 1; a < nc; a += 2) q[3 * a] = -6.0;
    const part_lines before = lines;
    calls.last = 0, calls.reports = 0;
    ck_assert_int_eq(frix_persistent_solve(ps, r, u, NULL, info), FRIX_OK);
    ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_CONVERGED);
    double e = 0.0;
    ck_assert_int_eq(frix_problem_error(p, r, NULL, &e), FRIX_OK);
    ck_assert_double_le(e, 1e-8);
    ck_assert_int_eq(lines.built, before.built + 1);
    ck_assert_int_gt(lines.whole_sweeps, before.whole_sweeps);
    ck_assert_int_gt(calls.reports, 0);
    ck_assert_int_eq(calls.out_of_order, 0);
    ck_assert_int_eq(calls.last, frix_info_iterations(info));
    frix_info_free(info);
    frix_persistent_free(ps);
    frix_options_free(o);
    frix_problem_free(p);
    frix_matrix_free(Wm);
}
END_TEST

static Suite *single_suite(void) {
    Suite *s = suite_create("single_sweeps");
    TCase *t = tcase_create("single");
    tcase_add_loop_test(t, single_pushes_meet_tight_tolerances_on_a_reduced_body, 0, 3);
    tcase_add_loop_test(t, single_pushes_meet_tight_tolerances_on_a_given_dense_w, 0, 3);
    tcase_add_test(t, below_the_size_frix_solve_pushes_in_double);
    tcase_add_test(t, single_pushes_need_room_in_the_memory_limit);
    tcase_add_test(t, single_push_is_the_column_times_dr);
    tcase_add_test(t, single_pushes_on_threads_are_one_threads_to_the_bit);
    tcase_add_test(t, persistent_steps_sweep_the_active_part);
    tcase_add_test(t, persistent_step_sweeps_on_after_the_active_part);
    suite_add_tcase(s, t);
    return s;
}

int main(void) { return frix_run_suite(single_suite()); }
