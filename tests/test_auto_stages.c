/* auto (900): which stages it runs on which problems, read from its stage records: random
 * restarts round by round, the interior point set aside or handed to Newton, ADMM's probe,
 * parts held to their share of the tolerance, NSGS judged by its rate, per-contact penalties
 * for contacts in other units, and the easy problems done before any part is set up. */
#define _DEFAULT_SOURCE /* MAP_ANONYMOUS */
#include <check.h>
#include <frix/frix.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>

#include "auto_runs.h"
#include "check_main.h"
#include "scenes.h"
#include "shared_data.h"
#include "stage_records.h"

/* Two coupled contacts, both pressed and sliding: a solution exists, but to a tolerance of
 * 1e-300 on the |q| measure no run can pass (rounding leaves ~1e-17), so auto goes round after
 * round, Newton stalling every time on this small part, until its iteration limit or until
 * rounds stop lowering the error (it gives up: stagnated). Round k makes 2^k random starts;
 * the trace must give each round's starts one line (2^k of them). (An iteration limit, not a
 * time limit: under valgrind 0.5 s gave one round only. A problem without a solution would not
 * do: its iterates run away, and auto then ends diverged at once.) */
START_TEST(test_random_restarts_one_trace_line_per_round) {
    double Wd[36] = {0};
    for (int i = 0; i < 6; ++i) Wd[i * 6 + i] = 1.0;
    Wd[3] = Wd[3 * 6] = 0.6, Wd[1 * 6 + 4] = Wd[4 * 6 + 1] = 0.3, Wd[2 * 6 + 5] = Wd[5 * 6 + 2] = 0.2;
    Wd[4] = Wd[4 * 6] = Wd[1 * 6 + 3] = Wd[3 * 6 + 1] = 0.12;
    const double q[6] = {-1, 0.71, 0.37, -0.7, 0.53, -0.29}, mu[2] = {0.3, 0.3};
    double r[6] = {0}, u[6];
    frix_matrix *W = NULL;
    frix_problem *p = NULL;
    frix_options *o = NULL;
    frix_info *info = NULL;
    ck_assert_int_eq(frix_matrix_from_dense(6, 6, Wd, 6, &W), FRIX_OK);
    ck_assert_int_eq(frix_problem_local(W, q, mu, 2, &p), FRIX_OK);
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_AUTO, &o), FRIX_OK);
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_ERROR_MEASURE, FRIX_MEASURE_Q_RELATIVE), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 1e-300), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_MAX_ITER, 100000), FRIX_OK);
    ck_assert_int_eq(frix_solve(p, o, r, u, NULL, info), FRIX_OK);
    const frix_status status = frix_info_status(info);
    ck_assert_msg(status == FRIX_STATUS_MAX_ITER || status == FRIX_STATUS_STAGNATED, "status %s",
                  frix_status_string(status));
    ck_assert_int_le(frix_info_iterations(info), 100000);
    const int64_t lines = frix_info_stage_count(info);
    int64_t restart_lines = 0, newton_lines = 0;
    long long starts_of[64] = {0};
    for (int64_t k = 0; k < lines; ++k) {
        const int64_t starts = stage_int(info, k, FRIX_STAGE_RANDOM_STARTS);
        if (starts > 0) {
            ck_assert_int_lt(restart_lines, 64);
            ck_assert_int_eq(stage_int(info, k, FRIX_STAGE_SOLVER_ID), FRIX_SOLVER_NSN_AC);
            starts_of[restart_lines++] = starts;
        } else if (stage_int(info, k, FRIX_STAGE_SOLVER_ID) == FRIX_SOLVER_NSN_AC) {
            ++newton_lines;
        }
    }
    ck_assert_int_ge(restart_lines, 2);
    /* Round k: 2^k starts; the iteration limit may cut the last round's short. */
    for (int64_t k = 0; k < restart_lines; ++k) {
        const long long expected = 1LL << k;
        if (k + 1 < restart_lines)
            ck_assert_msg(starts_of[k] == expected, "round %lld: %lld starts", (long long)k, starts_of[k]);
        else
            ck_assert(starts_of[k] >= 1 && starts_of[k] <= expected);
    }
    /* Newton from r = 0 and from the best iterate: one or two lines a round, never more. */
    ck_assert_int_le(restart_lines, newton_lines);
    ck_assert_int_le(lines, 8 * restart_lines + 8);
    frix_info_free(info);
    frix_options_free(o);
    frix_problem_free(p);
    frix_matrix_free(W);
}
END_TEST

/* The first NSGS stage (plain on a part of fewer than 64 contacts, velocity form on a
 * larger one), or -1. */
static int64_t first_nsgs_stage(const frix_info *info) {
    const int64_t plain = find_stage(info, FRIX_SOLVER_NSGS, 0), velocity = find_stage(info, FRIX_SOLVER_NSGS_VELOCITY, 0);
    return plain < 0 ? velocity : velocity < 0 ? plain : plain < velocity ? plain : velocity;
}

/* The sweeps of the first NSGS stage from r = 0 on a problem (-1 without one), and whether
 * that stage converged. */
static int64_t first_nsgs_sweeps(const frix_info *info, int *converged) {
    const int64_t k = first_nsgs_stage(info);
    *converged = k >= 0 && stage_int(info, k, FRIX_STAGE_STATUS) == FRIX_STATUS_CONVERGED;
    return k >= 0 ? stage_int(info, k, FRIX_STAGE_ITERATIONS) : -1;
}

/* The first NSGS stage is judged by its rate once it has done 1e5 block operations (sweeps x
 * W blocks): on OneObject-i100000 (25 contacts, 207 blocks) it is slow and is stopped after
 * 483 sweeps, where Newton finishes in a few steps (966 sweeps with 2e5); on
 * LMGC_100_PR_PerioBox (60 contacts) it converges after 35 sweeps, which a judgement after 3e4
 * operations or less would cut short, handing the problem to the costlier stages. */
START_TEST(test_first_nsgs_judged_after_its_work) {
    file_run f;
    if (!file_run_open(&f, "converted/OneObject-i100000-316.from_dat.hdf5", 1e-8)) return;
    file_run_solve(&f);
    int converged = 0;
    int64_t sweeps = first_nsgs_sweeps(f.info, &converged);
    ck_assert_msg(frix_info_status(f.info) == FRIX_STATUS_CONVERGED && !converged && sweeps >= 30 &&
                      sweeps <= 600,
                  "%s\n", frix_info_trace(f.info));
    file_run_close(&f);
    if (!file_run_open(&f, "local/LMGC_100_PR_PerioBox-i00361-60-03000.hdf5", 1e-8)) return;
    frix_test_siconos_measure(f.o);
    file_run_solve(&f);
    sweeps = first_nsgs_sweeps(f.info, &converged);
    ck_assert_msg(frix_info_status(f.info) == FRIX_STATUS_CONVERGED && converged && sweeps > 0,
                  "%s\n", frix_info_trace(f.info));
    file_run_close(&f);
}
END_TEST

/* Contacts in units that differ by decades (OneObject-i100000 rescaled per contact by
 * 10^[-2, 2]): auto sees the spread of |W_aa| and gives ADMM per-contact penalties; it
 * converges in 1277 iterations where, with one penalty for all contacts, it needed 18386. */
START_TEST(test_contacts_in_different_units) {
    scaled_problem sp;
    if (!scaled_problem_load(&sp, "converted/OneObject-i100000-316.from_dat.hdf5", 2.0)) return;
    const int64_t m = frix_problem_contact_dofs(sp.p);
    double *r = calloc((size_t)m, sizeof *r), *u = calloc((size_t)m, sizeof *u);
    frix_options *o = auto_options(1e-8);
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_solve(sp.p, o, r, u, NULL, info), FRIX_OK);
    double err = NAN;
    ck_assert_int_eq(frix_problem_error(sp.p, r, NULL, &err), FRIX_OK);
    ck_assert_msg(frix_info_status(info) == FRIX_STATUS_CONVERGED && err <= 1e-8, "%s, error %g",
                  frix_status_string(frix_info_status(info)), err);
    ck_assert_msg(frix_info_iterations(info) < 3000, "%lld iterations",
                  (long long)frix_info_iterations(info));
    frix_info_free(info);
    frix_options_free(o);
    scaled_problem_free(&sp);
    free(r);
    free(u);
}
END_TEST

/* At a loose tolerance on a large pile where NSGS stalls (the 8-layer pyramid of spheres, 960
 * contacts), ADMM is weighed against the interior-point stage by their prices and comes
 * first: auto converges by ADMM, and no factorising stage runs. */
START_TEST(test_loose_tolerance_pile_solved_by_admm_first) {
    frix_scene_params sp;
    frix_scene_defaults(FRIX_SCENE_SPHERES, &sp);
    sp.count = 8;
    frix_scene scene;
    ck_assert_int_eq(frix_scene_build(&sp, &scene, NULL), FRIX_OK);
    frix_scene_problems pr;
    ck_assert_int_eq(frix_scene_problems_make(&scene, &pr), FRIX_OK);
    ck_assert_int_eq(scene.nc, 960);
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_AUTO, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 1e-4), FRIX_OK);
    double *r = calloc((size_t)(3 * scene.nc), sizeof *r), *u = calloc((size_t)(3 * scene.nc), sizeof *u);
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_solve(pr.local, o, r, u, NULL, info), FRIX_OK);
    const char *trace = frix_info_trace(info);
    ck_assert_msg(frix_info_status(info) == FRIX_STATUS_CONVERGED, "%s\n%s",
                  frix_status_string(frix_info_status(info)), trace);
    const int64_t admm = find_stage(info, FRIX_SOLVER_ADMM, 0);
    ck_assert_msg(admm >= 0 && stage_int(info, admm, FRIX_STAGE_STATUS) == FRIX_STATUS_CONVERGED,
                  "no converged ADMM stage:\n%s", trace);
    ck_assert_msg(find_stage(info, FRIX_SOLVER_IPM, 0) < 0 && find_stage(info, FRIX_SOLVER_NSN_AC, 0) < 0,
                  "a factorising stage ran:\n%s", trace);
    double e = NAN;
    ck_assert_int_eq(frix_problem_error(pr.local, r, NULL, &e), FRIX_OK);
    ck_assert_double_le(e, 1e-4);
    frix_info_free(info);
    free(r);
    free(u);
    frix_options_free(o);
    frix_scene_problems_free(&pr);
    frix_scene_free(&scene);
}
END_TEST

/* Kapla-4x2x25-ball s100 (fclib-large): the interior-point run on its 941-contact island
 * stalls (at 1.8e-7 with OpenBLAS on one thread, 5.6e-7 on two), Newton from that iterate
 * lowers the error further (converges, or ends within 100 x the tolerance, and its point is
 * kept), and auto converges in a few hundred iterations, where the rounds from NSGS's iterate
 * needed about 30000 (10 s). */
START_TEST(test_newton_from_stalled_interior_point) {
    file_run f;
    if (!file_run_open(&f, "../fclib-large/Kapla-4x2x25-ball-seed2-s00100-nc2895.hdf5", 1e-8)) return;
    file_run_solve(&f);
    const char *trace = frix_info_trace(f.info);
    ck_assert_msg(frix_info_status(f.info) == FRIX_STATUS_CONVERGED, "%s, error %.3e\n%s",
                  frix_status_string(frix_info_status(f.info)), frix_info_error(f.info), trace);
    double e = NAN;
    ck_assert_int_eq(frix_problem_error(f.p, f.r, NULL, &e), FRIX_OK);
    ck_assert_double_le(e, 1e-8);
    const int64_t ipm = find_stage(f.info, FRIX_SOLVER_IPM, 0);
    ck_assert_msg(ipm >= 0 && stage_int(f.info, ipm, FRIX_STAGE_STATUS) == FRIX_STATUS_STAGNATED,
                  "no stalled interior-point stage:\n%s", trace);
    ck_assert_msg(ipm + 1 < frix_info_stage_count(f.info) &&
                      stage_int(f.info, ipm + 1, FRIX_STAGE_SOLVER_ID) == FRIX_SOLVER_NSN_AC,
                  "no Newton stage right after the interior-point stage:\n%s", trace);
    ck_assert_msg(stage_double(f.info, ipm + 1, FRIX_STAGE_ERROR) < stage_double(f.info, ipm, FRIX_STAGE_ERROR),
                  "Newton did not improve on the interior point:\n%s", trace);
    /* And by a decade at least, within its first budget (100 steps): the interior point is
     * within Newton's reach. */
    ck_assert_msg(stage_double(f.info, ipm + 1, FRIX_STAGE_ERROR) <= 0.1 * stage_double(f.info, ipm, FRIX_STAGE_ERROR) &&
                      stage_int(f.info, ipm + 1, FRIX_STAGE_ITERATIONS) <= 100,
                  "Newton did not take the interior point a decade down:\n%s", trace);
    file_run_close(&f);
}
END_TEST

/* Spheres-n400 s140 (fclib-large) capped at 170 iterations: the interior-point stage and
 * Newton after it reach about 1.7e-3, far above 100 x the tolerance, so the rounds start from
 * NSGS's 2.2e-2 instead, and the cap ends them above the interior point's result (1.3e-2).
 * That result is returned, not the rounds' best: the answer is the best of every stage. */
START_TEST(test_set_aside_interior_point_returned) {
    file_run f;
    if (!file_run_open(&f, "../fclib-large/Spheres-n400-seed2-s00140-nc1165.hdf5", 1e-8)) return;
    ck_assert_int_eq(frix_options_set_int(frix_test_plain_sweeps(frix_test_siconos_measure(f.o)), FRIX_OPT_MAX_ITER, 170),
                     FRIX_OK);
    file_run_solve(&f);
    const char *trace = frix_info_trace(f.info);
    ck_assert_int_eq(frix_info_status(f.info), FRIX_STATUS_MAX_ITER);
    double best = INFINITY, last = NAN;
    int after_ipm = 0, rounds_above = 0;
    for (int64_t k = 0; k < frix_info_stage_count(f.info); ++k) {
        if (stage_int(f.info, k, FRIX_STAGE_PART) != 1 || stage_int(f.info, k, FRIX_STAGE_SOLVER_ID) == 0) continue;
        const double e = stage_double(f.info, k, FRIX_STAGE_ERROR);
        if (e < best) best = e;
        last = e;
        if (after_ipm && e > best) rounds_above = 1;
        if (stage_int(f.info, k, FRIX_STAGE_SOLVER_ID) == FRIX_SOLVER_IPM) after_ipm = 1;
    }
    ck_assert_msg(after_ipm && rounds_above && last > best, "not the case meant:\n%s", trace);
    const double e = frix_test_error_of(f.p, f.r, NULL, f.o);
    /* (the part's own measure against the whole problem's: the same up to rounding) */
    ck_assert_msg(e <= 1.001 * best, "returned %.4e, best stage %.4e\n%s", e, best, trace);
    file_run_close(&f);
}
END_TEST

/* Kapla-3x3x20 s30 (fclib-large, nine towers of blocks of about 311 contacts) at 1e-6: on each
 * tower NSGS's rate predicts more than ADMM's probe costs, ADMM from r = 0 then converges
 * within the probe (about 50 iterations, where NSGS alone sweeps about 3500 times: its
 * primal residual is exactly 0 at first, the contacts inside their cones, and rho must fall
 * for it to converge), and no other stage runs. */
START_TEST(test_towers_at_simulation_tolerance_by_admm_probe) {
    file_run f;
    if (!file_run_open(&f, "../fclib-large/Kapla-3x3x20-seed1-s00030-nc2799.hdf5", 1e-6)) return;
    frix_test_plain_sweeps(f.o);
    file_run_solve(&f);
    const char *trace = frix_info_trace(f.info);
    ck_assert_msg(frix_info_status(f.info) == FRIX_STATUS_CONVERGED, "%s\n%s",
                  frix_status_string(frix_info_status(f.info)), trace);
    int64_t parts = 0;
    ck_assert_int_eq(frix_info_get_int(f.info, FRIX_INFO_ISLANDS, &parts), FRIX_OK);
    ck_assert_int_eq(parts, 9);
    for (int64_t part = 1; part <= parts; ++part) {
        int64_t nsgs = -1, admm = -1, stages = 0;
        for (int64_t k = 0; k < frix_info_stage_count(f.info); ++k) {
            if (stage_int(f.info, k, FRIX_STAGE_PART) != part || stage_int(f.info, k, FRIX_STAGE_SOLVER_ID) == 0) continue;
            ++stages;
            if (stage_int(f.info, k, FRIX_STAGE_SOLVER_ID) == FRIX_SOLVER_NSGS_VELOCITY) nsgs = k;
            if (stage_int(f.info, k, FRIX_STAGE_SOLVER_ID) == FRIX_SOLVER_ADMM) admm = k;
        }
        ck_assert_msg(stages == 2 && nsgs >= 0 && admm == nsgs + 1, "part %lld: not NSGS then ADMM:\n%s",
                      (long long)part, trace);
        ck_assert_msg(stage_int(f.info, nsgs, FRIX_STAGE_STOPPED_BY_AUTO) == 1 &&
                          stage_int(f.info, nsgs, FRIX_STAGE_ITERATIONS) < 1000,
                      "part %lld: NSGS not stopped early:\n%s", (long long)part, trace);
        ck_assert_msg(stage_int(f.info, admm, FRIX_STAGE_STATUS) == FRIX_STATUS_CONVERGED &&
                          stage_int(f.info, admm, FRIX_STAGE_ITERATIONS) <= 100,
                      "part %lld: ADMM did not converge within its probe:\n%s", (long long)part, trace);
    }
    double e = NAN;
    ck_assert_int_eq(frix_problem_error(f.p, f.r, NULL, &e), FRIX_OK);
    ck_assert_double_le(e, 1e-6);
    file_run_close(&f);
}
END_TEST

/* Capsules-i125 (36 islands, the largest 57 contacts) at 1e-4: the small parts, whose |q| is
 * a small share of the whole problem's, stop at errors of their own up to 100 x the
 * tolerance, and the whole problem still meets it: one NSGS stage per part, no Newton (which
 * a part of 17 contacts needed when held to 1e-4 of its own size). */
START_TEST(test_small_parts_held_to_their_share) {
    const double tol = 1e-5;
    file_run f;
    if (!file_run_open(&f, "local/Capsules-i125-1213.hdf5", tol)) return;
    frix_test_plain_sweeps(f.o); /* with momentum the first sweeps on the whole meet the tolerance */
    file_run_solve(&f);
    const char *trace = frix_info_trace(f.info);
    ck_assert_msg(frix_info_status(f.info) == FRIX_STATUS_CONVERGED, "%s\n%s",
                  frix_status_string(frix_info_status(f.info)), trace);
    /* The sweeps on the whole problem first (part 0), then one converged NSGS per part. */
    ck_assert_msg(stage_int(f.info, 1, FRIX_STAGE_SOLVER_ID) == FRIX_SOLVER_NSGS &&
                      stage_int(f.info, 1, FRIX_STAGE_PART) == 0 &&
                      stage_int(f.info, 1, FRIX_STAGE_STATUS) == FRIX_STATUS_MAX_ITER,
                  "%s", trace);
    int loosened = 0;
    for (int64_t k = 2; k < frix_info_stage_count(f.info); ++k) {
        const int64_t id = stage_int(f.info, k, FRIX_STAGE_SOLVER_ID);
        ck_assert_msg((id == FRIX_SOLVER_NSGS_VELOCITY || id == FRIX_SOLVER_NSGS) &&
                          stage_int(f.info, k, FRIX_STAGE_STATUS) == FRIX_STATUS_CONVERGED,
                      "a stage other than one converged NSGS per part:\n%s", trace);
        loosened += stage_double(f.info, k, FRIX_STAGE_ERROR) > tol;
    }
    ck_assert_msg(loosened > 0, "no part stopped above the tolerance:\n%s", trace);
    double e = NAN;
    ck_assert_int_eq(frix_problem_error(f.p, f.r, NULL, &e), FRIX_OK);
    ck_assert_double_le(e, tol);
    file_run_close(&f);
}
END_TEST

/* NSGS near the tolerance on a plateau of its error (spheres-in-a-box at 1e-4: 1.7e-4 from
 * about sweep 100 to 750): stopped by its rate within 3 times the tolerance, it goes on for
 * the work of ADMM's probe before the probe, and crosses the plateau: no ADMM stage runs. */
START_TEST(test_nsgs_crosses_a_plateau_before_the_probe) {
    file_run f;
    if (!file_run_open(&f, "converted/spheres-in-a-box-98-i10000-256-10.reduced.hdf5", 1e-4)) return;
    frix_test_siconos_measure(f.o);
    file_run_solve(&f);
    const char *trace = frix_info_trace(f.info);
    ck_assert_msg(frix_info_status(f.info) == FRIX_STATUS_CONVERGED, "%s", trace);
    ck_assert_msg(find_stage(f.info, FRIX_SOLVER_ADMM, 0) < 0, "%s", trace);
    const int64_t first = find_stage(f.info, FRIX_SOLVER_NSGS_VELOCITY, 0);
    ck_assert_msg(first >= 0 && stage_int(f.info, first, FRIX_STAGE_STATUS) != FRIX_STATUS_CONVERGED, "%s", trace);
    const int64_t after = find_stage(f.info, FRIX_SOLVER_NSGS_VELOCITY, first + 1);
    ck_assert_msg(after >= 0 && stage_int(f.info, after, FRIX_STAGE_STATUS) == FRIX_STATUS_CONVERGED, "%s", trace);
    file_run_close(&f);
}
END_TEST

/* A priced part whose NSGS rate promises the tolerance within three times its sweeps but
 * not within twice, while the factorising alternative is priced lower (Spheres-n400 s200 at
 * 1e-6, one part of 1171 contacts): NSGS is stopped after ADMM's probe and ADMM from r = 0
 * finishes the part. Under the patience of unpriced parts (three times) NSGS went on to the
 * tolerance at about twice the cost. */
START_TEST(test_priced_part_stops_a_late_promise) {
    file_run f;
    if (!file_run_open(&f, "../fclib-large/Spheres-n400-seed2-s00200-nc1186.hdf5", 1e-6)) return;
    frix_test_siconos_measure(f.o);
    file_run_solve(&f);
    const char *trace = frix_info_trace(f.info);
    ck_assert_msg(frix_info_status(f.info) == FRIX_STATUS_CONVERGED, "%s", trace);
    const int64_t probe = find_stage(f.info, FRIX_SOLVER_ADMM, 0);
    const int64_t nsgs = probe < 0 ? -1 : find_stage(f.info, FRIX_SOLVER_NSGS_VELOCITY, probe + 1);
    ck_assert_msg(nsgs > probe && stage_int(f.info, nsgs, FRIX_STAGE_STOPPED_BY_AUTO) == 1, "%s", trace);
    const int64_t admm = find_stage(f.info, FRIX_SOLVER_ADMM, nsgs + 1);
    ck_assert_msg(admm > nsgs && stage_int(f.info, admm, FRIX_STAGE_STATUS) == FRIX_STATUS_CONVERGED, "%s", trace);
    file_run_close(&f);
}
END_TEST

/* A small part that NSGS does not finish, at a loose tolerance: Newton from r = 0 for a few
 * steps, then the interior point, whose solution is not polished (local_problem_test at 1e-4:
 * NSGS stalls at 8e-3, Newton alone takes 67 line-searched steps, the IPM 8). At 1e-8 the
 * rounds run as before: no interior-point stage. */
START_TEST(test_small_part_at_loose_tolerance_by_interior_point) {
    file_run f;
    if (!file_run_open(&f, "local/local_problem_test.hdf5", 1e-4)) return;
    file_run_solve(&f);
    const char *trace = frix_info_trace(f.info);
    ck_assert_msg(frix_info_status(f.info) == FRIX_STATUS_CONVERGED, "%s", trace);
    const int64_t newton = find_stage(f.info, FRIX_SOLVER_NSN_AC, 0), ipm = find_stage(f.info, FRIX_SOLVER_IPM, 0);
    ck_assert_msg(newton >= 0 && stage_int(f.info, newton, FRIX_STAGE_ITERATIONS) <= 10 && ipm > newton &&
                      stage_int(f.info, ipm, FRIX_STAGE_STATUS) == FRIX_STATUS_CONVERGED &&
                      ipm == frix_info_stage_count(f.info) - 1,
                  "%s", trace);
    file_run_close(&f);
    if (!file_run_open(&f, "local/local_problem_test.hdf5", 1e-8)) return;
    file_run_solve(&f);
    trace = frix_info_trace(f.info);
    ck_assert_msg(frix_info_status(f.info) == FRIX_STATUS_CONVERGED && find_stage(f.info, FRIX_SOLVER_IPM, 0) < 0,
                  "%s", trace);
    file_run_close(&f);
}
END_TEST

/* Before any part is set up: a problem of several parts that NSGS solves in a few sweeps ends
 * in the sweeps on the whole of it, and a small problem that is one part runs its first
 * stage at once, the same NSGS as the nsgs solver's (same iterations, same r). */
START_TEST(test_easy_problems_before_the_parts) {
    file_run f;
    if (!file_run_open(&f, "local/Capsules-i125-1213.hdf5", 1e-4)) return;
    file_run_solve(&f);
    const char *trace = frix_info_trace(f.info);
    ck_assert_msg(frix_info_status(f.info) == FRIX_STATUS_CONVERGED && frix_info_stage_count(f.info) == 2 &&
                      stage_int(f.info, 1, FRIX_STAGE_SOLVER_ID) == FRIX_SOLVER_NSGS &&
                      stage_int(f.info, 1, FRIX_STAGE_PART) == 0,
                  "%s", trace);
    int64_t islands = 0;
    ck_assert_int_eq(frix_info_get_int(f.info, FRIX_INFO_ISLANDS, &islands), FRIX_OK);
    ck_assert_int_eq(islands, 36);
    file_run_close(&f);

    if (!file_run_open(&f, "converted/FC3D_Example1.from_dat.hdf5", 1e-8)) return;
    file_run_solve(&f);
    ck_assert_msg(frix_info_status(f.info) == FRIX_STATUS_CONVERGED && frix_info_stage_count(f.info) == 2 &&
                      stage_int(f.info, 1, FRIX_STAGE_SOLVER_ID) == FRIX_SOLVER_NSGS,
                  "%s", frix_info_trace(f.info));
    double *r = calloc((size_t)f.m + 1, sizeof *r), *u = calloc((size_t)f.m + 1, sizeof *u);
    frix_options *o = NULL;
    frix_info *info = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_NSGS, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 1e-8), FRIX_OK);
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_solve(f.p, o, r, u, NULL, info), FRIX_OK);
    ck_assert_int_eq(frix_info_iterations(info), frix_info_iterations(f.info));
    ck_assert_mem_eq(r, f.r, (size_t)f.m * sizeof *r);
    frix_options_free(o);
    frix_info_free(info);
    free(r);
    free(u);
    file_run_close(&f);
}
END_TEST

/* A stack of 500 cubes, 8 contacts a face (4,000 contacts), in both forms. */
static void stack_of_500(frix_scene *scene, frix_scene_problems *pr) {
    frix_scene_params sp;
    frix_scene_defaults(FRIX_SCENE_STACK, &sp);
    sp.count = 500;
    sp.per_face = 8;
    ck_assert_int_eq(frix_scene_build(&sp, scene, NULL), FRIX_OK);
    ck_assert_int_eq(frix_scene_problems_make(scene, pr), FRIX_OK);
}

/* A stack of 500 cubes (4,000 contacts) whose W would exceed a memory limit of 500 kB (the
 * driver's bound on its blocks: 61 MB), as would M + rho H H^T's factor (the route without W),
 * though M's fits: auto stays on the sweeps without W (gnsgs) with all its iterations and
 * returns their answer and status. It failed with FRIX_ERR_OUT_OF_MEMORY where the sweeps
 * missed the tolerance and it turned to forming W. */
START_TEST(test_memory_limit_keeps_auto_off_w) {
    frix_scene scene;
    frix_scene_problems pr;
    stack_of_500(&scene, &pr);
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_AUTO, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 1e-6), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_MAX_ITER, 3000), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_MEMORY_LIMIT, 5e5), FRIX_OK);
    double *r = calloc((size_t)(3 * scene.nc), sizeof *r), *u = calloc((size_t)(3 * scene.nc), sizeof *u);
    double *v = calloc((size_t)scene.n, sizeof *v);
    frix_info *info = NULL, *check = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_msg(frix_solve(pr.global, o, r, u, v, info) == FRIX_OK, "%s", frix_last_error_message());
    const char *trace = frix_info_trace(info);
    ck_assert_msg(
        find_stage(info, FRIX_SOLVER_GLOBAL_NSGS, 0) >= 0 && find_stage(info, FRIX_SOLVER_NSGS_VELOCITY, 0) < 0, "%s",
        trace);
    ck_assert_int_eq(frix_info_iterations(info), 3000);
    ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_MAX_ITER);
    ck_assert_int_eq(frix_info_create(&check), FRIX_OK);
    ck_assert_int_eq(frix_problem_measure(pr.global, r, v, NULL, check), FRIX_OK);
    ck_assert_double_eq_tol(frix_info_error(check), frix_info_error(info), 1e-12);
    ck_assert_double_gt(frix_info_error(info), 1e-6);
    frix_info_free(check);
    frix_info_free(info);
    frix_options_free(o);
    free(r), free(u), free(v);
    frix_scene_problems_free(&pr);
    frix_scene_free(&scene);
}
END_TEST

/* A log sink that, at the line of auto's prices, maps and touches `grab` bytes of fresh pages
 * (not the heap's, which may be resident already): the host's memory growing between the
 * price of a route and its factorisations. */
typedef struct {
    size_t grab;
    char *taken;
} memory_grab;

static void grab_at_prices(void *data, const char *line) {
    memory_grab *g = data;
    if (!g->taken && g->grab > 0 && strstr(line, "auto: forming W priced")) {
        void *pages = mmap(NULL, g->grab, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        if (pages == MAP_FAILED) return;
        g->taken = pages;
        memset(g->taken, 1, g->grab);
    }
}

/* The same stack under a memory limit of 1 MB, where the route without W fits (gadmm converges;
 * under a sanitizer, whose allocator grows the resident memory more, it may be refused too).
 * Where the memory left shrinks after the price (the log sink takes 1.5 MB at auto's price line),
 * gadmm's and gnsn-al's factorisations are refused: auto ended with "memory limit reached" at the
 * start (error 0.98); now it turns to the sweeps without W, which factorise nothing. */
START_TEST(test_memory_shrinking_after_the_price) {
    frix_scene scene;
    frix_scene_problems pr;
    stack_of_500(&scene, &pr);
    double *r = calloc((size_t)(3 * scene.nc), sizeof *r), *u = calloc((size_t)(3 * scene.nc), sizeof *u);
    double *v = calloc((size_t)scene.n, sizeof *v);
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    for (int shrink = 0; shrink < 2; ++shrink) {
        memory_grab g = {shrink ? (size_t)1500000 : 0, NULL};
        frix_options *o = NULL;
        ck_assert_int_eq(frix_options_create(FRIX_SOLVER_AUTO, &o), FRIX_OK);
        ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 1e-6), FRIX_OK);
        ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_MAX_ITER, 3000), FRIX_OK);
        ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_MEMORY_LIMIT, 1e6), FRIX_OK);
        ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_VERBOSITY, 1), FRIX_OK);
        ck_assert_int_eq(frix_options_set_log(o, grab_at_prices, &g), FRIX_OK);
        memset(r, 0, sizeof *r * (size_t)(3 * scene.nc));
        memset(v, 0, sizeof *v * (size_t)scene.n);
        ck_assert_msg(frix_solve(pr.global, o, r, u, v, info) == FRIX_OK, "%s", frix_last_error_message());
        const char *trace = frix_info_trace(info);
        const int64_t admm = find_stage(info, FRIX_SOLVER_GLOBAL_ADMM, 0);
        ck_assert_msg(admm >= 0, "%s", trace);
        /* Never the start: gadmm's converged answer, or gnsgs's after all the iterations. */
        const frix_status status = frix_info_status(info);
        ck_assert_msg(status == FRIX_STATUS_CONVERGED ||
                          (status == FRIX_STATUS_MAX_ITER && find_stage(info, FRIX_SOLVER_GLOBAL_NSGS, 0) >= 0 &&
                           frix_info_iterations(info) == 3000),
                      "%s\n%s", frix_status_string(status), trace);
        ck_assert_msg(frix_info_error(info) < 0.1, "error %g\n%s", frix_info_error(info), trace);
        if (shrink)
            ck_assert_msg(g.taken != NULL && stage_int(info, admm, FRIX_STAGE_STATUS) == FRIX_STATUS_MEMORY_LIMIT &&
                              status == FRIX_STATUS_MAX_ITER,
                          "%s", trace);
        if (g.taken) munmap(g.taken, g.grab);
        frix_options_free(o);
    }
    frix_info_free(info);
    free(r), free(u), free(v);
    frix_scene_problems_free(&pr);
    frix_scene_free(&scene);
}
END_TEST

int main(void) {
    Suite *s = suite_create("auto");
    TCase *tc = tcase_create("stages");
    tcase_set_timeout(tc, 300);
    tcase_add_test(tc, test_random_restarts_one_trace_line_per_round);
    tcase_add_test(tc, test_set_aside_interior_point_returned);
    tcase_add_test(tc, test_towers_at_simulation_tolerance_by_admm_probe);
    tcase_add_test(tc, test_small_parts_held_to_their_share);
    tcase_add_test(tc, test_easy_problems_before_the_parts);
    tcase_add_test(tc, test_nsgs_crosses_a_plateau_before_the_probe);
    tcase_add_test(tc, test_small_part_at_loose_tolerance_by_interior_point);
    tcase_add_test(tc, test_priced_part_stops_a_late_promise);
    tcase_add_test(tc, test_contacts_in_different_units);
    tcase_add_test(tc, test_newton_from_stalled_interior_point);
    tcase_add_test(tc, test_first_nsgs_judged_after_its_work);
    tcase_add_test(tc, test_loose_tolerance_pile_solved_by_admm_first);
    tcase_add_test(tc, test_memory_limit_keeps_auto_off_w);
    tcase_add_test(tc, test_memory_shrinking_after_the_price);
    suite_add_tcase(s, tc);
    return frix_run_suite(s);
}
