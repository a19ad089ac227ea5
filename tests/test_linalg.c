/* The linear algebra back-end (src/linalg) through tests/frix_testing.h: UMFPACK with its
 * symbolic analysis reused, CHOLMOD solves and B^T A^-1 B, dense LAPACK LU and Cholesky, and
 * factorisation failures returned as frix_error values. */
#include <frix/frix.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check_main.h"
#include "frix_testing.h"

/* A = [[4, 1, 0], [1, 3, 1], [0, 1, 2]] (SPD), CSC. */
static const int64_t kP[4] = {0, 2, 5, 7};
static const int64_t kI[7] = {0, 1, 0, 1, 2, 1, 2};
static const double kX[7] = {4, 1, 1, 3, 1, 1, 2};
static const double kDense[9] = {4, 1, 0, 1, 3, 1, 0, 1, 2};

static void check_solution(const double *x, double factor) {
    /* A (1, 2, 3) = (6, 10, 8). */
    const double want[3] = {1, 2, 3};
    for (int i = 0; i < 3; ++i) ck_assert_double_eq_tol(x[i], want[i] * factor, 1e-13);
}

START_TEST(sparse_lu_reuses_symbolic) {
    const double b[3] = {6, 10, 8};
    double x[3];
    int64_t sym = 0, num = 0;
    ck_assert_int_eq(frix_testing_sparse_lu(3, kP, kI, kX, b, x, &sym, &num), FRIX_OK);
    check_solution(x, 0.5); /* the second factorisation is of 2A */
    ck_assert_int_eq(sym, 1);
    ck_assert_int_eq(num, 2);
}
END_TEST

START_TEST(sparse_lu_singular_is_an_error) {
    /* [[1, 1], [1, 1]]: the factorisation fails cleanly. */
    const int64_t p[3] = {0, 2, 4}, i[4] = {0, 1, 0, 1};
    const double v[4] = {1, 1, 1, 1}, b[2] = {1, 1};
    double x[2];
    int64_t sym = 0, num = 0;
    ck_assert_int_eq(frix_testing_sparse_lu(2, p, i, v, b, x, &sym, &num), FRIX_ERR_NUMERICAL);
    ck_assert(frix_last_error_message()[0] != '\0');
}
END_TEST

START_TEST(sparse_cholesky_and_congruence) {
    const double b[3] = {6, 10, 8};
    double x[3], C[4];
    /* B = [[1, 0], [0, 0], [0, 1]]: C = B^T A^-1 B = the (0, 2) corner of A^-1. */
    const int64_t bp[3] = {0, 1, 2}, bi[2] = {0, 2};
    const double bx[2] = {1, 1};
    ck_assert_int_eq(frix_testing_sparse_cholesky(3, kP, kI, kX, b, x, 2, bp, bi, bx, C), FRIX_OK);
    check_solution(x, 1.0);
    /* det A = 18; A^-1(0,0) = 5/18, A^-1(2,2) = 11/18, A^-1(0,2) = 1/18. */
    ck_assert_double_eq_tol(C[0], 5.0 / 18.0, 1e-14);
    ck_assert_double_eq_tol(C[3], 11.0 / 18.0, 1e-14);
    ck_assert_double_eq_tol(C[1], 1.0 / 18.0, 1e-14);
    ck_assert_double_eq_tol(C[2], 1.0 / 18.0, 1e-14);
    /* Not positive definite: an error, not a crash. */
    const double neg[7] = {-4, 1, 1, 3, 1, 1, 2};
    ck_assert_int_eq(frix_testing_sparse_cholesky(3, kP, kI, neg, b, x, 0, NULL, NULL, NULL, NULL),
                     FRIX_ERR_NUMERICAL);
}
END_TEST

/* The layout for repeated solves: simplicial on a sparse factor (a chain: tridiag(-1, 4, -1),
 * a few flops per entry of L) and on a dense 120 x 120 (n I + ones: about 2n/3 = 80 flops per
 * entry, below the switch of 150), supernodal on a dense 300 x 300 (200 per entry); the same
 * solutions as the supernodal layout either way. */
START_TEST(sparse_cholesky_layout_for_solves) {
    enum { kLen = 200, kDenseN = 300, kSmallDenseN = 120 };
    static int64_t cp[kDenseN * kDenseN + 1], ci[kDenseN * kDenseN];
    static double cx[kDenseN * kDenseN];
    double b[kDenseN], x0[kDenseN], x1[kDenseN]; /* kDenseN >= kLen */
    for (int shape = 0; shape < 3; ++shape) {
        const int64_t n = shape == 0 ? kLen : shape == 1 ? kDenseN : kSmallDenseN;
        int64_t e = 0;
        for (int64_t j = 0; j < n; ++j) {
            cp[j] = e;
            for (int64_t i = 0; i < n; ++i) {
                if (shape == 0 && (i < j - 1 || i > j + 1)) continue;
                ci[e] = i;
                cx[e++] = shape == 0 ? (i == j ? 4.0 : -1.0) : (i == j ? (double)n + 1.0 : 1.0);
            }
            b[j] = 1.0 + (double)(j % 7);
        }
        cp[n] = e;
        int super0 = -1, super1 = -1;
        ck_assert_int_eq(frix_testing_sparse_cholesky_layout(0, n, cp, ci, cx, b, x0, &super0), FRIX_OK);
        ck_assert_int_eq(frix_testing_sparse_cholesky_layout(1, n, cp, ci, cx, b, x1, &super1), FRIX_OK);
        ck_assert_int_eq(super0, 1);
        ck_assert_int_eq(super1, shape == 1);
        for (int64_t i = 0; i < n; ++i) ck_assert_double_eq_tol(x1[i], x0[i], 1e-12 * fabs(x0[i]));
    }
}
END_TEST

/* The threads of this process, from /proc/self/status (-1 where there is none). */
static int process_threads(void) {
    FILE *f = fopen("/proc/self/status", "r");
    if (!f) return -1;
    char line[256];
    int threads = -1;
    while (fgets(line, sizeof line, f))
        if (strncmp(line, "Threads:", 8) == 0) threads = atoi(line + 8);
    fclose(f);
    return threads;
}

/* A supernodal factorisation of a 200 x 200 matrix (n I + ones: one supernode of 200
 * columns) starts no thread: CHOLMOD's OpenMP loops, which would otherwise start 3 threads
 * whatever OMP_NUM_THREADS says, run on the calling thread. */
START_TEST(sparse_cholesky_starts_no_thread) {
    enum { kN = 200 };
    static int64_t cp[kN + 1], ci[kN * kN];
    static double cx[kN * kN];
    double b[kN], x[kN];
    int64_t e = 0;
    for (int64_t j = 0; j < kN; ++j) {
        cp[j] = e;
        for (int64_t i = 0; i < kN; ++i) {
            ci[e] = i;
            cx[e++] = i == j ? (double)kN + 1.0 : 1.0;
        }
        b[j] = 1.0;
    }
    cp[kN] = e;
    /* The BLAS library's own threads, if it has any, are started first: they are its
     * business (OPENBLAS_NUM_THREADS), not CHOLMOD's. */
    static double dense[kN * kN];
    for (int64_t k = 0; k < kN * kN; ++k) dense[k] = cx[k];
    ck_assert_int_eq(frix_testing_dense_solve(1, kN, dense, b, x), FRIX_OK);
    const int before = process_threads();
    int super = -1;
    ck_assert_int_eq(frix_testing_sparse_cholesky_layout(0, kN, cp, ci, cx, b, x, &super), FRIX_OK);
    ck_assert_int_eq(super, 1);
    /* (n I + ones) x = ones: x = 1 / (2n) everywhere. */
    for (int64_t i = 0; i < kN; ++i) ck_assert_double_eq_tol(x[i], 1.0 / (2.0 * kN), 1e-14);
    if (before > 0) ck_assert_int_eq(process_threads(), before);
}
END_TEST

/* A: two components, a 12 x 12 grid (5-point Laplacian plus 0.5 I, whose factor is a tree of
 * several supernodes) and a chain of 20 (tridiag(-1, 4, -1)); CSC, both triangles. B (164 x 12,
 * 4 contacts of 3 columns): contact 0 on the grid, contact 1 on the chain, contact 2 on both,
 * contact 3 on the grid but for its middle column, which is zero. */
enum { kGrid = 12, kChain = 20, kN = kGrid * kGrid + kChain, kK = 12 };
typedef struct {
    int64_t ap[kN + 1], ai[5 * kN];
    double ax[5 * kN];
    int64_t bp[kK + 1], bi[2 * kK];
    double bx[2 * kK];
} CongruenceCase;

static void build_congruence_case(CongruenceCase *c) {
    int64_t e = 0;
    for (int j = 0; j < kN; ++j) {
        c->ap[j] = e;
        int neighbours[5], count = 0;
        if (j < kGrid * kGrid) {
            const int x = j % kGrid, y = j / kGrid;
            if (y > 0) neighbours[count++] = j - kGrid;
            if (x > 0) neighbours[count++] = j - 1;
            neighbours[count++] = j;
            if (x + 1 < kGrid) neighbours[count++] = j + 1;
            if (y + 1 < kGrid) neighbours[count++] = j + kGrid;
        } else {
            if (j > kGrid * kGrid) neighbours[count++] = j - 1;
            neighbours[count++] = j;
            if (j + 1 < kN) neighbours[count++] = j + 1;
        }
        for (int t = 0; t < count; ++t) {
            c->ai[e] = neighbours[t];
            c->ax[e++] = neighbours[t] == j ? 4.5 : -1.0;
        }
    }
    c->ap[kN] = e;
    /* Rows of each column's two entries (-1: none). */
    const int chain = kGrid * kGrid;
    const int rows[kK][2] = {{0, 13}, {40, 41}, {77, 90},            /* contact 0: grid */
                             {chain, chain + 1}, {chain + 7, -1}, {chain + 19, -1}, /* 1: chain */
                             {5, chain + 3}, {143, -1}, {chain + 12, -1},     /* 2: both */
                             {60, 61}, {-1, -1}, {130, 100}};                 /* 3: grid, zero column */
    e = 0;
    for (int j = 0; j < kK; ++j) {
        c->bp[j] = e;
        int r0 = rows[j][0], r1 = rows[j][1];
        if (r1 >= 0 && r1 < r0) { const int t = r0; r0 = r1; r1 = t; }
        if (r0 >= 0) { c->bi[e] = r0; c->bx[e++] = 1.0 + 0.25 * j; }
        if (r1 >= 0) { c->bi[e] = r1; c->bx[e++] = -0.5 + 0.125 * j; }
    }
    c->bp[kK] = e;
}

/* C = B^T A^-1 B by dense solves, column-major. */
static void dense_congruence(const CongruenceCase *c, double *C) {
    static double A[kN * kN], b[kN], x[kN];
    memset(A, 0, sizeof A);
    for (int j = 0; j < kN; ++j)
        for (int64_t e = c->ap[j]; e < c->ap[j + 1]; ++e) A[c->ai[e] + kN * j] = c->ax[e];
    for (int j = 0; j < kK; ++j) {
        memset(b, 0, sizeof b);
        for (int64_t e = c->bp[j]; e < c->bp[j + 1]; ++e) b[c->bi[e]] = c->bx[e];
        ck_assert_int_eq(frix_testing_dense_solve(1, kN, A, b, x), FRIX_OK);
        for (int i = 0; i < kK; ++i) {
            double s = 0.0;
            for (int64_t e = c->bp[i]; e < c->bp[i + 1]; ++e) s += c->bx[e] * x[c->bi[e]];
            C[i + kK * j] = s;
        }
    }
}

/* Columns i and j share a component of A (the zero column shares none). */
static int coupled(int i, int j) {
    static const int on_grid[kK] = {1, 1, 1, 0, 0, 0, 1, 1, 0, 1, 0, 1};
    static const int on_chain[kK] = {0, 0, 0, 1, 1, 1, 1, 0, 1, 0, 0, 0};
    return (on_grid[i] && on_grid[j]) || (on_chain[i] && on_chain[j]);
}

static void check_congruence(const double *C, const double *want) {
    double scale = 0.0;
    for (int i = 0; i < kK * kK; ++i) scale = fmax(scale, fabs(want[i]));
    ck_assert(scale > 0.0);
    for (int i = 0; i < kK; ++i)
        for (int j = 0; j < kK; ++j) {
            ck_assert_double_eq_tol(C[i + kK * j], want[i + kK * j], 1e-13 * scale);
            /* symmetric to the bit; nothing between columns no component couples */
            ck_assert(memcmp(&C[i + kK * j], &C[j + kK * i], sizeof(double)) == 0);
            if (!coupled(i, j)) ck_assert(C[i + kK * j] == 0.0);
        }
}

/* The price of a factorisation before it is paid: L of a tridiagonal matrix of size 10 has
 * 19 entries, of a dense one of size 6 has 21; the dense one costs more flops per entry. */
START_TEST(cholesky_cost_from_the_pattern) {
    int64_t tp[11], ti[30], e = 0;
    for (int j = 0; j < 10; ++j) {
        tp[j] = e;
        for (int i = j - 1; i <= j + 1; ++i)
            if (i >= 0 && i < 10) ti[e++] = i;
    }
    tp[10] = e;
    double flops = 0.0, entries = 0.0;
    ck_assert_int_eq(frix_testing_cholesky_cost(10, tp, ti, &flops, &entries), FRIX_OK);
    ck_assert_double_eq(entries, 19.0);
    ck_assert_double_gt(flops, 0.0);
    const double tridiagonal_ratio = flops / entries;
    int64_t dp[7], di[21];
    e = 0;
    for (int j = 0; j < 6; ++j) {  /* the upper triangle only */
        dp[j] = e;
        for (int i = 0; i <= j; ++i) di[e++] = i;
    }
    dp[6] = e;
    ck_assert_int_eq(frix_testing_cholesky_cost(6, dp, di, &flops, &entries), FRIX_OK);
    ck_assert_double_eq(entries, 21.0);
    ck_assert_double_gt(flops / entries, tridiagonal_ratio);
    /* W with every 3x3 block of 6 contacts, priced in closed form: 27 times the flops and 9
     * times the entries of the analysis of the dense 6 x 6 pattern just above. */
    const double dense_flops = flops;
    static int64_t wp[19], wi[18 * 18];
    static double wx[18 * 18];
    e = 0;
    for (int j = 0; j < 18; ++j) {
        wp[j] = e;
        for (int i = 0; i < 18; ++i) {
            wi[e] = i;
            wx[e++] = i == j ? 10.0 : 1.0;
        }
    }
    wp[18] = e;
    ck_assert_int_eq(frix_testing_block_cholesky_cost(18, wp, wi, wx, &flops, &entries), FRIX_OK);
    ck_assert_double_eq(flops, 27.0 * dense_flops);
    ck_assert_double_eq(entries, 9.0 * 21.0);
    /* No rows: nothing to pay. */
    const int64_t zp[1] = {0};
    ck_assert_int_eq(frix_testing_cholesky_cost(0, zp, NULL, &flops, &entries), FRIX_OK);
    ck_assert_double_eq(flops, 0.0);
}
END_TEST

/* A mesh-like SPD matrix: G x G x G nodes, 3 dofs each, every dof coupled with every dof of
 * the nodes around its node (as trilinear hexahedra couple them), diagonally dominant. */
enum { kG = 14, kMeshDofs = 3 * kG * kG * kG };
static void mesh_matrix(int64_t *colptr, int64_t *rowind, double *values) {
    int64_t e = 0;
    for (int64_t j = 0; j < kMeshDofs; ++j) {
        const int64_t node = j / 3, x = node % kG, y = node / kG % kG, z = node / (kG * kG);
        colptr[j] = e;
        for (int64_t dz = -1; dz <= 1; ++dz)
            for (int64_t dy = -1; dy <= 1; ++dy)
                for (int64_t dx = -1; dx <= 1; ++dx) {
                    const int64_t X = x + dx, Y = y + dy, Z = z + dz;
                    if (X < 0 || Y < 0 || Z < 0 || X >= kG || Y >= kG || Z >= kG) continue;
                    for (int64_t c = 0; c < 3; ++c) {
                        const int64_t i = 3 * (X + kG * (Y + kG * Z)) + c;
                        rowind[e] = i;
                        values[e++] = i == j ? 100.0 : -0.5 / (double)(1 + (i + j) % 3);
                    }
                }
        /* rows ascending: the loops above visit neighbours in increasing index order */
    }
    colptr[kMeshDofs] = e;
}

/* Prices of factorisations against the work they do, on fixed inputs (no timing): the price a
 * Cholesky asks its budget with is cholesky_cost's count of the same pattern (one analysis
 * rule for both: on a large mesh nested dissection, where AMD's ordering costs several times
 * more);
 * a large LU is priced by the count of its symmetrised pattern, within 2x of what UMFPACK then
 * does (its own estimate is a bound many times above it). */
START_TEST(factor_prices_match_the_work) {
    static int64_t colptr[kMeshDofs + 1], rowind[kMeshDofs * 81];
    static double values[kMeshDofs * 81];
    mesh_matrix(colptr, rowind, values);
    double cholesky_price = 0.0, cholesky_count = 0.0, lu_price = 0.0, lu_done = 0.0;
    int lu_upper = -1;
    ck_assert_int_eq(frix_testing_factor_prices(kMeshDofs, colptr, rowind, values, &cholesky_price,
                                                &cholesky_count, &lu_price, &lu_upper, &lu_done),
                     FRIX_OK);
    ck_assert_double_gt(cholesky_price, 1e8);
    ck_assert_double_eq_tol(cholesky_count, cholesky_price, 1e-12 * cholesky_price);
    ck_assert_int_eq(lu_upper, 0);
    ck_assert_double_gt(lu_done, 1e8);
    ck_assert_double_le(lu_price, 2.0 * lu_done);
    ck_assert_double_ge(lu_price, 0.5 * lu_done);
}
END_TEST

/* The ordering of a Cholesky: METIS's nested dissection only where it pays for its own time.
 * On the trilinear mesh AMD's factor does more flops per vertex and edge of the nodes' graph
 * than METIS takes, and the analysis keeps METIS's fewer flops; on a 7-point grid of one dof a
 * node AMD's factor is cheap beside that graph (though CHOLMOD's own test would try METIS) and
 * AMD's analysis is kept. */
START_TEST(nested_dissection_only_where_it_pays) {
    static int64_t colptr[kMeshDofs + 1], rowind[kMeshDofs * 81];
    static double values[kMeshDofs * 81];
    mesh_matrix(colptr, rowind, values);
    double flops = 0.0, entries = 0.0, amd_flops = 0.0, amd_entries = 0.0;
    ck_assert_int_eq(frix_testing_cholesky_cost(kMeshDofs, colptr, rowind, &flops, &entries), FRIX_OK);
    ck_assert_int_eq(frix_testing_amd_cholesky_cost(kMeshDofs, colptr, rowind, &amd_flops, &amd_entries), FRIX_OK);
    ck_assert_double_lt(flops, 0.75 * amd_flops);
    /* 25^3 nodes, upper triangle of the 7-point stencil */
    enum { kS = 25, kGridDofs = kS * kS * kS };
    static int64_t gp[kGridDofs + 1], gi[4 * kGridDofs];
    int64_t e = 0;
    for (int64_t j = 0; j < kGridDofs; ++j) {
        gp[j] = e;
        const int64_t x = j % kS, y = j / kS % kS, z = j / (kS * kS);
        if (z > 0) gi[e++] = j - kS * kS;
        if (y > 0) gi[e++] = j - kS;
        if (x > 0) gi[e++] = j - 1;
        gi[e++] = j;
    }
    gp[kGridDofs] = e;
    ck_assert_int_eq(frix_testing_cholesky_cost(kGridDofs, gp, gi, &flops, &entries), FRIX_OK);
    ck_assert_int_eq(frix_testing_amd_cholesky_cost(kGridDofs, gp, gi, &amd_flops, &amd_entries), FRIX_OK);
    /* CHOLMOD's test for trying METIS holds (flops per entry of L, entries of L per entry of A) */
    ck_assert_double_ge(amd_flops, 500.0 * amd_entries);
    ck_assert_double_ge(amd_entries, 5.0 * (double)e);
    ck_assert_double_eq(flops, amd_flops);
    ck_assert_double_eq(entries, amd_entries);
}
END_TEST

/* A single-precision copy of a supernodal factor: on a 3D 7-point grid (18^3, diagonal 6.5:
 * condition about 20; supernodes both below and above the size solved without the BLAS) its
 * solve agrees with the double one to single precision, and is not the double one, in units
 * scaled past single precision's range too; a budget that refuses the copy's bytes leaves none
 * (and its solve fails); a new factorisation drops it. */
START_TEST(single_precision_copy_of_a_factor) {
    enum { kS = 18, kDofs = kS * kS * kS };
    static int64_t gp[kDofs + 1], gi[4 * kDofs];
    static double gx[4 * kDofs], b[kDofs], xs[kDofs], xd[kDofs];
    int64_t e = 0;
    for (int64_t j = 0; j < kDofs; ++j) {
        gp[j] = e;
        const int64_t x = j % kS, y = j / kS % kS, z = j / (kS * kS);
        if (z > 0) gi[e] = j - kS * kS, gx[e++] = -1.0;
        if (y > 0) gi[e] = j - kS, gx[e++] = -1.0;
        if (x > 0) gi[e] = j - 1, gx[e++] = -1.0;
        gi[e] = j, gx[e++] = 6.5;
        b[j] = 1.0 + (double)(j % 11) - 0.3 * (double)(j % 5);
    }
    gp[kDofs] = e;
    /* refused; then A and b in units scaled by 1, 1e150 and 1e-150 (past single precision's range) */
    const double scales[4] = {1.0, 1.0, 1e150, 1e-150};
    for (int k = 0; k < 4; ++k) {
        const int refuse = k == 0;
        static double sx[4 * kDofs], sb[kDofs];
        for (int64_t e2 = 0; e2 < e; ++e2) sx[e2] = gx[e2] * scales[k];
        for (int64_t i = 0; i < kDofs; ++i) sb[i] = b[i] * scales[k];
        int kept = -1, dropped = -1;
        ck_assert_int_eq(frix_testing_single_cholesky(kDofs, gp, gi, sx, sb, refuse, xs, xd, &kept, &dropped),
                         FRIX_OK);
        ck_assert_int_eq(kept, !refuse);
        if (refuse) continue;
        ck_assert_int_eq(dropped, 1);
        double diff = 0.0, norm = 0.0;
        for (int64_t i = 0; i < kDofs; ++i) diff += (xs[i] - xd[i]) * (xs[i] - xd[i]), norm += xd[i] * xd[i];
        ck_assert_double_lt(sqrt(diff / norm), 1e-5);
        ck_assert_double_gt(sqrt(diff / norm), 1e-12);
    }
}
END_TEST

/* The price of forming W = H^T M^-1 H counts, besides its flops, the entries it writes outside
 * the BLAS: W's 9 per block (first touched) and those of the terms summed into them (the lower
 * part of X^T X per supernode of M's factor, X the rows of L^-1 P H there). Fixed inputs, no
 * timing. */
START_TEST(w_price_counts_its_writes) {
    /* A dense M (one supernode) and 2 contacts on it: one term of 6 columns, 21 entries. */
    enum { kDofs = 6, kCols = 6 };
    int64_t mp[kDofs + 1], mi[kDofs * kDofs], hp[kCols + 1], hi[kDofs * kCols];
    double mx[kDofs * kDofs], hx[kDofs * kCols];
    for (int64_t j = 0; j <= kDofs; ++j) mp[j] = hp[j] = kDofs * j;
    for (int64_t j = 0; j < kDofs; ++j)
        for (int64_t i = 0; i < kDofs; ++i) {
            mi[kDofs * j + i] = hi[kDofs * j + i] = i;
            mx[kDofs * j + i] = i == j ? 10.0 : 1.0;
            hx[kDofs * j + i] = 1.0 + (double)((i + 2 * j) % 5);
        }
    double flops = 0.0, writes = 0.0;
    int64_t blocks = 0;
    ck_assert_int_eq(frix_testing_w_price(kDofs, mp, mi, mx, kCols, hp, hi, hx, &flops, &writes, &blocks), FRIX_OK);
    ck_assert_int_eq(blocks, 4);
    ck_assert_double_eq(writes, 9.0 * 4 + 6.0 * 7.0 / 2.0);
    /* the triangular solve with the 6 x 6 diagonal block for 6 columns, then X^T X */
    ck_assert_double_eq(flops, 6.0 * 36.0 + 36.0 * 6.0);
    /* The mesh with its bottom face's nodes in contact: W dense; every column reaches the
     * root, whose term alone has k (k + 1) / 2 entries; the separators below take fewer
     * columns each, a few times the root's entries in all. */
    static int64_t colptr[kMeshDofs + 1], rowind[kMeshDofs * 81];
    static double values[kMeshDofs * 81];
    mesh_matrix(colptr, rowind, values);
    enum { kFace = kG * kG, kFaceCols = 3 * kFace };
    static int64_t fp[kFaceCols + 1], fi[kFaceCols];
    static double fx[kFaceCols];
    for (int64_t j = 0; j < kFaceCols; ++j) {
        fp[j] = j;
        fi[j] = j; /* node j / 3 of the face z = 0, dof j % 3 */
        fx[j] = 1.0;
    }
    fp[kFaceCols] = kFaceCols;
    ck_assert_int_eq(frix_testing_w_price(kMeshDofs, colptr, rowind, values, kFaceCols, fp, fi, fx, &flops, &writes,
                                          &blocks),
                     FRIX_OK);
    ck_assert_int_eq(blocks, (int64_t)kFace * kFace);
    const double stored = 9.0 * (double)blocks, root = (double)kFaceCols * (kFaceCols + 1.0) / 2.0;
    ck_assert_double_ge(writes - stored, root);
    ck_assert_double_le(writes - stored, 4.0 * root);
    /* A time limit prices the writes: 1e12 of them overrun a second at any rate a machine
     * writes (forming W's 1e12 entries takes tens of minutes), without a flop; 1e3 fit without
     * timing the machine. */
    ck_assert_int_eq(frix_testing_affords(0.0, 1e12, 1.0), FRIX_STATUS_TIME_LIMIT);
    ck_assert_int_eq(frix_testing_affords(0.0, 1e3, 1.0), FRIX_STATUS_NOT_RUN);
    ck_assert_int_eq(frix_testing_affords(1e3, 0.0, 1.0), FRIX_STATUS_NOT_RUN);
}
END_TEST

/* A Newton (v, r) Jacobian's pattern, [[K, -H], [H^T, D]] with K the mesh and H the face
 * z = 0's dofs: analysed where every contact is open (D = I: UMFPACK's symmetric strategy),
 * then factorised where they all stick (D = 0: the contact rows pivot off the diagonal). Here
 * the symmetric strategy keeps to its count (no second analysis); told to leave it above half
 * its count, the next factorisation is analysed again for the unsymmetric strategy and gives
 * the same answer. (On the soft grids of notes/2026-11-28-gnsn-ac-first-step.md, 50 x 50 x 4
 * and larger, the default 1.5 is passed; they take seconds.) */
static void saddle_solve(double excess, int64_t *symbolic, double *flops) {
    enum { kFace = kG * kG, kFaceCols = 3 * kFace, kSize = kMeshDofs + kFaceCols };
    static int64_t mp[kMeshDofs + 1], mi[kMeshDofs * 81], colptr[kSize + 1], rowind[kMeshDofs * 82 + 2 * kFaceCols];
    static double mx[kMeshDofs * 81], open[kMeshDofs * 82 + 2 * kFaceCols], stick[kMeshDofs * 82 + 2 * kFaceCols];
    static double b[kSize], x[kSize], Ax[kSize];
    mesh_matrix(mp, mi, mx);
    int64_t e = 0;
    for (int64_t j = 0; j < kSize; ++j) {
        colptr[j] = e;
        if (j < kMeshDofs) {
            for (int64_t p = mp[j]; p < mp[j + 1]; ++p) rowind[e] = mi[p], open[e] = stick[e] = mx[p], ++e;
            if (j < kFaceCols) rowind[e] = kMeshDofs + j, open[e] = stick[e] = 1.0, ++e; /* H^T */
        } else {
            rowind[e] = j - kMeshDofs, open[e] = stick[e] = -1.0, ++e; /* -H */
            rowind[e] = j, open[e] = 1.0, stick[e] = 0.0, ++e;         /* D */
        }
    }
    colptr[kSize] = e;
    for (int64_t i = 0; i < kSize; ++i) b[i] = 1.0 + (double)(i % 7);
    ck_assert_int_eq(frix_testing_lu_strategy(kSize, colptr, rowind, open, stick, excess, b, x, symbolic, flops),
                     FRIX_OK);
    for (int64_t i = 0; i < kSize; ++i) Ax[i] = 0.0;
    for (int64_t j = 0; j < kSize; ++j)
        for (int64_t p = colptr[j]; p < colptr[j + 1]; ++p) Ax[rowind[p]] += stick[p] * x[j];
    double worst = 0.0;
    for (int64_t i = 0; i < kSize; ++i) worst = fmax(worst, fabs(Ax[i] - b[i]) / 7.0);
    ck_assert_double_le(worst, 1e-9);
}

START_TEST(lu_leaves_the_symmetric_strategy_where_it_pivots_off_the_diagonal) {
    int64_t symbolic = 0;
    double flops[3] = {0, 0, 0};
    saddle_solve(1.5, &symbolic, flops);
    ck_assert_int_eq(symbolic, 1);
    ck_assert_double_eq(flops[2], flops[1]);
    const double symmetric = flops[1];
    /* Half the count is passed by the first factorisation already: the two after it are the
     * unsymmetric strategy's. */
    saddle_solve(0.5, &symbolic, flops);
    ck_assert_int_eq(symbolic, 2);
    ck_assert_double_eq(flops[2], flops[1]);
    ck_assert_double_ne(flops[1], symmetric);
}
END_TEST

START_TEST(congruence_up_the_supernodal_tree) {
    static CongruenceCase c;
    build_congruence_case(&c);
    static double want[kK * kK], C[kK * kK], again[kK * kK];
    dense_congruence(&c, want);
    int questions = -1, stopped = -1;
    int64_t nnz = -1;
    /* Asked at the default pace: this small case is done before the first question. */
    ck_assert_int_eq(frix_testing_congruence_questions(kN, c.ap, c.ai, c.ax, kK, c.bp, c.bi, c.bx, 32, 2e7, 0, C,
                                                       &questions, &stopped, &nnz),
                     FRIX_OK);
    check_congruence(C, want);
    ck_assert_int_eq(questions, 0);
    ck_assert_int_eq(stopped, 0);
    /* C's pattern: the grid's 7 columns with each other, the chain's 5 (one of them shared). */
    ck_assert_int_eq(nnz, 7 * 7 + 5 * 5 - 1);
    /* Asked after every supernode with work: the same bits, and at least the question
     * between the two components. */
    ck_assert_int_eq(frix_testing_congruence_questions(kN, c.ap, c.ai, c.ax, kK, c.bp, c.bi, c.bx, 1e9, 0.0, 0, again,
                                                       &questions, &stopped, &nnz),
                     FRIX_OK);
    ck_assert(questions >= 1);
    ck_assert_int_eq(stopped, 0);
    ck_assert(memcmp(C, again, sizeof C) == 0);
    /* Told to stop at the first question: it stops there, with nothing returned. */
    ck_assert_int_eq(frix_testing_congruence_questions(kN, c.ap, c.ai, c.ax, kK, c.bp, c.bi, c.bx, 1e9, 0.0, 1, again,
                                                       &questions, &stopped, &nnz),
                     FRIX_OK);
    ck_assert_int_eq(questions, 1);
    ck_assert_int_eq(stopped, 1);
    ck_assert_int_eq(nnz, 0);
    /* The reduction's W, summed into 3x3 blocks: the same values, and the blocks of contacts
     * sharing a component: {0, 2, 3} on the grid, {1, 2} on the chain. */
    int64_t blocks = -1;
    ck_assert_int_eq(frix_testing_reduction(kN, c.ap, c.ai, c.ax, kK, c.bp, c.bi, c.bx, again, &blocks), FRIX_OK);
    check_congruence(again, want);
    ck_assert_int_eq(blocks, 3 * 3 + 2 * 2 - 1);
}
END_TEST

START_TEST(dense_lu_and_cholesky) {
    const double b[3] = {6, 10, 8};
    double x[3];
    ck_assert_int_eq(frix_testing_dense_solve(0, 3, kDense, b, x), FRIX_OK);
    check_solution(x, 1.0);
    ck_assert_int_eq(frix_testing_dense_solve(1, 3, kDense, b, x), FRIX_OK);
    check_solution(x, 1.0);
    const double singular[4] = {1, 2, 2, 4}, b2[2] = {1, 1};
    ck_assert_int_eq(frix_testing_dense_solve(0, 2, singular, b2, x), FRIX_ERR_NUMERICAL);
    ck_assert_int_eq(frix_testing_dense_solve(1, 2, singular, b2, x), FRIX_ERR_NUMERICAL);
}
END_TEST

int main(void) {
    Suite *s = suite_create("linalg");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, sparse_lu_reuses_symbolic);
    tcase_add_test(tc, sparse_lu_singular_is_an_error);
    tcase_add_test(tc, sparse_cholesky_and_congruence);
    tcase_add_test(tc, sparse_cholesky_layout_for_solves);
    tcase_add_test(tc, sparse_cholesky_starts_no_thread);
    tcase_add_test(tc, congruence_up_the_supernodal_tree);
    tcase_add_test(tc, dense_lu_and_cholesky);
    tcase_add_test(tc, cholesky_cost_from_the_pattern);
    tcase_add_test(tc, factor_prices_match_the_work);
    tcase_add_test(tc, nested_dissection_only_where_it_pays);
    tcase_add_test(tc, single_precision_copy_of_a_factor);
    tcase_add_test(tc, w_price_counts_its_writes);
    tcase_add_test(tc, lu_leaves_the_symmetric_strategy_where_it_pivots_off_the_diagonal);
    suite_add_tcase(s, tc);
    return frix_run_suite(s);
}
