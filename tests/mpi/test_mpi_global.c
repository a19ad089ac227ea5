/* libfrix_mpi's nsgs on global problems (mpi_fixtures.h says how these programs run): a
 * global problem reduced on the root and solved by all, and rigid bodies in product form
 * (H^T's blocks and M's, no W) with the velocities the ranks return; every distributed form
 * reports the serial default measure of its answer. */
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

/* Whether a distributed value x is the serial measure's y of the same answer: to 1e-10 of it,
 * or both at rounding (1e-14: u and M v - H r - f are summed in another order). */
static int same_measure(double x, double y) { return fabs(x - y) <= 1e-10 * fabs(y) + 1e-14; }

/* Options of `solver` at tol and max_iter, on the default measure. */
static frix_options *default_options(int solver, double tol, int max_iter) {
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(solver, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, tol), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_MAX_ITER, max_iter), FRIX_OK);
    return o;
}

/* Whether the error, contact part and equilibrium part a distributed run reported (info) are
 * frix_problem_measure's of the gathered (r, v) on the whole problem p (v: NULL for a local
 * problem; NaN equilibrium where the form has no v: a reduced problem, whose v = M^-1 (H r + f)
 * is in equilibrium by its definition). */
static int measured_as_serial(const frix_problem *p, const double *r, const double *v, const frix_info *info,
                              const char *what) {
    frix_info *serial = NULL;
    double contact = NAN, equilibrium = NAN, mine_contact = NAN, mine_equilibrium = NAN;
    int ok;
    ck_assert_int_eq(frix_info_create(&serial), FRIX_OK);
    ck_assert_int_eq(frix_problem_measure(p, r, v, NULL, serial), FRIX_OK);
    frix_info_get_double(serial, FRIX_INFO_ERROR_CONTACT, &contact);
    frix_info_get_double(serial, FRIX_INFO_EQUILIBRIUM_SCALED, &equilibrium);
    frix_info_get_double(info, FRIX_INFO_ERROR_CONTACT, &mine_contact);
    frix_info_get_double(info, FRIX_INFO_EQUILIBRIUM_SCALED, &mine_equilibrium);
    ok = same_measure(frix_info_error(info), frix_info_error(serial)) && same_measure(mine_contact, contact) &&
         (isnan(mine_equilibrium) ? !v || equilibrium <= 1e-14 : same_measure(mine_equilibrium, equilibrium));
    if (g_rank == 0 || !ok)
        printf("%s, %d ranks: %s after %d, error %.9e (contact %.9e, equilibrium %.3e); libfrix: %.9e (%.9e, %.3e)%s\n",
               what, g_size, frix_status_string(frix_info_status(info)), (int)frix_info_iterations(info),
               frix_info_error(info), mine_contact, mine_equilibrium, frix_info_error(serial), contact, equilibrium,
               ok ? "" : " DIFFERENT");
    frix_info_free(serial);
    return ok;
}

/* A global problem (a pyramid of spheres) reduced on rank 0 and solved by all: the gathered
 * reactions, with the velocities they give, meet the tolerance on the global problem's
 * default measure, which the ranks computed too. */
START_TEST(a_global_problem_reduced_on_the_root) {
    frix_scene_params sp;
    frix_scene scene;
    frix_scene_problems forms;
    frix_options *o = default_options(FRIX_SOLVER_NSGS, 1e-8, 20000);
    outcome d;
    double *v, measured = 1.0;
    int ok;
    frix_scene_defaults(FRIX_SCENE_SPHERES, &sp);
    sp.count = 5;
    ck_assert_int_eq(frix_scene_build(&sp, &scene, NULL), FRIX_OK);
    ck_assert_int_eq(frix_scene_problems_make(&scene, &forms), FRIX_OK);
    d = solve_distributed(MPI_COMM_WORLD, forms.global, NULL, o, NULL, NULL);
    v = calloc((size_t)scene.n, sizeof(double));
    frix_scene_velocity(&scene, d.r, v);
    ck_assert_int_eq(frix_problem_error(forms.global, d.r, v, &measured), FRIX_OK);
    if (g_rank == 0)
        printf("spheres, %d layers, %lld contacts, %d ranks: %s after %d sweeps, error %.4e (libfrix: %.4e)\n",
               sp.count, (long long)scene.nc, g_size, frix_status_string(d.status), (int)d.iterations, d.error,
               measured);
    ok = d.status == FRIX_STATUS_CONVERGED && measured <= 1e-8 * (1.0 + 1e-6) && same_measure(d.error, measured);
    free(v);
    outcome_free(&d);
    frix_scene_problems_free(&forms);
    frix_scene_free(&scene);
    frix_options_free(o);
    ck_assert_msg(all_true(MPI_COMM_WORLD, ok), "the reduced global problem missed its tolerance");
}
END_TEST

/* Rigid bodies in product form, on 1 to 4 ranks: the reactions gathered, with the velocities
 * they give, meet the global measure's tolerance; the error, contact and equilibrium parts
 * reported, converged and after one sweep, are frix_problem_measure's of them; the ranks'
 * velocities are those; the same bits twice. Refusals: a contact on a body not given, a singular mass block. */
START_TEST(rigid_bodies_without_w) {
    frix_scene_params sp;
    frix_scene scene;
    frix_scene_problems forms;
    frix_mpi_context *ctx = NULL;
    frix_options *o = default_options(FRIX_SOLVER_NSGS, 1e-8, 20000);
    frix_options *one_sweep = default_options(FRIX_SOLVER_NSGS, 1e-8, 1);
    int ok = 1, pass;
    double *first_r = NULL;
    frix_scene_defaults(FRIX_SCENE_SPHERES, &sp);
    sp.count = 5;
    ck_assert_int_eq(frix_scene_build(&sp, &scene, NULL), FRIX_OK);
    ck_assert_int_eq(frix_scene_problems_make(&scene, &forms), FRIX_OK);
    ck_assert_int_eq(frix_mpi_context_create(MPI_COMM_WORLD, &ctx), FRIX_OK);
    {
        const int64_t nc = scene.nc, base = nc / g_size, extra = nc % g_size;
        const int64_t first = g_rank * base + (g_rank < extra ? g_rank : extra), owned = base + (g_rank < extra);
        /* Passes 0 and 1: every rank gives every body; pass 2: the bodies its contacts touch;
         * pass 3: one sweep. */
        for (pass = 0; pass < 4; ++pass) {
            frix_mpi_problem *p = NULL;
            int64_t held = 0, *ids = NULL;
            frix_info *info = NULL;
            double *r = calloc(3 * (size_t)owned + 1, sizeof(double)), *u = calloc(3 * (size_t)owned + 1, sizeof(double));
            double *r_all = calloc(3 * (size_t)nc, sizeof(double)), *v = calloc((size_t)scene.n, sizeof(double));
            double *v_ranks = calloc((size_t)scene.n, sizeof(double)), measured = 1.0, worst = 0.0;
            int64_t i;
            ck_assert_msg(rigid_part(ctx, &scene, first, owned, pass != 2, &p, &held, &ids) == FRIX_OK, "%s",
                          frix_mpi_last_error_message());
            ck_assert_int_eq(frix_mpi_problem_velocities(p, v_ranks), FRIX_ERR_INVALID_ARGUMENT); /* not solved */
            ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
            ck_assert_msg(frix_mpi_solve(p, pass == 3 ? one_sweep : o, r, u, info) == FRIX_OK, "%s",
                          frix_mpi_last_error_message());
            ck_assert_int_eq(frix_mpi_gather(p, 0, r, r_all), FRIX_OK);
            MPI_Bcast(r_all, (int)(3 * nc), MPI_DOUBLE, 0, MPI_COMM_WORLD);
            frix_scene_velocity(&scene, r_all, v);
            ck_assert_int_eq(frix_problem_error(forms.global, r_all, v, &measured), FRIX_OK);
            ok = measured_as_serial(forms.global, r_all, v, info, "rigid spheres, nsgs") && ok;
            ck_assert_int_eq(frix_mpi_problem_velocities(p, v_ranks), FRIX_OK);
            for (i = 0; i < 6 * held; ++i) {
                const double exact = v[6 * ids[i / 6] + i % 6];
                worst = fmax(worst, fabs(v_ranks[i] - exact) / (1.0 + fabs(exact)));
            }
            if (g_rank == 0 && (pass == 0 || pass == 2))
                printf("rigid spheres, %lld contacts, %d ranks, %s bodies: %s after %d sweeps, error %.4e (libfrix: "
                       "%.4e), velocities within %.1e\n",
                       (long long)nc, g_size, pass == 0 ? "all" : "touched", frix_status_string(frix_info_status(info)), (int)frix_info_iterations(info),
                       frix_info_error(info), measured, worst);
            if ((pass < 3 && (frix_info_status(info) != FRIX_STATUS_CONVERGED || !(measured <= 1e-8 * (1.0 + 1e-6)))) ||
                !same_measure(frix_info_error(info), measured) || !(worst <= 1e-12))
                ok = 0;
            if (pass == 0)
                first_r = r_all;
            else {
                if (pass == 1) ok = ok && memcmp(first_r, r_all, 3 * (size_t)nc * sizeof(double)) == 0;
                free(r_all);
            }
            free(ids);
            free(r);
            free(u);
            free(v);
            free(v_ranks);
            frix_info_free(info);
            frix_mpi_problem_free(p);
        }
        /* A contact on a body this rank did not give (the last rank gives none), and a
         * singular mass block (every rank). */
        {
            frix_mpi_problem *p = NULL;
            const int64_t held = g_rank == g_size - 1 ? 0 : 1, one = 0;
            double M[36] = {0}, f[6] = {0};
            frix_error e = frix_mpi_problem_rigid(ctx, first, owned, scene.body + 2 * first, scene.G + 36 * first,
                                                  scene.w + 3 * first, scene.mu + first, held, &one, M, f, &p);
            ok = ok && e == FRIX_ERR_INVALID_ARGUMENT && p == NULL;
            e = frix_mpi_problem_rigid(ctx, 0, 0, NULL, NULL, NULL, NULL, 1, &one, M, f, &p);
            ok = ok && e == FRIX_ERR_NUMERICAL && p == NULL;
        }
    }
    free(first_r);
    frix_mpi_context_free(ctx);
    frix_options_free(o);
    frix_options_free(one_sweep);
    frix_scene_problems_free(&forms);
    frix_scene_free(&scene);
    ck_assert_msg(all_true(MPI_COMM_WORLD, ok), "the distributed rigid bodies are not as the global problem");
}
END_TEST

/* Solves the whole problem p scattered from rank 0 (reduced there if global) and gathers r to
 * every rank (3 nc values, freed by the caller); info receives the run's measures. */
static double *scattered_solve(const frix_problem *p, const frix_options *o, frix_info *info) {
    const int64_t nc = frix_problem_contacts(p);
    frix_mpi_context *ctx = NULL;
    frix_mpi_problem *dist = NULL;
    int64_t owned = 0;
    double *r, *u, *r_all = calloc(3 * (size_t)nc + 1, sizeof(double));
    ck_assert_int_eq(frix_mpi_context_create(MPI_COMM_WORLD, &ctx), FRIX_OK);
    ck_assert_msg(frix_mpi_problem_scatter(ctx, 0, g_rank == 0 ? p : NULL, NULL, &dist) == FRIX_OK, "%s",
                  frix_mpi_last_error_message());
    frix_mpi_problem_get_int(dist, FRIX_MPI_OWNED, &owned);
    r = calloc(3 * (size_t)owned + 1, sizeof(double));
    u = calloc(3 * (size_t)owned + 1, sizeof(double));
    ck_assert_msg(frix_mpi_solve(dist, o, r, u, info) == FRIX_OK, "%s", frix_mpi_last_error_message());
    ck_assert_int_eq(frix_mpi_gather(dist, 0, r, r_all), FRIX_OK);
    MPI_Bcast(r_all, (int)(3 * nc), MPI_DOUBLE, 0, MPI_COMM_WORLD);
    free(r);
    free(u);
    frix_mpi_problem_free(dist);
    frix_mpi_context_free(ctx);
    return r_all;
}

/* Every distributed form reports the serial default measure of its answer: the error and its
 * contact part that nsgs and nsn-ac report after one iteration (where they are large) and at
 * the end (converged, but for nsn-ac's 30 steps on the spheres) are frix_problem_measure's of
 * the gathered answer on the whole problem: local problems (a chain, the spheres' W) and the
 * spheres' global problem reduced on the root (v = M^-1 (H r + f)); rigid bodies:
 * rigid_bodies_without_w. */
START_TEST(every_form_measures_as_the_serial_problem) {
    frix_scene_params sp;
    frix_scene scene;
    frix_scene_problems forms;
    frix_matrix *W = NULL;
    chain c = chain_make(40);
    frix_problem *chained = chain_problem(&c, &W);
    const int solvers[2] = {FRIX_SOLVER_NSGS, FRIX_SOLVER_NSN_AC};
    int ok = 1, k, s, steps;
    frix_scene_defaults(FRIX_SCENE_SPHERES, &sp);
    sp.count = 5;
    ck_assert_int_eq(frix_scene_build(&sp, &scene, NULL), FRIX_OK);
    ck_assert_int_eq(frix_scene_problems_make(&scene, &forms), FRIX_OK);
    for (k = 0; k < 3; ++k)
        for (s = 0; s < 2; ++s)
            for (steps = 0; steps < 2; ++steps) {
                const frix_problem *p = k == 0 ? chained : k == 1 ? forms.local : forms.global;
                const char *names[3] = {"chain", "spheres' W", "spheres reduced"};
                /* nsn-ac needs many steps on the spheres (nsgs converges): 30 at most. */
                frix_options *o = default_options(solvers[s], 1e-8, steps == 0 ? 1 : s == 0 ? 3000 : 30);
                frix_info *info = NULL;
                double *r, *v = calloc((size_t)scene.n + 1, sizeof(double));
                char what[96];
                ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
                r = scattered_solve(p, o, info);
                if (k == 2) frix_scene_velocity(&scene, r, v);
                snprintf(what, sizeof what, "%s, %s", names[k], s == 0 ? "nsgs" : "nsn-ac");
                ok = measured_as_serial(p, r, k == 2 ? v : NULL, info, what) && ok;
                if (steps == 1 && (s == 0 || k == 0)) ok = ok && frix_info_status(info) == FRIX_STATUS_CONVERGED;
                free(r);
                free(v);
                frix_info_free(info);
                frix_options_free(o);
            }
    frix_scene_problems_free(&forms);
    frix_scene_free(&scene);
    frix_problem_free(chained);
    frix_matrix_free(W);
    chain_free(&c);
    ck_assert_msg(all_true(MPI_COMM_WORLD, ok), "a distributed form does not report the serial measure of its answer");
}
END_TEST

int main(int argc, char **argv) {
    mpi_test_start(&argc, &argv);
    Suite *s = suite_create("mpi");
    TCase *tc = tcase_create("global");
    tcase_set_timeout(tc, 0);
    tcase_add_test(tc, a_global_problem_reduced_on_the_root);
    tcase_add_test(tc, rigid_bodies_without_w);
    tcase_add_test(tc, every_form_measures_as_the_serial_problem);
    suite_add_tcase(s, tc);
    return mpi_test_run(s);
}
