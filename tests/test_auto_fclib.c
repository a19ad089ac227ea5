/* auto (900) converges to 1e-8 on every local and global problem of ../shared/fclib,
 * RockPile_tob1 by NSGS's chain of stages and its 25-contact island by Newton's random
 * restarts. */
#include <check.h>
#include <frix/frix.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "auto_runs.h"
#include "check_main.h"
#include "shared_data.h"
#include "stage_records.h"

/* The connected component of the contact graph (contacts a, b linked when W_ab != 0) that
 * has exactly `size` contacts, as a local problem of its own in island->p; returns 0 if there
 * is none. The problem borrows the arrays of `island`, freed by island_free. */
typedef struct {
    frix_matrix *W;
    double *q, *mu;
    int64_t *colptr, *rowind;
    double *values;
    frix_problem *p;
} island_part;

static int island_of_size(const frix_problem *whole, int64_t size, island_part *island) {
    memset(island, 0, sizeof *island);
    const int64_t nc = frix_problem_contacts(whole), m = 3 * nc;
    int64_t nnz = 0;
    ck_assert_int_eq(frix_matrix_to_csc(frix_problem_W(whole), &nnz, NULL, NULL, NULL), FRIX_OK);
    int64_t *cp = malloc((size_t)(m + 1) * sizeof *cp), *ri = malloc((size_t)nnz * sizeof *ri);
    double *vx = malloc((size_t)nnz * sizeof *vx);
    ck_assert_int_eq(frix_matrix_to_csc(frix_problem_W(whole), &nnz, cp, ri, vx), FRIX_OK);
    /* Components by repeated labelling over the (symmetric) block pattern. */
    int64_t *label = malloc((size_t)nc * sizeof *label), *stack = malloc((size_t)nc * sizeof *stack);
    int64_t *index = malloc((size_t)nc * sizeof *index);
    for (int64_t a = 0; a < nc; ++a) label[a] = -1;
    int64_t found = -1;
    for (int64_t seed = 0; seed < nc && found < 0; ++seed) {
        if (label[seed] >= 0) continue;
        int64_t top = 0, count = 0;
        label[seed] = seed;
        stack[top++] = seed;
        while (top > 0) {
            const int64_t a = stack[--top];
            ++count;
            for (int64_t j = 3 * a; j < 3 * a + 3; ++j)
                for (int64_t k = cp[j]; k < cp[j + 1]; ++k) {
                    const int64_t b = ri[k] / 3;
                    if (label[b] < 0) label[b] = seed, stack[top++] = b;
                }
        }
        if (count == size) found = seed;
    }
    if (found >= 0) {
        int64_t n = 0;
        for (int64_t a = 0; a < nc; ++a) index[a] = label[a] == found ? n++ : -1;
        island->colptr = calloc((size_t)(3 * n + 1), sizeof *island->colptr);
        island->rowind = malloc((size_t)nnz * sizeof *island->rowind);
        island->values = malloc((size_t)nnz * sizeof *island->values);
        island->q = malloc((size_t)(3 * n) * sizeof *island->q);
        island->mu = malloc((size_t)n * sizeof *island->mu);
        int64_t e = 0;
        for (int64_t a = 0; a < nc; ++a) {
            if (index[a] < 0) continue;
            island->mu[index[a]] = frix_problem_mu(whole)[a];
            for (int d = 0; d < 3; ++d) {
                const int64_t j = 3 * a + d;
                island->q[3 * index[a] + d] = frix_problem_q(whole)[j];
                for (int64_t k = cp[j]; k < cp[j + 1]; ++k) {
                    island->rowind[e] = 3 * index[ri[k] / 3] + ri[k] % 3;
                    island->values[e++] = vx[k];
                }
                island->colptr[3 * index[a] + d + 1] = e;
            }
        }
        ck_assert_int_eq(frix_matrix_from_csc(3 * n, 3 * n, island->colptr, island->rowind, island->values, &island->W),
                         FRIX_OK);
        ck_assert_int_eq(frix_problem_local(island->W, island->q, island->mu, n, &island->p), FRIX_OK);
    }
    free(cp), free(ri), free(vx), free(label), free(stack), free(index);
    return found >= 0;
}

static void island_free(island_part *island) {
    frix_problem_free(island->p);
    frix_matrix_free(island->W);
    free(island->q), free(island->mu), free(island->colptr), free(island->rowind), free(island->values);
}

/* RockPile's 25-contact island: Newton from r = 0 and from the best iterate stops at a
 * stationary point of its merit function (error ~5e-8) that is not a solution, NSGS needs
 * ~1.6 million sweeps. The random restarts of Newton solve it within a few thousand
 * iterations; before them auto had not converged after 10 s (2.2 million iterations). */
START_TEST(test_random_restarts_solve_rockpile_small_island) {
    frix_problem *whole = load("converted/RockPile_tob1.from_dat.hdf5");
    if (!whole) return;
    island_part island;
    ck_assert_msg(island_of_size(whole, 25, &island), "RockPile has a 25-contact island");
    const int64_t m = frix_problem_contact_dofs(island.p);
    double *r = calloc((size_t)m, sizeof *r), *u = calloc((size_t)m, sizeof *u);
    frix_options *o = NULL;
    frix_info *info = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_AUTO, &o), FRIX_OK);
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 1e-8), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_MAX_ITER, 20000), FRIX_OK);
    ck_assert_int_eq(frix_solve(island.p, o, r, u, NULL, info), FRIX_OK);
    ck_assert_msg(frix_info_status(info) == FRIX_STATUS_CONVERGED, "%s, error %.3e\n%s",
                  frix_status_string(frix_info_status(info)), frix_info_error(info), frix_info_trace(info));
    double e = NAN;
    ck_assert_int_eq(frix_problem_error(island.p, r, NULL, &e), FRIX_OK);
    ck_assert_double_le(e, 1e-8);
    int random_start_converged = 0;
    for (int64_t k = 0; k < frix_info_stage_count(info); ++k)
        random_start_converged |= stage_int(info, k, FRIX_STAGE_SOLVER_ID) == FRIX_SOLVER_NSN_AC &&
                                  stage_int(info, k, FRIX_STAGE_RANDOM_STARTS) == 1 &&
                                  stage_int(info, k, FRIX_STAGE_STATUS) == FRIX_STATUS_CONVERGED;
    ck_assert_msg(random_start_converged, "%s", frix_info_trace(info));

    /* Deterministic: the same draws, the same iterations and reactions. */
    double *r2 = calloc((size_t)m, sizeof *r2);
    const int64_t iterations = frix_info_iterations(info);
    ck_assert_int_eq(frix_solve(island.p, o, r2, u, NULL, info), FRIX_OK);
    ck_assert_int_eq(frix_info_iterations(info), iterations);
    ck_assert_mem_eq(r, r2, (size_t)m * sizeof *r);

    free(r), free(r2), free(u);
    frix_info_free(info);
    frix_options_free(o);
    island_free(&island);
    frix_problem_free(whole);
}
END_TEST

static void solve_to_1e8(const char *relative) {
    file_run f;
    if (!file_run_open(&f, relative, 1e-8)) return;
    file_run_solve(&f);
    if (frix_info_status(f.info) != FRIX_STATUS_CONVERGED) fprintf(stderr, "%s\n%s", relative, frix_info_trace(f.info));
    ck_assert_msg(frix_info_status(f.info) == FRIX_STATUS_CONVERGED, "%s: %s, error %.3e (trace above)", relative,
                  frix_status_string(frix_info_status(f.info)), frix_info_error(f.info));
    double e = NAN;
    ck_assert_int_eq(frix_problem_error(f.p, f.r, f.v, &e), FRIX_OK);
    ck_assert_msg(e <= 1e-8, "%s: recomputed error %.3e", relative, e);
    file_run_close(&f);
}

/* Every local problem of ../shared/fclib (RockPile_tob1 in its own test, below). */
START_TEST(test_every_local_fclib_problem) {
    if (strstr(kFclibLocalProblems[_i], "RockPile")) return;
    solve_to_1e8(kFclibLocalProblems[_i]);
}
END_TEST

/* RockPile_tob1: its 295-contact island is solved by NSGS's stages, one chain across the rounds
 * that carries the steady drifts of r ahead (about 540000 iterations in all, 13 s). Restarted
 * from the best iterate every round and without the drift jumps, auto needed 9.2 million
 * iterations (220 s). */
START_TEST(test_rockpile_by_the_nsgs_chain) {
    file_run f;
    if (!file_run_open(&f, "converted/RockPile_tob1.from_dat.hdf5", 1e-8)) return;
    ck_assert_int_eq(frix_options_set_int(f.o, FRIX_OPT_MAX_ITER, 2000000), FRIX_OK);
    file_run_solve(&f);
    ck_assert_msg(frix_info_status(f.info) == FRIX_STATUS_CONVERGED, "%s after %lld iterations, error %.3e",
                  frix_status_string(frix_info_status(f.info)), (long long)frix_info_iterations(f.info),
                  frix_info_error(f.info));
    double e = NAN;
    ck_assert_int_eq(frix_problem_error(f.p, f.r, NULL, &e), FRIX_OK);
    ck_assert_double_le(e, 1e-8);
    file_run_close(&f);
}
END_TEST

/* auto's sweeps take momentum (option acceleration, default 1): Kapla-3x3x20 s30 (fclib-large,
 * nine towers of blocks) at 1e-4 takes at most a quarter of the iterations it takes with plain
 * sweeps (acceleration = 0), and both answers meet the tolerance. */
START_TEST(test_auto_sweeps_take_momentum) {
    file_run f;
    if (!file_run_open(&f, "../fclib-large/Kapla-3x3x20-seed1-s00030-nc2799.hdf5", 1e-4)) return;
    int64_t is_on = -1;
    ck_assert_int_eq(frix_options_get_int(f.o, FRIX_OPT_ACCELERATION, &is_on), FRIX_OK);
    ck_assert_int_eq(is_on, 1);
    file_run_solve(&f);
    ck_assert_int_eq(frix_info_status(f.info), FRIX_STATUS_CONVERGED);
    const int64_t with = frix_info_iterations(f.info);
    ck_assert_int_eq(frix_options_set_int(f.o, FRIX_OPT_ACCELERATION, 0), FRIX_OK);
    file_run_solve(&f);
    ck_assert_int_eq(frix_info_status(f.info), FRIX_STATUS_CONVERGED);
    const int64_t without = frix_info_iterations(f.info);
    ck_assert_msg(4 * with <= without, "%lld iterations with momentum, %lld without", (long long)with,
                  (long long)without);
    file_run_close(&f);
}
END_TEST

static const char *const kGlobalFiles[] = {
    "global/Box_Stacks-i0035-31-0.hdf5",
    "global/CubeH8.hdf5",
    "global/LMGC_GFC3D-i00501-4-00000.hdf5",
    "global/spheres-in-a-box-98-i10000-256-10.hdf5",
};

START_TEST(test_global_fclib_problems) { solve_to_1e8(kGlobalFiles[_i]); }
END_TEST

int main(void) {
    Suite *s = suite_create("auto");
    TCase *tc = tcase_create("fclib");
    tcase_set_timeout(tc, 300);
    tcase_add_test(tc, test_random_restarts_solve_rockpile_small_island);
    tcase_add_test(tc, test_rockpile_by_the_nsgs_chain);
    tcase_add_test(tc, test_auto_sweeps_take_momentum);
    tcase_add_loop_test(tc, test_every_local_fclib_problem, 0, FRIX_FCLIB_LOCAL_COUNT);
    tcase_add_loop_test(tc, test_global_fclib_problems, 0, (int)(sizeof kGlobalFiles / sizeof kGlobalFiles[0]));
    suite_add_tcase(s, tc);
    return frix_run_suite(s);
}
