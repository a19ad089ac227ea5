/* FCLIB files, writing: problems written and read back bit-identical (local, global, empty,
 * from files whose nzmax is a capacity or whose triplets repeat entries, the last also through
 * the command line), solutions and guesses, the info group's texts, and the compression level
 * chosen (frix_fclib_write_compressed). */
#define _POSIX_C_SOURCE 200809L /* the CLI runner's fork and dup2 under strict C99 */
#include <frix/frix.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <hdf5.h>
#include <sys/stat.h>
#include <unistd.h>

#include "check_main.h"
#include "cli_runner.h"
#include "fclib_fixtures.h"

/* nzmax is a capacity: a file declaring more than its arrays hold reads by the arrays'
 * real sizes (CSR, CSC and triplets), and so does a file with no contacts and nzmax > 0. */
START_TEST(test_nzmax_is_a_capacity) {
    const char *path = tmp_path("nzmax_capacity.hdf5");
    crafted c = crafted_base();
    write_crafted(path, &c);
    frix_problem *base = read_ok(path);

    c.nzmax = 1000; /* CSR with 7 entries */
    write_crafted(path, &c);
    frix_problem *p = read_ok(path);
    assert_same_problem(base, p);
    frix_problem_free(p);

    c = crafted_base();
    c.nz = -1;
    c.nzmax = 50;
    c.p = csc_p, c.i = csc_i, c.x = csc_x;
    write_crafted(path, &c);
    p = read_ok(path);
    assert_same_problem(base, p);
    frix_problem_free(p);

    static const long long t_i[] = {0, 1, 2, 3, 4, 5, 0};
    static const long long t_p[] = {0, 1, 2, 3, 4, 5, 3};
    c = crafted_base();
    c.nz = 7;
    c.nzmax = 64;
    static const double t_x[] = {2, 3, 4, 5, 6, 7, 0.5};
    c.i = t_i, c.p = t_p, c.x = t_x;
    write_crafted(path, &c);
    p = read_ok(path);
    assert_same_problem(base, p);
    frix_problem_free(p);
    frix_problem_free(base);

    /* No contacts: empty arrays, a p of one zero, nzmax 8. */
    static const long long zero[] = {0};
    c = crafted_base();
    c.m = c.n = 0;
    c.nzmax = 8;
    c.p = zero, c.np = 1;
    c.ni = c.nx = c.nq = c.nmu = 0;
    write_crafted(path, &c);
    p = read_ok(path);
    ck_assert_int_eq(frix_problem_contacts(p), 0);
    double r[1], u[1];
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_solve(p, NULL, r, u, NULL, info), FRIX_OK);
    ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_CONVERGED);
    frix_info_free(info);
    frix_problem_free(p);
}
END_TEST

/* A W stored as triplets with duplicates (and nzmax above nz) goes all the way: read,
 * solved, written with its solution (as CSC), read back with the same matrix and answer. */
START_TEST(test_triplets_with_duplicates_round_trip) {
    const char *path = tmp_path("triplets_dup.hdf5");
    const char *out = tmp_path("triplets_dup_solved.hdf5");
    crafted c = crafted_base();
    c.nz = 9;
    c.nzmax = 12;
    static const long long rows[] = {0, 1, 2, 3, 4, 5, 0, 0, 3};
    static const long long cols[] = {0, 1, 2, 3, 4, 5, 0, 3, 0};
    static const double vals[] = {1.5, 3, 4, 5, 6, 7, 0.5, 0.25, 0.25};
    c.i = rows, c.p = cols, c.x = vals;
    c.ni = c.np = c.nx = 9;
    write_crafted(path, &c);
    frix_problem *p = read_ok(path);
    double r[6] = {0}, u[6];
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_solve(p, NULL, r, u, NULL, info), FRIX_OK);
    ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_CONVERGED);
    frix_info_free(info);
    ck_assert_int_eq(frix_fclib_write(out, p, r, u, NULL, 0, NULL, NULL, NULL), FRIX_OK);
    frix_problem *back = read_ok(out);
    assert_same_problem(p, back);
    double r2[6], u2[6];
    ck_assert_int_eq(frix_fclib_read_solution(out, back, r2, u2, NULL), FRIX_OK);
    ck_assert(memcmp(r, r2, sizeof r) == 0 && memcmp(u, u2, sizeof u) == 0);
    /* W(0,0) = 1.5 + 0.5 and the symmetric pair 0.25 each way. */
    csc W = to_csc(frix_problem_W(back));
    ck_assert_double_eq(csc_entry(&W, 0, 0), 2.0);
    ck_assert_double_eq(csc_entry(&W, 0, 3), 0.25);
    ck_assert_double_eq(csc_entry(&W, 3, 0), 0.25);
    csc_free(&W);
    frix_problem_free(back);

    /* The command line on the triplet file: info, solve --output, convert, bench. */
    const char *cli_out = tmp_path("triplets_dup_cli.hdf5");
    const char *info_args[] = {"info", path, NULL};
    cli_run run = run_cli(info_args);
    ck_assert_msg(run.code == 0 && strstr(run.out, "local"), "info: %d %s%s", run.code, run.out, run.err);
    run_free(&run);
    const char *solve_args[] = {"solve", path, "--output", cli_out, NULL};
    run = run_cli(solve_args);
    ck_assert_msg(run.code == 0 && strstr(run.out, "converged"), "solve: %d %s%s", run.code, run.out, run.err);
    run_free(&run);
    back = read_ok(cli_out);
    assert_same_problem(p, back);
    double err = -1;
    ck_assert_int_eq(frix_fclib_read_solution(cli_out, back, r2, u2, NULL), FRIX_OK);
    ck_assert_int_eq(frix_problem_error(back, r2, NULL, &err), FRIX_OK);
    ck_assert_double_le(err, 1e-8);
    frix_problem_free(back);
    const char *convert_args[] = {"convert", path, cli_out, NULL};
    run = run_cli(convert_args);
    ck_assert_msg(run.code == 0, "convert: %d %s%s", run.code, run.out, run.err);
    run_free(&run);
    back = read_ok(cli_out);
    assert_same_problem(p, back);
    frix_problem_free(back);
    const char *bench_dir = tmp_path("triplets_dup_bench");
    const char *bench_args[] = {"bench", path, "--solvers", "auto,nsgs", "--out", bench_dir, NULL};
    run = run_cli(bench_args);
    ck_assert_msg(run.code == 0 && strstr(run.err, "2 runs"), "bench: %d %s%s", run.code, run.out, run.err);
    run_free(&run);
    frix_problem_free(p);
}
END_TEST

START_TEST(test_roundtrip_local) {
    REQUIRE_SHARED();
    const char *path = tmp_path("roundtrip_local.hdf5");
    frix_problem *a = read_ok(LOCAL_TEST); /* CSR in the file, CSC once rewritten */
    ck_assert_int_eq(frix_fclib_write(path, a, NULL, NULL, NULL, 0, NULL, NULL, NULL), FRIX_OK);
    frix_problem *b = read_ok(path);
    assert_same_problem(a, b);
    int64_t count = -1;
    ck_assert_int_eq(frix_fclib_guess_count(path, &count), FRIX_OK);
    ck_assert_int_eq(count, 0);
    frix_problem_free(b);
    frix_problem_free(a);
}
END_TEST

START_TEST(test_roundtrip_global) {
    REQUIRE_SHARED();
    const char *path = tmp_path("roundtrip_global.hdf5");
    frix_problem *a = read_ok(BOX_GLOBAL); /* triplets in the file */
    ck_assert_int_eq(frix_fclib_write(path, a, NULL, NULL, NULL, 0, NULL, NULL, NULL), FRIX_OK);
    frix_problem *b = read_ok(path);
    assert_same_problem(a, b);
    frix_problem_free(b);
    frix_problem_free(a);
}
END_TEST

/* Zero contacts writes and reads back. */
START_TEST(test_roundtrip_empty) {
    const char *path = tmp_path("empty.hdf5");
    frix_problem *a = NULL;
    ck_assert_int_eq(frix_problem_local(NULL, NULL, NULL, 0, &a), FRIX_OK);
    ck_assert_int_eq(frix_fclib_write(path, a, NULL, NULL, NULL, 0, NULL, NULL, NULL), FRIX_OK);
    frix_problem *b = read_ok(path);
    ck_assert_int_eq(frix_problem_contacts(b), 0);
    ck_assert_int_eq(frix_matrix_rows(frix_problem_W(b)), 0);
    frix_problem_free(b);
    frix_problem_free(a);
}
END_TEST

START_TEST(test_solution_and_guesses_local) {
    small_local s;
    small_local_make(&s, "small");
    const char *path = tmp_path("solution_local.hdf5");
    double r[6] = {1, 0.1, -0.2, 2, 0, 0}, u[6] = {0, 0.5, 0.25, 0, -1, 3};
    double gr[12], gu[12];
    for (int k = 0; k < 12; ++k) {
        gr[k] = 0.5 * k - 1;
        gu[k] = 1.0 / (k + 1);
    }
    double v_ignored[1] = {42};
    ck_assert_int_eq(frix_fclib_write(path, s.p, r, u, v_ignored, 2, gr, gu, NULL), FRIX_OK);

    frix_problem *p = read_ok(path);
    assert_same_problem(s.p, p);
    double rr[6], uu[6];
    ck_assert_int_eq(frix_fclib_read_solution(path, p, rr, uu, NULL), FRIX_OK);
    ck_assert(memcmp(rr, r, sizeof r) == 0);
    ck_assert(memcmp(uu, u, sizeof u) == 0);

    int64_t count = 0;
    ck_assert_int_eq(frix_fclib_guess_count(path, &count), FRIX_OK);
    ck_assert_int_eq(count, 2);
    for (int64_t g = 0; g < 2; ++g) {
        ck_assert_int_eq(frix_fclib_read_guess(path, p, g, rr, NULL, NULL), FRIX_OK);
        ck_assert(memcmp(rr, gr + 6 * g, sizeof rr) == 0);
        ck_assert_int_eq(frix_fclib_read_guess(path, p, g, NULL, uu, NULL), FRIX_OK);
        ck_assert(memcmp(uu, gu + 6 * g, sizeof uu) == 0);
    }
    /* Out of range guesses are refused and leave the caller's array alone. */
    memcpy(rr, r, sizeof r);
    ck_assert_int_eq(frix_fclib_read_guess(path, p, 2, rr, NULL, NULL), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_fclib_read_guess(path, p, -1, rr, NULL, NULL), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert(strlen(frix_last_error_message()) > 0);
    ck_assert(memcmp(rr, r, sizeof r) == 0);

    /* Without /solution: a format error naming it. */
    const char *bare = tmp_path("no_solution.hdf5");
    ck_assert_int_eq(frix_fclib_write(bare, s.p, NULL, NULL, NULL, 0, NULL, NULL, NULL), FRIX_OK);
    ck_assert_int_eq(frix_fclib_read_solution(bare, p, rr, uu, NULL), FRIX_ERR_FORMAT);
    ck_assert(strstr(frix_last_error_message(), "/solution") != NULL);

    /* Half a solution, or guesses without arrays, are argument errors. */
    ck_assert_int_eq(frix_fclib_write(bare, s.p, r, NULL, NULL, 0, NULL, NULL, NULL),
                     FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_fclib_write(bare, s.p, NULL, NULL, NULL, 1, gr, NULL, NULL),
                     FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_fclib_write(bare, s.p, NULL, NULL, NULL, -1, NULL, NULL, NULL),
                     FRIX_ERR_INVALID_ARGUMENT);
    r[1] = NAN;
    ck_assert_int_eq(frix_fclib_write(bare, s.p, r, u, NULL, 0, NULL, NULL, NULL),
                     FRIX_ERR_NOT_FINITE);
    frix_problem_free(p);
    small_local_free(&s);
}
END_TEST

START_TEST(test_solution_and_guesses_global) {
    REQUIRE_SHARED();
    frix_problem *g = read_ok(BOX_GLOBAL);
    const int64_t m = frix_problem_contact_dofs(g), n = frix_problem_dofs(g);
    double *r = malloc(sizeof(double) * (size_t)m), *u = malloc(sizeof(double) * (size_t)m);
    double *v = malloc(sizeof(double) * (size_t)n), *v2 = malloc(sizeof(double) * (size_t)n);
    double *r2 = malloc(sizeof(double) * (size_t)m);
    for (int64_t k = 0; k < m; ++k) {
        r[k] = sin((double)k);
        u[k] = cos((double)k);
    }
    for (int64_t k = 0; k < n; ++k) v[k] = 1.0 / (double)(k + 1);

    /* The shared file's own solution (r stored as an unwritten dataset) and guess. */
    ck_assert_int_eq(frix_fclib_read_solution(BOX_GLOBAL, g, r2, NULL, v2), FRIX_OK);
    for (int64_t k = 0; k < m; ++k) ck_assert_double_eq(r2[k], 0.0);
    int64_t count = 0;
    ck_assert_int_eq(frix_fclib_guess_count(BOX_GLOBAL, &count), FRIX_OK);
    ck_assert_int_eq(count, 1);
    ck_assert_int_eq(frix_fclib_read_guess(BOX_GLOBAL, g, 0, r2, NULL, v2), FRIX_OK);

    const char *path = tmp_path("solution_global.hdf5");
    ck_assert_int_eq(frix_fclib_write(path, g, r, u, v, 1, u, r, v), FRIX_OK);
    ck_assert_int_eq(frix_fclib_read_solution(path, g, r2, NULL, v2), FRIX_OK);
    ck_assert(memcmp(r2, r, sizeof(double) * (size_t)m) == 0);
    ck_assert(memcmp(v2, v, sizeof(double) * (size_t)n) == 0);
    ck_assert_int_eq(frix_fclib_read_guess(path, g, 0, r2, NULL, NULL), FRIX_OK);
    ck_assert(memcmp(r2, u, sizeof(double) * (size_t)m) == 0);
    /* A global solution needs v. */
    ck_assert_int_eq(frix_fclib_write(path, g, r, u, NULL, 0, NULL, NULL, NULL),
                     FRIX_ERR_INVALID_ARGUMENT);

    /* The local problem of the guesses-holding test file: guess 1 is a non-zero warm start;
     * reading it against a problem of another size is a format error. */
    frix_problem *l = read_ok(LOCAL_TEST);
    double rl[144];
    ck_assert_int_eq(frix_fclib_read_guess(LOCAL_TEST, l, 0, rl, NULL, NULL), FRIX_OK);
    double norm = 0;
    for (int k = 0; k < 144; ++k) norm += fabs(rl[k]);
    ck_assert(norm > 0);
    ck_assert_int_eq(frix_fclib_read_guess(LOCAL_TEST, g, 0, r2, NULL, NULL), FRIX_ERR_FORMAT);
    ck_assert(strstr(frix_last_error_message(), "/guesses/1/r") != NULL);
    frix_problem_free(l);

    free(r);
    free(u);
    free(v);
    free(v2);
    free(r2);
    frix_problem_free(g);
}
END_TEST

/* Title, description (multi-line) and math info go to the info group and come back; a problem
 * without a description gets frix's line. */
START_TEST(test_info_texts_round_trip) {
    const char *path = tmp_path("info_texts.hdf5");
    small_local s;
    small_local_make(&s, "two contacts");
    ck_assert_int_eq(frix_fclib_write(path, s.p, NULL, NULL, NULL, 0, NULL, NULL, NULL), FRIX_OK);
    frix_problem *back = read_ok(path);
    ck_assert_str_eq(frix_problem_title(back), "two contacts");
    ck_assert_msg(strncmp(frix_problem_description(back), "written by frix ", 16) == 0, "%s",
                  frix_problem_description(back));
    ck_assert_str_eq(frix_problem_math_info(back), "");
    frix_problem_free(back);

    const char *description = "W couples the contacts.\n\tSecond line, after a tab.";
    ck_assert_int_eq(frix_problem_set_description(s.p, description), FRIX_OK);
    ck_assert_int_eq(frix_problem_set_math_info(s.p, "u = W r + q, mu = (0.3, 0.5)"), FRIX_OK);
    ck_assert_int_eq(frix_fclib_write_compressed(path, s.p, NULL, NULL, NULL, 0, NULL, NULL, NULL, 0),
                     FRIX_OK);
    back = read_ok(path);
    ck_assert_str_eq(frix_problem_title(back), "two contacts");
    ck_assert_str_eq(frix_problem_description(back), description);
    ck_assert_str_eq(frix_problem_math_info(back), "u = W r + q, mu = (0.3, 0.5)");
    assert_same_problem(s.p, back);
    frix_problem_free(back);
    small_local_free(&s);
}
END_TEST

/* The deflate level of a dataset (0: stored without the filter, -1: chunked without it). */
static int deflate_level_of(const char *path, const char *dataset) {
    hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
    ck_assert(f >= 0);
    hid_t d = H5Dopen2(f, dataset, H5P_DEFAULT);
    ck_assert(d >= 0);
    hid_t dcpl = H5Dget_create_plist(d);
    int level = 0;
    if (H5Pget_layout(dcpl) == H5D_CHUNKED) {
        unsigned flags = 0, cd[4] = {0};
        size_t ncd = 4;
        char name[32];
        unsigned config = 0;
        level = H5Pget_filter_by_id2(dcpl, H5Z_FILTER_DEFLATE, &flags, &ncd, cd, sizeof name, name,
                                     &config) >= 0 ? (int)cd[0] : -1;
    }
    H5Pclose(dcpl);
    H5Dclose(d);
    H5Fclose(f);
    return level;
}

/* The level asked for is the level stored, on the arrays of 1024 entries or more (W's values,
 * q); level 0 stores them contiguous; every level reads back the same problem; a level out of
 * 0..9 is refused before any file exists. */
START_TEST(test_compression_level_chosen) {
    enum { NC = 400 };
    static int64_t rows[NC], cols[NC];
    static double blocks[9 * NC], q[3 * NC], mu[NC];
    for (int64_t a = 0; a < NC; ++a) {
        rows[a] = cols[a] = a;
        for (int k = 0; k < 9; ++k) blocks[9 * a + k] = k % 4 == 0 ? 1.0 + 0.001 * (double)(a % 7) : 0.0;
        q[3 * a] = -1.0 + 0.01 * (double)(a % 10);
        q[3 * a + 1] = q[3 * a + 2] = 0.0;
        mu[a] = 0.3;
    }
    frix_matrix *W = NULL;
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_matrix_from_blocks(NC, NC, NC, rows, cols, blocks, &W), FRIX_OK);
    ck_assert_int_eq(frix_problem_local(W, q, mu, NC, &p), FRIX_OK);

    const int levels[] = {0, 1, 9};
    long sizes[3];
    for (int k = 0; k < 3; ++k) {
        const char *path = tmp_path("level.hdf5");
        ck_assert_int_eq(frix_fclib_write_compressed(path, p, NULL, NULL, NULL, 0, NULL, NULL, NULL,
                                                     levels[k]), FRIX_OK);
        ck_assert_int_eq(deflate_level_of(path, "/fclib_local/vectors/q"), levels[k]);
        ck_assert_int_eq(deflate_level_of(path, "/fclib_local/W/x"), levels[k]);
        ck_assert_int_eq(deflate_level_of(path, "/fclib_local/vectors/mu"), 0); /* 400 entries */
        struct stat st;
        ck_assert_int_eq(stat(path, &st), 0);
        sizes[k] = (long)st.st_size;
        frix_problem *back = read_ok(path);
        assert_same_problem(p, back);
        frix_problem_free(back);
    }
    ck_assert_msg(sizes[1] < sizes[0] && sizes[2] <= sizes[1], "sizes %ld %ld %ld", sizes[0],
                  sizes[1], sizes[2]);
    const char *path = tmp_path("default_level.hdf5");
    ck_assert_int_eq(frix_fclib_write(path, p, NULL, NULL, NULL, 0, NULL, NULL, NULL), FRIX_OK);
    ck_assert_int_eq(deflate_level_of(path, "/fclib_local/vectors/q"), 4);

    const char *refused = tmp_path("bad_level.hdf5");
    unlink(refused);
    const int bad[] = {-1, 10, 1 << 30};
    for (int k = 0; k < 3; ++k) {
        ck_assert_int_eq(frix_fclib_write_compressed(refused, p, NULL, NULL, NULL, 0, NULL, NULL, NULL,
                                                     bad[k]), FRIX_ERR_INVALID_ARGUMENT);
        ck_assert_ptr_nonnull(strstr(frix_last_error_message(), "compression level"));
        ck_assert_int_ne(access(refused, F_OK), 0);
    }
    frix_problem_free(p);
    frix_matrix_free(W);
}
END_TEST

int main(void) {
    Suite *s = suite_create("fclib");
    TCase *write = tcase_create("write");
    tcase_add_test(write, test_roundtrip_local);
    tcase_add_test(write, test_roundtrip_global);
    tcase_add_test(write, test_roundtrip_empty);
    tcase_add_test(write, test_nzmax_is_a_capacity);
    tcase_add_test(write, test_triplets_with_duplicates_round_trip);
    tcase_add_test(write, test_solution_and_guesses_local);
    tcase_add_test(write, test_solution_and_guesses_global);
    tcase_add_test(write, test_info_texts_round_trip);
    tcase_add_test(write, test_compression_level_chosen);
    suite_add_tcase(s, write);
    return frix_run_suite(s);
}
