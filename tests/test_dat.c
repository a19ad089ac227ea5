/* Siconos text problems (.dat): every file of the shared collection reads, and gives the same
 * problem as its FCLIB conversion in converted/ (written by Siconos + libfclib):
 *   - local files: W, q and mu equal to the last bit, explicit zeros aside;
 *   - global files (M, H, f, w): their twins are the reduced local problems, so W = H^T M^-1 H
 *     and q = H^T M^-1 f + w are formed here densely and compared to round-off, mu exactly.
 * Also frix_read_problem's format detection, and malformed files with precise messages. */
#define _POSIX_C_SOURCE 200809L
#include <frix/frix.h>

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "check_main.h"
#include "files.h"

#define DAT_DIR FRIX_SHARED_DIR "/fclib/dat"
#define CONVERTED_DIR FRIX_SHARED_DIR "/fclib/converted"

/* ------------------------------------------------------------------ helpers */

static const char *tmp_path(const char *name) {
    static char buf[4][1024];
    static int next = 0;
    char *out = buf[next++ % 4];
    snprintf(out, sizeof buf[0], "%s/dat_%s", FRIX_TEST_TMPDIR, name);
    return out;
}

/* Dense column-major copy of a matrix (explicit zeros and stored zeros alike are 0). */
static double *dense_of(const frix_matrix *A) {
    int64_t m = frix_matrix_rows(A), n = frix_matrix_cols(A), nnz = 0;
    ck_assert_int_eq(frix_matrix_to_csc(A, &nnz, NULL, NULL, NULL), FRIX_OK);
    int64_t *cp = malloc((size_t)(n + 1) * sizeof *cp), *ri = malloc((size_t)(nnz + 1) * sizeof *ri);
    double *x = malloc((size_t)(nnz + 1) * sizeof *x), *D = calloc((size_t)(m * n + 1), sizeof *D);
    ck_assert_int_eq(frix_matrix_to_csc(A, &nnz, cp, ri, x), FRIX_OK);
    for (int64_t j = 0; j < n; ++j)
        for (int64_t e = cp[j]; e < cp[j + 1]; ++e) D[ri[e] + j * m] = x[e];
    free(cp);
    free(ri);
    free(x);
    return D;
}

/* Bit-for-bit equality of two vectors, reporting the first difference. */
static void expect_same_bits(const char *file, const char *what, const double *a, const double *b,
                             int64_t n) {
    for (int64_t i = 0; i < n; ++i)
        ck_assert_msg(memcmp(&a[i], &b[i], sizeof(double)) == 0, "%s: %s[%lld] = %.17g vs %.17g",
                      file, what, (long long)i, a[i], b[i]);
}

/* Solves A X = B in place (A n x n, B n x k, column-major) by LU with partial pivoting. */
static void dense_solve(int64_t n, double *A, int64_t k, double *B) {
    for (int64_t c = 0; c < n; ++c) {
        int64_t p = c;
        for (int64_t i = c + 1; i < n; ++i)
            if (fabs(A[i + c * n]) > fabs(A[p + c * n])) p = i;
        ck_assert_msg(A[p + c * n] != 0.0, "singular M");
        for (int64_t j = 0; j < n; ++j) { double t = A[c + j * n]; A[c + j * n] = A[p + j * n]; A[p + j * n] = t; }
        for (int64_t j = 0; j < k; ++j) { double t = B[c + j * n]; B[c + j * n] = B[p + j * n]; B[p + j * n] = t; }
        for (int64_t i = c + 1; i < n; ++i) {
            double l = A[i + c * n] / A[c + c * n];
            for (int64_t j = c; j < n; ++j) A[i + j * n] -= l * A[c + j * n];
            for (int64_t j = 0; j < k; ++j) B[i + j * n] -= l * B[c + j * n];
        }
    }
    for (int64_t j = 0; j < k; ++j)
        for (int64_t i = n - 1; i >= 0; --i) {
            double s = B[i + j * n];
            for (int64_t l = i + 1; l < n; ++l) s -= A[i + l * n] * B[l + j * n];
            B[i + j * n] = s / A[i + i * n];
        }
}

/* Same sizes, same non-zero pattern and the same bits in every non-zero entry (CSC export
 * drops explicit zeros on both sides). */
static void expect_same_matrix(const char *file, const char *what, const frix_matrix *A,
                               const frix_matrix *B) {
    int64_t n = frix_matrix_cols(A), na = 0, nb = 0;
    ck_assert_int_eq(frix_matrix_rows(A), frix_matrix_rows(B));
    ck_assert_int_eq(n, frix_matrix_cols(B));
    ck_assert_int_eq(frix_matrix_to_csc(A, &na, NULL, NULL, NULL), FRIX_OK);
    ck_assert_int_eq(frix_matrix_to_csc(B, &nb, NULL, NULL, NULL), FRIX_OK);
    ck_assert_msg(na == nb, "%s: %s has %lld non-zero entries vs %lld", file, what, (long long)na,
                  (long long)nb);
    int64_t *cp[2], *ri[2];
    double *x[2];
    for (int k = 0; k < 2; ++k) {
        cp[k] = malloc((size_t)(n + 1) * sizeof(int64_t));
        ri[k] = malloc((size_t)(na + 1) * sizeof(int64_t));
        x[k] = malloc((size_t)(na + 1) * sizeof(double));
        ck_assert_int_eq(frix_matrix_to_csc(k ? B : A, &na, cp[k], ri[k], x[k]), FRIX_OK);
    }
    ck_assert_msg(memcmp(cp[0], cp[1], (size_t)(n + 1) * sizeof(int64_t)) == 0 &&
                      memcmp(ri[0], ri[1], (size_t)na * sizeof(int64_t)) == 0,
                  "%s: %s has another non-zero pattern", file, what);
    expect_same_bits(file, what, x[0], x[1], na);
    for (int k = 0; k < 2; ++k) {
        free(cp[k]);
        free(ri[k]);
        free(x[k]);
    }
}

static void compare_local(const char *file, const frix_problem *dat, const frix_problem *twin) {
    expect_same_matrix(file, "W (non-zeros, column by column)", frix_problem_W(dat), frix_problem_W(twin));
    expect_same_bits(file, "q", frix_problem_q(dat), frix_problem_q(twin), frix_problem_contact_dofs(dat));
}

/* W = H^T M^-1 H, q = H^T M^-1 f + w against the twin, relative to the largest entry. */
static double compare_reduced(const char *file, const frix_problem *dat, const frix_problem *twin) {
    int64_t n = frix_problem_dofs(dat), m = frix_problem_contact_dofs(dat);
    double *M = dense_of(frix_problem_M(dat)), *H = dense_of(frix_problem_H(dat));
    double *X = malloc((size_t)(n * (m + 1)) * sizeof *X); /* [M^-1 H, M^-1 f] */
    memcpy(X, H, (size_t)(n * m) * sizeof *X);
    memcpy(X + n * m, frix_problem_f(dat), (size_t)n * sizeof *X);
    dense_solve(n, M, m + 1, X);
    double *Wt = dense_of(frix_problem_W(twin)), worst = 0, scale = 0, qscale = 0, qworst = 0;
    for (int64_t j = 0; j < m; ++j)
        for (int64_t i = 0; i < m; ++i) {
            double s = 0;
            for (int64_t l = 0; l < n; ++l) s += H[l + i * n] * X[l + j * n];
            worst = fmax(worst, fabs(s - Wt[i + j * m]));
            scale = fmax(scale, fabs(Wt[i + j * m]));
        }
    for (int64_t i = 0; i < m; ++i) {
        double s = frix_problem_w(dat)[i];
        for (int64_t l = 0; l < n; ++l) s += H[l + i * n] * X[l + m * n];
        qworst = fmax(qworst, fabs(s - frix_problem_q(twin)[i]));
        qscale = fmax(qscale, fabs(frix_problem_q(twin)[i]));
    }
    ck_assert_msg(worst <= 1e-12 * scale, "%s: reduced W differs by %g (max |W| %g)", file, worst, scale);
    ck_assert_msg(qworst <= 1e-12 * fmax(qscale, scale), "%s: reduced q differs by %g (max |q| %g)",
                  file, qworst, qscale);
    free(M);
    free(H);
    free(X);
    free(Wt);
    return fmax(worst / scale, qworst / fmax(qscale, scale));
}

/* converted/ names the twin of X.dat X.from_dat.hdf5, and of X.hdf5.dat too. */
static void twin_name(const char *dat, char *out, size_t size) {
    char base[512];
    snprintf(base, sizeof base, "%s", dat);
    base[strlen(base) - 4] = '\0';
    size_t len = strlen(base);
    if (len > 5 && strcmp(base + len - 5, ".hdf5") == 0) base[len - 5] = '\0';
    snprintf(out, size, "%s/%s.from_dat.hdf5", CONVERTED_DIR, base);
}

/* ------------------------------------------------------------------ tests */

START_TEST(every_dat_file_matches_its_fclib_twin) {
    DIR *dir = opendir(DAT_DIR);
    if (!dir) {
        printf("note: skipped: no shared .dat files under %s\n", DAT_DIR);
        return;
    }
    int files = 0;
    struct dirent *e;
    while ((e = readdir(dir)) != NULL) {
        size_t len = strlen(e->d_name);
        if (len < 5 || strcmp(e->d_name + len - 4, ".dat") != 0) continue;
        char path[1024], twin_path[1024];
        snprintf(path, sizeof path, "%s/%s", DAT_DIR, e->d_name);
        twin_name(e->d_name, twin_path, sizeof twin_path);
        frix_problem *dat = NULL, *twin = NULL, *detected = NULL;
        ck_assert_msg(frix_dat_read(path, &dat) == FRIX_OK, "%s: %s", path, frix_last_error_message());
        ck_assert_msg(frix_read_problem(path, &detected) == FRIX_OK, "%s", frix_last_error_message());
        ck_assert_msg(frix_read_problem(twin_path, &twin) == FRIX_OK, "%s", frix_last_error_message());
        ck_assert_int_eq(frix_problem_get_kind(twin), FRIX_PROBLEM_LOCAL);
        int64_t nc = frix_problem_contacts(dat);
        ck_assert_int_eq(nc, frix_problem_contacts(twin));
        ck_assert_int_eq(frix_problem_contacts(detected), nc);
        expect_same_bits(e->d_name, "mu", frix_problem_mu(dat), frix_problem_mu(twin), nc);
        if (frix_problem_get_kind(dat) == FRIX_PROBLEM_LOCAL) {
            compare_local(e->d_name, dat, twin);
            printf("%s: local, %lld contacts: W, q, mu identical to the last bit\n", e->d_name,
                   (long long)nc);
        } else {
            double rel = compare_reduced(e->d_name, dat, twin);
            printf("%s: global, n = %lld, %lld contacts: reduced W, q within %.1e (relative), mu identical\n",
                   e->d_name, (long long)frix_problem_dofs(dat), (long long)nc, rel);
        }
        frix_problem_free(dat);
        frix_problem_free(twin);
        frix_problem_free(detected);
        ++files;
    }
    closedir(dir);
    ck_assert_int_ge(files, 21); /* the collection of MANIFEST.md */
}
END_TEST

/* `frix convert` writes every problem it reads as FCLIB; reading that back gives the same
 * problem, global ones staying global. */
START_TEST(cli_convert_round_trip) {
    const char *inputs[] = {DAT_DIR "/Capsules-i101-404.dat", DAT_DIR "/Rover4396.dat",
                            DAT_DIR "/GFC3D_TwoRods1.dat", DAT_DIR "/GFC3D_Example1_v2.dat",
                            FRIX_SHARED_DIR "/fclib/global/Box_Stacks-i0035-31-0.hdf5"};
    if (access(inputs[0], R_OK) != 0) {
        printf("note: skipped: no shared .dat files under %s\n", DAT_DIR);
        return;
    }
    const char *out = tmp_path("converted.hdf5");
    for (size_t k = 0; k < sizeof inputs / sizeof inputs[0]; ++k) {
        char cmd[4096];
        snprintf(cmd, sizeof cmd, "'%s' convert '%s' '%s' > /dev/null", FRIX_CLI, inputs[k], out);
        ck_assert_msg(system(cmd) == 0, "%s failed", cmd);
        frix_problem *a = NULL, *b = NULL;
        ck_assert_int_eq(frix_read_problem(inputs[k], &a), FRIX_OK);
        ck_assert_msg(frix_fclib_read(out, &b) == FRIX_OK, "%s", frix_last_error_message());
        ck_assert_int_eq(frix_problem_get_kind(a), frix_problem_get_kind(b));
        int64_t nc = frix_problem_contacts(a), m = 3 * nc, n = frix_problem_dofs(a);
        ck_assert_int_eq(frix_problem_contacts(b), nc);
        expect_same_bits(inputs[k], "mu", frix_problem_mu(a), frix_problem_mu(b), nc);
        if (frix_problem_get_kind(a) == FRIX_PROBLEM_LOCAL) {
            expect_same_matrix(inputs[k], "W", frix_problem_W(a), frix_problem_W(b));
            expect_same_bits(inputs[k], "q", frix_problem_q(a), frix_problem_q(b), m);
        } else {
            ck_assert_int_eq(frix_problem_dofs(b), n);
            expect_same_matrix(inputs[k], "M", frix_problem_M(a), frix_problem_M(b));
            expect_same_matrix(inputs[k], "H", frix_problem_H(a), frix_problem_H(b));
            expect_same_bits(inputs[k], "f", frix_problem_f(a), frix_problem_f(b), n);
            expect_same_bits(inputs[k], "w", frix_problem_w(a), frix_problem_w(b), m);
        }
        frix_problem_free(a);
        frix_problem_free(b);
    }
    char cmd[2048];
    snprintf(cmd, sizeof cmd, "'%s' convert '%s' 2> /dev/null", FRIX_CLI, inputs[0]);
    ck_assert_int_eq(WEXITSTATUS(system(cmd)), 2); /* usage: no output file */
}
END_TEST

/* The layout by hand: a global problem with a sparse-block M of unequal blocks and a dense H. */
START_TEST(small_files_by_hand) {
    const char *local = tmp_path("local.dat");
    spit_text(local, "3 1\n0 3 3\n3 3\n2 0 0  1 3 0  0 0 4\n-1 0 0\n0.5\n");
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_read_problem(local, &p), FRIX_OK);
    double W[9];
    ck_assert_int_eq(frix_matrix_diagonal_block(frix_problem_W(p), 0, W), FRIX_OK);
    ck_assert(W[0] == 2 && W[1] == 0 && W[3] == 1 && W[4] == 3 && W[8] == 4); /* column-major */
    ck_assert(frix_problem_mu(p)[0] == 0.5 && frix_problem_q(p)[0] == -1);
    frix_problem_free(p);

    const char *global = tmp_path("global.dat");
    spit_text(global,
               "3 1\n"
               "1 4 4  2 2 2  1 4  1 4  3 2  0 1 2  0 1\n"      /* M: 1x1 and 3x3 blocks */
               "0  5\n"                                          /* block 0 */
               "1  1 0 0  7 1 0  0 0 1\n"                        /* block 1, column-major */
               "0 4 3  4 3  0 1 0 0  0 0 1 0  0 0 0 1\n"        /* H dense 4x3 */
               "1 2 3 4\n0 0 0\n0.3\n1\n");
    ck_assert_int_eq(frix_read_problem(global, &p), FRIX_OK);
    ck_assert_int_eq(frix_problem_get_kind(p), FRIX_PROBLEM_GLOBAL);
    ck_assert_int_eq(frix_problem_dofs(p), 4);
    double x[4] = {0, 1, 0, 0}, y[4];
    ck_assert_int_eq(frix_matrix_gemv(frix_problem_M(p), 1.0, x, 0.0, y), FRIX_OK);
    ck_assert(y[0] == 0 && y[1] == 1 && y[2] == 0 && y[3] == 0);
    x[1] = 0, x[2] = 1;
    ck_assert_int_eq(frix_matrix_gemv(frix_problem_M(p), 1.0, x, 0.0, y), FRIX_OK);
    ck_assert(y[1] == 7 && y[2] == 1);
    ck_assert(frix_problem_f(p)[3] == 4 && frix_problem_mu(p)[0] == 0.3);
    frix_problem_free(p);
}
END_TEST

static void expect_error(const char *name, const char *text, frix_error code, const char *needle) {
    const char *path = tmp_path(name);
    spit_text(path, text);
    frix_problem *p = (frix_problem *)0x1;
    frix_error err = frix_read_problem(path, &p);
    const char *msg = frix_last_error_message();
    ck_assert_msg(err == code, "%s: expected %d, got %d (%s)", name, code, err, msg);
    ck_assert_ptr_null(p);
    ck_assert_msg(strstr(msg, path) != NULL, "%s: message does not name the file: %s", name, msg);
    ck_assert_msg(strstr(msg, needle) != NULL, "%s: message lacks '%s': %s", name, needle, msg);
}

START_TEST(malformed_files) {
    expect_error("2d.dat", "2 1 0 2 2 2 2 1 0 0 1 -1 0 0.3\n", FRIX_ERR_UNSUPPORTED, "dimension 2");
    expect_error("short.dat", "3 1\n0 3 3\n3 3\n1 0 0 0 1 0\n", FRIX_ERR_FORMAT, "ends early");
    expect_error("word.dat", "3 1\n0 3 3\n3 3\n1 0 0 0 x 0 0 0 1\n-1 0 0 0.3\n", FRIX_ERR_FORMAT,
                 "line 4: expected a number (dense W or M), found 'x'");
    expect_error("nan.dat", "3 1\n0 3 3\n3 3\n1 0 0 0 nan 0 0 0 1\n-1 0 0 0.3\n", FRIX_ERR_NOT_FINITE,
                 "not finite");
    expect_error("sizes.dat", "3 1\n0 3 3\n3 4\n", FRIX_ERR_FORMAT, "sizes of dense");
    expect_error("storage2.dat", "3 1\n2 3 3\n", FRIX_ERR_UNSUPPORTED, "storage type 2");
    expect_error("storage7.dat", "3 1\n7 3 3\n", FRIX_ERR_FORMAT, "storage type of W or M is 7");
    expect_error("mu.dat", "3 1\n0 3 3 3 3 1 0 0 0 1 0 0 0 1\n-1 0 0\n-0.3\n", FRIX_ERR_FORMAT,
                 "mu[0]");
    expect_error("blocknum.dat", "3 1\n1 3 3 1 1 1 3 3 2 1 0 1 0\n5 1 0 0 0 1 0 0 0 1\n-1 0 0 0.3\n",
                 FRIX_ERR_FORMAT, "block number");
    /* Sizes no file of that length can back (the fuzzer's: 0 x 1443521715 made it allocate
     * 3.8 GB for an empty matrix): refused before anything of that size is allocated. */
    expect_error("wide.dat", "3 1\n0 0 1443521715\n0 1443521715\n-1 0 0 0.3\n", FRIX_ERR_FORMAT,
                 "0 x 1443521715, not square");
    expect_error("huge.dat", "3 1\n1 1443521715 1443521715 0 0 0 1 0\n-1 0 0 0.3\n", FRIX_ERR_FORMAT,
                 "W or M and the vector after it needs 1443521715 more numbers");
    expect_error("empty.dat", "", FRIX_ERR_FORMAT, "ends where the dimension");
    expect_error("text.txt", "hello\n", FRIX_ERR_FORMAT, "found 'hello'");
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_read_problem(tmp_path("missing.dat"), &p), FRIX_ERR_IO);
    ck_assert_int_eq(frix_dat_read(NULL, &p), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_read_problem("x", NULL), FRIX_ERR_INVALID_ARGUMENT);
}
END_TEST

/* An FCLIB file written by frix is detected as HDF5 and read back. */
START_TEST(read_problem_detects_fclib) {
    double Wd[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, q[3] = {-1, 0.2, 0}, mu[1] = {0.4};
    frix_matrix *W = NULL;
    frix_problem *p = NULL, *back = NULL;
    ck_assert_int_eq(frix_matrix_from_dense(3, 3, Wd, 3, &W), FRIX_OK);
    ck_assert_int_eq(frix_problem_local(W, q, mu, 1, &p), FRIX_OK);
    const char *path = tmp_path("one.hdf5");
    ck_assert_int_eq(frix_fclib_write(path, p, NULL, NULL, NULL, 0, NULL, NULL, NULL), FRIX_OK);
    ck_assert_int_eq(frix_read_problem(path, &back), FRIX_OK);
    ck_assert(frix_problem_q(back)[1] == 0.2 && frix_problem_mu(back)[0] == 0.4);
    frix_problem_free(back);
    frix_problem_free(p);
    frix_matrix_free(W);
}
END_TEST

int main(void) {
    Suite *s = suite_create("dat");
    TCase *tc = tcase_create("dat");
    tcase_add_test(tc, every_dat_file_matches_its_fclib_twin);
    tcase_add_test(tc, small_files_by_hand);
    tcase_add_test(tc, malformed_files);
    tcase_add_test(tc, read_problem_detects_fclib);
    tcase_add_test(tc, cli_convert_round_trip);
    suite_add_tcase(s, tc);
    return frix_run_suite(s);
}
