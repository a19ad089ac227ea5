/* `frix bench`, run as a separate process: the CSV files it writes (quoting included), the
 * performance-profile and work-precision computation on a hand-made table with known
 * values (`frix bench --report`), the isolation of runs (a hanging run is killed at its
 * time limit and a crashing one recorded, and the campaign goes on), and the Siconos
 * comparator when it was built (skipped with a note otherwise). Needs no shared data. */
#define _POSIX_C_SOURCE 200809L

#include <frix/frix.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "check_main.h"
#include "cli_runner.h"

#define TMP FRIX_TEST_TMPDIR "/bench"

/* ---- Files and processes ------------------------------------------------------------- */

static int exists(const char *path) {
    struct stat st;
    return stat(path, &st) == 0;
}

static void fresh_dir(const char *path) {
    char cmd[1024];
    mkdir(FRIX_TEST_TMPDIR, 0755);
    mkdir(TMP, 0755);
    snprintf(cmd, sizeof cmd, "rm -rf '%s' && mkdir -p '%s'", path, path);
    ck_assert_int_eq(system(cmd), 0);
}

static double now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int cli_exit_code(const char *const *args) {
    cli_run r = run_cli(args);
    run_free(&r);
    return r.code;
}

/* Two contacts, converges in a few sweeps. */
static void make_problem(const char *path) {
    static const double blocks[18] = {2, 0, 0, 0, 1, 0, 0, 0, 1, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    static const int64_t rows[2] = {0, 1}, cols[2] = {0, 1};
    static const double q[6] = {-1, 0.1, 0, -2, 0, 3}, mu[2] = {0.5, 0.3};
    frix_matrix *W = NULL;
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_matrix_from_blocks(2, 2, 2, rows, cols, blocks, &W), FRIX_OK);
    ck_assert_int_eq(frix_problem_local(W, q, mu, 2, &p), FRIX_OK);
    unlink(path);
    ck_assert_int_eq(frix_fclib_write(path, p, NULL, NULL, NULL, 0, NULL, NULL, NULL), FRIX_OK);
    frix_problem_free(p);
    frix_matrix_free(W);
}

/* The same forces as a global problem: two points (masses 1 and 2, n = 6) on their contacts,
 * H = I, pushed in by f; the first, 0.1 off its contact (w_N), sticks (r = (0.9, -0.1, 0)),
 * the second slides (r = (2, 0, -0.6), u = (0, 0, 1.2)). f and w both matter: a sign of
 * either taken the other way fails the error or the equilibrium. */
static void make_global_problem(const char *path) {
    static const int64_t idx[6] = {0, 1, 2, 3, 4, 5};
    static const double mass[6] = {1, 1, 1, 2, 2, 2}, ones[6] = {1, 1, 1, 1, 1, 1};
    static const double f[6] = {-1, 0.1, 0, -2, 0, 3}, w[6] = {0.1, 0, 0, 0, 0, 0};
    static const double mu[2] = {0.5, 0.3};
    frix_matrix *M = NULL, *H = NULL;
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_matrix_from_triplets(6, 6, 6, idx, idx, mass, &M), FRIX_OK);
    ck_assert_int_eq(frix_matrix_from_triplets(6, 6, 6, idx, idx, ones, &H), FRIX_OK);
    ck_assert_int_eq(frix_problem_global(M, H, f, w, mu, 2, &p), FRIX_OK);
    unlink(path);
    ck_assert_int_eq(frix_fclib_write(path, p, NULL, NULL, NULL, 0, NULL, NULL, NULL), FRIX_OK);
    frix_problem_free(p);
    frix_matrix_free(H);
    frix_matrix_free(M);
}

/* One sphere (6 dofs, M = I) on the ground, one rolling contact: H selects the normal (dof 2),
 * the tangents (0, 1) and the rolling directions (3, 4), so W = I and the contact sticks
 * with r = (1, -0.1, 0, -0.05, 0). */
static void make_global_rolling_problem(const char *path) {
    static const int64_t idx[6] = {0, 1, 2, 3, 4, 5}, rows[5] = {2, 0, 1, 3, 4}, cols[5] = {0, 1, 2, 3, 4};
    static const double ones[6] = {1, 1, 1, 1, 1, 1};
    static const double f[6] = {0.1, 0, -1, 0.05, 0, 0}, w[5] = {0, 0, 0, 0, 0};
    static const double mu = 0.5, mu_r = 0.1;
    frix_matrix *M = NULL, *H = NULL;
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_matrix_from_triplets(6, 6, 6, idx, idx, ones, &M), FRIX_OK);
    ck_assert_int_eq(frix_matrix_from_triplets(6, 5, 5, rows, cols, ones, &H), FRIX_OK);
    ck_assert_int_eq(frix_problem_rolling_global(M, H, f, w, &mu, &mu_r, 1, &p), FRIX_OK);
    unlink(path);
    ck_assert_int_eq(frix_fclib_write(path, p, NULL, NULL, NULL, 0, NULL, NULL, NULL), FRIX_OK);
    frix_problem_free(p);
    frix_matrix_free(H);
    frix_matrix_free(M);
}

/* The number after "key": in a one-line JSON object, NaN if absent. */
static double json_number_at(const char *json, const char *key) {
    char pattern[64];
    snprintf(pattern, sizeof pattern, "\"%s\":", key);
    const char *at = strstr(json, pattern);
    return at ? strtod(at + strlen(pattern), NULL) : NAN;
}

/* ---- A small RFC 4180 reader, independent of frix's -------------------------------------- */

typedef struct {
    int rows, cols[4096];
    char *field[4096][20];
} csv;

static csv *csv_read(const char *path) {
    char *text = slurp(path, NULL);
    csv *c = calloc(1, sizeof *c);
    ck_assert_ptr_nonnull(c);
    char buf[4096];
    size_t len = 0;
    int quoted = 0, row = 0, col = 0, any = 0;
    for (const char *p = text;; ++p) {
        char ch = *p;
        if (quoted && ch != '\0') {
            if (ch == '"' && p[1] == '"') {
                buf[len++] = '"';
                ++p;
            } else if (ch == '"') {
                quoted = 0;
            } else {
                buf[len++] = ch;
            }
            continue;
        }
        if (ch == '"') {
            quoted = any = 1;
        } else if (ch == ',' || ch == '\n' || (ch == '\0' && any)) {
            buf[len] = '\0';
            ck_assert_int_lt(row, 4096);
            ck_assert_int_lt(col, 20);
            c->field[row][col++] = strdup(buf);
            len = 0;
            if (ch != ',') {
                c->cols[row++] = col;
                col = any = 0;
            }
        } else if (ch != '\0') {
            buf[len++] = ch;
            any = 1;
        }
        if (ch == '\0') break;
        ck_assert_uint_lt(len, sizeof buf - 1);
    }
    c->rows = row;
    free(text);
    return c;
}

static int csv_col(const csv *c, const char *name) {
    for (int k = 0; k < c->cols[0]; ++k)
        if (strcmp(c->field[0][k], name) == 0) return k;
    ck_abort_msg("no column %s", name);
    return -1;
}

static const char *csv_get(const csv *c, int row, const char *name) {
    int k = csv_col(c, name);
    ck_assert_int_lt(k, c->cols[row]);
    return c->field[row][k];
}

/* The first data row whose columns a and b hold va and vb, or -1. */
static int csv_find(const csv *c, const char *a, const char *va, const char *b, const char *vb) {
    for (int r = 1; r < c->rows; ++r)
        if (strcmp(csv_get(c, r, a), va) == 0 && (!b || strcmp(csv_get(c, r, b), vb) == 0)) return r;
    return -1;
}

static void csv_free(csv *c) {
    for (int r = 0; r < c->rows; ++r)
        for (int k = 0; k < c->cols[r]; ++k) free(c->field[r][k]);
    free(c);
}

/* ---- The CSV files of a campaign --------------------------------------------------------- */

START_TEST(test_csv_files) {
    const char *odd = "odd, \"name\".hdf5"; /* a comma and quotes: must be quoted in CSV */
    fresh_dir(TMP "/csv/problems");
    char path[512];
    snprintf(path, sizeof path, "%s/%s", TMP "/csv/problems", odd);
    make_problem(path);
    const char *args[] = {"bench", TMP "/csv/problems", "--solvers", "nsgs,500", "--tol", "1e-10",
                          "--time-limit", "5", "--out", TMP "/csv/out", "--no-plots", NULL};
    ck_assert_int_eq(cli_exit_code(args), 0);

    char *raw = slurp(TMP "/csv/out/runs.csv", NULL);
    const char *header = "problem,family,contacts,dofs,solver,status,iterations,error,time,";
    ck_assert_msg(strncmp(raw, header, strlen(header)) == 0, "header: %.120s", raw);
    ck_assert_msg(strstr(raw, "\n\"odd, \"\"name\"\".hdf5\",other,2,6,nsgs,converged,") != NULL,
                  "row not quoted as RFC 4180 says: %s", raw);
    free(raw);

    csv *runs = csv_read(TMP "/csv/out/runs.csv");
    ck_assert_int_eq(runs->rows, 2); /* header + one run: "500" is nsgs again */
    ck_assert_int_eq(runs->cols[1], runs->cols[0]);
    ck_assert_str_eq(csv_get(runs, 1, "problem"), odd);
    ck_assert_str_eq(csv_get(runs, 1, "solver_id"), "500");
    ck_assert_double_le(atof(csv_get(runs, 1, "error")), 1e-10);
    ck_assert_double_gt(atof(csv_get(runs, 1, "time")), 0);
    ck_assert_int_gt(atoi(csv_get(runs, 1, "iterations")), 0);
    ck_assert_str_eq(csv_get(runs, 1, "tolerance"), "1e-10");
    /* The run's process held the problem, the library and its buffers: megabytes, not none. */
    ck_assert_double_gt(atof(csv_get(runs, 1, "peak_memory_mb")), 1.0);
    /* The problem's own storage, in blocks: at least its diagonal blocks. */
    ck_assert_double_ge(atof(csv_get(runs, 1, "stored_blocks")), atof(csv_get(runs, 1, "contacts")));
    csv_free(runs);

    csv *tr = csv_read(TMP "/csv/out/traces.csv");
    ck_assert_int_ge(tr->rows, 2);
    ck_assert_str_eq(tr->field[0][0], "problem");
    double last = -1;
    for (int r = 1; r < tr->rows; ++r) {
        ck_assert_str_eq(csv_get(tr, r, "problem"), odd);
        double t = atof(csv_get(tr, r, "elapsed"));
        ck_assert_double_ge(t, last); /* elapsed time only grows */
        last = t;
    }
    ck_assert_double_le(atof(csv_get(tr, tr->rows - 1, "error")), 1e-10);
    csv_free(tr);

    ck_assert(exists(TMP "/csv/out/profile.csv"));
    ck_assert(exists(TMP "/csv/out/work_precision.csv"));
    char *md = slurp(TMP "/csv/out/summary.md", NULL);
    ck_assert_msg(strstr(md, "| nsgs | 1/1 |") != NULL, "summary: %s", md);
    ck_assert_msg(strstr(md, "peak memory per contact (kB)") != NULL, "summary: %s", md);
    free(md);
}
END_TEST

/* A solver with options of its own (NAME@OPTION=VALUE) is a solver of its own in the tables,
 * and its option reaches the run: relaxation 0.5 changes the sweeps. */
START_TEST(test_solver_options) {
    fresh_dir(TMP "/opts/problems");
    make_problem(TMP "/opts/problems/p.hdf5");
    const char *args[] = {"bench", TMP "/opts/problems", "--solvers", "nsgs,nsgs@relaxation=0.5", "--tol", "1e-10",
                          "--time-limit", "5", "--out", TMP "/opts/out", "--no-plots", NULL};
    ck_assert_int_eq(cli_exit_code(args), 0);
    csv *runs = csv_read(TMP "/opts/out/runs.csv");
    ck_assert_int_eq(runs->rows, 3);
    ck_assert_str_eq(csv_get(runs, 1, "solver"), "nsgs");
    ck_assert_str_eq(csv_get(runs, 2, "solver"), "nsgs@relaxation=0.5");
    ck_assert_str_eq(csv_get(runs, 2, "status"), "converged");
    ck_assert_int_gt(atoi(csv_get(runs, 2, "iterations")), atoi(csv_get(runs, 1, "iterations")));
    csv_free(runs);
    const char *bad[] = {"bench", TMP "/opts/problems", "--solvers", "nsgs@nosuch=1", "--out", TMP "/never", NULL};
    ck_assert_int_eq(cli_exit_code(bad), 2);
}
END_TEST

START_TEST(test_usage_errors) {
    const char *no_out[] = {"bench", FRIX_TEST_TMPDIR, "--solvers", "nsgs", NULL};
    ck_assert_int_eq(cli_exit_code(no_out), 2);
    const char *bad_solver[] = {"bench", FRIX_TEST_TMPDIR, "--solvers", "nosuch", "--out",
                                TMP "/never", NULL};
    ck_assert_int_eq(cli_exit_code(bad_solver), 2);
    const char *bad_limit[] = {"bench", FRIX_TEST_TMPDIR, "--time-limit", "0", "--out", TMP "/never", NULL};
    ck_assert_int_eq(cli_exit_code(bad_limit), 2);
    ck_assert(!exists(TMP "/never"));
    const char *help[] = {"bench", "--help", NULL};
    ck_assert_int_eq(cli_exit_code(help), 0);
}
END_TEST

/* ---- Performance profile and work-precision on a hand-made table --------------------------
 * Three solvers, four problems (times in s; "-" = not converged):
 *          P1 (F1)  P2 (F1)  P3 (F2)  "P,4" (F2)
 *   A      1        3        -        -
 *   B      2        1.5      -        -
 *   C      4        -        2        -
 * Best times 1, 1.5, 2, none; ratios A: 1, 2; B: 2, 1; C: 4, 1. Hence over all four
 * problems rho_A = rho_B = 1/4 at tau = 1 and 1/2 from tau = 2 on; rho_C = 1/4 at 1, 1/2
 * from 4 on. In family F1: rho_A = rho_B = 1/2 at 1, 1 at 2; rho_C = 0 at 1, 1/2 at 4. In
 * F2: rho_A = rho_B = 0, rho_C = 1/2. */
static const char kRuns[] =
    "problem,family,contacts,dofs,solver,status,iterations,error,time,solver_id,tolerance,time_limit,max_iter,reported_error,note\n"
    "P1,F1,1,3,A,converged,5,1e-9,1.0,901,1e-8,10,1000,1e-9,\n"
    "P1,F1,1,3,B,converged,5,1e-9,2.0,902,1e-8,10,1000,1e-9,\n"
    "P1,F1,1,3,C,converged,5,1e-9,4.0,903,1e-8,10,1000,1e-9,\n"
    "P2,F1,1,3,A,converged,5,1e-9,3.0,901,1e-8,10,1000,1e-9,\n"
    "P2,F1,1,3,B,converged,5,1e-9,1.5,902,1e-8,10,1000,1e-9,\n"
    "P2,F1,1,3,C,max_iter,1000,1e-3,10.0,903,1e-8,10,1000,1e-3,\n"
    "P3,F2,1,3,A,timeout,7,1e-2,10.0,901,1e-8,10,1000,,killed\n"
    "P3,F2,1,3,B,crash(SIGSEGV),0,,0.1,902,1e-8,10,1000,,\n"
    "P3,F2,1,3,C,converged,5,1e-9,2.0,903,1e-8,10,1000,1e-9,\n"
    "\"P,4\",F2,1,3,A,max_iter,1000,1e-1,9.0,901,1e-8,10,1000,1e-1,\n"
    "\"P,4\",F2,1,3,B,time_limit,50,1e-2,10.0,902,1e-8,10,1000,1e-2,\n"
    "\"P,4\",F2,1,3,C,error,0,,,903,1e-8,10,1000,,\"said \"\"no\"\", twice\"\n"
    /* G takes none of these problems (as a global-only solver would): left out */
    "P1,F1,1,3,G,unsupported,0,,,607,1e-8,10,1000,,\n"
    "P2,F1,1,3,G,unsupported,0,,,607,1e-8,10,1000,,\n"
    "P3,F2,1,3,G,unsupported,0,,,607,1e-8,10,1000,,\n"
    "\"P,4\",F2,1,3,G,unsupported,0,,,607,1e-8,10,1000,,\n";
/* B on P1 reached 1e-3 at 0.5 s and 1e-6 at 1.2 s (then 1e-9 when it stopped at 2 s). */
static const char kTraces[] =
    "problem,solver,iteration,elapsed,error\n"
    "P1,B,1,0.1,1e-1\n"
    "P1,B,2,0.5,1e-3\n"
    "P1,B,3,1.2,1e-6\n"
    "P1,B,5,2.0,1e-9\n";

/* rho_s(tau) of `scope` from profile.csv: the last step at or before tau. */
static double rho_at(const csv *p, const char *scope, const char *solver, double tau) {
    double rho = -1;
    for (int r = 1; r < p->rows; ++r)
        if (strcmp(csv_get(p, r, "scope"), scope) == 0 && strcmp(csv_get(p, r, "solver"), solver) == 0 &&
            atof(csv_get(p, r, "tau")) <= tau * (1 + 1e-12))
            rho = atof(csv_get(p, r, "rho"));
    ck_assert_msg(rho >= 0, "no profile step for %s %s at %g", scope, solver, tau);
    return rho;
}

/* auto against the best other frix solver and the best Siconos solver, per problem:
 *          P1     P2          P3
 *   auto   2      4           -
 *   nsgs   1      -           3
 *   admm   4      2           -
 *   S:NSGS 8      -           -
 * Per problem: best frix nsgs 1 (ratio 2.00), admm 2 (2.00), nsgs 3 (auto unsolved);
 * Siconos NSGS 8 (0.25), none, none. Geometric means with a limit of 10:
 * auto (2*4*10)^(1/3), best frix (1*2*3)^(1/3), Siconos (8*10*10)^(1/3). Peak memory of
 * nsgs: 10, 30 and 20 MB, median 20; its times 1 (P1, which all solved), 10 (P2, max_iter:
 * counted at the limit) and 3: geometric mean 30^(1/3) = 3.11. */
static const char kBestRuns[] =
    "problem,family,contacts,dofs,solver,status,iterations,error,time,solver_id,tolerance,time_limit,max_iter,reported_error,note,peak_memory_mb\n"
    "P1,F1,7,3,auto,converged,5,1e-9,2.0,900,1e-8,10,1000,1e-9,,5\n"
    "P1,F1,7,3,nsgs,converged,5,1e-9,1.0,500,1e-8,10,1000,1e-9,,10\n"
    "P1,F1,7,3,admm,converged,5,1e-9,4.0,523,1e-8,10,1000,1e-9,,50\n"
    "P1,F1,7,3,siconos:NSGS,converged,5,1e-9,8.0,500,1e-8,10,1000,1e-9,,40\n"
    "P2,F1,9,3,auto,converged,5,1e-9,4.0,900,1e-8,10,1000,1e-9,,5\n"
    "P2,F1,9,3,nsgs,max_iter,5,1e-3,10.0,500,1e-8,10,1000,1e-3,,30\n"
    "P2,F1,9,3,admm,converged,5,1e-9,2.0,523,1e-8,10,1000,1e-9,,50\n"
    "P2,F1,9,3,siconos:NSGS,failed,5,1e-2,1.0,500,1e-8,10,1000,1e-2,,40\n"
    "P3,F1,11,3,auto,time_limit,5,1e-3,10.0,900,1e-8,10,1000,1e-3,,5\n"
    "P3,F1,11,3,nsgs,converged,5,1e-9,3.0,500,1e-8,10,1000,1e-9,,20\n"
    "P3,F1,11,3,admm,max_iter,5,1e-4,9.0,523,1e-8,10,1000,1e-4,,50\n"
    "P3,F1,11,3,siconos:NSGS,timeout,5,1e-4,12.0,500,1e-8,10,1000,,,\n";

START_TEST(test_best_per_problem) {
    fresh_dir(TMP "/best");
    spit_text(TMP "/best/runs.csv", kBestRuns);
    const char *args[] = {"bench", "--report", TMP "/best", "--no-plots", NULL};
    ck_assert_int_eq(cli_exit_code(args), 0);
    char *md = slurp(TMP "/best/summary.md", NULL);
    const char *rows[] = {"| P1 | 7 | 2 | nsgs 1 | 2.00 | siconos:NSGS 8 | 0.25 |",
                          "| P2 | 9 | 4 | admm 2 | 2.00 | none | - |",
                          "| P3 | 11 | unsolved | nsgs 3 | - | none | - |",
                          "| nsgs | 2/3 | 0 | 0 | 1 | 1 | 3.11 | 20 / 30 |"};
    for (size_t k = 0; k < sizeof rows / sizeof rows[0]; ++k)
        ck_assert_msg(strstr(md, rows[k]) != NULL, "no row '%s' in: %s", rows[k], md);
    char means[256];
    snprintf(means, sizeof means, "auto %.3g s; best other frix solver %.3g s (auto / it %.2f); best Siconos solver %.3g s",
             cbrt(80.0), cbrt(6.0), cbrt(80.0) / cbrt(6.0), cbrt(800.0));
    ck_assert_msg(strstr(md, means) != NULL, "no '%s' in: %s", means, md);
    free(md);
}
END_TEST

START_TEST(test_profile_known_values) {
    fresh_dir(TMP "/profile");
    spit_text(TMP "/profile/runs.csv", kRuns);
    spit_text(TMP "/profile/traces.csv", kTraces);
    const char *args[] = {"bench", "--report", TMP "/profile", "--no-plots", NULL};
    ck_assert_int_eq(cli_exit_code(args), 0);

    csv *p = csv_read(TMP "/profile/profile.csv");
    const double eps = 1e-12;
    const struct {
        const char *scope, *solver;
        double tau, rho;
    } expect[] = {
        {"all", "A", 1, 0.25},  {"all", "A", 1.99, 0.25}, {"all", "A", 2, 0.5},  {"all", "A", 1e6, 0.5},
        {"all", "B", 1, 0.25},  {"all", "B", 2, 0.5},     {"all", "C", 1, 0.25}, {"all", "C", 3.9, 0.25},
        {"all", "C", 4, 0.5},   {"all", "C", 1e6, 0.5},   {"F1", "A", 1, 0.5},   {"F1", "A", 2, 1.0},
        {"F1", "B", 1.5, 0.5},  {"F1", "B", 2, 1.0},      {"F1", "C", 1, 0.0},   {"F1", "C", 4, 0.5},
        {"F2", "A", 100, 0.0},  {"F2", "B", 100, 0.0},    {"F2", "C", 1, 0.5},   {"F2", "C", 100, 0.5},
    };
    for (size_t k = 0; k < sizeof expect / sizeof expect[0]; ++k)
        ck_assert_msg(fabs(rho_at(p, expect[k].scope, expect[k].solver, expect[k].tau) - expect[k].rho) < eps,
                      "rho_%s(%g) in %s: %g, expected %g", expect[k].solver, expect[k].tau,
                      expect[k].scope, rho_at(p, expect[k].scope, expect[k].solver, expect[k].tau),
                      expect[k].rho);
    int r = csv_find(p, "scope", "F2", "solver", "C");
    ck_assert_int_gt(r, 0);
    ck_assert_str_eq(csv_get(p, r, "problems"), "2");
    ck_assert_int_lt(csv_find(p, "solver", "G", NULL, NULL), 0);
    csv_free(p);

    /* Work-precision: time to reach an accuracy, from the traces where there are some. */
    csv *w = csv_read(TMP "/profile/work_precision.csv");
    r = csv_find(w, "solver", "B", "accuracy", "1e-03");
    ck_assert_int_gt(r, 0);
    ck_assert_str_eq(csv_get(w, r, "reached"), "2");      /* P1 at 0.5 s, P2 at 1.5 s */
    ck_assert_str_eq(csv_get(w, r, "problems"), "4");
    ck_assert_double_eq_tol(atof(csv_get(w, r, "geomean_time_reached")), sqrt(0.5 * 1.5), 1e-12);
    r = csv_find(w, "solver", "A", "accuracy", "1e-08");
    ck_assert_str_eq(csv_get(w, r, "reached"), "2");
    /* unreached counted at the time limit: (1 * 3 * 10 * 10)^(1/4) */
    ck_assert_double_eq_tol(atof(csv_get(w, r, "geomean_time_penalized")), pow(300.0, 0.25), 1e-12);
    r = csv_find(w, "solver", "A", "accuracy", "1e-10");
    ck_assert_str_eq(csv_get(w, r, "reached"), "0");
    r = csv_find(w, "solver", "A", "accuracy", "1e-02"); /* the killed run's last estimate counts */
    ck_assert_str_eq(csv_get(w, r, "reached"), "3");
    csv_free(w);

    char *md = slurp(TMP "/profile/summary.md", NULL);
    ck_assert_msg(strstr(md, "| A | 2/4 | 1 | 0 | 1 |") != NULL, "summary: %s", md);
    ck_assert_msg(strstr(md, "| B | 2/4 | 1 | 1 | 0 |") != NULL, "summary: %s", md);
    ck_assert_msg(strstr(md, "Solved by no solver: P,4.") != NULL, "summary: %s", md);
    ck_assert_msg(strstr(md, "Left out, as they take none of these problems (e.g. global-only solvers): G.") != NULL,
                  "summary: %s", md);
    ck_assert_msg(strstr(md, "| G |") == NULL, "summary: %s", md);
    free(md);
}
END_TEST

/* ---- Rounds: rivals' runs interleave, the time is the median of a pair's rounds ------------ */

/* The times the progress lines ("[n/N] PROBLEM SOLVER: STATUS, T s (...)") give the runs of
 * PROBLEM by SOLVER, in order; their count. */
static int progress_times(const char *err, const char *problem, const char *solver, double *times, int cap) {
    char key[256];
    snprintf(key, sizeof key, "] %s %s: ", problem, solver);
    int n = 0;
    for (const char *at = strstr(err, key); at; at = strstr(at + 1, key)) {
        const char *comma = strchr(at + strlen(key), ',');
        if (comma && n < cap) times[n] = atof(comma + 1);
        ++n;
    }
    return n;
}

/* --rounds 3 on two problems: a problem's solvers run round by round, nsgs three times and
 * CAPPED (two under-relaxed sweeps: max_iter, it needs 33) once; runs.csv keeps one row per
 * pair, nsgs's time the median of its three runs' (as the progress lines print them). */
#define CAPPED "nsgs@relaxation=0.5@max_iter=2"
START_TEST(test_rounds) {
    fresh_dir(TMP "/rounds/problems");
    make_problem(TMP "/rounds/problems/a.hdf5");
    make_problem(TMP "/rounds/problems/b.hdf5");
    const char *args[] = {"bench", TMP "/rounds/problems", "--solvers", "nsgs," CAPPED, "--tol", "1e-10",
                          "--time-limit", "5", "--rounds", "3", "--out", TMP "/rounds/out", "--no-plots", NULL};
    cli_run r = run_cli(args);
    ck_assert_msg(r.code == 0, "exit %d: %s", r.code, r.err);
    /* The order of the runs: a's four (nsgs, CAPPED, nsgs twice), then b's. */
    const char *order[] = {"] a.hdf5 nsgs: ", "] a.hdf5 " CAPPED ": ", "] a.hdf5 nsgs: ", "] a.hdf5 nsgs: ",
                           "] b.hdf5 nsgs: "};
    const char *at = r.err;
    for (int k = 0; k < 5; ++k) {
        at = strstr(at, order[k]);
        ck_assert_msg(at != NULL, "run %d (%s) not in order:\n%s", k, order[k], r.err);
        ++at;
    }
    csv *runs = csv_read(TMP "/rounds/out/runs.csv");
    ck_assert_int_eq(runs->rows, 5);
    const char *problems[] = {"a.hdf5", "b.hdf5"};
    for (int k = 0; k < 2; ++k) {
        double t[4], capped[4];
        ck_assert_int_eq(progress_times(r.err, problems[k], CAPPED, capped, 4), 1);
        ck_assert_int_eq(progress_times(r.err, problems[k], "nsgs", t, 4), 3);
        const double lo = fmin(t[0], fmin(t[1], t[2])), hi = fmax(t[0], fmax(t[1], t[2]));
        const double median = t[0] + t[1] + t[2] - lo - hi;
        const int row = csv_find(runs, "problem", problems[k], "solver", "nsgs");
        ck_assert_int_gt(row, 0);
        ck_assert_str_eq(csv_get(runs, row, "status"), "converged");
        char shown[32], expected[32];
        snprintf(shown, sizeof shown, "%.3g", atof(csv_get(runs, row, "time")));
        snprintf(expected, sizeof expected, "%.3g", median);
        ck_assert_msg(strcmp(shown, expected) == 0, "%s: time %s, the runs' %g %g %g", problems[k], shown, t[0], t[1],
                      t[2]);
        const int capped_row = csv_find(runs, "problem", problems[k], "solver", CAPPED);
        ck_assert_int_gt(capped_row, 0);
        ck_assert_str_eq(csv_get(runs, capped_row, "status"), "max_iter");
    }
    csv_free(runs);
    run_free(&r);
    const char *bad[] = {"bench", TMP "/rounds/problems", "--rounds", "0", "--out", TMP "/never", NULL};
    ck_assert_int_eq(cli_exit_code(bad), 2);
}
END_TEST

/* ---- Isolation: a hanging run is killed at its limit, a crash is recorded, the rest runs -- */

START_TEST(test_isolation) {
    fresh_dir(TMP "/iso/problems");
    make_problem(TMP "/iso/problems/a-hangs.hdf5");
    make_problem(TMP "/iso/problems/b-crashes.hdf5");
    make_problem(TMP "/iso/problems/c-fine.hdf5");
    setenv("FRIX_BENCH_FAULT", "hang:a-hangs,crash:b-crashes", 1);
    const char *args[] = {"bench", TMP "/iso/problems", "--solvers", "nsgs", "--time-limit", "0.3",
                          "--grace", "0.5", "--out", TMP "/iso/out", "--no-plots", NULL};
    double t0 = now();
    ck_assert_int_eq(cli_exit_code(args), 0);
    double wall = now() - t0;
    unsetenv("FRIX_BENCH_FAULT");
    ck_assert_msg(wall < 10, "campaign took %g s", wall);

    csv *runs = csv_read(TMP "/iso/out/runs.csv");
    ck_assert_int_eq(runs->rows, 4);
    int a = csv_find(runs, "problem", "a-hangs.hdf5", NULL, NULL);
    int b = csv_find(runs, "problem", "b-crashes.hdf5", NULL, NULL);
    int c = csv_find(runs, "problem", "c-fine.hdf5", NULL, NULL);
    ck_assert(a > 0 && b > 0 && c > 0);
    ck_assert_str_eq(csv_get(runs, a, "status"), "timeout");
    ck_assert_msg(strstr(csv_get(runs, a, "note"), "killed after") != NULL, "note: %s", csv_get(runs, a, "note"));
    double t = atof(csv_get(runs, a, "time"));
    ck_assert_msg(t >= 0.8 && t < 5, "killed after %g s, expected 0.3 + 0.5", t);
    ck_assert_str_eq(csv_get(runs, b, "status"), "crash(SIGABRT)");
    ck_assert_str_eq(csv_get(runs, c, "status"), "converged");
    csv_free(runs);
    char *md = slurp(TMP "/iso/out/summary.md", NULL);
    ck_assert_msg(strstr(md, "| nsgs | 1/3 | 1/3 | 1/3 | 1 | 1 | 0 |") != NULL, "summary: %s", md);
    free(md);
}
END_TEST

/* ---- The Siconos comparator, when built ---------------------------------------------------- */

START_TEST(test_siconos_comparator) {
    char adapter[1024];
    snprintf(adapter, sizeof adapter, "%s", FRIX_CLI);
    char *slash = strrchr(adapter, '/');
    ck_assert_ptr_nonnull(slash);
    strcpy(slash + 1, "frix-siconos");
    if (access(adapter, X_OK) != 0) {
        printf("test_bench: frix-siconos not built (no Siconos): comparator test skipped\n");
        return;
    }
    fresh_dir(TMP "/sic/problems");
    make_problem(TMP "/sic/problems/tiny.hdf5");
    const char *direct[] = {TMP "/sic/problems/tiny.hdf5", "--solver", "FC3D_NSN_AC", "--tol", "1e-10", "--json", NULL};
    cli_run sic = run_program(adapter, direct);
    ck_assert_int_eq(sic.code, 0);
    ck_assert_msg(strstr(sic.out, "\"solver\":\"siconos:NSN_AC\"") && strstr(sic.out, "\"status\":\"converged\""),
                  "frix-siconos: %s", sic.out);
    run_free(&sic);

    /* --guess K: from a guess that is the solution, Siconos's NSGS is done at its first sweep;
     * a guess the file lacks is refused. */
    frix_problem *p = NULL;
    double r0[6] = {0}, u0[6] = {0};
    ck_assert_int_eq(frix_fclib_read(TMP "/sic/problems/tiny.hdf5", &p), FRIX_OK);
    ck_assert_int_eq(frix_problem_contacts(p), 2);
    ck_assert_int_eq(frix_solve(p, NULL, r0, u0, NULL, NULL), FRIX_OK);
    ck_assert_int_eq(frix_fclib_write(TMP "/sic/guessed.hdf5", p, NULL, NULL, NULL, 1, r0, u0, NULL), FRIX_OK);
    frix_problem_free(p);
    const char *from_guess[] = {TMP "/sic/guessed.hdf5", "--solver", "NSGS", "--tol", "1e-8", "--guess", "1", "--json", NULL};
    const char *past[] = {TMP "/sic/guessed.hdf5", "--solver", "NSGS", "--guess", "2", NULL};
    cli_run g = run_program(adapter, from_guess), bad = run_program(adapter, past);
    ck_assert_msg(g.code == 0 && json_number_at(g.out, "iterations") <= 1, "frix-siconos --guess 1: %s%s", g.out, g.err);
    ck_assert_msg(bad.code == 2 && strstr(bad.err, "holds 1 guess"), "frix-siconos --guess 2: %d %s", bad.code, bad.err);
    run_free(&g);
    run_free(&bad);
    /* The bench's --guess: both libraries' runs start from the guess (the solution here), so
     * each takes at most one sweep; a guess the file lacks is the run's error. */
    fresh_dir(TMP "/sic/guessed");
    ck_assert_int_eq(rename(TMP "/sic/guessed.hdf5", TMP "/sic/guessed/guessed.hdf5"), 0);
    const char *bench_guess[] = {"bench", TMP "/sic/guessed", "--solvers", "nsgs,siconos:NSGS", "--tol", "1e-8",
                                 "--guess", "1", "--out", TMP "/sic/guess-out", "--no-plots", "-q", NULL};
    ck_assert_int_eq(cli_exit_code(bench_guess), 0);
    csv *guessed = csv_read(TMP "/sic/guess-out/runs.csv");
    ck_assert_int_eq(guessed->rows, 3); /* the header and two runs */
    for (int row = 1; row <= 2; ++row) {
        ck_assert_str_eq(csv_get(guessed, row, "status"), "converged");
        ck_assert_int_le(atoi(csv_get(guessed, row, "iterations")), 1);
    }
    csv_free(guessed);
    bench_guess[7] = "2";
    ck_assert_int_eq(cli_exit_code(bench_guess), 0);
    guessed = csv_read(TMP "/sic/guess-out/runs.csv");
    ck_assert_int_gt(csv_find(guessed, "solver", "nsgs", "status", "error"), 0);
    csv_free(guessed);

    const char *args[] = {"bench", TMP "/sic/problems", "--solvers", "nsgs,siconos:NSGS,siconos:504",
                          "--tol", "1e-10", "--time-limit", "5", "--out", TMP "/sic/out", "--no-plots", NULL};
    ck_assert_int_eq(cli_exit_code(args), 0);
    csv *runs = csv_read(TMP "/sic/out/runs.csv");
    ck_assert_int_eq(runs->rows, 4);
    int r = csv_find(runs, "solver", "siconos:NSGS", NULL, NULL);
    ck_assert_int_gt(r, 0);
    ck_assert_str_eq(csv_get(runs, r, "status"), "converged");
    ck_assert_str_eq(csv_get(runs, r, "solver_id"), "500");
    ck_assert_double_le(atof(csv_get(runs, r, "error")), 1e-10); /* frix's measure of Siconos's r */
    ck_assert_int_gt(csv_find(runs, "solver", "siconos:NSN_AC", "status", "converged"), 0);
    csv_free(runs);
    char *md = slurp(TMP "/sic/out/summary.md", NULL);
    ck_assert_msg(strstr(md, "| 500 | nsgs | 1 | siconos:NSGS | 1 | 1 |") != NULL, "summary: %s", md);
    free(md);

    /* A global problem: a GFC3D solver (gfc3d_driver) solves it, frix measures (r, v). */
    fresh_dir(TMP "/sicg/problems");
    make_problem(TMP "/sicg/problems/tiny.hdf5");
    make_global_problem(TMP "/sicg/problems/tiny-global.hdf5");
    const char *global[] = {TMP "/sicg/problems/tiny-global.hdf5", "--solver", "GLOBAL_FRICTION_3D_NSN_AC",
                            "--tol", "1e-10", "--json", NULL};
    sic = run_program(adapter, global);
    ck_assert_msg(sic.code == 0, "frix-siconos: exit %d: %s%s", sic.code, sic.out, sic.err);
    ck_assert_msg(strstr(sic.out, "\"kind\":\"global\"") && strstr(sic.out, "\"solver\":\"siconos:GFC3D_NSN_AC\"") &&
                      strstr(sic.out, "\"status\":\"converged\""),
                  "frix-siconos: %s", sic.out);
    ck_assert_double_le(json_number_at(sic.out, "error"), 1e-10); /* frix's measure of Siconos's (r, v) */
    ck_assert_double_le(json_number_at(sic.out, "equilibrium"), 1e-10);
    ck_assert_msg(strchr(sic.out, '\n') == sic.out + strlen(sic.out) - 1, "one JSON line: %s", sic.out);
    run_free(&sic);

    /* A global rolling problem: GRFC3D_NSGS_WR (g_rolling_fc3d_driver) solves it; the local
     * rolling solvers refuse it and name the global one. */
    make_global_rolling_problem(TMP "/sicg/rolling-global.hdf5");
    const char *rolling_global[] = {TMP "/sicg/rolling-global.hdf5", "--solver", "GLOBAL_ROLLING_FRICTION_3D_NSGS_WR",
                                    "--tol", "1e-10", "--json", NULL};
    sic = run_program(adapter, rolling_global);
    ck_assert_msg(sic.code == 0 && strstr(sic.out, "\"kind\":\"rolling-global\"") &&
                      strstr(sic.out, "\"solver\":\"siconos:GRFC3D_NSGS_WR\""),
                  "frix-siconos: exit %d: %s%s", sic.code, sic.out, sic.err);
    ck_assert_double_le(json_number_at(sic.out, "error"), 1e-10);
    run_free(&sic);
    const char *local_rolling_on_global[] = {TMP "/sicg/rolling-global.hdf5", "--solver", "RFC3D_NSGS", NULL};
    sic = run_program(adapter, local_rolling_on_global);
    ck_assert_msg(sic.code == 2 && strstr(sic.err, "use GRFC3D_NSGS_WR"), "%d %s", sic.code, sic.err);
    run_free(&sic);

    /* A solver for the other kind of problem is refused, with exit status 2. */
    const char *local_on_global[] = {TMP "/sicg/problems/tiny-global.hdf5", "--solver", "NSGS", NULL};
    sic = run_program(adapter, local_on_global);
    ck_assert_int_eq(sic.code, 2);
    ck_assert_msg(strstr(sic.err, "is a local solver") != NULL, "stderr: %s", sic.err);
    run_free(&sic);
    const char *global_on_local[] = {TMP "/sicg/problems/tiny.hdf5", "--solver", "607", NULL};
    sic = run_program(adapter, global_on_local);
    ck_assert_int_eq(sic.code, 2);
    ck_assert_msg(strstr(sic.err, "is a global solver") != NULL, "stderr: %s", sic.err);
    run_free(&sic);

    /* The bench runs each solver on each problem: the mismatched pairs are unsupported. */
    const char *mixed[] = {"bench", TMP "/sicg/problems", "--solvers", "siconos:NSGS,siconos:GFC3D_NSN_AC",
                           "--tol", "1e-10", "--time-limit", "5", "--out", TMP "/sicg/out", "--no-plots", NULL};
    ck_assert_int_eq(cli_exit_code(mixed), 0);
    runs = csv_read(TMP "/sicg/out/runs.csv");
    ck_assert_int_eq(runs->rows, 5);
    r = csv_find(runs, "problem", "tiny-global.hdf5", "solver", "siconos:GFC3D_NSN_AC");
    ck_assert_int_gt(r, 0);
    ck_assert_str_eq(csv_get(runs, r, "status"), "converged");
    ck_assert_str_eq(csv_get(runs, r, "solver_id"), "607");
    ck_assert_double_le(atof(csv_get(runs, r, "error")), 1e-10);
    ck_assert_int_gt(csv_find(runs, "problem", "tiny.hdf5", "solver", "siconos:GFC3D_NSN_AC"), 0);
    ck_assert_str_eq(csv_get(runs, csv_find(runs, "problem", "tiny.hdf5", "solver", "siconos:GFC3D_NSN_AC"), "status"),
                     "unsupported");
    ck_assert_str_eq(csv_get(runs, csv_find(runs, "problem", "tiny-global.hdf5", "solver", "siconos:NSGS"), "status"),
                     "unsupported");
    ck_assert_str_eq(csv_get(runs, csv_find(runs, "problem", "tiny.hdf5", "solver", "siconos:NSGS"), "status"),
                     "converged");
    csv_free(runs);
}
END_TEST

/* ==== Issue 49: the bench reads no problem itself; each run reads its own, in its child ====
 * A bad file costs its own rows only (status unreadable, the reader's message as the note,
 * left out of the tables), and the per-run time limit covers the read. */

/* Writes a slow .dat at `path` and returns how long `frix info` takes to read it here (the
 * machine's speed decides: the file grows until the read takes at least 0.25 s, or nc 1500). */
static double make_slow_dat(const char *path) {
    double seconds = 0;
    for (int nc = 1000; nc <= 1500; nc += 500) {
        frix_test_write_slow_dat(path, nc);
        const char *info[] = {"info", path, NULL};
        const double t0 = now();
        ck_assert_int_eq(cli_exit_code(info), 0);
        seconds = now() - t0;
        if (seconds >= 0.25) break;
    }
    return seconds;
}

START_TEST(test_bad_file_costs_its_row) {
    fresh_dir(TMP "/bad/problems");
    make_problem(TMP "/bad/problems/a-good.hdf5");
    /* A truncated copy of a good file, and a .dat with a NUL byte: both refused by the reader. */
    long size = 0;
    char *good = slurp(TMP "/bad/problems/a-good.hdf5", &size);
    spit(TMP "/bad/problems/b-truncated.hdf5", good, size / 2);
    free(good);
    spit(TMP "/bad/nul.dat", "3 1\n0 3 3\n3 3\n1 0\0 0", 20);
    const char *args[] = {"bench", TMP "/bad/problems", TMP "/bad/nul.dat", "--solvers", "nsgs", "--time-limit", "10",
                          "--out", TMP "/bad/out", "--no-plots", NULL};
    cli_run r = run_cli(args);
    ck_assert_msg(r.code == 0, "exit %d: %s", r.code, r.err);
    run_free(&r);

    csv *runs = csv_read(TMP "/bad/out/runs.csv");
    ck_assert_int_eq(runs->rows, 4);
    int a = csv_find(runs, "problem", "a-good.hdf5", NULL, NULL);
    int b = csv_find(runs, "problem", "b-truncated.hdf5", NULL, NULL);
    int n = csv_find(runs, "problem", "nul.dat", NULL, NULL);
    ck_assert(a > 0 && b > 0 && n > 0);
    ck_assert_str_eq(csv_get(runs, a, "status"), "converged");
    ck_assert_str_eq(csv_get(runs, a, "contacts"), "2"); /* the sizes come from the run's read */
    ck_assert_str_eq(csv_get(runs, a, "dofs"), "6");
    for (int k = 0; k < 2; ++k) {
        int row = k == 0 ? b : n;
        ck_assert_str_eq(csv_get(runs, row, "status"), "unreadable");
        ck_assert_msg(strstr(csv_get(runs, row, "note"), "cannot read ") != NULL, "note: %s",
                      csv_get(runs, row, "note"));
        ck_assert_str_eq(csv_get(runs, row, "contacts"), ""); /* not known: never read */
    }
    ck_assert_msg(strstr(csv_get(runs, n, "note"), "NUL") != NULL || strstr(csv_get(runs, n, "note"), "nul") != NULL,
                  "note: %s", csv_get(runs, n, "note"));
    csv_free(runs);
    /* Left out of the tables: the one good problem is all there is to solve. */
    char *md = slurp(TMP "/bad/out/summary.md", NULL);
    ck_assert_msg(strstr(md, "| nsgs | 1/1 |") != NULL, "summary: %s", md);
    ck_assert_msg(strstr(md, "Left out, as no run could read them: b-truncated.hdf5") != NULL, "summary: %s", md);
    free(md);
}
END_TEST

START_TEST(test_time_limit_covers_read) {
    fresh_dir(TMP "/slow");
    const char *dat = TMP "/slow/slow.dat";
    const double read = make_slow_dat(dat);
    /* A limit well below the read: the run must be stopped while reading. */
    double limit = read / 5;
    if (limit > 0.05) limit = 0.05;
    char limit_text[32];
    snprintf(limit_text, sizeof limit_text, "%g", limit);

    /* No grace: killed at the limit, mid-read; the campaign does not wait for the read. */
    const char *kill_args[] = {"bench", dat, "--solvers", "nsgs", "--time-limit", limit_text, "--grace", "0",
                               "--out", TMP "/slow/killed", "--no-plots", NULL};
    cli_run r = run_cli(kill_args);
    ck_assert_msg(r.code == 0, "exit %d: %s", r.code, r.err);
    run_free(&r);
    csv *runs = csv_read(TMP "/slow/killed/runs.csv");
    ck_assert_int_eq(runs->rows, 2);
    ck_assert_str_eq(csv_get(runs, 1, "status"), "timeout");
    ck_assert_msg(strstr(csv_get(runs, 1, "note"), "while reading the problem") != NULL, "note: %s",
                  csv_get(runs, 1, "note"));
    const double killed_after = atof(csv_get(runs, 1, "time"));
    ck_assert_msg(killed_after < read, "killed after %g s, the read takes %g s", killed_after, read);
    csv_free(runs);

    /* With grace the read ends, past the limit: the run reports it and does not solve. */
    const char *late_args[] = {"bench", dat, "--solvers", "nsgs", "--time-limit", limit_text, "--grace", "60",
                               "--out", TMP "/slow/late", "--no-plots", NULL};
    r = run_cli(late_args);
    ck_assert_msg(r.code == 0, "exit %d: %s", r.code, r.err);
    run_free(&r);
    runs = csv_read(TMP "/slow/late/runs.csv");
    ck_assert_str_eq(csv_get(runs, 1, "status"), "time_limit");
    ck_assert_msg(strstr(csv_get(runs, 1, "note"), "reading the problem took") != NULL, "note: %s",
                  csv_get(runs, 1, "note"));
    ck_assert_str_eq(csv_get(runs, 1, "iterations"), "0");
    csv_free(runs);
    unlink(dat);
}
END_TEST
/* ==== end of the issue 49 block ==== */

int main(void) {
    Suite *s = suite_create("bench");
    TCase *tc = tcase_create("bench");
    tcase_set_timeout(tc, 120);
    tcase_add_test(tc, test_csv_files);
    tcase_add_test(tc, test_usage_errors);
    tcase_add_test(tc, test_solver_options);
    tcase_add_test(tc, test_profile_known_values);
    tcase_add_test(tc, test_best_per_problem);
    tcase_add_test(tc, test_rounds);
    tcase_add_test(tc, test_isolation);
    tcase_add_test(tc, test_siconos_comparator);
    tcase_add_test(tc, test_bad_file_costs_its_row);
    tcase_add_test(tc, test_time_limit_covers_read);
    suite_add_tcase(s, tc);
    return frix_run_suite(s);
}
