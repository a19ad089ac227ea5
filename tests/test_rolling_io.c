/* Rolling-friction problems in files: FCLIB's /fclib_global_rolling (as Siconos writes it) and
 * frix's /fclib_local_rolling, written and read back bit for bit with a solution; Siconos's
 * rolling .dat; Siconos's own file from the shared collection; bad input in every field the
 * rolling groups add (crafted with the HDF5 C API from a valid file); `frix info`, `solve` and
 * `convert` on them. The same for spinning friction (the rolling groups with spacedim 6 and
 * vectors/mu_s, frix's extension): round trips, bad input, the command line, and the Siconos
 * comparator's refusal. */
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
    const int spinning = frix_problem_mu_s(a) != NULL;
    ck_assert_int_eq(spinning, frix_problem_mu_s(b) != NULL);
    ck_assert_int_eq(m, (spinning ? 6 : 5) * nc);
    same_vector(frix_problem_mu(a), frix_problem_mu(b), nc);
    same_vector(frix_problem_mu_r(a), frix_problem_mu_r(b), nc);
    if (spinning) same_vector(frix_problem_mu_s(a), frix_problem_mu_s(b), nc);
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

/* ---- Spinning friction: six entries a contact ------------------------------------------------ */

/* Two contacts of six entries, both forms, from chosen numbers (no solve: the measure and the
 * files need none). Local: W = 12 x 12, symmetric, diagonal 2..13, W(i, j) = 0.01 (i + j) off it.
 * Global: M = diag(1..6), H of 6 x 12 with entries (i - 2j) / 7. */
typedef struct {
    frix_matrix *W, *M, *H;
    double q[12], w[12], f[6], mu[2], mu_r[2], mu_s[2];
    frix_problem *local, *global;
} spinning_pair;

static void spinning_pair_make(spinning_pair *s) {
    double W[144], M[36] = {0}, H[72];
    for (int j = 0; j < 12; ++j)
        for (int i = 0; i < 12; ++i) W[i + 12 * j] = i == j ? 2.0 + i : 0.01 * (i + j);
    for (int i = 0; i < 6; ++i) M[7 * i] = 1.0 + i;
    for (int j = 0; j < 12; ++j)
        for (int i = 0; i < 6; ++i) H[i + 6 * j] = (i - 2.0 * j) / 7.0;
    for (int k = 0; k < 12; ++k) s->q[k] = k % 6 == 0 ? -1.0 - 0.1 * k : 0.01 * (k - 5);
    for (int k = 0; k < 12; ++k) s->w[k] = 0.001 * k;
    for (int k = 0; k < 6; ++k) s->f[k] = -0.5 + 0.2 * k;
    const double mu[2] = {0.3, 0.4}, mu_r[2] = {0.01, 0.02}, mu_s[2] = {0.003, 0.004};
    memcpy(s->mu, mu, sizeof mu), memcpy(s->mu_r, mu_r, sizeof mu_r), memcpy(s->mu_s, mu_s, sizeof mu_s);
    ck_assert_int_eq(frix_matrix_from_dense(12, 12, W, 12, &s->W), FRIX_OK);
    ck_assert_int_eq(frix_matrix_from_dense(6, 6, M, 6, &s->M), FRIX_OK);
    ck_assert_int_eq(frix_matrix_from_dense(6, 12, H, 6, &s->H), FRIX_OK);
    ck_assert_int_eq(frix_problem_spinning_local(s->W, s->q, s->mu, s->mu_r, s->mu_s, 2, &s->local), FRIX_OK);
    ck_assert_int_eq(frix_problem_spinning_global(s->M, s->H, s->f, s->w, s->mu, s->mu_r, s->mu_s, 2, &s->global),
                     FRIX_OK);
}

static void spinning_pair_free(spinning_pair *s) {
    frix_problem_free(s->local);
    frix_problem_free(s->global);
    frix_matrix_free(s->W);
    frix_matrix_free(s->M);
    frix_matrix_free(s->H);
}

/* p written with a solution and two guesses (chosen numbers, as a file may hold any), at a
 * compression level (-1: frix_fclib_write's), and read back: the group has spacedim 6 and mu_s,
 * and the problem, solution and guesses are identical. */
static void spinning_round_trip(const frix_problem *p, const char *name, const char *group, int level) {
    const int64_t m = frix_problem_contact_dofs(p), n = frix_problem_dofs(p);
    ck_assert_int_eq(m, 12);
    const int global = frix_problem_get_kind(p) == FRIX_PROBLEM_ROLLING_GLOBAL;
    double r[12], u[12], v[6], gr[24], gu[24], gv[12];
    for (int k = 0; k < 12; ++k) r[k] = 0.25 * k - 1.0, u[k] = 1.0 / (k + 1);
    for (int k = 0; k < 6; ++k) v[k] = -0.125 * k;
    for (int k = 0; k < 24; ++k) gr[k] = 0.5 * k, gu[k] = -0.5 * k;
    for (int k = 0; k < 12; ++k) gv[k] = 0.75 * k;
    const char *path = tmp_path(name);
    frix_error err = level < 0 ? frix_fclib_write(path, p, r, u, global ? v : NULL, 2, gr, gu, global ? gv : NULL)
                               : frix_fclib_write_compressed(path, p, r, u, global ? v : NULL, 2, gr, gu,
                                                             global ? gv : NULL, level);
    ck_assert_msg(err == FRIX_OK, "%s", frix_last_error_message());
    hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
    ck_assert(f >= 0);
    char dataset[128];
    snprintf(dataset, sizeof dataset, "%s/spacedim", group);
    ck_assert_int_eq(read_int(f, dataset), 6);
    snprintf(dataset, sizeof dataset, "%s/vectors/mu_s", group);
    ck_assert(H5Lexists(f, dataset, H5P_DEFAULT) > 0);
    H5Fclose(f);
    frix_problem *back = read_ok(path);
    same_problem(p, back);
    double r2[12], u2[12], v2[6];
    ck_assert_int_eq(frix_fclib_read_solution(path, back, r2, u2, global ? v2 : NULL), FRIX_OK);
    same_vector(r, r2, m);
    same_vector(u, u2, m);
    if (global) same_vector(v, v2, n);
    int64_t count = 0;
    ck_assert_int_eq(frix_fclib_guess_count(path, &count), FRIX_OK);
    ck_assert_int_eq(count, 2);
    ck_assert_int_eq(frix_fclib_read_guess(path, back, 1, r2, u2, global ? v2 : NULL), FRIX_OK);
    same_vector(gr + m, r2, m);
    same_vector(gu + m, u2, m);
    if (global) same_vector(gv + n, v2, n);
    frix_problem *any = NULL;
    ck_assert_int_eq(frix_read_problem(path, &any), FRIX_OK);
    same_problem(p, any);
    frix_problem_free(any);
    frix_problem_free(back);
}

START_TEST(test_spinning_round_trip) {
    spinning_pair s;
    spinning_pair_make(&s);
    for (int level = -1; level <= 9; level += 5) {
        spinning_round_trip(s.local, "spinning_local.hdf5", "/fclib_local_rolling", level);
        spinning_round_trip(s.global, "spinning_global.hdf5", "/fclib_global_rolling", level);
    }
    spinning_pair_free(&s);
}
END_TEST

static void write_valid_spinning(const char *path, int global) {
    spinning_pair s;
    spinning_pair_make(&s);
    ck_assert_int_eq(frix_fclib_write(path, global ? s.global : s.local, NULL, NULL, NULL, 0, NULL, NULL, NULL),
                     FRIX_OK);
    spinning_pair_free(&s);
}

START_TEST(test_spinning_bad_input) {
    const char *path = tmp_path("spinning_bad.hdf5");
    const char *roots[2] = {"/fclib_local_rolling", "/fclib_global_rolling"};
    for (int global = 0; global < 2; ++global) {
        char mu_s[128], spacedim[128];
        snprintf(mu_s, sizeof mu_s, "%s/vectors/mu_s", roots[global]);
        snprintf(spacedim, sizeof spacedim, "%s/spacedim", roots[global]);
        double values[3] = {0.01, 0.01, 0.01};
        /* mu_s absent, short, long, negative, not finite. */
        write_valid_spinning(path, global);
        replace(path, mu_s, -1, NULL, 0);
        expect_read_error(path, FRIX_ERR_FORMAT, "mu_s");
        write_valid_spinning(path, global);
        replace(path, mu_s, 1, values, 0);
        expect_read_error(path, FRIX_ERR_FORMAT, "mu_s");
        write_valid_spinning(path, global);
        replace(path, mu_s, 3, values, 0);
        expect_read_error(path, FRIX_ERR_FORMAT, "mu_s");
        write_valid_spinning(path, global);
        values[1] = -0.5;
        replace(path, mu_s, 2, values, 0);
        expect_read_error(path, FRIX_ERR_FORMAT, "friction must be >= 0");
        write_valid_spinning(path, global);
        values[1] = INFINITY;
        replace(path, mu_s, 2, values, 0);
        expect_read_error(path, FRIX_ERR_FORMAT, "mu_s: entry 1 is inf");
        /* spacedim 5 with mu_s: the file says two things. 12 rows are no contacts of 5
         * entries either, but the contradiction is what the reader names. */
        const double five = 5, seven = 7;
        write_valid_spinning(path, global);
        replace(path, spacedim, 1, &five, 1);
        expect_read_error(path, FRIX_ERR_FORMAT, "needs spacedim 6");
        /* spacedim 7: no such law. */
        write_valid_spinning(path, global);
        replace(path, spacedim, 1, &seven, 1);
        expect_read_error(path, FRIX_ERR_UNSUPPORTED, "spacedim is 7");
    }
    /* A rolling file (10 rows, two contacts of five) that claims spacedim 6 and has mu_s: 10
     * is no multiple of 6. */
    write_valid(path, 0);
    double two[2] = {0.01, 0.01};
    const double six = 6;
    hid_t f = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
    ck_assert(f >= 0);
    make_dataset(f, "/fclib_local_rolling/vectors/mu_s", 2, two, 0);
    H5Fclose(f);
    replace(path, "/fclib_local_rolling/spacedim", 1, &six, 1);
    expect_read_error(path, FRIX_ERR_FORMAT, "not a multiple of spacedim 6");
    /* A solution of five entries a contact given to the six-entry problem. */
    spinning_pair s;
    spinning_pair_make(&s);
    double r[12] = {0}, u[12] = {0};
    ck_assert_int_eq(frix_fclib_write(path, s.local, r, u, NULL, 0, NULL, NULL, NULL), FRIX_OK);
    replace(path, "/solution/r", 10, (const double[10]){0}, 0);
    ck_assert_int_eq(frix_fclib_read_solution(path, s.local, r, u, NULL), FRIX_ERR_FORMAT);
    ck_assert_msg(strstr(frix_last_error_message(), "6 x contacts") != NULL, "%s", frix_last_error_message());
    spinning_pair_free(&s);
}
END_TEST

/* The command line: info names the law and mu_s's range, convert keeps the law, a
 * three-component solver is refused, and the Siconos comparator (when built) refuses the
 * problem, naming spinning friction. */
START_TEST(test_spinning_cli) {
    const char *h5 = tmp_path("cli_spinning.hdf5"), *copy = tmp_path("cli_spinning_copy.hdf5");
    spinning_pair s;
    spinning_pair_make(&s);
    ck_assert_int_eq(frix_fclib_write(h5, s.global, NULL, NULL, NULL, 0, NULL, NULL, NULL), FRIX_OK);
    cli_run r = run_cli((const char *[]){"info", h5, NULL});
    ck_assert_msg(r.code == 0, "info: %s", r.err);
    ck_assert_msg(strstr(r.out, "rolling and spinning friction") != NULL && strstr(r.out, "0.003 .. 0.004") != NULL,
                  "info: %s", r.out);
    ck_assert(strstr(r.out, "12 (r, u)") != NULL);
    run_free(&r);
    r = run_cli((const char *[]){"info", h5, "--json", NULL});
    ck_assert_int_eq(r.code, 0);
    ck_assert_msg(strstr(r.out, "\"law\":\"spinning\"") != NULL && strstr(r.out, "\"mu_s_max\":0.004") != NULL,
                  "info --json: %s", r.out);
    run_free(&r);
    r = run_cli((const char *[]){"convert", h5, copy, "--title", "copied", NULL});
    ck_assert_msg(r.code == 0, "convert: %s", r.err);
    run_free(&r);
    frix_problem *back = read_ok(copy);
    same_problem(s.global, back);
    ck_assert_str_eq(frix_problem_title(back), "copied");
    frix_problem_free(back);
    r = run_cli((const char *[]){"solve", h5, "--solver", "nsgs", NULL});
    ck_assert_int_ne(r.code, 0);
    ck_assert_msg(strstr(r.err, "rolling") != NULL, "solve --solver nsgs: %s", r.err);
    run_free(&r);
    /* Rolling-friction files say "rolling" alone. */
    write_valid(copy, 1);
    r = run_cli((const char *[]){"info", copy, "--json", NULL});
    ck_assert_msg(strstr(r.out, "\"law\":\"rolling\"") != NULL && strstr(r.out, "mu_s") == NULL, "%s", r.out);
    run_free(&r);

    char adapter[1024];
    snprintf(adapter, sizeof adapter, "%s", FRIX_CLI);
    strcpy(strrchr(adapter, '/') + 1, "frix-siconos");
    if (access(adapter, X_OK) == 0) {
        const char *solvers[2] = {"GRFC3D_NSGS_WR", "GFC3D_NSGS"};
        for (int k = 0; k < 2; ++k) {
            r = run_program(adapter, (const char *[]){h5, "--solver", solvers[k], NULL});
            ck_assert_int_eq(r.code, 2);
            ck_assert_msg(strstr(r.err, "spinning friction") != NULL, "frix-siconos %s: %s", solvers[k], r.err);
            run_free(&r);
        }
    } else {
        printf("test_rolling_io: frix-siconos not built (no Siconos): its refusal not tested\n");
    }
    spinning_pair_free(&s);
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
    tcase_add_test(tc, test_spinning_round_trip);
    tcase_add_test(tc, test_spinning_bad_input);
    tcase_add_test(tc, test_spinning_cli);
    suite_add_tcase(s, tc);
    return frix_run_suite(s);
}
