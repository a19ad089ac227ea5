/* The `frix` command line, run as a separate process: exit codes, output, JSON validity,
 * the written solution file, and one-line messages for usage errors and bad input.
 * The shared-data cases (FRIX_SHARED_DIR/fclib) are skipped with a note when absent. */
#define _POSIX_C_SOURCE 200809L

#include <frix/frix.h>

#include <ctype.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "check_main.h"
#include "cli_runner.h"

#define SHARED_FCLIB FRIX_SHARED_DIR "/fclib"
#define CAPSULES SHARED_FCLIB "/local/Capsules-i125-1213.hdf5"
#define ROVER SHARED_FCLIB "/converted/Rover4613.from_dat.hdf5"
#define BOX_STACKS SHARED_FCLIB "/global/Box_Stacks-i0035-31-0.hdf5"
#define ROCKPILE SHARED_FCLIB "/converted/RockPile_tob1.from_dat.hdf5"
#define TINY FRIX_TEST_TMPDIR "/cli_tiny.hdf5"
#define TEXT_FILE FRIX_TEST_TMPDIR "/cli_not_hdf5.txt"

static int exists(const char *path) {
    struct stat st;
    return stat(path, &st) == 0;
}

/* ---- A strict JSON validator (RFC 8259 grammar), enough to prove the output parses. - */

static const char *json_value(const char *p);

static const char *json_ws(const char *p) {
    while (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r') ++p;
    return p;
}

static const char *json_string(const char *p) {
    if (*p++ != '"') return NULL;
    while (*p != '"') {
        unsigned char c = (unsigned char)*p;
        if (c == '\0' || c < 0x20) return NULL;
        if (c == '\\') {
            ++p;
            if (*p == 'u') {
                for (int k = 1; k <= 4; ++k)
                    if (!isxdigit((unsigned char)p[k])) return NULL;
                p += 4;
            } else if (!strchr("\"\\/bfnrt", *p) || *p == '\0') {
                return NULL;
            }
        }
        ++p;
    }
    return p + 1;
}

static const char *json_number(const char *p) {
    if (*p == '-') ++p;
    if (*p == '0')
        ++p;
    else if (isdigit((unsigned char)*p))
        while (isdigit((unsigned char)*p)) ++p;
    else
        return NULL;
    if (*p == '.') {
        ++p;
        if (!isdigit((unsigned char)*p)) return NULL;
        while (isdigit((unsigned char)*p)) ++p;
    }
    if (*p == 'e' || *p == 'E') {
        ++p;
        if (*p == '+' || *p == '-') ++p;
        if (!isdigit((unsigned char)*p)) return NULL;
        while (isdigit((unsigned char)*p)) ++p;
    }
    return p;
}

static const char *json_members(const char *p, char close, int keyed) {
    p = json_ws(p + 1);
    if (*p == close) return p + 1;
    for (;;) {
        if (keyed) {
            p = json_string(p);
            if (!p) return NULL;
            p = json_ws(p);
            if (*p++ != ':') return NULL;
        }
        p = json_value(p);
        if (!p) return NULL;
        p = json_ws(p);
        if (*p == close) return p + 1;
        if (*p++ != ',') return NULL;
        p = json_ws(p);
    }
}

static const char *json_value(const char *p) {
    p = json_ws(p);
    switch (*p) {
        case '{': return json_members(p, '}', 1);
        case '[': return json_members(p, ']', 0);
        case '"': return json_string(p);
        case 't': return strncmp(p, "true", 4) == 0 ? p + 4 : NULL;
        case 'f': return strncmp(p, "false", 5) == 0 ? p + 5 : NULL;
        case 'n': return strncmp(p, "null", 4) == 0 ? p + 4 : NULL;
        default: return json_number(p);
    }
}

static int json_valid(const char *text) {
    const char *end = json_value(text);
    return end != NULL && *json_ws(end) == '\0';
}

/* ---- Fixtures --------------------------------------------------------------------- */

/* Two independent contacts with a closed-form solution, written once per process, so the
 * CLI can be exercised without the shared data. */
static void make_tiny_problem(void) {
    if (exists(TINY)) return;
    static const double blocks[18] = {2, 0, 0, 0, 1, 0, 0, 0, 1, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    static const int64_t rows[2] = {0, 1}, cols[2] = {0, 1};
    static const double q[6] = {-1, 0.1, 0, -2, 0, 3}, mu[2] = {0.5, 0.3};
    frix_matrix *W = NULL;
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_matrix_from_blocks(2, 2, 2, rows, cols, blocks, &W), FRIX_OK);
    ck_assert_int_eq(frix_problem_local(W, q, mu, 2, &p), FRIX_OK);
    ck_assert_int_eq(frix_problem_set_title(p, "cli test: two contacts"), FRIX_OK);
    ck_assert_int_eq(frix_problem_set_description(p, "independent,\nin closed form"), FRIX_OK);
    ck_assert_int_eq(frix_problem_set_math_info(p, "u = W r + q"), FRIX_OK);
    char tmp[512];
    snprintf(tmp, sizeof tmp, "%s.%ld", TINY, (long)getpid());
    ck_assert_int_eq(frix_fclib_write(tmp, p, NULL, NULL, NULL, 0, NULL, NULL, NULL), FRIX_OK);
    ck_assert_int_eq(rename(tmp, TINY), 0);
    frix_problem_free(p);
    frix_matrix_free(W);
}

static void make_text_file(void) { spit_text(TEXT_FILE, "this is not an HDF5 file\n"); }

/* Reads back a file written by `frix solve --output` and returns the error of its
 * solution, recomputed by the library from the stored problem and r (and v). */
static double stored_solution_error(const char *path, int64_t expected_contacts) {
    frix_problem *p = NULL;
    ck_assert_msg(frix_fclib_read(path, &p) == FRIX_OK, "%s: %s", path, frix_last_error_message());
    ck_assert_int_eq(frix_problem_contacts(p), expected_contacts);
    int64_t m = frix_problem_contact_dofs(p), n = frix_problem_dofs(p);
    double *r = calloc((size_t)m + 1, sizeof *r), *u = calloc((size_t)m + 1, sizeof *u);
    double *v = calloc((size_t)n + 1, sizeof *v);
    int global = frix_problem_get_kind(p) == FRIX_PROBLEM_GLOBAL;
    ck_assert_msg(frix_fclib_read_solution(path, p, r, u, global ? v : NULL) == FRIX_OK, "%s: %s",
                  path, frix_last_error_message());
    double err = NAN;
    ck_assert_int_eq(frix_problem_error(p, r, global ? v : NULL, &err), FRIX_OK);
    /* The stored u must be the u of the stored r. */
    double *u2 = calloc((size_t)m + 1, sizeof *u2);
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_problem_measure(p, r, global ? v : NULL, u2, info), FRIX_OK);
    for (int64_t i = 0; i < m; ++i)
        ck_assert_msg(fabs(u[i] - u2[i]) <= 1e-9 * (1 + fabs(u2[i])), "u[%lld] %g vs %g",
                      (long long)i, u[i], u2[i]);
    frix_info_free(info);
    free(r);
    free(u);
    free(u2);
    free(v);
    frix_problem_free(p);
    return err;
}

/* The value of a "label   value" line of the text output, or NULL. */
static const char *text_field(const char *out, const char *label) {
    size_t n = strlen(label);
    for (const char *line = out; *line;) {
        if (strncmp(line, label, n) == 0 && line[n] == ' ') return line + n;
        const char *eol = strchr(line, '\n');
        if (!eol) break;
        line = eol + 1;
    }
    return NULL;
}

/* A usage error or bad input: exit 2, nothing on stdout, one "frix: ..." line on stderr. */
static void expect_usage_error(const char *const *args, const char *must_contain) {
    cli_run r = run_cli(args);
    ck_assert_msg(r.code == 2, "%s %s: exit %d, stderr: %s", args[0], args[1] ? args[1] : "",
                  r.code, r.err);
    ck_assert_msg(strncmp(r.err, "frix: ", 6) == 0, "stderr: %s", r.err);
    size_t len = strlen(r.err);
    ck_assert_msg(len > 7 && r.err[len - 1] == '\n' && strchr(r.err, '\n') == r.err + len - 1,
                  "stderr is not one line: '%s'", r.err);
    if (must_contain)
        ck_assert_msg(strstr(r.err, must_contain) != NULL, "stderr lacks '%s': %s", must_contain,
                      r.err);
    ck_assert_str_eq(r.out, "");
    run_free(&r);
}

/* ---- Tests without shared data ---------------------------------------------------- */

START_TEST(test_help_and_version) {
    const char *a1[] = {"--help", NULL};
    cli_run r = run_cli(a1);
    ck_assert_int_eq(r.code, 0);
    ck_assert(strstr(r.out, "frix solve FILE.hdf5") && strstr(r.out, "frix info") &&
              strstr(r.out, "frix solvers"));
    run_free(&r);

    const char *a2[] = {"help", "solve", NULL};
    const char *a3[] = {"solve", "--help", NULL};
    cli_run h1 = run_cli(a2), h2 = run_cli(a3);
    ck_assert_int_eq(h1.code, 0);
    ck_assert_int_eq(h2.code, 0);
    ck_assert(strstr(h1.out, "--tol") && strstr(h1.out, "--output"));
    ck_assert_str_eq(h1.out, h2.out);
    run_free(&h1);
    run_free(&h2);

    const char *a4[] = {"info", "--help", NULL};
    const char *a5[] = {"solvers", "-h", NULL};
    cli_run i = run_cli(a4), s = run_cli(a5);
    ck_assert_int_eq(i.code, 0);
    ck_assert_int_eq(s.code, 0);
    ck_assert(strstr(i.out, "Usage: frix info") && strstr(s.out, "Usage: frix solvers"));
    run_free(&i);
    run_free(&s);

    const char *a6[] = {"--version", NULL};
    cli_run v = run_cli(a6);
    ck_assert_int_eq(v.code, 0);
    ck_assert_msg(strstr(v.out, FRIX_VERSION_STRING) != NULL, "%s", v.out);
    run_free(&v);
}
END_TEST

START_TEST(test_solvers) {
    const char *a1[] = {"solvers", NULL};
    cli_run r = run_cli(a1);
    ck_assert_int_eq(r.code, 0);
    const char *line = strstr(r.out, "500");
    ck_assert_msg(line != NULL, "%s", r.out);
    const char *eol = strchr(line, '\n');
    const char *name = strstr(line, "nsgs");
    ck_assert_msg(name != NULL && (eol == NULL || name < eol), "500 and nsgs not on one line: %s",
                  r.out);
    run_free(&r);

    const char *a2[] = {"solvers", "--json", NULL};
    cli_run j = run_cli(a2);
    ck_assert_int_eq(j.code, 0);
    ck_assert_msg(json_valid(j.out), "invalid JSON: %s", j.out);
    ck_assert(strstr(j.out, "\"id\":500") && strstr(j.out, "\"name\":\"nsgs\""));
    run_free(&j);

    /* One solver in detail, by name, id or Siconos spelling. */
    const char *spellings[] = {"nsgs", "500", "FRICTION_3D_NSGS"};
    for (int k = 0; k < 3; ++k) {
        const char *a3[] = {"solvers", spellings[k], NULL};
        cli_run d = run_cli(a3);
        ck_assert_int_eq(d.code, 0);
        ck_assert_msg(strstr(d.out, "nsgs (id 500)") && strstr(d.out, "tolerance"), "%s", d.out);
        run_free(&d);
    }
    const char *a4[] = {"solvers", "nsgs", "--json", NULL};
    cli_run dj = run_cli(a4);
    ck_assert_int_eq(dj.code, 0);
    ck_assert_msg(json_valid(dj.out), "invalid JSON: %s", dj.out);
    run_free(&dj);
}
END_TEST

START_TEST(test_tiny_problem) {
    make_tiny_problem();
    const char *a1[] = {"info", TINY, NULL};
    cli_run i = run_cli(a1);
    ck_assert_int_eq(i.code, 0);
    ck_assert_msg(text_field(i.out, "contacts") && atoi(text_field(i.out, "contacts")) == 2, "%s",
                  i.out);
    ck_assert(strstr(i.out, "cli test: two contacts") && strstr(i.out, "local"));
    /* The texts come through the reading process, the description on one line. */
    ck_assert_msg(strstr(i.out, "\ndescription      independent, in closed form\n") &&
                      strstr(i.out, "\nmath info        u = W r + q\n"),
                  "%s", i.out);
    run_free(&i);

    const char *out = FRIX_TEST_TMPDIR "/cli_tiny_solution.hdf5";
    unlink(out);
    const char *a2[] = {"solve", TINY, "--tol", "1e-12", "--output", out, NULL};
    cli_run s = run_cli(a2);
    ck_assert_msg(s.code == 0, "exit %d: %s%s", s.code, s.out, s.err);
    ck_assert(strstr(s.out, "auto (id 900)") && strstr(s.out, "converged"));
    run_free(&s);
    ck_assert_double_le(stored_solution_error(out, 2), 1e-12);

    /* Options as --name=value, the solver by its Siconos spelling, and --set. */
    const char *a3[] = {"solve", "--tol=1e-10", "--solver=FC3D_NSGS", "--set", "max_iter=50",
                        "--json", TINY, NULL};
    cli_run j = run_cli(a3);
    ck_assert_msg(j.code == 0, "exit %d: %s%s", j.code, j.out, j.err);
    ck_assert_msg(json_valid(j.out), "invalid JSON: %s", j.out);
    ck_assert_msg(strstr(j.out, "\"status\":\"converged\"") && strstr(j.out, "\"solver_id\":500") &&
                      strstr(j.out, "\"tolerance\":1e-10") && strstr(j.out, "\"output\":null"),
                  "%s", j.out);
    run_free(&j);
}
END_TEST

/* --guess K starts from the file's guess K: a file whose one guess is its solution has converged
 * before any sweep, where the same solve from r = 0 takes sweeps; a guess the file lacks, or a
 * number that is none, is refused (exit 2) with the count the file holds. */
START_TEST(test_solve_from_a_guess) {
    make_tiny_problem();
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_fclib_read(TINY, &p), FRIX_OK);
    double r[6] = {0}, u[6] = {0};
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_NSGS, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 1e-13), FRIX_OK);
    ck_assert_int_eq(frix_solve(p, o, r, u, NULL, NULL), FRIX_OK);
    const char *guessed = FRIX_TEST_TMPDIR "/cli_tiny_guessed.hdf5";
    ck_assert_int_eq(frix_fclib_write(guessed, p, NULL, NULL, NULL, 1, r, u, NULL), FRIX_OK);
    frix_options_free(o);
    frix_problem_free(p);

    const char *from_guess[] = {"solve", guessed, "--guess", "1", "--solver", "nsgs", "--tol", "1e-10", "--json", NULL};
    const char *from_zero[] = {"solve", guessed, "--solver", "nsgs", "--tol", "1e-10", "--json", NULL};
    cli_run g = run_cli(from_guess), z = run_cli(from_zero);
    ck_assert_msg(g.code == 0 && z.code == 0, "exit %d, %d: %s%s", g.code, z.code, g.err, z.err);
    ck_assert_msg(strstr(g.out, "\"iterations\":0,"), "%s", g.out);
    ck_assert_msg(!strstr(z.out, "\"iterations\":0,"), "%s", z.out);
    run_free(&g);
    run_free(&z);

    const char *past[] = {"solve", guessed, "--guess", "2", NULL};
    const char *none[] = {"solve", TINY, "--guess", "1", NULL};
    const char *bad[] = {"solve", TINY, "--guess", "0", NULL};
    cli_run a = run_cli(past), b = run_cli(none), c = run_cli(bad);
    ck_assert_msg(a.code == 2 && strstr(a.err, "holds 1 guess"), "exit %d: %s", a.code, a.err);
    ck_assert_msg(b.code == 2 && strstr(b.err, "holds 0 guesses"), "exit %d: %s", b.code, b.err);
    ck_assert_msg(c.code == 2 && strstr(c.err, "--guess expects"), "exit %d: %s", c.code, c.err);
    run_free(&a);
    run_free(&b);
    run_free(&c);
}
END_TEST

START_TEST(test_usage_errors) {
    make_tiny_problem();
    make_text_file();
    const char *none[] = {NULL};
    expect_usage_error(none, "missing command");
    const char *a1[] = {"frobnicate", NULL};
    expect_usage_error(a1, "unknown command");
    const char *a2[] = {"--frobnicate", NULL};
    expect_usage_error(a2, "unknown option");
    const char *a3[] = {"solve", NULL};
    expect_usage_error(a3, "FILE");
    const char *a4[] = {"solve", TINY, "--frobnicate", NULL};
    expect_usage_error(a4, "unknown option '--frobnicate'");
    const char *a5[] = {"solve", TINY, "--tol", NULL};
    expect_usage_error(a5, "needs a value");
    const char *a6[] = {"solve", TINY, "--tol", "abc", NULL};
    expect_usage_error(a6, "--tol");
    const char *a7[] = {"solve", TINY, "--tol", "-1", NULL};
    expect_usage_error(a7, "--tol -1");
    const char *a8[] = {"solve", TINY, "--max-iter", "1.5", NULL};
    expect_usage_error(a8, "integer");
    const char *a9[] = {"solve", TINY, "--max-iter", "-3", NULL};
    expect_usage_error(a9, "--max-iter -3");
    const char *a10[] = {"solve", TINY, "--time-limit", "nan", NULL};
    expect_usage_error(a10, "--time-limit");
    const char *a11[] = {"solve", TINY, "--solver", "nosuch", NULL};
    expect_usage_error(a11, "unknown solver 'nosuch'");
    const char *a12[] = {"solve", TINY, "--json=1", NULL};
    expect_usage_error(a12, "takes no value");
    const char *a13[] = {"solve", TINY, "--set", "nosuch=1", NULL};
    expect_usage_error(a13, "nosuch");
    const char *a14[] = {"solve", TINY, TINY, NULL};
    expect_usage_error(a14, "one FILE");
    const char *a15[] = {"help", "frobnicate", NULL};
    expect_usage_error(a15, "frobnicate");
    const char *a16[] = {"solvers", "nosuch", NULL};
    expect_usage_error(a16, "unknown solver");

    /* Bad input files. */
    const char *missing = FRIX_TEST_TMPDIR "/cli_no_such_file.hdf5";
    const char *b1[] = {"solve", missing, NULL};
    expect_usage_error(b1, "cannot read");
    const char *b2[] = {"solve", TEXT_FILE, NULL};
    expect_usage_error(b2, "cannot read");
    const char *b3[] = {"info", missing, NULL};
    expect_usage_error(b3, "cannot read");
    const char *b4[] = {"info", TEXT_FILE, "--json", NULL};
    expect_usage_error(b4, "cannot read");
    const char *b5[] = {"solve", FRIX_TEST_TMPDIR, NULL}; /* a directory */
    expect_usage_error(b5, "cannot read");

    /* An unwritable output: refused before the solve (test_outputs covers the cases). */
    const char *b6[] = {"solve", TINY, "--output", FRIX_TEST_TMPDIR "/no/such/dir/x.hdf5", NULL};
    cli_run w = run_cli(b6);
    ck_assert_int_eq(w.code, 2);
    ck_assert_msg(strstr(w.err, "cannot write"), "%s", w.err);
    run_free(&w);
}
END_TEST

/* ---- Tests on the shared FCLIB files ---------------------------------------------- */

START_TEST(test_info_shared) {
    const char *a1[] = {"info", CAPSULES, NULL};
    cli_run r = run_cli(a1);
    ck_assert_msg(r.code == 0, "exit %d: %s", r.code, r.err);
    ck_assert_msg(text_field(r.out, "contacts") && atoi(text_field(r.out, "contacts")) == 286, "%s",
                  r.out);
    ck_assert(strstr(r.out, "local") && strstr(r.out, "0.7 .. 0.7"));
    run_free(&r);

    const char *a2[] = {"info", "--json", CAPSULES, NULL};
    cli_run j = run_cli(a2);
    ck_assert_int_eq(j.code, 0);
    ck_assert_msg(json_valid(j.out), "invalid JSON: %s", j.out);
    ck_assert(strstr(j.out, "\"contacts\":286") && strstr(j.out, "\"kind\":\"local\""));
    run_free(&j);

    const char *a3[] = {"info", BOX_STACKS, NULL};
    cli_run g = run_cli(a3);
    ck_assert_msg(g.code == 0, "exit %d: %s", g.code, g.err);
    ck_assert_msg(text_field(g.out, "contacts") && atoi(text_field(g.out, "contacts")) == 31, "%s",
                  g.out);
    ck_assert(strstr(g.out, "global") && text_field(g.out, "M") && text_field(g.out, "H"));
    run_free(&g);
}
END_TEST

START_TEST(test_solve_shared) {
    const char *out = FRIX_TEST_TMPDIR "/cli_rover_solution.hdf5";
    unlink(out);
    const char *a1[] = {"solve", ROVER, "--tol", "1e-8", "--output", out, NULL};
    cli_run r = run_cli(a1);
    ck_assert_msg(r.code == 0, "exit %d: %s%s", r.code, r.out, r.err);
    ck_assert(strstr(r.out, "converged") && strstr(r.out, "iterations"));
    /* auto's trace, one line per step, the first its analysis. */
    const char *trace = text_field(r.out, "trace");
    while (trace && *trace == ' ') ++trace;
    ck_assert_msg(trace && strncmp(trace, "analysis: 5 contacts", 20) == 0, "%s", r.out);
    run_free(&r);
    double err = stored_solution_error(out, 5);
    ck_assert_msg(err <= 1e-8, "recomputed error %g", err);

    const char *a2[] = {"solve", ROVER, "--json", "--solver", "500", NULL};
    cli_run j = run_cli(a2);
    ck_assert_msg(j.code == 0, "exit %d: %s%s", j.code, j.out, j.err);
    ck_assert_msg(json_valid(j.out), "invalid JSON: %s", j.out);
    ck_assert_msg(strstr(j.out, "\"status\":\"converged\"") && strstr(j.out, "\"converged\":true") &&
                      strstr(j.out, "\"contacts\":5") && strstr(j.out, "\"trace\":[]"),
                  "%s", j.out);
    run_free(&j);
}
END_TEST

START_TEST(test_not_converged_shared) {
    /* The default solver (auto) starts with NSGS, which needs thousands of sweeps on this
     * one: a single sweep cannot converge, and the limit holds over all the islands. */
    const char *a1[] = {"solve", CAPSULES, "--max-iter", "1", NULL};
    cli_run r = run_cli(a1);
    ck_assert_msg(r.code == 1, "exit %d: %s%s", r.code, r.out, r.err);
    ck_assert(strstr(r.out, "maximum iterations"));
    run_free(&r);

    const char *a2[] = {"solve", CAPSULES, "--max-iter", "1", "--json", NULL};
    cli_run j = run_cli(a2);
    ck_assert_int_eq(j.code, 1);
    ck_assert_msg(json_valid(j.out), "invalid JSON: %s", j.out);
    ck_assert_msg(strstr(j.out, "\"status\":\"max_iter\"") && strstr(j.out, "\"converged\":false") &&
                      strstr(j.out, "\"iterations\":1"),
                  "%s", j.out);
    run_free(&j);
}
END_TEST

START_TEST(test_progress_shared) {
    /* NSGS takes far longer than 1.6 s on RockPile: --progress prints a line a second after
     * the first second, plain lines (stderr is a file here, not a terminal). */
    const char *a1[] = {"solve", ROCKPILE, "--solver", "nsgs", "--max-iter", "1000000000",
                        "--time-limit", "1.6", "--progress", NULL};
    cli_run r = run_cli(a1);
    ck_assert_msg(r.code == 1, "exit %d: %s%s", r.code, r.out, r.err);
    const double first = strncmp(r.err, "frix solve: ", 12) == 0 ? strtod(r.err + 12, NULL) : -1.0;
    ck_assert_msg(first >= 1.0 && strstr(r.err, " iterations, error ") &&
                      r.err[strlen(r.err) - 1] == '\n' && strchr(r.err, '\033') == NULL,
                  "progress lines: '%s'", r.err);
    ck_assert(strstr(r.out, "time limit reached"));
    run_free(&r);

    /* Without it, and stderr not a terminal: no progress line. */
    const char *a2[] = {"solve", ROCKPILE, "--solver", "nsgs", "--max-iter", "1000000000",
                        "--time-limit", "1.2", NULL};
    cli_run q = run_cli(a2);
    ck_assert_msg(q.code == 1 && q.err[0] == '\0', "exit %d, stderr '%s'", q.code, q.err);
    run_free(&q);

    const char *a3[] = {"solve", ROCKPILE, "--quiet", "--progress", NULL};
    expect_usage_error(a3, "exclude each other");
}
END_TEST

/* Whether the library solves this global problem with the default solver, asked directly:
 * FRIX_ERR_UNSUPPORTED means not in this build (the rest of the test then does not apply). */
static int global_solve_supported(const char *path) {
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_fclib_read(path, &p), FRIX_OK);
    size_t m = (size_t)frix_problem_contact_dofs(p), n = (size_t)frix_problem_dofs(p);
    double *r = calloc(m + 1, sizeof *r), *u = calloc(m + 1, sizeof *u), *v = calloc(n + 1, sizeof *v);
    frix_error err = frix_solve(p, NULL, r, u, v, NULL);
    ck_assert_msg(err == FRIX_OK || err == FRIX_ERR_UNSUPPORTED, "%s", frix_last_error_message());
    free(r);
    free(u);
    free(v);
    frix_problem_free(p);
    return err == FRIX_OK;
}

START_TEST(test_solve_global_shared) {
    /* A global problem: the written solution carries v, and the error is recomputed from it. */
    const char *out = FRIX_TEST_TMPDIR "/cli_boxstacks_solution.hdf5";
    unlink(out);
    if (!global_solve_supported(BOX_STACKS)) {
        /* Then the CLI must say so, as a failure of the solve, not crash or print junk. */
        const char *a0[] = {"solve", BOX_STACKS, NULL};
        expect_usage_error(a0, "cannot solve");
        printf("test_cli: this build does not solve global problems yet: CLI global solve "
               "checked for its error message only\n");
        return;
    }
    const char *a1[] = {"solve", BOX_STACKS, "--output", out, "--json", NULL};
    cli_run r = run_cli(a1);
    ck_assert_msg(r.code == 0, "exit %d: %s%s", r.code, r.out, r.err);
    ck_assert_msg(json_valid(r.out), "invalid JSON: %s", r.out);
    ck_assert_msg(strstr(r.out, "\"kind\":\"global\"") && strstr(r.out, "\"equilibrium\":") &&
                      strstr(r.out, "\"trace\":[\"analysis: 31 contacts") && strstr(r.out, "\"nsgs: converged"),
                  "%s", r.out);
    /* The setup's time and, of it, W's, both given. */
    ck_assert_msg(strstr(r.out, "\"setup_time\":") && strstr(r.out, "\"reduction_time\":"), "%s", r.out);
    run_free(&r);
    ck_assert_double_le(stored_solution_error(out, 31), 1e-8);
    /* The text says what the setup was: M and q, then W, then the solver. */
    const char *a2[] = {"solve", BOX_STACKS, NULL};
    r = run_cli(a2);
    ck_assert_msg(r.code == 0 && strstr(r.out, "then the solver") &&
                      strstr(r.out, "M (factorised, or analysed only) and q") && strstr(r.out, "W = H^T M^-1 H"),
                  "%s%s", r.out, r.err);
    run_free(&r);
}
END_TEST

/* Options whose values are choices take their names in --set (the numbers still work), `frix
 * solvers NAME` lists the names, and range messages state the value given and the real
 * bounds (integers in full for int keys; 1e-310 is a number, 1e400 beyond the doubles). */
START_TEST(test_choice_names_and_range_messages) {
    make_tiny_problem();
    const char *a1[] = {"solve", TINY, "--solver", "nsgs", "--set", "shuffle=once", "--set",
                        "local_solver=newton_ac", "--set", "error_measure=siconos", "--json", NULL};
    cli_run r = run_cli(a1);
    ck_assert_msg(r.code == 0 && strstr(r.out, "\"status\":\"converged\""), "exit %d: %s%s", r.code,
                  r.out, r.err);
    run_free(&r);
    const char *a2[] = {"solve", TINY, "--solver", "nsgs", "--set", "shuffle=2", NULL};
    r = run_cli(a2);
    ck_assert_msg(r.code == 0, "exit %d: %s%s", r.code, r.out, r.err);
    run_free(&r);
    const char *a3[] = {"solve", TINY, "--solver", "nsgs", "--set", "shuffle=sometimes", NULL};
    expect_usage_error(a3, "none, once, each_sweep, got 'sometimes'");
    const char *a4[] = {"solve", TINY, "--solver", "prox", "--set", "inner_solver=nsn-fb", NULL};
    r = run_cli(a4);
    ck_assert_msg(r.code == 0 || r.code == 1, "exit %d: %s%s", r.code, r.out, r.err);
    run_free(&r);

    const char *s1[] = {"solvers", "nsgs", NULL};
    r = run_cli(s1);
    ck_assert_msg(r.code == 0 && strstr(r.out, "none (0), once (1), each_sweep (2)") &&
                      strstr(r.out, "siconos (0), q_relative (1), scaled (2)") &&
                      strstr(r.out, "closed_form (562)"),
                  "%s", r.out);
    run_free(&r);
    const char *s2[] = {"solvers", "nsn-ac", "--json", NULL};
    r = run_cli(s2);
    ck_assert_msg(r.code == 0 && json_valid(r.out) &&
                      strstr(r.out, "\"default_name\":\"goldstein_price\",\"choices\":[{\"name\":\"none\",\"value\":0}"),
                  "%s", r.out);
    run_free(&r);

    const char *m1[] = {"solve", TINY, "--max-iter", "1000000001", NULL};
    expect_usage_error(m1, "max_iter = 1000000001 is outside [1, 1000000000]");
    const char *m2[] = {"solve", TINY, "--max-iter", "99999999999999999999", NULL};
    expect_usage_error(m2, "--max-iter 99999999999999999999 is outside [1, 1000000000]");
    const char *m3[] = {"solve", TINY, "--tol", "1e400", NULL};
    expect_usage_error(m3, "--tol 1e400 is outside [0, 1]");
    const char *m4[] = {"solve", TINY, "--solver", "admm", "--set", "rho=1e-310", NULL};
    expect_usage_error(m4, "rho = 1e-310 is outside [1e-300, 1e+300]");
    /* 1e-310 is a finite tolerance inside [0, 1]: taken as it is. */
    const char *m5[] = {"solve", TINY, "--solver", "nsgs", "--tol", "1e-310", "--max-iter", "3", NULL};
    r = run_cli(m5);
    ck_assert_msg((r.code == 0 || r.code == 1) && strstr(r.out, "tolerance 1.0e-310"), "exit %d: %s%s",
                  r.code, r.out, r.err);
    run_free(&r);
}
END_TEST

/* The progress line states the tolerance the solve must reach. */
START_TEST(test_progress_shows_the_target_shared) {
    const char *a1[] = {"solve", ROCKPILE, "--solver", "nsgs", "--tol", "1e-9", "--max-iter",
                        "1000000000", "--time-limit", "1.3", "--progress", NULL};
    cli_run r = run_cli(a1);
    ck_assert_msg(r.code == 1 && strstr(r.err, "frix solve: ") && strstr(r.err, " (target 1e-09)\n"),
                  "exit %d, progress lines: '%s'", r.code, r.err);
    run_free(&r);
}
END_TEST

static void add_issue49_tests(Suite *s); /* the issue 49 block, at the end */

static Suite *cli_suite(void) {
    Suite *s = suite_create("cli");
    TCase *basic = tcase_create("basic");
    tcase_add_test(basic, test_help_and_version);
    tcase_add_test(basic, test_solvers);
    tcase_add_test(basic, test_tiny_problem);
    tcase_add_test(basic, test_usage_errors);
    tcase_add_test(basic, test_solve_from_a_guess);
    tcase_add_test(basic, test_choice_names_and_range_messages);
    suite_add_tcase(s, basic);
    add_issue49_tests(s);

    struct stat st;
    if (stat(SHARED_FCLIB, &st) == 0 && S_ISDIR(st.st_mode)) {
        TCase *shared = tcase_create("shared");
        tcase_add_test(shared, test_info_shared);
        tcase_add_test(shared, test_solve_shared);
        tcase_add_test(shared, test_not_converged_shared);
        tcase_add_test(shared, test_progress_shared);
        tcase_add_test(shared, test_solve_global_shared);
        tcase_add_test(shared, test_progress_shows_the_target_shared);
        suite_add_tcase(s, shared);
    } else {
        printf("test_cli: %s not found: skipping the shared-data tests\n", SHARED_FCLIB);
    }
    return s;
}

int main(void) {
    /* A tiny problem left by an earlier build may predate a format change: start afresh. */
    unlink(TINY);
    return frix_run_suite(cli_suite());
}

/* ==== Issue 49: the time limit covers the read; out-of-memory and memory-limit messages ====
 * (a block of its own: other tests are appended above it) */

#include <sys/resource.h>
#include <time.h>

#define SLOW_DAT FRIX_TEST_TMPDIR "/cli_slow_read.dat"

static double slow_read_now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* Writes SLOW_DAT and returns how long `frix info` takes to read it here (the machine's speed
 * decides: the file grows until the read takes at least 0.25 s, or nc 1500). */
static double make_slow_read_dat(void) {
    double seconds = 0;
    for (int nc = 1000; nc <= 1500; nc += 500) {
        frix_test_write_slow_dat(SLOW_DAT, nc);
        const char *info[] = {"info", SLOW_DAT, NULL};
        const double t0 = slow_read_now();
        cli_run r = run_cli(info);
        seconds = slow_read_now() - t0;
        ck_assert_msg(r.code == 0, "info: exit %d: %s", r.code, r.err);
        run_free(&r);
        if (seconds >= 0.25) break;
    }
    return seconds;
}

START_TEST(test_time_limit_covers_read) {
    const double read = make_slow_read_dat();
    double limit = read / 5;
    if (limit > 0.05) limit = 0.05;
    char limit_text[32];
    snprintf(limit_text, sizeof limit_text, "%g", limit);
    const char *args[] = {"solve", SLOW_DAT, "--time-limit", limit_text, NULL};
    const double t0 = slow_read_now();
    cli_run r = run_cli(args);
    const double wall = slow_read_now() - t0;
    /* Ended like a solve stopped by its time limit (exit 1), with one line saying why. */
    ck_assert_msg(r.code == 1, "exit %d: %s%s", r.code, r.out, r.err);
    char expected[512];
    snprintf(expected, sizeof expected, "frix: reading %s took longer than the time limit of %s s", SLOW_DAT,
             limit_text);
    ck_assert_msg(strncmp(r.err, expected, strlen(expected)) == 0, "stderr: %s", r.err);
    ck_assert_msg(strchr(r.err, '\n') == r.err + strlen(r.err) - 1, "stderr is not one line: %s", r.err);
    ck_assert_str_eq(r.out, "");
    ck_assert_msg(wall < read, "stopped after %g s, the read alone takes %g s", wall, read);
    run_free(&r);

    /* Under a limit it respects, the file read in a child solves as the one read in place. */
    make_tiny_problem();
    const char *plain[] = {"solve", TINY, "--json", NULL};
    const char *limited[] = {"solve", TINY, "--json", "--time-limit", "60", NULL};
    cli_run p = run_cli(plain), l = run_cli(limited);
    ck_assert_msg(p.code == 0 && l.code == 0, "exit %d, %d: %s %s", p.code, l.code, p.err, l.err);
    ck_assert_str_eq(l.err, "");
    const char *keys[] = {"\"iterations\":", "\"error\":", "\"contacts\":", "\"status\":"};
    for (int k = 0; k < 4; ++k) {
        const char *a = strstr(p.out, keys[k]), *b = strstr(l.out, keys[k]);
        ck_assert(a && b);
        size_t n = strcspn(a, ",}");
        ck_assert_msg(n == strcspn(b, ",}") && strncmp(a, b, n) == 0, "%s: %s vs %s", keys[k], a, b);
    }
    run_free(&p);
    run_free(&l);

    /* The reader's refusal comes back from the child as it is: exit 2, "cannot read". */
    make_text_file();
    const char *bad[] = {"solve", TEXT_FILE, "--time-limit", "60", NULL};
    expect_usage_error(bad, "cannot read " TEXT_FILE ": ");
}
END_TEST

#if !defined(__SANITIZE_ADDRESS__) /* (AddressSanitizer's address space admits no limit) */
/* Runs `frix ARGS` with its address space limited to `bytes`, stderr into *err. Returns the
 * exit code, or 128 + signal. */
static int run_with_address_limit(const char *const *args, double bytes, char **err) {
    cli_run r = run_program_within(FRIX_CLI, args, bytes);
    free(r.out);
    *err = r.err;
    return r.code;
}
#endif

START_TEST(test_out_of_memory_message) {
#if defined(__SANITIZE_ADDRESS__)
    return; /* AddressSanitizer reserves terabytes of address space: no limit can be set */
#else
    frix_test_write_slow_dat(SLOW_DAT, 1000); /* its dense W takes 72 MB while it is read */
    const char *args[] = {"solve", SLOW_DAT, NULL};
    const char *limited[] = {"solve", SLOW_DAT, "--time-limit", "60", NULL};
    /* The smallest limit, in 32 MB steps, under which frix starts at all: too small for the
     * file, whatever the libraries take on this machine. */
    int tested = 0;
    for (double mb = 64; mb <= 2048 && !tested; mb += 32) {
        char *err = NULL;
        const int code = run_with_address_limit(args, mb * 1048576.0, &err);
        if (code == 127 || strstr(err, "error while loading shared libraries")) {
            free(err);
            continue;
        }
        ck_assert_msg(code == 2, "under %g MB: exit %d: %s", mb, code, err);
        /* What ran out, the limit, and what to do. */
        ck_assert_msg(strstr(err, "out of memory") && strstr(err, "limited to") && strstr(err, "ulimit -v") &&
                          strstr(err, "smaller problem"),
                      "under %g MB: %s", mb, err);
        free(err);
        /* The same from the reading child of a time-limited solve. */
        ck_assert_int_eq(run_with_address_limit(limited, mb * 1048576.0, &err), 2);
        ck_assert_msg(strstr(err, "out of memory") && strstr(err, "ulimit -v"), "under %g MB: %s", mb, err);
        free(err);
        tested = 1;
    }
    ck_assert_msg(tested, "frix did not start under any limit up to 2 GB");
    unlink(SLOW_DAT);
#endif
}
END_TEST

START_TEST(test_memory_limit_message) {
    make_tiny_problem();
    /* ipm factorises: with 1 byte allowed it stops before the first factorisation. */
    const char *args[] = {"solve", TINY, "--solver", "ipm", "--set", "memory_limit=1", NULL};
    cli_run r = run_cli(args);
    ck_assert_msg(r.code == 1, "exit %d: %s%s", r.code, r.out, r.err);
    ck_assert_msg(strstr(r.out, "memory limit reached") != NULL, "%s", r.out);
    /* Which limit, what the error shown is, what to do. */
    ck_assert_msg(strstr(r.err, "memory limit of 1 B") && strstr(r.err, "is the start") &&
                      strstr(r.err, "--set memory_limit=BYTES") && strstr(r.err, "nsgs"),
                  "stderr: %s", r.err);
    run_free(&r);
}
END_TEST

static void add_issue49_tests(Suite *s) {
    TCase *tc = tcase_create("issue49");
    tcase_add_test(tc, test_time_limit_covers_read);
    tcase_add_test(tc, test_out_of_memory_message);
    tcase_add_test(tc, test_memory_limit_message);
    suite_add_tcase(s, tc);
}
/* ==== end of the issue 49 block ==== */
