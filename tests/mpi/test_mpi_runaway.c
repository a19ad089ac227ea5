/* libfrix_mpi on problems without a solution (mpi_fixtures.h says how these programs run):
 * every distributed form ends a runaway as frix_solve does, DIVERGED within a few iterations of
 * a large limit, with a finite answer: the start, or an r whose error is below half of the
 * start's (notes/2026-11-28-rolling-trust.md, the serial rule). */
#include <check.h>
#include <frix/frix.h>
#include <frix/frix_mpi.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../check_main.h"
#include "mpi_fixtures.h"
#include "scenes.h"

/* The limit the runs are given, and the iterations a diverged run may have taken: the Monitor
 * checks for a runaway every few iterations, and stops it within a few hundred. */
enum { kLimit = 100000, kFewIterations = 1000 };

/* The runs checked, each (bodies in the row, warm start or r = 0): those on which frix_solve's
 * run ends diverged. On the others (6 bodies from the warm start for nsgs and nsn-ac, 1 body
 * from r = 0 for gnsn-ac) r drifts below the bound, in the serial runs as in the distributed
 * ones, which end as they do (notes/2026-11-28-mpi-runaway.md). */
typedef struct {
    int bodies, warm;
} run_case;
static const run_case kSweepCases[3] = {{1, 0}, {1, 1}, {6, 0}};
static const run_case kGlobalNewtonCases[3] = {{1, 1}, {6, 0}, {6, 1}};

/* The pushed row: k bodies of unit mass in a row along x, contact c (c < k) between body c and
 * body c-1 (the wall for c = 0), normal +x, approaching at unit speed (w_N = -1); and contact
 * k on the last body, pressed too (w_N = -1) along a normal that reaches no dof (its tangents
 * reach the body's y and z): u_N = -1 there whatever r, so no r solves the problem, and its
 * reactions run away. With the contacts dealt in blocks, the last one is the last rank's: the
 * other ranks see no runaway of their own. */
static void pushed_row(int k, frix_scene *s) {
    const int64_t nc = k + 1;
    int64_t c;
    int i;
    memset(s, 0, sizeof *s);
    s->bodies = k;
    s->nc = nc;
    s->n = 6 * (int64_t)k;
    s->minv = malloc((size_t)s->n * sizeof(double));
    s->f = calloc((size_t)s->n, sizeof(double));
    s->w = calloc(3 * (size_t)nc, sizeof(double));
    s->mu = malloc((size_t)nc * sizeof(double));
    s->body = malloc(2 * (size_t)nc * sizeof(int64_t));
    s->G = calloc(36 * (size_t)nc, sizeof(double));
    s->frame = calloc(9 * (size_t)nc, sizeof(double));
    for (i = 0; i < 6 * k; ++i) s->minv[i] = 1.0;
    for (c = 0; c < nc; ++c) {
        double *G = &s->G[36 * c];
        s->w[3 * c] = -1.0;
        s->mu[c] = 0.5;
        s->body[2 * c] = c < k ? c : k - 1;
        s->body[2 * c + 1] = c < k ? c - 1 : -1;
        for (i = 0; i < 3; ++i) {
            s->frame[9 * c + 4 * i] = 1.0;
            if (c == k && i == 0) continue;  /* the normal that reaches nothing */
            G[6 * i + i] = 1.0;              /* side 0: u += v_c along the frame */
            if (c < k && c > 0) G[18 + 6 * i + i] = -1.0;  /* side 1: u -= v_(c-1) */
        }
    }
    snprintf(s->title, sizeof s->title, "pushed row of %d bodies", k);
}

static frix_options *options_of(int solver) {
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(solver, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 1e-8), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_MAX_ITER, kLimit), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_EXISTENCE_CHECK, 0), FRIX_OK);
    return o;
}

/* The serial run of p from r0 (NULL: 0), v for a global problem. */
static outcome serial_run(const frix_problem *p, const frix_options *o, const double *r0, int64_t n) {
    const int64_t m = 3 * frix_problem_contacts(p);
    outcome out;
    frix_info *info = NULL;
    double *v = calloc((size_t)n + 1, sizeof(double));
    out.r = calloc((size_t)m + 1, sizeof(double));
    out.u = calloc((size_t)m + 1, sizeof(double));
    if (r0) memcpy(out.r, r0, (size_t)m * sizeof(double));
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_msg(frix_solve(p, o, out.r, out.u, n > 0 ? v : NULL, info) == FRIX_OK, "%s", frix_last_error_message());
    out.status = frix_info_status(info);
    out.iterations = frix_info_iterations(info);
    out.error = frix_info_error(info);
    frix_info_free(info);
    free(v);
    return out;
}

/* The default measure of the answer r (3 nc, gathered) of the scene's problem p (global: with
 * v = M^-1 (H r + f)). */
static double error_of(const frix_problem *p, const frix_scene *s, const double *r) {
    double *v = calloc((size_t)s->n + 1, sizeof(double)), e = NAN;
    const int global = frix_problem_get_kind(p) == FRIX_PROBLEM_GLOBAL;
    if (global) frix_scene_velocity(s, r, v);
    ck_assert_int_eq(frix_problem_error(p, r, global ? v : NULL, &e), FRIX_OK);
    free(v);
    return e;
}

/* Whether the distributed run d ended as the serial run `serial` of the same problem p (the
 * scene's, from r0; NULL: 0) must: both DIVERGED, d within kFewIterations, its answer finite and
 * the start, or an r whose error is below half of the start's. */
static int ends_diverged(const char *what, const frix_problem *p, const frix_scene *s, const outcome *serial,
                         const outcome *d, const double *r0) {
    const int64_t m = 3 * s->nc;
    double *start = calloc((size_t)m, sizeof(double)), largest = 0.0, start_error, error;
    int64_t i;
    int ok, finite = 1, is_start;
    if (r0) memcpy(start, r0, (size_t)m * sizeof(double));
    for (i = 0; i < m; ++i) {
        finite = finite && isfinite(d->r[i]);
        largest = fmax(largest, fabs(d->r[i]));
    }
    is_start = memcmp(start, d->r, (size_t)m * sizeof(double)) == 0;
    start_error = error_of(p, s, start);
    error = finite ? error_of(p, s, d->r) : NAN;
    ok = serial->status == FRIX_STATUS_DIVERGED && d->status == FRIX_STATUS_DIVERGED &&
         d->iterations < kFewIterations && finite && (is_start || error < 0.5 * start_error);
    if (g_rank == 0 || !ok)
        printf("%s, %s start, %d ranks: %s after %d (serial: %s after %d), max |r| %.3g%s, error %.3g (start %.3g)%s\n",
               what, r0 ? "warm" : "cold", g_size, frix_status_string(d->status), (int)d->iterations,
               frix_status_string(serial->status), (int)serial->iterations, largest, is_start ? " (the start)" : "",
               error, start_error, ok ? "" : " WRONG");
    free(start);
    return ok;
}

/* A warm start for the pushed row: each contact pressed a little and sliding. */
static double *warm_start(int64_t nc) {
    double *r = malloc(3 * (size_t)nc * sizeof(double));
    int64_t c;
    for (c = 0; c < nc; ++c) r[3 * c] = 0.5, r[3 * c + 1] = 0.1, r[3 * c + 2] = 0.0;
    return r;
}

/* Whether values x (count) are, to rounding, v[at[i]] (at: NULL for v[i]). */
static int near_values(const double *x, const double *v, const int64_t *at, int64_t count) {
    int64_t i;
    int ok = 1;
    for (i = 0; i < count; ++i) {
        const double exact = v[at ? at[i] : i];
        ok = ok && fabs(x[i] - exact) <= 1e-9 * (1.0 + fabs(exact));
    }
    return ok;
}

/* The local problem (W's rows) and the global one reduced on the root, scattered in blocks of
 * contacts: nsgs and nsn-ac end DIVERGED as frix_solve does; at one rank nsgs gives its bits. */
START_TEST(the_scattered_forms_end_diverged) {
    frix_scene scene;
    frix_scene_problems forms;
    const int solvers[2] = {FRIX_SOLVER_NSGS, FRIX_SOLVER_NSN_AC};
    int ok = 1, k, s, form;
    for (k = 0; k < 3; ++k) {
        pushed_row(kSweepCases[k].bodies, &scene);
        ck_assert_int_eq(frix_scene_problems_make(&scene, &forms), FRIX_OK);
        for (form = 0; form < 2; ++form)
            for (s = 0; s < 2; ++s) {
                const frix_problem *p = form == 0 ? forms.local : forms.global;
                frix_options *o = options_of(solvers[s]);
                double *r0 = kSweepCases[k].warm ? warm_start(scene.nc) : NULL;
                outcome serial = serial_run(p, o, r0, form == 0 ? 0 : scene.n);
                outcome d = solve_distributed(MPI_COMM_WORLD, p, NULL, o, r0, NULL);
                char what[256];
                snprintf(what, sizeof what, "%s, %s, %s", scene.title, form == 0 ? "W's rows" : "reduced",
                         s == 0 ? "nsgs" : "nsn-ac");
                ok = ends_diverged(what, p, &scene, &serial, &d, r0) && ok;
                if (g_size == 1 && s == 0) ok = ok && same_bits(&serial, &d, 3 * scene.nc);
                outcome_free(&serial);
                outcome_free(&d);
                free(r0);
                frix_options_free(o);
            }
        frix_scene_problems_free(&forms);
        frix_scene_free(&scene);
    }
    ck_assert_msg(all_true(MPI_COMM_WORLD, ok), "a scattered form without a solution did not end diverged");
}
END_TEST

/* The pushed row of k bodies as a global problem the ranks hold without W: rigid bodies in
 * product form (frix_mpi_problem_rigid, each rank its block of contacts and the bodies they
 * touch) run by nsgs, or rows of M and H^T (frix_mpi_problem_scatter_global) run by gnsn-ac.
 * Whether the run ends as ends_diverged says, with the velocities the ranks return those of
 * its answer. */
static int held_without_w(frix_mpi_context *ctx, int rigid, run_case rc) {
    frix_scene scene;
    frix_scene_problems forms;
    frix_options *o = options_of(rigid ? FRIX_SOLVER_NSGS : FRIX_SOLVER_GLOBAL_NSN_AC);
    const int64_t nc = rc.bodies + 1, base = nc / g_size, extra = nc % g_size;
    const int64_t first = g_rank * base + (g_rank < extra ? g_rank : extra), owned = base + (g_rank < extra);
    frix_mpi_problem *p = NULL;
    int64_t held = 0, *ids = NULL, *at = NULL, count = 0, first_dof = 0, i;
    double *r0 = rc.warm ? warm_start(nc) : NULL, *v_ranks, *v;
    outcome serial, d;
    int ok;
    pushed_row(rc.bodies, &scene);
    ck_assert_int_eq(frix_scene_problems_make(&scene, &forms), FRIX_OK);
    serial = serial_run(forms.global, o, r0, scene.n);
    if (rigid)
        ck_assert_msg(rigid_part(ctx, &scene, first, owned, 0, &p, &held, &ids) == FRIX_OK, "%s",
                      frix_mpi_last_error_message());
    else
        ck_assert_msg(frix_mpi_problem_scatter_global(ctx, 0, g_rank == 0 ? forms.global : NULL, NULL, &p) == FRIX_OK,
                      "%s", frix_mpi_last_error_message());
    d = solve_part(MPI_COMM_WORLD, p, o, r0, nc);
    ok = ends_diverged(rigid ? "rigid, nsgs" : "host's M, gnsn-ac", forms.global, &scene, &serial, &d, r0);
    /* The velocities the ranks return: 6 a body held, or those of this rank's dofs. */
    if (rigid) {
        count = 6 * held;
        at = calloc((size_t)count + 1, sizeof(int64_t));
        for (i = 0; i < count; ++i) at[i] = 6 * ids[i / 6] + i % 6;
    } else {
        frix_mpi_problem_get_int(p, FRIX_MPI_DOFS, &count);
        frix_mpi_problem_get_int(p, FRIX_MPI_DOF_FIRST, &first_dof);
    }
    v_ranks = calloc((size_t)count + 1, sizeof(double));
    v = calloc((size_t)scene.n, sizeof(double));
    frix_scene_velocity(&scene, d.r, v);
    ck_assert_int_eq(frix_mpi_problem_velocities(p, v_ranks), FRIX_OK);
    ok = near_values(v_ranks, v + first_dof, at, count) && ok;
    free(at);
    free(v);
    free(v_ranks);
    outcome_free(&serial);
    outcome_free(&d);
    free(ids);
    free(r0);
    frix_mpi_problem_free(p);
    frix_options_free(o);
    frix_scene_problems_free(&forms);
    frix_scene_free(&scene);
    return ok;
}

/* Rigid bodies in product form: nsgs ends DIVERGED as frix_solve does on the global problem. */
START_TEST(rigid_bodies_end_diverged) {
    frix_mpi_context *ctx = NULL;
    int ok = 1, c;
    ck_assert_int_eq(frix_mpi_context_create(MPI_COMM_WORLD, &ctx), FRIX_OK);
    for (c = 0; c < 3; ++c) ok = held_without_w(ctx, 1, kSweepCases[c]) && ok;
    frix_mpi_context_free(ctx);
    ck_assert_msg(all_true(MPI_COMM_WORLD, ok), "rigid bodies without a solution did not end diverged");
}
END_TEST

/* A global problem with the host's M: gnsn-ac ends DIVERGED as the serial gnsn-ac does. */
START_TEST(the_hosts_mass_matrix_ends_diverged) {
    frix_mpi_context *ctx = NULL;
    int ok = 1, c;
    ck_assert_int_eq(frix_mpi_context_create(MPI_COMM_WORLD, &ctx), FRIX_OK);
    for (c = 0; c < 3; ++c) ok = held_without_w(ctx, 0, kGlobalNewtonCases[c]) && ok;
    frix_mpi_context_free(ctx);
    ck_assert_msg(all_true(MPI_COMM_WORLD, ok), "a global problem with the host's M did not end diverged");
}
END_TEST

int main(int argc, char **argv) {
    mpi_test_start(&argc, &argv);
    Suite *s = suite_create("mpi");
    TCase *tc = tcase_create("runaway");
    tcase_set_timeout(tc, 0);
    tcase_add_test(tc, the_scattered_forms_end_diverged);
    tcase_add_test(tc, rigid_bodies_end_diverged);
    tcase_add_test(tc, the_hosts_mass_matrix_ends_diverged);
    suite_add_tcase(s, tc);
    return mpi_test_run(s);
}
