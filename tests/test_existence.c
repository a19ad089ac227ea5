/* The existence check (frix_problem_check_existence): problems whose best margin
 * t* = sup{t : some z has W z + q - t e in K*} is known in closed form (a body squeezed
 * between two walls, a chain of bodies between two walls, one contact that cannot move
 * along its normal), in local and global form; real FCLIB problems; bad input; and the
 * existence line of `frix solve` when a solve fails. */
#define _POSIX_C_SOURCE 200809L

#include <frix/frix.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check_main.h"
#include "cli_runner.h"
#include "frix_testing.h"
#include "shared_data.h"

typedef struct {
    frix_existence verdict;
    double margin;
} verdict;

static verdict check_with(const frix_problem *p, double time_limit) {
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_msg(frix_problem_check_existence(p, time_limit, info) == FRIX_OK, "%s",
                  frix_last_error_message());
    int64_t v = -1;
    verdict out;
    ck_assert_int_eq(frix_info_get_int(info, FRIX_INFO_EXISTENCE, &v), FRIX_OK);
    ck_assert_int_eq(frix_info_get_double(info, FRIX_INFO_EXISTENCE_MARGIN, &out.margin), FRIX_OK);
    out.verdict = (frix_existence)v;
    frix_info_free(info);
    return out;
}

static verdict check(const frix_problem *p) { return check_with(p, 0.0); }

/* The root mean square over contacts of |b_a|: what margins are relative to. */
static double contact_rms(const double *b, int nc) {
    double s = 0.0;
    for (int i = 0; i < 3 * nc; ++i) s += b[i] * b[i];
    return sqrt(s / nc);
}

static void expect_guaranteed(verdict v, double best_relative_margin) {
    ck_assert_msg(v.verdict == FRIX_EXISTENCE_GUARANTEED, "verdict %s (margin %g)",
                  frix_existence_describe(v.verdict), v.margin);
    /* A witness clears the cone by its margin, which no witness can exceed. */
    ck_assert_msg(v.margin > 0.0 && v.margin <= best_relative_margin * (1 + 1e-12),
                  "margin %.17g, best %.17g", v.margin, best_relative_margin);
}

/* A certificate bounds the best margin from above; these ones are (nearly) exact. */
static void expect_doubtful(verdict v, double best_relative_margin) {
    ck_assert_msg(v.verdict == FRIX_EXISTENCE_DOUBTFUL, "verdict %s (margin %g)",
                  frix_existence_describe(v.verdict), v.margin);
    ck_assert_msg(v.margin < 0.0 && fabs(v.margin - best_relative_margin) <= 1e-5 * fabs(best_relative_margin),
                  "margin %.17g, best %.17g", v.margin, best_relative_margin);
}

/* ---- One body (one dof along the normal, M = 1) squeezed between two walls: contact 1
 * has u_N = v + w_N1, contact 2 the opposite normal, u_N = -v + w_N2; tangential velocities
 * are w_T. t* = (w_N1 + w_N2 - mu |w_T1| - mu |w_T2|) / 2. */

static double walls_best_margin(const double w[6], double mu) {
    return (w[0] + w[3] - mu * hypot(w[1], w[2]) - mu * hypot(w[4], w[5])) / 2 / contact_rms(w, 2);
}

static verdict walls_global(const double w[6], double mu_value) {
    const double one = 1.0, H_row[6] = {1, 0, 0, -1, 0, 0}, f = 0.0, mu[2] = {mu_value, mu_value};
    frix_matrix *M = NULL, *H = NULL;
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_matrix_from_dense(1, 1, &one, 1, &M), FRIX_OK);
    ck_assert_int_eq(frix_matrix_from_dense(1, 6, H_row, 1, &H), FRIX_OK);
    ck_assert_int_eq(frix_problem_global(M, H, &f, w, mu, 2, &p), FRIX_OK);
    verdict v = check(p);
    frix_problem_free(p);
    frix_matrix_free(H);
    frix_matrix_free(M);
    return v;
}

/* The same in local form: W = H^T M^-1 H (rank 1: the two normals only), q = w (f = 0). */
static const double kWallsW[36] = {1, 0, 0, -1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
                                   -1, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};

static frix_problem *walls_local_scaled(const double *q, const double *mu, double W_scale,
                                        frix_matrix **W) {
    double scaled[36];
    for (int i = 0; i < 36; ++i) scaled[i] = W_scale * kWallsW[i];
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_matrix_from_dense(6, 6, scaled, 6, W), FRIX_OK);
    ck_assert_int_eq(frix_problem_local(*W, q, mu, 2, &p), FRIX_OK);
    return p;
}

static frix_problem *walls_local(const double *q, const double *mu, frix_matrix **W) {
    return walls_local_scaled(q, mu, 1.0, W);
}

/* q and W scaled by q_scale and W_scale: margins are relative, the verdict is the same. */
static verdict walls_local_check_scaled(const double q[6], double mu_value, double q_scale,
                                        double W_scale) {
    const double mu[2] = {mu_value, mu_value};
    double qs[6];
    for (int i = 0; i < 6; ++i) qs[i] = q_scale * q[i];
    frix_matrix *W = NULL;
    frix_problem *p = walls_local_scaled(qs, mu, W_scale, &W);
    verdict v = check(p);
    frix_problem_free(p);
    frix_matrix_free(W);
    return v;
}

static verdict walls_local_check(const double q[6], double mu_value) {
    return walls_local_check_scaled(q, mu_value, 1.0, 1.0);
}

START_TEST(test_walls_global) {
    const double squeezed[6] = {-1, 0, 0, -1, 0, 0}; /* t* = -1, |w| per contact 1 */
    expect_doubtful(walls_global(squeezed, 0.5), -1.0);
    const double open[6] = {-1, 0, 0, 1.5, 0, 0}; /* t* = 0.25 */
    expect_guaranteed(walls_global(open, 0.5), walls_best_margin(open, 0.5));
    /* Tangential velocities eat into the margin: mu |w_T| = 0.4, then 0.7. */
    /* On the boundary: t* = 0, no strictly feasible point (though v = 1 solves it). */
    const double touching[6] = {-1, 0, 0, 1, 0, 0};
    verdict v = walls_global(touching, 0.5);
    ck_assert_msg(v.verdict == FRIX_EXISTENCE_DOUBTFUL && v.margin <= 0.0 && v.margin > -1e-9,
                  "%s, margin %g", frix_existence_describe(v.verdict), v.margin);
    const double sliding_open[6] = {1, 0.8, 0, -0.5, 0, 0}; /* t* = 0.05 */
    expect_guaranteed(walls_global(sliding_open, 0.5), walls_best_margin(sliding_open, 0.5));
    const double sliding_shut[6] = {1, 0, 1.4, -0.5, 0, 0}; /* t* = -0.1 */
    expect_doubtful(walls_global(sliding_shut, 0.5), walls_best_margin(sliding_shut, 0.5));
}
END_TEST

START_TEST(test_walls_local) {
    const double squeezed[6] = {-1, 0, 0, -1, 0, 0};
    expect_doubtful(walls_local_check(squeezed, 0.5), -1.0);
    const double open[6] = {-1, 0, 0, 1.5, 0, 0};
    expect_guaranteed(walls_local_check(open, 0.5), walls_best_margin(open, 0.5));
    const double sliding_shut[6] = {1, 0, 1.4, -0.5, 0, 0};
    expect_doubtful(walls_local_check(sliding_shut, 0.5), walls_best_margin(sliding_shut, 0.5));
    const double frictionless_shut[6] = {1, 5, 5, -1.2, 0, 0}; /* mu = 0: w_T is free */
    expect_doubtful(walls_local_check(frictionless_shut, 0.0), walls_best_margin(frictionless_shut, 0.0));
}
END_TEST

/* Scales whose squares overflow or underflow change nothing. */
START_TEST(test_walls_scaled) {
    static const double scales[4][2] = {{1e200, 1.0}, {1e-200, 1e150}, {1.0, 1e-250}, {1e150, 1e250}};
    const double q_scale = scales[_i][0], W_scale = scales[_i][1];
    const double squeezed[6] = {-1, 0, 0, -1, 0, 0}, open[6] = {-1, 0, 0, 1.5, 0, 0};
    expect_doubtful(walls_local_check_scaled(squeezed, 0.5, q_scale, W_scale), -1.0);
    expect_guaranteed(walls_local_check_scaled(open, 0.5, q_scale, W_scale), walls_best_margin(open, 0.5));
}
END_TEST

/* ---- One contact whose W cannot move u_N: W = diag(0, 1, 1), or a non-symmetric W with
 * a zero normal row. With q_N < 0 the certificate is y = (1, 0, 0): W^T y = 0, q.y = q_N. */

static verdict one_contact(const double W_dense[9], const double q[3], double mu) {
    frix_matrix *W = NULL;
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_matrix_from_dense(3, 3, W_dense, 3, &W), FRIX_OK);
    ck_assert_int_eq(frix_problem_local(W, q, &mu, 1, &p), FRIX_OK);
    verdict v = check(p);
    frix_problem_free(p);
    frix_matrix_free(W);
    return v;
}

START_TEST(test_one_contact_without_normal_stiffness) {
    const double W[9] = {0, 0, 0, 0, 1, 0, 0, 0, 1}; /* column-major */
    const double pressed[3] = {-1, 0.3, 0};
    expect_doubtful(one_contact(W, pressed, 0.5), -1.0 / contact_rms(pressed, 1));
    /* Taking off is fine: the search moves u_T inside the cone. */
    const double leaving[3] = {1, 30, 0}; /* t* = 1 */
    expect_guaranteed(one_contact(W, leaving, 0.5), 1.0 / contact_rms(leaving, 1));

    /* Non-symmetric: row 0 (u_N) is zero, u_T depends on r_N. Columns: (0,1,0), (0,1,0), (0,0,1). */
    const double Wns[9] = {0, 1, 0, 0, 1, 0, 0, 0, 1};
    expect_doubtful(one_contact(Wns, pressed, 0.5), -1.0 / contact_rms(pressed, 1));
    /* Its transpose: W y = 0 for y = (1, 0, 0) but W^T y != 0, and u_N = z_T1 + q_N takes
     * any value. The reaction that does no work is no certificate here; and its symmetric
     * part is indefinite, so a reachable u is no proof either. */
    const double Wt[9] = {0, 0, 0, 1, 1, 0, 0, 0, 1};
    ck_assert_int_eq(one_contact(Wt, pressed, 0.5).verdict, FRIX_EXISTENCE_UNDETERMINED);
    /* Non-symmetric and invertible (its symmetric part is positive definite): any u is
     * reachable, so any margin. */
    const double Winv[9] = {2, -1, 0, 1, 2, 0, 0, 0, 1};
    expect_guaranteed(one_contact(Winv, pressed, 0.5), INFINITY);
    /* Symmetric but indefinite: W z + q reaches every u, but a strictly feasible z proves a
     * solution only for a PSD W (W = -I with q_N < 0 has none: u_N = q_N - r_N < 0). */
    const double Windef[9] = {-1, 0, 0, 0, 1, 0, 0, 0, 1}, Wneg[9] = {-1, 0, 0, 0, -1, 0, 0, 0, -1};
    ck_assert_int_eq(one_contact(Windef, pressed, 0.5).verdict, FRIX_EXISTENCE_UNDETERMINED);
    ck_assert_int_eq(one_contact(Wneg, pressed, 0.5).verdict, FRIX_EXISTENCE_UNDETERMINED);
    /* A negative curvature that neither the power iterations (the dominant eigenvalue is 1)
     * nor the search's reactions (in the cone, y_N >= |y_T| / mu) meet: the factorisation of
     * W's symmetric part finds it. */
    const double Wtangent[9] = {1, 0, 0, 0, -0.01, 0, 0, 0, 1};
    ck_assert_int_eq(one_contact(Wtangent, pressed, 0.5).verdict, FRIX_EXISTENCE_UNDETERMINED);
}
END_TEST

/* The same contact solved, without the existence check: nothing holds r_N, which grows without
 * end. A solver that watches its iterate (the driver's runaway bound; auto in each stage, part
 * and route) ends the run diverged within a few hundred iterations of 100000, and answers with
 * a finite r on the scale of its start and of q, never the runaway; u (and v) finite. */
static void expect_diverges(const frix_problem *p, int64_t n, const double start[3], int solver) {
    double scale = 1.0; /* |q|_inf */
    for (int i = 0; i < 3; ++i) scale = fmax(scale, fabs(start[i]));
    double r[3], u[3], v[3] = {0};
    memcpy(r, start, sizeof r);
    frix_options *o = NULL;
    frix_info *info = NULL;
    ck_assert_int_eq(frix_options_create(solver, &o), FRIX_OK);
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_MAX_ITER, 100000), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_EXISTENCE_CHECK, 0), FRIX_OK);
    ck_assert_int_eq(frix_solve(p, o, r, u, n > 0 ? v : NULL, info), FRIX_OK);
    const char *form = n > 0 ? "global" : "local";
    ck_assert_msg(frix_info_status(info) == FRIX_STATUS_DIVERGED, "%s, %s: status %s", frix_solver_name(solver), form,
                  frix_status_string(frix_info_status(info)));
    ck_assert_msg(frix_info_iterations(info) < 1000, "%s, %s: %lld iterations", frix_solver_name(solver), form,
                  (long long)frix_info_iterations(info));
    ck_assert(isfinite(frix_info_error(info)));
    for (int i = 0; i < 3; ++i) {
        ck_assert(isfinite(r[i]) && isfinite(u[i]));
        ck_assert_msg(fabs(r[i]) <= scale, "%s, %s: r[%d] = %g", frix_solver_name(solver), form, i, r[i]);
    }
    for (int64_t j = 0; j < n; ++j) ck_assert(isfinite(v[j]));
    frix_info_free(info);
    frix_options_free(o);
}

/* W = diag(0, 1, 1) and W = 0, each also in global form (M = I, H reaching the tangential rows
 * only, or nothing), q = (-1, 0, 0), from r = 0 and from a start inside the cone. auto's first
 * sweeps drift slowly on diag(0, 1, 1) from the warm start (thousands of sweeps before the
 * bound): auto is asked there from r = 0 only. */
START_TEST(test_no_solution_diverges) {
    const double q[3] = {-1, 0, 0}, f[3] = {0}, mu = 0.5, cold[3] = {0}, warm[3] = {0.5, 0.1, 0};
    const double diag[9] = {0, 0, 0, 0, 1, 0, 0, 0, 1}, zero[9] = {0}, I3[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    const double *Ws[2] = {diag, zero};
    for (int k = 0; k < 2; ++k) {
        frix_matrix *W = NULL, *M = NULL, *H = NULL;
        frix_problem *local = NULL, *global = NULL;
        ck_assert_int_eq(frix_matrix_from_dense(3, 3, Ws[k], 3, &W), FRIX_OK);
        ck_assert_int_eq(frix_matrix_from_dense(3, 3, I3, 3, &M), FRIX_OK);
        ck_assert_int_eq(frix_matrix_from_dense(3, 3, Ws[k], 3, &H), FRIX_OK); /* H^T M^-1 H = W */
        ck_assert_int_eq(frix_problem_local(W, q, &mu, 1, &local), FRIX_OK);
        ck_assert_int_eq(frix_problem_global(M, H, f, q, &mu, 1, &global), FRIX_OK);
        for (int g = 0; g < 2; ++g) {
            const frix_problem *p = g ? global : local;
            const int64_t n = g ? 3 : 0;
            expect_diverges(p, n, cold, FRIX_SOLVER_PROX);
            expect_diverges(p, n, warm, FRIX_SOLVER_PROX);
            expect_diverges(p, n, cold, FRIX_SOLVER_AUTO);
            if (k == 1) expect_diverges(p, n, warm, FRIX_SOLVER_AUTO);
        }
        /* The interior point's own iterate, watched (its answer is its best iterate). */
        if (k == 0) expect_diverges(global, 3, warm, FRIX_SOLVER_IPM);
        frix_problem_free(local), frix_problem_free(global);
        frix_matrix_free(W), frix_matrix_free(M), frix_matrix_free(H);
    }
}
END_TEST

/* ---- N bodies on a line between two walls, N + 1 contacts along x: contact k has
 * u_N = v_k - v_{k-1} + w_N,k (v_0 = v_{N+1} = 0, the walls), u_T = w_T,k = 0. The normal
 * velocities telescope: t* = mean_k w_N,k, and y = (1, 0, 0) at every contact is the
 * certificate when that mean is negative. Dense columns here, so both storage kinds of H
 * are met (N not a multiple of 3: general sparse). */
#define CHAIN_BODIES 40
#define CHAIN_CONTACTS (CHAIN_BODIES + 1)

typedef struct {
    double M[CHAIN_BODIES * CHAIN_BODIES], H[CHAIN_BODIES * 3 * CHAIN_CONTACTS];
    double W[9 * CHAIN_CONTACTS * CHAIN_CONTACTS];
    double w[3 * CHAIN_CONTACTS], f[CHAIN_BODIES], mu[CHAIN_CONTACTS];
} chain;

/* w_N varies along the chain around the given mean; masses vary too. */
static chain *make_chain(double mean_w) {
    chain *c = calloc(1, sizeof *c);
    ck_assert_ptr_nonnull(c);
    const int n = CHAIN_BODIES, m = 3 * CHAIN_CONTACTS;
    double mass[CHAIN_BODIES];
    for (int i = 0; i < n; ++i) {
        mass[i] = 1.0 + 9.0 * (i % 4); /* 1, 10, 19, 28 */
        c->M[i + n * i] = mass[i];
    }
    for (int k = 0; k < CHAIN_CONTACTS; ++k) {
        if (k < n) c->H[k + n * (3 * k)] = 1.0;          /* body k (0-based) on its left contact */
        if (k > 0) c->H[(k - 1) + n * (3 * k)] = -1.0; /* body k-1 on its right contact */
        c->mu[k] = 0.3;
    }
    double sum = 0.0;
    for (int k = 0; k < CHAIN_CONTACTS; ++k) sum += c->w[3 * k] = 0.8 * cos(1.7 * k);
    for (int k = 0; k < CHAIN_CONTACTS; ++k) c->w[3 * k] += mean_w - sum / CHAIN_CONTACTS;
    /* W = H^T M^-1 H, f = 0 so that q = w. */
    for (int a = 0; a < m; ++a)
        for (int b = 0; b < m; ++b) {
            double s = 0.0;
            for (int i = 0; i < n; ++i) s += c->H[i + n * a] * c->H[i + n * b] / mass[i];
            c->W[a + m * b] = s;
        }
    return c;
}

static verdict chain_check(const chain *c, int global) {
    const int n = CHAIN_BODIES, m = 3 * CHAIN_CONTACTS;
    frix_matrix *A = NULL, *B = NULL;
    frix_problem *p = NULL;
    if (global) {
        ck_assert_int_eq(frix_matrix_from_dense(n, n, c->M, n, &A), FRIX_OK);
        ck_assert_int_eq(frix_matrix_from_dense(n, m, c->H, n, &B), FRIX_OK);
        ck_assert_int_eq(frix_problem_global(A, B, c->f, c->w, c->mu, CHAIN_CONTACTS, &p), FRIX_OK);
    } else {
        ck_assert_int_eq(frix_matrix_from_dense(m, m, c->W, m, &A), FRIX_OK);
        ck_assert_int_eq(frix_problem_local(A, c->w, c->mu, CHAIN_CONTACTS, &p), FRIX_OK);
    }
    verdict v = check(p);
    frix_problem_free(p);
    frix_matrix_free(B);
    frix_matrix_free(A);
    return v;
}

/* A dense W = I + G, |G_ij| <= 0.5 / (3 nc), with its first diagonal entry set to d: the test of
 * its symmetric part decides where the factorisation is cheap (d = -1: not positive
 * semidefinite; d = 1: it is), and declines without building it where W is dense and large
 * enough that the factorisation would cost more than its limit (500 contacts, n^3 / 3 = 1.1e9). */
static int dense_psd(int64_t nc, double d) {
    const int64_t k = 3 * nc;
    double *D = malloc((size_t)(k * k) * sizeof(double)), *q = malloc((size_t)k * sizeof(double)),
           *mu = malloc((size_t)nc * sizeof(double));
    ck_assert(D && q && mu);
    for (int64_t i = 0; i < k; ++i)
        for (int64_t j = 0; j <= i; ++j) {
            const double g = 0.5 / (double)k * sin(0.37 * (double)(i + 1) * (double)(j + 2));
            D[i + k * j] = D[j + k * i] = (i == j ? 1.0 : 0.0) + g;
        }
    D[0] = d;
    for (int64_t i = 0; i < k; ++i) q[i] = -1.0;
    for (int64_t a = 0; a < nc; ++a) mu[a] = 0.3;
    frix_matrix *W = NULL;
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_matrix_from_dense(k, k, D, k, &W), FRIX_OK);
    ck_assert_int_eq(frix_problem_local(W, q, mu, nc, &p), FRIX_OK);
    const int psd = frix_testing_symmetric_part_psd(p, 1e-10);
    frix_problem_free(p);
    frix_matrix_free(W);
    free(D), free(q), free(mu);
    return psd;
}

START_TEST(test_psd_check_declines_dense_large_w) {
    ck_assert_int_eq(dense_psd(40, -1.0), 1);
    ck_assert_int_eq(dense_psd(40, 1.0), 0);
    ck_assert_int_eq(dense_psd(500, -1.0), 2);
}
END_TEST

START_TEST(test_chain) {
    const int global = _i;
    chain *shut = make_chain(-0.05);
    expect_doubtful(chain_check(shut, global), -0.05 / contact_rms(shut->w, CHAIN_CONTACTS));
    free(shut);
    chain *open = make_chain(0.05);
    expect_guaranteed(chain_check(open, global), 0.05 / contact_rms(open->w, CHAIN_CONTACTS));
    free(open);
}
END_TEST

/* ---- A budget too small for a single step leaves the question open: z = 0 is no witness. */
START_TEST(test_budget) {
    const double q[6] = {-1, 0, 0, -1, 0, 0}, mu[2] = {0.5, 0.5};
    frix_matrix *W = NULL;
    frix_problem *p = walls_local(q, mu, &W);
    verdict v = check_with(p, 1e-9); /* the setup alone takes longer than 1 ns */
    ck_assert_int_eq(v.verdict, FRIX_EXISTENCE_UNDETERMINED);
    ck_assert(isnan(v.margin));
    v = check_with(p, 1e9); /* the largest limit accepted: settled at the first step */
    ck_assert_int_eq(v.verdict, FRIX_EXISTENCE_DOUBTFUL);
    frix_problem_free(p);
    frix_matrix_free(W);
}
END_TEST

/* ---- Trivial cases: no contacts; every contact separating at r = 0 (r = 0 solves it). */
START_TEST(test_trivial) {
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_problem_local(NULL, NULL, NULL, 0, &p), FRIX_OK);
    verdict v = check(p);
    ck_assert_int_eq(v.verdict, FRIX_EXISTENCE_GUARANTEED);
    ck_assert(isinf(v.margin) && v.margin > 0);
    frix_problem_free(p);

    /* q_N = 0 and q_T outside the cone, with no stiffness at all: no strictly feasible
     * point, but r = 0 is a solution. */
    const double zero[9] = {0}, grazing[3] = {0, 1, 0};
    v = one_contact(zero, grazing, 0.5);
    ck_assert_int_eq(v.verdict, FRIX_EXISTENCE_GUARANTEED);
    ck_assert_double_eq(v.margin, 0.0);
    /* ... whereas pushing in (q_N < 0) with W = 0 has the certificate y = P_K(-q). */
    const double pushing[3] = {-1, 0, 0};
    expect_doubtful(one_contact(zero, pushing, 0.5), -1.0);
}
END_TEST

/* ---- Real problems: rigid bodies that can all move apart have a strictly feasible point. */

/* Whether z = 0 is already a witness: q (w) strictly inside K* at every contact. */
static int b_strictly_feasible(const frix_problem *p) {
    const double *b = frix_problem_get_kind(p) == FRIX_PROBLEM_LOCAL ? frix_problem_q(p) : frix_problem_w(p);
    const double *mu = frix_problem_mu(p);
    for (int64_t a = 0; a < frix_problem_contacts(p); ++a)
        if (!(b[3 * a] > mu[a] * hypot(b[3 * a + 1], b[3 * a + 2]))) return 0;
    return 1;
}

static void expect_real_guaranteed(const char *relative, double time_limit) {
    frix_problem *p = load(relative);
    if (!p) return;
    ck_assert_msg(!b_strictly_feasible(p), "%s: no search needed", relative);
    verdict v = check_with(p, time_limit);
    ck_assert_msg(v.verdict == FRIX_EXISTENCE_GUARANTEED, "%s: %s (margin %g)", relative,
                  frix_existence_describe(v.verdict), v.margin);
    ck_assert_msg(v.margin > 0.0, "%s: margin %g", relative, v.margin);
    frix_problem_free(p);
}

START_TEST(test_real_problems) {
    /* q itself is not strictly feasible in these: the search has to move. The default
     * budget (5000 steps, 2 s) is far more than they take (milliseconds). */
    expect_real_guaranteed("local/Capsules-i125-1213.hdf5", 0.0);
    expect_real_guaranteed("converted/Rover4613.from_dat.hdf5", 0.0);
    expect_real_guaranteed("converted/RockPile_tob1.from_dat.hdf5", 0.0);
    expect_real_guaranteed("converted/OneObject-i100000-316.from_dat.hdf5", 0.0);
    expect_real_guaranteed("global/spheres-in-a-box-98-i10000-256-10.hdf5", 0.0);
    expect_real_guaranteed("converted/spheres-in-a-box-98-i10000-256-10.reduced.hdf5", 1.0);
}
END_TEST

/* q strictly inside K* at every contact: z = 0 is the witness, margin min_a (q_N - mu|q_T|)
 * relative to the RMS of |q_a|. */
START_TEST(test_q_strictly_feasible) {
    const double q[6] = {2, 1, 0, 1, 0, 0.5}, mu[2] = {0.5, 1.0};
    frix_matrix *W = NULL;
    frix_problem *p = walls_local(q, mu, &W);
    verdict v = check(p);
    ck_assert_int_eq(v.verdict, FRIX_EXISTENCE_GUARANTEED);
    ck_assert_double_eq_tol(v.margin, 0.5 / contact_rms(q, 2), 1e-15);
    frix_problem_free(p);
    frix_matrix_free(W);
}
END_TEST

/* ---- Bad input, and what the check leaves alone in info. */
START_TEST(test_bad_input) {
    const double q[6] = {-1, 0, 0, -1, 0, 0};
    double mu[2] = {0.5, 0.5};
    frix_matrix *W = NULL;
    frix_problem *p = walls_local(q, mu, &W);
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);

    int64_t v = -1;
    double margin = 0.0;
    ck_assert_int_eq(frix_info_get_int(info, FRIX_INFO_EXISTENCE, &v), FRIX_OK);
    ck_assert_int_eq(v, FRIX_EXISTENCE_NOT_CHECKED);
    ck_assert_int_eq(frix_info_get_double(info, FRIX_INFO_EXISTENCE_MARGIN, &margin), FRIX_OK);
    ck_assert(isnan(margin));

    ck_assert_int_eq(frix_problem_check_existence(NULL, 0.0, info), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_ptr_nonnull(strstr(frix_last_error_message(), "problem is NULL"));
    ck_assert_int_eq(frix_problem_check_existence(p, 0.0, NULL), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_ptr_nonnull(strstr(frix_last_error_message(), "info is NULL"));
    const double bad_limits[4] = {-1.0, NAN, INFINITY, 2e9};
    for (int k = 0; k < 4; ++k) {
        ck_assert_int_eq(frix_problem_check_existence(p, bad_limits[k], info), FRIX_ERR_INVALID_ARGUMENT);
        ck_assert_ptr_nonnull(strstr(frix_last_error_message(), "time_limit"));
    }
    /* The borrowed mu changed in place to an invalid value since the problem was made. */
    mu[1] = -1.0;
    ck_assert_int_eq(frix_problem_check_existence(p, 0.0, info), FRIX_ERR_INVALID_ARGUMENT);
    mu[1] = 0.5;
    ck_assert_int_eq(frix_info_get_int(info, FRIX_INFO_EXISTENCE, &v), FRIX_OK);
    ck_assert_int_eq(v, FRIX_EXISTENCE_NOT_CHECKED); /* refused calls touched nothing */

    /* A solve's keys survive the check. */
    double r[6] = {0}, u[6];
    ck_assert_int_eq(frix_solve(p, NULL, r, u, NULL, info), FRIX_OK);
    const int64_t iterations = frix_info_iterations(info);
    const double error = frix_info_error(info);
    ck_assert_int_gt(iterations, 0);
    ck_assert_int_eq(frix_problem_check_existence(p, 0.5, info), FRIX_OK);
    ck_assert_int_eq(frix_info_iterations(info), iterations);
    ck_assert_double_eq(frix_info_error(info), error);
    ck_assert_int_eq(frix_info_get_int(info, FRIX_INFO_EXISTENCE, &v), FRIX_OK);
    ck_assert_int_eq(v, FRIX_EXISTENCE_DOUBTFUL);

    ck_assert_str_eq(frix_existence_describe(FRIX_EXISTENCE_NOT_CHECKED), "not checked");
    ck_assert_str_eq(frix_existence_describe(FRIX_EXISTENCE_GUARANTEED), "a solution exists");
    ck_assert_str_eq(frix_existence_describe(FRIX_EXISTENCE_DOUBTFUL), "no solution may exist");
    ck_assert_str_eq(frix_existence_describe(FRIX_EXISTENCE_UNDETERMINED), "undetermined");
    ck_assert_str_eq(frix_existence_describe((frix_existence)42), "unknown verdict");

    frix_info_free(info);
    frix_problem_free(p);
    frix_matrix_free(W);
}
END_TEST

/* ---- `frix solve`: a failed solve says whether a solution exists; a converged one does not. */

static void write_problem(const char *path, const frix_problem *p) {
    char tmp[512];
    snprintf(tmp, sizeof tmp, "%s.%ld", path, (long)getpid());
    ck_assert_int_eq(frix_fclib_write(tmp, p, NULL, NULL, NULL, 0, NULL, NULL, NULL), FRIX_OK);
    ck_assert_int_eq(rename(tmp, path), 0);
}

static void write_walls(const char *path, const double q[6]) {
    const double mu[2] = {0.5, 0.5};
    frix_matrix *W = NULL;
    frix_problem *p = walls_local(q, mu, &W);
    write_problem(path, p);
    frix_problem_free(p);
    frix_matrix_free(W);
}

static void write_chain(const char *path) {
    chain *c = make_chain(0.05);
    const int m = 3 * CHAIN_CONTACTS;
    frix_matrix *W = NULL;
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_matrix_from_dense(m, m, c->W, m, &W), FRIX_OK);
    ck_assert_int_eq(frix_problem_local(W, c->w, c->mu, CHAIN_CONTACTS, &p), FRIX_OK);
    write_problem(path, p);
    frix_problem_free(p);
    frix_matrix_free(W);
    free(c);
}

static const char *line_of(const char *text, const char *label) {
    const char *at = strstr(text, label);
    return at && (at == text || at[-1] == '\n') ? at : NULL;
}

START_TEST(test_cli_existence_line) {
    const char *shut = FRIX_TEST_TMPDIR "/existence_walls_shut.hdf5";
    const char *open = FRIX_TEST_TMPDIR "/existence_walls_open.hdf5";
    const char *chain_file = FRIX_TEST_TMPDIR "/existence_chain.hdf5";
    const double q_shut[6] = {-1, 0, 0, -1, 0, 0}, q_open[6] = {-1, 0, 0, 1.5, 0, 0};
    write_walls(shut, q_shut);
    write_walls(open, q_open);
    write_chain(chain_file);

    /* No solution: every solver fails, and the CLI says why. */
    const char *a1[] = {"solve", shut, "--solver", "nsgs", "--max-iter", "50", NULL};
    cli_run r = run_cli(a1);
    ck_assert_msg(r.code == 1, "exit %d: %s%s", r.code, r.out, r.err);
    const char *line = line_of(r.out, "existence ");
    ck_assert_msg(line && strncmp(line + 17, "no solution may exist (certificate", 34) == 0, "%s", r.out);
    run_free(&r);

    const char *a2[] = {"solve", shut, "--solver", "nsgs", "--max-iter", "50", "--json", NULL};
    r = run_cli(a2);
    ck_assert_msg(r.code == 1, "exit %d: %s%s", r.code, r.out, r.err);
    ck_assert_msg(strstr(r.out, "\"existence\":\"no solution may exist\"") &&
                      strstr(r.out, "\"existence_margin\":-1"),
                  "%s", r.out);
    run_free(&r);

    /* A solution exists, the solver ran out of sweeps: the failure is the solver's. */
    const char *a3[] = {"solve", chain_file, "--solver", "nsgs", "--max-iter", "1", NULL};
    r = run_cli(a3);
    ck_assert_msg(r.code == 1, "exit %d: %s%s", r.code, r.out, r.err);
    line = line_of(r.out, "existence ");
    ck_assert_msg(line && strncmp(line + 17, "a solution exists (margin ", 26) == 0 &&
                      strstr(line, "the solver failed to find it"),
                  "%s", r.out);
    run_free(&r);

    /* Converged: no existence line, and "not checked" in JSON. */
    const char *a4[] = {"solve", open, "--solver", "nsgs", NULL};
    r = run_cli(a4);
    ck_assert_msg(r.code == 0, "exit %d: %s%s", r.code, r.out, r.err);
    ck_assert_msg(line_of(r.out, "existence ") == NULL, "%s", r.out);
    run_free(&r);
    const char *a5[] = {"solve", open, "--solver", "nsgs", "--json", NULL};
    r = run_cli(a5);
    ck_assert_msg(r.code == 0, "exit %d: %s%s", r.code, r.out, r.err);
    ck_assert_msg(strstr(r.out, "\"existence\":\"not checked\",\"existence_margin\":null"), "%s", r.out);
    run_free(&r);
}
END_TEST

/* Every failed run says whether a solution exists, a time limit or not: frix_solve keeps a
 * share of the limit for the check. W = diag(0, 1, 1) with q_N = -1 has no solution. */
START_TEST(test_failed_runs_report_existence) {
    const double W_dense[9] = {0, 0, 0, 0, 1, 0, 0, 0, 1}, q[3] = {-1, 0, 0}, mu = 0.5;
    frix_matrix *W = NULL;
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_matrix_from_dense(3, 3, W_dense, 3, &W), FRIX_OK);
    ck_assert_int_eq(frix_problem_local(W, q, &mu, 1, &p), FRIX_OK);
    const int solvers[] = {FRIX_SOLVER_NSGS, FRIX_SOLVER_AUTO, FRIX_SOLVER_NSN_AC};
    for (int k = 0; k < 3; ++k)
        for (int limited = 0; limited < 2; ++limited) {
            frix_options *o = NULL;
            frix_info *info = NULL;
            double r[3] = {0, 0, 0}, u[3];
            ck_assert_int_eq(frix_options_create(solvers[k], &o), FRIX_OK);
            if (limited) {
                ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_MAX_ITER, 1000000000), FRIX_OK);
                ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TIME_LIMIT, 0.3), FRIX_OK);
            }
            ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
            ck_assert_int_eq(frix_solve(p, o, r, u, NULL, info), FRIX_OK);
            int64_t existence = -1;
            ck_assert_int_eq(frix_info_get_int(info, FRIX_INFO_EXISTENCE, &existence), FRIX_OK);
            ck_assert_int_ne(frix_info_status(info), FRIX_STATUS_CONVERGED);
            ck_assert_msg(existence == FRIX_EXISTENCE_DOUBTFUL, "%s%s: %s, existence %s",
                          frix_solver_name(solvers[k]), limited ? " (time limit)" : "",
                          frix_status_string(frix_info_status(info)), frix_existence_describe((frix_existence)existence));
            if (limited) ck_assert_double_le(frix_info_solve_time(info), 0.3 * 1.5);
            frix_info_free(info);
            frix_options_free(o);
        }
    frix_problem_free(p);
    frix_matrix_free(W);
}
END_TEST

static Suite *existence_suite(void) {
    Suite *s = suite_create("existence");
    TCase *tc = tcase_create("closed_form");
    tcase_add_test(tc, test_walls_global);
    tcase_add_test(tc, test_walls_local);
    tcase_add_loop_test(tc, test_walls_scaled, 0, 4);
    tcase_add_test(tc, test_one_contact_without_normal_stiffness);
    tcase_add_test(tc, test_no_solution_diverges);
    tcase_add_loop_test(tc, test_chain, 0, 2);
    tcase_add_test(tc, test_trivial);
    tcase_add_test(tc, test_budget);
    tcase_add_test(tc, test_q_strictly_feasible);
    tcase_add_test(tc, test_bad_input);
    tcase_add_test(tc, test_failed_runs_report_existence);
    tcase_add_test(tc, test_psd_check_declines_dense_large_w);
    suite_add_tcase(s, tc);
    TCase *real = tcase_create("real");
    tcase_add_test(real, test_real_problems);
    tcase_set_timeout(real, 60);
    suite_add_tcase(s, real);
    TCase *cli = tcase_create("cli");
    tcase_add_test(cli, test_cli_existence_line);
    tcase_set_timeout(cli, 60);
    suite_add_tcase(s, cli);
    return s;
}

int main(void) { return frix_run_suite(existence_suite()); }
