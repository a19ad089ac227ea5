/* libfrix_mpi's nsgs on global problems (mpi_fixtures.h says how these programs run): a
 * global problem reduced on the root and solved by all, and rigid bodies in product form
 * (H^T's blocks and M's, no W) with the velocities the ranks return. */
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

/* A global problem (a pyramid of spheres) reduced on rank 0 and solved by all: the gathered
 * reactions, with the velocities they give, meet the tolerance on the global measure (scale
 * |w|), which the ranks computed too. */
START_TEST(a_global_problem_reduced_on_the_root) {
    frix_scene_params sp;
    frix_scene scene;
    frix_scene_problems forms;
    frix_options *o = nsgs_options(1e-8);
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
    ck_assert_int_eq(siconos_error(forms.global, d.r, v, &measured), FRIX_OK);
    if (g_rank == 0)
        printf("spheres, %d layers, %lld contacts, %d ranks: %s after %d sweeps, error %.4e (libfrix: %.4e)\n",
               sp.count, (long long)scene.nc, g_size, frix_status_string(d.status), (int)d.iterations, d.error,
               measured);
    ok = d.status == FRIX_STATUS_CONVERGED && measured <= 1e-8 * (1.0 + 1e-6) &&
         fabs(measured - d.error) <= 1e-6 * d.error;
    free(v);
    outcome_free(&d);
    frix_scene_problems_free(&forms);
    frix_scene_free(&scene);
    frix_options_free(o);
    ck_assert_msg(all_true(MPI_COMM_WORLD, ok), "the reduced global problem missed its tolerance");
}
END_TEST

/* A scene of rigid bodies given as H^T's blocks and M's, each rank its block of contacts and
 * every body (all: a rank may give more bodies than its contacts touch), or only the bodies
 * its contacts touch; *held and *ids: how many and which (free *ids). */
static frix_error rigid_part(frix_mpi_context *ctx, const frix_scene *scene, int64_t first, int64_t owned, int all,
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

/* Rigid bodies in product form, on 1 to 4 ranks: the reactions gathered, with the velocities
 * they give, meet the global measure's tolerance; the ranks' velocities are those; the same bits
 * twice. Refusals: a contact on a body not given, a singular mass block. */
START_TEST(rigid_bodies_without_w) {
    frix_scene_params sp;
    frix_scene scene;
    frix_scene_problems forms;
    frix_mpi_context *ctx = NULL;
    frix_options *o = nsgs_options(1e-8);
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
        /* Passes 0 and 1: every rank gives every body; pass 2: the bodies its contacts touch. */
        for (pass = 0; pass < 3; ++pass) {
            frix_mpi_problem *p = NULL;
            int64_t held = 0, *ids = NULL;
            frix_info *info = NULL;
            double *r = calloc(3 * (size_t)owned + 1, sizeof(double)), *u = calloc(3 * (size_t)owned + 1, sizeof(double));
            double *r_all = calloc(3 * (size_t)nc, sizeof(double)), *v = calloc((size_t)scene.n, sizeof(double));
            double *v_ranks = calloc((size_t)scene.n, sizeof(double)), measured = 1.0, worst = 0.0;
            int64_t i;
            ck_assert_msg(rigid_part(ctx, &scene, first, owned, pass < 2, &p, &held, &ids) == FRIX_OK, "%s",
                          frix_mpi_last_error_message());
            ck_assert_int_eq(frix_mpi_problem_velocities(p, v_ranks), FRIX_ERR_INVALID_ARGUMENT); /* not solved */
            ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
            ck_assert_msg(frix_mpi_solve(p, o, r, u, info) == FRIX_OK, "%s", frix_mpi_last_error_message());
            ck_assert_int_eq(frix_mpi_gather(p, 0, r, r_all), FRIX_OK);
            MPI_Bcast(r_all, (int)(3 * nc), MPI_DOUBLE, 0, MPI_COMM_WORLD);
            frix_scene_velocity(&scene, r_all, v);
            ck_assert_int_eq(siconos_error(forms.global, r_all, v, &measured), FRIX_OK);
            ck_assert_int_eq(frix_mpi_problem_velocities(p, v_ranks), FRIX_OK);
            for (i = 0; i < 6 * held; ++i) {
                const double exact = v[6 * ids[i / 6] + i % 6];
                worst = fmax(worst, fabs(v_ranks[i] - exact) / (1.0 + fabs(exact)));
            }
            if (g_rank == 0 && pass != 1)
                printf("rigid spheres, %lld contacts, %d ranks, %s bodies: %s after %d sweeps, error %.4e (libfrix: "
                       "%.4e), velocities within %.1e\n",
                       (long long)nc, g_size, pass == 0 ? "all" : "touched", frix_status_string(frix_info_status(info)), (int)frix_info_iterations(info),
                       frix_info_error(info), measured, worst);
            if (frix_info_status(info) != FRIX_STATUS_CONVERGED || !(measured <= 1e-8 * (1.0 + 1e-6)) ||
                !(fabs(measured - frix_info_error(info)) <= 1e-6 * measured) || !(worst <= 1e-12))
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
    frix_scene_problems_free(&forms);
    frix_scene_free(&scene);
    ck_assert_msg(all_true(MPI_COMM_WORLD, ok), "the distributed rigid bodies are not as the global problem");
}
END_TEST

int main(int argc, char **argv) {
    mpi_test_start(&argc, &argv);
    Suite *s = suite_create("mpi");
    TCase *tc = tcase_create("global");
    tcase_set_timeout(tc, 0);
    tcase_add_test(tc, a_global_problem_reduced_on_the_root);
    tcase_add_test(tc, rigid_bodies_without_w);
    suite_add_tcase(s, tc);
    return mpi_test_run(s);
}
