/* Global problems (M, H, f, w, mu): the reduction W = H^T M^-1 H (CHOLMOD, or UMFPACK when M
 * is not SPD) followed by any local solver, and the Newton solver on (v, r) (607), on the
 * FCLIB global files and on small problems stored as general CSC. */
#include <frix/frix.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check_main.h"
#include "frix_testing.h"
#include "stage_records.h"
#include "elastic_grid.h"
#include "shared_data.h"



typedef struct {
    frix_status status;
    double error, equilibrium;
} outcome;

/* Solves, then checks the reported measures against an independent frix_problem_measure.
 * `kept`, when not NULL, receives the solve's info (for its trace). */
static outcome solve_global_into(const frix_problem *p, int solver, double *r, double *v, frix_info *kept) {
    const int64_t m = frix_problem_contact_dofs(p), n = frix_problem_dofs(p);
    double *u = calloc((size_t)m + 1, sizeof *u);
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(solver, &o), FRIX_OK);
    if (kept) frix_test_siconos_measure(o); /* the routing cases were measured on it */
    frix_info *info = kept, *check = NULL;
    if (!kept) ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_info_create(&check), FRIX_OK);
    ck_assert_msg(frix_solve(p, o, r, u, v, info) == FRIX_OK, "%s", frix_last_error_message());
    for (int64_t i = 0; i < m; ++i) ck_assert(isfinite(r[i]));
    for (int64_t j = 0; j < n; ++j) ck_assert(isfinite(v[j]));
    ck_assert_int_eq(frix_problem_measure(p, r, v, NULL, check), FRIX_OK);
    outcome out = {frix_info_status(info), NAN, NAN};
    ck_assert_int_eq(frix_info_get_double(check, FRIX_INFO_ERROR_RELATIVE, &out.error), FRIX_OK);
    ck_assert_int_eq(frix_info_get_double(check, FRIX_INFO_EQUILIBRIUM, &out.equilibrium), FRIX_OK);
    double reported = NAN;
    ck_assert_int_eq(frix_info_get_double(info, FRIX_INFO_EQUILIBRIUM, &reported), FRIX_OK);
    ck_assert_double_eq_tol(reported, out.equilibrium, 1e-12);
    frix_info_free(check);
    if (!kept) frix_info_free(info);
    frix_options_free(o);
    free(u);
    return out;
}

static outcome solve_global(const frix_problem *p, int solver, double *r, double *v) {
    return solve_global_into(p, solver, r, v, NULL);
}

/* An elastic grid (tests/support/elastic_grid.h) with zeroed r, u (3nc) and v (n). */
typedef struct {
    frix_elastic_grid grid;
    const frix_problem *p;
    int64_t m, n;
    double *r, *u, *v;
} grid_case;

static grid_case grid_case_make(int nx, int ny, int nz, double gap, double stiffness) {
    grid_case c;
    ck_assert_int_eq(frix_elastic_grid_make(nx, ny, nz, gap, stiffness, &c.grid), FRIX_OK);
    c.p = c.grid.problem;
    c.m = frix_problem_contact_dofs(c.p);
    c.n = frix_problem_dofs(c.p);
    c.r = calloc((size_t)c.m, sizeof *c.r);
    c.u = calloc((size_t)c.m, sizeof *c.u);
    c.v = calloc((size_t)c.n, sizeof *c.v);
    ck_assert(c.r && c.u && c.v);
    return c;
}

static void grid_case_free(grid_case *c) {
    free(c->r), free(c->u), free(c->v);
    frix_elastic_grid_free(&c->grid);
}

/* Solves with `o` into `info`, then checks status and the reported error and equilibrium <=
 * 1e-8 (the message carries the trace); returns the iterations. */
static int64_t expect_converged_into(const grid_case *c, const frix_options *o, frix_info *info) {
    ck_assert_msg(frix_solve(c->p, o, c->r, c->u, c->v, info) == FRIX_OK, "%s", frix_last_error_message());
    double equilibrium = NAN;
    ck_assert_int_eq(frix_info_get_double(info, FRIX_INFO_EQUILIBRIUM, &equilibrium), FRIX_OK);
    ck_assert_msg(frix_info_status(info) == FRIX_STATUS_CONVERGED && frix_info_error(info) <= 1e-8 &&
                      equilibrium <= 1e-8,
                  "%s, error %g, equilibrium %g\n%s", frix_status_string(frix_info_status(info)),
                  frix_info_error(info), equilibrium, frix_info_trace(info));
    return frix_info_iterations(info);
}

/* expect_converged_into with an info of its own. */
static int64_t expect_converged(const grid_case *c, const frix_options *o) {
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    const int64_t iterations = expect_converged_into(c, o, info);
    frix_info_free(info);
    return iterations;
}

/* The FEM (LMGC90) problems and the box stack, by both routes and from NSGS too. */
static const char *const kGlobalFiles[] = {
    "global/CubeH8.hdf5",
    "global/LMGC_GFC3D-i00501-4-00000.hdf5",
    "global/Box_Stacks-i0035-31-0.hdf5",
};

START_TEST(both_routes_solve_the_global_files) {
    const char *file = kGlobalFiles[_i];
    frix_problem *p = load(file);
    if (!p) return;
    const int solvers[] = {FRIX_SOLVER_GLOBAL_NSN_AC, FRIX_SOLVER_NSN_AC, FRIX_SOLVER_PROX, FRIX_SOLVER_NSGS};
    for (int k = 0; k < 4; ++k) {
        double *r = calloc((size_t)frix_problem_contact_dofs(p) + 1, sizeof *r);
        double *v = calloc((size_t)frix_problem_dofs(p) + 1, sizeof *v);
        outcome out = solve_global(p, solvers[k], r, v);
        ck_assert_msg(out.status == FRIX_STATUS_CONVERGED && out.error <= 1e-8 && out.equilibrium <= 1e-8,
                      "%s by %d: %s, error %g, equilibrium %g", file, solvers[k],
                      frix_status_string(out.status), out.error, out.equilibrium);
        free(r);
        free(v);
    }
    frix_problem_free(p);
}
END_TEST

/* The solvers that never form W (613: ADMM with M + rho H H^T factorised; 901: the augmented
 * Lagrangian with Newton on v, M + rho H J H^T factorised) reach 1e-8 on both measures, to
 * 607's answer, on a thin elastic body, with no reduction time and one symbolic analysis for
 * all their factorisations; and on the global files, CubeH8's M included (an FEM matrix
 * written with 7 digits: symmetric to 1.5e-7, its skew part applied apart). */
START_TEST(solvers_without_w) {
    grid_case c = grid_case_make(16, 16, 2, 0.5, 1e4);
    outcome out = solve_global(c.p, FRIX_SOLVER_GLOBAL_NSN_AC, c.r, c.v);
    ck_assert_int_eq(out.status, FRIX_STATUS_CONVERGED);
    double *r607 = malloc(sizeof *r607 * (size_t)c.m), scale = 0.0;
    memcpy(r607, c.r, sizeof *r607 * (size_t)c.m);
    for (int64_t i = 0; i < c.m; ++i) scale = fmax(scale, fabs(r607[i]));
    const int solvers[] = {FRIX_SOLVER_GLOBAL_ADMM, FRIX_SOLVER_GLOBAL_AL_NEWTON};
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    for (int k = 0; k < 2; ++k) {
        memset(c.r, 0, sizeof *c.r * (size_t)c.m), memset(c.v, 0, sizeof *c.v * (size_t)c.n);
        out = solve_global_into(c.p, solvers[k], c.r, c.v, info);
        ck_assert_msg(out.status == FRIX_STATUS_CONVERGED && out.error <= 1e-8 && out.equilibrium <= 1e-8,
                      "grid by %d: %s, error %g, equilibrium %g", solvers[k], frix_status_string(out.status),
                      out.error, out.equilibrium);
        double diff = 0.0, reduction = NAN;
        for (int64_t i = 0; i < c.m; ++i) diff = fmax(diff, fabs(c.r[i] - r607[i]));
        ck_assert_msg(diff <= 1e-5 * scale, "%d and 607 differ by %g (max |r| %g)", solvers[k], diff, scale);
        ck_assert_int_eq(frix_info_get_double(info, FRIX_INFO_REDUCTION_TIME, &reduction), FRIX_OK);
        ck_assert(reduction == 0.0);
        int64_t symbolic = 0, numeric = 0;
        ck_assert_int_eq(frix_info_get_int(info, FRIX_INFO_SYMBOLIC_ANALYSES, &symbolic), FRIX_OK);
        ck_assert_int_eq(frix_info_get_int(info, FRIX_INFO_FACTORIZATIONS, &numeric), FRIX_OK);
        /* M's (the driver's) and the solver's own: two analyses, however many factorisations. */
        ck_assert_msg(symbolic == 2 && numeric >= 2, "%d: %lld analyses, %lld factorisations", solvers[k],
                      (long long)symbolic, (long long)numeric);
        for (int f = 0; f < 3; ++f) {
            frix_problem *p = load(kGlobalFiles[f]);
            if (!p) continue;
            double *r = calloc((size_t)frix_problem_contact_dofs(p) + 1, sizeof *r);
            double *v = calloc((size_t)frix_problem_dofs(p) + 1, sizeof *v);
            out = solve_global(p, solvers[k], r, v);
            ck_assert_msg(out.status == FRIX_STATUS_CONVERGED && out.error <= 1e-8 && out.equilibrium <= 1e-8,
                          "%s by %d: %s, error %g, equilibrium %g", kGlobalFiles[f], solvers[k],
                          frix_status_string(out.status), out.error, out.equilibrium);
            free(r), free(v);
            frix_problem_free(p);
        }
    }
    frix_info_free(info);
    free(r607);
    grid_case_free(&c);
}
END_TEST

/* A FEM host's steps with M and H unchanged and the load swinging: a persistent gadmm, and auto
 * (which takes the route without W here), factorise M + rho H H^T at the first step only, a
 * persistent gnsn-al analyses its pattern at the first step only, and each step's answer meets
 * the tolerance. */
START_TEST(persistent_without_w_factorises_once) {
    grid_case c = grid_case_make(30, 30, 2, 0.5, 1e4);
    const int64_t n = c.n;
    double *f0 = malloc(sizeof *f0 * (size_t)n), *fk = malloc(sizeof *fk * (size_t)n);
    memcpy(f0, c.grid.f, sizeof *f0 * (size_t)n);
    const int solvers[] = {FRIX_SOLVER_GLOBAL_ADMM, FRIX_SOLVER_AUTO, FRIX_SOLVER_GLOBAL_AL_NEWTON};
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    for (int k = 0; k < 3; ++k) {
        frix_options *o = NULL;
        frix_persistent *ps = NULL;
        ck_assert_int_eq(frix_options_create(solvers[k], &o), FRIX_OK);
        ck_assert_int_eq(frix_persistent_create(c.p, o, &ps), FRIX_OK);
        memset(c.r, 0, sizeof *c.r * (size_t)c.m);
        for (int step = 0; step < 4; ++step) {
            for (int64_t j = 0; j < n; ++j) fk[j] = f0[j] * (1.0 + 0.2 * sin(0.8 * step));
            if (step > 0) ck_assert_int_eq(frix_persistent_update_global(ps, NULL, NULL, fk, NULL, NULL), FRIX_OK);
            ck_assert_msg(frix_persistent_solve(ps, c.r, c.u, c.v, info) == FRIX_OK, "%s", frix_last_error_message());
            double equilibrium = NAN;
            ck_assert_int_eq(frix_info_get_double(info, FRIX_INFO_EQUILIBRIUM, &equilibrium), FRIX_OK);
            ck_assert_msg(frix_info_status(info) == FRIX_STATUS_CONVERGED && frix_info_error(info) <= 1e-8 &&
                              equilibrium <= 1e-8,
                          "%d, step %d: %s, error %g, equilibrium %g\n%s", solvers[k], step,
                          frix_status_string(frix_info_status(info)), frix_info_error(info), equilibrium,
                          frix_info_trace(info));
            int64_t factorizations = -1, analyses = -1;
            ck_assert_int_eq(frix_info_get_int(info, FRIX_INFO_FACTORIZATIONS, &factorizations), FRIX_OK);
            ck_assert_int_eq(frix_info_get_int(info, FRIX_INFO_SYMBOLIC_ANALYSES, &analyses), FRIX_OK);
            if (solvers[k] == FRIX_SOLVER_GLOBAL_AL_NEWTON) {
                /* Newton refactorises every step, on the analyses of the first. */
                ck_assert_msg(analyses == (step == 0 ? 2 : 0) && factorizations >= 1, "901, step %d: %lld analyses",
                              step, (long long)analyses);
                continue;
            }
            /* M's (the driver's) and M + rho H H^T's at the first step; none after. */
            ck_assert_msg(factorizations == (step == 0 ? 2 : 0), "%d, step %d: %lld factorisations", solvers[k],
                          step, (long long)factorizations);
        }
        frix_persistent_free(ps);
        frix_options_free(o);
    }
    frix_info_free(info);
    free(f0), free(fk);
    grid_case_free(&c);
}
END_TEST

/* The rigid spheres (rank-deficient: 768 contact dofs on 588), by the reduction (nsn-ac) and
 * by Newton on (v, r). The latter stagnates near 4e-7 with a monotone Armijo line search (the
 * merit's kinks stop every step short); the non-monotone search, its default, lets full
 * steps through and converges. */
START_TEST(the_rigid_spheres_by_both_routes) {
    frix_problem *p = load("global/spheres-in-a-box-98-i10000-256-10.hdf5");
    if (!p) return;
    const int64_t m = frix_problem_contact_dofs(p), n = frix_problem_dofs(p);
    double *r = calloc((size_t)m, sizeof *r), *u = calloc((size_t)m, sizeof *u);
    double *v = calloc((size_t)n, sizeof *v);
    const int solvers[2] = {FRIX_SOLVER_NSN_AC, FRIX_SOLVER_GLOBAL_NSN_AC};
    for (int k = 0; k < 2; ++k) {
        memset(r, 0, sizeof *r * (size_t)m), memset(v, 0, sizeof *v * (size_t)n);
        outcome out = solve_global(p, solvers[k], r, v);
        ck_assert_msg(out.status == FRIX_STATUS_CONVERGED && out.error <= 1e-8 && out.equilibrium <= 1e-8,
                      "%d: %s, error %g, equilibrium %g", solvers[k], frix_status_string(out.status), out.error,
                      out.equilibrium);
    }
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_GLOBAL_NSN_AC, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_LINE_SEARCH, FRIX_LINE_SEARCH_ARMIJO), FRIX_OK);
    memset(r, 0, sizeof *r * (size_t)m), memset(v, 0, sizeof *v * (size_t)n);
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_solve(p, o, r, u, v, info), FRIX_OK);
    ck_assert_msg(frix_info_status(info) != FRIX_STATUS_CONVERGED, "monotone Armijo converged: the case tests nothing");
    frix_info_free(info);
    frix_options_free(o);
    free(r), free(u), free(v);
    frix_problem_free(p);
}
END_TEST

/* Two contacts on a 4-dof system (n not a multiple of 3: M and H stored as CSC). */
static frix_problem *small_global(const double *m_dense, frix_matrix **M, frix_matrix **H,
                                  double *f, double *w, double *mu) {
    const double h[24] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0,    /* contact 0 */
                          0, 0, 0, 1, 0.5, 0, 0, 0, 0, 0.5, 0, 0}; /* contact 1 */
    ck_assert_int_eq(frix_matrix_from_dense(4, 4, m_dense, 4, M), FRIX_OK);
    ck_assert_int_eq(frix_matrix_from_dense(4, 6, h, 4, H), FRIX_OK);
    ck_assert_int_eq(frix_matrix_is_block(*M), 0);
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_problem_global(*M, *H, f, w, mu, 2, &p), FRIX_OK);
    return p;
}

START_TEST(small_problems_stored_as_csc) {
    /* SPD M (CHOLMOD), then a non-symmetric M (the LU fallback). */
    const double spd[16] = {2, 0.1, 0, 0, 0.1, 2, 0, 0, 0, 0, 1, 0.2, 0, 0, 0.2, 3};
    const double unsym[16] = {2, 0.3, 0, 0, 0.1, 2, 0, 0, 0, 0, 1, 0.2, 0, 0, 0.5, 3};
    const double *ms[2] = {spd, unsym};
    for (int k = 0; k < 2; ++k) {
        double f[4] = {-1, 0.5, 0.2, -2}, w[6] = {0, 0, 0, 0.1, 0, 0}, mu[2] = {0.3, 0.5};
        frix_matrix *M = NULL, *H = NULL;
        frix_problem *p = small_global(ms[k], &M, &H, f, w, mu);
        const int solvers[] = {FRIX_SOLVER_GLOBAL_NSN_AC, FRIX_SOLVER_NSN_AC, FRIX_SOLVER_NSGS,
                               FRIX_SOLVER_GLOBAL_ADMM, FRIX_SOLVER_GLOBAL_AL_NEWTON, FRIX_SOLVER_GLOBAL_NSGS};
        for (int s = 0; s < 6; ++s) {
            double r[6] = {0}, u[6] = {0}, v[4] = {0};
            if (k == 1 && (s == 3 || s == 4)) {
                /* No Cholesky of M + H S H^T: refused, with the way out. */
                frix_options *o = NULL;
                frix_info *info = NULL;
                ck_assert_int_eq(frix_options_create(solvers[s], &o), FRIX_OK);
                ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
                ck_assert_int_eq(frix_solve(p, o, r, u, v, info), FRIX_ERR_UNSUPPORTED);
                ck_assert_msg(strstr(frix_last_error_message(), "needs a symmetric M") != NULL &&
                                  strstr(frix_last_error_message(), "gnsn-ac") != NULL,
                              "%s", frix_last_error_message());
                frix_info_free(info);
                frix_options_free(o);
                continue;
            }
            outcome out = solve_global(p, solvers[s], r, v);
            ck_assert_msg(out.status == FRIX_STATUS_CONVERGED && out.error <= 1e-8 && out.equilibrium <= 1e-8,
                          "M %d solver %d: %s error %g equilibrium %g", k, solvers[s],
                          frix_status_string(out.status), out.error, out.equilibrium);
        }
        frix_problem_free(p);
        frix_matrix_free(M);
        frix_matrix_free(H);
    }
}
END_TEST

/* `solver` at tolerance tol from r = 0: its status, sweeps, and the error and equilibrium
 * measured afresh. */
static outcome solve_at(const frix_problem *p, int solver, double tol, int64_t *iterations) {
    const int64_t m = frix_problem_contact_dofs(p), n = frix_problem_dofs(p);
    double *r = calloc((size_t)m + 1, sizeof *r), *u = calloc((size_t)m + 1, sizeof *u);
    double *v = calloc((size_t)n + 1, sizeof *v);
    frix_options *o = NULL;
    frix_info *info = NULL;
    ck_assert_int_eq(frix_options_create(solver, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, tol), FRIX_OK);
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_msg(frix_solve(p, o, r, u, v, info) == FRIX_OK, "%s", frix_last_error_message());
    outcome out = {frix_info_status(info), NAN, NAN};
    *iterations = frix_info_iterations(info);
    ck_assert_int_eq(frix_problem_measure(p, r, v, NULL, info), FRIX_OK);
    ck_assert_int_eq(frix_info_get_double(info, FRIX_INFO_ERROR_RELATIVE, &out.error), FRIX_OK);
    ck_assert_int_eq(frix_info_get_double(info, FRIX_INFO_EQUILIBRIUM, &out.equilibrium), FRIX_OK);
    frix_info_free(info);
    frix_options_free(o);
    free(r), free(u), free(v);
    return out;
}

/* gnsgs sweeps on H and M^-1 H as nsgs-v sweeps on W = H^T M^-1 H, contact by contact, in
 * its domains' order instead of contact order: on rigid spheres it converges in about as many
 * sweeps (within a factor 2); a deformable body's M is refused with the way out. */
START_TEST(product_form_sweeps_as_nsgs_v) {
    frix_problem *p = load("global/spheres-in-a-box-98-i10000-256-10.hdf5");
    if (p) {
        int64_t it_w = 0, it_product = 0;
        const outcome w = solve_at(p, FRIX_SOLVER_NSGS_VELOCITY, 1e-4, &it_w);
        const outcome product = solve_at(p, FRIX_SOLVER_GLOBAL_NSGS, 1e-4, &it_product);
        ck_assert_int_eq(w.status, FRIX_STATUS_CONVERGED);
        ck_assert_msg(product.status == FRIX_STATUS_CONVERGED && product.error <= 1e-4 && product.equilibrium <= 1e-12,
                      "gnsgs: %s error %g equilibrium %g", frix_status_string(product.status), product.error,
                      product.equilibrium);
        ck_assert_msg(2 * it_product >= it_w && it_product <= 2 * it_w, "gnsgs %lld sweeps, nsgs-v %lld",
                      (long long)it_product, (long long)it_w);
        frix_problem_free(p);
    }
    grid_case c = grid_case_make(9, 9, 1, 0.5, 1e4); /* M couples 81 dofs a direction */
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_GLOBAL_NSGS, &o), FRIX_OK);
    ck_assert_int_eq(frix_solve(c.p, o, c.r, c.u, c.v, NULL), FRIX_ERR_UNSUPPORTED);
    ck_assert_msg(strstr(frix_last_error_message(), "deformable") && strstr(frix_last_error_message(), "gadmm"), "%s",
                  frix_last_error_message());
    frix_options_free(o);
    grid_case_free(&c);
}
END_TEST

/* gnsgs with Anderson's mix (option anderson) keeps v following the mixed r: on the rigid
 * spheres at 1e-8, where the plain sweeps reach their 20000-sweep limit, the mixed ones
 * converge, and the answer, measured afresh, meets the tolerance. */
START_TEST(product_form_mixes_sweeps) {
    frix_problem *p = load("global/spheres-in-a-box-98-i10000-256-10.hdf5");
    if (!p) return;
    const int64_t m = frix_problem_contact_dofs(p), n = frix_problem_dofs(p);
    for (int64_t depth = 0; depth <= 10; depth += 10) {
        double *r = calloc((size_t)m, sizeof *r), *u = calloc((size_t)m, sizeof *u), *v = calloc((size_t)n, sizeof *v);
        frix_options *o = NULL;
        frix_info *info = NULL;
        ck_assert_int_eq(frix_options_create(FRIX_SOLVER_GLOBAL_NSGS, &o), FRIX_OK);
        ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_ANDERSON, depth), FRIX_OK);
        ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
        ck_assert_msg(frix_solve(p, o, r, u, v, info) == FRIX_OK, "%s", frix_last_error_message());
        const frix_status status = frix_info_status(info);
        ck_assert_int_eq(frix_problem_measure(p, r, v, NULL, info), FRIX_OK);
        const double error = frix_info_error(info);
        if (depth == 0) {
            ck_assert_msg(status == FRIX_STATUS_MAX_ITER && error > 1e-8, "plain gnsgs: %s at %g: the case tests nothing",
                          frix_status_string(status), error);
        } else {
            ck_assert_msg(status == FRIX_STATUS_CONVERGED && error <= 1e-8, "gnsgs, anderson %lld: %s, measured %g",
                          (long long)depth, frix_status_string(status), error);
        }
        frix_info_free(info);
        frix_options_free(o);
        free(r), free(u), free(v);
    }
    frix_problem_free(p);
}
END_TEST

/* A massless dof (M singular) that a contact's friction reaches: held where the friction cone
 * takes its load (0.2 against mu r_N = 0.3), solved to the tolerance equilibrium included;
 * refused with the reason where it does not (0.5). */
START_TEST(singular_mass_matrix_held_or_refused) {
    const double zero_row[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1};
    const double loads[2] = {0.2, 0.5};
    for (int k = 0; k < 2; ++k) {
        double f[4] = {-1, 0.5, loads[k], -2}, w[6] = {0}, mu[2] = {0.3, 0.5};
        frix_matrix *M = NULL, *H = NULL;
        frix_problem *p = small_global(zero_row, &M, &H, f, w, mu);
        double r[6] = {0}, u[6], v[4] = {0};
        frix_options *o = NULL;
        frix_info *info = NULL;
        ck_assert_int_eq(frix_options_create(FRIX_SOLVER_NSGS, &o), FRIX_OK);
        ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
        const frix_error e = frix_solve(p, o, r, u, v, info);
        if (k == 0) {
            double eq = NAN;
            ck_assert_msg(e == FRIX_OK, "%s", frix_last_error_message());
            ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_CONVERGED);
            ck_assert_int_eq(frix_info_get_double(info, FRIX_INFO_EQUILIBRIUM_SCALED, &eq), FRIX_OK);
            ck_assert_msg(frix_info_error(info) <= 1e-8 && eq <= 1e-8, "error %g equilibrium %g", frix_info_error(info), eq);
            ck_assert_double_eq_tol(r[2], -0.2, 1e-7); /* the friction holds the massless dof */
        } else {
            ck_assert_int_eq(e, FRIX_ERR_NUMERICAL);
            ck_assert_msg(strstr(frix_last_error_message(), "M is singular") &&
                              strstr(frix_last_error_message(), "do not hold"), "%s", frix_last_error_message());
        }
        frix_info_free(info);
        frix_options_free(o);
        frix_problem_free(p);
        frix_matrix_free(M);
        frix_matrix_free(H);
    }
}
END_TEST

START_TEST(no_contacts) {
    const double m[9] = {2, 0, 0, 0, 4, 0, 0, 0, 1};
    double f[3] = {2, -4, 3};
    frix_matrix *M = NULL;
    ck_assert_int_eq(frix_matrix_from_dense(3, 3, m, 3, &M), FRIX_OK);
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_problem_global(M, NULL, f, NULL, NULL, 0, &p), FRIX_OK);
    double v[3] = {0};
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_solve(p, NULL, NULL, NULL, v, info), FRIX_OK);
    ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_CONVERGED);
    ck_assert_double_eq_tol(v[0], 1.0, 1e-15);
    ck_assert_double_eq_tol(v[1], -1.0, 1e-15);
    ck_assert_double_eq_tol(v[2], 3.0, 1e-15);
    frix_info_free(info);
    frix_problem_free(p);
    frix_matrix_free(M);
}
END_TEST

/* auto prices the dense W of a deformable body before forming it. On a thin body (30 x 30 x 2
 * nodes, W dense among its 900 contacts, M's factor thin) the route without W, ADMM on (v, r)
 * with M + rho H H^T factorised, is priced below it: auto takes that route, to 607's answer, and
 * forms no W (no reduction time). Under a memory limit W would overrun it does the same, and
 * says so. On rigid bodies it reduces as before. */
/* What the driver logged of M (verbosity 1): analysed alone, factorised. */
typedef struct {
    int analysed, factorised;
} mass_log;
static void note_mass(void *data, const char *line) {
    mass_log *seen = data;
    if (strncmp(line, "M analysed", 10) == 0) ++seen->analysed;
    if (strncmp(line, "M factorised", 12) == 0) ++seen->factorised;
}

START_TEST(auto_prices_the_reduction_of_a_deformable_body) {
    /* 900 contacts, some sticking, some sliding, some off the plane. */
    frix_elastic_grid g;
    ck_assert_int_eq(frix_elastic_grid_make(30, 30, 2, 0.5, 1e4, &g), FRIX_OK);
    const frix_problem *p = g.problem;
    const int64_t m = frix_problem_contact_dofs(p), n = frix_problem_dofs(p);
    double *r = calloc((size_t)m, sizeof *r), *u = calloc((size_t)m, sizeof *u), *v = calloc((size_t)n, sizeof *v);
    double *r607 = calloc((size_t)m, sizeof *r607), *v607 = calloc((size_t)n, sizeof *v607);
    outcome out = solve_global(p, FRIX_SOLVER_GLOBAL_NSN_AC, r607, v607);
    ck_assert_msg(out.status == FRIX_STATUS_CONVERGED && out.error <= 1e-8 && out.equilibrium <= 1e-8,
                  "607: %s, error %g", frix_status_string(out.status), out.error);
    double scale = 0.0;
    for (int64_t i = 0; i < m; ++i) scale = fmax(scale, fabs(r607[i]));

    frix_info *info = NULL;
    frix_options *o = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_AUTO, &o), FRIX_OK);
    /* Without limits, then under a memory limit of 40 MB (W's 900 x 900 blocks take 65 MB; M + rho H H^T's
     * factor a few MB, with room for a sanitizer's overhead on what the process holds). */
    for (int limited = 0; limited < 2; ++limited) {
        if (limited) ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_MEMORY_LIMIT, 40e6), FRIX_OK);
        mass_log seen = {0, 0};
        ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_VERBOSITY, 1), FRIX_OK);
        ck_assert_int_eq(frix_options_set_log(o, note_mass, &seen), FRIX_OK);
        memset(r, 0, sizeof *r * (size_t)m), memset(v, 0, sizeof *v * (size_t)n);
        ck_assert_msg(frix_solve(p, o, r, u, v, info) == FRIX_OK, "%s", frix_last_error_message());
        const char *trace = frix_info_trace(info);
        double equilibrium = NAN;
        ck_assert_int_eq(frix_info_get_double(info, FRIX_INFO_EQUILIBRIUM, &equilibrium), FRIX_OK);
        ck_assert_msg(frix_info_status(info) == FRIX_STATUS_CONVERGED && frix_info_error(info) <= 1e-8 &&
                          equilibrium <= 1e-8,
                      "auto: %s, error %g, equilibrium %g\n%s", frix_status_string(frix_info_status(info)),
                      frix_info_error(info), equilibrium, trace);
        /* The analysis (record 0, a note) bounds W by 3 x 900^2 entries, the dense coupling of
         * the grid, and says why W is not formed; the first run is ADMM on (v, r). */
        const char *note = frix_info_stage_note(info, 0);
        ck_assert_msg(strstr(note, "up to 2.43e+06 entries") != NULL, "trace:\n%s", trace);
        ck_assert_msg(strstr(note, limited ? "overrun the memory limit" : "is priced") != NULL, "trace:\n%s", trace);
        const int64_t first_run = find_other_run(info, 0, 0);
        ck_assert_msg(first_run >= 0 && stage_int(info, first_run, FRIX_STAGE_SOLVER_ID) == FRIX_SOLVER_GLOBAL_ADMM,
                      "trace:\n%s", trace);
        double reduction = NAN;
        ck_assert_int_eq(frix_info_get_double(info, FRIX_INFO_REDUCTION_TIME, &reduction), FRIX_OK);
        ck_assert_msg(reduction == 0.0, "W formed: %g s\n%s", reduction, trace);
        /* Two analyses: M's, and M + rho H S H^T's, made once while pricing the route and handed
         * to ADMM, which factorises on it and counts it as its own. */
        int64_t analyses = -1;
        ck_assert_int_eq(frix_info_get_int(info, FRIX_INFO_SYMBOLIC_ANALYSES, &analyses), FRIX_OK);
        ck_assert_msg(limited || analyses == 2, "%lld analyses\n%s", (long long)analyses, trace);
        /* The route never solves with M: M is analysed (for the prices and the ordering), not
         * factorised. */
        ck_assert_msg(seen.analysed == 1 && seen.factorised == 0, "M analysed %d, factorised %d times\n%s",
                      seen.analysed, seen.factorised, trace);
        double diff = 0.0;
        for (int64_t i = 0; i < m; ++i) diff = fmax(diff, fabs(r[i] - r607[i]));
        ck_assert_msg(diff <= 1e-5 * scale, "auto and 607 differ by %g (max |r| %g)", diff, scale);
    }
    /* A thicker grid whose W has 24 entries per entry of M and H (625 contacts on 4 layers):
     * priced as well, and solved without W, the cheaper route. */
    frix_elastic_grid thick;
    ck_assert_int_eq(frix_elastic_grid_make(25, 25, 4, 0.5, 1e4, &thick), FRIX_OK);
    double *rt = calloc((size_t)frix_problem_contact_dofs(thick.problem), sizeof *rt);
    double *vt = calloc((size_t)frix_problem_dofs(thick.problem), sizeof *vt);
    out = solve_global_into(thick.problem, FRIX_SOLVER_AUTO, rt, vt, info);
    ck_assert_int_eq(out.status, FRIX_STATUS_CONVERGED);
    const char *thick_note = frix_info_stage_note(info, 0);
    ck_assert_msg(strstr(thick_note, "(23.7 per entry of M and H") != NULL && strstr(thick_note, "is priced") != NULL,
                  "trace:\n%s", frix_info_trace(info));
    ck_assert_msg(stage_int(info, find_other_run(info, 0, 0), FRIX_STAGE_SOLVER_ID) == FRIX_SOLVER_GLOBAL_ADMM,
                  "trace:\n%s", frix_info_trace(info));
    free(rt), free(vt);
    frix_elastic_grid_free(&thick);

    const char *trace = NULL;
    int64_t first_run = 0;
    frix_options_free(o);
    free(r), free(u), free(v), free(r607), free(v607);

    /* Rigid spheres in a box: W has 13 entries per entry of M and H; reduced as before. */
    frix_problem *rigid = load("global/spheres-in-a-box-98-i10000-256-10.hdf5");
    if (rigid) {
        r = calloc((size_t)frix_problem_contact_dofs(rigid), sizeof *r);
        v = calloc((size_t)frix_problem_dofs(rigid), sizeof *v);
        out = solve_global_into(rigid, FRIX_SOLVER_AUTO, r, v, info);
        ck_assert_int_eq(out.status, FRIX_STATUS_CONVERGED);
        trace = frix_info_trace(info);
        /* The reduced solve's stages first, no Newton on (v, r) before them. */
        first_run = find_other_run(info, 0, 0);
        ck_assert_msg(first_run >= 0 && stage_int(info, first_run, FRIX_STAGE_SOLVER_ID) != FRIX_SOLVER_GLOBAL_NSN_AC,
                      "trace:\n%s", trace);
        ck_assert_msg(strstr(frix_info_stage_note(info, 0), "at most 1.02e+05 entries") != NULL, "trace:\n%s", trace);
        free(r), free(v);
        frix_problem_free(rigid);
    }
    frix_info_free(info);
    frix_elastic_grid_free(&g);
}
END_TEST

/* Under a time limit far below any price of forming W, the grid of the test above still reads
 * "is priced": where the route without W is the cheaper one, whether W fits the time limit is
 * asked only before W would be formed after that route (asking may time the machine; before,
 * it was asked up front and this note said "would overrun the time limit"). */
START_TEST(auto_asks_whether_forming_w_fits_the_time_only_where_it_would_form_it) {
    frix_elastic_grid g;
    ck_assert_int_eq(frix_elastic_grid_make(30, 30, 2, 0.5, 1e4, &g), FRIX_OK);
    double *r = calloc((size_t)frix_problem_contact_dofs(g.problem), sizeof *r);
    double *u = calloc((size_t)frix_problem_contact_dofs(g.problem), sizeof *u);
    double *v = calloc((size_t)frix_problem_dofs(g.problem), sizeof *v);
    frix_info *info = NULL;
    frix_options *o = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_AUTO, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TIME_LIMIT, 1e-6), FRIX_OK);
    ck_assert_msg(frix_solve(g.problem, o, r, u, v, info) == FRIX_OK, "%s", frix_last_error_message());
    const char *trace = frix_info_trace(info);
    const char *note = frix_info_stage_note(info, 0);
    ck_assert_msg(note && strstr(note, "is priced") != NULL && strstr(note, "overrun") == NULL, "trace:\n%s", trace);
    ck_assert_msg(stage_int(info, find_other_run(info, 0, 0), FRIX_STAGE_SOLVER_ID) == FRIX_SOLVER_GLOBAL_ADMM,
                  "trace:\n%s", trace);
    ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_TIME_LIMIT);
    frix_options_free(o);
    frix_info_free(info);
    free(r), free(u), free(v);
    frix_elastic_grid_free(&g);
}
END_TEST

/* On a stiff thin body (30 x 30 x 2 nodes, springs of 1e8) auto takes the route without W, where
 * ADMM's linear rate would take more than a thousand iterations to 1e-8: it stops ADMM at 200
 * and gnsn-ac finishes from its answer (gnsn-al is not needed). */
START_TEST(auto_finishes_a_stiff_body_with_newton_after_admm) {
    grid_case c = grid_case_make(30, 30, 2, 0.5, 1e8);
    frix_options *o = NULL;
    frix_info *info = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_AUTO, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 1e-8), FRIX_OK);
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    expect_converged_into(&c, o, info);
    const char *trace = frix_info_trace(info);
    const int64_t admm = find_stage(info, FRIX_SOLVER_GLOBAL_ADMM, 0);
    ck_assert_msg(admm >= 0 && stage_int(info, admm, FRIX_STAGE_ITERATIONS) == 200, "trace:\n%s", trace);
    const int64_t newton = find_other_run(info, FRIX_SOLVER_GLOBAL_ADMM, admm);
    ck_assert_msg(newton >= 0 && stage_int(info, newton, FRIX_STAGE_SOLVER_ID) == FRIX_SOLVER_GLOBAL_NSN_AC &&
                      stage_int(info, newton, FRIX_STAGE_ITERATIONS) <= 5,
                  "trace:\n%s", trace);
    ck_assert_msg(find_stage(info, FRIX_SOLVER_GLOBAL_AL_NEWTON, 0) < 0, "trace:\n%s", trace);
    frix_info_free(info);
    frix_options_free(o);
    grid_case_free(&c);
}
END_TEST

/* The solvers' log lines that start with `prefix`, the last one kept. */
typedef struct {
    const char *prefix;
    char last[512];
} log_grab;
static void grab_line(void *data, const char *line) {
    log_grab *g = data;
    if (strncmp(line, g->prefix, strlen(g->prefix)) == 0) snprintf(g->last, sizeof g->last, "%s", line);
}

/* gadmm's solves through a single-precision copy of M + rho H H^T's factor (solve_near), on a
 * thick grid (a supernodal factor). On a well-conditioned M (k = 1e4), in units scaled by 1,
 * 1e150 and 1e-150 (past single precision's range): one solve from 0 lands within single
 * precision of the double answer and solves again from there refine it to double precision;
 * gadmm reaches 1e-8 with every solve through the copy. On an ill-conditioned M (k = 1e10,
 * condition about 1e7) solves from 0 and from its answer miss the contraction asked, a double
 * solve finishes each, and two misses in a row drop the copy. */
START_TEST(single_precision_solves_refined_in_double) {
    const double stiffness[2] = {1e4, 1e10}, scales[3] = {1.0, 1e150, 1e-150};
    for (int k = 0; k < 2; ++k) {
        frix_elastic_grid g;
        ck_assert_int_eq(frix_elastic_grid_make(20, 20, 10, 0.1, stiffness[k], &g), FRIX_OK);
        const int64_t n = frix_problem_dofs(g.problem);
        double *b = malloc(sizeof *b * (size_t)n), *exact = malloc(sizeof *exact * (size_t)n),
               *x = malloc(sizeof *x * (size_t)n);
        for (int64_t j = 0; j < n; ++j) b[j] = 1.0 + (double)(j % 5) - 0.7 * (double)(j % 3);
        double flops = 0.0;
        int ordered = -1;
        ck_assert_int_eq(frix_testing_mass_plus_contacts(1, g.M, g.H, 3.0, b, exact, &flops, &ordered), FRIX_OK);
        for (int s = 0; s < (k == 0 ? 3 : 1); ++s) {
            const int solves = k == 0 ? 1 : 3;
            int kept = -1, in_use = -1;
            int64_t through = -1, in_double = -1;
            memset(x, 0, sizeof *x * (size_t)n);
            ck_assert_int_eq(frix_testing_solve_near(g.M, g.H, 3.0, scales[s], b, x, solves, &kept, &through,
                                                     &in_double, &in_use),
                             FRIX_OK);
            ck_assert_int_eq(kept, 1);
            double diff = 0.0, norm = 0.0;
            for (int64_t j = 0; j < n; ++j)
                diff += (x[j] - exact[j]) * (x[j] - exact[j]), norm += exact[j] * exact[j];
            if (k == 1) {
                ck_assert_int_eq(through, 2);
                ck_assert_int_eq(in_double, 2);
                ck_assert_int_eq(in_use, 0);
                ck_assert_double_lt(sqrt(diff / norm), 1e-7);
                continue;
            }
            ck_assert_int_eq(through, 1);
            ck_assert_int_eq(in_double, 0);
            ck_assert_int_eq(in_use, 1);
            ck_assert_double_lt(sqrt(diff / norm), 1e-5);
            ck_assert_double_gt(sqrt(diff / norm), 1e-13);
            ck_assert_int_eq(frix_testing_solve_near(g.M, g.H, 3.0, scales[s], b, x, 3, &kept, &through,
                                                     &in_double, &in_use),
                             FRIX_OK);
            ck_assert(through >= 1 && in_double == 0);
            diff = 0.0;
            for (int64_t j = 0; j < n; ++j) diff += (x[j] - exact[j]) * (x[j] - exact[j]);
            ck_assert_double_lt(sqrt(diff / norm), 1e-12);
        }
        if (k == 0) { /* gadmm, every solve through the copy, reaches 1e-8, equilibrium included */
            double *r = calloc((size_t)frix_problem_contact_dofs(g.problem), sizeof *r),
                   *u = calloc((size_t)frix_problem_contact_dofs(g.problem), sizeof *u),
                   *v = calloc((size_t)n, sizeof *v);
            frix_options *o = NULL;
            frix_info *info = NULL;
            log_grab grab = {"gadmm: converged", ""};
            ck_assert_int_eq(frix_options_create(FRIX_SOLVER_GLOBAL_ADMM, &o), FRIX_OK);
            ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
            ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_VERBOSITY, 1), FRIX_OK);
            ck_assert_int_eq(frix_options_set_log(o, grab_line, &grab), FRIX_OK);
            ck_assert_int_eq(frix_solve(g.problem, o, r, u, v, info), FRIX_OK);
            double equilibrium = NAN;
            ck_assert_int_eq(frix_info_get_double(info, FRIX_INFO_EQUILIBRIUM, &equilibrium), FRIX_OK);
            ck_assert_msg(frix_info_status(info) == FRIX_STATUS_CONVERGED && frix_info_error(info) <= 1e-8 &&
                              equilibrium <= 1e-8,
                          "%s, error %g, equilibrium %g", frix_status_string(frix_info_status(info)),
                          frix_info_error(info), equilibrium);
            long long iterations = -1, restarts = -1, changes = -1, singles = -1, doubles = -1;
            const char *counts = strstr(grab.last, "iterations (");
            ck_assert_msg(counts != NULL, "log: %s", grab.last);
            ck_assert_int_eq(sscanf(grab.last, "gadmm: converged after %lld", &iterations), 1);
            ck_assert_int_eq(sscanf(counts, "iterations (%lld rho changes, %lld restarts; %lld solves in single "
                                            "precision, %lld",
                                    &changes, &restarts, &singles, &doubles),
                             4);
            ck_assert_msg(iterations > 0 && singles == iterations && doubles == 0, "log: %s", grab.last);
            frix_info_free(info);
            frix_options_free(o);
            free(r), free(u), free(v);
        }
        free(b);
        free(exact);
        free(x);
        frix_elastic_grid_free(&g);
    }
}
END_TEST


/* An ADMM's M + rho H H^T (contact blocks rho I) holds H_a H_a^T's entries only where two
 * rows of H_a share a column. On the grid (M apart per direction, H_a a permutation) that keeps
 * the three directions apart: a tenth of the flops of the pattern any block could fill, the
 * same solution, analysed in M's ordering (its pattern is M's). Under contact frames turned
 * off the axes every pair is coupled and both patterns are the same. */
START_TEST(admm_system_keeps_only_the_couplings_rho_i_makes) {
    frix_elastic_grid g;
    ck_assert_int_eq(frix_elastic_grid_make(16, 16, 2, 0.1, 1e4, &g), FRIX_OK);
    const int64_t n = frix_problem_dofs(g.problem), nc = frix_problem_contacts(g.problem);
    double *b = malloc(sizeof *b * (size_t)n), *x0 = malloc(sizeof *x0 * (size_t)n),
           *x1 = malloc(sizeof *x1 * (size_t)n);
    for (int64_t j = 0; j < n; ++j) b[j] = 1.0 + (double)(j % 5);
    double any = 0.0, identity = 0.0;
    int any_ordered = -1, identity_ordered = -1;
    ck_assert_int_eq(frix_testing_mass_plus_contacts(0, g.M, g.H, 3.0, b, x0, &any, &any_ordered), FRIX_OK);
    ck_assert_int_eq(frix_testing_mass_plus_contacts(1, g.M, g.H, 3.0, b, x1, &identity, &identity_ordered), FRIX_OK);
    ck_assert_double_lt(identity, 0.25 * any);
    /* Its pattern is M's: analysed in M's ordering; the one coupling the directions is not. */
    ck_assert_int_eq(identity_ordered, 1);
    ck_assert_int_eq(any_ordered, 0);
    for (int64_t j = 0; j < n; ++j) ck_assert_double_eq_tol(x1[j], x0[j], 1e-12 * fabs(x0[j]));
    /* The same M, each contact's frame turned by 30 degrees about x then about z. */
    int64_t *rows = malloc(sizeof *rows * (size_t)(9 * nc)), *cols = malloc(sizeof *cols * (size_t)(9 * nc));
    double *vals = malloc(sizeof *vals * (size_t)(9 * nc));
    const double c = cos(M_PI / 6.0), s = sin(M_PI / 6.0);
    const double R[3][3] = {{c, -s * c, s * s}, {s, c * c, -c * s}, {0.0, s, c}}; /* Rz Rx */
    int64_t e = 0;
    for (int64_t a = 0; a < nc; ++a)
        for (int i = 0; i < 3; ++i)
            for (int k = 0; k < 3; ++k) rows[e] = 3 * a + i, cols[e] = 3 * a + k, vals[e++] = R[i][k];
    frix_matrix *H = NULL;
    ck_assert_int_eq(frix_matrix_from_triplets(n, 3 * nc, e, rows, cols, vals, &H), FRIX_OK);
    ck_assert_int_eq(frix_testing_mass_plus_contacts(0, g.M, H, 3.0, b, x0, &any, &any_ordered), FRIX_OK);
    ck_assert_int_eq(frix_testing_mass_plus_contacts(1, g.M, H, 3.0, b, x1, &identity, &identity_ordered), FRIX_OK);
    ck_assert_double_eq(identity, any);
    for (int64_t j = 0; j < n; ++j) ck_assert_double_eq_tol(x1[j], x0[j], 1e-12 * fabs(x0[j]));
    frix_matrix_free(H);
    free(rows);
    free(cols);
    free(vals);
    free(b);
    free(x0);
    free(x1);
    frix_elastic_grid_free(&g);
}
END_TEST

/* gadmm changes rho only where the iterations left at its rate cost more than the
 * factorisation the change takes. On this grid its first rho converges a few iterations after
 * the residual balance would change it, and a change there only adds a factorisation; from a rho
 * 10^4 times too small the change pays and is made. */
START_TEST(admm_changes_rho_only_where_it_pays) {
    grid_case c = grid_case_make(16, 16, 4, 0.0, 1e4);
    const double rhos[2] = {1.0, 1e-4};
    for (int k = 0; k < 2; ++k) {
        frix_options *o = NULL;
        ck_assert_int_eq(frix_options_create(FRIX_SOLVER_GLOBAL_ADMM, &o), FRIX_OK);
        ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 1e-8), FRIX_OK);
        ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_RHO, rhos[k]), FRIX_OK);
        frix_info *info = NULL;
        ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
        memset(c.r, 0, sizeof *c.r * (size_t)c.m), memset(c.v, 0, sizeof *c.v * (size_t)c.n);
        expect_converged_into(&c, o, info);
        int64_t factorizations = -1;
        ck_assert_int_eq(frix_info_get_int(info, FRIX_INFO_FACTORIZATIONS, &factorizations), FRIX_OK);
        /* M's (the driver's), then M + rho H H^T's: once, or again after a change. */
        if (k == 0) ck_assert_int_eq(factorizations, 2);
        else ck_assert_int_ge(factorizations, 3);
        frix_info_free(info);
        frix_options_free(o);
    }
    grid_case_free(&c);
}
END_TEST

/* The callback's iterations, which must rise through a solve. */
typedef struct {
    int64_t last, reports, backwards;
} rising;

static int note_rising(void *data, int64_t iteration, double error, double elapsed) {
    (void)error, (void)elapsed;
    rising *c = data;
    if (c->reports > 0 && iteration < c->last) ++c->backwards;
    c->last = iteration, ++c->reports;
    return 0;
}

/* A local solver through the reduction on a body falling onto its contacts (q outweighs w):
 * its answer at the tolerance misses the global measure, and a tightened pass goes on from it.
 * The callback's iterations rise through both, up to the solve's count. */
START_TEST(tightened_passes_number_on) {
    grid_case c = grid_case_make(10, 10, 4, 0.0, 1e4);
    const int solvers[2] = {FRIX_SOLVER_NSGS_VELOCITY, FRIX_SOLVER_ADMM};
    for (int k = 0; k < 2; ++k) {
        frix_options *o = NULL;
        ck_assert_int_eq(frix_options_create(solvers[k], &o), FRIX_OK);
        ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 1e-8), FRIX_OK);
        rising seen = {0, 0, 0};
        ck_assert_int_eq(frix_options_set_callback(o, note_rising, &seen), FRIX_OK);
        frix_info *info = NULL;
        ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
        memset(c.r, 0, sizeof *c.r * (size_t)c.m), memset(c.v, 0, sizeof *c.v * (size_t)c.n);
        expect_converged_into(&c, o, info);
        ck_assert_int_gt(seen.reports, 1);
        ck_assert_int_eq(seen.backwards, 0);
        ck_assert_int_eq(seen.last, frix_info_iterations(info));
        frix_info_free(info);
        frix_options_free(o);
    }
    grid_case_free(&c);
}
END_TEST

/* gadmm ends within two iterations of its first iterate that meets the tolerance (the runs are
 * deterministic: the run stopped after k iterations returns iterate k, which the driver
 * measures). Waiting for its oscillating light error to pass a tolerance lowered by a failed
 * check ran 28 iterations on this grid at 1e-6, where iterate 24 met it. */
START_TEST(admm_stops_near_the_first_iterate_within_the_tolerance) {
    grid_case c = grid_case_make(10, 10, 4, 0.0, 1e4);
    const double tols[2] = {1e-6, 1e-4};
    for (int t = 0; t < 2; ++t) {
        int64_t ran = 0, first = -1;
        for (int64_t k = 1; first < 0; ++k) {
            frix_options *o = NULL;
            ck_assert_int_eq(frix_options_create(FRIX_SOLVER_GLOBAL_ADMM, &o), FRIX_OK);
            ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, tols[t]), FRIX_OK);
            if (k > 1) ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_MAX_ITER, k - 1), FRIX_OK);
            frix_info *info = NULL;
            ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
            memset(c.r, 0, sizeof *c.r * (size_t)c.m), memset(c.v, 0, sizeof *c.v * (size_t)c.n);
            ck_assert_int_eq(frix_solve(c.p, o, c.r, c.u, c.v, info), FRIX_OK);
            if (k == 1) { /* the whole run first */
                ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_CONVERGED);
                ran = frix_info_iterations(info);
            } else if (frix_info_error(info) <= tols[t]) {
                first = k - 1;
            }
            ck_assert_int_le(k, ran + 1);
            frix_info_free(info);
            frix_options_free(o);
        }
        ck_assert_msg(ran <= first + 2, "tol %g: %lld iterations, iterate %lld met it", tols[t], (long long)ran,
                      (long long)first);
    }
    grid_case_free(&c);
}
END_TEST

/* A grid without masses held by its contacts alone (M singular), whose route is the one without
 * W: pressed down, auto solves it without ever factorising M (M + rho H H^T is regular where
 * the contacts hold the free motions); pushed sideways beyond friction, the route's failure
 * leads to M's factorisation, which finds M singular, and the solve is refused with the reason. */
START_TEST(auto_without_w_on_a_floating_grid) {
    const double side[2] = {0.0, 0.5};
    for (int k = 0; k < 2; ++k) {
        frix_elastic_grid g;
        ck_assert_int_eq(frix_elastic_grid_make_floating(30, 30, 2, side[k], -1.0, &g), FRIX_OK);
        const int64_t m = frix_problem_contact_dofs(g.problem), n = frix_problem_dofs(g.problem);
        double *r = calloc((size_t)m, sizeof *r), *u = calloc((size_t)m, sizeof *u), *v = calloc((size_t)n, sizeof *v);
        frix_options *o = NULL;
        frix_info *info = NULL;
        ck_assert_int_eq(frix_options_create(FRIX_SOLVER_AUTO, &o), FRIX_OK);
        ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 1e-8), FRIX_OK);
        mass_log seen = {0, 0};
        ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_VERBOSITY, 1), FRIX_OK);
        ck_assert_int_eq(frix_options_set_log(o, note_mass, &seen), FRIX_OK);
        ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
        const frix_error e = frix_solve(g.problem, o, r, u, v, info);
        ck_assert_int_eq(seen.analysed, 1);
        if (k == 0) {
            ck_assert_msg(e == FRIX_OK, "%s", frix_last_error_message());
            double equilibrium = NAN, normal = 0.0;
            ck_assert_int_eq(frix_info_get_double(info, FRIX_INFO_EQUILIBRIUM, &equilibrium), FRIX_OK);
            ck_assert_msg(frix_info_status(info) == FRIX_STATUS_CONVERGED && frix_info_error(info) <= 1e-8 &&
                              equilibrium <= 1e-8,
                          "%s, error %g, equilibrium %g\n%s", frix_status_string(frix_info_status(info)),
                          frix_info_error(info), equilibrium, frix_info_trace(info));
            for (int64_t a = 0; a < m / 3; ++a) normal += r[3 * a];
            ck_assert_double_eq_tol(normal, (double)n / 3.0, 1e-6 * (double)n); /* the contacts carry the load */
            ck_assert_msg(seen.factorised == 0, "M factorised %d times\n%s", seen.factorised, frix_info_trace(info));
        } else {
            ck_assert_int_ge(seen.factorised, 1);
            ck_assert_msg(e == FRIX_ERR_NUMERICAL && strstr(frix_last_error_message(), "M is singular") &&
                              strstr(frix_last_error_message(), "do not hold"),
                          "%d, %s", e, frix_last_error_message());
        }
        frix_info_free(info);
        frix_options_free(o);
        free(r), free(u), free(v);
        frix_elastic_grid_free(&g);
    }
}
END_TEST

/* W's diagonal entries for a few columns of H (the sampling of rho's unit), from the forward
 * solves up L's tree alone: the same as from a full solve per column. */
START_TEST(inverse_diagonal_matches_full_solves) {
    frix_elastic_grid g;
    ck_assert_int_eq(frix_elastic_grid_make(12, 10, 3, 0.1, 1e4, &g), FRIX_OK);
    const int64_t n = frix_problem_dofs(g.problem);
    /* Columns: the normal of contacts 0, 37 and 119, and a column over several nodes. */
    const int64_t rows[6] = {2, 3 * 37 + 2, 3 * 119 + 2, 5, 3 * 50 + 1, n - 1};
    const int64_t cols[6] = {0, 1, 2, 3, 3, 3};
    const double vals[6] = {1.0, 1.0, 1.0, 0.5, -2.0, 1.5};
    frix_matrix *B = NULL;
    ck_assert_int_eq(frix_matrix_from_triplets(n, 4, 6, rows, cols, vals, &B), FRIX_OK);
    double diag[4], by_solves[4];
    ck_assert_int_eq(frix_testing_inverse_diagonal(g.M, B, diag, by_solves), FRIX_OK);
    for (int j = 0; j < 4; ++j) {
        ck_assert_double_gt(diag[j], 0.0);
        ck_assert_double_eq_tol(diag[j], by_solves[j], 1e-12 * by_solves[j]);
    }
    frix_matrix_free(B);
    frix_elastic_grid_free(&g);
}
END_TEST

/* The grid generator refuses what it cannot build, and leaves nothing to leak. */
START_TEST(elastic_grid_arguments) {
    frix_elastic_grid g;
    ck_assert_int_eq(frix_elastic_grid_make(3, 2, 4, 0.1, 1e4, &g), FRIX_OK);
    ck_assert_int_eq(frix_problem_contacts(g.problem), 6);
    ck_assert_int_eq(frix_problem_dofs(g.problem), 72);
    frix_elastic_grid_free(&g);
    ck_assert_ptr_null(g.problem);
    frix_elastic_grid_free(&g); /* twice, and NULL: harmless */
    frix_elastic_grid_free(NULL);
    const int bad[4][3] = {{0, 3, 3}, {3, -1, 3}, {3, 3, 0}, {100000, 100000, 1}};
    for (int k = 0; k < 4; ++k) {
        ck_assert_int_eq(frix_elastic_grid_make(bad[k][0], bad[k][1], bad[k][2], 0.0, 1e4, &g), FRIX_ERR_INVALID_ARGUMENT);
        ck_assert_ptr_null(g.problem);
    }
    ck_assert_int_eq(frix_elastic_grid_make(3, 3, 3, -1.0, 1e4, &g), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_elastic_grid_make(3, 3, 3, NAN, 1e4, &g), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_elastic_grid_make(3, 3, 3, INFINITY, 1e4, &g), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_elastic_grid_make(3, 3, 3, 0.0, 0.0, &g), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_elastic_grid_make(3, 3, 3, 0.0, NAN, &g), FRIX_ERR_INVALID_ARGUMENT);
}
END_TEST

/* rho from the lumped blocks H_a^T diag(M)^-1 H_a is far too large on a stiff body (k = 1e12:
 * diag(M)^-1 underrates W's blocks about 4e5-fold); 607 corrects it from a few exact blocks
 * and converges (stagnated after 7 steps without the correction). */
START_TEST(newton_corrects_the_lumped_rho) {
    grid_case c = grid_case_make(25, 25, 2, 0.0, 1e12);
    outcome out = solve_global(c.p, FRIX_SOLVER_GLOBAL_NSN_AC, c.r, c.v);
    ck_assert_msg(out.status == FRIX_STATUS_CONVERGED && out.error <= 1e-8 && out.equilibrium <= 1e-8,
                  "%s, error %g, equilibrium %g", frix_status_string(out.status), out.error, out.equilibrium);
    grid_case_free(&c);
}
END_TEST

/* 607 also cuts rho while no step is accepted: a constant rho of 1e5 on the grid with k = 1e8
 * (where 1e3 converges) lets no step lower the merit; cut twice, it converges. */
START_TEST(newton_cuts_a_rho_too_large) {
    grid_case c = grid_case_make(25, 25, 2, 0.0, 1e8);
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_GLOBAL_NSN_AC, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_RHO_STRATEGY, FRIX_RHO_CONSTANT), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_RHO, 1e5), FRIX_OK);
    expect_converged(&c, o);
    frix_options_free(o);
    grid_case_free(&c);
}
END_TEST

/* On a soft deformable body 607 takes its first step full where that lowers the error: from
 * v = 0 the merit is mostly the equilibrium rows', the line search cut that step to a quarter,
 * and Newton then crept towards the contacts' states (9 steps on this grid, 24 on 40 x 40 x 4;
 * 4 and 5 now). */
START_TEST(newton_takes_a_full_first_step_on_a_soft_body) {
    grid_case c = grid_case_make(20, 20, 4, 0.2, 1e4);
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_GLOBAL_NSN_AC, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 1e-8), FRIX_OK);
    const int64_t steps = expect_converged(&c, o);
    ck_assert_msg(steps <= 5, "converged after %lld steps", (long long)steps);
    frix_options_free(o);
    grid_case_free(&c);
}
END_TEST

/* From a warm r on a deformable body 607 keeps the velocity that r gives (from v = 0 it took 7
 * steps from ADMM's answer at 1e-3 on this grid; 1 now). */
START_TEST(newton_keeps_a_warm_starts_velocity_on_a_soft_body) {
    grid_case c = grid_case_make(20, 20, 4, 0.2, 1e4);
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_GLOBAL_ADMM, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 1e-3), FRIX_OK);
    ck_assert_msg(frix_solve(c.p, o, c.r, c.u, c.v, NULL) == FRIX_OK, "%s", frix_last_error_message());
    frix_options_free(o);
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_GLOBAL_NSN_AC, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 1e-8), FRIX_OK);
    const int64_t steps = expect_converged(&c, o);
    ck_assert_msg(steps <= 2, "converged after %lld steps", (long long)steps);
    frix_options_free(o);
    grid_case_free(&c);
}
END_TEST

/* Where Newton on (v, r) fails, auto's reduction does not: on a very stiff grid (k = 1e13)
 * 607 stagnates with an equilibrium residual of 5e-8; auto forms the dense W, its reduced
 * solve's stages come first, and it converges. */
START_TEST(auto_reduces_where_newton_fails) {
    grid_case c = grid_case_make(25, 25, 2, 0.0, 1e13);
    outcome out = solve_global(c.p, FRIX_SOLVER_GLOBAL_NSN_AC, c.r, c.v);
    ck_assert_msg(out.status != FRIX_STATUS_CONVERGED, "607 converged: the case tests nothing");
    memset(c.r, 0, sizeof *c.r * (size_t)c.m), memset(c.v, 0, sizeof *c.v * (size_t)c.n);
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    out = solve_global_into(c.p, FRIX_SOLVER_AUTO, c.r, c.v, info);
    const char *trace = frix_info_trace(info);
    ck_assert_msg(out.status == FRIX_STATUS_CONVERGED && out.error <= 1e-8 && out.equilibrium <= 1e-8,
                  "%s, error %g, equilibrium %g\n%s", frix_status_string(out.status), out.error,
                  out.equilibrium, trace);
    const int64_t first_run = find_other_run(info, 0, 0);
    ck_assert_msg(first_run >= 0 && stage_int(info, first_run, FRIX_STAGE_SOLVER_ID) != FRIX_SOLVER_GLOBAL_NSN_AC,
                  "trace:\n%s", trace);
    frix_info_free(info);
    grid_case_free(&c);
}
END_TEST

/* The sweeps on a 10 x 10 x 4 elastic grid (gap and spring stiffness as given) to 1e-8 with
 * the given acceleration (momentum) and Anderson depth (-1: the solver's default); their count.
 * The answer must meet the tolerance. */
static int64_t grid_sweeps(int solver, double gap, double stiffness, int64_t acceleration, int64_t anderson) {
    grid_case c = grid_case_make(10, 10, 4, gap, stiffness);
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(solver, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_ACCELERATION, acceleration), FRIX_OK);
    if (anderson >= 0) ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_ANDERSON, anderson), FRIX_OK);
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_msg(frix_solve(c.p, o, c.r, c.u, c.v, info) == FRIX_OK, "%s", frix_last_error_message());
    ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_CONVERGED);
    const int64_t sweeps = frix_info_iterations(info);
    frix_info *check = NULL;
    ck_assert_int_eq(frix_info_create(&check), FRIX_OK);
    ck_assert_int_eq(frix_problem_measure(c.p, c.r, c.v, NULL, check), FRIX_OK);
    double error = NAN;
    ck_assert_int_eq(frix_info_get_double(check, FRIX_INFO_ERROR, &error), FRIX_OK);
    ck_assert_msg(error <= 1e-8, "solver %d, acceleration %lld, anderson %lld: measured %.3e", solver,
                  (long long)acceleration, (long long)anderson, error);
    frix_info_free(check);
    frix_info_free(info);
    frix_options_free(o);
    grid_case_free(&c);
    return sweeps;
}

/* On a regular W (an elastic body, 3 nc <= n) momentum takes several times the plain sweeps,
 * and Anderson's mix of the last sweeps fewer: auto's acceleration takes Anderson's there. */
START_TEST(auto_mixes_sweeps_on_a_regular_w) {
    const int64_t plain = grid_sweeps(FRIX_SOLVER_NSGS_VELOCITY, 0.0, 1e4, 0, 0);
    const int64_t momentum = grid_sweeps(FRIX_SOLVER_NSGS_VELOCITY, 0.0, 1e4, 1, 0);
    ck_assert_msg(2 * plain < momentum, "nsgs-v: %lld sweeps plain, %lld with momentum: the case tests nothing",
                  (long long)plain, (long long)momentum);
    /* Stiffer springs: the sweeps contract slowly, and the mix gains most. */
    const int64_t stiff_plain = grid_sweeps(FRIX_SOLVER_NSGS_VELOCITY, 0.05, 1e6, 0, 0);
    const int64_t stiff_mixed = grid_sweeps(FRIX_SOLVER_NSGS_VELOCITY, 0.05, 1e6, 0, 10);
    ck_assert_msg(2 * stiff_mixed < stiff_plain, "nsgs-v, stiff grid: %lld sweeps plain, %lld with anderson 10",
                  (long long)stiff_plain, (long long)stiff_mixed);
    /* Anderson takes the place of momentum when both are asked. */
    ck_assert_int_eq(grid_sweeps(FRIX_SOLVER_NSGS_VELOCITY, 0.05, 1e6, 1, 10), stiff_mixed);
    const int64_t auto_plain = grid_sweeps(FRIX_SOLVER_AUTO, 0.0, 1e4, 0, -1);
    ck_assert_int_le(auto_plain, plain);
    ck_assert_int_lt(grid_sweeps(FRIX_SOLVER_AUTO, 0.0, 1e4, 1, -1), auto_plain);
}
END_TEST

/* A progress callback that stops the solve at its `at`-th call. */
typedef struct {
    int at, calls;
    int64_t largest_iteration;
    double error;
} stop_at_call;

static int stop_at(void *data, int64_t iteration, double error, double seconds) {
    (void)seconds;
    stop_at_call *s = data;
    s->largest_iteration = iteration > s->largest_iteration ? iteration : s->largest_iteration;
    s->error = error;
    return ++s->calls == s->at;
}

/* auto stopped by the caller while it forms a dense W (the first calls of the callback, at
 * iteration 0) returns the start with its velocity: r = 0, v = M^-1 f, their measures. */
START_TEST(auto_stopped_while_forming_w_returns_the_start) {
    /* Thick: W (400 contacts) is formed, its factor as thick as M's. */
    grid_case c = grid_case_make(20, 20, 10, 0.5, 1e4);
    frix_options *o = NULL;
    frix_info *info = NULL, *check = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_AUTO, &o), FRIX_OK);
    stop_at_call stopper = {2, 0, 0, NAN};
    ck_assert_int_eq(frix_options_set_callback(o, stop_at, &stopper), FRIX_OK);
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_info_create(&check), FRIX_OK);
    ck_assert_msg(frix_solve(c.p, o, c.r, c.u, c.v, info) == FRIX_OK, "%s", frix_last_error_message());
    ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_STOPPED_BY_CALLBACK);
    ck_assert_int_eq(stopper.calls, 2);
    ck_assert_int_eq(stopper.largest_iteration, 0);
    ck_assert_int_eq(frix_info_iterations(info), 0);
    for (int64_t i = 0; i < c.m; ++i) ck_assert(c.r[i] == 0.0);
    double reported = NAN, independent = NAN, equilibrium = NAN;
    ck_assert_int_eq(frix_problem_measure(c.p, c.r, c.v, NULL, check), FRIX_OK);
    ck_assert_int_eq(frix_info_get_double(info, FRIX_INFO_ERROR_RELATIVE, &reported), FRIX_OK);
    ck_assert_int_eq(frix_info_get_double(check, FRIX_INFO_ERROR_RELATIVE, &independent), FRIX_OK);
    ck_assert_int_eq(frix_info_get_double(check, FRIX_INFO_EQUILIBRIUM, &equilibrium), FRIX_OK);
    ck_assert_double_eq_tol(reported, independent, 1e-14);
    ck_assert_msg(equilibrium <= 1e-12, "v is not the start's velocity: equilibrium %g", equilibrium);
    frix_info_free(check);
    frix_info_free(info);
    frix_options_free(o);
    grid_case_free(&c);
}
END_TEST

/* An explicit local solver on a deformable body forms the dense W, which takes long on a
 * large mesh: the time limit and the callback end that too, with the
 * caller's start returned, its velocity and its measures. Forming W asks the clock and the
 * callback about 32 times over its work, and the limit here is over before the first time. */
START_TEST(time_limit_and_callback_end_the_forming_of_w) {
    grid_case c = grid_case_make(30, 30, 2, 0.5, 1e4);
    const frix_problem *p = c.p;
    const int64_t m = c.m;
    double *r = c.r, *u = c.u, *v = c.v, *r0 = calloc((size_t)m, sizeof *r0);
    for (int64_t i = 0; i < m; i += 3) r0[i] = 0.01, r0[i + 1] = 0.002;
    memcpy(r, r0, sizeof *r * (size_t)m);
    frix_options *o = NULL;
    frix_info *info = NULL, *check = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_NSGS, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(frix_test_siconos_measure(o), FRIX_OPT_TIME_LIMIT, 1e-6), FRIX_OK);
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_info_create(&check), FRIX_OK);
    ck_assert_msg(frix_solve(p, o, r, u, v, info) == FRIX_OK, "%s", frix_last_error_message());
    ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_TIME_LIMIT);
    ck_assert_int_eq(frix_info_iterations(info), 0); /* NSGS sweeps before it looks at the clock */
    ck_assert(memcmp(r, r0, sizeof *r * (size_t)m) == 0);
    ck_assert_int_eq(frix_problem_measure(p, r, v, NULL, check), FRIX_OK);
    double reported = NAN, independent = NAN, equilibrium = NAN;
    ck_assert_int_eq(frix_info_get_double(info, FRIX_INFO_ERROR_RELATIVE, &reported), FRIX_OK);
    ck_assert_int_eq(frix_info_get_double(check, FRIX_INFO_ERROR_RELATIVE, &independent), FRIX_OK);
    ck_assert_int_eq(frix_info_get_double(check, FRIX_INFO_EQUILIBRIUM, &equilibrium), FRIX_OK);
    ck_assert(isfinite(reported) && reported > 1e-3);
    ck_assert_double_eq_tol(reported, independent, 1e-14);
    ck_assert_msg(equilibrium <= 1e-12, "v is not the start's velocity: equilibrium %g", equilibrium);

    /* The callback is asked too (iteration 0, the start's error): told to stop at its third
     * call, the solve stops there, with the start. */
    stop_at_call stopper = {3, 0, 0, NAN};
    memcpy(r, r0, sizeof *r * (size_t)m);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TIME_LIMIT, 0.0), FRIX_OK);
    ck_assert_int_eq(frix_options_set_callback(o, stop_at, &stopper), FRIX_OK);
    ck_assert_msg(frix_solve(p, o, r, u, v, info) == FRIX_OK, "%s", frix_last_error_message());
    ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_STOPPED_BY_CALLBACK);
    ck_assert_int_eq(stopper.calls, 3);
    ck_assert_int_eq(stopper.largest_iteration, 0);
    ck_assert_double_eq_tol(stopper.error, independent, 1e-14);
    ck_assert(memcmp(r, r0, sizeof *r * (size_t)m) == 0);
    frix_info_free(check);
    frix_info_free(info);
    frix_options_free(o);
    free(r0);
    grid_case_free(&c);
}
END_TEST

/* The same on the LU path (M not symmetric): 130 contacts, each on its own 3 dofs, M with
 * unequal off-diagonals; W's 390 columns are asked about once, after the 384th. */
START_TEST(callback_ends_the_forming_of_w_with_lu) {
    enum { kContacts = 130, kDofs = 3 * kContacts };
    double *m = calloc((size_t)kDofs * kDofs, sizeof *m), *h = calloc((size_t)kDofs * kDofs, sizeof *h);
    double f[kDofs], w[kDofs] = {0}, mu[kContacts], r[kDofs] = {0}, u[kDofs], v[kDofs];
    for (int i = 0; i < kDofs; ++i) {
        m[i + kDofs * i] = 2.0;
        if (i + 1 < kDofs) m[i + kDofs * (i + 1)] = 0.3, m[i + 1 + kDofs * i] = 0.1;
        h[i + kDofs * i] = 1.0;
        f[i] = i % 3 == 0 ? -1.0 : 0.2;
    }
    for (int a = 0; a < kContacts; ++a) mu[a] = 0.3;
    frix_matrix *M = NULL, *H = NULL;
    ck_assert_int_eq(frix_matrix_from_dense(kDofs, kDofs, m, kDofs, &M), FRIX_OK);
    ck_assert_int_eq(frix_matrix_from_dense(kDofs, kDofs, h, kDofs, &H), FRIX_OK);
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_problem_global(M, H, f, w, mu, kContacts, &p), FRIX_OK);
    frix_options *o = NULL;
    frix_info *info = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_NSGS, &o), FRIX_OK);
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    stop_at_call stopper = {1, 0, 0, NAN};
    ck_assert_int_eq(frix_options_set_callback(o, stop_at, &stopper), FRIX_OK);
    ck_assert_msg(frix_solve(p, o, r, u, v, info) == FRIX_OK, "%s", frix_last_error_message());
    ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_STOPPED_BY_CALLBACK);
    ck_assert_int_eq(stopper.calls, 1);
    ck_assert_int_eq(stopper.largest_iteration, 0);
    for (int i = 0; i < kDofs; ++i) ck_assert(r[i] == 0.0);
    /* Without the callback, NSGS solves it. */
    double r2[kDofs] = {0};
    const outcome out = solve_global(p, FRIX_SOLVER_NSGS, r2, v);
    ck_assert_msg(out.status == FRIX_STATUS_CONVERGED && out.error <= 1e-8, "%s, error %g",
                  frix_status_string(out.status), out.error);
    frix_info_free(info);
    frix_options_free(o);
    frix_problem_free(p);
    frix_matrix_free(M);
    frix_matrix_free(H);
    free(m), free(h);
}
END_TEST

/* Where W would not fit in memory, a local solver on a global problem is refused before it
 * starts forming it (the system would kill the process part-way): a chain of 160000 nodes
 * on the plane, one body, W up to 3 x 160000^2 entries (1.2 TB). */
START_TEST(reduction_refused_where_w_would_not_fit) {
    grid_case c = grid_case_make(160000, 1, 1, 0.5, 1e4);
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_NSGS, &o), FRIX_OK);
    /* Only a safety net: a broken refusal ends at the time limit, not out of memory. */
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TIME_LIMIT, 0.5), FRIX_OK);
    ck_assert_int_eq(frix_solve(c.p, o, c.r, c.u, c.v, NULL), FRIX_ERR_OUT_OF_MEMORY);
    const char *why = frix_last_error_message();
    ck_assert_msg(strstr(why, "nsgs reduces the global problem") && strstr(why, "7.68e+10 entries") &&
                      strstr(why, "gnsn-ac (607) and auto"),
                  "%s", why);
    frix_options_free(o);
    grid_case_free(&c);
}
END_TEST

int main(void) {
    Suite *s = suite_create("global");
    TCase *tc = tcase_create("core");
    tcase_set_timeout(tc, 120);
    tcase_add_loop_test(tc, both_routes_solve_the_global_files, 0,
                        (int)(sizeof kGlobalFiles / sizeof kGlobalFiles[0]));
    tcase_add_test(tc, the_rigid_spheres_by_both_routes);
    tcase_add_test(tc, small_problems_stored_as_csc);
    tcase_add_test(tc, product_form_sweeps_as_nsgs_v);
    tcase_add_test(tc, product_form_mixes_sweeps);
    tcase_add_test(tc, singular_mass_matrix_held_or_refused);
    tcase_add_test(tc, no_contacts);
    tcase_add_test(tc, auto_prices_the_reduction_of_a_deformable_body);
    tcase_add_test(tc, auto_asks_whether_forming_w_fits_the_time_only_where_it_would_form_it);
    tcase_add_test(tc, auto_finishes_a_stiff_body_with_newton_after_admm);
    tcase_add_test(tc, solvers_without_w);
    tcase_add_test(tc, persistent_without_w_factorises_once);
    tcase_add_test(tc, elastic_grid_arguments);
    tcase_add_test(tc, admm_changes_rho_only_where_it_pays);
    tcase_add_test(tc, admm_stops_near_the_first_iterate_within_the_tolerance);
    tcase_add_test(tc, tightened_passes_number_on);
    tcase_add_test(tc, auto_without_w_on_a_floating_grid);
    tcase_add_test(tc, admm_system_keeps_only_the_couplings_rho_i_makes);
    tcase_add_test(tc, single_precision_solves_refined_in_double);
    tcase_add_test(tc, inverse_diagonal_matches_full_solves);
    tcase_add_test(tc, newton_corrects_the_lumped_rho);
    tcase_add_test(tc, newton_cuts_a_rho_too_large);
    tcase_add_test(tc, newton_takes_a_full_first_step_on_a_soft_body);
    tcase_add_test(tc, newton_keeps_a_warm_starts_velocity_on_a_soft_body);
    tcase_add_test(tc, auto_reduces_where_newton_fails);
    tcase_add_test(tc, auto_mixes_sweeps_on_a_regular_w);
    tcase_add_test(tc, auto_stopped_while_forming_w_returns_the_start);
    tcase_add_test(tc, time_limit_and_callback_end_the_forming_of_w);
    tcase_add_test(tc, callback_ends_the_forming_of_w_with_lu);
    tcase_add_test(tc, reduction_refused_where_w_would_not_fit);
    suite_add_tcase(s, tc);
    return frix_run_suite(s);
}
