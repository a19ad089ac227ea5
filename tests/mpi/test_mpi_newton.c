/* libfrix_mpi's Newton solvers on PETSc with MUMPS (mpi_fixtures.h says how these programs
 * run): nsn-ac over the ranks and on the halves of a split communicator; gnsn-ac on global
 * problems with the host's M, scattered or given as each rank's rows; and, in the build that
 * starts PETSc itself, the problem given as the host's PETSc objects. */
#include <check.h>
#include <frix/frix.h>
#include <frix/frix_mpi.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../check_main.h"
#include "mpi_fixtures.h"
#include "elastic_grid.h"
#include "unit_cases.h"

/* The distributed Newton (nsn-ac, PETSc with MUMPS): on all ranks (a chain, and two shared
 * problems cut by Scotch), the gathered answer meets the tolerance by libfrix's measure and
 * two runs agree (to the bit on one rank); then on the halves of a split communicator at once (PETSc
 * started on each half, by the first context that needs it, and stopped with it). */
static int newton_case(MPI_Comm comm, const frix_problem *p, double tol, int use_parts, const char *what) {
    frix_options *o = NULL;
    int ok = 1, rank = 0, size = 1, *part = NULL;
    const int64_t nc = frix_problem_contacts(p);
    outcome a, b;
    double measured = 1.0;
    MPI_Comm_rank(comm, &rank);
    MPI_Comm_size(comm, &size);
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_NSN_AC, &o), FRIX_OK);
    frix_test_siconos_measure(o);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, tol), FRIX_OK);
    if (use_parts) {
        frix_mpi_context *ctx = NULL;
        part = calloc((size_t)nc + 1, sizeof(int));
        ck_assert_int_eq(frix_mpi_context_create(comm, &ctx), FRIX_OK);
        ck_assert_int_eq(frix_mpi_partition(ctx, 0, rank == 0 ? p : NULL, part), FRIX_OK);
        frix_mpi_context_free(ctx);
    }
    a = solve_distributed(comm, p, part, o, NULL, NULL);
    b = solve_distributed(comm, p, part, o, NULL, NULL);
    ck_assert_int_eq(siconos_error(p, a.r, NULL, &measured), FRIX_OK);
    if (rank == 0)
        printf("nsn-ac, %s, %d ranks: %s after %d Newton steps, error %.4e (libfrix: %.4e)\n", what, size,
               frix_status_string(a.status), (int)a.iterations, a.error, measured);
    /* MUMPS's factorisation over 2 ranks or more schedules its tasks as they come: its rounding,
     * and so the last bits of the answer, may change from run to run (seen on spheres-in-a-box,
     * once in 8 runs at 2 ranks, every run at 4); on one rank it gives the same bits. */
    ok = a.status == FRIX_STATUS_CONVERGED && measured <= tol * (1.0 + 1e-6) &&
         (size == 1 ? same_bits(&a, &b, 3 * nc)
                    : a.iterations == b.iterations && b.status == a.status && fabs(a.error - b.error) <= 1e-3 * a.error);
    if (!ok && rank == 0)
        fprintf(stderr, "nsn-ac, %s: %s, %d and %d steps, errors %.17g and %.17g\n", what,
                same_bits(&a, &b, 3 * nc) ? "the same bits" : "other bits", (int)a.iterations, (int)b.iterations,
                a.error, b.error);
    outcome_free(&a);
    outcome_free(&b);
    free(part);
    frix_options_free(o);
    return ok;
}

START_TEST(newton_over_the_ranks) {
    chain c = chain_make(40 * g_size);
    frix_matrix *W = NULL;
    frix_problem *p = chain_problem(&c, &W);
    frix_problem *capsules = shared_problem("fclib/converted/Capsules-i101-404.from_dat.hdf5");
    frix_problem *box = shared_problem("fclib/converted/spheres-in-a-box-98-i10000-256-10.reduced.hdf5");
    int ok = newton_case(MPI_COMM_WORLD, p, 1e-10, 0, "chain");
    if (capsules) ok = newton_case(MPI_COMM_WORLD, capsules, 1e-8, 1, "Capsules-i101-404") && ok;
    if (box) ok = newton_case(MPI_COMM_WORLD, box, 1e-8, 1, "spheres-in-a-box") && ok;
    if (g_size >= 2) {
        MPI_Comm half;
        MPI_Comm_split(MPI_COMM_WORLD, g_rank < g_size / 2, g_rank, &half);
        ok = newton_case(half, p, 1e-10, 0, "chain, a half") && ok;
        MPI_Comm_free(&half);
    }
    frix_problem_free(capsules);
    frix_problem_free(box);
    frix_problem_free(p);
    frix_matrix_free(W);
    chain_free(&c);
    ck_assert_msg(all_true(MPI_COMM_WORLD, ok), "the distributed Newton missed its tolerance or changed between runs");
}
END_TEST

/* ---- Global problems with the host's M, solved by gnsn-ac over the ranks' rows of (v, r). */

/* A distributed global solve: r and v gathered to every rank (3nc and n values). */
typedef struct {
    frix_status status;
    int64_t iterations;
    double error, equilibrium, error_contact, equilibrium_scaled;
    double *r, *v;
} global_outcome;

static void global_outcome_free(global_outcome *o) {
    free(o->r);
    free(o->v);
}

static frix_options *gnsn_options(double tol) {
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_GLOBAL_NSN_AC, &o), FRIX_OK);
    frix_test_siconos_measure(o);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, tol), FRIX_OK);
    return o;
}

/* Solves `dist` (a global problem with the host's M) from r = 0, or from the whole problem's
 * warm_r (3nc values, NULL: none), and gathers r (by the contacts' ids) and v (the dofs in rank
 * order) to every rank. */
static global_outcome solve_global_from(MPI_Comm comm, frix_mpi_problem *dist, const frix_options *o, int64_t nc,
                                        int64_t n, const double *warm_r) {
    global_outcome out;
    frix_info *info = NULL;
    int64_t owned = 0, dofs = 0, dof_first = 0;
    int size = 1, k, *counts, *at, mine;
    double *r, *u, *v;
    MPI_Comm_size(comm, &size);
    frix_mpi_problem_get_int(dist, FRIX_MPI_OWNED, &owned);
    frix_mpi_problem_get_int(dist, FRIX_MPI_DOFS, &dofs);
    frix_mpi_problem_get_int(dist, FRIX_MPI_DOF_FIRST, &dof_first);
    r = calloc((size_t)(3 * owned) + 1, sizeof(double));
    u = calloc((size_t)(3 * owned) + 1, sizeof(double));
    v = calloc((size_t)dofs + 1, sizeof(double));
    if (warm_r) {
        int64_t a, *ids = calloc((size_t)owned + 1, sizeof(int64_t));
        ck_assert_int_eq(frix_mpi_problem_ids(dist, ids), FRIX_OK);
        for (a = 0; a < owned; ++a) memcpy(r + 3 * a, warm_r + 3 * ids[a], 3 * sizeof(double));
        free(ids);
    }
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_msg(frix_mpi_solve(dist, o, r, u, info) == FRIX_OK, "%s", frix_mpi_last_error_message());
    ck_assert_int_eq(frix_mpi_problem_velocities(dist, v), FRIX_OK);
    out.status = frix_info_status(info);
    out.iterations = frix_info_iterations(info);
    out.error = frix_info_error(info);
    frix_info_get_double(info, FRIX_INFO_EQUILIBRIUM, &out.equilibrium);
    frix_info_get_double(info, FRIX_INFO_ERROR_CONTACT, &out.error_contact);
    frix_info_get_double(info, FRIX_INFO_EQUILIBRIUM_SCALED, &out.equilibrium_scaled);
    out.r = calloc((size_t)(3 * nc) + 1, sizeof(double));
    out.v = calloc((size_t)n + 1, sizeof(double));
    ck_assert_int_eq(frix_mpi_gather(dist, 0, r, out.r), FRIX_OK);
    MPI_Bcast(out.r, (int)(3 * nc), MPI_DOUBLE, 0, comm);
    counts = calloc((size_t)size, sizeof(int));
    at = calloc((size_t)size, sizeof(int));
    mine = (int)dofs;
    MPI_Allgather(&mine, 1, MPI_INT, counts, 1, MPI_INT, comm);
    for (k = 1; k < size; ++k) at[k] = at[k - 1] + counts[k - 1];
    ck_assert_int_eq(at[size - 1] + counts[size - 1], (int)n);
    {
        int rank = 0;
        MPI_Comm_rank(comm, &rank);
        ck_assert_int_eq((int)dof_first, at[rank]);
    }
    MPI_Allgatherv(v, mine, MPI_DOUBLE, out.v, counts, at, MPI_DOUBLE, comm);
    free(counts);
    free(at);
    free(r);
    free(u);
    free(v);
    frix_info_free(info);
    return out;
}

static global_outcome solve_global_part(MPI_Comm comm, frix_mpi_problem *dist, const frix_options *o, int64_t nc,
                                        int64_t n) {
    return solve_global_from(comm, dist, o, nc, n, NULL);
}

/* The global problem p (read on every rank) scattered from rank 0 with its M (dofs in blocks,
 * contacts by Scotch's parts or in blocks) and solved twice by gnsn-ac at tol: converged, libfrix's
 * measure of the gathered (r, v) meets tol, v is near the serial gnsn-ac's (within 1e-3 of |v|:
 * with friction the answer need not be unique, and spheres-in-a-box's two differ by 2e-5), and
 * the two runs agree (to the bit on one rank). */
static int global_case(MPI_Comm comm, const frix_problem *p, double tol, int use_parts, const char *what) {
    const int64_t nc = frix_problem_contacts(p), n = frix_problem_dofs(p);
    frix_options *o = gnsn_options(tol);
    frix_mpi_context *ctx = NULL;
    frix_mpi_problem *dist = NULL;
    frix_info *info = NULL;
    global_outcome a, b;
    double *r = calloc((size_t)(3 * nc) + 1, sizeof(double)), *u = calloc((size_t)(3 * nc) + 1, sizeof(double));
    double *v = calloc((size_t)n + 1, sizeof(double));
    double dv = 0.0, vmax = 0.0, measured = 1.0, equilibrium = 1.0;
    int ok, rank = 0, size = 1, *part = NULL;
    int64_t i, serial_steps = 0;
    MPI_Comm_rank(comm, &rank);
    MPI_Comm_size(comm, &size);
    ck_assert_int_eq(frix_mpi_context_create(comm, &ctx), FRIX_OK);
    if (use_parts) {
        part = calloc((size_t)nc + 1, sizeof(int));
        ck_assert_int_eq(frix_mpi_partition(ctx, 0, rank == 0 ? p : NULL, part), FRIX_OK);
    }
    ck_assert_msg(frix_mpi_problem_scatter_global(ctx, 0, rank == 0 ? p : NULL, part, &dist) == FRIX_OK, "%s",
                  frix_mpi_last_error_message());
    a = solve_global_part(comm, dist, o, nc, n);
    frix_mpi_problem_free(dist);
    ck_assert_int_eq(frix_mpi_problem_scatter_global(ctx, 0, rank == 0 ? p : NULL, part, &dist), FRIX_OK);
    b = solve_global_part(comm, dist, o, nc, n);
    frix_mpi_problem_free(dist);
    frix_mpi_context_free(ctx);
    /* The serial gnsn-ac, and libfrix's measure of the distributed answer. */
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_msg(frix_solve(p, o, r, u, v, info) == FRIX_OK, "%s", frix_last_error_message());
    serial_steps = frix_info_iterations(info);
    for (i = 0; i < n; ++i) {
        dv = fmax(dv, fabs(a.v[i] - v[i]));
        vmax = fmax(vmax, fabs(v[i]));
    }
    ck_assert_int_eq(frix_problem_measure(p, a.r, a.v, NULL, info), FRIX_OK);
    ck_assert_int_eq(frix_info_get_double(info, FRIX_INFO_ERROR_RELATIVE, &measured), FRIX_OK);
    frix_info_get_double(info, FRIX_INFO_EQUILIBRIUM, &equilibrium);
    if (rank == 0)
        printf("gnsn-ac, %s, %d ranks: %s after %d Newton steps, error %.4e, equilibrium %.2e (libfrix: %.4e, %.2e); "
               "|v - v_serial| %.2e of %.2e (serial: %d steps)\n",
               what, size, frix_status_string(a.status), (int)a.iterations, a.error, a.equilibrium, measured, equilibrium,
               dv, vmax, (int)serial_steps);
    ok = a.status == FRIX_STATUS_CONVERGED && measured <= tol * (1.0 + 1e-6) && equilibrium <= tol * (1.0 + 1e-6) &&
         dv <= 1e-3 * fmax(vmax, 1e-300) &&
         (size == 1 ? a.iterations == b.iterations && memcmp(a.r, b.r, (size_t)(3 * nc) * sizeof(double)) == 0 &&
                          memcmp(a.v, b.v, (size_t)n * sizeof(double)) == 0
                    : a.iterations == b.iterations && b.status == a.status);
    if (!ok && rank == 0)
        fprintf(stderr, "gnsn-ac, %s: %s, %d and %d steps, errors %.17g and %.17g\n", what, frix_status_string(a.status),
                (int)a.iterations, (int)b.iterations, a.error, b.error);
    global_outcome_free(&a);
    global_outcome_free(&b);
    frix_info_free(info);
    frix_options_free(o);
    free(part);
    free(r);
    free(u);
    free(v);
    return ok;
}

/* This rank's rows of the grid's M (symmetric: its columns) and of H^T (H's columns), in the
 * blocks frix_mpi_problem_scatter_global deals (the first ranks one more). */
static frix_mpi_problem *grid_rows(frix_mpi_context *ctx, const frix_elastic_grid *g, int64_t dof_shift,
                                   int refused) {
    const frix_problem *p = g->problem;
    const int64_t nc = frix_problem_contacts(p), n = frix_problem_dofs(p);
    const int64_t dofs = n / g_size + (g_rank < n % g_size), dof_first = g_rank * (n / g_size) + (g_rank < n % g_size ? g_rank : n % g_size);
    const int64_t owned = nc / g_size + (g_rank < nc % g_size), first = g_rank * (nc / g_size) + (g_rank < nc % g_size ? g_rank : nc % g_size);
    int64_t m_nnz = 0, h_nnz = 0, i;
    int64_t *m_ptr = calloc((size_t)n + 1, sizeof(int64_t)), *m_row = NULL, *h_ptr = calloc((size_t)(3 * nc) + 1, sizeof(int64_t)), *h_row = NULL;
    double *m_val = NULL, *h_val = NULL;
    frix_mpi_problem *out = NULL;
    frix_error e;
    ck_assert_int_eq(frix_matrix_to_csc(g->M, &m_nnz, NULL, NULL, NULL), FRIX_OK);
    ck_assert_int_eq(frix_matrix_to_csc(g->H, &h_nnz, NULL, NULL, NULL), FRIX_OK);
    m_row = calloc((size_t)m_nnz + 1, sizeof(int64_t));
    m_val = calloc((size_t)m_nnz + 1, sizeof(double));
    h_row = calloc((size_t)h_nnz + 1, sizeof(int64_t));
    h_val = calloc((size_t)h_nnz + 1, sizeof(double));
    ck_assert_int_eq(frix_matrix_to_csc(g->M, &m_nnz, m_ptr, m_row, m_val), FRIX_OK);
    ck_assert_int_eq(frix_matrix_to_csc(g->H, &h_nnz, h_ptr, h_row, h_val), FRIX_OK);
    {
        int64_t *mp = calloc((size_t)dofs + 1, sizeof(int64_t)), *hp = calloc((size_t)(3 * owned) + 1, sizeof(int64_t));
        for (i = 0; i <= dofs; ++i) mp[i] = m_ptr[dof_first + i] - m_ptr[dof_first];
        for (i = 0; i <= 3 * owned; ++i) hp[i] = h_ptr[3 * first + i] - h_ptr[3 * first];
        e = frix_mpi_problem_global(ctx, dof_first + dof_shift, dofs, mp, m_row + m_ptr[dof_first],
                                    m_val + m_ptr[dof_first], g->f + dof_first, first, owned, hp,
                                    h_row + h_ptr[3 * first], h_val + h_ptr[3 * first], g->w + 3 * first, g->mu + first,
                                    &out);
        ck_assert_msg(refused ? e == FRIX_ERR_DIMENSION && !out : e == FRIX_OK, "%d: %s", (int)e,
                      frix_mpi_last_error_message());
        free(mp);
        free(hp);
    }
    free(m_ptr);
    free(m_row);
    free(m_val);
    free(h_ptr);
    free(h_row);
    free(h_val);
    return out;
}

START_TEST(the_hosts_mass_matrix) {
    frix_elastic_grid grid;
    frix_problem *files[4] = {shared_problem("fclib/global/CubeH8.hdf5"),
                              shared_problem("fclib/global/Box_Stacks-i0035-31-0.hdf5"),
                              shared_problem("fclib/global/LMGC_GFC3D-i00501-4-00000.hdf5"),
                              shared_problem("fclib/global/spheres-in-a-box-98-i10000-256-10.hdf5")};
    const char *names[4] = {"CubeH8", "Box_Stacks-i0035", "LMGC_GFC3D-i00501", "spheres-in-a-box (global)"};
    frix_mpi_context *ctx = NULL;
    frix_mpi_problem *rows = NULL, *scattered = NULL;
    frix_options *o = gnsn_options(1e-8), *nsgs = nsgs_options(1e-8);
    const int64_t n_grid = 6 * 6 * 3 * 3, nc_grid = 36;
    global_outcome x, y;
    int ok = 1, k;
    ck_assert_int_eq(frix_elastic_grid_make(6, 6, 3, 0.1, 1e4, &grid), FRIX_OK);
    ok = global_case(MPI_COMM_WORLD, grid.problem, 1e-8, 0, "elastic grid 6x6x3") && ok;
    for (k = 0; k < 4; ++k)
        if (files[k]) ok = global_case(MPI_COMM_WORLD, files[k], 1e-8, k % 2, names[k]) && ok;
    if (g_size >= 2) {
        MPI_Comm half;
        MPI_Comm_split(MPI_COMM_WORLD, g_rank < g_size / 2, g_rank, &half);
        ok = global_case(half, grid.problem, 1e-8, 0, "elastic grid 6x6x3, a half") && ok;
        MPI_Comm_free(&half);
    }
    /* The rows given by each rank are the problem frix_mpi_problem_scatter_global deals: the
     * same answer (to the bit on one rank; MUMPS's rounding may vary over more). */
    ck_assert_int_eq(frix_mpi_context_create(MPI_COMM_WORLD, &ctx), FRIX_OK);
    rows = grid_rows(ctx, &grid, 0, 0);
    ck_assert_int_eq(frix_mpi_problem_scatter_global(ctx, 0, g_rank == 0 ? grid.problem : NULL, NULL, &scattered),
                     FRIX_OK);
    x = solve_global_part(MPI_COMM_WORLD, rows, o, nc_grid, n_grid);
    y = solve_global_part(MPI_COMM_WORLD, scattered, o, nc_grid, n_grid);
    if (g_size == 1)
        ok = ok && x.iterations == y.iterations && memcmp(x.r, y.r, 3 * nc_grid * sizeof(double)) == 0 &&
             memcmp(x.v, y.v, n_grid * sizeof(double)) == 0;
    else {
        double d = 0.0, big = 0.0;
        for (k = 0; k < 3 * nc_grid; ++k) d = fmax(d, fabs(x.r[k] - y.r[k])), big = fmax(big, fabs(y.r[k]));
        ok = ok && x.iterations == y.iterations && d <= 1e-10 * big;
    }
    /* Refusals: nsgs on such a problem; a local problem to scatter_global; dofs out of order. */
    {
        double r[3 * 36] = {0}, u[3 * 36] = {0};
        frix_mpi_problem *none = NULL;
        ok = ok && frix_mpi_solve(rows, nsgs, r, u, NULL) == FRIX_ERR_UNSUPPORTED;
        chain c = chain_make(10);
        frix_matrix *W = NULL;
        frix_problem *local = chain_problem(&c, &W);
        ok = ok && frix_mpi_problem_scatter_global(ctx, 0, local, NULL, &none) == FRIX_ERR_INVALID_ARGUMENT && !none;
        frix_problem_free(local);
        frix_matrix_free(W);
        chain_free(&c);
        if (g_size >= 2) grid_rows(ctx, &grid, g_rank == 1 ? 1 : 0, 1); /* rank 1's dofs start one late */
    }
    global_outcome_free(&x);
    global_outcome_free(&y);
    frix_mpi_problem_free(rows);
    frix_mpi_problem_free(scattered);
    frix_mpi_context_free(ctx);
    for (k = 0; k < 4; ++k) frix_problem_free(files[k]);
    frix_elastic_grid_free(&grid);
    frix_options_free(o);
    frix_options_free(nsgs);
    ck_assert_msg(all_true(MPI_COMM_WORLD, ok), "gnsn-ac over the ranks missed its tolerance, the serial v, or its bits");
}
END_TEST

/* From a warm r on a soft elastic grid (ADMM's answer at 1e-3), the distributed gnsn-ac
 * starts from v = M^-1 (H r + f), as the serial one: 1e-8 in at most 2 Newton steps (from the
 * same r with v = 0 it took 7). */
START_TEST(a_warm_start_keeps_its_velocity) {
    frix_elastic_grid grid;
    frix_options *admm = NULL, *o = gnsn_options(1e-8);
    frix_mpi_context *ctx = NULL;
    frix_mpi_problem *dist = NULL;
    ck_assert_int_eq(frix_elastic_grid_make(20, 20, 4, 0.2, 1e4, &grid), FRIX_OK);
    const frix_problem *p = grid.problem;
    const int64_t nc = frix_problem_contacts(p), n = frix_problem_dofs(p);
    double *r = calloc((size_t)(3 * nc), sizeof(double)), *u = calloc((size_t)(3 * nc), sizeof(double));
    double *v = calloc((size_t)n, sizeof(double));
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_GLOBAL_ADMM, &admm), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(admm, FRIX_OPT_TOLERANCE, 1e-3), FRIX_OK);
    ck_assert_msg(frix_solve(p, admm, r, u, v, NULL) == FRIX_OK, "%s", frix_last_error_message());
    ck_assert_int_eq(frix_mpi_context_create(MPI_COMM_WORLD, &ctx), FRIX_OK);
    ck_assert_int_eq(frix_mpi_problem_scatter_global(ctx, 0, g_rank == 0 ? p : NULL, NULL, &dist), FRIX_OK);
    global_outcome warm = solve_global_from(MPI_COMM_WORLD, dist, o, nc, n, r);
    if (g_rank == 0)
        printf("gnsn-ac from ADMM's 1e-3 answer, %d ranks: %s after %d Newton steps, error %.3e\n", g_size,
               frix_status_string(warm.status), (int)warm.iterations, warm.error);
    ck_assert_msg(all_true(MPI_COMM_WORLD,
                           warm.status == FRIX_STATUS_CONVERGED && warm.error <= 1e-8 && warm.iterations <= 2),
                  "%s after %d steps, error %g", frix_status_string(warm.status), (int)warm.iterations, warm.error);
    global_outcome_free(&warm);
    frix_mpi_problem_free(dist);
    frix_mpi_context_free(ctx);
    frix_options_free(admm);
    frix_options_free(o);
    frix_elastic_grid_free(&grid);
    free(r), free(u), free(v);
}
END_TEST

/* Whether a distributed value x is the serial measure's y of the same answer: to 1e-10 of it,
 * or both at rounding (1e-14: u = H^T v + w and M v - H r - f are summed in another order). */
static int same_measure(double x, double y) { return fabs(x - y) <= 1e-10 * fabs(y) + 1e-14; }

/* gnsn-ac over the ranks on p (scattered from rank 0) with the default measure at tol,
 * max_iter steps at most: its reported error, contact part and equilibrium part are
 * frix_problem_measure's of the gathered (r, v). *out: the outcome (free it). */
static int measured_as_serial(const frix_problem *p, double tol, int max_iter, const char *what,
                              global_outcome *out) {
    const int64_t nc = frix_problem_contacts(p), n = frix_problem_dofs(p);
    frix_options *o = NULL;
    frix_mpi_context *ctx = NULL;
    frix_mpi_problem *dist = NULL;
    frix_info *info = NULL;
    double error = NAN, contact = NAN, equilibrium = NAN;
    int ok;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_GLOBAL_NSN_AC, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, tol), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_MAX_ITER, max_iter), FRIX_OK);
    ck_assert_int_eq(frix_mpi_context_create(MPI_COMM_WORLD, &ctx), FRIX_OK);
    ck_assert_msg(frix_mpi_problem_scatter_global(ctx, 0, g_rank == 0 ? p : NULL, NULL, &dist) == FRIX_OK, "%s",
                  frix_mpi_last_error_message());
    *out = solve_global_part(MPI_COMM_WORLD, dist, o, nc, n);
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_problem_measure(p, out->r, out->v, NULL, info), FRIX_OK);
    error = frix_info_error(info);
    frix_info_get_double(info, FRIX_INFO_ERROR_CONTACT, &contact);
    frix_info_get_double(info, FRIX_INFO_EQUILIBRIUM_SCALED, &equilibrium);
    ok = same_measure(out->error, error) && same_measure(out->error_contact, contact) &&
         same_measure(out->equilibrium_scaled, equilibrium);
    if (g_rank == 0)
        printf("gnsn-ac, %s, %d ranks, at most %d steps: %s after %d, error %.9e (contact %.9e, equilibrium %.9e); "
               "libfrix: %.9e (%.9e, %.9e)\n",
               what, g_size, max_iter, frix_status_string(out->status), (int)out->iterations, out->error,
               out->error_contact, out->equilibrium_scaled, error, contact, equilibrium);
    frix_info_free(info);
    frix_mpi_problem_free(dist);
    frix_mpi_context_free(ctx);
    frix_options_free(o);
    return ok;
}

/* The default measure over the ranks is the serial one: the error gnsn-ac reports of its
 * answer (after 1 step, where it is large, and converged) is frix_problem_measure's of the
 * gathered (r, v), on the rigid cube, the clamped elastic block, the elastic grid and two
 * shared FEM files (LMGC_GFC3D's floor is the load's velocity: H^T D^-1 f is 0 there); and the
 * cube and the block in three unit systems converge, with the same normal reactions, and with
 * the same error to 3 digits where they took the same steps. (The steps themselves may
 * differ: MUMPS's pivoting of the Jacobian, whose rows mix units, may turn the Newton's
 * regularisation on in one system and not in another, as on the block at 1 rank.) */
START_TEST(the_serial_measure_over_the_ranks) {
    frix_elastic_grid grid;
    frix_problem *files[2] = {shared_problem("fclib/global/CubeH8.hdf5"),
                              shared_problem("fclib/global/LMGC_GFC3D-i00501-4-00000.hdf5")};
    const char *names[2] = {"CubeH8", "LMGC_GFC3D-i00501"};
    int ok = 1, shape, k, steps;
    ck_assert_int_eq(frix_elastic_grid_make(6, 6, 3, 0.1, 1e4, &grid), FRIX_OK);
    for (k = 0; k < 3; ++k)
        for (steps = 0; steps < 2; ++steps) {
            const frix_problem *p = k == 0 ? grid.problem : files[k - 1];
            global_outcome out;
            if (!p) continue;
            ok = measured_as_serial(p, 1e-8, steps == 0 ? 1 : 100, k == 0 ? "elastic grid 6x6x3" : names[k - 1], &out) &&
                 ok;
            global_outcome_free(&out);
        }
    for (k = 0; k < 2; ++k) frix_problem_free(files[k]);
    for (shape = 0; shape < 2; ++shape) {
        global_outcome first = {FRIX_STATUS_CONVERGED, 0, 0.0, 0.0, 0.0, 0.0, NULL, NULL};
        double first_sum = 0.0;
        for (k = 0; k < 3; ++k) {
            const units un = kUnits[k];
            const double force = shape == 0 ? un.Mu * un.L / un.T : un.Mu * un.L / (un.T * un.T);
            char what[64];
            dense_case c;
            global_outcome out;
            double sum = 0.0;
            int64_t a;
            snprintf(what, sizeof what, "%s in %s", shape == 0 ? "rigid cube" : "clamped block 4x4x3", un.name);
            ck_assert_int_eq(shape == 0 ? rigid_cube(&c, un) : elastic_block(&c, 4, 4, 3, 1, 0.2, -1.0, un), FRIX_OK);
            for (steps = 0; steps < 2; ++steps) {
                ok = measured_as_serial(c.p, 1e-8, steps == 0 ? 1 : 100, what, &out) && ok;
                if (steps == 0) global_outcome_free(&out);
            }
            for (a = 0; a < c.nc; ++a) sum += out.r[3 * a] / force;
            ok = ok && out.status == FRIX_STATUS_CONVERGED && out.error <= 1e-8;
            if (k == 0) {
                first = out;
                first_sum = sum;
            } else {
                ok = ok && out.status == first.status && fabs(sum - first_sum) <= 1e-6 &&
                     (out.iterations != first.iterations ||
                      fabs(out.error - first.error) <= 1e-3 * fmax(out.error, first.error) + 1e-14);
                global_outcome_free(&out);
            }
            case_free(&c);
        }
        global_outcome_free(&first);
    }
    frix_elastic_grid_free(&grid);
    ck_assert_msg(all_true(MPI_COMM_WORLD, ok), "the distributed measure is not the serial one, or depends on the units");
}
END_TEST

#ifdef FRIX_TEST_PETSC_HOST
/* The host started PETSc (mpi_test_start, in this build): the chain given as PETSc objects
 * (an AIJ matrix, a vector) gives the problem its arrays give, to the bit; nsn-ac runs on the
 * host's PETSc, which is still there after the context is freed. */
START_TEST(the_hosts_petsc_objects) {
    const int64_t per_rank = 6, nc = per_rank * g_size, first = per_rank * g_rank;
    chain c = chain_make(nc);
    frix_mpi_context *ctx = NULL;
    frix_mpi_problem *from_petsc = NULL, *from_rows = NULL;
    frix_options *o = nsgs_options(1e-10), *newton = NULL;
    Mat W = NULL;
    Vec q = NULL;
    int64_t row_ptr[7], i, k;
    double r1[18] = {0}, u1[18] = {0}, r2[18] = {0}, u2[18] = {0};
    PetscBool still = PETSC_FALSE;
    int ok = 1;
    for (i = 0; i <= per_rank; ++i) row_ptr[i] = c.row_ptr[first + i] - c.row_ptr[first];
    ck_assert_int_eq(MatCreateAIJ(MPI_COMM_WORLD, (PetscInt)(3 * per_rank), (PetscInt)(3 * per_rank), PETSC_DETERMINE,
                                  PETSC_DETERMINE, 9, NULL, 6, NULL, &W),
                     0);
    ck_assert_int_eq(MatCreateVecs(W, NULL, &q), 0);
    for (i = first; i < first + per_rank; ++i) {
        for (k = c.row_ptr[i]; k < c.row_ptr[i + 1]; ++k) {
            int a, b;
            for (b = 0; b < 3; ++b)
                for (a = 0; a < 3; ++a) {
                    const PetscInt row = (PetscInt)(3 * c.rows[k] + a), col = (PetscInt)(3 * c.cols[k] + b);
                    ck_assert_int_eq(MatSetValue(W, row, col, c.vals[9 * k + a + 3 * b], INSERT_VALUES), 0);
                }
        }
        for (k = 0; k < 3; ++k) ck_assert_int_eq(VecSetValue(q, (PetscInt)(3 * i + k), c.q[3 * i + k], INSERT_VALUES), 0);
    }
    ck_assert_int_eq(MatAssemblyBegin(W, MAT_FINAL_ASSEMBLY), 0);
    ck_assert_int_eq(MatAssemblyEnd(W, MAT_FINAL_ASSEMBLY), 0);
    ck_assert_int_eq(VecAssemblyBegin(q), 0);
    ck_assert_int_eq(VecAssemblyEnd(q), 0);
    ck_assert_int_eq(frix_mpi_context_create(MPI_COMM_WORLD, &ctx), FRIX_OK);
    ck_assert_msg(frix_mpi_problem_petsc(ctx, W, q, c.mu + first, &from_petsc) == FRIX_OK, "%s",
                  frix_mpi_last_error_message());
    ck_assert_int_eq(frix_mpi_problem_local(ctx, first, per_rank, row_ptr, c.cols + c.row_ptr[first],
                                            c.vals + 9 * c.row_ptr[first], c.q + 3 * first, c.mu + first, &from_rows),
                     FRIX_OK);
    MatDestroy(&W); /* the problem holds copies */
    VecDestroy(&q);
    ck_assert_int_eq(frix_mpi_solve(from_petsc, o, r1, u1, NULL), FRIX_OK);
    ck_assert_int_eq(frix_mpi_solve(from_rows, o, r2, u2, NULL), FRIX_OK);
    ok = memcmp(r1, r2, sizeof r1) == 0 && memcmp(u1, u2, sizeof u1) == 0;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_NSN_AC, &newton), FRIX_OK);
    frix_test_siconos_measure(newton);
    memset(r1, 0, sizeof r1);
    ok = ok && frix_mpi_solve(from_petsc, newton, r1, u1, NULL) == FRIX_OK;
    frix_mpi_problem_free(from_petsc);
    frix_mpi_problem_free(from_rows);
    frix_mpi_context_free(ctx);
    PetscInitialized(&still);
    ok = ok && still == PETSC_TRUE;
    /* W on a communicator the context does not share is refused on every rank. */
    if (g_size > 1) {
        Mat alone = NULL;
        frix_mpi_problem *none = NULL;
        ck_assert_int_eq(frix_mpi_context_create(MPI_COMM_WORLD, &ctx), FRIX_OK);
        ck_assert_int_eq(MatCreateAIJ(PETSC_COMM_SELF, 3, 3, 3, 3, 1, NULL, 0, NULL, &alone), 0);
        ck_assert_int_eq(MatAssemblyBegin(alone, MAT_FINAL_ASSEMBLY), 0);
        ck_assert_int_eq(MatAssemblyEnd(alone, MAT_FINAL_ASSEMBLY), 0);
        ok = ok && frix_mpi_problem_petsc(ctx, alone, NULL, c.mu, &none) == FRIX_ERR_INVALID_ARGUMENT && !none;
        MatDestroy(&alone);
        frix_mpi_context_free(ctx);
    }
    frix_options_free(o);
    frix_options_free(newton);
    chain_free(&c);
    ck_assert_msg(all_true(MPI_COMM_WORLD, ok), "the host's PETSc objects did not give the problem of their arrays");
}
END_TEST
#endif

#ifdef FRIX_TEST_PETSC_HOST
/* The grid's M, f, H^T and w as the host's PETSc objects, in the blocks of grid_rows, give the
 * answer of the rows given as arrays; a matrix of the wrong shape is refused on every rank. */
START_TEST(the_hosts_petsc_mass_matrix) {
    frix_elastic_grid grid;
    frix_mpi_context *ctx = NULL;
    frix_mpi_problem *from_petsc = NULL, *from_rows = NULL, *none = NULL;
    frix_options *o = gnsn_options(1e-8);
    int64_t n, nc, dofs, dof_first, owned, first, m_nnz = 0, h_nnz = 0, i, k;
    int64_t *m_ptr, *m_row, *h_ptr, *h_row;
    double *m_val, *h_val, d = 0.0, big = 0.0;
    Mat M = NULL, Ht = NULL;
    Vec f = NULL, w = NULL;
    global_outcome x, y;
    int ok = 1;
    ck_assert_int_eq(frix_elastic_grid_make(6, 6, 3, 0.1, 1e4, &grid), FRIX_OK);
    n = frix_problem_dofs(grid.problem);
    nc = frix_problem_contacts(grid.problem);
    dofs = n / g_size + (g_rank < n % g_size);
    dof_first = g_rank * (n / g_size) + (g_rank < n % g_size ? g_rank : n % g_size);
    owned = nc / g_size + (g_rank < nc % g_size);
    first = g_rank * (nc / g_size) + (g_rank < nc % g_size ? g_rank : nc % g_size);
    ck_assert_int_eq(frix_matrix_to_csc(grid.M, &m_nnz, NULL, NULL, NULL), FRIX_OK);
    ck_assert_int_eq(frix_matrix_to_csc(grid.H, &h_nnz, NULL, NULL, NULL), FRIX_OK);
    m_ptr = calloc((size_t)n + 1, sizeof(int64_t));
    h_ptr = calloc((size_t)(3 * nc) + 1, sizeof(int64_t));
    m_row = calloc((size_t)m_nnz + 1, sizeof(int64_t));
    h_row = calloc((size_t)h_nnz + 1, sizeof(int64_t));
    m_val = calloc((size_t)m_nnz + 1, sizeof(double));
    h_val = calloc((size_t)h_nnz + 1, sizeof(double));
    ck_assert_int_eq(frix_matrix_to_csc(grid.M, &m_nnz, m_ptr, m_row, m_val), FRIX_OK);
    ck_assert_int_eq(frix_matrix_to_csc(grid.H, &h_nnz, h_ptr, h_row, h_val), FRIX_OK);
    ck_assert_int_eq(MatCreateAIJ(MPI_COMM_WORLD, (PetscInt)dofs, (PetscInt)dofs, PETSC_DETERMINE, PETSC_DETERMINE, 7,
                                  NULL, 7, NULL, &M),
                     0);
    ck_assert_int_eq(MatCreateAIJ(MPI_COMM_WORLD, (PetscInt)(3 * owned), (PetscInt)dofs, PETSC_DETERMINE,
                                  PETSC_DETERMINE, 3, NULL, 3, NULL, &Ht),
                     0);
    ck_assert_int_eq(MatCreateVecs(M, NULL, &f), 0);
    ck_assert_int_eq(MatCreateVecs(Ht, NULL, &w), 0);
    for (i = dof_first; i < dof_first + dofs; ++i) { /* M is symmetric: its column i is row i */
        for (k = m_ptr[i]; k < m_ptr[i + 1]; ++k)
            ck_assert_int_eq(MatSetValue(M, (PetscInt)i, (PetscInt)m_row[k], m_val[k], INSERT_VALUES), 0);
        ck_assert_int_eq(VecSetValue(f, (PetscInt)i, grid.f[i], INSERT_VALUES), 0);
    }
    for (i = 3 * first; i < 3 * (first + owned); ++i) {
        for (k = h_ptr[i]; k < h_ptr[i + 1]; ++k)
            ck_assert_int_eq(MatSetValue(Ht, (PetscInt)i, (PetscInt)h_row[k], h_val[k], INSERT_VALUES), 0);
        ck_assert_int_eq(VecSetValue(w, (PetscInt)i, grid.w[i], INSERT_VALUES), 0);
    }
    ck_assert_int_eq(MatAssemblyBegin(M, MAT_FINAL_ASSEMBLY), 0);
    ck_assert_int_eq(MatAssemblyEnd(M, MAT_FINAL_ASSEMBLY), 0);
    ck_assert_int_eq(MatAssemblyBegin(Ht, MAT_FINAL_ASSEMBLY), 0);
    ck_assert_int_eq(MatAssemblyEnd(Ht, MAT_FINAL_ASSEMBLY), 0);
    ck_assert_int_eq(VecAssemblyBegin(f), 0);
    ck_assert_int_eq(VecAssemblyEnd(f), 0);
    ck_assert_int_eq(VecAssemblyBegin(w), 0);
    ck_assert_int_eq(VecAssemblyEnd(w), 0);
    ck_assert_int_eq(frix_mpi_context_create(MPI_COMM_WORLD, &ctx), FRIX_OK);
    ck_assert_msg(frix_mpi_problem_petsc_global(ctx, M, f, Ht, w, grid.mu + first, &from_petsc) == FRIX_OK, "%s",
                  frix_mpi_last_error_message());
    /* w given for f: not in M's row layout. */
    ok = frix_mpi_problem_petsc_global(ctx, M, w, Ht, w, grid.mu + first, &none) == FRIX_ERR_DIMENSION && !none;
    MatDestroy(&M); /* the problem holds copies */
    MatDestroy(&Ht);
    VecDestroy(&f);
    VecDestroy(&w);
    from_rows = grid_rows(ctx, &grid, 0, 0);
    x = solve_global_part(MPI_COMM_WORLD, from_petsc, o, nc, n);
    y = solve_global_part(MPI_COMM_WORLD, from_rows, o, nc, n);
    for (k = 0; k < 3 * nc; ++k) d = fmax(d, fabs(x.r[k] - y.r[k])), big = fmax(big, fabs(y.r[k]));
    ok = ok && x.status == FRIX_STATUS_CONVERGED && x.iterations == y.iterations && d <= 1e-10 * big;
    global_outcome_free(&x);
    global_outcome_free(&y);
    frix_mpi_problem_free(from_petsc);
    frix_mpi_problem_free(from_rows);
    frix_mpi_context_free(ctx);
    free(m_ptr);
    free(h_ptr);
    free(m_row);
    free(h_row);
    free(m_val);
    free(h_val);
    frix_options_free(o);
    frix_elastic_grid_free(&grid);
    ck_assert_msg(all_true(MPI_COMM_WORLD, ok), "the host's PETSc M and H^T did not give the answer of their arrays");
}
END_TEST
#endif

int main(int argc, char **argv) {
    mpi_test_start(&argc, &argv);
    Suite *s = suite_create("mpi");
    TCase *tc = tcase_create("newton");
    tcase_set_timeout(tc, 0);
    tcase_add_test(tc, newton_over_the_ranks);
    tcase_add_test(tc, the_hosts_mass_matrix);
    tcase_add_test(tc, a_warm_start_keeps_its_velocity);
    tcase_add_test(tc, the_serial_measure_over_the_ranks);
#ifdef FRIX_TEST_PETSC_HOST
    tcase_add_test(tc, the_hosts_petsc_objects);
    tcase_add_test(tc, the_hosts_petsc_mass_matrix);
#endif
    suite_add_tcase(s, tc);
    return mpi_test_run(s);
}
