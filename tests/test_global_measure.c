/* The default measure of a global problem: complete (the equilibrium residual is part of the
 * error) and free of units (one problem in three unit systems: the same verdict, the same
 * error); and a singular M (a body held only by its contacts) solved where the contacts hold
 * it, refused with the reason where they do not. */
#include <frix/frix.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check_main.h"

/* Units: a length, a mass and a time unit, as factors from m, kg, s (mm: L = 1000). A value
 * of dimension mass^a length^b time^c is multiplied by Mu^a L^b T^-c. */
typedef struct {
    const char *name;
    double L, Mu, T;
} units;
static const units kUnits[3] = {{"m/kg/s", 1, 1, 1}, {"mm/kg/s", 1000, 1, 1}, {"m/g/ms", 1, 1000, 1000}};

typedef struct {
    int64_t n, nc;
    double *M, *H, *f, *w, *mu; /* M n x n and H n x 3nc dense, column-major */
    frix_matrix *Mm, *Hm;
    frix_problem *p;
} dense_case;

static void case_alloc(dense_case *c, int64_t n, int64_t nc) {
    c->n = n, c->nc = nc;
    c->M = calloc((size_t)(n * n), sizeof(double));
    c->H = calloc((size_t)(n * 3 * nc), sizeof(double));
    c->f = calloc((size_t)n, sizeof(double));
    c->w = calloc((size_t)(3 * nc), sizeof(double));
    c->mu = calloc((size_t)nc, sizeof(double));
}

static void case_make(dense_case *c) {
    ck_assert_int_eq(frix_matrix_from_dense(c->n, c->n, c->M, c->n, &c->Mm), FRIX_OK);
    ck_assert_int_eq(frix_matrix_from_dense(c->n, 3 * c->nc, c->H, c->n, &c->Hm), FRIX_OK);
    ck_assert_int_eq(frix_problem_global(c->Mm, c->Hm, c->f, c->w, c->mu, c->nc, &c->p), FRIX_OK);
}

static void case_free(dense_case *c) {
    frix_problem_free(c->p);
    frix_matrix_free(c->Mm);
    frix_matrix_free(c->Hm);
    free(c->M), free(c->H), free(c->f), free(c->w), free(c->mu);
}

/* A rigid cube (3 translations, 3 rotations) of 2 kg and side 0.1 m falling (1 m/s) and
 * sliding (0.1 m/s) onto a plane at its 4 bottom corners, a time step of 1 ms, in units u:
 * translations and rotations scale apart, which a measure that mixes them does not survive. */
static void rigid_cube(dense_case *c, units u) {
    case_alloc(c, 6, 4);
    const double m = 2.0, a = 0.1, I = m * a * a / 6.0, h = 1e-3, g = 9.81;
    const double v0[6] = {0.1, 0, -1.0, 0, 0.5, 0};
    const double sm[6] = {u.Mu, u.Mu, u.Mu, u.Mu * u.L * u.L, u.Mu * u.L * u.L, u.Mu * u.L * u.L};
    const double sp[6] = {u.Mu * u.L / u.T, u.Mu * u.L / u.T, u.Mu * u.L / u.T, u.Mu * u.L * u.L / u.T,
                          u.Mu * u.L * u.L / u.T, u.Mu * u.L * u.L / u.T}; /* momentum */
    for (int i = 0; i < 6; ++i) {
        const double mi = i < 3 ? m : I;
        c->M[i * 6 + i] = mi * sm[i];
        c->f[i] = (mi * v0[i] - (i == 2 ? h * m * g : 0.0)) * sp[i];
    }
    /* Contact frame: normal z, tangents x and y; u = v + omega x p, p the corner. */
    const double frame[3][3] = {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}};
    for (int k = 0; k < 4; ++k) {
        const double p[3] = {(k & 1 ? 0.5 : -0.5) * a, (k & 2 ? 0.5 : -0.5) * a, -0.5 * a};
        for (int d = 0; d < 3; ++d) {
            const double *e = frame[d];
            double *col = c->H + 6 * (3 * k + d);
            for (int i = 0; i < 3; ++i) col[i] = e[i];
            col[3] = (p[1] * e[2] - p[2] * e[1]) * u.L; /* p x e: a lever arm, a length */
            col[4] = (p[2] * e[0] - p[0] * e[2]) * u.L;
            col[5] = (p[0] * e[1] - p[1] * e[0]) * u.L;
        }
        c->mu[k] = 0.3;
    }
    case_make(c);
}

/* A static elastic block of nx x ny x nz nodes joined by springs of stiffness k (the same in
 * each direction: a stiffness matrix whose free motions are the 3 translations), standing on
 * a plane at its bottom nodes (contact frame: normal z, tangents x, y; gaps 0), loaded on its
 * top nodes by (fx, 0, fz) in all. clamp: the top nodes are also held by springs to the
 * ground (M positive definite); else the contacts alone hold the block. In units u: M is a
 * stiffness (mass / time^2), v a displacement, f and r forces, w a length. */
static void elastic_block(dense_case *c, int nx, int ny, int nz, int clamp, double fx, double fz, units u) {
    const int64_t nodes = (int64_t)nx * ny * nz;
    case_alloc(c, 3 * nodes, (int64_t)nx * ny);
    const double k = 1e4 * u.Mu / (u.T * u.T), force = u.Mu * u.L / (u.T * u.T);
    const int64_t n = c->n;
#define NODE(i, j, l) (((int64_t)(l) * ny + (j)) * nx + (i))
    for (int l = 0; l < nz; ++l)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) {
                const int64_t a = NODE(i, j, l);
                const int64_t nb[3] = {i + 1 < nx ? NODE(i + 1, j, l) : -1, j + 1 < ny ? NODE(i, j + 1, l) : -1,
                                       l + 1 < nz ? NODE(i, j, l + 1) : -1};
                for (int s = 0; s < 3; ++s) {
                    if (nb[s] < 0) continue;
                    for (int d = 0; d < 3; ++d) {
                        const int64_t x = 3 * a + d, y = 3 * nb[s] + d;
                        c->M[x * n + x] += k, c->M[y * n + y] += k;
                        c->M[x * n + y] -= k, c->M[y * n + x] -= k;
                    }
                }
            }
    const double top = (double)nx * ny;
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            const int64_t t = NODE(i, j, nz - 1), b = NODE(i, j, 0), a = (int64_t)j * nx + i;
            c->f[3 * t] += fx / top * force;
            c->f[3 * t + 2] += fz / top * force;
            if (clamp)
                for (int d = 0; d < 3; ++d) c->M[(3 * t + d) * n + 3 * t + d] += k;
            double *col = c->H + n * 3 * a;
            col[3 * b + 2] = 1.0;          /* normal: z */
            col[n + 3 * b] = 1.0;          /* tangent: x */
            col[2 * n + 3 * b + 1] = 1.0;  /* tangent: y */
            c->mu[a] = 0.3;
        }
#undef NODE
    case_make(c);
}

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
                if (shape == 0) rigid_cube(&c, un);
                else elastic_block(&c, 4, 4, 3, 1, 0.2, -1.0, un);
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
        rigid_cube(&c, un);
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
    elastic_block(&c, 3, 3, 2, 1, 0.0, -1.0, kUnits[0]);
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
    elastic_block(&c, 3, 3, 2, 1, 0.0, -1.0, kUnits[0]);
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
            elastic_block(&c, 4, 4, 3, 0, loads[l][0], loads[l][1], kUnits[0]);
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
    elastic_block(&c, 4, 4, 3, 0, 0.2, -1.0, kUnits[0]);
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
