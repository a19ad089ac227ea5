/* The default measure of a global problem: complete (the equilibrium residual is part of the
 * error) and free of units (one problem in three unit systems: the same verdict, the same
 * error); and a singular M (a body held only by its contacts) solved where the contacts hold
 * it, refused with the reason where they do not. */
#include <frix/frix.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check_main.h"
#include "unit_cases.h"

typedef struct {
    frix_error err;
    frix_status status;
    double error, equilibrium, normal_sum; /* normal_sum: sum of r_N in the units' force */
} run;

static run solve_case(const dense_case *c, int solver, double tol, double force_unit) {
    double *r = calloc((size_t)(3 * c->nc), sizeof(double)), *u = calloc((size_t)(3 * c->nc), sizeof(double));
    double *v = calloc((size_t)c->n, sizeof(double));
    frix_options *o = NULL;
    frix_info *info = NULL;
    ck_assert_int_eq(frix_options_create(solver, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, tol), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_MAX_ITER, 5000), FRIX_OK);
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    run out = {frix_solve(c->p, o, r, u, v, info), frix_info_status(info), frix_info_error(info), NAN, 0.0};
    ck_assert_int_eq(frix_info_get_double(info, FRIX_INFO_EQUILIBRIUM_SCALED, &out.equilibrium), FRIX_OK);
    for (int64_t a = 0; a < c->nc; ++a) out.normal_sum += r[3 * a] / force_unit;
    frix_info_free(info);
    frix_options_free(o);
    free(r), free(u), free(v);
    return out;
}

static const int kGlobalSolvers[] = {FRIX_SOLVER_AUTO, FRIX_SOLVER_NSGS, FRIX_SOLVER_GLOBAL_ADMM,
                                     FRIX_SOLVER_GLOBAL_AL_NEWTON, FRIX_SOLVER_GLOBAL_NSN_AC};

/* Errors that agree to 3 digits, or both at rounding (1e-14). */
static int same_error(double a, double b) { return fabs(a - b) <= 1e-3 * fmax(a, b) + 1e-14; }

/* The cube and the clamped block in three unit systems, by each global route (and gnsgs, for
 * rigid bodies only, on the cube): the same status and the same error, at 1e-8. */
START_TEST(three_unit_systems_one_verdict) {
    const size_t routes = sizeof kGlobalSolvers / sizeof kGlobalSolvers[0];
    for (int shape = 0; shape < 2; ++shape)
        for (size_t s = 0; s < routes + (shape == 0); ++s) {
            const int solver = s < routes ? kGlobalSolvers[s] : FRIX_SOLVER_GLOBAL_NSGS;
            run first = {0};
            for (int k = 0; k < 3; ++k) {
                dense_case c;
                const units un = kUnits[k];
                ck_assert_int_eq(shape == 0 ? rigid_cube(&c, un) : elastic_block(&c, 4, 4, 3, 1, 0.2, -1.0, un),
                                 FRIX_OK);
                const run out = solve_case(&c, solver, 1e-8,
                                           shape == 0 ? un.Mu * un.L / un.T : un.Mu * un.L / (un.T * un.T));
                case_free(&c);
                ck_assert_msg(out.err == FRIX_OK, "%s", frix_last_error_message());
                ck_assert_msg(out.status == FRIX_STATUS_CONVERGED && out.error <= 1e-8,
                              "shape %d solver %d in %s: %s, error %g", shape, solver, un.name,
                              frix_status_string(out.status), out.error);
                if (k == 0) {
                    first = out;
                    continue;
                }
                ck_assert_msg(same_error(out.error, first.error) && fabs(out.normal_sum - first.normal_sum) <= 1e-6,
                              "shape %d solver %d: error %.6e in %s, %.6e in m/kg/s; sum r_N %.9f, %.9f", shape,
                              solver, out.error, un.name, first.error, out.normal_sum, first.normal_sum);
            }
        }
}
END_TEST

/* The same (r, v), out of equilibrium, measured in three unit systems: one value of the default
 * measure; and (r, v) = 0 on a problem whose contacts are closed (w = 0), where the contact
 * part is exactly 0, reports the equilibrium residual 1 instead of 0. */
START_TEST(measure_is_unit_free_and_complete) {
    double first = NAN;
    for (int k = 0; k < 3; ++k) {
        dense_case c;
        const units un = kUnits[k];
        ck_assert_int_eq(rigid_cube(&c, un), FRIX_OK);
        /* r: 0.4 N s at each contact, normal; v: the start's velocity, scaled. */
        double r[12] = {0}, v[6] = {0.1 * un.L / un.T, 0, -0.2 * un.L / un.T, 0, 0.3 / un.T, 0};
        for (int a = 0; a < 4; ++a) r[3 * a] = 0.4 * un.Mu * un.L / un.T, r[3 * a + 1] = 0.05 * un.Mu * un.L / un.T;
        frix_info *info = NULL;
        ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
        ck_assert_int_eq(frix_problem_measure(c.p, r, v, NULL, info), FRIX_OK);
        double e = NAN, contact = NAN, eq = NAN;
        ck_assert_int_eq(frix_info_get_double(info, FRIX_INFO_ERROR_SCALED, &e), FRIX_OK);
        ck_assert_int_eq(frix_info_get_double(info, FRIX_INFO_ERROR_CONTACT, &contact), FRIX_OK);
        ck_assert_int_eq(frix_info_get_double(info, FRIX_INFO_EQUILIBRIUM_SCALED, &eq), FRIX_OK);
        ck_assert_msg(e == fmax(contact, eq) && eq > 1e-3, "error %g, contact %g, equilibrium %g", e, contact, eq);
        if (k == 0) first = e;
        else ck_assert_msg(fabs(e - first) <= 1e-12 * first, "%s: %.15e against %.15e", un.name, e, first);
        frix_info_free(info);
        case_free(&c);
    }
    dense_case c;
    ck_assert_int_eq(elastic_block(&c, 3, 3, 2, 1, 0.0, -1.0, kUnits[0]), FRIX_OK);
    double *r = calloc((size_t)(3 * c.nc), sizeof(double)), *v = calloc((size_t)c.n, sizeof(double));
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_problem_measure(c.p, r, v, NULL, info), FRIX_OK);
    double contact = NAN;
    ck_assert_int_eq(frix_info_get_double(info, FRIX_INFO_ERROR_CONTACT, &contact), FRIX_OK);
    ck_assert_msg(contact == 0.0 && frix_info_error(info) == 1.0, "contact %g error %g", contact,
                  frix_info_error(info));
    frix_info_free(info);
    free(r), free(v);
    case_free(&c);
}
END_TEST

static int stop_at_once(void *data, int64_t iteration, double error, double seconds) {
    (void)data, (void)iteration, (void)error, (void)seconds;
    return 1;
}

/* A run its caller stops at once reports the error of what it returns, equilibrium included:
 * never 0 for an answer that is not one. */
START_TEST(stopped_run_reports_its_error) {
    dense_case c;
    ck_assert_int_eq(elastic_block(&c, 3, 3, 2, 1, 0.0, -1.0, kUnits[0]), FRIX_OK);
    for (size_t s = 0; s < sizeof kGlobalSolvers / sizeof kGlobalSolvers[0]; ++s) {
        double *r = calloc((size_t)(3 * c.nc), sizeof(double)), *u = calloc((size_t)(3 * c.nc), sizeof(double));
        double *v = calloc((size_t)c.n, sizeof(double));
        frix_options *o = NULL;
        frix_info *info = NULL;
        ck_assert_int_eq(frix_options_create(kGlobalSolvers[s], &o), FRIX_OK);
        ck_assert_int_eq(frix_options_set_callback(o, stop_at_once, NULL), FRIX_OK);
        ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
        ck_assert_int_eq(frix_solve(c.p, o, r, u, v, info), FRIX_OK);
        ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_STOPPED_BY_CALLBACK);
        ck_assert_msg(frix_info_error(info) > 1e-3, "solver %d: error %g", kGlobalSolvers[s], frix_info_error(info));
        frix_info_free(info);
        frix_options_free(o);
        free(r), free(u), free(v);
    }
    case_free(&c);
}
END_TEST

/* The block held by its contacts alone (M singular: 3 free translations): pressed down with a
 * side load friction takes (0.2 < 0.3), it is solved, equilibrium included, by every global
 * route; pushed sideways beyond friction (0.5) or lifted, it is refused with the reason. */
START_TEST(floating_block_held_or_refused) {
    const int solvers[] = {FRIX_SOLVER_AUTO, FRIX_SOLVER_GLOBAL_ADMM, FRIX_SOLVER_GLOBAL_AL_NEWTON,
                           FRIX_SOLVER_GLOBAL_NSN_AC};
    const double loads[3][2] = {{0.2, -1.0}, {0.5, -1.0}, {0.0, 1.0}};
    for (int l = 0; l < 3; ++l)
        for (size_t s = 0; s < sizeof solvers / sizeof solvers[0]; ++s) {
            dense_case c;
            ck_assert_int_eq(elastic_block(&c, 4, 4, 3, 0, loads[l][0], loads[l][1], kUnits[0]), FRIX_OK);
            const run out = solve_case(&c, solvers[s], 1e-8, 1.0);
            case_free(&c);
            if (l == 0) {
                ck_assert_msg(out.err == FRIX_OK, "%s", frix_last_error_message());
                ck_assert_msg(out.status == FRIX_STATUS_CONVERGED && out.error <= 1e-8 && out.equilibrium <= 1e-8,
                              "solver %d: %s, error %g, equilibrium %g", solvers[s], frix_status_string(out.status),
                              out.error, out.equilibrium);
                ck_assert_double_eq_tol(out.normal_sum, 1.0, 1e-6); /* the contacts carry the load */
            } else {
                ck_assert_msg(out.err == FRIX_ERR_NUMERICAL && strstr(frix_last_error_message(), "M is singular") &&
                                  strstr(frix_last_error_message(), "do not hold"),
                              "load %d solver %d: %d, %s", l, solvers[s], out.err, frix_last_error_message());
            }
        }
}
END_TEST

/* A host's steps on the floating block with a persistent solver: each step converges, equilibrium
 * included; the later steps reuse M's test and the shifted factorisation (no factorisation of
 * M or of the shifted M again: only what the solver itself factorises). */
START_TEST(floating_block_persistent_steps) {
    dense_case c;
    ck_assert_int_eq(elastic_block(&c, 4, 4, 3, 0, 0.2, -1.0, kUnits[0]), FRIX_OK);
    frix_options *o = NULL;
    frix_persistent *ps = NULL;
    frix_info *info = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_GLOBAL_NSN_AC, &o), FRIX_OK);
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_persistent_create(c.p, o, &ps), FRIX_OK);
    double *r = calloc((size_t)(3 * c.nc), sizeof(double)), *u = calloc((size_t)(3 * c.nc), sizeof(double));
    double *v = calloc((size_t)c.n, sizeof(double));
    const double f0[2] = {c.f[3 * (c.n / 3 - 1)], c.f[3 * (c.n / 3 - 1) + 2]};
    int64_t first_factorizations = 0;
    for (int step = 0; step < 3; ++step) {
        /* The load changes in place: 0.2, 0.1, 0.25 sideways against 1 down. */
        const double side[3] = {1.0, 0.5, 1.25};
        for (int64_t i = 0; i < c.n; i += 3)
            if (c.f[i + 2] != 0.0) c.f[i] = f0[0] * side[step] * (c.f[i + 2] / f0[1]);
        ck_assert_msg(frix_persistent_solve(ps, r, u, v, info) == FRIX_OK, "%s", frix_last_error_message());
        double eq = NAN;
        ck_assert_int_eq(frix_info_get_double(info, FRIX_INFO_EQUILIBRIUM_SCALED, &eq), FRIX_OK);
        ck_assert_msg(frix_info_status(info) == FRIX_STATUS_CONVERGED && eq <= 1e-8,
                      "step %d: %s, error %g, equilibrium %g, %lld iterations", step,
                      frix_status_string(frix_info_status(info)), frix_info_error(info), eq,
                      (long long)frix_info_iterations(info));
        int64_t factorizations = 0;
        ck_assert_int_eq(frix_info_get_int(info, FRIX_INFO_FACTORIZATIONS, &factorizations), FRIX_OK);
        if (step == 0) first_factorizations = factorizations;
        else ck_assert_msg(factorizations < first_factorizations, "step %d: %lld factorisations, the first %lld", step,
                           (long long)factorizations, (long long)first_factorizations);
    }
    free(r), free(u), free(v);
    frix_persistent_free(ps);
    frix_info_free(info);
    frix_options_free(o);
    case_free(&c);
}
END_TEST

int main(void) {
    Suite *s = suite_create("global_measure");
    TCase *tc = tcase_create("core");
    tcase_set_timeout(tc, 120);
    tcase_add_test(tc, three_unit_systems_one_verdict);
    tcase_add_test(tc, measure_is_unit_free_and_complete);
    tcase_add_test(tc, stopped_run_reports_its_error);
    tcase_add_test(tc, floating_block_held_or_refused);
    tcase_add_test(tc, floating_block_persistent_steps);
    suite_add_tcase(s, tc);
    return frix_run_suite(s);
}
