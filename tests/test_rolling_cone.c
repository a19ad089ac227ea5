/* The projection on the rolling cone (src/rolling.hpp), five entries and six (spinning
 * friction), checked by Moreau's decomposition: x = P(x) + y with P(x) in K, y in the polar cone
 * K° = {y_N + mu |y_T| + mu_r |y_R| (+ mu_s |y_S|) <= 0} and P(x) . y = 0, which holds for the
 * projection only. Random points of every case, and the five-entry projection (Siconos's cases)
 * against the six-entry one with no spin. */
#include <math.h>
#include <stdint.h>

#include "check_main.h"
#include "frix_testing.h"
#include "support/lcg.h"

/* A deterministic stream in [-1, 1). */
static double next(uint64_t *state) { return 2.0 * lcg_uniform(state) - 1.0; }

static double norm_of(const double *x, int n) {
    double s = 0.0;
    for (int i = 0; i < n; ++i) s += x[i] * x[i];
    return sqrt(s);
}

/* The parts' norms: tangential, rolling, spinning (0 for five entries). */
static void parts(const double *x, int size, double n[3]) {
    n[0] = sqrt(x[1] * x[1] + x[2] * x[2]);
    n[1] = sqrt(x[3] * x[3] + x[4] * x[4]);
    n[2] = size == 6 ? fabs(x[5]) : 0.0;
}

static void check_moreau(const double *x, int size, const double c[3]) {
    double p[6];
    for (int i = 0; i < size; ++i) p[i] = x[i];
    const int which = frix_testing_project_on_rolling_cone(p, c[0], c[1], c[2], size);
    const double scale = norm_of(x, size), tol = 1e-13 * (scale > 1.0 ? scale : 1.0);
    double y[6], np[3], ny[3], dot = 0.0;
    for (int i = 0; i < size; ++i) y[i] = x[i] - p[i], dot += p[i] * y[i];
    parts(p, size, np);
    parts(y, size, ny);
    ck_assert_double_ge(p[0], -tol);
    for (int k = 0; k < 3; ++k) ck_assert_double_le(np[k], c[k] * p[0] + tol);
    ck_assert_msg(y[0] + c[0] * ny[0] + c[1] * ny[1] + c[2] * ny[2] <= tol, "size %d case %d x %.17g %.17g %.17g %.17g %.17g %.17g c %.17g %.17g %.17g", size, which, x[0], x[1], x[2], x[3], x[4], size == 6 ? x[5] : 0.0, c[0], c[1], c[2]);
    ck_assert_double_le(fabs(dot), tol * (scale > 1.0 ? scale : 1.0));
    /* The case: 0 for the origin; else the parts on their boundary where something was cut. */
    if (which == 0) ck_assert_double_le(norm_of(p, size), tol);
    else if (which == 1) ck_assert_double_le(norm_of(y, size), tol);
    else
        for (int k = 0; k < 3; ++k)
            if ((which - 1) & (1 << k)) ck_assert_double_le(fabs(np[k] - c[k] * p[0]), tol);
}

START_TEST(test_moreau_decomposition) {
    uint64_t state = 12345;
    int seen[9] = {0};
    for (int trial = 0; trial < 20000; ++trial) {
        const int size = trial % 2 ? 6 : 5;
        /* Coefficients of several scales (mu_r, mu_s are lengths: small), and 0 at times. */
        double c[3] = {fabs(next(&state)), 0.05 * fabs(next(&state)), 0.05 * fabs(next(&state))};
        if (trial % 7 == 0) c[1] = 0.0;
        if (trial % 11 == 0) c[2] = 0.0;
        if (size == 5) c[2] = 0.0;
        double x[6];
        for (int i = 0; i < size; ++i) x[i] = next(&state);
        /* Parts small enough for each case to occur. */
        x[3] *= 0.1, x[4] *= 0.1;
        if (size == 6) x[5] *= 0.1;
        check_moreau(x, size, c);
        double p[6];
        for (int i = 0; i < size; ++i) p[i] = x[i];
        ++seen[frix_testing_project_on_rolling_cone(p, c[0], c[1], c[2], size)];
    }
    /* Every case occurred: the origin, inside, and each set of parts cut. */
    for (int k = 0; k < 9; ++k) ck_assert_msg(seen[k] > 0, "case %d never occurred", k);
}
END_TEST

START_TEST(test_five_entries_are_six_without_spin) {
    uint64_t state = 777;
    for (int trial = 0; trial < 5000; ++trial) {
        const double mu = fabs(next(&state)), mu_r = 0.05 * fabs(next(&state));
        double x5[5], x6[6];
        for (int i = 0; i < 5; ++i) x5[i] = x6[i] = next(&state);
        x6[5] = 0.0;
        const int c5 = frix_testing_project_on_rolling_cone(x5, mu, mu_r, 0.0, 5);
        const int c6 = frix_testing_project_on_rolling_cone(x6, mu, mu_r, 0.3, 6);
        ck_assert_int_eq(c5, c6);
        for (int i = 0; i < 5; ++i) ck_assert_double_eq_tol(x5[i], x6[i], 1e-14);
        ck_assert_double_eq(x6[5], 0.0);
    }
}
END_TEST

int main(void) {
    Suite *s = suite_create("rolling_cone");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, test_moreau_decomposition);
    tcase_add_test(tc, test_five_entries_are_six_without_spin);
    suite_add_tcase(s, tc);
    return frix_run_suite(s);
}
