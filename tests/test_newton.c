/* Semismooth Newton solvers (504 nsn-ac, 513 nsn-fb, 520 nsn-nm), PROX (502) and the
 * one-contact Newton solvers (550, 551, 561, 565): generalized Jacobians against finite
 * differences, quadratic convergence, factorisation reuse, the FCLIB problems Siconos's
 * NSN_AC solves to 1e-8, and PROX leaving the caller's problem untouched. */
#include <frix/frix.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check_main.h"
#include "shared_data.h"
#include "frix_testing.h"
#include "support/lcg.h"



/* A small deterministic generator (the tests must not depend on rand()). */
static uint64_t rng_state = 12345;
static double uniform(double lo, double hi) { return lo + (hi - lo) * lcg_uniform(&rng_state); }

/* ---- Jacobians against central finite differences. */

enum { REGIME_STICK, REGIME_SLIDE, REGIME_TAKE_OFF, REGIME_MU0, REGIMES };

/* A point (r, u) well inside one regime of the Coulomb law (away from the kinks). */
static void random_point(int regime, double *r, double *u, double *mu) {
    *mu = regime == REGIME_MU0 ? 0.0 : uniform(0.2, 1.0);
    const double th = uniform(0.0, 6.283185307179586);
    switch (regime) {
        case REGIME_STICK: /* r strictly inside the cone, u small */
            r[0] = uniform(0.5, 2.0);
            r[1] = 0.5 * *mu * r[0] * cos(th), r[2] = 0.5 * *mu * r[0] * sin(th);
            u[0] = uniform(-0.05, 0.05), u[1] = uniform(-0.05, 0.05), u[2] = uniform(-0.05, 0.05);
            break;
        case REGIME_SLIDE: /* r on the cone side, u_T opposite to r_T, u_N ~ 0 */
            r[0] = uniform(0.5, 2.0);
            r[1] = 1.5 * *mu * r[0] * cos(th), r[2] = 1.5 * *mu * r[0] * sin(th);
            u[0] = uniform(-0.1, 0.1);
            u[1] = -uniform(0.5, 1.0) * cos(th + 0.3), u[2] = -uniform(0.5, 1.0) * sin(th + 0.3);
            break;
        case REGIME_TAKE_OFF: /* separating */
            r[0] = uniform(-0.5, 0.2), r[1] = uniform(-0.3, 0.3), r[2] = uniform(-0.3, 0.3);
            u[0] = uniform(1.0, 2.0), u[1] = uniform(-1, 1), u[2] = uniform(-1, 1);
            break;
        default: /* mu = 0: generic */
            for (int i = 0; i < 3; ++i) r[i] = uniform(-1, 1), u[i] = uniform(-1, 1);
            break;
    }
}

START_TEST(jacobians_match_finite_differences) {
    const int formulation = _i; /* 0 AC, 1 FB, 2 NM */
    const double h = 1e-7;
    int checked = 0;
    rng_state = 777 + (uint64_t)formulation;
    for (int regime = 0; regime < REGIMES; ++regime)
        for (int trial = 0; trial < 200; ++trial) {
            double r[3], u[3], mu, phi[3], A[9], B[9];
            random_point(regime, r, u, &mu);
            const double rho_n = uniform(0.3, 2.0), rho_t = uniform(0.3, 2.0);
            frix_testing_contact_function(formulation, r, u, mu, rho_n, rho_t, phi, A, B);
            for (int j = 0; j < 3; ++j) {
                double rp[3], rm[3], up[3], um[3], pp[3], pm[3];
                memcpy(rp, r, sizeof rp), memcpy(rm, r, sizeof rm);
                memcpy(up, u, sizeof up), memcpy(um, u, sizeof um);
                rp[j] += h, rm[j] -= h, up[j] += h, um[j] -= h;
                frix_testing_contact_function(formulation, rp, u, mu, rho_n, rho_t, pp, NULL, NULL);
                frix_testing_contact_function(formulation, rm, u, mu, rho_n, rho_t, pm, NULL, NULL);
                for (int i = 0; i < 3; ++i)
                    ck_assert_msg(fabs((pp[i] - pm[i]) / (2 * h) - A[i + 3 * j]) < 1e-5,
                                  "formulation %d regime %d: dPhi_%d/dr_%d = %g, finite difference %g",
                                  formulation, regime, i, j, A[i + 3 * j], (pp[i] - pm[i]) / (2 * h));
                frix_testing_contact_function(formulation, r, up, mu, rho_n, rho_t, pp, NULL, NULL);
                frix_testing_contact_function(formulation, r, um, mu, rho_n, rho_t, pm, NULL, NULL);
                for (int i = 0; i < 3; ++i)
                    ck_assert_msg(fabs((pp[i] - pm[i]) / (2 * h) - B[i + 3 * j]) < 1e-5,
                                  "formulation %d regime %d: dPhi_%d/du_%d = %g, finite difference %g",
                                  formulation, regime, i, j, B[i + 3 * j], (pp[i] - pm[i]) / (2 * h));
            }
            ++checked;
        }
    ck_assert_int_eq(checked, 4 * 200);
}
END_TEST

START_TEST(phi_vanishes_at_solutions) {
    /* A sticking, a sliding and a separating contact that satisfy Coulomb's law exactly. */
    const double mu = 0.5;
    const double stick_r[3] = {1, 0.2, -0.1}, stick_u[3] = {0, 0, 0};
    const double slide_r[3] = {2, 0.6, 0.8}, slide_u[3] = {0, -0.3, -0.4};
    const double off_r[3] = {0, 0, 0}, off_u[3] = {1, 0.5, -2};
    for (int f = 0; f < 3; ++f) {
        double phi[3];
        frix_testing_contact_function(f, stick_r, stick_u, mu, 0.7, 0.9, phi, NULL, NULL);
        for (int i = 0; i < 3; ++i) ck_assert_double_eq_tol(phi[i], 0.0, 1e-14);
        frix_testing_contact_function(f, slide_r, slide_u, mu, 0.7, 0.9, phi, NULL, NULL);
        for (int i = 0; i < 3; ++i) ck_assert_double_eq_tol(phi[i], 0.0, 1e-14);
        frix_testing_contact_function(f, off_r, off_u, mu, 0.7, 0.9, phi, NULL, NULL);
        for (int i = 0; i < 3; ++i) ck_assert_double_eq_tol(phi[i], 0.0, 1e-14);
    }
}
END_TEST

/* ---- A small problem with a mix of sticking, sliding and separating contacts: nc contacts,
 * W = L L^T + 0.5 I (symmetric positive definite, dense), L random. */

#define MAX_NC 25

typedef struct {
    int nc;
    frix_matrix *W;
    double q[3 * MAX_NC], mu[MAX_NC];
    frix_problem *p;
} small_problem;

static void make_problem(small_problem *s, int nc) {
    const int m = 3 * nc;
    rng_state = 12345 + (uint64_t)nc; /* the same problem with and without CK_FORK */
    double *L = malloc((size_t)(m * m) * sizeof *L), *W = malloc((size_t)(m * m) * sizeof *W);
    for (int i = 0; i < m * m; ++i) L[i] = uniform(-0.5, 0.5);
    for (int i = 0; i < m; ++i)
        for (int j = 0; j < m; ++j) {
            double sum = i == j ? 0.5 : 0.0;
            for (int k = 0; k < m; ++k) sum += L[i + m * k] * L[j + m * k];
            W[i + m * j] = sum;
        }
    s->nc = nc;
    ck_assert_int_eq(frix_matrix_from_dense(m, m, W, m, &s->W), FRIX_OK);
    const double q4[12] = {-1, 0.1, 0.05, -1, 2.0, -1.5, 0.5, 0.3, 0.1, -0.8, 0.6, 0.9};
    for (int i = 0; i < m; ++i) s->q[i] = nc == 4 ? q4[i] : (i % 3 == 0 ? uniform(-1.5, -0.5) : uniform(-1, 1));
    for (int a = 0; a < nc; ++a) s->mu[a] = 0.4;
    ck_assert_int_eq(frix_problem_local(s->W, s->q, s->mu, nc, &s->p), FRIX_OK);
    free(L);
    free(W);
}

static void make_small(small_problem *s) { make_problem(s, 4); }

static void free_small(small_problem *s) {
    frix_problem_free(s->p);
    frix_matrix_free(s->W);
}

typedef struct {
    int n;
    double e[64];
} error_trace;

static int record(void *data, int64_t it, double error, double elapsed) {
    (void)it, (void)elapsed;
    error_trace *t = data;
    if (t->n < 64) t->e[t->n++] = error;
    return 0;
}

static frix_info *solve(const frix_problem *p, frix_options *o, double *r) {
    const int64_t m = frix_problem_contact_dofs(p);
    double *u = calloc((size_t)m + 1, sizeof *u);
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_solve(p, o, r, u, NULL, info), FRIX_OK);
    for (int64_t i = 0; i < m; ++i) ck_assert(isfinite(r[i]));
    double err = NAN;
    frix_info *check = NULL;
    ck_assert_int_eq(frix_info_create(&check), FRIX_OK);
    ck_assert_int_eq(frix_problem_measure(p, r, NULL, NULL, check), FRIX_OK);
    ck_assert_int_eq(frix_info_get_double(check, frix_test_error_key(o), &err), FRIX_OK);
    frix_info_free(check);
    if (frix_info_status(info) == FRIX_STATUS_CONVERGED) ck_assert(err <= frix_info_error(info) * 1.000001 + 1e-300);
    free(u);
    return info;
}

static int64_t info_int(const frix_info *info, frix_info_key key) {
    int64_t v = -1;
    ck_assert_int_eq(frix_info_get_int(info, key, &v), FRIX_OK);
    return v;
}

START_TEST(quadratic_convergence_near_the_solution) {
    const int id = _i == 0 ? FRIX_SOLVER_NSN_AC : _i == 1 ? FRIX_SOLVER_NSN_FB : FRIX_SOLVER_NSN_NM;
    small_problem s;
    make_small(&s);
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(id, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 1e-15), FRIX_OK);
    error_trace tr = {0};
    ck_assert_int_eq(frix_options_set_callback(o, record, &tr), FRIX_OK);
    double r[12] = {0};
    frix_info *info = solve(s.p, o, r);
    ck_assert_msg(frix_info_status(info) == FRIX_STATUS_CONVERGED, "%s", frix_status_string(frix_info_status(info)));
    /* Near the solution each step squares the error (up to a constant): every step that
     * starts below 1e-4 ends below 100 e^2 (or at round-off). A linearly converging method
     * fails this at once (e.g. 1e-4 -> 1e-5). */
    int seen = 0;
    for (int k = 0; k + 1 < tr.n; ++k)
        if (tr.e[k] < 1e-4 && tr.e[k] > 1e-12) {
            ck_assert_msg(tr.e[k + 1] <= 100.0 * tr.e[k] * tr.e[k] || tr.e[k + 1] <= 1e-14,
                          "step %d: %g -> %g is not quadratic", k, tr.e[k], tr.e[k + 1]);
            ++seen;
        }
    ck_assert_msg(seen >= 1, "no step in the quadratic zone (trace of %d)", tr.n);
    frix_info_free(info);
    frix_options_free(o);
    free_small(&s);
}
END_TEST

START_TEST(symbolic_analysis_is_reused) {
    /* 25 contacts: 75 unknowns, above the size the Newton solvers factorise dense. */
    small_problem s;
    make_problem(&s, 25);
    for (int k = 0; k < 2; ++k) {
        frix_options *o = NULL;
        ck_assert_int_eq(frix_options_create(k == 0 ? FRIX_SOLVER_NSN_AC : FRIX_SOLVER_PROX, &o), FRIX_OK);
        ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 1e-12), FRIX_OK);
        ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_LINE_SEARCH, FRIX_LINE_SEARCH_NONE), FRIX_OK);
        double r[3 * MAX_NC] = {0};
        frix_info *info = solve(s.p, o, r);
        ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_CONVERGED);
        const int64_t newton = info_int(info, FRIX_INFO_NEWTON_ITERATIONS);
        const int64_t sym = info_int(info, FRIX_INFO_SYMBOLIC_ANALYSES);
        ck_assert_int_ge(newton, 3);
        ck_assert_int_ge(info_int(info, FRIX_INFO_FACTORIZATIONS), newton);
        /* One analysis, plus one each time contacts join the active set. */
        ck_assert_int_ge(sym, 1);
        ck_assert_msg(sym < newton, "%lld analyses for %lld Newton steps", (long long)sym, (long long)newton);
        double ft = -1;
        ck_assert_int_eq(frix_info_get_double(info, FRIX_INFO_FACTORIZATION_TIME, &ft), FRIX_OK);
        ck_assert(ft >= 0.0);
        frix_info_free(info);
        frix_options_free(o);
    }
    free_small(&s);
}
END_TEST

START_TEST(prox_leaves_the_problem_unchanged) {
    small_problem s;
    make_small(&s);
    double q0[12], mu0[4];
    memcpy(q0, s.q, sizeof q0);
    memcpy(mu0, s.mu, sizeof mu0);
    int64_t nnz0 = 0, nnz1 = 0;
    ck_assert_int_eq(frix_matrix_to_csc(s.W, &nnz0, NULL, NULL, NULL), FRIX_OK);
    int64_t *p0 = malloc(13 * sizeof *p0), *i0 = malloc((size_t)nnz0 * sizeof *i0);
    double *x0 = malloc((size_t)nnz0 * sizeof *x0);
    ck_assert_int_eq(frix_matrix_to_csc(s.W, &nnz0, p0, i0, x0), FRIX_OK);

    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_PROX, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_PROX_ALPHA, 0.3), FRIX_OK); /* fixed */
    double r[12] = {0};
    frix_info *info = solve(s.p, o, r);
    ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_CONVERGED);

    ck_assert_int_eq(memcmp(q0, s.q, sizeof q0), 0);
    ck_assert_int_eq(memcmp(mu0, s.mu, sizeof mu0), 0);
    ck_assert_int_eq(frix_matrix_to_csc(s.W, &nnz1, NULL, NULL, NULL), FRIX_OK);
    ck_assert_int_eq(nnz1, nnz0);
    int64_t *p1 = malloc(13 * sizeof *p1), *i1 = malloc((size_t)nnz0 * sizeof *i1);
    double *x1 = malloc((size_t)nnz0 * sizeof *x1);
    ck_assert_int_eq(frix_matrix_to_csc(s.W, &nnz1, p1, i1, x1), FRIX_OK);
    ck_assert_int_eq(memcmp(p0, p1, 13 * sizeof *p0), 0);
    ck_assert_int_eq(memcmp(i0, i1, (size_t)nnz0 * sizeof *i0), 0);
    ck_assert_int_eq(memcmp(x0, x1, (size_t)nnz0 * sizeof *x0), 0);
    free(p0), free(i0), free(x0), free(p1), free(i1), free(x1);
    frix_info_free(info);
    frix_options_free(o);
    free_small(&s);
}
END_TEST

/* ---- FCLIB: every problem Siconos 4.4's NSN_AC solves to 1e-8 (siconos-4.4-baseline.csv):
 * all the local ones but RockPile_tob1. */

START_TEST(nsn_ac_solves_what_siconos_solves) {
    const char *file = kFclibLocalProblems[_i];
    if (strstr(file, "RockPile")) return; /* Siconos's NSN_AC does not solve it either */
    frix_problem *p = load(file);
    if (!p) return;
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_NSN_AC, &o), FRIX_OK);
    double *r = calloc((size_t)frix_problem_contact_dofs(p) + 1, sizeof *r);
    frix_info *info = solve(p, o, r);
    double err = NAN;
    ck_assert_int_eq(frix_problem_error(p, r, NULL, &err), FRIX_OK);
    ck_assert_msg(frix_info_status(info) == FRIX_STATUS_CONVERGED && err <= 1e-8,
                  "%s: %s, error %g after %lld iterations", file,
                  frix_status_string(frix_info_status(info)), err, (long long)frix_info_iterations(info));
    free(r);
    frix_info_free(info);
    frix_options_free(o);
    frix_problem_free(p);
}
END_TEST

/* The watchdog's failed excursion is undone whole: on local_problem_test nsn-ac tries the full
 * step once (its line search stalls where the full step halves the error), the error has not
 * fallen tenfold k steps later, and the run goes back to where it was with everything it knew
 * there: the same path as without the watchdog, k steps later (63 steps without it, 66 with
 * k = 3, 68 with k = 5). A state left behind (the regularisation, the best iterate, the stall
 * counters) changes that path. On spheres-in-a-box, where the full steps go on to converge,
 * the kept excursion is what solves it for nsn-fb (which stagnates at 2.3e-6 without it). */
START_TEST(watchdog_undoes_a_failed_excursion) {
    frix_problem *p = load("local/local_problem_test.hdf5");
    if (!p) return;
    const int64_t m = frix_problem_contact_dofs(p);
    double *r = calloc((size_t)m + 1, sizeof *r);
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_NSN_AC, &o), FRIX_OK);
    frix_test_siconos_measure(o);
    int64_t its[3] = {0, 0, 0};
    const int64_t steps[3] = {0, 3, 5};
    for (int k = 0; k < 3; ++k) {
        ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_WATCHDOG, steps[k]), FRIX_OK);
        memset(r, 0, sizeof(double) * (size_t)m);
        frix_info *info = solve(p, o, r);
        ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_CONVERGED);
        its[k] = frix_info_iterations(info);
        frix_info_free(info);
    }
    ck_assert_msg(its[1] == its[0] + 3 && its[2] == its[0] + 5,
                  "iterations: %lld without the watchdog, %lld with 3 steps, %lld with 5", (long long)its[0],
                  (long long)its[1], (long long)its[2]);
    frix_options_free(o);
    free(r);
    frix_problem_free(p);

    p = load("converted/spheres-in-a-box-98-i10000-256-10.reduced.hdf5");
    if (!p) return;
    r = calloc((size_t)frix_problem_contact_dofs(p) + 1, sizeof *r);
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_NSN_FB, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(frix_test_siconos_measure(o), FRIX_OPT_TIME_LIMIT, 30.0), FRIX_OK);
    frix_info *info = solve(p, o, r);
    ck_assert_msg(frix_info_status(info) == FRIX_STATUS_CONVERGED, "nsn-fb on spheres-in-a-box: %s, error %.3e",
                  frix_status_string(frix_info_status(info)), frix_info_error(info));
    frix_info_free(info);
    frix_options_free(o);
    free(r);
    frix_problem_free(p);
}
END_TEST

/* PROX on the rank-deficient rigid problems the literature gives it. */
static const char *const kProxSolves[] = {
    "local/Capsules-i125-1213.hdf5",
    "local/local_problem_test.hdf5",
    "local/LMGC_100_PR_PerioBox-i00361-60-03000.hdf5",
    "converted/Capsules-i100-1090.from_dat.hdf5",
    "converted/Capsules-i101-404.from_dat.hdf5",
    "converted/Box_Stacks-i0035-31-0.reduced.hdf5",
    "converted/OneObject-i100000-316.from_dat.hdf5",
};

START_TEST(prox_solves_rigid_problems) {
    const char *file = kProxSolves[_i];
    frix_problem *p = load(file);
    if (!p) return;
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_PROX, &o), FRIX_OK);
    double *r = calloc((size_t)frix_problem_contact_dofs(p) + 1, sizeof *r);
    frix_info *info = solve(p, o, r);
    ck_assert_msg(frix_info_status(info) == FRIX_STATUS_CONVERGED, "%s: %s, error %g", file,
                  frix_status_string(frix_info_status(info)), frix_info_error(info));
    /* Analyses happen only when contacts join the active set: far fewer than factorisations. */
    ck_assert_int_lt(2 * info_int(info, FRIX_INFO_SYMBOLIC_ANALYSES), info_int(info, FRIX_INFO_FACTORIZATIONS));
    free(r);
    frix_info_free(info);
    frix_options_free(o);
    frix_problem_free(p);
}
END_TEST

/* On RockPile_tob1 PROX's alpha rule cycles (a rejected step, alpha x10, x10, back to what the
 * error asks for, the same rejected step...): it must stop, stagnated, once a step would repeat
 * one already taken from the same iterate (14 steps), instead of spending max_iter (here 100
 * proximal steps; 1000 by default, over a minute) on the cycle. No time limit: the outcome
 * must not depend on the machine's speed. */
START_TEST(prox_stops_when_its_steps_would_repeat) {
    frix_problem *p = load("converted/RockPile_tob1.from_dat.hdf5");
    if (!p) return;
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_PROX, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_MAX_ITER, 100), FRIX_OK);
    const int64_t m = frix_problem_contact_dofs(p);
    double *r = calloc((size_t)m, sizeof *r);
    frix_info *info = solve(p, o, r);
    ck_assert_msg(frix_info_status(info) == FRIX_STATUS_STAGNATED, "%s after %lld steps",
                  frix_status_string(frix_info_status(info)), (long long)frix_info_iterations(info));
    ck_assert_int_le(frix_info_iterations(info), 50);
    /* r is the last accepted iterate, whose error the info reports. */
    double err = NAN;
    ck_assert_int_eq(frix_problem_error(p, r, NULL, &err), FRIX_OK);
    ck_assert(isfinite(err) && err < 1e-2);
    ck_assert_double_eq_tol(frix_info_error(info), err, 1e-12 * (1.0 + err));
    free(r);
    frix_info_free(info);
    frix_options_free(o);
    frix_problem_free(p);
}
END_TEST

/* nsn-fb and nsn-nm on a few problems of each family. */
START_TEST(fb_and_nm_solve_small_problems) {
    static const char *const files[] = {"converted/Rover4613.from_dat.hdf5",
                                        "converted/Confeti-ex03-Fc3D-SBM.from_dat.hdf5",
                                        "converted/LMGC_GFC3D-i00501-4-00000.reduced.hdf5",
                                        "local/LMGC_100_PR_PerioBox-i00361-60-03000.hdf5"};
    for (int k = 0; k < 4; ++k) {
        frix_problem *p = load(files[k]);
        if (!p) return;
        for (int f = 0; f < 2; ++f) {
            frix_options *o = NULL;
            ck_assert_int_eq(frix_options_create(f == 0 ? FRIX_SOLVER_NSN_FB : FRIX_SOLVER_NSN_NM, &o), FRIX_OK);
            double *r = calloc((size_t)frix_problem_contact_dofs(p) + 1, sizeof *r);
            frix_info *info = solve(p, o, r);
            ck_assert_msg(frix_info_status(info) == FRIX_STATUS_CONVERGED, "%s (%s): %s", files[k],
                          f == 0 ? "fb" : "nm", frix_status_string(frix_info_status(info)));
            free(r);
            frix_info_free(info);
            frix_options_free(o);
        }
        frix_problem_free(p);
    }
}
END_TEST

START_TEST(newton_options) {
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_NSN_AC, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_RHO_STRATEGY, FRIX_RHO_SPLIT), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_RHO_STRATEGY, 3), FRIX_ERR_OPTION_RANGE);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_LINE_SEARCH, FRIX_LINE_SEARCH_NONMONOTONE), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_RHO, 0.0), FRIX_ERR_OPTION_RANGE);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_PROX_ALPHA, 1.0), FRIX_ERR_UNKNOWN_OPTION);
    frix_options_free(o);
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_PROX, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_INNER_SOLVER, FRIX_SOLVER_NSN_FB), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_INNER_SOLVER, FRIX_SOLVER_NSGS), FRIX_ERR_OPTION_RANGE);
    frix_options_free(o);
    int id = 0;
    ck_assert_int_eq(frix_solver_by_name("FC3D_NSN_AC", &id), FRIX_OK);
    ck_assert_int_eq(id, 504);
    ck_assert_int_eq(frix_solver_by_name("nsn-nm", &id), FRIX_OK);
    ck_assert_int_eq(id, 520);
    ck_assert_int_eq(frix_solver_by_name("GFC3D_NSN_AC", &id), FRIX_OK);
    ck_assert_int_eq(id, 607);
    /* The global Newton refuses local problems with a clear error. */
    small_problem s;
    make_small(&s);
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_GLOBAL_NSN_AC, &o), FRIX_OK);
    double r[12] = {0}, u[12];
    ck_assert_int_eq(frix_solve(s.p, o, r, u, NULL, NULL), FRIX_ERR_UNSUPPORTED);
    frix_options_free(o);
    free_small(&s);
}
END_TEST

/* ---- One-contact Newton solvers against the closed form (562). */
START_TEST(local_newton_solvers) {
    static const int solvers[] = {553, 550, 551, 561, 565};
    int solved[5] = {0}, total = 0;
    rng_state = 4242;
    for (int trial = 0; trial < 300; ++trial) {
        double L[9], W[9], q[3], mu = trial % 7 == 0 ? 0.0 : uniform(0.1, 1.0);
        for (int i = 0; i < 9; ++i) L[i] = uniform(-1, 1);
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) {
                double sum = i == j ? 0.2 : 0.0;
                for (int k = 0; k < 3; ++k) sum += L[i + 3 * k] * L[j + 3 * k];
                W[i + 3 * j] = sum;
            }
        q[0] = uniform(-1, 0.3), q[1] = uniform(-1, 1), q[2] = uniform(-1, 1);
        ++total;
        int ok[5];
        for (int k = 0; k < 5; ++k) {
            double r[3] = {0, 0, 0}, rel = 1;
            const int out = frix_testing_solve_contact(W, q, mu, r, solvers[k], 1e-12, 50);
            frix_testing_contact_residual(W, q, mu, r, &rel);
            ck_assert(isfinite(r[0]) && isfinite(r[1]) && isfinite(r[2]));
            ok[k] = out != FRIX_TESTING_NOT_CONVERGED;
            if (ok[k]) {
                ck_assert_msg(rel <= 1e-10, "solver %d: outcome %d with residual %g", solvers[k], out, rel);
                ++solved[k];
            }
        }
        /* The hybrid solves every contact the projections (553) solve. */
        ck_assert_msg(!ok[0] || ok[4], "trial %d: 553 solves it, 565 does not", trial);
    }
    /* The line-searched Newton solvers solve nearly all of them from r = 0. */
    for (int k = 2; k < 4; ++k)
        ck_assert_msg(solved[k] >= total * 95 / 100, "solver %d solved %d of %d", solvers[k], solved[k], total);
}
END_TEST

/* NSGS with the hybrid local solver solves what NSGS with projections (553) solves. */
static const char *const kNsgs553Solves[] = {
    "converted/OneObject-i100000-316.from_dat.hdf5",
    "converted/OneObject-i1028-138.from_dat.hdf5",
    "local/LMGC_100_PR_PerioBox-i00361-60-03000.hdf5",
    "converted/Confeti-ex03-Fc3D-SBM.from_dat.hdf5",
    "converted/NESpheres_10_1.from_dat.hdf5",
    "converted/Rover4613.from_dat.hdf5",
    "converted/GFC3D_Example00_badly_scaled.from_dat.hdf5",
};

START_TEST(nsgs_hybrid_as_robust_as_projection) {
    const char *file = kNsgs553Solves[_i];
    frix_problem *p = load(file);
    if (!p) return;
    for (int k = 0; k < 2; ++k) {
        frix_options *o = NULL;
        ck_assert_int_eq(frix_options_create(FRIX_SOLVER_NSGS, &o), FRIX_OK);
        frix_test_siconos_measure(o);
        const frix_local_solver local = k == 0 ? FRIX_LOCAL_PROJECTION_ITERATED : FRIX_LOCAL_HYBRID;
        ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_LOCAL_SOLVER, local), FRIX_OK);
        double *r = calloc((size_t)frix_problem_contact_dofs(p) + 1, sizeof *r);
        frix_info *info = solve(p, o, r);
        ck_assert_msg(frix_info_status(info) == FRIX_STATUS_CONVERGED, "%s with %d: %s", file,
                      k == 0 ? 553 : 565, frix_status_string(frix_info_status(info)));
        free(r);
        frix_info_free(info);
        frix_options_free(o);
    }
    frix_problem_free(p);
}
END_TEST

int main(void) {
    Suite *s = suite_create("newton");
    TCase *tc = tcase_create("core");
    tcase_set_timeout(tc, 120);
    tcase_add_loop_test(tc, jacobians_match_finite_differences, 0, 3);
    tcase_add_test(tc, phi_vanishes_at_solutions);
    tcase_add_loop_test(tc, quadratic_convergence_near_the_solution, 0, 3);
    tcase_add_test(tc, symbolic_analysis_is_reused);
    tcase_add_test(tc, prox_leaves_the_problem_unchanged);
    tcase_add_test(tc, newton_options);
    tcase_add_test(tc, local_newton_solvers);
    tcase_add_loop_test(tc, nsn_ac_solves_what_siconos_solves, 0, FRIX_FCLIB_LOCAL_COUNT);
    tcase_add_loop_test(tc, prox_solves_rigid_problems, 0, (int)(sizeof kProxSolves / sizeof kProxSolves[0]));
    tcase_add_test(tc, prox_stops_when_its_steps_would_repeat);
    tcase_add_test(tc, watchdog_undoes_a_failed_excursion);
    tcase_add_test(tc, fb_and_nm_solve_small_problems);
    tcase_add_loop_test(tc, nsgs_hybrid_as_robust_as_projection, 0,
                        (int)(sizeof kNsgs553Solves / sizeof kNsgs553Solves[0]));
    suite_add_tcase(s, tc);
    return frix_run_suite(s);
}
