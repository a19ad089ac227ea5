/* The granular client's contact rows (examples/granular/pour.c) with the library's rolling and
 * spinning law: one sphere resting on the floor and spinning about the vertical, one time step.
 * Spinning friction brakes the spin by mu_s r_N / I (r_N = m g h, the weight's impulse) or stops
 * it, if that is less; the rolling law alone leaves it as it is. Checks the spin row's sign and
 * the law's projection through the whole solve. */
#include <math.h>
#include <stdlib.h>

#include "check_main.h"
#include "pour.h"

enum { kDofs = 6 };

/* v after one step of h for a sphere of radius R on the floor spinning at omega about z: the
 * contact's rows by contact_blocks_of (dim 5: rolling resistance only; 6: spinning too). */
static void one_step(int dim, double omega, double mu_s, double h, double v_out[kDofs], double r_out[6]) {
    const double R = 0.01, mass = DENSITY * 4.0 / 3.0 * M_PI * R * R * R, inertia = 0.4 * mass * R * R;
    double x[3] = {0.05, 0.05, R}, v[kDofs] = {0, 0, 0, 0, 0, omega};
    world w = {.n = 1, .x = x, .v = v, .radius = (double[]){R}, .mass = (double[]){mass},
               .inertia = (double[]){inertia}, .box = {0.1, 0.1}, .rmax = R, .rmin = R};
    contact c = {.a = 0, .b = 1, .gap = 0.0, .frame = {0, 0, 1, 1, 0, 0, 0, 1, 0}};
    contacts cs = {.c = &c, .count = 1, .capacity = 1};
    int64_t rows[72], cols[72];
    double vals[72];
    const int64_t entries = assemble_h(&w, &cs, dim, rows, cols, vals);
    frix_matrix *M = NULL, *H = NULL;
    double mdiag[kDofs] = {mass, mass, mass, inertia, inertia, inertia}, f[kDofs];
    int64_t idx[kDofs] = {0, 1, 2, 3, 4, 5};
    for (int q = 0; q < kDofs; ++q) f[q] = mdiag[q] * v[q] - (q == 2 ? h * mass * GRAVITY : 0.0);
    ck_assert_int_eq(frix_matrix_from_triplets(kDofs, kDofs, kDofs, idx, idx, mdiag, &M), FRIX_OK);
    ck_assert_int_eq(frix_matrix_from_triplets(kDofs, dim, entries, rows, cols, vals, &H), FRIX_OK);
    double wv[6] = {0}, mu = 0.5, mu_r = 1e-3, u[6];
    frix_problem *p = NULL;
    if (dim == 6) ck_assert_int_eq(frix_problem_spinning_global(M, H, f, wv, &mu, &mu_r, &mu_s, 1, &p), FRIX_OK);
    else ck_assert_int_eq(frix_problem_rolling_global(M, H, f, wv, &mu, &mu_r, 1, &p), FRIX_OK);
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_AUTO, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 1e-12), FRIX_OK);
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    for (int k = 0; k < 6; ++k) r_out[k] = 0.0;
    ck_assert_int_eq(frix_solve(p, o, r_out, u, v_out, info), FRIX_OK);
    ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_CONVERGED);
    frix_info_free(info);
    frix_options_free(o);
    frix_problem_free(p);
    frix_matrix_free(H);
    frix_matrix_free(M);
}

START_TEST(test_spin_braked_or_stopped) {
    const double R = 0.01, mass = DENSITY * 4.0 / 3.0 * M_PI * R * R * R, inertia = 0.4 * mass * R * R;
    const double h = 2e-3, mu_s = 1e-3, weight = mass * GRAVITY * h, brake = mu_s * weight / inertia;
    double v[kDofs], r[6];
    /* Spinning fast: the moment is on its bound, against the spin. */
    one_step(6, 5.0, mu_s, h, v, r);
    ck_assert_double_eq_tol(r[0], weight, 1e-10 * weight);
    ck_assert_double_eq_tol(r[5], -mu_s * weight, 1e-8 * mu_s * weight);
    ck_assert_double_eq_tol(v[5], 5.0 - brake, 1e-8);
    ck_assert_double_eq_tol(v[2], 0.0, 1e-10);
    /* Spinning slowly: stopped within the step, the moment inside its bound. */
    one_step(6, 0.5 * brake, mu_s, h, v, r);
    ck_assert_double_eq_tol(v[5], 0.0, 1e-8 * brake);
    ck_assert_double_lt(fabs(r[5]), mu_s * weight);
    /* No spinning friction (mu_s 0, and the five-entry law): the spin stays. */
    one_step(6, 5.0, 0.0, h, v, r);
    ck_assert_double_eq_tol(v[5], 5.0, 1e-10);
    one_step(5, 5.0, mu_s, h, v, r);
    ck_assert_double_eq_tol(v[5], 5.0, 1e-10);
}
END_TEST

int main(void) {
    Suite *s = suite_create("granular_spin");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, test_spin_braked_or_stopped);
    suite_add_tcase(s, tc);
    return frix_run_suite(s);
}
