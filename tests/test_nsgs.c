/* NSGS (id 500) through the public API: the FCLIB problems it must solve to 1e-8, checked
 * with an independent recomputation of the error; determinism, warm start, the stopping
 * statuses and the callback. The slow problems belong to tools/bench, not here. */
#include <frix/frix.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check_main.h"
#include "frix_testing.h"
#include "shared_data.h"



static frix_options *nsgs_options(double tol) {
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_NSGS, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, tol), FRIX_OK);
    return o;
}

static void assert_finite(const double *x, int64_t n) {
    for (int64_t i = 0; i < n; ++i) ck_assert_msg(isfinite(x[i]), "entry %lld is not finite", (long long)i);
}

typedef struct {
    frix_status status;
    int64_t iterations;
    double error; /* recomputed from r */
} outcome;

static outcome solve(const frix_problem *p, const frix_options *o, double *r) {
    const int64_t m = frix_problem_contact_dofs(p);
    double *u = malloc((size_t)(m > 0 ? m : 1) * sizeof *u);
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_solve(p, o, r, u, NULL, info), FRIX_OK);
    outcome out = {frix_info_status(info), frix_info_iterations(info), NAN};
    assert_finite(r, m);
    out.error = frix_test_error_of(p, r, NULL, o);
    /* The measure is also what the info reports, and u is W r + q. */
    ck_assert_double_eq_tol(out.error, frix_info_error(info), 1e-12 + 1e-6 * out.error);
    double *w_r_q = malloc((size_t)(m > 0 ? m : 1) * sizeof *w_r_q);
    frix_info *measured = NULL;
    ck_assert_int_eq(frix_info_create(&measured), FRIX_OK);
    ck_assert_int_eq(frix_problem_measure(p, r, NULL, w_r_q, measured), FRIX_OK);
    for (int64_t i = 0; i < m; ++i) ck_assert_double_eq_tol(u[i], w_r_q[i], 1e-12 * (1.0 + fabs(w_r_q[i])));
    frix_info_free(measured);
    free(w_r_q);
    frix_info_free(info);
    free(u);
    return out;
}

static double *zeros(const frix_problem *p) {
    return calloc((size_t)frix_problem_contact_dofs(p) + 1, sizeof(double));
}

/* Every problem Siconos 4.4's NSGS solves to 1e-8 (siconos-4.4-baseline.csv); each takes well
 * under a second here. */
static const char *const kMustSolve[] = {
    "local/Capsules-i125-1213.hdf5",
    "local/LMGC_100_PR_PerioBox-i00361-60-03000.hdf5",
    "converted/Capsules-i100-1090.from_dat.hdf5",
    "converted/Capsules-i101-404.from_dat.hdf5",
    "converted/Confeti-ex03-Fc3D-SBM.from_dat.hdf5",
    "converted/Confeti-ex13-4contact-Fc3D-SBM.from_dat.hdf5",
    "converted/OneObject-i1028-138.from_dat.hdf5",
    "converted/NESpheres_10_1.from_dat.hdf5",
    "converted/LMGC_GFC3D-i00501-4-00000.reduced.hdf5",
    "converted/Box_Stacks-i0035-31-0.reduced.hdf5",
    "converted/FC3D_Example1.from_dat.hdf5",
    "converted/FrictionContact3D_1c.from_dat.hdf5",
    "converted/GFC3D_Example1_v2.from_dat.hdf5",
    "converted/GFC3D_TwoRods1.from_dat.hdf5",
    "converted/Rover1039.from_dat.hdf5",
    "converted/Rover1040.from_dat.hdf5",
    "converted/Rover11035.from_dat.hdf5",
    "converted/Rover3865.from_dat.hdf5",
    "converted/Rover4396.from_dat.hdf5",
    "converted/Rover4516.from_dat.hdf5",
    "converted/Rover4613.from_dat.hdf5",
};
#define N_MUST_SOLVE ((int)(sizeof kMustSolve / sizeof kMustSolve[0]))

START_TEST(solves_to_1e8) {
    const char *file = kMustSolve[_i];
    frix_problem *p = load(file);
    if (!p) return;
    frix_options *o = nsgs_options(1e-8);
    double *r = zeros(p);
    outcome out = solve(p, o, r);
    ck_assert_msg(out.status == FRIX_STATUS_CONVERGED, "%s: status %s after %lld sweeps, error %g",
                  file, frix_status_string(out.status), (long long)out.iterations, out.error);
    ck_assert_msg(out.error <= 1e-8, "%s: recomputed error %g", file, out.error);
    free(r);
    frix_options_free(o);
    frix_problem_free(p);
}
END_TEST

START_TEST(first_sweep_gets_a_full_check) {
    /* PerioBox: after one sweep from r = 0 the error is 3.6e-6 while r still moves by 0.6 %
     * a sweep (W's null space); the light error alone would keep sweeping for 16. */
    frix_problem *p = load("local/LMGC_100_PR_PerioBox-i00361-60-03000.hdf5");
    if (!p) return;
    frix_options *o = frix_test_siconos_measure(nsgs_options(1e-4));
    double *r = zeros(p);
    outcome out = solve(p, o, r);
    ck_assert_int_eq(out.status, FRIX_STATUS_CONVERGED);
    ck_assert_int_eq(out.iterations, 1);
    ck_assert(out.error <= 1e-4);
    free(r);
    frix_options_free(o);
    frix_problem_free(p);
}
END_TEST

START_TEST(relaxation_breaks_limit_cycle) {
    /* Plain NSGS (Siconos' too) cycles at an error of 1.7e-3 on this one; omega = 0.9 solves it. */
    frix_problem *p = load("converted/OneObject-i100000-316.from_dat.hdf5");
    if (!p) return;
    frix_options *o = nsgs_options(1e-8);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_RELAXATION, 0.9), FRIX_OK);
    double *r = zeros(p);
    outcome out = solve(p, o, r);
    ck_assert_int_eq(out.status, FRIX_STATUS_CONVERGED);
    ck_assert(out.error <= 1e-8);
    free(r);
    frix_options_free(o);
    frix_problem_free(p);
}
END_TEST

START_TEST(drift_window_carries_load_transfer_ahead) {
    /* RockPile: on its 295-contact island the sweeps sit for millions of iterations on plateaus
     * of the error while two contacts hand load to each other at a steady rate (plain nsgs-v:
     * about 6.5 million sweeps to 1e-8 on the island alone; at 620000 sweeps on the whole
     * problem they are at 6.3e-8). Carried ahead every 1000 sweeps, that drift takes nsgs-v to
     * 1e-8 in about 620000 sweeps on the whole problem. */
    frix_problem *p = load("converted/RockPile_tob1.from_dat.hdf5");
    if (!p) return;
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_NSGS_VELOCITY, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_MAX_ITER, 1000000), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_DRIFT_WINDOW, 1000), FRIX_OK);
    double *r = zeros(p);
    const outcome drift = solve(p, o, r);
    ck_assert_msg(drift.status == FRIX_STATUS_CONVERGED && drift.error <= 1e-8,
                  "with drift_window: %s after %lld sweeps, error %g", frix_status_string(drift.status),
                  (long long)drift.iterations, drift.error);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_DRIFT_WINDOW, -1), FRIX_ERR_OPTION_RANGE);
    free(r);
    frix_options_free(o);
    frix_problem_free(p);
}
END_TEST

START_TEST(acceleration_cuts_sweeps_on_a_pile) {
    /* Kapla-3x3x20 s30 (fclib-large, towers of blocks): load crosses a tower about a layer a
     * sweep. With acceleration (momentum with restart), nsgs-v reaches 1e-4 in less than half
     * the sweeps it needs without. Freezing is off under momentum: freezing 10 (nsgs-v's
     * default) and 0 give the same bits. */
    frix_problem *p = load("../fclib-large/Kapla-3x3x20-seed1-s00030-nc2799.hdf5");
    if (!p) return;
    const int64_t m = frix_problem_contact_dofs(p);
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_NSGS_VELOCITY, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 1e-4), FRIX_OK);
    int64_t is_on = -1;
    ck_assert_int_eq(frix_options_get_int(o, FRIX_OPT_ACCELERATION, &is_on), FRIX_OK);
    ck_assert_int_eq(is_on, 0);
    double *plain = zeros(p), *fast = zeros(p), *unfrozen = zeros(p);
    const outcome without = solve(p, o, plain);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_ACCELERATION, 1), FRIX_OK);
    const outcome with = solve(p, o, fast);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_FREEZING, 0), FRIX_OK);
    const outcome with_unfrozen = solve(p, o, unfrozen);
    ck_assert_int_eq(without.status, FRIX_STATUS_CONVERGED);
    ck_assert_int_eq(with.status, FRIX_STATUS_CONVERGED);
    ck_assert(with.error <= 1e-4);
    ck_assert_msg(2 * with.iterations <= without.iterations, "%lld sweeps with acceleration, %lld without",
                  (long long)with.iterations, (long long)without.iterations);
    ck_assert_int_eq(with_unfrozen.iterations, with.iterations);
    ck_assert_mem_eq(unfrozen, fast, sizeof(double) * (size_t)m);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_ACCELERATION, 2), FRIX_ERR_OPTION_RANGE);
    free(plain);
    free(fast);
    free(unfrozen);
    frix_options_free(o);
    frix_problem_free(p);
}
END_TEST

START_TEST(momentum_gives_up_on_a_plateau) {
    /* Kapla-4x2x25-ball s60 (fclib-large): with momentum nsgs-v's error sits on a plateau above
     * 1e-4 (40000 sweeps did not end it); once the best full check has not halved in 2000
     * sweeps the momentum is off for the rest of the run, and the plain sweeps with freezing
     * converge. */
    frix_problem *p = load("../fclib-large/Kapla-4x2x25-ball-seed2-s00060-nc2948.hdf5");
    if (!p) return;
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_NSGS_VELOCITY, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 1e-4), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_ACCELERATION, 1), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_MAX_ITER, 12000), FRIX_OK);
    double *r = zeros(p);
    const outcome run = solve(p, o, r);
    ck_assert_msg(run.status == FRIX_STATUS_CONVERGED && run.error <= 1e-4, "%s after %lld sweeps, error %.3e",
                  frix_status_string(run.status), (long long)run.iterations, run.error);
    free(r);
    frix_options_free(o);
    frix_problem_free(p);
}
END_TEST

START_TEST(same_seed_same_bits) {
    frix_problem *p = load("local/Capsules-i125-1213.hdf5");
    if (!p) return;
    const int64_t m = frix_problem_contact_dofs(p);
    frix_options *o = nsgs_options(1e-8);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_SHUFFLE, FRIX_SHUFFLE_EACH_SWEEP), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_SEED, 42), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_MAX_ITER, 300), FRIX_OK);
    double *r1 = zeros(p), *r2 = zeros(p), *r3 = zeros(p);
    solve(p, o, r1);
    solve(p, o, r2);
    ck_assert(memcmp(r1, r2, (size_t)m * sizeof(double)) == 0);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_SEED, 43), FRIX_OK);
    solve(p, o, r3);
    ck_assert(memcmp(r1, r3, (size_t)m * sizeof(double)) != 0); /* the seed is really used */
    free(r1);
    free(r2);
    free(r3);
    frix_options_free(o);
    frix_problem_free(p);
}
END_TEST

START_TEST(warm_start_from_solution) {
    frix_problem *p = load("converted/Capsules-i100-1090.from_dat.hdf5");
    if (!p) return;
    frix_options *o = nsgs_options(1e-8);
    double *r = zeros(p);
    ck_assert_int_eq(solve(p, o, r).status, FRIX_STATUS_CONVERGED);
    outcome again = solve(p, o, r);
    ck_assert_int_eq(again.status, FRIX_STATUS_CONVERGED);
    ck_assert_int_le(again.iterations, 2);
    ck_assert(again.error <= 1e-8);
    free(r);
    frix_options_free(o);
    frix_problem_free(p);
}
END_TEST

/* A stage of auto whose part already holds its warm start's measures (u = W r + q) takes them
 * instead of paying for the same product with W again: handed a start that claims to solve
 * the problem it ends at once on that claim; handed the true measures it sweeps, to the same
 * answer as from a start it measures itself. */
START_TEST(stage_takes_the_measured_start) {
    frix_problem *p = load("converted/Capsules-i100-1090.from_dat.hdf5");
    if (!p) return;
    const int64_t m = frix_problem_contact_dofs(p);
    frix_options *o = nsgs_options(1e-8);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_MAX_ITER, 5), FRIX_OK);
    double *start = zeros(p), *r = zeros(p);
    ck_assert_int_eq(solve(p, o, start).status, FRIX_STATUS_MAX_ITER); /* a warm start short of 1e-8 */
    const int solvers[] = {FRIX_SOLVER_NSGS, FRIX_SOLVER_NSGS_VELOCITY};
    for (int k = 0; k < 2; ++k) {
        int64_t sweeps = -1;
        double error = NAN;
        memcpy(r, start, (size_t)m * sizeof *r);
        ck_assert_int_eq(frix_testing_stage_from_measured_start(p, solvers[k], 0.0, r, &sweeps, &error), FRIX_OK);
        ck_assert_int_eq(sweeps, 0);
        ck_assert(error == 0.0);
        ck_assert(memcmp(r, start, (size_t)m * sizeof *r) == 0);
        memcpy(r, start, (size_t)m * sizeof *r);
        ck_assert_int_eq(frix_testing_stage_from_measured_start(p, solvers[k], 1.0, r, &sweeps, &error), FRIX_OK);
        ck_assert_int_gt(sweeps, 0);
        ck_assert(error <= 1e-8);
        ck_assert_double_eq_tol(error, frix_test_error_of(p, r, NULL, o), 1e-12);
    }
    free(r);
    free(start);
    frix_options_free(o);
    frix_problem_free(p);
}
END_TEST

START_TEST(max_iter_status) {
    frix_problem *p = load("local/Capsules-i125-1213.hdf5");
    if (!p) return;
    frix_options *o = nsgs_options(1e-8);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_MAX_ITER, 5), FRIX_OK);
    double *r = zeros(p);
    outcome out = solve(p, o, r);
    ck_assert_int_eq(out.status, FRIX_STATUS_MAX_ITER);
    ck_assert_int_eq(out.iterations, 5);
    ck_assert(out.error > 1e-8);
    free(r);
    frix_options_free(o);
    frix_problem_free(p);
}
END_TEST

START_TEST(time_limit_status) {
    /* NSGS does not reach 1e-8 on this one (nor does Siconos'): only the clock stops it. */
    frix_problem *p = load("local/local_problem_test.hdf5");
    if (!p) return;
    frix_options *o = nsgs_options(1e-8);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TIME_LIMIT, 0.05), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_MAX_ITER, 1000000000), FRIX_OK);
    double *r = zeros(p);
    frix_info *info = NULL;
    double *u = zeros(p);
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_solve(p, o, r, u, NULL, info), FRIX_OK);
    ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_TIME_LIMIT);
    ck_assert(frix_info_solve_time(info) < 2.0);
    assert_finite(r, frix_problem_contact_dofs(p));
    frix_info_free(info);
    free(u);
    free(r);
    frix_options_free(o);
    frix_problem_free(p);
}
END_TEST

typedef struct {
    int64_t calls, last_iteration, stop_at;
    int monotone;
} callback_log;

static int on_progress(void *data, int64_t iteration, double error, double elapsed) {
    callback_log *log = data;
    if (iteration != log->last_iteration + 1 || !(error >= 0) || !(elapsed >= 0)) log->monotone = 0;
    log->last_iteration = iteration;
    ++log->calls;
    return iteration >= log->stop_at;
}

START_TEST(callback_stops) {
    frix_problem *p = load("local/Capsules-i125-1213.hdf5");
    if (!p) return;
    frix_options *o = nsgs_options(1e-8);
    callback_log log = {0, 0, 3, 1};
    ck_assert_int_eq(frix_options_set_callback(o, on_progress, &log), FRIX_OK);
    double *r = zeros(p);
    outcome out = solve(p, o, r);
    ck_assert_int_eq(out.status, FRIX_STATUS_STOPPED_BY_CALLBACK);
    ck_assert_int_eq(out.iterations, 3);
    ck_assert_int_eq(log.calls, 3);
    ck_assert(log.monotone);
    free(r);
    frix_options_free(o);
    frix_problem_free(p);
}
END_TEST

START_TEST(variants_stay_finite_and_in_cone) {
    /* Single-step local solver, over-relaxation and shuffles: r finite, inside the cones. */
    frix_problem *p = load("converted/OneObject-i1028-138.from_dat.hdf5");
    if (!p) return;
    const int64_t m = frix_problem_contact_dofs(p);
    struct {
        int local, shuffle;
        double omega;
    } cases[] = {{552, 0, 1.0}, {553, 1, 1.5}, {562, 2, 0.7}, {552, 2, 1.3}, {553, 0, 1.0}};
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
        frix_options *o = nsgs_options(1e-8);
        ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_LOCAL_SOLVER, cases[k].local), FRIX_OK);
        ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_SHUFFLE, cases[k].shuffle), FRIX_OK);
        ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_RELAXATION, cases[k].omega), FRIX_OK);
        ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_MAX_ITER, 200), FRIX_OK);
        double *r = zeros(p), *u = zeros(p);
        frix_info *info = NULL;
        ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
        ck_assert_int_eq(frix_solve(p, o, r, u, NULL, info), FRIX_OK);
        assert_finite(r, m);
        double cone;
        ck_assert_int_eq(frix_info_get_double(info, FRIX_INFO_CONE_VIOLATION, &cone), FRIX_OK);
        ck_assert_msg(cone <= 1e-12, "case %zu: cone violation %g", k, cone);
        frix_info_free(info);
        free(u);
        free(r);
        frix_options_free(o);
    }
    frix_problem_free(p);
}
END_TEST

START_TEST(contact_without_diagonal_block) {
    /* Contact 1 has no diagonal block (W_11 = 0) and q_N < 0: no local solution exists.
     * The solve must end cleanly, r finite, without claiming convergence. */
    const int64_t rows[3] = {0, 0, 1}, cols[3] = {0, 1, 0};
    double blocks[27] = {2, 0, 0, 0, 1, 0, 0, 0, 1, /* W_00 */
                         0.1, 0, 0, 0, 0, 0, 0, 0, 0, /* W_01 */
                         0.1, 0, 0, 0, 0, 0, 0, 0, 0 /* W_10 */};
    frix_matrix *W = NULL;
    ck_assert_int_eq(frix_matrix_from_blocks(2, 2, 3, rows, cols, blocks, &W), FRIX_OK);
    const double q[6] = {-1, 0.1, 0, -1, 0.2, 0}, mu[2] = {0.5, 0.5};
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_problem_local(W, q, mu, 2, &p), FRIX_OK);
    frix_options *o = nsgs_options(1e-8);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_MAX_ITER, 50), FRIX_OK);
    double r[6] = {0}, u[6];
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_solve(p, o, r, u, NULL, info), FRIX_OK);
    assert_finite(r, 6);
    ck_assert_int_ne(frix_info_status(info), FRIX_STATUS_CONVERGED);
    frix_info_free(info);
    frix_options_free(o);
    frix_problem_free(p);
    frix_matrix_free(W);
}
END_TEST

static Suite *nsgs_suite(void) {
    Suite *s = suite_create("nsgs");
    TCase *files = tcase_create("fclib");
    tcase_add_loop_test(files, solves_to_1e8, 0, N_MUST_SOLVE);
    tcase_add_test(files, first_sweep_gets_a_full_check);
    tcase_add_test(files, relaxation_breaks_limit_cycle);
    tcase_add_test(files, drift_window_carries_load_transfer_ahead);
    tcase_add_test(files, acceleration_cuts_sweeps_on_a_pile);
    tcase_add_test(files, momentum_gives_up_on_a_plateau);
    tcase_add_test(files, same_seed_same_bits);
    tcase_add_test(files, warm_start_from_solution);
    tcase_add_test(files, stage_takes_the_measured_start);
    suite_add_tcase(s, files);
    TCase *stops = tcase_create("stopping");
    tcase_add_test(stops, max_iter_status);
    tcase_add_test(stops, time_limit_status);
    tcase_add_test(stops, callback_stops);
    suite_add_tcase(s, stops);
    TCase *robust = tcase_create("robustness");
    tcase_add_test(robust, variants_stay_finite_and_in_cone);
    tcase_add_test(robust, contact_without_diagonal_block);
    suite_add_tcase(s, robust);
    return s;
}

int main(void) { return frix_run_suite(nsgs_suite()); }
