/* The loads a factorised M was solved for (src/load_span.hpp, through frix_testing_load_span,
 * which presents loads in order as a host's steps): a load in the span of those solved before
 * is answered by the combination of their answers, as accurately as a solve; a load off the
 * span, a combination that cancels large terms, or one less accurate than the solves behind
 * it, is left to a solve; along a line the span follows the loads, so that its combinations
 * stay short. */
#include <frix/frix.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check_main.h"
#include "frix_testing.h"

enum { kN = 300, kMaxLoads = 16 };

/* M: tridiagonal, 2.01 + 0.001 i on the diagonal, -1 beside it (symmetric positive definite,
 * condition number about 3e3), CSC; diag: its diagonal, for solve(). */
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

/* x = M^-1 f for M of n dofs with diag on its diagonal and -1 beside it, by elimination along
 * the diagonal (Thomas); work: n values. */
static void solve_tridiagonal(int n, const double *diag, const double *f, double *x, double *work) {
    work[0] = -1.0 / diag[0];
    x[0] = f[0] / diag[0];
    for (int i = 1; i < n; ++i) {
        const double den = diag[i] + work[i - 1];
        work[i] = -1.0 / den;
        x[i] = (f[i] + x[i - 1]) / den;
    }
    for (int i = n - 2; i >= 0; --i) x[i] -= work[i] * x[i + 1];
}

static void solve(const tridiagonal *m, const double *f, double *x) {
    double work[kN];
    solve_tridiagonal(kN, m->diag, f, x, work);
}

static void load(int kind, double *f) {
    for (int i = 0; i < kN; ++i)
        f[i] = kind == 0   ? sin(0.05 * i) + 0.3
               : kind == 1 ? cos(0.11 * i)
               : kind == 2 ? (double)((i * 7919) % 13) - 6.0
                           : 1.0;
}

/* The k loads F presented in order, each answer given by solve() where the span leaves it;
 * from_span out. Every answer taken from the span is within 1e-12 of a solve's (max norms). */
static void present(const tridiagonal *m, int k, const double *F, int *from_span) {
    static double X[kMaxLoads * kN], answers[kMaxLoads * kN];
    ck_assert_int_le(k, kMaxLoads);
    for (int i = 0; i < k; ++i) solve(m, F + i * kN, X + i * kN);
    frix_testing_load_span(kN, m->colptr, m->rowind, m->values, k, F, X, answers, from_span);
    for (int i = 0; i < k; ++i) {
        double diff = 0.0, size = 0.0;
        for (int j = 0; j < kN; ++j) {
            diff = fmax(diff, fabs(answers[i * kN + j] - X[i * kN + j]));
            size = fmax(size, fabs(X[i * kN + j]));
        }
        ck_assert_double_le(diff, 1e-12 * size);
    }
}

/* Whether the last of the k loads F is answered from the span of those before it. */
static int last_answered(const tridiagonal *m, int k, const double *F) {
    int from_span[kMaxLoads];
    present(m, k, F, from_span);
    return from_span[k - 1];
}

/* A multiple of one load, combinations of two and of four; 0 is left to the solve. */
START_TEST(test_combinations) {
    tridiagonal m;
    make_m(&m);
    double F[5 * kN];
    for (int i = 0; i < 4; ++i) load(i, F + i * kN);
    for (int i = 0; i < kN; ++i) F[kN + i] = 1.01 * F[i];
    ck_assert(last_answered(&m, 2, F));
    load(1, F + kN);
    for (int i = 0; i < kN; ++i) F[2 * kN + i] = 2.0 * F[i] - 0.5 * F[kN + i];
    ck_assert(last_answered(&m, 3, F));
    load(2, F + 2 * kN);
    for (int i = 0; i < kN; ++i) F[4 * kN + i] = 0.3 * F[i] - 0.2 * F[kN + i] + 0.7 * F[2 * kN + i] + 0.1 * F[3 * kN + i];
    int from_span[5];
    present(&m, 5, F, from_span);
    ck_assert_int_eq(from_span[0] + from_span[1] + from_span[2] + from_span[3], 0);
    ck_assert_int_eq(from_span[4], 1);
    for (int i = 0; i < kN; ++i) F[2 * kN + i] = 0.0;
    ck_assert(!last_answered(&m, 3, F));
}
END_TEST

/* A load off the span by 1e-6 of it, 1e-10, or 5e-13 (within the span's test of fit; the
 * backward error decides: a solve's is about 1e-16); a combination that cancels large terms
 * (loads nearly parallel: the second is the first plus 1e-4 of another); one between them. */
START_TEST(test_left_to_a_solve) {
    tridiagonal m;
    make_m(&m);
    double F[3 * kN], g[kN];
    load(0, F);
    load(1, F + kN);
    load(2, g);
    const double off[3] = {1e-6, 1e-10, 5e-13};
    for (int c = 0; c < 3; ++c) {
        for (int i = 0; i < kN; ++i) F[2 * kN + i] = F[i] + off[c] * g[i];
        ck_assert(!last_answered(&m, 3, F));
    }
    for (int i = 0; i < kN; ++i) F[kN + i] = F[i] + 1e-4 * g[i];
    for (int i = 0; i < kN; ++i) F[2 * kN + i] = F[i] + 0.01 * g[i]; /* 101 F0 - 100 F1 */
    ck_assert(!last_answered(&m, 3, F));
    for (int i = 0; i < kN; ++i) F[2 * kN + i] = 0.5 * (F[i] + F[kN + i]); /* between them */
    ck_assert(last_answered(&m, 3, F));
}
END_TEST

/* A host's load path (a FEM block pressed, then pushed sideways a little more each step): loads
 * a + k b / 20, k = 0 .. 15. The first two span the line; far along it their combination
 * cancels more and more, and the span takes a later load in place of the oldest: of the 14
 * later loads, at most 2 are solved. */
START_TEST(test_along_a_line) {
    tridiagonal m;
    make_m(&m);
    double F[kMaxLoads * kN], a[kN], b[kN];
    load(0, a);
    load(1, b);
    for (int k = 0; k < kMaxLoads; ++k)
        for (int i = 0; i < kN; ++i) F[k * kN + i] = a[i] + (k / 20.0) * b[i];
    int from_span[kMaxLoads], solved = 0;
    present(&m, kMaxLoads, F, from_span);
    ck_assert_int_eq(from_span[0] + from_span[1], 0);
    for (int k = 2; k < kMaxLoads; ++k) solved += !from_span[k];
    ck_assert_int_le(solved, 2);
}
END_TEST

/* F: two loads and their sum. */
static void sum_of_two(double *F) {
    load(0, F);
    load(1, F + kN);
    for (int i = 0; i < kN; ++i) F[2 * kN + i] = F[i] + F[kN + i];
}

/* Answers that are not M^-1 of their loads to round-off (solves of another M): a combination is
 * held to the solves behind it, whose backward errors are measured: it is their combination. */
START_TEST(test_as_accurate_as_the_solves) {
    tridiagonal m, other;
    make_m(&m);
    make_m(&other);
    for (int j = 0; j < kN; ++j) {
        other.values[other.colptr[j] + (j > 0)] += 0.5;
        other.diag[j] += 0.5;
    }
    double F[3 * kN], X[3 * kN], answers[3 * kN];
    int from_span[3];
    sum_of_two(F);
    for (int i = 0; i < 3; ++i) solve(&other, F + i * kN, X + i * kN);
    frix_testing_load_span(kN, m.colptr, m.rowind, m.values, 3, F, X, answers, from_span);
    ck_assert_int_eq(from_span[2], 1);
    for (int i = 0; i < kN; ++i)
        ck_assert_double_le(fabs(answers[2 * kN + i] - (X[i] + X[kN + i])), 1e-12 * fabs(answers[2 * kN + i]) + 1e-300);
}
END_TEST

/* An answer that is not finite is not kept: a load that would combine it is solved. */
START_TEST(test_answers_not_finite) {
    tridiagonal m;
    make_m(&m);
    double F[3 * kN], X[3 * kN], answers[3 * kN];
    int from_span[3];
    sum_of_two(F);
    for (int i = 0; i < 3; ++i) solve(&m, F + i * kN, X + i * kN);
    X[kN + 7] = INFINITY;
    frix_testing_load_span(kN, m.colptr, m.rowind, m.values, 3, F, X, answers, from_span);
    ck_assert_int_eq(from_span[2], 0);
    X[kN + 7] = NAN;
    frix_testing_load_span(kN, m.colptr, m.rowind, m.values, 3, F, X, answers, from_span);
    ck_assert_int_eq(from_span[2], 0);
}
END_TEST

/* Through M's load solves: a load that combines one solved with an M since replaced is not
 * answered from the old answer (M's factorisation forgets its loads). M a 3D grid's graph
 * Laplacian plus the identity (its factor several times larger than it), then 2 M. */
START_TEST(test_forgotten_with_m) {
    enum { side = 12, n = side * side * side };
    int64_t *colptr = malloc((n + 1) * sizeof(int64_t)), *rowind = malloc(7 * n * sizeof(int64_t));
    double *val = malloc(7 * n * sizeof(double)), *val2 = malloc(7 * n * sizeof(double));
    double *f = malloc(n * sizeof(double)), *x0 = malloc(n * sizeof(double)), *x1 = malloc(n * sizeof(double));
    int64_t e = 0;
    for (int j = 0; j < n; ++j) {
        colptr[j] = e;
        const int a = j % side, b = (j / side) % side, c = j / (side * side);
        const int nb[7] = {c > 0 ? j - side * side : -1, b > 0 ? j - side : -1, a > 0 ? j - 1 : -1, j,
                           a < side - 1 ? j + 1 : -1, b < side - 1 ? j + side : -1, c < side - 1 ? j + side * side : -1};
        int degree = 0;
        for (int k = 0; k < 7; ++k) degree += nb[k] >= 0 && nb[k] != j;
        for (int k = 0; k < 7; ++k)
            if (nb[k] >= 0) rowind[e] = nb[k], val[e++] = nb[k] == j ? 1.0 + degree : -1.0;
    }
    colptr[n] = e;
    for (int64_t k = 0; k < e; ++k) val2[k] = 2.0 * val[k];
    frix_matrix *M = NULL, *M2 = NULL;
    ck_assert_int_eq(frix_matrix_from_csc(n, n, colptr, rowind, val, &M), FRIX_OK);
    ck_assert_int_eq(frix_matrix_from_csc(n, n, colptr, rowind, val2, &M2), FRIX_OK);
    for (int i = 0; i < n; ++i) f[i] = 1.0 + sin(0.37 * i);
    ck_assert_int_eq(frix_testing_mass_loads(M, M2, f, 1.1, x0, x1), FRIX_OK);
    /* M2^-1 (1.1 f) = 0.55 M^-1 f: within round-off, not the old answer's 1.1 x0. */
    for (int i = 0; i < n; ++i) ck_assert_double_le(fabs(x1[i] - 0.55 * x0[i]), 1e-12 * fabs(x0[i]) + 1e-14);
    frix_matrix_free(M), frix_matrix_free(M2);
    free(colptr), free(rowind), free(val), free(val2), free(f), free(x0), free(x1);
}
END_TEST

/* Many dofs: the coefficients of a combination come from dot products of n terms, whose plain
 * sums are off by about sqrt(n) units of round-off; a multiple of one load of 2^16 dofs is
 * answered as accurately as its solve. */
START_TEST(test_many_dofs) {
    enum { n = 1 << 16 };
    int64_t *colptr = malloc((n + 1) * sizeof(int64_t)), *rowind = malloc(3 * n * sizeof(int64_t));
    double *values = malloc(3 * n * sizeof(double)), *F = malloc(2 * n * sizeof(double));
    double *X = malloc(2 * n * sizeof(double)), *answers = malloc(2 * n * sizeof(double)), *c = malloc(n * sizeof(double));
    double *diag = malloc(n * sizeof(double));
    int64_t e = 0;
    for (int j = 0; j < n; ++j) {
        colptr[j] = e;
        diag[j] = 2.5;
        for (int i = j - 1; i <= j + 1; ++i)
            if (i >= 0 && i < n) rowind[e] = i, values[e++] = i == j ? diag[j] : -1.0;
    }
    colptr[n] = e;
    for (int i = 0; i < n; ++i) F[i] = 1.0 + 0.5 * sin(0.001 * i), F[n + i] = 1.01 * F[i];
    solve_tridiagonal(n, diag, F, X, c);
    for (int i = 0; i < n; ++i) X[n + i] = NAN; /* must not be taken */
    int from_span[2];
    frix_testing_load_span(n, colptr, rowind, values, 2, F, X, answers, from_span);
    ck_assert_int_eq(from_span[1], 1);
    for (int i = 0; i < n; ++i) ck_assert_double_le(fabs(answers[n + i] - 1.01 * X[i]), 1e-14 * fabs(answers[n + i]));
    free(colptr), free(rowind), free(values), free(F), free(X), free(answers), free(c), free(diag);
}
END_TEST

/* The span holds at most four loads: a fifth new direction starts it over from itself. */
START_TEST(test_a_full_span_starts_over) {
    tridiagonal m;
    make_m(&m);
    double F[7 * kN];
    for (int i = 0; i < 4; ++i) load(i, F + i * kN);
    for (int i = 0; i < kN; ++i) F[4 * kN + i] = (i % 5 == 0) ? 1.0 : 0.0;
    for (int i = 0; i < kN; ++i) F[5 * kN + i] = -3.0 * F[4 * kN + i];        /* kept */
    for (int i = 0; i < kN; ++i) F[6 * kN + i] = F[kN + i] + F[2 * kN + i]; /* gone: solved */
    int from_span[7];
    present(&m, 7, F, from_span);
    for (int i = 0; i < 5; ++i) ck_assert_int_eq(from_span[i], 0);
    ck_assert_int_eq(from_span[5], 1);
    ck_assert_int_eq(from_span[6], 0);
}
END_TEST

int main(void) {
    Suite *s = suite_create("load_span");
    TCase *tc = tcase_create("load_span");
    tcase_add_test(tc, test_combinations);
    tcase_add_test(tc, test_left_to_a_solve);
    tcase_add_test(tc, test_along_a_line);
    tcase_add_test(tc, test_as_accurate_as_the_solves);
    tcase_add_test(tc, test_answers_not_finite);
    tcase_add_test(tc, test_forgotten_with_m);
    tcase_add_test(tc, test_many_dofs);
    tcase_add_test(tc, test_a_full_span_starts_over);
    suite_add_tcase(s, tc);
    return frix_run_suite(s);
}
