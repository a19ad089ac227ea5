/* The FCLIB test fixtures of fclib_fixtures.h. */
#include "fclib_fixtures.h"

#include <check.h>
#include <hdf5.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

int have_shared(void) { return access(LOCAL_TEST, R_OK) == 0; }

const char *tmp_path(const char *name) {
    static char buf[8][1024];
    static int next = 0;
    char *out = buf[next++ % 8];
    snprintf(out, sizeof buf[0], "%s/fclib_%s", FRIX_TEST_TMPDIR, name);
    return out;
}

frix_problem *read_ok(const char *path) {
    frix_problem *p = NULL;
    frix_error err = frix_fclib_read(path, &p);
    ck_assert_msg(err == FRIX_OK, "reading %s: %d %s", path, err, frix_last_error_message());
    ck_assert_ptr_nonnull(p);
    return p;
}

void expect_read_error(const char *path, frix_error code, const char *needle) {
    frix_problem *p = (frix_problem *)0x1;
    frix_error err = frix_fclib_read(path, &p);
    const char *msg = frix_last_error_message();
    ck_assert_msg(err == code, "%s: expected error %d, got %d (%s)", path, code, err, msg);
    ck_assert_ptr_null(p);
    ck_assert_msg(strstr(msg, path) != NULL, "message does not name the file: %s", msg);
    if (needle != NULL)
        ck_assert_msg(strstr(msg, needle) != NULL, "message lacks '%s': %s", needle, msg);
}

csc to_csc(const frix_matrix *A) {
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

void csc_free(csc *c) {
    free(c->p);
    free(c->i);
    free(c->x);
}

double csc_entry(const csc *c, int64_t row, int64_t col) {
    for (int64_t k = c->p[col]; k < c->p[col + 1]; ++k)
        if (c->i[k] == row) return c->x[k];
    return 0.0;
}

void assert_same_matrix(const frix_matrix *A, const frix_matrix *B) {
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

void assert_same_vector(const double *a, const double *b, int64_t n) {
    ck_assert(n == 0 || memcmp(a, b, sizeof(double) * (size_t)n) == 0);
}

void assert_same_problem(const frix_problem *a, const frix_problem *b) {
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

void small_local_make(small_local *s, const char *title) {
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

void small_local_free(small_local *s) {
    frix_problem_free(s->p);
    frix_matrix_free(s->W);
}

static const long long base_p[] = {0, 2, 3, 4, 5, 6, 7};
static const long long base_i[] = {0, 3, 1, 2, 3, 4, 5};
static const double base_x[] = {2, 0.5, 3, 4, 5, 6, 7};
static const double base_q[] = {-1, 0, 0, -1, 0, 0};
static const double base_mu[] = {0.3, 0.5};
const long long csc_p[7] = {0, 1, 2, 3, 5, 6, 7};
const long long csc_i[7] = {0, 1, 2, 0, 3, 4, 5};
const double csc_x[7] = {2, 3, 4, 0.5, 5, 6, 7};

crafted crafted_base(void) {
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

void write_crafted(const char *path, const crafted *c) {
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
