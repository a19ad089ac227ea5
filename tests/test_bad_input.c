/* Bad input, beyond the cases of test_fclib_*, test_problem, test_matrix and test_options:
 * FCLIB files truncated at many lengths and corrupted at many places (local and global,
 * with solutions and guesses), global files with a dataset missing, wrong sizes or non-finite
 * values, NaN/Inf through every matrix constructor, enormous declared sizes (allocation must
 * fail cleanly), every option key of every solver pushed out of range, unknown solver ids,
 * NULL arguments across the API, and the same through the `frix` command line (exit 2, one
 * line on stderr, no existing file destroyed).
 * Each refusal is a specific frix_error with a message; nothing crashes, nothing leaks (the
 * suite runs under ASan/LSan and valgrind). The counts of inputs tried are printed. */
#define _POSIX_C_SOURCE 200809L
#include <frix/frix.h>

#include <hdf5.h>

#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "check_main.h"
#include "cli_runner.h"
#include "scenes.h"

/* An allocation of terabytes fails with std::bad_alloc, which frix turns into
 * FRIX_ERR_OUT_OF_MEMORY. Under AddressSanitizer and valgrind a failed operator new aborts the
 * process instead (neither can throw), so those cases run only without them. */
#if defined(__has_include)
#if __has_include(<valgrind/valgrind.h>)
#include <valgrind/valgrind.h>
#endif
#endif
static int allocation_failure_testable(void) {
#if defined(__SANITIZE_ADDRESS__)
    return 0;
#elif defined(RUNNING_ON_VALGRIND)
    return !RUNNING_ON_VALGRIND;
#else
    return 1;
#endif
}

static const char *tmp_path(const char *name) {
    static char buf[8][1024];
    static int next = 0;
    char *out = buf[next++ % 8];
    snprintf(out, sizeof buf[0], "%s/bad_%s", FRIX_TEST_TMPDIR, name);
    return out;
}

/* A deterministic generator (no rand(): the same inputs every run). */
static uint64_t rng_state = 0x9E3779B97F4A7C15ull;
static uint64_t rng(void) {
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return rng_state;
}

/* Writes a scene problem (local or global) with a solution and two guesses. */
static void write_scene_file(const char *path, int global) {
    frix_scene_params sp;
    frix_scene_defaults(FRIX_SCENE_STACK, &sp);
    sp.count = 2;
    frix_scene s;
    frix_scene_problems f;
    ck_assert_int_eq(frix_scene_build(&sp, &s, NULL), FRIX_OK);
    ck_assert_int_eq(frix_scene_problems_make(&s, &f), FRIX_OK);
    const frix_problem *p = global ? f.global : f.local;
    const int64_t m = frix_problem_contact_dofs(p), n = frix_problem_dofs(p);
    double *r = calloc((size_t)(3 * m), sizeof *r), *u = calloc((size_t)(3 * m), sizeof *u);
    double *v = calloc((size_t)(3 * n + 1), sizeof *v);
    ck_assert_int_eq(frix_solve(p, NULL, r, u, global ? v : NULL, NULL), FRIX_OK);
    for (int64_t i = 0; i < 2 * m; ++i) r[m + i] = 0.5 * r[i % m];
    ck_assert_int_eq(frix_fclib_write(path, p, r, u, global ? v : NULL, 2, r + m, u + m,
                                      global ? v + n : NULL),
                     FRIX_OK);
    free(r);
    free(u);
    free(v);
    frix_scene_problems_free(&f);
    frix_scene_free(&s);
}

/* What a reader may answer to a damaged file: a refusal with a message naming the file, or
 * (damage in bytes the reader never uses) a valid problem that solves to finite values. */
static int check_damaged_read(const char *path, frix_error *code) {
    frix_problem *p = (frix_problem *)0x1;
    frix_error err = frix_read_problem(path, &p);
    *code = err;
    if (err != FRIX_OK) {
        ck_assert_msg(err == FRIX_ERR_IO || err == FRIX_ERR_FORMAT || err == FRIX_ERR_UNSUPPORTED,
                      "%s: unexpected error %d: %s", path, err, frix_last_error_message());
        ck_assert_ptr_null(p);
        ck_assert_msg(strstr(frix_last_error_message(), path) != NULL, "message does not name the file: %s",
                      frix_last_error_message());
        return 0;
    }
    const int64_t m = frix_problem_contact_dofs(p), n = frix_problem_dofs(p);
    const int global = frix_problem_get_kind(p) == FRIX_PROBLEM_GLOBAL;
    double *r = calloc((size_t)m + 1, sizeof *r), *u = calloc((size_t)m + 1, sizeof *u);
    double *v = calloc((size_t)n + 1, sizeof *v);
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_NSGS, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_MAX_ITER, 20), FRIX_OK);
    frix_error se = frix_solve(p, o, r, u, global ? v : NULL, NULL);
    ck_assert_msg(se == FRIX_OK || se == FRIX_ERR_NUMERICAL, "%s: solve: %d %s", path, se,
                  frix_last_error_message());
    for (int64_t i = 0; i < m; ++i) ck_assert(isfinite(r[i]) && isfinite(u[i]));
    /* The solution and guess readers on the same damaged file. */
    int64_t count = 0;
    if (frix_fclib_guess_count(path, &count) == FRIX_OK)
        for (int64_t k = 0; k < count && k < 4; ++k)
            (void)frix_fclib_read_guess(path, p, k, r, u, global ? v : NULL);
    (void)frix_fclib_read_solution(path, p, r, u, global ? v : NULL);
    frix_options_free(o);
    free(r);
    free(u);
    free(v);
    frix_problem_free(p);
    return 1;
}

static int tried = 0; /* bad inputs tried in this process (printed by each test) */

/* ---- Truncated and corrupted files ---------------------------------------------------- */

START_TEST(test_truncated_files) {
    for (int global = 0; global < 2; ++global) {
        const char *good = tmp_path(global ? "good_global.hdf5" : "good_local.hdf5");
        write_scene_file(good, global);
        long size = 0;
        char *data = slurp(good, &size);
        const char *cut = tmp_path("truncated.hdf5");
        int refused = 0, n = 0;
        for (long len = 0; len < size; len += len < 64 ? 8 : 1 + size / 97) {
            spit(cut, data, len);
            frix_error code;
            int read = check_damaged_read(cut, &code);
            ck_assert_msg(!read, "a file truncated to %ld of %ld bytes was read as valid", len, size);
            ++refused;
            ++n;
        }
        ++tried;
        tried += n - 1;
        printf("truncated %s files: %d tried, %d refused\n", global ? "global" : "local", n, refused);
        free(data);
    }
}
END_TEST

START_TEST(test_corrupted_files) {
    for (int global = 0; global < 2; ++global) {
        const char *good = tmp_path(global ? "good_global.hdf5" : "good_local.hdf5");
        write_scene_file(good, global);
        long size = 0;
        char *data = slurp(good, &size);
        char *bad = malloc((size_t)size);
        const char *path = tmp_path("corrupted.hdf5");
        int n = 0, refused = 0, io = 0, format = 0;
        for (int trial = 0; trial < 300; ++trial) {
            memcpy(bad, data, (size_t)size);
            const int kind = trial % 3;
            if (kind == 0) { /* one byte */
                bad[rng() % (uint64_t)size] = (char)(rng() & 0xff);
            } else if (kind == 1) { /* a few bytes in the first 4 KiB (superblock, headers) */
                for (int k = 0; k < 4; ++k) bad[rng() % (uint64_t)(size < 4096 ? size : 4096)] = (char)(rng() & 0xff);
            } else { /* a run of 0xff or 0x00 (sizes and addresses become enormous or zero) */
                long at = (long)(rng() % (uint64_t)size), len = 1 + (long)(rng() % 16);
                memset(bad + at, trial % 2 ? 0xff : 0x00, (size_t)(at + len <= size ? len : size - at));
            }
            spit(path, bad, size);
            frix_error code;
            if (!check_damaged_read(path, &code)) {
                ++refused;
                io += code == FRIX_ERR_IO;
                format += code == FRIX_ERR_FORMAT;
            }
            ++n;
        }
        tried += n;
        printf("corrupted %s files: %d tried, %d refused (%d I/O, %d format), %d read as valid\n",
               global ? "global" : "local", n, refused, io, format, n - refused);
        free(bad);
        free(data);
    }
}
END_TEST

/* ---- Global files with one defect each ------------------------------------------------ */

static void replace_doubles(const char *path, const char *name, const double *x, size_t n) {
    hid_t f = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
    ck_assert(f >= 0);
    if (H5Lexists(f, name, H5P_DEFAULT) > 0) ck_assert(H5Ldelete(f, name, H5P_DEFAULT) >= 0);
    hsize_t dim = n;
    hid_t sp = H5Screate_simple(1, &dim, NULL);
    hid_t ds = H5Dcreate2(f, name, H5T_IEEE_F64LE, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    ck_assert(ds >= 0);
    if (n > 0) ck_assert(H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, x) >= 0);
    H5Dclose(ds);
    H5Sclose(sp);
    H5Fclose(f);
}

static void replace_int(const char *path, const char *name, int v) {
    hid_t f = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
    ck_assert(f >= 0);
    if (H5Lexists(f, name, H5P_DEFAULT) > 0) ck_assert(H5Ldelete(f, name, H5P_DEFAULT) >= 0);
    hsize_t dim = 1;
    hid_t sp = H5Screate_simple(1, &dim, NULL);
    hid_t ds = H5Dcreate2(f, name, H5T_STD_I32LE, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    ck_assert(ds >= 0);
    ck_assert(H5Dwrite(ds, H5T_NATIVE_INT, H5S_ALL, H5S_ALL, H5P_DEFAULT, &v) >= 0);
    H5Dclose(ds);
    H5Sclose(sp);
    H5Fclose(f);
}

static void delete_link(const char *path, const char *name) {
    hid_t f = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
    ck_assert(f >= 0);
    ck_assert_msg(H5Ldelete(f, name, H5P_DEFAULT) >= 0, "cannot delete %s", name);
    H5Fclose(f);
}

/* Reading fails with `code`, and the message names the file and contains `needle`. */
static void expect_read_error(const char *path, frix_error code, const char *needle) {
    frix_problem *p = (frix_problem *)0x1;
    frix_error err = frix_fclib_read(path, &p);
    const char *msg = frix_last_error_message();
    ck_assert_msg(err == code, "%s (%s): expected error %d, got %d (%s)", path, needle, code, err, msg);
    ck_assert_ptr_null(p);
    ck_assert_msg(strstr(msg, path) != NULL, "message does not name the file: %s", msg);
    ck_assert_msg(strstr(msg, needle) != NULL, "message lacks '%s': %s", needle, msg);
    ++tried;
}

START_TEST(test_global_file_defects) {
    const char *good = tmp_path("defect_base.hdf5"), *path = tmp_path("defect.hdf5");
    write_scene_file(good, 1);
    long size = 0;
    char *data = slurp(good, &size);
    frix_problem *base = NULL;
    ck_assert_int_eq(frix_fclib_read(good, &base), FRIX_OK);
    const int64_t n = frix_problem_dofs(base), m = frix_problem_contact_dofs(base), nc = m / 3;
    double *x = calloc((size_t)(n + m + 8), sizeof *x);

    /* Every dataset of the problem missing, one at a time. */
    static const char *const required[] = {
        "/fclib_global/M", "/fclib_global/H", "/fclib_global/vectors/f", "/fclib_global/vectors/w",
        "/fclib_global/vectors/mu", "/fclib_global/M/p", "/fclib_global/M/i", "/fclib_global/M/x",
        "/fclib_global/H/p", "/fclib_global/H/x", "/fclib_global/M/m", "/fclib_global/H/n",
        "/fclib_global/spacedim"};
    for (size_t k = 0; k < sizeof required / sizeof required[0]; ++k) {
        spit(path, data, size);
        delete_link(path, required[k]);
        expect_read_error(path, FRIX_ERR_FORMAT, required[k]);
    }

    /* Wrong sizes. */
    spit(path, data, size);
    replace_doubles(path, "/fclib_global/vectors/f", x, (size_t)n - 1);
    expect_read_error(path, FRIX_ERR_FORMAT, "/fclib_global/vectors/f");
    spit(path, data, size);
    replace_doubles(path, "/fclib_global/vectors/w", x, (size_t)m + 3);
    expect_read_error(path, FRIX_ERR_FORMAT, "/fclib_global/vectors/w");
    spit(path, data, size);
    replace_doubles(path, "/fclib_global/vectors/mu", x, (size_t)nc + 1);
    expect_read_error(path, FRIX_ERR_FORMAT, "/fclib_global/vectors/mu");
    spit(path, data, size);
    replace_int(path, "/fclib_global/M/n", (int)n + 3); /* M not square */
    expect_read_error(path, FRIX_ERR_FORMAT, "/fclib_global/M");
    spit(path, data, size);
    replace_int(path, "/fclib_global/H/m", (int)n + 3); /* H rows != n */
    expect_read_error(path, FRIX_ERR_FORMAT, "/fclib_global/H");
    spit(path, data, size);
    replace_int(path, "/fclib_global/H/n", (int)m + 1); /* not 3 x contacts */
    expect_read_error(path, FRIX_ERR_FORMAT, "/fclib_global/H");
    spit(path, data, size);
    replace_int(path, "/fclib_global/M/m", 2000000000); /* enormous declared size */
    expect_read_error(path, FRIX_ERR_FORMAT, "/fclib_global/M");

    /* Non-finite values, negative mu. */
    static const double bad_values[] = {NAN, INFINITY, -INFINITY};
    static const char *const vectors[] = {"/fclib_global/vectors/f", "/fclib_global/vectors/w",
                                          "/fclib_global/vectors/mu"};
    const size_t lengths[] = {(size_t)n, (size_t)m, (size_t)nc};
    for (size_t vi = 0; vi < 3; ++vi)
        for (size_t bi = 0; bi < 3; ++bi) {
            for (size_t k = 0; k < lengths[vi]; ++k) x[k] = 0.5;
            x[lengths[vi] / 2] = bad_values[bi];
            spit(path, data, size);
            replace_doubles(path, vectors[vi], x, lengths[vi]);
            expect_read_error(path, FRIX_ERR_FORMAT, vectors[vi]);
        }
    for (size_t k = 0; k < (size_t)nc; ++k) x[k] = k == 1 ? -0.25 : 0.5;
    spit(path, data, size);
    replace_doubles(path, "/fclib_global/vectors/mu", x, (size_t)nc);
    expect_read_error(path, FRIX_ERR_FORMAT, "/fclib_global/vectors/mu");
    /* Non-finite matrix entries. */
    for (int which = 0; which < 2; ++which)
        for (size_t bi = 0; bi < 3; ++bi) {
            const char *name = which ? "/fclib_global/H/x" : "/fclib_global/M/x";
            spit(path, data, size);
            hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
            hid_t ds = H5Dopen2(f, name, H5P_DEFAULT);
            hid_t sp = H5Dget_space(ds);
            hssize_t len = H5Sget_simple_extent_npoints(sp);
            double *vals = calloc((size_t)len + 1, sizeof *vals);
            ck_assert(H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, vals) >= 0);
            H5Sclose(sp);
            H5Dclose(ds);
            H5Fclose(f);
            vals[len / 2] = bad_values[bi];
            replace_doubles(path, name, vals, (size_t)len);
            free(vals);
            expect_read_error(path, FRIX_ERR_FORMAT, name);
        }

    /* A /solution or guess of the wrong size: refused by the solution readers. */
    spit(path, data, size);
    replace_doubles(path, "/solution/r", x, (size_t)m - 1);
    double *r = calloc((size_t)m, sizeof *r), *u = calloc((size_t)m, sizeof *u);
    double *v = calloc((size_t)n, sizeof *v);
    ck_assert_int_eq(frix_fclib_read_solution(path, base, r, u, v), FRIX_ERR_FORMAT);
    ck_assert(strstr(frix_last_error_message(), "/solution/r") != NULL);
    spit(path, data, size);
    x[0] = NAN;
    replace_doubles(path, "/guesses/2/v", x, (size_t)n);
    ck_assert_int_eq(frix_fclib_read_guess(path, base, 1, r, u, v), FRIX_ERR_FORMAT);
    ck_assert(strstr(frix_last_error_message(), "/guesses/2/v") != NULL);
    ck_assert_int_eq(frix_fclib_read_guess(path, base, 2, r, u, v), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_fclib_read_guess(path, base, -1, r, u, v), FRIX_ERR_INVALID_ARGUMENT);
    spit(path, data, size);
    replace_int(path, "/guesses/number_of_guesses", 5); /* says 5, stores 2 */
    int64_t count = -1;
    frix_error ge = frix_fclib_guess_count(path, &count);
    ck_assert_msg(ge == FRIX_ERR_FORMAT || (ge == FRIX_OK && count == 5), "guess count: %d", ge);
    if (ge == FRIX_OK) ck_assert_int_eq(frix_fclib_read_guess(path, base, 4, r, u, v), FRIX_ERR_FORMAT);
    tried += 6;
    /* A local problem's solution reader handed the global problem of another file. */
    const char *local = tmp_path("defect_local.hdf5");
    write_scene_file(local, 0);
    ck_assert_int_ne(frix_fclib_read_solution(local, base, r, u, v), FRIX_OK);
    ++tried;

    free(r);
    free(u);
    free(v);
    free(x);
    free(data);
    frix_problem_free(base);
    printf("global file defects: %d refused\n", tried);
}
END_TEST

/* ---- NaN/Inf through the API ---------------------------------------------------------- */

START_TEST(test_non_finite_through_every_constructor) {
    static const double bad[] = {NAN, INFINITY, -INFINITY};
    const double W[9] = {2, 0, 0, 0, 1, 0, 0, 0, 1};
    const int64_t cp[4] = {0, 1, 2, 3}, ri[3] = {0, 1, 2}, rows[3] = {0, 1, 2};
    const int64_t zero = 0;
    for (int b = 0; b < 3; ++b) {
        double dense[9], vals[3] = {2, 1, 1};
        memcpy(dense, W, sizeof dense);
        dense[4] = bad[b];
        vals[1] = bad[b];
        frix_matrix *M = (frix_matrix *)0x1;
        ck_assert_int_eq(frix_matrix_from_dense(3, 3, dense, 3, &M), FRIX_ERR_NOT_FINITE);
        ck_assert_ptr_null(M);
        ck_assert_int_eq(frix_matrix_from_csc(3, 3, cp, ri, vals, &M), FRIX_ERR_NOT_FINITE);
        ck_assert_int_eq(frix_matrix_from_csr(3, 3, cp, ri, vals, &M), FRIX_ERR_NOT_FINITE);
        ck_assert_int_eq(frix_matrix_from_triplets(3, 3, 3, rows, ri, vals, &M), FRIX_ERR_NOT_FINITE);
        ck_assert_int_eq(frix_matrix_from_blocks(1, 1, 1, &zero, &zero, dense, &M), FRIX_ERR_NOT_FINITE);
        ck_assert_msg(strlen(frix_last_error_message()) > 0, "no message");
        tried += 5;

        /* q, mu; f, w of a global problem. */
        frix_matrix *A = NULL;
        ck_assert_int_eq(frix_matrix_from_dense(3, 3, W, 3, &A), FRIX_OK);
        double q[3] = {-1, 0, 0}, mu = 0.5, f[3] = {0, 0, -1}, w[3] = {0, 0, 0};
        frix_problem *p = (frix_problem *)0x1;
        q[2] = bad[b];
        ck_assert_int_eq(frix_problem_local(A, q, &mu, 1, &p), FRIX_ERR_NOT_FINITE);
        ck_assert_ptr_null(p);
        q[2] = 0;
        mu = bad[b];
        frix_error e = frix_problem_local(A, q, &mu, 1, &p);
        ck_assert_msg(e == FRIX_ERR_NOT_FINITE || (b == 2 && e == FRIX_ERR_INVALID_ARGUMENT), "mu %g: %d", mu, e);
        ck_assert(strstr(frix_last_error_message(), "mu") != NULL);
        mu = 0.5;
        f[1] = bad[b];
        ck_assert_int_eq(frix_problem_global(A, A, f, w, &mu, 1, &p), FRIX_ERR_NOT_FINITE);
        f[1] = 0;
        w[0] = bad[b];
        ck_assert_int_eq(frix_problem_global(A, A, f, w, &mu, 1, &p), FRIX_ERR_NOT_FINITE);
        w[0] = 0;
        tried += 4;

        /* Borrowed data poisoned after creation: caught at solve and measure time. */
        ck_assert_int_eq(frix_problem_global(A, A, f, w, &mu, 1, &p), FRIX_OK);
        double r[3] = {0}, u[3], v[3] = {0};
        w[1] = bad[b];
        ck_assert_int_eq(frix_solve(p, NULL, r, u, v, NULL), FRIX_ERR_NOT_FINITE);
        ck_assert_int_eq(frix_problem_error(p, r, v, &mu), FRIX_ERR_NOT_FINITE);
        mu = 0.5;
        w[1] = 0;
        /* A non-finite warm start (r, v) is not an error: it restarts from 0. */
        r[0] = bad[b];
        v[2] = bad[b];
        frix_info *info = NULL;
        ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
        ck_assert_int_eq(frix_solve(p, NULL, r, u, v, info), FRIX_OK);
        ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_CONVERGED);
        ck_assert(isfinite(r[0]) && isfinite(v[2]));
        /* But measuring a non-finite r is refused. */
        r[1] = bad[b];
        ck_assert_int_eq(frix_problem_measure(p, r, v, NULL, info), FRIX_ERR_NOT_FINITE);
        tried += 4;
        frix_info_free(info);
        frix_problem_free(p);
        frix_matrix_free(A);
    }
    /* mu = -0.0 is a valid zero; a negative mu is refused whatever its size. */
    frix_matrix *A = NULL;
    ck_assert_int_eq(frix_matrix_from_dense(3, 3, W, 3, &A), FRIX_OK);
    double q[3] = {-1, 0, 0}, mu = -0.0;
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_problem_local(A, q, &mu, 1, &p), FRIX_OK);
    frix_problem_free(p);
    mu = -1e-300;
    ck_assert_int_eq(frix_problem_local(A, q, &mu, 1, &p), FRIX_ERR_INVALID_ARGUMENT);
    tried += 2;
    frix_matrix_free(A);
    printf("non-finite values and negative mu through the API: %d refused\n", tried);
}
END_TEST

/* ---- Enormous sizes ------------------------------------------------------------------- */

START_TEST(test_enormous_sizes) {
    frix_matrix *M = (frix_matrix *)0x1;
    /* Within the declared-size cap but far beyond memory: the allocation fails cleanly. */
    const int64_t huge = allocation_failure_testable() ? (int64_t)3 << 37 : (int64_t)1 << 41;
    frix_error e = frix_matrix_from_triplets(huge, huge, 0, NULL, NULL, NULL, &M);
    ck_assert_msg(e == FRIX_ERR_OUT_OF_MEMORY || e == FRIX_ERR_DIMENSION, "got %d", e);
    ck_assert_ptr_null(M);
    ck_assert(strlen(frix_last_error_message()) > 0);
    e = frix_matrix_from_blocks(huge / 3, huge / 3, 0, NULL, NULL, NULL, &M);
    ck_assert_msg(e == FRIX_ERR_OUT_OF_MEMORY || e == FRIX_ERR_DIMENSION, "got %d", e);
    /* A general (not 3x3-block) matrix, and a wide one. */
    e = frix_matrix_from_triplets(huge + 1, 7, 0, NULL, NULL, NULL, &M);
    ck_assert_msg(e == FRIX_ERR_OUT_OF_MEMORY || e == FRIX_ERR_DIMENSION || e == FRIX_OK, "got %d", e);
    frix_matrix_free(e == FRIX_OK ? M : NULL);
    e = frix_matrix_from_triplets(7, huge + 1, 0, NULL, NULL, NULL, &M);
    ck_assert_msg(e == FRIX_ERR_OUT_OF_MEMORY || e == FRIX_ERR_DIMENSION, "got %d", e);
    /* Negative and overflowing sizes. */
    ck_assert_int_eq(frix_matrix_from_triplets(INT64_MAX, 3, 0, NULL, NULL, NULL, &M), FRIX_ERR_DIMENSION);
    ck_assert_int_eq(frix_matrix_from_triplets(3, INT64_MIN, 0, NULL, NULL, NULL, &M), FRIX_ERR_DIMENSION);
    ck_assert_int_eq(frix_matrix_from_blocks(INT64_MAX / 2, 1, 0, NULL, NULL, NULL, &M), FRIX_ERR_DIMENSION);
    ck_assert_int_eq(frix_matrix_from_dense(INT64_MAX, INT64_MAX, NULL, INT64_MAX, &M) < 0, 1);
    /* A problem claiming more contacts than W has. */
    frix_matrix *A = NULL;
    const double W[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    ck_assert_int_eq(frix_matrix_from_dense(3, 3, W, 3, &A), FRIX_OK);
    double q[3] = {-1, 0, 0}, mu = 0.3, f[3] = {0}, w[3] = {0};
    frix_problem *p = (frix_problem *)0x1;
    ck_assert_int_eq(frix_problem_local(A, q, &mu, INT64_MAX / 3, &p), FRIX_ERR_DIMENSION);
    ck_assert_ptr_null(p);
    ck_assert_int_eq(frix_problem_global(A, A, f, w, &mu, INT64_MAX, &p), FRIX_ERR_DIMENSION);
    tried += 11;
    frix_matrix_free(A);
    printf("enormous, negative and overflowing sizes: %d refused\n", tried);
}
END_TEST

/* ---- Options: every key of every solver out of range, unknown solvers and keys -------- */

START_TEST(test_options_out_of_range) {
    int n = 0;
    static const int bad_ids[] = {-1, 0, 1, 499, 501, 599, 999, 99999, INT_MAX, INT_MIN};
    for (size_t i = 0; i < sizeof bad_ids / sizeof bad_ids[0]; ++i) {
        int registered = 0; /* the registry grows: skip an id that has become real */
        for (int64_t k = 0; k < frix_solver_count(); ++k) registered |= frix_solver_id_at(k) == bad_ids[i];
        if (registered) continue;
        frix_options *o = (frix_options *)0x1;
        ck_assert_int_eq(frix_options_create(bad_ids[i], &o), FRIX_ERR_UNKNOWN_SOLVER);
        ck_assert_ptr_null(o);
        ck_assert(strlen(frix_last_error_message()) > 0);
        ck_assert_ptr_null(frix_solver_name(bad_ids[i]));
        ck_assert_ptr_null(frix_solver_describe(bad_ids[i]));
        ++n;
    }
    static const char *const bad_names[] = {"", " ", "nsgs ", "500x", "-500", "0x1f4", "99999999999999999999",
                                            "FRICTION_3D_", "FC3D_", "nsgs\n", "\xff\xfe"};
    for (size_t i = 0; i < sizeof bad_names / sizeof bad_names[0]; ++i) {
        int id = 12345;
        ck_assert_msg(frix_solver_by_name(bad_names[i], &id) == FRIX_ERR_UNKNOWN_SOLVER, "'%s'", bad_names[i]);
        ck_assert_int_eq(id, 12345);
        ++n;
    }
    ck_assert_int_eq(frix_solver_by_name(NULL, NULL), FRIX_ERR_INVALID_ARGUMENT);

    for (int64_t s = 0; s < frix_solver_count(); ++s) {
        const int solver = frix_solver_id_at(s);
        frix_options *o = NULL;
        ck_assert_int_eq(frix_options_create(solver, &o), FRIX_OK);
        for (int key = -2; key <= 64; ++key) {
            double lo, hi, before, after;
            int is_int;
            frix_error be = frix_options_bounds(o, (frix_option_key)key, &lo, &hi, &is_int);
            if (be != FRIX_OK) {
                ck_assert_int_eq(be, FRIX_ERR_UNKNOWN_OPTION);
                ck_assert_int_eq(frix_options_set_double(o, (frix_option_key)key, 1.0), FRIX_ERR_UNKNOWN_OPTION);
                ck_assert_int_eq(frix_options_set_int(o, (frix_option_key)key, 1), FRIX_ERR_UNKNOWN_OPTION);
                ck_assert_int_eq(frix_options_get_double(o, (frix_option_key)key, &before), FRIX_ERR_UNKNOWN_OPTION);
                n += 3;
                continue;
            }
            ck_assert_msg(lo <= hi, "solver %d key %d: bounds [%g, %g]", solver, key, lo, hi);
            ck_assert_int_eq(frix_options_get_double(o, (frix_option_key)key, &before), FRIX_OK);
            const double outside[] = {lo - 1.0, hi + 1.0, lo - fabs(lo) - 1e300 * 0, -INFINITY, INFINITY, NAN,
                                      hi * 2 + 1e9, -1e300, 1e300};
            for (size_t k = 0; k < sizeof outside / sizeof outside[0]; ++k) {
                const double x = outside[k];
                if (x >= lo && x <= hi) continue; /* not outside (e.g. unbounded keys) */
                frix_error e = frix_options_set_double(o, (frix_option_key)key, x);
                ck_assert_msg(e == FRIX_ERR_OPTION_RANGE, "solver %d key %d value %g: %d", solver, key, x, e);
                ck_assert_msg(strstr(frix_last_error_message(), frix_option_name((frix_option_key)key)) != NULL,
                              "message does not name the option: %s", frix_last_error_message());
                if (is_int && isfinite(x) && fabs(x) < 9e18) {
                    ck_assert_int_eq(frix_options_set_int(o, (frix_option_key)key, (int64_t)x), FRIX_ERR_OPTION_RANGE);
                    ++n;
                }
                ck_assert_int_eq(frix_options_get_double(o, (frix_option_key)key, &after), FRIX_OK);
                ck_assert_msg(after == before, "solver %d key %d: a refused value changed it", solver, key);
                ++n;
            }
            if (is_int) {
                /* An int key refuses a fraction, and the extreme int64 values. */
                if (lo + 0.5 < hi) {
                    ck_assert_int_eq(frix_options_set_double(o, (frix_option_key)key, lo + 0.5), FRIX_ERR_OPTION_RANGE);
                    ++n;
                }
                if (hi < 9e18) {
                    ck_assert_int_eq(frix_options_set_int(o, (frix_option_key)key, INT64_MAX), FRIX_ERR_OPTION_RANGE);
                    ++n;
                }
                if (lo > -9e18) {
                    ck_assert_int_eq(frix_options_set_int(o, (frix_option_key)key, INT64_MIN), FRIX_ERR_OPTION_RANGE);
                    ++n;
                }
                ck_assert_int_eq(frix_options_get_double(o, (frix_option_key)key, &after), FRIX_OK);
                ck_assert(after == before);
            }
        }
        /* NULL handles and outputs. */
        double d;
        int64_t i64;
        ck_assert_int_eq(frix_options_set_double(NULL, FRIX_OPT_TOLERANCE, 1e-6), FRIX_ERR_INVALID_ARGUMENT);
        ck_assert_int_eq(frix_options_set_int(NULL, FRIX_OPT_MAX_ITER, 5), FRIX_ERR_INVALID_ARGUMENT);
        ck_assert_int_eq(frix_options_get_double(o, FRIX_OPT_TOLERANCE, NULL), FRIX_ERR_INVALID_ARGUMENT);
        ck_assert_int_eq(frix_options_get_int(NULL, FRIX_OPT_MAX_ITER, &i64), FRIX_ERR_INVALID_ARGUMENT);
        ck_assert_int_eq(frix_options_get_double(NULL, FRIX_OPT_TOLERANCE, &d), FRIX_ERR_INVALID_ARGUMENT);
        ck_assert_int_eq(frix_options_bounds(NULL, FRIX_OPT_TOLERANCE, &d, &d, NULL), FRIX_ERR_INVALID_ARGUMENT);
        ck_assert_int_eq(frix_options_copy(NULL, &o) < 0, 1);
        ck_assert_int_eq(frix_options_create(solver, NULL), FRIX_ERR_INVALID_ARGUMENT);
        n += 8;
        frix_options_free(o);
    }
    frix_option_key k;
    ck_assert_int_eq(frix_option_by_name(NULL, &k), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_option_by_name("tolerance", NULL), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_ptr_null(frix_option_name((frix_option_key)-1));
    ck_assert_ptr_null(frix_option_name((frix_option_key)1000));
    tried += n;
    printf("options: %d out-of-range values, unknown keys, solver ids and names refused\n", n);
}
END_TEST

/* ---- NULL arguments across the API ---------------------------------------------------- */

START_TEST(test_null_arguments) {
    double x[9] = {0}, y[9] = {0};
    int64_t i64 = 0;
    ck_assert_int_eq(frix_matrix_gemv(NULL, 1, x, 0, y), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_matrix_gemv_transposed(NULL, 1, x, 0, y), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_matrix_diagonal_block(NULL, 0, y), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_matrix_to_csc(NULL, &i64, NULL, NULL, NULL), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_matrix_rows(NULL), 0);
    ck_assert_int_eq(frix_matrix_nnz(NULL), 0);
    frix_matrix *A = NULL;
    const double W[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    ck_assert_int_eq(frix_matrix_from_dense(3, 3, W, 3, &A), FRIX_OK);
    ck_assert_int_eq(frix_matrix_gemv(A, 1, NULL, 0, y), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_matrix_gemv(A, 1, x, 0, NULL), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_matrix_diagonal_block(A, 1, y) < 0, 1); /* out of range */
    ck_assert_int_eq(frix_matrix_diagonal_block(A, -1, y) < 0, 1);
    ck_assert_int_eq(frix_matrix_to_csc(A, NULL, NULL, NULL, NULL), FRIX_ERR_INVALID_ARGUMENT);
    int64_t cp[4];
    ck_assert_int_eq(frix_matrix_to_csc(A, &i64, cp, NULL, x), FRIX_ERR_INVALID_ARGUMENT); /* 3 entries */
    ck_assert_int_eq(frix_matrix_to_csc(A, &i64, cp, (int64_t *)cp, NULL), FRIX_ERR_INVALID_ARGUMENT);
    double q[3] = {-1, 0, 0}, mu = 0.3, r[3] = {0}, u[3];
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_problem_local(A, q, &mu, 1, NULL), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_problem_local(A, q, NULL, 1, &p), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_problem_global(NULL, A, q, q, &mu, 1, &p), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_problem_global(A, NULL, q, q, &mu, 1, &p), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_problem_global(A, A, NULL, q, &mu, 1, &p), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_problem_global(A, A, q, NULL, &mu, 1, &p), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_problem_set_title(NULL, "x"), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_str_eq(frix_problem_title(NULL), "");
    ck_assert_int_eq(frix_problem_local(A, q, &mu, 1, &p), FRIX_OK);
    ck_assert_int_eq(frix_problem_set_title(p, NULL) <= 0, 1);
    ck_assert_int_eq(frix_problem_measure(p, r, NULL, u, NULL), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_problem_measure(NULL, r, NULL, u, NULL), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_problem_error(p, NULL, NULL, &mu), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_problem_error(p, r, NULL, NULL), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_solve(p, NULL, r, NULL, NULL, NULL), FRIX_ERR_INVALID_ARGUMENT);
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(NULL), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    double d;
    ck_assert_int_eq(frix_info_get_int(NULL, FRIX_INFO_STATUS, &i64), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_info_get_int(info, FRIX_INFO_STATUS, NULL), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_info_get_double(info, (frix_info_key)9999, &d) < 0, 1);
    ck_assert_int_eq(frix_info_get_int(info, (frix_info_key)-5, &i64) < 0, 1);
    ck_assert_int_eq(frix_info_status(NULL), FRIX_STATUS_NOT_RUN);
    ck_assert(isnan(frix_info_error(NULL)));
    frix_problem *rp = (frix_problem *)0x1;
    ck_assert_int_eq(frix_read_problem(NULL, &rp), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_dat_read(NULL, &rp), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_read_problem("", &rp) < 0, 1);
    ck_assert_int_eq(frix_fclib_write(NULL, p, NULL, NULL, NULL, 0, NULL, NULL, NULL), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_fclib_write(tmp_path("never.hdf5"), p, NULL, NULL, NULL, 3, NULL, NULL, NULL),
                     FRIX_ERR_INVALID_ARGUMENT); /* guesses announced, not given */
    ck_assert_int_eq(frix_fclib_write(tmp_path("never.hdf5"), p, NULL, NULL, NULL, -1, NULL, NULL, NULL) < 0, 1);
    ck_assert_int_eq(access(tmp_path("never.hdf5"), F_OK), -1);
    ck_assert_int_eq(frix_fclib_read_solution(NULL, p, r, u, NULL), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_fclib_read_solution(tmp_path("never.hdf5"), NULL, r, u, NULL), FRIX_ERR_INVALID_ARGUMENT);
    tried += 44;
    printf("NULL and out-of-range arguments: %d refused\n", tried);
    frix_info_free(info);
    frix_problem_free(p);
    frix_matrix_free(A);
}
END_TEST

/* ---- The command line ----------------------------------------------------------------- */

/* Exit 2, nothing on stdout, exactly one line on stderr starting "frix: " and containing
 * `needle`. */
static void expect_cli_refusal(const char *const *args, const char *needle) {
    cli_run r = run_cli(args);
    ck_assert_msg(r.code == 2, "%s %s: exit %d, stderr: %s", args[0], args[1] ? args[1] : "", r.code, r.err);
    ck_assert_msg(r.out[0] == '\0', "stdout not empty: %s", r.out);
    const char *nl = strchr(r.err, '\n');
    ck_assert_msg(strncmp(r.err, "frix: ", 6) == 0 && nl != NULL && nl[1] == '\0',
                  "not one 'frix: ' line: [%s]", r.err);
    ck_assert_msg(strstr(r.err, needle) != NULL, "stderr lacks '%s': %s", needle, r.err);
    free(r.out);
    free(r.err);
    ++tried;
}

/* A problem's texts: NULL problems refused, NULL text empty, 65536 bytes taken and one more
 * refused with the text before kept (a file could not carry it back: the reader's bound). */
START_TEST(test_problem_texts_bounded) {
    typedef frix_error (*setter)(frix_problem *, const char *);
    typedef const char *(*getter)(const frix_problem *);
    const setter set[] = {frix_problem_set_title, frix_problem_set_description, frix_problem_set_math_info};
    const getter get[] = {frix_problem_title, frix_problem_description, frix_problem_math_info};
    double W[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, q[3] = {-1, 0, 0}, mu = 0.3;
    frix_matrix *A = NULL;
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_matrix_from_dense(3, 3, W, 3, &A), FRIX_OK);
    ck_assert_int_eq(frix_problem_local(A, q, &mu, 1, &p), FRIX_OK);
    char *text = malloc(65538);
    ck_assert_ptr_nonnull(text);
    memset(text, 'x', 65537);
    text[65537] = '\0';
    for (int k = 0; k < 3; ++k) {
        ck_assert_int_eq(set[k](NULL, "x"), FRIX_ERR_INVALID_ARGUMENT);
        ck_assert_str_eq(get[k](NULL), "");
        ck_assert_str_eq(get[k](p), "");
        ck_assert_int_eq(set[k](p, "kept"), FRIX_OK);
        ck_assert_int_eq(set[k](p, text), FRIX_ERR_INVALID_ARGUMENT);
        ck_assert_ptr_nonnull(strstr(frix_last_error_message(), "65537 bytes"));
        ck_assert_str_eq(get[k](p), "kept");
        text[65536] = '\0';
        ck_assert_int_eq(set[k](p, text), FRIX_OK);
        ck_assert_uint_eq(strlen(get[k](p)), 65536);
        text[65536] = 'x';
        ck_assert_int_eq(set[k](p, NULL), FRIX_OK);
        ck_assert_str_eq(get[k](p), "");
    }
    free(text);
    frix_problem_free(p);
    frix_matrix_free(A);
}
END_TEST

START_TEST(test_cli_bad_input) {
    const char *good = tmp_path("cli_good.hdf5"), *global = tmp_path("cli_global.hdf5");
    write_scene_file(good, 0);
    write_scene_file(global, 1);
    long size = 0;
    char *data = slurp(good, &size);
    const char *cut = tmp_path("cli_truncated.hdf5"), *nanmu = tmp_path("cli_nanmu.hdf5");
    spit(cut, data, size / 3);
    long gsize = 0;
    char *gdata = slurp(global, &gsize);
    spit(nanmu, gdata, gsize);
    double mus[8] = {0.5, NAN, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5};
    replace_doubles(nanmu, "/fclib_global/vectors/mu", mus, 8);
    const char *nomat = tmp_path("cli_nomatrix.hdf5");
    spit(nomat, gdata, gsize);
    delete_link(nomat, "/fclib_global/H");

    /* The bad files, through every command that reads a problem. */
    const char *bad_files[] = {cut, nanmu, nomat};
    for (int i = 0; i < 3; ++i) {
        const char *a1[] = {"solve", bad_files[i], NULL};
        expect_cli_refusal(a1, bad_files[i]);
        const char *a2[] = {"info", bad_files[i], "--json", NULL};
        expect_cli_refusal(a2, bad_files[i]);
        /* convert onto an existing file: refused, the file is untouched. */
        const char *target = tmp_path("cli_existing.hdf5");
        spit(target, data, size);
        const char *a3[] = {"convert", bad_files[i], target, NULL};
        expect_cli_refusal(a3, bad_files[i]);
        const char *a4[] = {"solve", bad_files[i], "--output", target, NULL};
        expect_cli_refusal(a4, bad_files[i]);
        long after_size = 0;
        char *after = slurp(target, &after_size);
        ck_assert_int_eq(after_size, size);
        ck_assert(memcmp(after, data, (size_t)size) == 0);
        free(after);
    }
    /* Unknown solver ids and out-of-range options. */
    const char *c1[] = {"solve", good, "--solver", "99999", NULL};
    expect_cli_refusal(c1, "99999");
    const char *c2[] = {"solve", good, "--solver", "-1", NULL};
    expect_cli_refusal(c2, "-1");
    const char *c3[] = {"solve", good, "--set", "max_iter=-5", NULL};
    expect_cli_refusal(c3, "max_iter");
    const char *c4[] = {"solve", good, "--set", "tolerance=nan", NULL};
    expect_cli_refusal(c4, "tolerance");
    const char *c5[] = {"solve", good, "--set", "relaxation=7", NULL};
    expect_cli_refusal(c5, "relaxation");
    const char *c6[] = {"solve", good, "--max-iter", "99999999999999999999999", NULL};
    expect_cli_refusal(c6, "--max-iter");
    const char *c7[] = {"solve", good, "--time-limit", "-1", NULL};
    expect_cli_refusal(c7, "--time-limit");
    const char *c8[] = {"solve", good, "--tol", "inf", NULL};
    expect_cli_refusal(c8, "--tol");
    const char *c9[] = {"solve", good, "--set", "local_solver=12", NULL};
    expect_cli_refusal(c9, "local_solver");
    const char *c10[] = {"solve", good, "--set", "=1", NULL};
    expect_cli_refusal(c10, "--set");
    const char *c11[] = {"solvers", "99999", NULL};
    expect_cli_refusal(c11, "99999");
    const char *c12[] = {"solve", global, "--solver", "nsgs", "--set", "max_iter=0", NULL};
    expect_cli_refusal(c12, "max_iter");
    /* A good solve whose output path is a directory: refused, the directory stays. */
    const char *c13[] = {"solve", good, "--output", FRIX_TEST_TMPDIR, NULL};
    cli_run r = run_cli(c13);
    ck_assert_int_eq(r.code, 2);
    struct stat st;
    ck_assert(stat(FRIX_TEST_TMPDIR, &st) == 0 && S_ISDIR(st.st_mode));
    free(r.out);
    free(r.err);
    ++tried;
    free(data);
    free(gdata);
    printf("command line: %d bad invocations refused cleanly\n", tried);
}
END_TEST

int main(void) {
    Suite *s = suite_create("bad_input");
    TCase *files = tcase_create("files");
    tcase_set_timeout(files, 600);
    tcase_add_test(files, test_truncated_files);
    tcase_add_test(files, test_corrupted_files);
    tcase_add_test(files, test_global_file_defects);
    suite_add_tcase(s, files);
    TCase *api = tcase_create("api");
    tcase_add_test(api, test_non_finite_through_every_constructor);
    tcase_add_test(api, test_enormous_sizes);
    tcase_add_test(api, test_options_out_of_range);
    tcase_add_test(api, test_null_arguments);
    tcase_add_test(api, test_problem_texts_bounded);
    suite_add_tcase(s, api);
    TCase *cli = tcase_create("cli");
    tcase_set_timeout(cli, 600);
    tcase_add_test(cli, test_cli_bad_input);
    suite_add_tcase(s, cli);
    return frix_run_suite(s);
}
