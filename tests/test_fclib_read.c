/* FCLIB files, reading: every shared problem file reads (with the sizes MANIFEST.md gives),
 * the triplet convention checked on the data, and the storage variants the real files do not
 * all use. The malformed files are in test_fclib_bad_input, writing in test_fclib_write. */
#include <frix/frix.h>

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check_main.h"
#include "fclib_fixtures.h"

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

int main(void) {
    Suite *s = suite_create("fclib");
    TCase *read = tcase_create("read");
    tcase_add_test(read, test_read_every_shared_file);
    tcase_add_test(read, test_read_large_files);
    tcase_add_test(read, test_manifest_values);
    tcase_add_test(read, test_triplet_orientation_by_reduction);
    tcase_add_test(read, test_read_storage_variants);
    suite_add_tcase(s, read);
    return frix_run_suite(s);
}
