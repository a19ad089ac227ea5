/* FCLIB files: every shared problem file reads (with the sizes MANIFEST.md gives), write and
 * read back bit-identical, solutions and guesses, malformed files (each with its error code
 * and a message naming the file and dataset), HDF5 kept silent, and failed writes that
 * leave an existing file untouched.
 * Malformed files are built here with the HDF5 C API. */
#define _POSIX_C_SOURCE 200809L /* mkdtemp, dup2, setrlimit under strict C99 */
#include <frix/frix.h>

#include <hdf5.h>

#include <dirent.h>
#include <fcntl.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include "check_main.h"
#include "cli_runner.h"

#define FCLIB_DIR FRIX_SHARED_DIR "/fclib"
#define LARGE_DIR FRIX_SHARED_DIR "/fclib-large"
#define LOCAL_TEST FCLIB_DIR "/local/local_problem_test.hdf5"
#define CAPSULES FCLIB_DIR "/local/Capsules-i125-1213.hdf5"
#define BOX_GLOBAL FCLIB_DIR "/global/Box_Stacks-i0035-31-0.hdf5"
#define BOX_REDUCED FCLIB_DIR "/converted/Box_Stacks-i0035-31-0.reduced.hdf5"
#define ROLLING FCLIB_DIR "/other/Chute-ndof-768-nc-4-3.hdf5"

/* ------------------------------------------------------------------ helpers */

static int have_shared(void) { return access(LOCAL_TEST, R_OK) == 0; }

/* Tests that need the shared collection skip (with a note) rather than fail without it. */
#define REQUIRE_SHARED()                                                                 \
    do {                                                                                 \
        if (!have_shared()) {                                                            \
            printf("note: %s skipped: no shared FCLIB data under %s\n", __func__,        \
                   FRIX_SHARED_DIR);                                                     \
            return;                                                                      \
        }                                                                                \
    } while (0)

static const char *tmp_path(const char *name) {
    static char buf[8][1024];
    static int next = 0;
    char *out = buf[next++ % 8];
    snprintf(out, sizeof buf[0], "%s/fclib_%s", FRIX_TEST_TMPDIR, name);
    return out;
}

static frix_problem *read_ok(const char *path) {
    frix_problem *p = NULL;
    frix_error err = frix_fclib_read(path, &p);
    ck_assert_msg(err == FRIX_OK, "reading %s: %d %s", path, err, frix_last_error_message());
    ck_assert_ptr_nonnull(p);
    return p;
}

/* Reading `path` fails with `code`, and the message names the file and contains `needle`. */
static void expect_read_error(const char *path, frix_error code, const char *needle) {
    frix_problem *p = (frix_problem *)0x1;
    frix_error err = frix_fclib_read(path, &p);
    const char *msg = frix_last_error_message();
    ck_assert_msg(err == code, "%s: expected error %d, got %d (%s)", path, code, err, msg);
    ck_assert_ptr_null(p);
    ck_assert_msg(strstr(msg, path) != NULL, "message does not name the file: %s", msg);
    if (needle != NULL)
        ck_assert_msg(strstr(msg, needle) != NULL, "message lacks '%s': %s", needle, msg);
}

typedef struct {
    int64_t rows, cols, nnz;
    int64_t *p, *i;
    double *x;
} csc;

static csc to_csc(const frix_matrix *A) {
    csc c;
    c.rows = frix_matrix_rows(A);
    c.cols = frix_matrix_cols(A);
    ck_assert_int_eq(frix_matrix_to_csc(A, &c.nnz, NULL, NULL, NULL), FRIX_OK);
    c.p = malloc(sizeof(int64_t) * (size_t)(c.cols + 1));
    c.i = malloc(sizeof(int64_t) * (size_t)(c.nnz + 1));
    c.x = malloc(sizeof(double) * (size_t)(c.nnz + 1));
    ck_assert_int_eq(frix_matrix_to_csc(A, &c.nnz, c.p, c.i, c.x), FRIX_OK);
    return c;
}

static void csc_free(csc *c) {
    free(c->p);
    free(c->i);
    free(c->x);
}

static double csc_entry(const csc *c, int64_t row, int64_t col) {
    for (int64_t k = c->p[col]; k < c->p[col + 1]; ++k)
        if (c->i[k] == row) return c->x[k];
    return 0.0;
}

static void assert_same_matrix(const frix_matrix *A, const frix_matrix *B) {
    csc a = to_csc(A), b = to_csc(B);
    ck_assert_int_eq(a.rows, b.rows);
    ck_assert_int_eq(a.cols, b.cols);
    ck_assert_int_eq(a.nnz, b.nnz);
    ck_assert(memcmp(a.p, b.p, sizeof(int64_t) * (size_t)(a.cols + 1)) == 0);
    ck_assert(memcmp(a.i, b.i, sizeof(int64_t) * (size_t)a.nnz) == 0);
    ck_assert(memcmp(a.x, b.x, sizeof(double) * (size_t)a.nnz) == 0);
    csc_free(&a);
    csc_free(&b);
}

static void assert_same_vector(const double *a, const double *b, int64_t n) {
    ck_assert(n == 0 || memcmp(a, b, sizeof(double) * (size_t)n) == 0);
}

static void assert_same_problem(const frix_problem *a, const frix_problem *b) {
    ck_assert_int_eq(frix_problem_get_kind(a), frix_problem_get_kind(b));
    ck_assert_int_eq(frix_problem_contacts(a), frix_problem_contacts(b));
    ck_assert_int_eq(frix_problem_dofs(a), frix_problem_dofs(b));
    const int64_t m = frix_problem_contact_dofs(a), n = frix_problem_dofs(a);
    assert_same_vector(frix_problem_mu(a), frix_problem_mu(b), frix_problem_contacts(a));
    ck_assert_str_eq(frix_problem_title(a), frix_problem_title(b));
    if (frix_problem_get_kind(a) == FRIX_PROBLEM_LOCAL) {
        assert_same_matrix(frix_problem_W(a), frix_problem_W(b));
        assert_same_vector(frix_problem_q(a), frix_problem_q(b), m);
    } else {
        assert_same_matrix(frix_problem_M(a), frix_problem_M(b));
        assert_same_matrix(frix_problem_H(a), frix_problem_H(b));
        assert_same_vector(frix_problem_f(a), frix_problem_f(b), n);
        assert_same_vector(frix_problem_w(a), frix_problem_w(b), m);
    }
}

/* Whole file content, for byte-identity checks. */
static char *slurp_sized(const char *path, long *size) {
    FILE *f = fopen(path, "rb");
    ck_assert_msg(f != NULL, "cannot open %s", path);
    fseek(f, 0, SEEK_END);
    *size = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *data = malloc((size_t)*size + 1);
    ck_assert_int_eq(fread(data, 1, (size_t)*size, f), (size_t)*size);
    fclose(f);
    return data;
}

static void spit(const char *path, const char *data, long size) {
    FILE *f = fopen(path, "wb");
    ck_assert_msg(f != NULL, "cannot create %s", path);
    ck_assert_int_eq(fwrite(data, 1, (size_t)size, f), (size_t)size);
    fclose(f);
}

/* Files in `dir` whose name starts with `prefix` (leftover temporary files). */
static int count_prefixed(const char *dir, const char *prefix) {
    DIR *d = opendir(dir);
    ck_assert_ptr_nonnull(d);
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)) != NULL)
        if (strncmp(e->d_name, prefix, strlen(prefix)) == 0) ++n;
    closedir(d);
    return n;
}

/* A 2-contact local problem built in memory (no shared data needed). */
typedef struct {
    frix_matrix *W;
    double q[6], mu[2];
    frix_problem *p;
} small_local;

static void small_local_make(small_local *s, const char *title) {
    double a[36] = {0};
    for (int k = 0; k < 6; ++k) a[k * 6 + k] = 2.0 + k;
    a[0 * 6 + 3] = a[3 * 6 + 0] = 0.5; /* a coupling between the contacts */
    ck_assert_int_eq(frix_matrix_from_dense(6, 6, a, 6, &s->W), FRIX_OK);
    const double q[6] = {-1, 0.25, 0, -2, 0, 0.125}, mu[2] = {0.3, 0.5};
    memcpy(s->q, q, sizeof q);
    memcpy(s->mu, mu, sizeof mu);
    ck_assert_int_eq(frix_problem_local(s->W, s->q, s->mu, 2, &s->p), FRIX_OK);
    ck_assert_int_eq(frix_problem_set_title(s->p, title), FRIX_OK);
}

static void small_local_free(small_local *s) {
    frix_problem_free(s->p);
    frix_matrix_free(s->W);
}

/* ------------------------------------------------- crafted (malformed) files */

typedef struct {
    int int64; /* integers stored as int64 instead of FCLIB's int32 */
    long long spacedim, m, n, nz, nzmax;
    const long long *p, *i;
    size_t np, ni;
    const double *x, *q, *mu;
    size_t nx, nq, nmu;
    const char *vlen_title; /* title as a variable-length string, NULL for none */
} crafted;

/* A valid base: W = 6x6 CSR with diagonal 2..7 and W(0,3) = 0.5, two contacts. */
static const long long base_p[] = {0, 2, 3, 4, 5, 6, 7};
static const long long base_i[] = {0, 3, 1, 2, 3, 4, 5};
static const double base_x[] = {2, 0.5, 3, 4, 5, 6, 7};
static const double base_q[] = {-1, 0, 0, -1, 0, 0};
static const double base_mu[] = {0.3, 0.5};
/* The base's W as CSC (column pointers, row indices). */
static const long long csc_p[] = {0, 1, 2, 3, 5, 6, 7};
static const long long csc_i[] = {0, 1, 2, 0, 3, 4, 5};
static const double csc_x[] = {2, 3, 4, 0.5, 5, 6, 7};

static crafted crafted_base(void) {
    crafted c;
    memset(&c, 0, sizeof c);
    c.spacedim = 3;
    c.m = c.n = 6;
    c.nz = -2;
    c.nzmax = 7;
    c.p = base_p;
    c.np = 7;
    c.i = base_i;
    c.ni = 7;
    c.x = base_x;
    c.nx = 7;
    c.q = base_q;
    c.nq = 6;
    c.mu = base_mu;
    c.nmu = 2;
    return c;
}

static void put_ints(hid_t loc, const char *name, const long long *v, size_t n, int int64) {
    hsize_t dim = n;
    hid_t sp = H5Screate_simple(1, &dim, NULL);
    hid_t ds = H5Dcreate2(loc, name, int64 ? H5T_STD_I64LE : H5T_STD_I32LE, sp, H5P_DEFAULT,
                          H5P_DEFAULT, H5P_DEFAULT);
    ck_assert(ds >= 0);
    if (n > 0) ck_assert(H5Dwrite(ds, H5T_NATIVE_LLONG, H5S_ALL, H5S_ALL, H5P_DEFAULT, v) >= 0);
    H5Dclose(ds);
    H5Sclose(sp);
}

static void put_int(hid_t loc, const char *name, long long v, int int64) {
    put_ints(loc, name, &v, 1, int64);
}

static void put_doubles(hid_t loc, const char *name, const double *v, size_t n) {
    hsize_t dim = n;
    hid_t sp = H5Screate_simple(1, &dim, NULL);
    hid_t ds = H5Dcreate2(loc, name, H5T_IEEE_F64LE, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    ck_assert(ds >= 0);
    if (n > 0) ck_assert(H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v) >= 0);
    H5Dclose(ds);
    H5Sclose(sp);
}

static void write_crafted(const char *path, const crafted *c) {
    hid_t f = H5Fcreate(path, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    ck_assert_msg(f >= 0, "cannot create %s", path);
    hid_t g = H5Gcreate2(f, "/fclib_local", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    put_int(g, "spacedim", c->spacedim, c->int64);
    hid_t w = H5Gcreate2(g, "W", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    put_int(w, "m", c->m, c->int64);
    put_int(w, "n", c->n, c->int64);
    put_int(w, "nz", c->nz, c->int64);
    put_int(w, "nzmax", c->nzmax, c->int64);
    put_ints(w, "p", c->p, c->np, c->int64);
    put_ints(w, "i", c->i, c->ni, c->int64);
    put_doubles(w, "x", c->x, c->nx);
    H5Gclose(w);
    hid_t v = H5Gcreate2(g, "vectors", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    if (c->q != NULL) put_doubles(v, "q", c->q, c->nq);
    put_doubles(v, "mu", c->mu, c->nmu);
    H5Gclose(v);
    if (c->vlen_title != NULL) {
        hid_t info = H5Gcreate2(g, "info", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
        hid_t t = H5Tcopy(H5T_C_S1);
        H5Tset_size(t, H5T_VARIABLE);
        H5Tset_cset(t, H5T_CSET_UTF8);
        hid_t sp = H5Screate(H5S_SCALAR);
        hid_t ds = H5Dcreate2(info, "title", t, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
        ck_assert(H5Dwrite(ds, t, H5S_ALL, H5S_ALL, H5P_DEFAULT, &c->vlen_title) >= 0);
        H5Dclose(ds);
        H5Sclose(sp);
        H5Tclose(t);
        H5Gclose(info);
    }
    H5Gclose(g);
    ck_assert(H5Fclose(f) >= 0);
}

/* ------------------------------------------------------------------ tests */

/* Every *.hdf5 of local/, converted/ and global/ reads, with the kind its directory says and
 * consistent sizes. */
START_TEST(test_read_every_shared_file) {
    REQUIRE_SHARED();
    const char *dirs[3] = {"local", "converted", "global"};
    const int at_least[3] = {3, 25, 4}; /* the files MANIFEST.md lists */
    for (int d = 0; d < 3; ++d) {
        char dirpath[1024];
        snprintf(dirpath, sizeof dirpath, "%s/%s", FCLIB_DIR, dirs[d]);
        DIR *dir = opendir(dirpath);
        ck_assert_ptr_nonnull(dir);
        int count = 0;
        struct dirent *e;
        while ((e = readdir(dir)) != NULL) {
            const size_t len = strlen(e->d_name);
            if (len < 5 || strcmp(e->d_name + len - 5, ".hdf5") != 0) continue;
            char path[2048];
            snprintf(path, sizeof path, "%s/%s", dirpath, e->d_name);
            frix_problem *p = read_ok(path);
            const int global = strcmp(dirs[d], "global") == 0;
            ck_assert_int_eq(frix_problem_get_kind(p),
                             global ? FRIX_PROBLEM_GLOBAL : FRIX_PROBLEM_LOCAL);
            const int64_t nc = frix_problem_contacts(p);
            ck_assert_int_gt(nc, 0);
            const frix_matrix *A = global ? frix_problem_H(p) : frix_problem_W(p);
            ck_assert_int_eq(frix_matrix_cols(A), 3 * nc);
            if (global) ck_assert_int_eq(frix_matrix_rows(A), frix_problem_dofs(p));
            for (int64_t k = 0; k < nc; ++k) ck_assert(frix_problem_mu(p)[k] >= 0);
            ck_assert(strlen(frix_problem_title(p)) > 0);
            frix_problem_free(p);
            ++count;
        }
        closedir(dir);
        printf("fclib/%s: %d files read\n", dirs[d], count);
        ck_assert_int_ge(count, at_least[d]);
    }
}
END_TEST

/* The CSC files of fclib-large, each with the contact count its name carries. */
START_TEST(test_read_large_files) {
    DIR *dir = opendir(LARGE_DIR);
    if (dir == NULL) {
        printf("note: %s skipped: no %s\n", __func__, LARGE_DIR);
        return;
    }
    int count = 0;
    struct dirent *e;
    while ((e = readdir(dir)) != NULL) {
        const char *nc_tag = strstr(e->d_name, "-nc");
        const size_t len = strlen(e->d_name);
        if (nc_tag == NULL || len < 5 || strcmp(e->d_name + len - 5, ".hdf5") != 0) continue;
        char path[2048];
        snprintf(path, sizeof path, "%s/%s", LARGE_DIR, e->d_name);
        frix_problem *p = read_ok(path);
        ck_assert_int_eq(frix_problem_get_kind(p), FRIX_PROBLEM_LOCAL);
        ck_assert_int_eq(frix_problem_contacts(p), atoll(nc_tag + 3));
        frix_problem_free(p);
        ++count;
    }
    closedir(dir);
    printf("fclib-large: %d files read\n", count);
    ck_assert_int_ge(count, 1);
}
END_TEST

static void check_local(const char *path, int64_t nc, int64_t nnz, double mu, const char *title) {
    frix_problem *p = read_ok(path);
    ck_assert_int_eq(frix_problem_get_kind(p), FRIX_PROBLEM_LOCAL);
    ck_assert_int_eq(frix_problem_contacts(p), nc);
    const frix_matrix *W = frix_problem_W(p);
    ck_assert_int_eq(frix_matrix_rows(W), 3 * nc);
    ck_assert_int_eq(frix_matrix_cols(W), 3 * nc);
    int64_t stored = 0;
    ck_assert_int_eq(frix_matrix_to_csc(W, &stored, NULL, NULL, NULL), FRIX_OK);
    ck_assert_int_eq(stored, nnz);
    for (int64_t k = 0; k < nc; ++k) ck_assert_double_eq(frix_problem_mu(p)[k], mu);
    ck_assert_str_eq(frix_problem_title(p), title);
    frix_problem_free(p);
}

/* Sizes against MANIFEST.md: CSR (local/), CSC (fclib-large) and triplet (global/) files. */
START_TEST(test_manifest_values) {
    REQUIRE_SHARED();
    check_local(CAPSULES, 286, 11772, 0.7, "Capsules");
    check_local(LOCAL_TEST, 48, 4896, 0.7, "Boxes Stack");
    check_local(BOX_REDUCED, 31, 279, 0.3, "Box_stacks");
    const char *spheres = LARGE_DIR "/Spheres-n400-seed2-s00140-nc1165.hdf5";
    if (access(spheres, R_OK) == 0) check_local(spheres, 1165, 95121, 0.3, "SpheresInABox");

    frix_problem *g = read_ok(BOX_GLOBAL);
    ck_assert_int_eq(frix_problem_get_kind(g), FRIX_PROBLEM_GLOBAL);
    ck_assert_int_eq(frix_problem_contacts(g), 31);
    ck_assert_int_eq(frix_problem_dofs(g), 450);
    ck_assert_int_eq(frix_matrix_rows(frix_problem_H(g)), 450);
    ck_assert_int_eq(frix_matrix_cols(frix_problem_H(g)), 93);
    int64_t nnz = 0;
    ck_assert_int_eq(frix_matrix_to_csc(frix_problem_M(g), &nnz, NULL, NULL, NULL), FRIX_OK);
    ck_assert_int_eq(nnz, 450); /* diagonal M */
    ck_assert_str_eq(frix_problem_title(g), "Box_stacks");
    frix_problem_free(g);
}
END_TEST

/* The triplet convention (i = rows, p = columns) checked on the data: the global Box_Stacks
 * problem reduced by hand (M is diagonal) equals the reduced file libfclib wrote,
 * W = H^T M^-1 H and q = H^T M^-1 f + w. */
START_TEST(test_triplet_orientation_by_reduction) {
    REQUIRE_SHARED();
    frix_problem *g = read_ok(BOX_GLOBAL);
    frix_problem *l = read_ok(BOX_REDUCED);
    const int64_t n = frix_problem_dofs(g), m = frix_problem_contact_dofs(g);
    ck_assert_int_eq(frix_problem_contact_dofs(l), m);
    csc M = to_csc(frix_problem_M(g));
    csc W = to_csc(frix_problem_W(l));
    double *diag = malloc(sizeof(double) * (size_t)n), *y = malloc(sizeof(double) * (size_t)n);
    double *col = malloc(sizeof(double) * (size_t)m), *e = calloc((size_t)m, sizeof(double));
    for (int64_t k = 0; k < n; ++k) diag[k] = csc_entry(&M, k, k);
    double worst = 0, scale = 0;
    for (int64_t j = 0; j < m; ++j) {
        e[j] = 1.0;
        ck_assert_int_eq(frix_matrix_gemv(frix_problem_H(g), 1.0, e, 0.0, y), FRIX_OK);
        for (int64_t k = 0; k < n; ++k) y[k] /= diag[k];
        ck_assert_int_eq(frix_matrix_gemv_transposed(frix_problem_H(g), 1.0, y, 0.0, col),
                         FRIX_OK);
        for (int64_t r = 0; r < m; ++r) {
            worst = fmax(worst, fabs(col[r] - csc_entry(&W, r, j)));
            scale = fmax(scale, fabs(col[r]));
        }
        e[j] = 0.0;
    }
    ck_assert_msg(worst <= 1e-10 * scale, "W differs by %g (scale %g)", worst, scale);

    for (int64_t k = 0; k < n; ++k) y[k] = frix_problem_f(g)[k] / diag[k];
    ck_assert_int_eq(frix_matrix_gemv_transposed(frix_problem_H(g), 1.0, y, 0.0, col), FRIX_OK);
    for (int64_t r = 0; r < m; ++r)
        ck_assert(fabs(col[r] + frix_problem_w(g)[r] - frix_problem_q(l)[r]) <=
                  1e-10 * (1 + fabs(frix_problem_q(l)[r])));
    free(diag);
    free(y);
    free(col);
    free(e);
    csc_free(&M);
    csc_free(&W);
    frix_problem_free(g);
    frix_problem_free(l);
}
END_TEST

/* Storage variants the real files do not all use: int64 integers, triplets with duplicates
 * (summed) and an off-diagonal entry (row from i, column from p), CSC, and a variable-length
 * non-UTF-8 title kept as bytes. */
START_TEST(test_read_storage_variants) {
    const char *path = tmp_path("variants.hdf5");
    crafted c = crafted_base();
    c.int64 = 1;
    c.nz = 8;
    c.nzmax = 10;
    static const long long rows[] = {0, 1, 2, 3, 4, 5, 0, 0};
    static const long long cols[] = {0, 1, 2, 3, 4, 5, 0, 3};
    static const double vals[] = {1.5, 3, 4, 5, 6, 7, 0.5, 0.25};
    c.i = rows;
    c.p = cols;
    c.x = vals;
    c.ni = c.np = c.nx = 8;
    c.vlen_title = "\xff\xfe title";
    write_crafted(path, &c);
    frix_problem *p = read_ok(path);
    csc W = to_csc(frix_problem_W(p));
    ck_assert_double_eq(csc_entry(&W, 0, 0), 2.0); /* 1.5 + 0.5 */
    ck_assert_double_eq(csc_entry(&W, 0, 3), 0.25);
    ck_assert_double_eq(csc_entry(&W, 3, 0), 0.0);
    ck_assert_double_eq(csc_entry(&W, 5, 5), 7.0);
    csc_free(&W);
    ck_assert_str_eq(frix_problem_title(p), "\xff\xfe title");
    frix_problem_free(p);

    /* The same matrix as CSC (column pointers, row indices) and as the base CSR. */
    c = crafted_base();
    c.nz = -1;
    c.p = csc_p;
    c.i = csc_i;
    c.x = csc_x;
    write_crafted(path, &c);
    frix_problem *a = read_ok(path);
    c = crafted_base();
    write_crafted(path, &c);
    frix_problem *b = read_ok(path);
    assert_same_matrix(frix_problem_W(a), frix_problem_W(b));
    W = to_csc(frix_problem_W(b));
    ck_assert_double_eq(csc_entry(&W, 0, 3), 0.5);
    ck_assert_double_eq(csc_entry(&W, 3, 0), 0.0);
    csc_free(&W);
    frix_problem_free(a);
    frix_problem_free(b);
}
END_TEST

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

START_TEST(test_unreadable_files) {
    expect_read_error(tmp_path("does_not_exist.hdf5"), FRIX_ERR_IO, "No such file");
    expect_read_error(FRIX_TEST_TMPDIR, FRIX_ERR_IO, "directory");

    const char *text = tmp_path("text.hdf5");
    spit(text, "this is not HDF5\n", 17);
    expect_read_error(text, FRIX_ERR_IO, "not an HDF5 file");

    /* Version 0 superblocks found by fuzz_read_problem, refused before HDF5 opens them: a
     * reserved byte set, then the same with the reserved byte clear but a group B-tree rank K
     * of 65525, from which HDF5 1.10 sizes buffers of gigabytes before it fails. */
    static const unsigned char corrupt[49] = {
        0x89, 0x48, 0x44, 0x46, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x00, 0x00, 0x08, 0x08, 0xb8, 0xf5,
        0xff, 0xff, 0xff, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xff, 0xff,
        0x09, 0x00, 0x00, 0xff, 0xff, 0xff, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x08};
    const char *bad = tmp_path("corrupt_superblock.hdf5");
    spit(bad, (const char *)corrupt, (long)sizeof corrupt);
    expect_read_error(bad, FRIX_ERR_FORMAT, "corrupt HDF5 superblock");
    unsigned char bad_rank[49];
    memcpy(bad_rank, corrupt, sizeof bad_rank);
    bad_rank[15] = 0x00;
    spit(bad, (const char *)bad_rank, (long)sizeof bad_rank);
    expect_read_error(bad, FRIX_ERR_FORMAT, "corrupt HDF5 superblock");
    bad_rank[16] = 0x04; /* HDF5's default ranks (4 and 16) pass the check: HDF5 then finds the file unreadable */
    bad_rank[17] = 0x00;
    bad_rank[18] = 0x10;
    bad_rank[19] = 0x00;
    spit(bad, (const char *)bad_rank, (long)sizeof bad_rank);
    expect_read_error(bad, FRIX_ERR_IO, "as an HDF5 file");

    /* A version 0 superblock (sizes 8 and 8, HDF5's ranks, end of file 128) whose driver
     * information block at 96 declares 0xff000000 bytes: HDF5 1.10 allocates that much before
     * it finds the file short (fuzz_read_problem). Then the same block placed past the end. */
    unsigned char driver[128] = {0x89, 0x48, 0x44, 0x46, 0x0d, 0x0a, 0x1a, 0x0a, 0, 0, 0, 0, 0, 8, 8, 0, 4, 0, 16, 0};
    memset(driver + 32, 0xff, 8); /* no free-space index */
    driver[40] = 128;             /* end of file */
    driver[48] = 96;              /* driver information block */
    driver[96 + 7] = 0xff;        /* its length, little-endian 0xff000000 */
    memcpy(driver + 96 + 8, "NCSAmult", 8);
    spit(bad, (const char *)driver, (long)sizeof driver);
    expect_read_error(bad, FRIX_ERR_FORMAT, "driver information block is longer than the file");
    driver[48] = 0;
    driver[49] = 0x10; /* at 4096 */
    spit(bad, (const char *)driver, (long)sizeof driver);
    expect_read_error(bad, FRIX_ERR_FORMAT, "driver information block lies beyond the end of the file");

    frix_problem *p = (frix_problem *)0x1;
    ck_assert_int_eq(frix_fclib_read(NULL, &p), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_fclib_read(text, NULL), FRIX_ERR_INVALID_ARGUMENT);
    int64_t count;
    ck_assert_int_eq(frix_fclib_guess_count(text, &count), FRIX_ERR_IO);
    ck_assert_int_eq(frix_fclib_guess_count(text, NULL), FRIX_ERR_INVALID_ARGUMENT);

    if (have_shared()) {
        long size = 0;
        char *data = slurp_sized(LOCAL_TEST, &size);
        const char *half = tmp_path("truncated.hdf5");
        spit(half, data, size / 2);
        free(data);
        expect_read_error(half, FRIX_ERR_IO, "truncated");
    }
}
END_TEST

START_TEST(test_malformed_content) {
    const char *path = tmp_path("malformed.hdf5");
    crafted c;

    /* The base is valid (so each failure below is the one change). */
    c = crafted_base();
    write_crafted(path, &c);
    frix_problem_free(read_ok(path));

    /* Missing q: written by frix, then the dataset unlinked. */
    small_local s;
    small_local_make(&s, "missing q");
    ck_assert_int_eq(frix_fclib_write(path, s.p, NULL, NULL, NULL, 0, NULL, NULL, NULL), FRIX_OK);
    small_local_free(&s);
    hid_t f = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
    ck_assert(f >= 0);
    ck_assert(H5Ldelete(f, "/fclib_local/vectors/q", H5P_DEFAULT) >= 0);
    H5Fclose(f);
    expect_read_error(path, FRIX_ERR_FORMAT, "/fclib_local/vectors/q is missing");

    c = crafted_base();
    c.nq = 5;
    write_crafted(path, &c);
    expect_read_error(path, FRIX_ERR_FORMAT, "/fclib_local/vectors/q has 5 entries, expected 6");

    c = crafted_base();
    c.nmu = 1;
    write_crafted(path, &c);
    expect_read_error(path, FRIX_ERR_FORMAT, "/fclib_local/vectors/mu");

    static const long long bad_p[] = {0, 2, 1, 4, 5, 6, 7};
    c = crafted_base();
    c.p = bad_p;
    write_crafted(path, &c);
    expect_read_error(path, FRIX_ERR_FORMAT, "/fclib_local/W/p decreases");

    static const long long bad_i[] = {0, 3, 1, 2, 3, 4, 6};
    c = crafted_base();
    c.i = bad_i;
    write_crafted(path, &c);
    expect_read_error(path, FRIX_ERR_FORMAT, "/fclib_local/W/i");

    c = crafted_base();
    c.n = 9;
    write_crafted(path, &c);
    expect_read_error(path, FRIX_ERR_FORMAT, "expected square");

    c = crafted_base();
    c.spacedim = 2;
    write_crafted(path, &c);
    expect_read_error(path, FRIX_ERR_UNSUPPORTED, "spacedim");

    /* m not a multiple of spacedim. */
    static const double q4[] = {-1, 0, 0, -1};
    static const long long p4[] = {0, 1, 2, 3, 4};
    c = crafted_base();
    c.m = c.n = 4;
    c.p = p4;
    c.np = 5;
    c.q = q4;
    c.nq = 4;
    write_crafted(path, &c);
    expect_read_error(path, FRIX_ERR_FORMAT, "multiple of spacedim");

    /* Huge declared sizes with small arrays: refused before anything that size exists. */
    c = crafted_base();
    c.int64 = 1;
    c.m = c.n = 3LL << 38;
    write_crafted(path, &c);
    expect_read_error(path, FRIX_ERR_FORMAT, "/fclib_local/vectors/q");
    c = crafted_base();
    c.int64 = 1;
    c.nz = 1LL << 40;
    c.nzmax = 1LL << 40;
    write_crafted(path, &c);
    expect_read_error(path, FRIX_ERR_FORMAT, "triplet count");
    c = crafted_base();
    c.nz = 7;
    c.nzmax = 5; /* fewer than the nz triplets */
    write_crafted(path, &c);
    expect_read_error(path, FRIX_ERR_FORMAT, "nzmax");
    c = crafted_base();
    c.nzmax = 3; /* fewer than the 7 entries p says */
    write_crafted(path, &c);
    expect_read_error(path, FRIX_ERR_FORMAT, "nzmax");

    c = crafted_base();
    c.nz = -3;
    write_crafted(path, &c);
    expect_read_error(path, FRIX_ERR_FORMAT, "/fclib_local/W/nz");

    static const double q_nan[] = {-1, NAN, 0, -1, 0, 0};
    c = crafted_base();
    c.q = q_nan;
    write_crafted(path, &c);
    expect_read_error(path, FRIX_ERR_FORMAT, "/fclib_local/vectors/q: entry 1");

    static const double mu_neg[] = {0.3, -0.5};
    c = crafted_base();
    c.mu = mu_neg;
    write_crafted(path, &c);
    expect_read_error(path, FRIX_ERR_FORMAT, "/fclib_local/vectors/mu: entry 1");

    /* A dataset whose extent is forged far beyond what the file stores. */
    c = crafted_base();
    c.int64 = 1;
    c.m = c.n = 3LL << 31;
    c.q = NULL;
    write_crafted(path, &c);
    f = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
    hsize_t dim = 3ULL << 31;
    hid_t sp = H5Screate_simple(1, &dim, NULL);
    hid_t ds = H5Dcreate2(f, "/fclib_local/vectors/q", H5T_IEEE_F64LE, sp, H5P_DEFAULT,
                          H5P_DEFAULT, H5P_DEFAULT);
    ck_assert(ds >= 0);
    H5Dclose(ds);
    H5Sclose(sp);
    H5Fclose(f);
    expect_read_error(path, FRIX_ERR_FORMAT, "stores only");

    /* An HDF5 file with no FCLIB group. */
    f = H5Fcreate(path, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    H5Fclose(f);
    expect_read_error(path, FRIX_ERR_FORMAT, "/fclib_local");

    if (have_shared()) expect_read_error(ROLLING, FRIX_ERR_UNSUPPORTED, "rolling");
}
END_TEST

/* Failing reads print nothing, and HDF5's error handler is the caller's again afterwards. */
START_TEST(test_hdf5_stays_silent) {
    H5E_auto2_t before_fn = NULL, after_fn = NULL;
    void *before_data = NULL, *after_data = NULL;
    ck_assert(H5Eget_auto2(H5E_DEFAULT, &before_fn, &before_data) >= 0);
    ck_assert_ptr_nonnull((void *)before_fn); /* HDF5's default printer */

    const char *text = tmp_path("silent.hdf5");
    spit(text, "not HDF5 at all, but long enough to be probed by the library......", 66);
    const char *captured = tmp_path("stderr.txt");
    fflush(stderr);
    int saved = dup(2);
    int fd = open(captured, O_CREAT | O_TRUNC | O_WRONLY, 0644);
    ck_assert(saved >= 0 && fd >= 0);
    dup2(fd, 2);
    frix_problem *p = NULL;
    frix_error e1 = frix_fclib_read(text, &p);
    frix_error e2 = have_shared() ? frix_fclib_read(ROLLING, &p) : FRIX_ERR_UNSUPPORTED;
    crafted c = crafted_base();
    c.nz = -3;
    write_crafted(tmp_path("silent2.hdf5"), &c);
    frix_error e3 = frix_fclib_read(tmp_path("silent2.hdf5"), &p);
    small_local s;
    small_local_make(&s, "silent");
    frix_error e4 = frix_fclib_write(FRIX_TEST_TMPDIR "/no/such/dir/x.hdf5", s.p, NULL, NULL,
                                     NULL, 0, NULL, NULL, NULL);
    frix_error e5 = frix_fclib_write(FRIX_TEST_TMPDIR, s.p, NULL, NULL, NULL, 0, NULL, NULL, NULL);
    small_local_free(&s);
    fflush(stderr);
    dup2(saved, 2);
    close(saved);
    close(fd);
    ck_assert_int_eq(e1, FRIX_ERR_IO);
    ck_assert_int_eq(e2, FRIX_ERR_UNSUPPORTED);
    ck_assert_int_eq(e3, FRIX_ERR_FORMAT);
    ck_assert_int_eq(e4, FRIX_ERR_IO);
    ck_assert_int_eq(e5, FRIX_ERR_IO);
    struct stat st;
    ck_assert_int_eq(stat(captured, &st), 0);
    ck_assert_msg(st.st_size == 0, "frix printed %lld bytes to stderr", (long long)st.st_size);

    ck_assert(H5Eget_auto2(H5E_DEFAULT, &after_fn, &after_data) >= 0);
    ck_assert(after_fn == before_fn);
    ck_assert_ptr_eq(after_data, before_data);
}
END_TEST

/* A failed write leaves the file that was there byte for byte, and no temporary file. */
START_TEST(test_failed_write_keeps_existing_file) {
    /* A fresh directory, so the leftover check cannot see files of an earlier run. */
    char dir[1024];
    snprintf(dir, sizeof dir, "%s", tmp_path("writefail.XXXXXX"));
    ck_assert_ptr_nonnull(mkdtemp(dir));
    char target[1100];
    snprintf(target, sizeof target, "%s/problem.hdf5", dir);

    small_local s;
    small_local_make(&s, "original");
    ck_assert_int_eq(frix_fclib_write(target, s.p, NULL, NULL, NULL, 0, NULL, NULL, NULL),
                     FRIX_OK);
    long size0 = 0;
    char *before = slurp_sized(target, &size0);

    /* The write runs out of room half-way (a file size limit stands in for a full disk). */
    small_local big;
    small_local_make(&big, "replacement");
    const int64_t n_guesses = 2000; /* ~200 KB of guesses */
    double *g = calloc((size_t)(6 * n_guesses), sizeof(double));
    struct rlimit old_limit, limit;
    ck_assert_int_eq(getrlimit(RLIMIT_FSIZE, &old_limit), 0);
    limit = old_limit;
    limit.rlim_cur = 16 * 1024;
    void (*old_handler)(int) = signal(SIGXFSZ, SIG_IGN);
    ck_assert_int_eq(setrlimit(RLIMIT_FSIZE, &limit), 0);
    frix_error err = frix_fclib_write(target, big.p, NULL, NULL, NULL, n_guesses, g, g, NULL);
    setrlimit(RLIMIT_FSIZE, &old_limit);
    signal(SIGXFSZ, old_handler);
    ck_assert_msg(err == FRIX_ERR_IO, "got %d: %s", err, frix_last_error_message());
    ck_assert(strstr(frix_last_error_message(), target) != NULL);
    free(g);

    /* The path is a directory: refused, the directory stays. */
    char as_dir[1100];
    snprintf(as_dir, sizeof as_dir, "%s/a_directory", dir);
    mkdir(as_dir, 0755);
    ck_assert_int_eq(frix_fclib_write(as_dir, s.p, NULL, NULL, NULL, 0, NULL, NULL, NULL),
                     FRIX_ERR_IO);
    struct stat st;
    ck_assert(stat(as_dir, &st) == 0 && S_ISDIR(st.st_mode));

    /* The directory does not exist. */
    char missing[1100];
    snprintf(missing, sizeof missing, "%s/no_such_dir/problem.hdf5", dir);
    ck_assert_int_eq(frix_fclib_write(missing, s.p, NULL, NULL, NULL, 0, NULL, NULL, NULL),
                     FRIX_ERR_IO);
    ck_assert(strstr(frix_last_error_message(), "no_such_dir") != NULL);

    /* Refused arguments never touch the file. */
    ck_assert_int_eq(frix_fclib_write(target, NULL, NULL, NULL, NULL, 0, NULL, NULL, NULL),
                     FRIX_ERR_INVALID_ARGUMENT);

    long size1 = 0;
    char *after = slurp_sized(target, &size1);
    ck_assert_int_eq(size0, size1);
    ck_assert(memcmp(before, after, (size_t)size0) == 0);
    ck_assert_int_eq(count_prefixed(dir, "problem.hdf5.tmp."), 0);
    ck_assert_int_eq(count_prefixed(dir, "a_directory.tmp."), 0);
    frix_problem *p = read_ok(target);
    ck_assert_str_eq(frix_problem_title(p), "original");
    frix_problem_free(p);

    /* And a successful write replaces it. */
    ck_assert_int_eq(frix_fclib_write(target, big.p, NULL, NULL, NULL, 0, NULL, NULL, NULL),
                     FRIX_OK);
    p = read_ok(target);
    ck_assert_str_eq(frix_problem_title(p), "replacement");
    frix_problem_free(p);
    ck_assert_int_eq(count_prefixed(dir, "problem.hdf5.tmp."), 0);

    free(before);
    free(after);
    small_local_free(&big);
    small_local_free(&s);
    ck_assert_int_eq(unlink(target), 0);
    ck_assert_int_eq(rmdir(as_dir), 0);
    ck_assert_int_eq(rmdir(dir), 0); /* fails if anything else was left behind */
}
END_TEST

static Suite *fclib_suite(void) {
    Suite *s = suite_create("fclib");
    TCase *read = tcase_create("read");
    tcase_add_test(read, test_read_every_shared_file);
    tcase_add_test(read, test_read_large_files);
    tcase_add_test(read, test_manifest_values);
    tcase_add_test(read, test_triplet_orientation_by_reduction);
    tcase_add_test(read, test_read_storage_variants);
    suite_add_tcase(s, read);
    TCase *write = tcase_create("write");
    tcase_add_test(write, test_roundtrip_local);
    tcase_add_test(write, test_roundtrip_global);
    tcase_add_test(write, test_roundtrip_empty);
    tcase_add_test(write, test_nzmax_is_a_capacity);
    tcase_add_test(write, test_triplets_with_duplicates_round_trip);
    tcase_add_test(write, test_solution_and_guesses_local);
    tcase_add_test(write, test_solution_and_guesses_global);
    suite_add_tcase(s, write);
    TCase *bad = tcase_create("bad_input");
    tcase_add_test(bad, test_unreadable_files);
    tcase_add_test(bad, test_malformed_content);
    tcase_add_test(bad, test_hdf5_stays_silent);
    tcase_add_test(bad, test_failed_write_keeps_existing_file);
    suite_add_tcase(s, bad);
    return s;
}

int main(void) { return frix_run_suite(fclib_suite()); }
