/* The libfrix_mpi test fixtures of mpi_fixtures.h. */
#include "mpi_fixtures.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "../check_main.h"

#ifndef FRIX_SHARED_DIR
#define FRIX_SHARED_DIR ""
#endif

int g_rank, g_size;

void mpi_test_start(int *argc, char ***argv) {
    MPI_Init(argc, argv);
#ifdef FRIX_TEST_PETSC_HOST
    /* This build is a host that starts PETSc itself: the library must use it and leave it. */
    PetscInitialize(argc, argv, NULL, NULL);
#endif
    MPI_Comm_rank(MPI_COMM_WORLD, &g_rank);
    MPI_Comm_size(MPI_COMM_WORLD, &g_size);
}

int mpi_test_run(Suite *s) {
    SRunner *sr = srunner_create(s);
    /* One process per rank: Check must not fork (MPI forbids it); CTest's timeout is the
     * guard against a rank left waiting. */
    srunner_set_fork_status(sr, CK_NOFORK);
    srunner_run_all(sr, g_rank == 0 ? CK_NORMAL : CK_SILENT);
    const int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
#ifdef FRIX_TEST_PETSC_HOST
    PetscFinalize();
#endif
    MPI_Finalize();
    return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}

int all_true(MPI_Comm comm, int ok) {
    int all = 0;
    MPI_Allreduce(&ok, &all, 1, MPI_INT, MPI_LAND, comm);
    return all;
}

frix_error siconos_error(const frix_problem *p, const double *r, const double *v, double *error) {
    frix_info *info = NULL;
    frix_error e = frix_info_create(&info);
    if (!e) e = frix_problem_measure(p, r, v, NULL, info);
    if (!e) e = frix_info_get_double(info, FRIX_INFO_ERROR_RELATIVE, error);
    frix_info_free(info);
    return e;
}

frix_problem *shared_problem(const char *relative) {
    char path[4096];
    frix_problem *p = NULL;
    snprintf(path, sizeof path, "%s/%s", FRIX_SHARED_DIR, relative);
    if (access(path, R_OK) != 0) {
        if (g_rank == 0) fprintf(stderr, "note: %s not found, test skipped\n", path);
        return NULL;
    }
    ck_assert_msg(frix_fclib_read(path, &p) == FRIX_OK, "%s: %s", path, frix_last_error_message());
    return p;
}

frix_options *nsgs_options(double tol) {
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_NSGS, &o), FRIX_OK);
    frix_test_siconos_measure(o);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, tol), FRIX_OK);
    return o;
}

void outcome_free(outcome *o) {
    free(o->r);
    free(o->u);
}

outcome solve_serial(const frix_problem *p, const frix_options *o, const double *r0) {
    const int64_t m = 3 * frix_problem_contacts(p);
    outcome out;
    frix_info *info = NULL;
    out.r = calloc((size_t)m + 1, sizeof(double));
    out.u = calloc((size_t)m + 1, sizeof(double));
    if (r0) memcpy(out.r, r0, (size_t)m * sizeof(double));
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_msg(frix_solve(p, o, out.r, out.u, NULL, info) == FRIX_OK, "%s", frix_last_error_message());
    out.status = frix_info_status(info);
    out.iterations = frix_info_iterations(info);
    out.error = frix_info_error(info);
    frix_info_free(info);
    return out;
}

outcome solve_part(MPI_Comm comm, frix_mpi_problem *dist, const frix_options *o, const double *r0, int64_t nc) {
    const int64_t m = 3 * nc;
    frix_info *info = NULL;
    int64_t owned = 0, i, *ids;
    outcome out;
    double *r, *u;
    frix_mpi_problem_get_int(dist, FRIX_MPI_OWNED, &owned);
    r = calloc((size_t)(3 * owned) + 1, sizeof(double));
    u = calloc((size_t)(3 * owned) + 1, sizeof(double));
    ids = calloc((size_t)owned + 1, sizeof(int64_t));
    ck_assert_int_eq(frix_mpi_problem_ids(dist, ids), FRIX_OK);
    if (r0)
        for (i = 0; i < owned; ++i) memcpy(r + 3 * i, r0 + 3 * ids[i], 3 * sizeof(double));
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_msg(frix_mpi_solve(dist, o, r, u, info) == FRIX_OK, "%s", frix_mpi_last_error_message());
    out.status = frix_info_status(info);
    out.iterations = frix_info_iterations(info);
    out.error = frix_info_error(info);
    out.r = calloc((size_t)m + 1, sizeof(double));
    out.u = calloc((size_t)m + 1, sizeof(double));
    ck_assert_int_eq(frix_mpi_gather(dist, 0, r, out.r), FRIX_OK);
    ck_assert_int_eq(frix_mpi_gather(dist, 0, u, out.u), FRIX_OK);
    MPI_Bcast(out.r, (int)m, MPI_DOUBLE, 0, comm);
    MPI_Bcast(out.u, (int)m, MPI_DOUBLE, 0, comm);
    free(r);
    free(u);
    free(ids);
    frix_info_free(info);
    return out;
}

outcome solve_distributed(MPI_Comm comm, const frix_problem *p, const int *part, const frix_options *o,
                                 const double *r0, frix_mpi_problem **keep) {
    frix_mpi_context *ctx = NULL;
    frix_mpi_problem *dist = NULL;
    int rank = 0;
    outcome out;
    MPI_Comm_rank(comm, &rank);
    ck_assert_int_eq(frix_mpi_context_create(comm, &ctx), FRIX_OK);
    ck_assert_msg(frix_mpi_problem_scatter(ctx, 0, rank == 0 ? p : NULL, part, &dist) == FRIX_OK, "%s",
                  frix_mpi_last_error_message());
    out = solve_part(comm, dist, o, r0, frix_problem_contacts(p));
    if (keep)
        *keep = dist;
    else
        frix_mpi_problem_free(dist);
    frix_mpi_context_free(ctx);
    return out;
}

int same_bits(const outcome *a, const outcome *b, int64_t m) {
    return a->status == b->status && a->iterations == b->iterations &&
           memcmp(&a->error, &b->error, sizeof(double)) == 0 && memcmp(a->r, b->r, (size_t)m * sizeof(double)) == 0 &&
           memcmp(a->u, b->u, (size_t)m * sizeof(double)) == 0;
}

chain chain_make(int64_t nc) {
    chain c;
    int64_t i, k = 0;
    c.nc = nc;
    c.row_ptr = calloc((size_t)nc + 1, sizeof(int64_t));
    c.rows = calloc((size_t)(3 * nc), sizeof(int64_t));
    c.cols = calloc((size_t)(3 * nc), sizeof(int64_t));
    c.vals = calloc((size_t)(27 * nc), sizeof(double));
    c.q = calloc((size_t)(3 * nc), sizeof(double));
    c.mu = calloc((size_t)nc, sizeof(double));
    for (i = 0; i < nc; ++i) {
        int64_t j;
        for (j = i - 1; j <= i + 1; ++j) {
            int e;
            if (j < 0 || j >= nc) continue;
            c.rows[k] = i;
            c.cols[k] = j;
            for (e = 0; e < 9; ++e) {
                const int diag = e % 4 == 0;
                c.vals[9 * k + e] = j == i ? (diag ? 4.0 + 0.1 * (double)(i % 3) : 0.05 * (double)(e % 3))
                                           : (diag ? -1.0 : 0.02 * (double)(j > i ? 1 : -1));
            }
            ++k;
        }
        c.row_ptr[i + 1] = k;
        c.q[3 * i] = -1.0 - 0.25 * (double)(i % 5);
        c.q[3 * i + 1] = 0.6 * cos((double)i);
        c.q[3 * i + 2] = 0.6 * sin((double)i);
        c.mu[i] = 0.3 + 0.1 * (double)(i % 4);
    }
    c.nb = k;
    return c;
}

void chain_free(chain *c) {
    free(c->row_ptr);
    free(c->rows);
    free(c->cols);
    free(c->vals);
    free(c->q);
    free(c->mu);
}

frix_problem *chain_problem(const chain *c, frix_matrix **W) {
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_matrix_from_blocks(c->nc, c->nc, c->nb, c->rows, c->cols, c->vals, W), FRIX_OK);
    ck_assert_int_eq(frix_problem_local(*W, c->q, c->mu, c->nc, &p), FRIX_OK);
    return p;
}

frix_error rigid_part(frix_mpi_context *ctx, const frix_scene *scene, int64_t first, int64_t owned, int all,
                             frix_mpi_problem **out, int64_t *held, int64_t **ids_out) {
    const int64_t bodies = scene->bodies;
    int64_t *ids = calloc((size_t)bodies + 1, sizeof(int64_t)), b, i, n = 0;
    char *touched = calloc((size_t)bodies + 1, 1);
    double *M = calloc(36 * (size_t)bodies + 1, sizeof(double)), *f = calloc(6 * (size_t)bodies + 1, sizeof(double));
    frix_error e;
    int j;
    for (i = 2 * first; i < 2 * (first + owned); ++i)
        if (scene->body[i] >= 0) touched[scene->body[i]] = 1;
    for (b = 0; b < bodies; ++b) {
        if (!all && !touched[b]) continue;
        ids[n] = b;
        for (j = 0; j < 6; ++j) {
            M[36 * n + 7 * j] = 1.0 / scene->minv[6 * b + j];
            f[6 * n + j] = scene->f[6 * b + j];
        }
        ++n;
    }
    e = frix_mpi_problem_rigid(ctx, first, owned, scene->body + 2 * first, scene->G + 36 * first, scene->w + 3 * first,
                               scene->mu + first, n, ids, M, f, out);
    *held = n;
    *ids_out = ids;
    free(touched);
    free(M);
    free(f);
    return e;
}
