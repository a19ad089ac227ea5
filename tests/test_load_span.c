/* The loads a factorised M was solved for (src/load_span.hpp, through frix_testing_load_span):
 * a load in their span is answered by the combination of their answers, as accurately as a
 * solve; a load off the span, a combination that cancels large terms, or one whose answers
 * are not as accurate as the solves, is left to a solve. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <frix/frix.h>

#include "check_main.h"
#include "frix_testing.h"

enum { kN = 300 };

/* M: tridiagonal, 2.01 + 0.001 i on the diagonal, -1 beside it (symmetric positive definite,
 * condition number about 3e3), CSC. */
typedef struct {
    int64_t colptr[kN + 1], rowind[3 * kN];
    double values[3 * kN], diag[kN];
} tridiagonal;

static void make_m(tridiagonal *m) {
    int64_t e = 0;
    for (int j = 0; j < kN; ++j) {
        m->colptr[j] = e;
        m->diag[j] = 2.01 + 0.001 * j;
        for (int i = j - 1; i <= j + 1; ++i) {
            if (i < 0 || i >= kN) continue;
            m->rowind[e] = i;
            m->values[e++] = i == j ? m->diag[j] : -1.0;
        }
    }
    m->colptr[kN] = e;
}

/* x = M^-1 f by elimination along the diagonal (Thomas). */
static void solve(const tridiagonal *m, const double *f, double *x) {
    double c[kN], d[kN];
    c[0] = -1.0 / m->diag[0];
    d[0] = f[0] / m->diag[0];
    for (int i = 1; i < kN; ++i) {
        const double den = m->diag[i] + c[i - 1];
        c[i] = -1.0 / den;
        d[i] = (f[i] + d[i - 1]) / den;
    }
    x[kN - 1] = d[kN - 1];
    for (int i = kN - 2; i >= 0; --i) x[i] = d[i] - c[i] * x[i + 1];
}

static void load(int kind, double *f) {
    for (int i = 0; i < kN; ++i)
        f[i] = kind == 0 ? sin(0.05 * i) + 0.3 : kind == 1 ? cos(0.11 * i) : kind == 2 ? (double)((i * 7919) % 13) - 6.0 : 1.0;
}

/* Whether f is answered from the k loads F (with their answers), and if so x within 1e-12 of a
 * solve's (max norms). */
static int answered(const tridiagonal *m, int k, const double *F, const double *f) {
    double X[4 * kN], x[kN], direct[kN];
    for (int i = 0; i < k; ++i) solve(m, F + i * kN, X + i * kN);
    for (int i = 0; i < kN; ++i) x[i] = NAN;
    const int got = frix_testing_load_span(kN, m->colptr, m->rowind, m->values, k, F, X, f, x);
    if (!got) {
        for (int i = 0; i < kN; ++i) ck_assert(isnan(x[i])); /* untouched */
        return 0;
    }
    solve(m, f, direct);
    double diff = 0.0, size = 0.0;
    for (int i = 0; i < kN; ++i) diff = fmax(diff, fabs(x[i] - direct[i])), size = fmax(size, fabs(direct[i]));
    ck_assert_double_le(diff, 1e-12 * size);
    return 1;
}

/* A load path's loads: a multiple of one load, a combination of two, of four. */
START_TEST(test_combinations) {
    tridiagonal m;
    make_m(&m);
    double F[4 * kN], f[kN];
    for (int i = 0; i < 4; ++i) load(i, F + i * kN);
    for (int i = 0; i < kN; ++i) f[i] = 1.01 * F[i];
    ck_assert(answered(&m, 1, F, f));
    for (int i = 0; i < kN; ++i) f[i] = 2.0 * F[i] - 0.5 * F[kN + i];
    ck_assert(answered(&m, 2, F, f));
    for (int i = 0; i < kN; ++i) f[i] = 0.3 * F[i] - 0.2 * F[kN + i] + 0.7 * F[2 * kN + i] + 0.1 * F[3 * kN + i];
    ck_assert(answered(&m, 4, F, f));
    for (int i = 0; i < kN; ++i) f[i] = 0.0;
    ck_assert(!answered(&m, 2, F, f)); /* nothing to combine: the solve gives 0 */
}
END_TEST

/* A load off the span by 1e-6 of it, 1e-10, or 1e-13 (within the span's test of fit; the
 * backward error decides: a solve's is about 1e-16); a combination that cancels large terms
 * (loads nearly parallel: the second is the first plus 1e-4 of another); one between them. */
START_TEST(test_left_to_a_solve) {
    tridiagonal m;
    make_m(&m);
    double F[4 * kN], f[kN];
    for (int i = 0; i < 3; ++i) load(i, F + i * kN);
    for (int i = 0; i < kN; ++i) f[i] = F[i] + 1e-6 * F[2 * kN + i];
    ck_assert(!answered(&m, 2, F, f));
    for (int i = 0; i < kN; ++i) f[i] = F[i] + 1e-10 * F[2 * kN + i];
    ck_assert(!answered(&m, 2, F, f));
    for (int i = 0; i < kN; ++i) f[i] = F[i] + 1e-13 * F[2 * kN + i];
    ck_assert(!answered(&m, 2, F, f));
    for (int i = 0; i < kN; ++i) F[kN + i] = F[i] + 1e-4 * F[2 * kN + i];
    for (int i = 0; i < kN; ++i) f[i] = F[i] + 0.01 * F[2 * kN + i]; /* 101 F0 - 100 F1 */
    ck_assert(!answered(&m, 2, F, f));
    for (int i = 0; i < kN; ++i) f[i] = 0.5 * (F[i] + F[kN + i]); /* between them: no cancellation */
    ck_assert(answered(&m, 2, F, f));
}
END_TEST

/* Answers that are not M^-1 of their loads to round-off (solves of another M): the
 * combination is held to the solves behind it, whose backward errors are measured, and is
 * their combination; the right answers give the solve's accuracy. */
START_TEST(test_as_accurate_as_the_solves) {
    tridiagonal m, other;
    make_m(&m);
    make_m(&other);
    for (int j = 0; j < kN; ++j) other.values[other.colptr[j] + (j > 0)] += 0.5;
    for (int j = 0; j < kN; ++j) other.diag[j] += 0.5;
    double F[2 * kN], X[2 * kN], f[kN], x[kN];
    for (int i = 0; i < 2; ++i) load(i, F + i * kN);
    for (int i = 0; i < 2; ++i) solve(&other, F + i * kN, X + i * kN);
    for (int i = 0; i < kN; ++i) f[i] = F[i] + F[kN + i];
    ck_assert_int_eq(frix_testing_load_span(kN, m.colptr, m.rowind, m.values, 2, F, X, f, x), 1);
    for (int i = 0; i < kN; ++i) ck_assert_double_le(fabs(x[i] - (X[i] + X[kN + i])), 1e-12 * fabs(x[i]) + 1e-300);
    ck_assert(answered(&m, 2, F, f));
}
END_TEST

/* The span holds at most four loads: a fifth new direction starts it over from itself. */
/* Many dofs: the coefficients of a combination come from dot products of n terms, whose plain
 * sums are off by about sqrt(n) units of round-off; a multiple of one load of 2^16 dofs is
 * answered as accurately as its solve. */
START_TEST(test_many_dofs) {
    enum { n = 1 << 16 };
    int64_t *colptr = malloc((n + 1) * sizeof(int64_t)), *rowind = malloc(3 * n * sizeof(int64_t));
    double *values = malloc(3 * n * sizeof(double)), *F = malloc(n * sizeof(double)), *X = malloc(n * sizeof(double));
    double *f = malloc(n * sizeof(double)), *x = malloc(n * sizeof(double)), *c = malloc(n * sizeof(double));
    int64_t e = 0;
    for (int j = 0; j < n; ++j) {
        colptr[j] = e;
        for (int i = j - 1; i <= j + 1; ++i)
            if (i >= 0 && i < n) rowind[e] = i, values[e++] = i == j ? 2.5 : -1.0;
    }
    colptr[n] = e;
    for (int i = 0; i < n; ++i) F[i] = 1.0 + 0.5 * sin(0.001 * i);
    /* Thomas, as solve() above, on this M. */
    c[0] = -1.0 / 2.5;
    X[0] = F[0] / 2.5;
    for (int i = 1; i < n; ++i) {
        const double den = 2.5 + c[i - 1];
        c[i] = -1.0 / den;
        X[i] = (F[i] + X[i - 1]) / den;
    }
    for (int i = n - 2; i >= 0; --i) X[i] -= c[i] * X[i + 1];
    for (int i = 0; i < n; ++i) f[i] = 1.01 * F[i];
    ck_assert_int_eq(frix_testing_load_span(n, colptr, rowind, values, 1, F, X, f, x), 1);
    for (int i = 0; i < n; ++i) ck_assert_double_le(fabs(x[i] - 1.01 * X[i]), 1e-14 * fabs(x[i]));
    free(colptr), free(rowind), free(values), free(F), free(X), free(f), free(x), free(c);
}
END_TEST

START_TEST(test_a_full_span_starts_over) {
    tridiagonal m;
    make_m(&m);
    double F[5 * kN], X[5 * kN], f[kN], x[kN];
    for (int i = 0; i < 4; ++i) load(i, F + i * kN);
    for (int i = 0; i < kN; ++i) F[4 * kN + i] = (i % 5 == 0) ? 1.0 : 0.0;
    for (int i = 0; i < 5; ++i) solve(&m, F + i * kN, X + i * kN);
    for (int i = 0; i < kN; ++i) f[i] = F[i] + F[kN + i];
    ck_assert_int_eq(frix_testing_load_span(kN, m.colptr, m.rowind, m.values, 4, F, X, f, x), 1);
    ck_assert_int_eq(frix_testing_load_span(kN, m.colptr, m.rowind, m.values, 5, F, X, f, x), 0);
    for (int i = 0; i < kN; ++i) f[i] = 3.0 * F[4 * kN + i];
    ck_assert_int_eq(frix_testing_load_span(kN, m.colptr, m.rowind, m.values, 5, F, X, f, x), 1);
}
END_TEST

int main(void) {
    Suite *s = suite_create("load_span");
    TCase *tc = tcase_create("load_span");
    tcase_add_test(tc, test_combinations);
    tcase_add_test(tc, test_left_to_a_solve);
    tcase_add_test(tc, test_as_accurate_as_the_solves);
    tcase_add_test(tc, test_many_dofs);
    tcase_add_test(tc, test_a_full_span_starts_over);
    suite_add_tcase(s, tc);
    return frix_run_suite(s);
}
