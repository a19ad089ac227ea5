/* Degenerate shapes of a problem, end to end (SHAPE_COUNT of them): no contacts (local, with
 * W absent or 0 x 0; global with dofs and no contacts, with H n x 0 or absent; global with
 * neither), one contact, every contact separating, mu = 0 everywhere (local and global), a W
 * with no stored entries, a W given as triplets with duplicates. Each shape is built,
 * written as FCLIB, read back (by frix_fclib_read and frix_read_problem), solved by every
 * registered solver that takes its kind, written with its solution and read back again.
 *
 * The same source runs twice: linked to libfrix (the C API, plus the `frix` command line on
 * the files: solve --output, convert, info, bench), and as a plugin host that loads
 * libfrix.so.0 with dlopen and calls nothing but the plugin table (SHAPES_VIA_PLUGIN). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#ifdef SHAPES_VIA_PLUGIN
#include <dlfcn.h>
#include <frix/frix_plugin.h>
#else
#include <frix/frix.h>
#endif

#include "check_main.h"
#ifndef SHAPES_VIA_PLUGIN
#include "cli_runner.h"
#endif

/* The library's functions: called directly when linked, through the table as a plugin. */
#ifdef SHAPES_VIA_PLUGIN
static const frix_plugin_table *fx;
#define FX(name) fx->name
#else
#define FX(name) frix_##name
#endif

static void ok(frix_error e, const char *what, const char *shape) {
    ck_assert_msg(e == FRIX_OK, "%s: %s: %s", shape, what, FX(last_error_message)());
}

/* ---- The shapes. Each builds its problem (and the matrices it borrows) and knows what the
 * answer must be. */

typedef struct {
    const char *name;
    frix_problem *p;
    frix_matrix *A, *B; /* W, or M and H */
    double vec1[12], vec2[12], mu[4];
    /* Expected answer where it is unique and known exactly (has_r, has_v), or NULL. */
    int has_r, has_v;
    double r[12], v[4];
    int mu_zero; /* r_T must vanish */
} shape;

static frix_matrix *empty_matrix(int64_t rows, int64_t cols, const char *name) {
    frix_matrix *A = NULL;
    ok(FX(matrix_from_triplets)(rows, cols, 0, NULL, NULL, NULL, &A), "empty matrix", name);
    return A;
}

/* Two contacts' W: SPD, coupled between the contacts, column-major 6 x 6. */
static frix_matrix *coupled_w(const char *name) {
    double W[36] = {0};
    static const double d[6] = {4, 3, 3, 5, 3.5, 3.5};
    for (int i = 0; i < 6; ++i) W[i + 6 * i] = d[i];
    W[0 + 6 * 3] = W[3 + 6 * 0] = 1.0; /* normal-normal coupling */
    W[1 + 6 * 4] = W[4 + 6 * 1] = 0.5;
    W[0 + 6 * 1] = W[1 + 6 * 0] = 0.25;
    frix_matrix *A = NULL;
    ok(FX(matrix_from_dense)(6, 6, W, 6, &A), "dense W", name);
    return A;
}

enum {
    LOCAL_NO_CONTACT,
    LOCAL_NO_CONTACT_EMPTY_W,
    GLOBAL_DOFS_NO_CONTACT,
    GLOBAL_NOTHING,
    GLOBAL_NO_H,
    ONE_CONTACT,
    ALL_SEPARATING,
    MU_ZERO,
    W_NO_ENTRIES,
    W_TRIPLET_DUPLICATES,
    GLOBAL_ONE_CONTACT_MU_ZERO,
    SHAPE_COUNT
};

static void shape_make(int which, shape *s) {
    memset(s, 0, sizeof *s);
    switch (which) {
    case LOCAL_NO_CONTACT:
        s->name = "local_no_contact";
        ok(FX(problem_local)(NULL, NULL, NULL, 0, &s->p), "problem", s->name);
        break;
    case LOCAL_NO_CONTACT_EMPTY_W:
        s->name = "local_no_contact_empty_w";
        s->A = empty_matrix(0, 0, s->name);
        ok(FX(problem_local)(s->A, NULL, NULL, 0, &s->p), "problem", s->name);
        break;
    case GLOBAL_DOFS_NO_CONTACT: {
        /* M v = f with nothing else: v = M^-1 f. n = 2 is not a multiple of 3 (CSC storage). */
        s->name = "global_dofs_no_contact";
        const double M[4] = {2, 0, 0, 4};
        ok(FX(matrix_from_dense)(2, 2, M, 2, &s->A), "M", s->name);
        s->B = empty_matrix(2, 0, s->name);
        s->vec1[0] = 1, s->vec1[1] = -2;
        ok(FX(problem_global)(s->A, s->B, s->vec1, NULL, NULL, 0, &s->p), "problem", s->name);
        s->has_v = 1, s->v[0] = 0.5, s->v[1] = -0.5;
        break;
    }
    case GLOBAL_NOTHING:
        s->name = "global_nothing";
        s->A = empty_matrix(0, 0, s->name);
        s->B = empty_matrix(0, 0, s->name);
        ok(FX(problem_global)(s->A, s->B, NULL, NULL, NULL, 0, &s->p), "problem", s->name);
        break;
    case GLOBAL_NO_H: {
        /* No contacts and no H at all (allowed without contacts): written as an n x 0 H. */
        s->name = "global_no_h";
        const double M[9] = {2, 0, 0, 0, 4, 0, 0, 0, 1};
        ok(FX(matrix_from_dense)(3, 3, M, 3, &s->A), "M", s->name);
        s->vec1[0] = 2, s->vec1[1] = -4, s->vec1[2] = 3;
        ok(FX(problem_global)(s->A, NULL, s->vec1, NULL, NULL, 0, &s->p), "problem", s->name);
        s->has_v = 1, s->v[0] = 1, s->v[1] = -1, s->v[2] = 3;
        break;
    }
    case ONE_CONTACT: {
        /* Sticking: W diagonal, r = -W^-1 q lies inside the cone (|r_T| = 0.05 < 0.5 r_N). */
        s->name = "one_contact";
        const double W[9] = {2, 0, 0, 0, 4, 0, 0, 0, 4};
        ok(FX(matrix_from_dense)(3, 3, W, 3, &s->A), "W", s->name);
        s->vec1[0] = -2, s->vec1[1] = 0.2, s->vec1[2] = 0;
        s->mu[0] = 0.5;
        ok(FX(problem_local)(s->A, s->vec1, s->mu, 1, &s->p), "problem", s->name);
        s->has_r = 1, s->r[0] = 1, s->r[1] = -0.05, s->r[2] = 0;
        break;
    }
    case ALL_SEPARATING: {
        s->name = "all_separating";
        s->A = coupled_w(s->name);
        const double q[6] = {0.5, 1, -2, 0, 3, 0}; /* q_N >= 0, one of them exactly 0 */
        memcpy(s->vec1, q, sizeof q);
        s->mu[0] = 0.3, s->mu[1] = 0.8;
        ok(FX(problem_local)(s->A, s->vec1, s->mu, 2, &s->p), "problem", s->name);
        s->has_r = 1; /* r = 0 */
        break;
    }
    case MU_ZERO: {
        /* Frictionless: r_T = 0 whatever q_T, and r_N solves the LCP of W's normal rows. */
        s->name = "mu_zero";
        s->A = coupled_w(s->name);
        const double q[6] = {-1, 0.7, -0.2, -2, 0.1, 0.4};
        memcpy(s->vec1, q, sizeof q);
        ok(FX(problem_local)(s->A, s->vec1, s->mu, 2, &s->p), "problem", s->name);
        /* Both closed: [4 1; 1 5] r_N = (1, 2) gives r_N = (3/19, 7/19), both positive. */
        s->has_r = 1, s->r[0] = 3.0 / 19, s->r[3] = 7.0 / 19;
        s->mu_zero = 1;
        break;
    }
    case W_NO_ENTRIES: {
        /* W = 0 stored with no entries: u = q; q_N >= 0 so r = 0 answers it. */
        s->name = "w_no_entries";
        s->A = empty_matrix(6, 6, s->name);
        const double q[6] = {0, 1, 0, 2, -1, 1};
        memcpy(s->vec1, q, sizeof q);
        s->mu[0] = 0.4, s->mu[1] = 0.4;
        ok(FX(problem_local)(s->A, s->vec1, s->mu, 2, &s->p), "problem", s->name);
        break;
    }
    case W_TRIPLET_DUPLICATES: {
        /* diag(4, 3, 3, 5, 3.5, 3.5) given in pieces that add up, with one off-diagonal pair
         * given twice: the sum is W = coupled_w's normal-normal coupling. */
        s->name = "w_triplet_duplicates";
        static const int64_t rows[] = {0, 0, 1, 2, 3, 4, 5, 3, 0, 3, 0, 3};
        static const int64_t cols[] = {0, 0, 1, 2, 3, 4, 5, 3, 3, 0, 3, 0};
        static const double vals[] = {3, 1, 3, 3, 2, 3.5, 3.5, 3, 0.5, 0.5, 0.5, 0.5};
        ok(FX(matrix_from_triplets)(6, 6, 12, rows, cols, vals, &s->A), "W", s->name);
        const double q[6] = {-1, 0, 0, -2, 0, 0};
        memcpy(s->vec1, q, sizeof q);
        s->mu[0] = 0.3, s->mu[1] = 0.3;
        ok(FX(problem_local)(s->A, s->vec1, s->mu, 2, &s->p), "problem", s->name);
        /* q_T = 0 and W's tangential part decoupled: r_T = 0, [4 1; 1 5] r_N = (1, 2). */
        s->has_r = 1, s->r[0] = 3.0 / 19, s->r[3] = 7.0 / 19;
        break;
    }
    case GLOBAL_ONE_CONTACT_MU_ZERO: {
        /* One particle (3 dofs, unit mass) pushed into a plane by f: v_N = 0 after the step,
         * the tangential velocity kept (mu = 0), r_N = -f_N. */
        s->name = "global_one_contact_mu_zero";
        const double M[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
        ok(FX(matrix_from_dense)(3, 3, M, 3, &s->A), "M", s->name);
        ok(FX(matrix_from_dense)(3, 3, M, 3, &s->B), "H", s->name);
        s->vec1[0] = -3, s->vec1[1] = 0.5, s->vec1[2] = -0.25; /* f */
        ok(FX(problem_global)(s->A, s->B, s->vec1, s->vec2, s->mu, 1, &s->p), "problem", s->name);
        s->has_r = 1, s->r[0] = 3;
        s->has_v = 1, s->v[0] = 0, s->v[1] = 0.5, s->v[2] = -0.25;
        s->mu_zero = 1;
        break;
    }
    default:
        ck_abort_msg("no shape %d", which);
    }
}

static void shape_free(shape *s) {
    FX(problem_free)(s->p);
    FX(matrix_free)(s->A);
    FX(matrix_free)(s->B);
}

/* ---- Checks. */

typedef struct {
    char path[512];
} file_name;

static file_name tmp_file(const char *shape_name, const char *suffix) {
    file_name f;
    snprintf(f.path, sizeof f.path, "%s/shapes%s_%s%s", FRIX_TEST_TMPDIR,
#ifdef SHAPES_VIA_PLUGIN
             "_plugin",
#else
             "",
#endif
             shape_name, suffix);
    return f;
}

/* The same problem: kind, sizes, data vectors exactly, and the same u (and error) at a
 * probe point, which compares the matrices through the solver's own products. */
static void assert_same_problem(const frix_problem *a, const frix_problem *b, const char *name) {
    ck_assert_int_eq(FX(problem_get_kind)(a), FX(problem_get_kind)(b));
    ck_assert_int_eq(FX(problem_contacts)(a), FX(problem_contacts)(b));
    ck_assert_int_eq(FX(problem_dofs)(a), FX(problem_dofs)(b));
    const int64_t nc = FX(problem_contacts)(a), m = 3 * nc, n = FX(problem_dofs)(a);
    const int global = FX(problem_get_kind)(a) == FRIX_PROBLEM_GLOBAL;
    for (int64_t k = 0; k < nc; ++k) ck_assert_double_eq(FX(problem_mu)(a)[k], FX(problem_mu)(b)[k]);
    for (int64_t k = 0; k < m; ++k) {
        const double *x = global ? FX(problem_w)(a) : FX(problem_q)(a);
        const double *y = global ? FX(problem_w)(b) : FX(problem_q)(b);
        ck_assert_msg(x[k] == y[k], "%s: q/w[%lld] %g read back as %g", name, (long long)k, x[k], y[k]);
    }
    for (int64_t k = 0; k < n; ++k) ck_assert_double_eq(FX(problem_f)(a)[k], FX(problem_f)(b)[k]);
    double r[12], v[4], ua[12], ub[12], ea, eb;
    for (int64_t k = 0; k < m; ++k) r[k] = 0.1 * (double)(k + 1);
    for (int64_t k = 0; k < n; ++k) v[k] = 0.3 - 0.2 * (double)k;
    frix_info *info = NULL;
    ok(FX(info_create)(&info), "info", name);
    ok(FX(problem_measure)(a, r, v, ua, info), "measure", name);
    ea = FX(info_error)(info);
    ok(FX(problem_measure)(b, r, v, ub, info), "measure read back", name);
    eb = FX(info_error)(info);
    FX(info_free)(info);
    for (int64_t k = 0; k < m; ++k) ck_assert_msg(ua[k] == ub[k], "%s: u[%lld] differs", name, (long long)k);
    ck_assert_msg(ea == eb || (isnan(ea) && isnan(eb)), "%s: error %g read back as %g", name, ea, eb);
}

static frix_problem *read_back(const char *path, const frix_problem *original, const char *name) {
    frix_problem *a = NULL, *b = NULL;
    ok(FX(fclib_read)(path, &a), "fclib_read", name);
    ok(FX(read_problem)(path, &b), "read_problem", name);
    assert_same_problem(original, a, name);
    assert_same_problem(original, b, name);
    FX(problem_free)(b);
    return a;
}

/* The answer a solver returned: converged, its error within the tolerance by our own
 * measure, and equal to the exact answer where the shape knows it. Each shape is scaled so
 * that its answer is of order 1; 1e-6 is far above what the 1e-8 relative error allows on
 * problems this well conditioned, and far below what a wrong answer is off by. */
static void check_answer(const shape *s, const frix_problem *p, int solver, const double *r,
                         const double *u, const double *v, const frix_info *info) {
    const char *who = FX(solver_name)(solver);
    ck_assert_msg(FX(info_status)(info) == FRIX_STATUS_CONVERGED, "%s: %s: %s, error %g", s->name,
                  who, FX(status_string)(FX(info_status)(info)), FX(info_error)(info));
    double err = -1;
    ok(FX(problem_error)(p, r, v, &err), "problem_error", s->name);
    ck_assert_msg(err <= 1e-8, "%s: %s: error %g by frix_problem_error", s->name, who, err);
    const int64_t nc = FX(problem_contacts)(p), n = FX(problem_dofs)(p);
    for (int64_t k = 0; k < 3 * nc; ++k) {
        ck_assert_msg(isfinite(r[k]) && isfinite(u[k]), "%s: %s: r or u not finite", s->name, who);
        if (s->has_r)
            ck_assert_msg(fabs(r[k] - s->r[k]) <= 1e-6, "%s: %s: r[%lld] = %.10g, exact %.10g",
                          s->name, who, (long long)k, r[k], s->r[k]);
        if (s->mu_zero && k % 3 != 0)
            ck_assert_msg(r[k] == 0.0 || fabs(r[k]) <= 1e-6 * fabs(r[k - k % 3]), "%s: %s: r_T = %g with mu = 0",
                          s->name, who, r[k]);
    }
    for (int64_t k = 0; k < n && s->has_v; ++k)
        ck_assert_msg(fabs(v[k] - s->v[k]) <= 1e-6, "%s: %s: v[%lld] = %.10g, exact %.10g", s->name,
                      who, (long long)k, v[k], s->v[k]);
}

/* Solves with every solver that takes the problem's kind; returns auto's answer in r, u, v. */
static void solve_with_every_solver(const shape *s, const frix_problem *p, double *r, double *u,
                                    double *v) {
    const int64_t m = FX(problem_contact_dofs)(p);
    frix_info *info = NULL;
    ok(FX(info_create)(&info), "info", s->name);
    int solved = 0, global_only = 0, rolling_only = 0;
    for (int64_t k = 0; k < FX(solver_count)(); ++k) {
        const int id = FX(solver_id_at)(k);
        frix_options *o = NULL;
        ok(FX(options_create)(id, &o), "options", s->name);
        for (int64_t i = 0; i < m; ++i) r[i] = 0, u[i] = NAN;
        /* Without contacts r and u have no entries: NULL is what a caller may pass. */
        const frix_error e = FX(solve)(p, o, m ? r : NULL, m ? u : NULL, v, info);
        FX(options_free)(o);
        if (e == FRIX_ERR_UNSUPPORTED && strstr(FX(last_error_message)(), "rolling-friction problems only")) {
            ++rolling_only; /* a solver of rolling-friction problems only (test_rolling) */
            continue;
        }
        if (e == FRIX_ERR_UNSUPPORTED && FX(problem_get_kind)(p) == FRIX_PROBLEM_LOCAL) {
            /* A solver of global problems only; it says so and does nothing else. */
            ck_assert_msg(strstr(FX(last_error_message)(), "global problems only") != NULL, "%s: %s: %s",
                          s->name, FX(solver_name)(id), FX(last_error_message)());
            ++global_only;
            continue;
        }
        ck_assert_msg(e == FRIX_OK, "%s: %s refused: %s", s->name, FX(solver_name)(id),
                      FX(last_error_message)());
        check_answer(s, p, id, r, u, v, info);
        ++solved;
    }
    /* Every solver solved the problem, or said it solves global (or rolling) problems only. */
    ck_assert_int_eq(solved + global_only + rolling_only, FX(solver_count)());
    /* Leave the default solver's answer for the caller to write. */
    for (int64_t i = 0; i < m; ++i) r[i] = 0;
    ok(FX(solve)(p, NULL, r, u, v, info), "solve (default)", s->name);
    check_answer(s, p, FRIX_SOLVER_AUTO, r, u, v, info);
    FX(info_free)(info);
}

static void round_trip(int which) {
    shape s;
    shape_make(which, &s);
    const file_name file = tmp_file(s.name, ".hdf5");
    const char *path = file.path;
    ok(FX(fclib_write)(path, s.p, NULL, NULL, NULL, 0, NULL, NULL, NULL), "fclib_write", s.name);
    frix_problem *back = read_back(path, s.p, s.name);

    /* NaN-filled so that an output left unwritten shows. */
    double r[12], u[12], v[4];
    for (int k = 0; k < 4; ++k) v[k] = NAN;
    solve_with_every_solver(&s, back, r, u, v);

    const file_name sol_file = tmp_file(s.name, "_solution.hdf5");
    const char *sol_path = sol_file.path;
    /* Without contacts, a global solution is v alone: r and u (no entries) may be NULL. All
     * NULL would mean no solution at all, so the other shapes pass their arrays. */
    const int v_alone = FX(problem_contact_dofs)(back) == 0 && FX(problem_dofs)(back) > 0;
    ok(FX(fclib_write)(sol_path, back, v_alone ? NULL : r, v_alone ? NULL : u, v, 1, v_alone ? NULL : r,
                       v_alone ? NULL : u, v),
       "fclib_write with a solution", s.name);
    frix_problem *again = read_back(sol_path, s.p, s.name);
    const int64_t m = FX(problem_contact_dofs)(again), n = FX(problem_dofs)(again);
    double r2[12], u2[12], v2[4];
    for (int k = 0; k < 12; ++k) r2[k] = u2[k] = -7;
    for (int k = 0; k < 4; ++k) v2[k] = -7;
    ok(FX(fclib_read_solution)(sol_path, again, r2, u2, v2), "fclib_read_solution", s.name);
    ck_assert(memcmp(r, r2, (size_t)m * sizeof *r) == 0 && memcmp(u, u2, (size_t)m * sizeof *u) == 0);
    ck_assert(memcmp(v, v2, (size_t)n * sizeof *v) == 0);
    int64_t guesses = -1;
    ok(FX(fclib_guess_count)(sol_path, &guesses), "fclib_guess_count", s.name);
    ck_assert_int_eq(guesses, 1);
    for (int k = 0; k < 12; ++k) r2[k] = -7;
    ok(FX(fclib_read_guess)(sol_path, again, 0, r2, NULL, NULL), "fclib_read_guess", s.name);
    ck_assert(memcmp(r, r2, (size_t)m * sizeof *r) == 0);
    /* Untouched beyond the problem's sizes. */
    ck_assert_double_eq(r2[m], -7);
    ck_assert_double_eq(v2[n], -7);

    /* The solution read back solves the problem read back, with the same error. */
    double err = -1;
    ok(FX(problem_error)(again, r2, v2, &err), "problem_error", s.name);
    ck_assert_double_le(err, 1e-8);

    FX(problem_free)(again);
    FX(problem_free)(back);
    shape_free(&s);
}

START_TEST(test_round_trip) { round_trip(_i); }
END_TEST

#ifndef SHAPES_VIA_PLUGIN
/* ---- The command line on the same files. */

static void expect_cli(const char *const *args, int code, const char *needle, const char *name) {
    cli_run r = run_cli(args);
    ck_assert_msg(r.code == code, "%s: frix %s %s: exit %d, expected %d\nstdout: %s\nstderr: %s", name, args[0],
                  args[1], r.code, code, r.out, r.err);
    if (needle) ck_assert_msg(strstr(r.out, needle) != NULL, "%s: frix %s: no '%s' in\n%s", name, args[0], needle, r.out);
    run_free(&r);
}

START_TEST(test_command_line) {
    shape s;
    shape_make(_i, &s);
    const file_name file = tmp_file(s.name, "_cli.hdf5");
    const char *path = file.path;
    ok(FX(fclib_write)(path, s.p, NULL, NULL, NULL, 0, NULL, NULL, NULL), "fclib_write", s.name);
    char contacts[64];
    snprintf(contacts, sizeof contacts, "\"contacts\":%lld", (long long)FX(problem_contacts)(s.p));

    const char *info_args[] = {"info", path, "--json", NULL};
    expect_cli(info_args, 0, contacts, s.name);

    const file_name out_file = tmp_file(s.name, "_cli_solution.hdf5");
    const char *out = out_file.path;
    const char *solve_args[] = {"solve", path, "--output", out, "--json", NULL};
    expect_cli(solve_args, 0, "\"status\":\"converged\"", s.name);
    frix_problem *back = read_back(out, s.p, s.name);
    double r[12], u[12], v[4], err = -1;
    ok(FX(fclib_read_solution)(out, back, r, u, v), "read the CLI's solution", s.name);
    ok(FX(problem_error)(back, r, v, &err), "problem_error", s.name);
    ck_assert_msg(err <= 1e-8, "%s: the CLI's solution has error %g", s.name, err);
    FX(problem_free)(back);

    const file_name converted_file = tmp_file(s.name, "_cli_converted.hdf5");
    const char *converted = converted_file.path;
    const char *convert_args[] = {"convert", path, converted, NULL};
    expect_cli(convert_args, 0, "written as FCLIB", s.name);
    back = read_back(converted, s.p, s.name);
    FX(problem_free)(back);

    const file_name dir_file = tmp_file(s.name, "_bench");
    const char *dir = dir_file.path;
    const char *bench_args[] = {"bench", path, "--solvers", "auto,nsgs,nsn-ac,ipm", "--out", dir, NULL};
    expect_cli(bench_args, 0, NULL, s.name);
    char csv_path[700];
    snprintf(csv_path, sizeof csv_path, "%s/runs.csv", dir);
    char *csv = slurp(csv_path, NULL);
    /* One header line and one row per solver, each converged. */
    int rows = 0, converged = 0;
    for (char *line = strchr(csv, '\n'); line && line[1]; line = strchr(line + 1, '\n')) {
        ++rows;
        const char *end = strchr(line + 1, '\n');
        const char *hit = strstr(line + 1, ",converged,");
        converged += hit != NULL && (end == NULL || hit < end);
    }
    ck_assert_msg(rows == 4 && converged == 4, "%s: bench runs.csv has %d rows, %d converged:\n%s", s.name, rows,
                  converged, csv);
    free(csv);
    shape_free(&s);
}
END_TEST
#endif

int main(void) {
#ifdef SHAPES_VIA_PLUGIN
    /* As a host would: by name through the loader's path, never linked to libfrix. The
     * library stays loaded until exit (LeakSanitizer cannot scan an unmapped library). */
    void *lib = dlopen("libfrix.so.0", RTLD_NOW | RTLD_LOCAL);
    if (!lib) {
        fprintf(stderr, "cannot load libfrix.so.0: %s\n", dlerror());
        return EXIT_FAILURE;
    }
    union {
        void *object;
        frix_plugin_api_fn function;
    } entry;
    entry.object = dlsym(lib, "frix_plugin_api");
    fx = entry.object ? entry.function(FRIX_PLUGIN_ABI_VERSION) : NULL;
    if (!fx) {
        fprintf(stderr, "libfrix.so.0 serves no plugin table of version %d\n", FRIX_PLUGIN_ABI_VERSION);
        return EXIT_FAILURE;
    }
#endif
    Suite *suite = suite_create("shapes");
    TCase *tc = tcase_create("round trip");
    tcase_add_loop_test(tc, test_round_trip, 0, SHAPE_COUNT);
    suite_add_tcase(suite, tc);
#ifndef SHAPES_VIA_PLUGIN
    TCase *cli = tcase_create("command line");
    tcase_add_loop_test(cli, test_command_line, 0, SHAPE_COUNT);
    suite_add_tcase(suite, cli);
#endif
    return frix_run_suite(suite);
}
