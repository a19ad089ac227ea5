/* Interoperability with the FCLIB reference library (Debian libfclib-dev): files frix
 * writes load with fclib_read_local / fclib_read_global / fclib_read_solution /
 * fclib_read_guesses with the same sizes and values, and frix reads files written by
 * fclib_write_local / fclib_write_global / fclib_write_solution / fclib_write_guesses.
 * libfclib calls exit(1) on any failure, so every file it touches here is fresh. */
#include <frix/frix.h>

#include <fclib.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check_main.h"

#define LOCAL_TEST FRIX_SHARED_DIR "/fclib/local/local_problem_test.hdf5"
#define BOX_GLOBAL FRIX_SHARED_DIR "/fclib/global/Box_Stacks-i0035-31-0.hdf5"

static const char *tmp_path(const char *name) {
    static char buf[4][1024];
    static int next = 0;
    char *out = buf[next++ % 4];
    snprintf(out, sizeof buf[0], "%s/fclib_ref_%s", FRIX_TEST_TMPDIR, name);
    unlink(out); /* libfclib's writers refuse (and exit) if the groups already exist */
    return out;
}

/* A libfclib matrix equals frix's CSC export, entry for entry. */
static void assert_fclib_matrix_is(const struct fclib_matrix *F, const frix_matrix *A) {
    int64_t nnz = 0;
    ck_assert_int_eq(frix_matrix_to_csc(A, &nnz, NULL, NULL, NULL), FRIX_OK);
    const int64_t cols = frix_matrix_cols(A);
    int64_t *p = malloc(sizeof(int64_t) * (size_t)(cols + 1));
    int64_t *i = malloc(sizeof(int64_t) * (size_t)(nnz + 1));
    double *x = malloc(sizeof(double) * (size_t)(nnz + 1));
    ck_assert_int_eq(frix_matrix_to_csc(A, &nnz, p, i, x), FRIX_OK);
    ck_assert_int_eq(F->nz, -1);
    ck_assert_int_eq(F->m, frix_matrix_rows(A));
    ck_assert_int_eq(F->n, cols);
    ck_assert_int_eq(F->nzmax, nnz);
    for (int64_t k = 0; k <= cols; ++k) ck_assert_int_eq(F->p[k], p[k]);
    for (int64_t k = 0; k < nnz; ++k) {
        ck_assert_int_eq(F->i[k], i[k]);
        ck_assert(F->x[k] == x[k]);
    }
    free(p);
    free(i);
    free(x);
}

static void assert_same(const double *a, const double *b, int64_t n) {
    ck_assert(n == 0 || memcmp(a, b, sizeof(double) * (size_t)n) == 0);
}

/* A 2-contact local problem, or the shared test problem when it is there. */
static frix_problem *local_problem(frix_matrix **W_out) {
    frix_problem *p = NULL;
    *W_out = NULL;
    if (access(LOCAL_TEST, R_OK) == 0) {
        ck_assert_int_eq(frix_fclib_read(LOCAL_TEST, &p), FRIX_OK);
        return p;
    }
    static double q[6] = {-1, 0.5, 0, -2, 0, 0.25}, mu[2] = {0.3, 0.6};
    double a[36] = {0};
    for (int k = 0; k < 6; ++k) a[7 * k] = 1.0 + k;
    a[3] = a[18] = 0.5;
    ck_assert_int_eq(frix_matrix_from_dense(6, 6, a, 6, W_out), FRIX_OK);
    ck_assert_int_eq(frix_problem_local(*W_out, q, mu, 2, &p), FRIX_OK);
    ck_assert_int_eq(frix_problem_set_title(p, "two contacts"), FRIX_OK);
    return p;
}

START_TEST(test_fclib_reads_frix_local) {
    frix_matrix *W = NULL;
    frix_problem *p = local_problem(&W);
    const int64_t nc = frix_problem_contacts(p), m = 3 * nc;
    double *r = malloc(sizeof(double) * (size_t)(3 * m)), *u = r + m, *g = r + 2 * m;
    for (int64_t k = 0; k < 3 * m; ++k) r[k] = sin(0.3 * (double)k);

    const char *path = tmp_path("local.hdf5");
    ck_assert_int_eq(frix_problem_set_description(p, "a block of W\nand q, mu"), FRIX_OK);
    ck_assert_int_eq(frix_problem_set_math_info(p, "u = W r + q"), FRIX_OK);
    ck_assert_int_eq(frix_fclib_write(path, p, r, u, NULL, 1, g, r, NULL), FRIX_OK);

    struct fclib_local *F = fclib_read_local(path);
    ck_assert_ptr_nonnull(F);
    ck_assert_int_eq(F->spacedim, 3);
    ck_assert_ptr_null(F->V);
    ck_assert_ptr_null(F->R);
    assert_fclib_matrix_is(F->W, frix_problem_W(p));
    assert_same(F->q, frix_problem_q(p), m);
    assert_same(F->mu, frix_problem_mu(p), nc);
    ck_assert_ptr_nonnull(F->info);
    ck_assert_str_eq(F->info->title, frix_problem_title(p));
    ck_assert_str_eq(F->info->description, "a block of W\nand q, mu");
    ck_assert_str_eq(F->info->math_info, "u = W r + q");
    fclib_delete_local(F);
    free(F);

    struct fclib_solution *S = fclib_read_solution(path);
    ck_assert_ptr_nonnull(S);
    assert_same(S->r, r, m);
    assert_same(S->u, u, m);
    fclib_delete_solutions(S, 1);

    int n = 0;
    struct fclib_solution *G = fclib_read_guesses(path, &n);
    ck_assert_int_eq(n, 1);
    assert_same(G[0].r, g, m);
    assert_same(G[0].u, r, m);
    fclib_delete_solutions(G, n);

    free(r);
    frix_problem_free(p);
    frix_matrix_free(W);
}
END_TEST

START_TEST(test_fclib_reads_frix_global) {
    /* In memory: M (5 x 5, not a multiple of 3: general storage) and H (5 x 6). */
    double Md[25] = {0}, Hd[30] = {0};
    for (int k = 0; k < 5; ++k) Md[6 * k] = 2.0 + k;
    Md[1] = Md[5] = 0.5;
    for (int k = 0; k < 6; ++k) Hd[5 * k + (k % 5)] = 1.0 - 0.1 * k;
    Hd[5 * 2 + 4] = 0.75;
    static double f[5] = {1, -1, 0.5, 0, 2}, w[6] = {0, 0.1, 0, -0.5, 0, 0}, mu[2] = {0.4, 0.2};
    frix_matrix *M = NULL, *H = NULL;
    ck_assert_int_eq(frix_matrix_from_dense(5, 5, Md, 5, &M), FRIX_OK);
    ck_assert_int_eq(frix_matrix_from_dense(5, 6, Hd, 5, &H), FRIX_OK);
    frix_problem *mem = NULL;
    ck_assert_int_eq(frix_problem_global(M, H, f, w, mu, 2, &mem), FRIX_OK);

    frix_problem *problems[2] = {mem, NULL};
    if (access(BOX_GLOBAL, R_OK) == 0)
        ck_assert_int_eq(frix_fclib_read(BOX_GLOBAL, &problems[1]), FRIX_OK);

    for (int t = 0; t < 2 && problems[t] != NULL; ++t) {
        frix_problem *p = problems[t];
        const int64_t nc = frix_problem_contacts(p), m = 3 * nc, n = frix_problem_dofs(p);
        double *r = malloc(sizeof(double) * (size_t)(2 * m + n));
        double *u = r + m, *v = r + 2 * m;
        for (int64_t k = 0; k < 2 * m + n; ++k) r[k] = cos(0.7 * (double)k);
        const char *path = tmp_path("global.hdf5");
        ck_assert_int_eq(frix_fclib_write(path, p, r, u, v, 1, u, r, v), FRIX_OK);

        struct fclib_global *F = fclib_read_global(path);
        ck_assert_ptr_nonnull(F);
        ck_assert_int_eq(F->spacedim, 3);
        ck_assert_ptr_null(F->G);
        assert_fclib_matrix_is(F->M, frix_problem_M(p));
        assert_fclib_matrix_is(F->H, frix_problem_H(p));
        assert_same(F->f, frix_problem_f(p), n);
        assert_same(F->w, frix_problem_w(p), m);
        assert_same(F->mu, frix_problem_mu(p), nc);
        fclib_delete_global(F);
        free(F);

        struct fclib_solution *S = fclib_read_solution(path);
        ck_assert_ptr_nonnull(S);
        assert_same(S->r, r, m);
        assert_same(S->u, u, m);
        assert_same(S->v, v, n);
        fclib_delete_solutions(S, 1);
        int count = 0;
        struct fclib_solution *G = fclib_read_guesses(path, &count);
        ck_assert_int_eq(count, 1);
        assert_same(G[0].r, u, m);
        assert_same(G[0].v, v, n);
        fclib_delete_solutions(G, count);
        free(r);
        frix_problem_free(p);
    }
    frix_matrix_free(M);
    frix_matrix_free(H);
}
END_TEST

/* fclib_write_local with W in CSR (what Siconos writes), solution and guesses; frix reads
 * all of it back. */
START_TEST(test_frix_reads_fclib_local) {
    /* W = diag(2..7) + W(0,3) = 0.5, rows compressed. */
    int p[7] = {0, 2, 3, 4, 5, 6, 7}, i[7] = {0, 3, 1, 2, 3, 4, 5};
    double x[7] = {2, 0.5, 3, 4, 5, 6, 7};
    double q[6] = {-1, 0, 0.5, -1, 0.25, 0}, mu[2] = {0.3, 0.8};
    struct fclib_matrix W = {7, 6, 6, p, i, x, -2, NULL};
    struct fclib_info info = {"written by libfclib", "a test", "none"};
    struct fclib_local L = {&W, NULL, NULL, mu, q, NULL, 3, &info};
    const char *path = tmp_path("by_fclib_local.hdf5");
    ck_assert_int_eq(fclib_write_local(&L, path), 1);
    double r[6] = {1, 2, 3, 4, 5, 6}, u[6] = {-1, -2, -3, -4, -5, -6};
    double r2[6] = {0.5, 0, 0, 0.25, 0, 0}, u2[6] = {0, 0, 1, 0, 0, 1};
    struct fclib_solution sol = {NULL, u, r, NULL};
    ck_assert_int_eq(fclib_write_solution(&sol, path), 1);
    struct fclib_solution guesses[2] = {{NULL, u, r, NULL}, {NULL, u2, r2, NULL}};
    ck_assert_int_eq(fclib_write_guesses(2, guesses, path), 1);

    frix_problem *fp = NULL;
    ck_assert_int_eq(frix_fclib_read(path, &fp), FRIX_OK);
    ck_assert_int_eq(frix_problem_contacts(fp), 2);
    assert_same(frix_problem_q(fp), q, 6);
    assert_same(frix_problem_mu(fp), mu, 2);
    ck_assert_str_eq(frix_problem_title(fp), "written by libfclib");
    ck_assert_str_eq(frix_problem_description(fp), "a test");
    ck_assert_str_eq(frix_problem_math_info(fp), "none");
    double e[6] = {0}, col[6];
    for (int c = 0; c < 6; ++c) { /* W column by column */
        e[c] = 1;
        ck_assert_int_eq(frix_matrix_gemv(frix_problem_W(fp), 1.0, e, 0.0, col), FRIX_OK);
        for (int row = 0; row < 6; ++row) {
            double expected = 0;
            for (int k = p[row]; k < p[row + 1]; ++k)
                if (i[k] == c) expected += x[k];
            ck_assert(col[row] == expected);
        }
        e[c] = 0;
    }

    double rr[6], uu[6];
    ck_assert_int_eq(frix_fclib_read_solution(path, fp, rr, uu, NULL), FRIX_OK);
    assert_same(rr, r, 6);
    assert_same(uu, u, 6);
    int64_t count = 0;
    ck_assert_int_eq(frix_fclib_guess_count(path, &count), FRIX_OK);
    ck_assert_int_eq(count, 2);
    ck_assert_int_eq(frix_fclib_read_guess(path, fp, 1, rr, uu, NULL), FRIX_OK);
    assert_same(rr, r2, 6);
    assert_same(uu, u2, 6);
    frix_problem_free(fp);
}
END_TEST

/* fclib_write_global with triplet M and H (what Siconos and LMGC90 write). */
START_TEST(test_frix_reads_fclib_global) {
    /* M = diag(1..4) with a duplicate on (0,0); H is 4 x 3. Triplets: p = columns, i = rows. */
    int Mi[5] = {0, 1, 2, 3, 0}, Mp[5] = {0, 1, 2, 3, 0};
    double Mx[5] = {0.5, 2, 3, 4, 0.5};
    int Hi[4] = {0, 1, 3, 2}, Hp[4] = {0, 0, 1, 2};
    double Hx[4] = {1, -1, 0.5, 2};
    double f[4] = {0, -9.81, 0, 1}, w[3] = {0.1, 0, 0}, mu[1] = {0.5};
    struct fclib_matrix Mf = {5, 4, 4, Mp, Mi, Mx, 5, NULL};
    struct fclib_matrix Hf = {4, 4, 3, Hp, Hi, Hx, 4, NULL};
    struct fclib_info info = {"global by libfclib", "", ""};
    struct fclib_global G = {&Mf, &Hf, NULL, mu, f, NULL, w, 3, &info};
    const char *path = tmp_path("by_fclib_global.hdf5");
    ck_assert_int_eq(fclib_write_global(&G, path), 1);

    frix_problem *fp = NULL;
    ck_assert_int_eq(frix_fclib_read(path, &fp), FRIX_OK);
    ck_assert_int_eq(frix_problem_get_kind(fp), FRIX_PROBLEM_GLOBAL);
    ck_assert_int_eq(frix_problem_dofs(fp), 4);
    ck_assert_int_eq(frix_problem_contacts(fp), 1);
    assert_same(frix_problem_f(fp), f, 4);
    assert_same(frix_problem_w(fp), w, 3);
    double ones[4] = {1, 1, 1, 1}, y[4];
    ck_assert_int_eq(frix_matrix_gemv(frix_problem_M(fp), 1.0, ones, 0.0, y), FRIX_OK);
    ck_assert(y[0] == 1.0 && y[1] == 2.0 && y[2] == 3.0 && y[3] == 4.0);
    double e[3] = {1, 0, 0};
    ck_assert_int_eq(frix_matrix_gemv(frix_problem_H(fp), 1.0, e, 0.0, y), FRIX_OK);
    ck_assert(y[0] == 1.0 && y[1] == -1.0 && y[2] == 0.0 && y[3] == 0.0);
    double e2[3] = {0, 0, 1};
    ck_assert_int_eq(frix_matrix_gemv(frix_problem_H(fp), 1.0, e2, 0.0, y), FRIX_OK);
    ck_assert(y[0] == 0.0 && y[1] == 0.0 && y[2] == 2.0 && y[3] == 0.0);
    ck_assert_str_eq(frix_problem_title(fp), "global by libfclib");
    frix_problem_free(fp);
}
END_TEST

static Suite *reference_suite(void) {
    Suite *s = suite_create("fclib_reference");
    TCase *tc = tcase_create("interop");
    tcase_add_test(tc, test_fclib_reads_frix_local);
    tcase_add_test(tc, test_fclib_reads_frix_global);
    tcase_add_test(tc, test_frix_reads_fclib_local);
    tcase_add_test(tc, test_frix_reads_fclib_global);
    suite_add_tcase(s, tc);
    return s;
}

int main(void) { return frix_run_suite(reference_suite()); }
