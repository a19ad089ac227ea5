/* libfrix_mpi's nsgs on local problems (mpi_fixtures.h says how these programs run): one rank
 * equals the serial solver bit for bit; more ranks converge to the same tolerance, the same
 * bits on every run, with the contacts in blocks, round-robin or cut by Scotch; two problems
 * solve at once on the halves of a split communicator; the exchange plan of a chain given
 * by rows; refusals and a callback's stop reach every rank. */
#include <check.h>
#include <frix/frix.h>
#include <frix/frix_mpi.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../check_main.h"
#include "mpi_fixtures.h"

/* Each rank alone (a communicator of one): the distributed solve is frix_solve, bit for bit
 * (status, sweeps, error, r and u), cold and warm, with freezing, on shared problems and a
 * chain. */
START_TEST(one_rank_is_the_serial_solver) {
    MPI_Comm alone;
    const char *files[] = {"fclib/converted/Capsules-i101-404.from_dat.hdf5",
                           "fclib-large/Spheres-n400-seed2-s00200-nc1186.hdf5",
                           "fclib-large/Kapla-3x3x20-seed1-s00030-nc2799.hdf5"};
    const double tols[] = {1e-8, 1e-4, 1e-4};
    int ok = 1, f;
    MPI_Comm_split(MPI_COMM_WORLD, g_rank, 0, &alone);
    for (f = 0; f < 4; ++f) {
        frix_matrix *W = NULL;
        chain c = chain_make(200);
        frix_problem *p = f < 3 ? shared_problem(files[f]) : chain_problem(&c, &W);
        int variant;
        if (p) {
            const int64_t m = 3 * frix_problem_contacts(p);
            double *half = calloc((size_t)m + 1, sizeof(double));
            for (variant = 0; variant < 3; ++variant) {
                /* 0: cold; 1: freezing 10; 2: warm, from half of the answer. */
                frix_options *o = nsgs_options(f < 3 ? tols[f] : 1e-10);
                outcome s, d;
                if (variant == 1) ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_FREEZING, 10), FRIX_OK);
                s = solve_serial(p, o, variant == 2 ? half : NULL);
                d = solve_distributed(alone, p, NULL, o, variant == 2 ? half : NULL, NULL);
                if (!same_bits(&s, &d, m)) {
                    fprintf(stderr, "rank %d: problem %d variant %d: serial %d sweeps %.17g, distributed %d sweeps %.17g\n",
                            g_rank, f, variant, (int)s.iterations, s.error, (int)d.iterations, d.error);
                    ok = 0;
                }
                if (variant == 0) {
                    int64_t i;
                    for (i = 0; i < m; ++i) half[i] = 0.5 * s.r[i];
                }
                outcome_free(&s);
                outcome_free(&d);
                frix_options_free(o);
            }
            free(half);
        }
        frix_problem_free(p);
        frix_matrix_free(W);
        chain_free(&c);
    }
    MPI_Comm_free(&alone);
    ck_assert_msg(all_true(MPI_COMM_WORLD, ok), "a one-rank solve differs from frix_solve");
}
END_TEST

/* All ranks together on the shared piles at 1e-4: converged, and the gathered answer meets
 * the tolerance by libfrix's own measure (which agrees with the distributed one up to the
 * order of the sums). */
START_TEST(the_ranks_converge_on_the_piles) {
    const char *files[] = {"fclib-large/Kapla-3x3x20-seed1-s00030-nc2799.hdf5",
                           "fclib-large/Spheres-n400-seed2-s00140-nc1165.hdf5",
                           "fclib-large/Kapla-4x4x25-seed4-s00010-nc6251.hdf5"};
    int ok = 1, f;
    for (f = 0; f < 3; ++f) {
        frix_problem *p = shared_problem(files[f]);
        frix_options *o = nsgs_options(1e-4);
        if (p) {
            outcome d = solve_distributed(MPI_COMM_WORLD, p, NULL, o, NULL, NULL);
            double measured = 0.0;
            ck_assert_int_eq(siconos_error(p, d.r, NULL, &measured), FRIX_OK);
            if (g_rank == 0)
                printf("%s, %d ranks: %s after %d sweeps, error %.4e (libfrix: %.4e)\n", files[f], g_size,
                       frix_status_string(d.status), (int)d.iterations, d.error, measured);
            if (d.status != FRIX_STATUS_CONVERGED || !(d.error <= 1e-4) || !(measured <= 1e-4 * (1.0 + 1e-9)) ||
                !(fabs(measured - d.error) <= 1e-9 * d.error))
                ok = 0;
            outcome_free(&d);
        }
        frix_problem_free(p);
        frix_options_free(o);
    }
    ck_assert_msg(all_true(MPI_COMM_WORLD, ok), "a distributed solve missed 1e-4");
}
END_TEST

/* Two runs at one number of ranks: the same bits, with the contacts in equal blocks, dealt
 * round-robin, and cut by Scotch (twice: the same parts). The parts by Scotch leave
 * fewer boundary contacts than equal blocks of the stored order, and every part is gathered
 * back in the problem's order (the error libfrix measures on it meets the tolerance). */
START_TEST(the_same_bits_on_every_run) {
    frix_problem *p = shared_problem("fclib-large/Spheres-n400-seed2-s00200-nc1186.hdf5");
    frix_options *o = nsgs_options(1e-4);
    int ok = 1, pass;
    if (p) {
        const int64_t nc = frix_problem_contacts(p);
        int *part = calloc((size_t)nc, sizeof(int)), *again = calloc((size_t)nc, sizeof(int));
        long long boundary[2] = {0, 0};
        frix_mpi_context *ctx = NULL;
        int64_t a;
        ck_assert_int_eq(frix_mpi_context_create(MPI_COMM_WORLD, &ctx), FRIX_OK);
        for (pass = 0; pass < 3; ++pass) {
            frix_mpi_problem *kept = NULL;
            int64_t mine = 0;
            long long all = 0;
            outcome a1, a2;
            double measured = 1.0;
            if (pass == 1)
                for (a = 0; a < nc; ++a) part[a] = (int)(a % g_size);
            if (pass == 2) {
                ck_assert_msg(frix_mpi_partition(ctx, 0, g_rank == 0 ? p : NULL, part) == FRIX_OK, "%s",
                              frix_mpi_last_error_message());
                ck_assert_int_eq(frix_mpi_partition(ctx, 0, g_rank == 0 ? p : NULL, again), FRIX_OK);
                if (g_rank == 0 && memcmp(part, again, (size_t)nc * sizeof(int)) != 0) {
                    fprintf(stderr, "Scotch gave other parts the second time\n");
                    ok = 0;
                }
            }
            a1 = solve_distributed(MPI_COMM_WORLD, p, pass == 0 ? NULL : part, o, NULL, &kept);
            a2 = solve_distributed(MPI_COMM_WORLD, p, pass == 0 ? NULL : part, o, NULL, NULL);
            ck_assert_int_eq(siconos_error(p, a1.r, NULL, &measured), FRIX_OK);
            if (!same_bits(&a1, &a2, 3 * nc) || a1.status != FRIX_STATUS_CONVERGED || !(measured <= 1e-4 * (1.0 + 1e-9))) {
                fprintf(stderr, "rank %d, pass %d: same bits %d, %s, measured %.6e\n", g_rank, pass,
                        same_bits(&a1, &a2, 3 * nc), frix_status_string(a1.status), measured);
                ok = 0;
            }
            frix_mpi_problem_get_int(kept, FRIX_MPI_BOUNDARY, &mine);
            all = (long long)mine;
            MPI_Allreduce(MPI_IN_PLACE, &all, 1, MPI_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
            if (pass != 1) boundary[pass / 2] = all;
            if (g_rank == 0)
                printf("%s, %d ranks: %lld boundary contacts, %d sweeps\n",
                       pass == 0 ? "equal blocks" : pass == 1 ? "round-robin" : "Scotch", g_size, all,
                       (int)a1.iterations);
            frix_mpi_problem_free(kept);
            outcome_free(&a1);
            outcome_free(&a2);
        }
        if (g_size > 1) ok = ok && boundary[1] < boundary[0];
        frix_mpi_context_free(ctx);
        free(part);
        free(again);
    }
    frix_problem_free(p);
    frix_options_free(o);
    ck_assert_msg(all_true(MPI_COMM_WORLD, ok), "two runs differ, or the parts are not as expected");
}
END_TEST

/* The halves of a split communicator solve two problems at once, each as it does alone. */
START_TEST(two_problems_on_the_halves) {
    const char *files[] = {"fclib-large/Spheres-n400-seed2-s00200-nc1186.hdf5",
                           "fclib-large/Kapla-3x3x20-seed1-s00030-nc2799.hdf5"};
    MPI_Comm half;
    const int side = g_rank < g_size / 2 ? 0 : 1;
    frix_problem *p;
    frix_options *o = nsgs_options(1e-4);
    int ok = 1;
    if (g_size < 2) {
        if (g_rank == 0) fprintf(stderr, "note: two_problems_on_the_halves needs 2 ranks or more, skipped\n");
        frix_options_free(o);
        return;
    }
    MPI_Comm_split(MPI_COMM_WORLD, side, g_rank, &half);
    p = shared_problem(files[side]);
    if (p) {
        const int64_t m = 3 * frix_problem_contacts(p);
        outcome at_once = solve_distributed(half, p, NULL, o, NULL, NULL);
        outcome alone;
        MPI_Barrier(MPI_COMM_WORLD); /* the other half is done too: this half now runs alone */
        alone = solve_distributed(half, p, NULL, o, NULL, NULL);
        if (!same_bits(&at_once, &alone, m) || at_once.status != FRIX_STATUS_CONVERGED) ok = 0;
        outcome_free(&at_once);
        outcome_free(&alone);
    }
    frix_problem_free(p);
    frix_options_free(o);
    MPI_Comm_free(&half);
    ck_assert_msg(all_true(MPI_COMM_WORLD, ok), "a half's solve depended on the other half");
}
END_TEST

/* A chain in equal blocks: each rank's ghosts, boundary, neighbours and colours are known;
 * rows given by each rank (frix_mpi_problem_local) solve to the bits of the scattered
 * problem, and the answer meets the tolerance. */
START_TEST(a_chain_in_blocks) {
    const int64_t per_rank = 7, nc = per_rank * g_size;
    chain c = chain_make(nc);
    frix_matrix *W = NULL;
    frix_problem *p = chain_problem(&c, &W);
    frix_mpi_context *ctx = NULL;
    frix_mpi_problem *mine = NULL, *scattered = NULL;
    frix_options *o = nsgs_options(1e-10);
    const int64_t first = per_rank * g_rank;
    const int64_t expect_neighbours = (g_rank > 0) + (g_rank < g_size - 1);
    int64_t v, *row_ptr = calloc((size_t)per_rank + 1, sizeof(int64_t));
    double *r = calloc((size_t)(3 * per_rank), sizeof(double)), *u = calloc((size_t)(3 * per_rank), sizeof(double));
    outcome s;
    frix_info *info = NULL;
    int ok = 1, i;
    for (i = 0; i <= per_rank; ++i) row_ptr[i] = c.row_ptr[first + i] - c.row_ptr[first];
    ck_assert_int_eq(frix_mpi_context_create(MPI_COMM_WORLD, &ctx), FRIX_OK);
    ck_assert_int_eq(frix_mpi_problem_local(ctx, first, per_rank, row_ptr, c.cols + c.row_ptr[first],
                                            c.vals + 9 * c.row_ptr[first], c.q + 3 * first, c.mu + first, &mine),
                     FRIX_OK);
    frix_mpi_problem_get_int(mine, FRIX_MPI_GHOSTS, &v);
    ok = ok && v == expect_neighbours;
    frix_mpi_problem_get_int(mine, FRIX_MPI_NEIGHBOURS, &v);
    ok = ok && v == expect_neighbours;
    frix_mpi_problem_get_int(mine, FRIX_MPI_BOUNDARY, &v);
    ok = ok && v == expect_neighbours;
    frix_mpi_problem_get_int(mine, FRIX_MPI_MESSAGES_SENT, &v);
    ok = ok && v == expect_neighbours;
    frix_mpi_problem_get_int(mine, FRIX_MPI_COLOURS, &v);
    ok = ok && v == (g_size == 1 ? 1 : 2);
    frix_mpi_problem_get_int(mine, FRIX_MPI_COLOUR, &v);
    ok = ok && v == g_rank % 2;
    frix_mpi_problem_get_int(mine, FRIX_MPI_CONTACTS, &v);
    ok = ok && v == nc;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_mpi_solve(mine, o, r, u, info), FRIX_OK);
    s = solve_distributed(MPI_COMM_WORLD, p, NULL, o, NULL, &scattered);
    ok = ok && frix_info_status(info) == FRIX_STATUS_CONVERGED && frix_info_iterations(info) == s.iterations &&
         memcmp(r, s.r + 3 * first, (size_t)(3 * per_rank) * sizeof(double)) == 0;
    {
        double measured = 1.0;
        ck_assert_int_eq(siconos_error(p, s.r, NULL, &measured), FRIX_OK);
        ok = ok && measured <= 1e-10 * (1.0 + 1e-9);
    }
    outcome_free(&s);
    frix_info_free(info);
    free(r);
    free(u);
    free(row_ptr);
    frix_mpi_problem_free(mine);
    frix_mpi_problem_free(scattered);
    frix_mpi_context_free(ctx);
    frix_options_free(o);
    frix_problem_free(p);
    frix_matrix_free(W);
    chain_free(&c);
    ck_assert_msg(all_true(MPI_COMM_WORLD, ok), "the chain's plan or answer is not as expected");
}
END_TEST

static int stop_at_five(void *data, int64_t iteration, double error, double seconds) {
    (void)data, (void)error, (void)seconds;
    return iteration >= 5;
}

/* Refusals reach every rank with the same code; a callback on one rank stops all. */
START_TEST(refusals_and_stops_reach_every_rank) {
    const int64_t per_rank = 5, nc = per_rank * g_size, first = per_rank * g_rank;
    const int last = g_size - 1;
    chain c = chain_make(nc);
    frix_mpi_context *ctx = NULL;
    frix_mpi_problem *part = NULL;
    frix_options *o = nsgs_options(1e-12);
    frix_info *info = NULL;
    int64_t row_ptr[6];
    double r[15] = {0}, u[15] = {0}, mu[5];
    frix_error e;
    int ok = 1, i;
    for (i = 0; i <= per_rank; ++i) row_ptr[i] = c.row_ptr[first + i] - c.row_ptr[first];
    for (i = 0; i < per_rank; ++i) mu[i] = g_rank == last && i == 2 ? -1.0 : c.mu[first + i];
    ck_assert_int_eq(frix_mpi_context_create(MPI_COMM_NULL, &ctx), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_mpi_context_create(MPI_COMM_WORLD, NULL), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_mpi_context_create(MPI_COMM_WORLD, &ctx), FRIX_OK);

    /* A negative mu on the last rank only. */
    e = frix_mpi_problem_local(ctx, first, per_rank, row_ptr, c.cols + c.row_ptr[first], c.vals + 9 * c.row_ptr[first],
                               c.q + 3 * first, mu, &part);
    ok = ok && e == FRIX_ERR_INVALID_ARGUMENT && part == NULL;
    if (g_rank != last) ok = ok && strstr(frix_mpi_last_error_message(), "refused") != NULL;
    ok = ok && strstr(frix_mpi_last_error_message(), "mu[2]") != NULL;
    /* Blocks that do not follow each other (each rank claims to start one further on). */
    e = frix_mpi_problem_local(ctx, first + 1, per_rank, row_ptr, c.cols + c.row_ptr[first],
                               c.vals + 9 * c.row_ptr[first], c.q + 3 * first, c.mu + first, &part);
    ok = ok && e == FRIX_ERR_DIMENSION;
    /* A root that is not a rank; no problem on the root. */
    e = frix_mpi_problem_scatter(ctx, g_size, NULL, NULL, &part);
    ok = ok && e == FRIX_ERR_INVALID_ARGUMENT && part == NULL;
    e = frix_mpi_problem_scatter(ctx, 0, NULL, NULL, &part);
    ok = ok && e == FRIX_ERR_INVALID_ARGUMENT && part == NULL;
    /* A problem with spinning friction on the root (a rolling problem of six entries a
     * contact): refused on every rank, by the partition and the scatter, naming its law. */
    {
        double eye[36] = {0}, q6[6] = {-1, 0, 0, 0, 0, 0.05}, mu1 = 0.5, mu_r = 0.01, mu_s = 0.02;
        frix_matrix *I6 = NULL;
        frix_problem *spinning = NULL;
        int part1[1] = {0};
        for (i = 0; i < 6; ++i) eye[7 * i] = 1.0;
        ck_assert_int_eq(frix_matrix_from_dense(6, 6, eye, 6, &I6), FRIX_OK);
        ck_assert_int_eq(frix_problem_spinning_local(I6, q6, &mu1, &mu_r, &mu_s, 1, &spinning), FRIX_OK);
        e = frix_mpi_partition(ctx, 0, g_rank == 0 ? spinning : NULL, g_rank == 0 ? part1 : NULL);
        ok = ok && e == FRIX_ERR_UNSUPPORTED;
        e = frix_mpi_problem_scatter(ctx, 0, g_rank == 0 ? spinning : NULL, NULL, &part);
        ok = ok && e == FRIX_ERR_UNSUPPORTED && part == NULL;
        ok = ok && strstr(frix_mpi_last_error_message(), "spinning friction") != NULL;
        frix_problem_free(spinning);
        frix_matrix_free(I6);
    }

    /* A good part; options the distributed solve refuses; missing r. */
    ck_assert_int_eq(frix_mpi_problem_local(ctx, first, per_rank, row_ptr, c.cols + c.row_ptr[first],
                                            c.vals + 9 * c.row_ptr[first], c.q + 3 * first, c.mu + first, &part),
                     FRIX_OK);
    {
        frix_options *drift = nsgs_options(1e-8), *other = NULL;
        int64_t v = 0;
        ck_assert_int_eq(frix_options_set_int(drift, FRIX_OPT_DRIFT_WINDOW, 10), FRIX_OK);
        ok = ok && frix_mpi_solve(part, drift, r, u, NULL) == FRIX_ERR_UNSUPPORTED;
        ck_assert_int_eq(frix_options_set_int(drift, FRIX_OPT_DRIFT_WINDOW, 0), FRIX_OK);
        ck_assert_int_eq(frix_options_set_int(drift, FRIX_OPT_ANDERSON, 5), FRIX_OK);
        ok = ok && frix_mpi_solve(part, drift, r, u, NULL) == FRIX_ERR_UNSUPPORTED;
        ok = ok && strstr(frix_mpi_last_error_message(), "anderson") != NULL;
        ck_assert_int_eq(frix_options_create(FRIX_SOLVER_AUTO, &other), FRIX_OK);
        frix_test_siconos_measure(other);
        ok = ok && frix_mpi_solve(part, other, r, u, NULL) == FRIX_ERR_UNSUPPORTED;
        ok = ok && frix_mpi_solve(part, o, g_rank == last ? NULL : r, u, NULL) == FRIX_ERR_INVALID_ARGUMENT;
        ok = ok && frix_mpi_problem_get_int(part, (frix_mpi_key)99, &v) == FRIX_ERR_INVALID_ARGUMENT;
        ok = ok && frix_mpi_gather(part, -1, r, NULL) == FRIX_ERR_INVALID_ARGUMENT;
        frix_options_free(drift);
        frix_options_free(other);
    }
    /* Rank 0's callback stops every rank after the fifth sweep. */
    if (g_rank == 0) ck_assert_int_eq(frix_options_set_callback(o, stop_at_five, NULL), FRIX_OK);
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_mpi_solve(part, o, r, u, info), FRIX_OK);
    ok = ok && frix_info_status(info) == FRIX_STATUS_STOPPED_BY_CALLBACK && frix_info_iterations(info) == 5;

    frix_mpi_problem_free(NULL);
    frix_mpi_context_free(NULL);
    frix_info_free(info);
    frix_mpi_problem_free(part);
    frix_mpi_context_free(ctx);
    frix_options_free(o);
    chain_free(&c);
    ck_assert_msg(all_true(MPI_COMM_WORLD, ok), "a refusal or a stop did not reach every rank alike");
}
END_TEST

int main(int argc, char **argv) {
    mpi_test_start(&argc, &argv);
    Suite *s = suite_create("mpi");
    TCase *tc = tcase_create("nsgs");
    tcase_set_timeout(tc, 0);
    tcase_add_test(tc, one_rank_is_the_serial_solver);
    tcase_add_test(tc, the_ranks_converge_on_the_piles);
    tcase_add_test(tc, the_same_bits_on_every_run);
    tcase_add_test(tc, two_problems_on_the_halves);
    tcase_add_test(tc, a_chain_in_blocks);
    tcase_add_test(tc, refusals_and_stops_reach_every_rank);
    suite_add_tcase(s, tc);
    return mpi_test_run(s);
}
