/* Rolling-friction problems in files: FCLIB's /fclib_global_rolling (as Siconos writes it) and
 * frix's /fclib_local_rolling, written and read back bit for bit with a solution; Siconos's
 * rolling .dat; Siconos's own file from the shared collection; bad input in every field the
 * rolling groups add (crafted with the HDF5 C API from a valid file); `frix info`, `solve` and
 * `convert` on them. */
#define _POSIX_C_SOURCE 200809L
#include <frix/frix.h>

#include <hdf5.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check_main.h"
#include "cli_runner.h"
#include "fclib_fixtures.h"
#include "files.h"
#include "support/rolling_pile.h"

/* A 1-D dataset of n values (native doubles or ints), with the plain HDF5 API. */
static void make_dataset(hid_t f, const char *name, int n, const void *values, int is_int) {
    hsize_t dim = (hsize_t)n;
    hid_t space = H5Screate_simple(1, &dim, NULL);
    hid_t type = is_int ? H5T_STD_I32LE : H5T_IEEE_F64LE;
    hid_t ds = H5Dcreate2(f, name, type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    ck_assert(ds >= 0);
    ck_assert(H5Dwrite(ds, is_int ? H5T_NATIVE_INT : H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values) >= 0);
    H5Dclose(ds);
    H5Sclose(space);
}

static int read_int(hid_t f, const char *name) {
    int value = -1;
    hid_t ds = H5Dopen2(f, name, H5P_DEFAULT);
    ck_assert(ds >= 0);
    ck_assert(H5Dread(ds, H5T_NATIVE_INT, H5S_ALL, H5S_ALL, H5P_DEFAULT, &value) >= 0);
    H5Dclose(ds);
    return value;
}

static void same_vector(const double *a, const double *b, int64_t n) {
    for (int64_t i = 0; i < n; ++i) ck_assert_msg(a[i] == b[i], "entry %lld: %.17g vs %.17g", (long long)i, a[i], b[i]);
}

/* A and B equal entry by entry (as CSC exports). */
static void same_matrix(const frix_matrix *A, const frix_matrix *B) {
    ck_assert_int_eq(frix_matrix_rows(A), frix_matrix_rows(B));
    ck_assert_int_eq(frix_matrix_cols(A), frix_matrix_cols(B));
    const int64_t n = frix_matrix_cols(A);
    int64_t na = 0, nb = 0;
    ck_assert_int_eq(frix_matrix_to_csc(A, &na, NULL, NULL, NULL), FRIX_OK);
    ck_assert_int_eq(frix_matrix_to_csc(B, &nb, NULL, NULL, NULL), FRIX_OK);
    ck_assert_int_eq(na, nb);
    int64_t *pa = malloc((size_t)(n + 1) * 8), *pb = malloc((size_t)(n + 1) * 8);
    int64_t *ia = malloc((size_t)(na + 1) * 8), *ib = malloc((size_t)(nb + 1) * 8);
    double *xa = malloc((size_t)(na + 1) * 8), *xb = malloc((size_t)(nb + 1) * 8);
    ck_assert_int_eq(frix_matrix_to_csc(A, &na, pa, ia, xa), FRIX_OK);
    ck_assert_int_eq(frix_matrix_to_csc(B, &nb, pb, ib, xb), FRIX_OK);
    ck_assert_int_eq(memcmp(pa, pb, (size_t)(n + 1) * 8), 0);
    ck_assert_int_eq(memcmp(ia, ib, (size_t)na * 8), 0);
    same_vector(xa, xb, na);
    free(pa), free(pb), free(ia), free(ib), free(xa), free(xb);
}

static void same_problem(const frix_problem *a, const frix_problem *b) {
    ck_assert_int_eq(frix_problem_get_kind(a), frix_problem_get_kind(b));
    const int64_t nc = frix_problem_contacts(a), m = frix_problem_contact_dofs(a);
    ck_assert_int_eq(nc, frix_problem_contacts(b));
    ck_assert_int_eq(m, 5 * nc);
    same_vector(frix_problem_mu(a), frix_problem_mu(b), nc);
    same_vector(frix_problem_mu_r(a), frix_problem_mu_r(b), nc);
    if (frix_problem_get_kind(a) == FRIX_PROBLEM_ROLLING_LOCAL) {
        same_matrix(frix_problem_W(a), frix_problem_W(b));
        same_vector(frix_problem_q(a), frix_problem_q(b), m);
    } else {
        same_matrix(frix_problem_M(a), frix_problem_M(b));
        same_matrix(frix_problem_H(a), frix_problem_H(b));
        same_vector(frix_problem_f(a), frix_problem_f(b), frix_problem_dofs(a));
        same_vector(frix_problem_w(a), frix_problem_w(b), m);
    }
}

/* Solves p, writes it with its solution, reads both back. */
static void round_trip(frix_problem *p, const char *name, const char *group) {
    const int64_t m = frix_problem_contact_dofs(p), n = frix_problem_dofs(p);
    const int global = frix_problem_get_kind(p) == FRIX_PROBLEM_ROLLING_GLOBAL;
    double *r = calloc((size_t)m, 8), *u = calloc((size_t)m, 8), *v = calloc((size_t)n + 1, 8);
    ck_assert_int_eq(frix_solve(p, NULL, r, u, global ? v : NULL, NULL), FRIX_OK);
    const char *path = tmp_path(name);
    ck_assert_int_eq(frix_problem_set_title(p, "rolling pile"), FRIX_OK);
    ck_assert_int_eq(frix_fclib_write(path, p, r, u, global ? v : NULL, 0, NULL, NULL, NULL), FRIX_OK);
    /* The group is the one named (FCLIB's for the global form), with spacedim 5. */
    hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
    ck_assert(f >= 0);
    char spacedim[128];
    snprintf(spacedim, sizeof spacedim, "%s/spacedim", group);
    ck_assert_int_eq(read_int(f, spacedim), 5);
    H5Fclose(f);
    frix_problem *back = read_ok(path);
    same_problem(p, back);
    ck_assert_str_eq(frix_problem_title(back), "rolling pile");
    double *r2 = calloc((size_t)m, 8), *u2 = calloc((size_t)m, 8), *v2 = calloc((size_t)n + 1, 8);
    ck_assert_int_eq(frix_fclib_read_solution(path, back, r2, u2, global ? v2 : NULL), FRIX_OK);
    same_vector(r, r2, m);
    same_vector(u, u2, m);
    if (global) same_vector(v, v2, n);
    frix_problem *any = NULL;
    ck_assert_int_eq(frix_read_problem(path, &any), FRIX_OK);
    same_problem(p, any);
    frix_problem_free(any);
    frix_problem_free(back);
    free(r), free(u), free(v), free(r2), free(u2), free(v2);
}

START_TEST(test_round_trip) {
    rolling_pile pile;
    ck_assert_int_eq(rolling_pile_make(2, 2, 0.3, 0.02, 5, &pile), 0);
    round_trip(pile.local, "rolling_local.hdf5", "/fclib_local_rolling");
    round_trip(pile.global, "rolling_global.hdf5", "/fclib_global_rolling");
    rolling_pile_free(&pile);
}
END_TEST

/* Siconos's own rolling file (its fclib_global_rolling writer): read, solved. */
START_TEST(test_siconos_file) {
    REQUIRE_SHARED();
    frix_problem *p = read_ok(ROLLING);
    ck_assert_int_eq(frix_problem_get_kind(p), FRIX_PROBLEM_ROLLING_GLOBAL);
    ck_assert_int_eq(frix_problem_contacts(p), 4);
    ck_assert_ptr_nonnull(frix_problem_mu_r(p));
    const int64_t m = frix_problem_contact_dofs(p), n = frix_problem_dofs(p);
    double *r = calloc((size_t)m, 8), *u = calloc((size_t)m, 8), *v = calloc((size_t)n, 8);
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_solve(p, NULL, r, u, v, info), FRIX_OK);
    ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_CONVERGED);
    frix_info_free(info);
    free(r), free(u), free(v);
    frix_problem_free(p);
}
END_TEST

/* Reading the .dat at path fails with code, the message containing needle. */
static void expect_dat_error(const char *path, frix_error code, const char *needle) {
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_dat_read(path, &p), code);
    ck_assert_ptr_null(p);
    ck_assert_msg(strstr(frix_last_error_message(), needle) != NULL, "message: %s", frix_last_error_message());
}

/* Siconos's rolling .dat (rollingFrictionContact_printInFile): dense W = 2 I, one contact. */
START_TEST(test_dat) {
    const char *path = tmp_path("rolling.dat");
    char text[2048] = "5\n1\n0 5 5\n5 5\n";
    for (int j = 0; j < 5; ++j)
        for (int i = 0; i < 5; ++i) strcat(text, i == j ? "2 " : "0 ");
    strcat(text, "\n-1 0.1 0 0.001 0\n0.5\n0.01\n");
    spit_text(path, text);
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_read_problem(path, &p), FRIX_OK);
    ck_assert_int_eq(frix_problem_get_kind(p), FRIX_PROBLEM_ROLLING_LOCAL);
    ck_assert_double_eq(frix_problem_mu_r(p)[0], 0.01);
    ck_assert_double_eq(frix_problem_q(p)[3], 0.001);
    frix_problem_free(p);
    /* mu_r missing, then a number too many, then W for the wrong number of contacts. */
    char cut[2048];
    strcpy(cut, text);
    cut[strlen(cut) - 5] = '\0';
    spit_text(path, cut);
    expect_dat_error(path, FRIX_ERR_FORMAT, "mu_r");
    strcpy(cut, text);
    strcat(cut, "7\n");
    spit_text(path, cut);
    expect_dat_error(path, FRIX_ERR_FORMAT, "follow mu_r");
    strcpy(cut, text);
    cut[2] = '2';
    spit_text(path, cut);
    expect_dat_error(path, FRIX_ERR_FORMAT, "rolling contacts");
}
END_TEST

/* A valid rolling file of `kind` at path, then one dataset replaced by `values` (n of them,
 * doubles; or ints when is_int), or removed when n < 0. */
static void write_valid(const char *path, int global) {
    rolling_pile pile;
    ck_assert_int_eq(rolling_pile_make(1, 2, 0.3, 0.02, 9, &pile), 0);
    ck_assert_int_eq(frix_fclib_write(path, global ? pile.global : pile.local, NULL, NULL, NULL, 0, NULL, NULL, NULL),
                     FRIX_OK);
    rolling_pile_free(&pile);
}

static void replace(const char *path, const char *name, int n, const double *values, int is_int) {
    hid_t f = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
    ck_assert(f >= 0);
    ck_assert(H5Ldelete(f, name, H5P_DEFAULT) >= 0);
    if (n >= 0) {
        int iv[8];
        for (int i = 0; i < n && is_int; ++i) iv[i] = (int)values[i];
        make_dataset(f, name, n, is_int ? (const void *)iv : (const void *)values, is_int);
    }
    H5Fclose(f);
}

START_TEST(test_bad_input) {
    const char *path = tmp_path("rolling_bad.hdf5");
    /* Per group: mu_r absent, short, negative, not finite; spacedim 3 in a rolling group. */
    const char *roots[2] = {"/fclib_local_rolling", "/fclib_global_rolling"};
    for (int global = 0; global < 2; ++global) {
        char name[128];
        snprintf(name, sizeof name, "%s/vectors/mu_r", roots[global]);
        write_valid(path, global);
        frix_problem *p = read_ok(path);
        const int64_t nc = frix_problem_contacts(p);
        frix_problem_free(p);
        ck_assert_int_ge(nc, 2);
        ck_assert_int_le(nc, 8);
        double values[8];
        for (int i = 0; i < 8; ++i) values[i] = 0.01;
        replace(path, name, -1, NULL, 0);
        expect_read_error(path, FRIX_ERR_FORMAT, "mu_r");
        write_valid(path, global);
        replace(path, name, (int)nc - 1, values, 0);
        expect_read_error(path, FRIX_ERR_FORMAT, "mu_r");
        write_valid(path, global);
        values[1] = -0.5;
        replace(path, name, (int)nc, values, 0);
        expect_read_error(path, FRIX_ERR_FORMAT, "friction must be >= 0");
        write_valid(path, global);
        values[1] = NAN;
        replace(path, name, (int)nc, values, 0);
        expect_read_error(path, FRIX_ERR_FORMAT, "mu_r: entry 1 is nan");
        write_valid(path, global);
        snprintf(name, sizeof name, "%s/spacedim", roots[global]);
        const double three = 3;
        replace(path, name, 1, &three, 1);
        expect_read_error(path, FRIX_ERR_UNSUPPORTED, "spacedim is 3");
    }
    /* Two problem groups in one file. */
    write_valid(path, 1);
    hid_t f = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
    ck_assert(f >= 0);
    hid_t g = H5Gcreate2(f, "/fclib_local", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    ck_assert(g >= 0);
    H5Gclose(g);
    H5Fclose(f);
    expect_read_error(path, FRIX_ERR_FORMAT, "holds both");
    /* A global rolling file whose H has a number of columns no multiple of 5: w and H checked
     * against each other (w shortened, then H's declared n). */
    write_valid(path, 1);
    double w[4] = {0, 0, 0, 0};
    replace(path, "/fclib_global_rolling/vectors/w", 4, w, 0);
    expect_read_error(path, FRIX_ERR_FORMAT, "/fclib_global_rolling/vectors/w");
}
END_TEST

/* The command line: info names the kind and mu_r, solve converges with auto's rolling stage,
 * convert takes a rolling .dat to FCLIB, and a three-component solver is refused by name. */
START_TEST(test_cli) {
    const char *dat = tmp_path("cli_rolling.dat"), *h5 = tmp_path("cli_rolling.hdf5");
    char text[2048] = "5\n1\n0 5 5\n5 5\n";
    for (int j = 0; j < 5; ++j)
        for (int i = 0; i < 5; ++i) strcat(text, i == j ? "2 " : "0 ");
    strcat(text, "\n-1 0 0 0.05 0\n0.5\n0.01\n");
    spit_text(dat, text);
    cli_run r = run_cli((const char *[]){"convert", dat, h5, "--force", NULL});
    ck_assert_msg(r.code == 0, "convert: %s", r.err);
    ck_assert(strstr(r.out, "rolling-local") != NULL);
    run_free(&r);
    r = run_cli((const char *[]){"info", h5, NULL});
    ck_assert_int_eq(r.code, 0);
    ck_assert(strstr(r.out, "rolling-local") != NULL && strstr(r.out, "mu_r") != NULL);
    ck_assert(strstr(r.out, "5 (r, u)") != NULL);
    run_free(&r);
    r = run_cli((const char *[]){"solve", h5, "--tol", "1e-12", "--json", NULL});
    ck_assert_msg(r.code == 0, "solve: %s", r.err);
    ck_assert(strstr(r.out, "\"converged\"") != NULL && strstr(r.out, "rolling-nsgs") != NULL);
    run_free(&r);
    r = run_cli((const char *[]){"solve", h5, "--solver", "nsgs", NULL});
    ck_assert_int_ne(r.code, 0);
    ck_assert(strstr(r.err, "rolling") != NULL);
    run_free(&r);
}
END_TEST

int main(void) {
    Suite *s = suite_create("rolling_io");
    TCase *tc = tcase_create("core");
    tcase_set_timeout(tc, 120);
    tcase_add_test(tc, test_round_trip);
    tcase_add_test(tc, test_siconos_file);
    tcase_add_test(tc, test_dat);
    tcase_add_test(tc, test_bad_input);
    tcase_add_test(tc, test_cli);
    suite_add_tcase(s, tc);
    return frix_run_suite(s);
}
