/* Shared by the test programs that read problems of ../shared/fclib. */
#ifndef FRIX_SHARED_DATA_H
#define FRIX_SHARED_DATA_H

#include <check.h>
#include <frix/frix.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#ifndef FRIX_SHARED_DIR
#define FRIX_SHARED_DIR ""
#endif

/* The problem at FRIX_SHARED_DIR/fclib/<relative>, or NULL with a note when the shared data
 * directory is absent (e.g. a bare checkout): such tests then pass instead of failing. */
static inline frix_problem *load(const char *relative) {
    char path[4096];
    snprintf(path, sizeof path, "%s/fclib/%s", FRIX_SHARED_DIR, relative);
    if (access(path, R_OK) != 0) {
        fprintf(stderr, "note: %s not found, test skipped\n", path);
        return NULL;
    }
    frix_problem *p = NULL;
    ck_assert_msg(frix_fclib_read(path, &p) == FRIX_OK, "%s: %s", path, frix_last_error_message());
    return p;
}

/* A local problem of ../shared/fclib in other units per contact: contact a's r scaled by
 * 1/d_a and u by d_a, i.e. W' = D W D, q' = D q, with d_a = 10^(decades * t_a) and t_a spread
 * over [-1, 1] deterministically. The same problem (a solution of one maps to the other's), but
 * its diagonal blocks spread over 4 x decades more decades. Owns what its problem borrows. */
typedef struct {
    frix_problem *original, *p;
    frix_matrix *W;
    double *q;
} scaled_problem;

/* 0 when the shared data is absent (the test then passes). */
static inline int scaled_problem_load(scaled_problem *s, const char *relative, double decades) {
    s->original = load(relative);
    if (!s->original) return 0;
    const frix_matrix *W = frix_problem_W(s->original);
    const int64_t nc = frix_problem_contacts(s->original), m = 3 * nc;
    int64_t nnz = 0;
    ck_assert_int_eq(frix_matrix_to_csc(W, &nnz, NULL, NULL, NULL), FRIX_OK);
    int64_t *colptr = malloc((size_t)(m + 1) * sizeof *colptr), *rows = malloc((size_t)nnz * sizeof *rows);
    double *vals = malloc((size_t)nnz * sizeof *vals), *d = malloc((size_t)nc * sizeof *d);
    ck_assert_int_eq(frix_matrix_to_csc(W, &nnz, colptr, rows, vals), FRIX_OK);
    for (int64_t a = 0; a < nc; ++a) d[a] = pow(10.0, decades * (double)((a * 7) % 9 - 4) / 4.0);
    for (int64_t j = 0; j < m; ++j)
        for (int64_t k = colptr[j]; k < colptr[j + 1]; ++k) vals[k] *= d[rows[k] / 3] * d[j / 3];
    ck_assert_int_eq(frix_matrix_from_csc(m, m, colptr, rows, vals, &s->W), FRIX_OK);
    s->q = malloc((size_t)m * sizeof *s->q);
    const double *q = frix_problem_q(s->original);
    for (int64_t i = 0; i < m; ++i) s->q[i] = q[i] * d[i / 3];
    ck_assert_int_eq(frix_problem_local(s->W, s->q, frix_problem_mu(s->original), nc, &s->p), FRIX_OK);
    free(colptr);
    free(rows);
    free(vals);
    free(d);
    return 1;
}

static inline void scaled_problem_free(scaled_problem *s) {
    frix_problem_free(s->p);
    frix_matrix_free(s->W);
    free(s->q);
    frix_problem_free(s->original);
}

/* The 28 local problems of ../shared/fclib (local/ and converted/, as its MANIFEST advises). */
static const char *const kFclibLocalProblems[] = {
    "local/Capsules-i125-1213.hdf5",
    "local/LMGC_100_PR_PerioBox-i00361-60-03000.hdf5",
    "local/local_problem_test.hdf5",
    "converted/Box_Stacks-i0035-31-0.reduced.hdf5",
    "converted/Capsules-i100-1090.from_dat.hdf5",
    "converted/Capsules-i101-404.from_dat.hdf5",
    "converted/Confeti-ex03-Fc3D-SBM.from_dat.hdf5",
    "converted/Confeti-ex13-4contact-Fc3D-SBM.from_dat.hdf5",
    "converted/CubeH8.reduced.hdf5",
    "converted/FC3D_Example1.from_dat.hdf5",
    "converted/FrictionContact3D_1c.from_dat.hdf5",
    "converted/GFC3D_Example0.from_dat.hdf5",
    "converted/GFC3D_Example00_badly_scaled.from_dat.hdf5",
    "converted/GFC3D_Example1_v2.from_dat.hdf5",
    "converted/GFC3D_TwoRods1.from_dat.hdf5",
    "converted/LMGC_GFC3D-i00501-4-00000.reduced.hdf5",
    "converted/NESpheres_10_1.from_dat.hdf5",
    "converted/OneObject-i100000-316.from_dat.hdf5",
    "converted/OneObject-i1028-138.from_dat.hdf5",
    "converted/RockPile_tob1.from_dat.hdf5",
    "converted/Rover1039.from_dat.hdf5",
    "converted/Rover1040.from_dat.hdf5",
    "converted/Rover11035.from_dat.hdf5",
    "converted/Rover3865.from_dat.hdf5",
    "converted/Rover4396.from_dat.hdf5",
    "converted/Rover4516.from_dat.hdf5",
    "converted/Rover4613.from_dat.hdf5",
    "converted/spheres-in-a-box-98-i10000-256-10.reduced.hdf5",
};
#define FRIX_FCLIB_LOCAL_COUNT ((int)(sizeof kFclibLocalProblems / sizeof kFclibLocalProblems[0]))

#endif
