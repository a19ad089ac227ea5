/* Every registered solver (frix_solver_count / frix_solver_id_at, so that solvers added later
 * are covered; global-only solvers are skipped) on small problems with known solutions, built
 * from arrays: one contact sticking, sliding, and taking off (the last behind a compressed
 * neighbour, since a lone separating contact never reaches a solver), two stacked boxes at
 * rest and with the top box pushed into sliding, a frictionless pair, and one contact with an
 * unsymmetric W. The error is
 * recomputed independently with frix_problem_error, the reaction compared with the known one
 * (or, where W is rank-deficient and r not unique, the resultant forces and the velocities).
 * Then, per solver: warm start, iteration limit, callback, time limit. Also the NSGS variants
 * (velocity-based, freezing, error frequency) and the first-order solvers' options on FCLIB
 * problems. */
#include <frix/frix.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check_main.h"
#include "shared_data.h"


#define TOL 1e-9
#define MAX_CONTACTS 8

/* ---- Problems with known solutions. */

typedef struct {
    const char *name;
    int nc;
    double W[9 * MAX_CONTACTS * MAX_CONTACTS]; /* dense, column-major, 3nc x 3nc */
    double q[3 * MAX_CONTACTS];
    double mu[MAX_CONTACTS];
    int unique;                     /* r* unique: compare r with r_star */
    double r_star[3 * MAX_CONTACTS];
    /* Stacked boxes: expected resultants of the ground (0..3) and top (4..7) contacts, and
     * the expected u (3 per contact). */
    int boxes;
    double ground_sum[3], top_sum[3];
    double u_star[3 * MAX_CONTACTS];
} known_problem;

static void matvec(int n, const double *A, const double *x, double *y) {
    for (int i = 0; i < n; ++i) {
        y[i] = 0.0;
        for (int j = 0; j < n; ++j) y[i] += A[i + n * j] * x[j];
    }
}

/* An SPD 3x3 block (column-major) and q = u* - W r*. */
static const double kW1[9] = {2.0, 0.3, 0.1, 0.3, 1.5, 0.2, 0.1, 0.2, 1.8};

static void one_contact(known_problem *k, const char *name, const double r[3], const double u[3]) {
    memset(k, 0, sizeof *k);
    k->name = name;
    k->nc = 1;
    memcpy(k->W, kW1, sizeof kW1);
    k->mu[0] = 0.3;
    double wr[3];
    matvec(3, kW1, r, wr);
    for (int i = 0; i < 3; ++i) k->q[i] = u[i] - wr[i];
    memcpy(k->r_star, r, 3 * sizeof(double));
    k->unique = 1;
}

static void make_stick(known_problem *k) {
    const double r[3] = {1.0, 0.2, -0.1}; /* |r_T| = 0.22 < 0.3 */
    const double u[3] = {0.0, 0.0, 0.0};
    one_contact(k, "one contact sticking", r, u);
}

/* An unsymmetric W_aa (its symmetric part positive definite), as in Siconos' chute local
 * problems: sticking. */
static void make_unsymmetric(known_problem *k) {
    const double r[3] = {1.0, 0.2, -0.1};
    const double u[3] = {0.0, 0.0, 0.0};
    one_contact(k, "one contact, unsymmetric W, sticking", r, u);
    const double skew[9] = {0.0, 0.3, -0.2, -0.3, 0.0, 0.25, 0.2, -0.25, 0.0};
    for (int i = 0; i < 9; ++i) k->W[i] += skew[i];
    double wr[3];
    matvec(3, k->W, r, wr);
    for (int i = 0; i < 3; ++i) k->q[i] = u[i] - wr[i];
}

static void make_slide(known_problem *k) {
    const double th = 0.7, mu = 0.3, lambda = 0.8;
    const double r[3] = {1.0, mu * cos(th), mu * sin(th)};
    const double u[3] = {0.0, -lambda * cos(th), -lambda * sin(th)};
    one_contact(k, "one contact sliding", r, u);
}

/* Contact 0 sticks; contact 1, coupled to it, separates although its q_N < 0. */
static void make_take_off(known_problem *k) {
    memset(k, 0, sizeof *k);
    k->name = "one contact taking off (beside a sticking one)";
    k->nc = 2;
    const int n = 6;
    /* W = [[A, C], [C^T, B]], SPD. */
    const double A[9] = {2.0, 0.3, 0.1, 0.3, 1.5, 0.2, 0.1, 0.2, 1.8};
    const double B[9] = {1.6, -0.2, 0.1, -0.2, 1.2, 0.0, 0.1, 0.0, 1.4};
    const double C[9] = {0.9, 0.1, 0.0, 0.0, 0.2, 0.1, 0.1, 0.0, 0.3}; /* block (0,1) */
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) {
            k->W[i + n * j] = A[i + 3 * j];
            k->W[(3 + i) + n * (3 + j)] = B[i + 3 * j];
            k->W[i + n * (3 + j)] = C[i + 3 * j];
            k->W[(3 + j) + n * i] = C[i + 3 * j];
        }
    k->mu[0] = 0.5;
    k->mu[1] = 0.5;
    const double r[6] = {1.0, 0.1, 0.2, 0.0, 0.0, 0.0};
    const double u[6] = {0.0, 0.0, 0.0, 0.2, 0.4, -0.3};
    double wr[6];
    matvec(n, k->W, r, wr);
    for (int i = 0; i < n; ++i) k->q[i] = u[i] - wr[i];
    memcpy(k->r_star, r, sizeof r);
    k->unique = 1;
}

/* mu = 0 on two contacts: contact 0 pressed, contact 1 separating (q_N < 0 for both). */
static void make_frictionless(known_problem *k) {
    memset(k, 0, sizeof *k);
    k->name = "mu = 0";
    k->nc = 2;
    const int n = 6;
    const double d[6] = {2.0, 1.0, 1.2, 1.5, 0.8, 1.1};
    for (int i = 0; i < n; ++i) k->W[i + n * i] = d[i];
    k->W[0 + n * 3] = k->W[3 + n * 0] = 0.9;
    k->W[1 + n * 4] = k->W[4 + n * 1] = 0.2;
    k->W[0 + n * 1] = k->W[1 + n * 0] = 0.3;
    const double r[6] = {1.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    const double u[6] = {0.0, 0.4, -0.2, 0.3, 0.1, 0.5};
    double wr[6];
    matvec(n, k->W, r, wr);
    for (int i = 0; i < n; ++i) k->q[i] = u[i] - wr[i];
    memcpy(k->r_star, r, sizeof r);
    k->unique = 1;
}

/* Two boxes stacked on the ground, 4 corner contacts each (ground-A 0..3, A-B 4..7), as a
 * time step: W = H^T M^-1 H, q = H^T M^-1 f, f = h F (v = 0 at the start). Contact frame:
 * n = z, t1 = x, t2 = y; u = velocity of the upper body minus the lower one at the point.
 * push > 0 pushes B along x at its centre of mass, hard enough to make it slide on A. */
static void make_boxes(known_problem *k, double push) {
    memset(k, 0, sizeof *k);
    k->name = push > 0.0 ? "two stacked boxes, top one sliding" : "two stacked boxes at rest";
    k->nc = 8;
    k->boxes = 1;
    const double g = 9.81, h = 0.01;
    const double mA = 2.0, mB = 1.0;
    const double a = 1.0, b = 0.8, c = 0.2; /* half sizes of both boxes (wide, flat) */
    const double IA[3] = {mA * (b * b + c * c) / 3.0, mA * (a * a + c * c) / 3.0, mA * (a * a + b * b) / 3.0};
    const double IB[3] = {mB * (b * b + c * c) / 3.0, mB * (a * a + c * c) / 3.0, mB * (a * a + b * b) / 3.0};
    const double cA[3] = {0.0, 0.0, c}, cB[3] = {0.0, 0.0, 3.0 * c};
    /* Jacobians J[k] (3 x 12, column-major): u_k = J_k (vA, wA, vB, wB). */
    double J[8][36];
    memset(J, 0, sizeof J);
    const double sx[4] = {-1, 1, 1, -1}, sy[4] = {-1, -1, 1, 1};
    for (int kk = 0; kk < 8; ++kk) {
        const int top = kk >= 4;
        const double p[3] = {a * sx[kk % 4], b * sy[kk % 4], top ? 2.0 * c : 0.0};
        /* u = (velocity of the upper body - velocity of the lower body) at p, rows
         * (n, t1, t2) = world (z, x, y); the velocity of a point of body b is v - [d]x w,
         * d = p - c_b. Ground contacts: A over the ground; top contacts: B over A. */
        for (int body = 0; body < 2; ++body) {
            const double sign = !top ? (body == 0 ? 1.0 : 0.0) : (body == 1 ? 1.0 : -1.0);
            if (sign == 0.0) continue;
            const double *cb = body == 0 ? cA : cB;
            const double d[3] = {p[0] - cb[0], p[1] - cb[1], p[2] - cb[2]};
            const double V[3][6] = {{1, 0, 0, 0, d[2], -d[1]}, {0, 1, 0, -d[2], 0, d[0]}, {0, 0, 1, d[1], -d[0], 0}};
            const int world_of_row[3] = {2, 0, 1};
            for (int row = 0; row < 3; ++row)
                for (int col = 0; col < 6; ++col)
                    J[kk][row + 3 * (6 * body + col)] = sign * V[world_of_row[row]][col];
        }
    }
    double Minv[12];
    for (int i = 0; i < 3; ++i) {
        Minv[i] = 1.0 / mA;
        Minv[3 + i] = 1.0 / IA[i];
        Minv[6 + i] = 1.0 / mB;
        Minv[9 + i] = 1.0 / IB[i];
    }
    double f[12] = {0};
    f[2] = -h * mA * g;
    f[8] = -h * mB * g;
    f[6] = h * push;
    const int n = 24;
    for (int k1 = 0; k1 < 8; ++k1)
        for (int k2 = 0; k2 < 8; ++k2)
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j) {
                    double s = 0.0;
                    for (int dof = 0; dof < 12; ++dof)
                        s += J[k1][i + 3 * dof] * Minv[dof] * J[k2][j + 3 * dof];
                    k->W[(3 * k1 + i) + n * (3 * k2 + j)] = s;
                }
    for (int kk = 0; kk < 8; ++kk)
        for (int i = 0; i < 3; ++i) {
            double s = 0.0;
            for (int dof = 0; dof < 12; ++dof) s += J[kk][i + 3 * dof] * Minv[dof] * f[dof];
            k->q[3 * kk + i] = s;
        }
    const double mu_ground = 0.8, mu_top = 0.3;
    for (int kk = 0; kk < 8; ++kk) k->mu[kk] = kk < 4 ? mu_ground : mu_top;
    /* Resultants (frame n, t1, t2) that cancel the impulses of gravity and of the push. */
    /* r of a top contact acts on B, -r on A; A stays at rest: ground = top + A's weight. */
    k->top_sum[0] = h * mB * g;
    k->ground_sum[0] = h * (mA + mB) * g;
    if (push > 0.0) {
        /* B slides along +x (the push exceeds mu_top m_B g, and A's ground friction holds A):
         * friction -mu_top N on B, passed on to the ground through A. */
        k->top_sum[1] = -mu_top * h * mB * g;
        k->ground_sum[1] = k->top_sum[1];
        const double vB = h * (push - mu_top * mB * g) / mB;
        for (int kk = 4; kk < 8; ++kk) k->u_star[3 * kk + 1] = vB;
    }
}

/* ---- Solving. */

typedef struct {
    frix_error rc;
    frix_status status;
    int64_t iterations;
    double error; /* recomputed */
} outcome;

static frix_problem *build(const known_problem *k, frix_matrix **W) {
    const int n = 3 * k->nc;
    ck_assert_int_eq(frix_matrix_from_dense(n, n, k->W, n, W), FRIX_OK);
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_problem_local(*W, k->q, k->mu, k->nc, &p), FRIX_OK);
    return p;
}

static outcome run(const frix_problem *p, const frix_options *o, double *r, double *u) {
    outcome out = {FRIX_OK, FRIX_STATUS_NOT_RUN, 0, NAN};
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    out.rc = frix_solve(p, o, r, u, NULL, info);
    if (out.rc == FRIX_OK) {
        out.status = frix_info_status(info);
        out.iterations = frix_info_iterations(info);
        const int64_t m = frix_problem_contact_dofs(p);
        for (int64_t i = 0; i < m; ++i) ck_assert_msg(isfinite(r[i]) && isfinite(u[i]), "r or u not finite");
        ck_assert_int_eq(frix_problem_error(p, r, NULL, &out.error), FRIX_OK);
    }
    frix_info_free(info);
    return out;
}

static frix_options *options_for(int id, double tol) {
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(id, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, tol), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TIME_LIMIT, 20.0), FRIX_OK);
    return o;
}

static void make_known(int which, known_problem *k) {
    switch (which) {
        case 0: make_stick(k); break;
        case 1: make_slide(k); break;
        case 2: make_take_off(k); break;
        case 3: make_frictionless(k); break;
        case 4: make_boxes(k, 0.0); break;
        case 5: make_boxes(k, 6.0); break;
        default: make_unsymmetric(k); break;
    }
}
#define N_KNOWN 7

static void check_known(const known_problem *k, int id, const double *r, const double *u) {
    const char *name = frix_solver_name(id);
    if (k->unique) {
        for (int i = 0; i < 3 * k->nc; ++i)
            ck_assert_msg(fabs(r[i] - k->r_star[i]) <= 1e-6 * (1.0 + fabs(k->r_star[i])),
                          "%s, %s: r[%d] = %.12g, expected %.12g", name, k->name, i, r[i], k->r_star[i]);
        return;
    }
    double ground[3] = {0, 0, 0}, top[3] = {0, 0, 0};
    for (int c = 0; c < k->nc; ++c)
        for (int i = 0; i < 3; ++i) (c < 4 ? ground : top)[i] += r[3 * c + i];
    /* The ground contacts carry what the top contacts carry plus box A's own load. */
    const double scale = k->ground_sum[0];
    for (int i = 0; i < 3; ++i) {
        ck_assert_msg(fabs(top[i] - k->top_sum[i]) <= 1e-6 * scale, "%s, %s: top resultant[%d] = %.12g, expected %.12g",
                      name, k->name, i, top[i], k->top_sum[i]);
        ck_assert_msg(fabs(ground[i] - k->ground_sum[i]) <= 1e-6 * scale,
                      "%s, %s: ground resultant[%d] = %.12g, expected %.12g", name, k->name, i, ground[i],
                      k->ground_sum[i]);
    }
    double umax = 0.0;
    for (int i = 0; i < 3 * k->nc; ++i) umax = fmax(umax, fabs(k->u_star[i]));
    for (int i = 0; i < 3 * k->nc; ++i)
        ck_assert_msg(fabs(u[i] - k->u_star[i]) <= 1e-6 * (umax + 0.1),
                      "%s, %s: u[%d] = %.12g, expected %.12g", name, k->name, i, u[i], k->u_star[i]);
}

/* Every registered solver that takes local problems, on every known problem. */
START_TEST(every_solver_finds_the_known_solutions) {
    const int id = frix_solver_id_at(_i);
    ck_assert_int_gt(id, 0);
    for (int which = 0; which < N_KNOWN; ++which) {
        known_problem k;
        make_known(which, &k);
        frix_matrix *W = NULL;
        frix_problem *p = build(&k, &W);
        frix_options *o = options_for(id, TOL);
        double r[3 * MAX_CONTACTS] = {0}, u[3 * MAX_CONTACTS] = {0};
        const outcome out = run(p, o, r, u);
        if (out.rc == FRIX_ERR_UNSUPPORTED) { /* a global-only solver */
            frix_options_free(o);
            frix_problem_free(p);
            frix_matrix_free(W);
            return;
        }
        ck_assert_msg(out.rc == FRIX_OK, "%s on %s: %s", frix_solver_name(id), k.name, frix_last_error_message());
        ck_assert_msg(out.status == FRIX_STATUS_CONVERGED, "%s on %s: %s after %lld iterations, error %g",
                      frix_solver_name(id), k.name, frix_status_string(out.status), (long long)out.iterations,
                      out.error);
        ck_assert_msg(out.error <= TOL, "%s on %s: recomputed error %g", frix_solver_name(id), k.name, out.error);
        check_known(&k, id, r, u);
        frix_options_free(o);
        frix_problem_free(p);
        frix_matrix_free(W);
    }
}
END_TEST

/* Warm start from the solution, the iteration limit, the callback and the time limit, for
 * every solver, on the stacked boxes. */
static int stop_at_once(void *data, int64_t it, double err, double t) {
    (void)it, (void)err, (void)t;
    ++*(int *)data;
    return 1;
}

static int count_calls(void *data, int64_t it, double err, double t) {
    (void)err, (void)t;
    int *calls = data;
    ck_assert_int_gt(it, 0);
    ++*calls;
    return 0;
}

START_TEST(every_solver_honours_the_common_options) {
    const int id = frix_solver_id_at(_i);
    const char *name = frix_solver_name(id);
    known_problem k;
    make_boxes(&k, 6.0);
    frix_matrix *W = NULL;
    frix_problem *p = build(&k, &W);
    double r[3 * MAX_CONTACTS] = {0}, u[3 * MAX_CONTACTS] = {0};
    frix_options *o = options_for(id, TOL);
    int calls = 0;
    ck_assert_int_eq(frix_options_set_callback(o, count_calls, &calls), FRIX_OK);
    outcome out = run(p, o, r, u);
    if (out.rc == FRIX_ERR_UNSUPPORTED) goto done;
    ck_assert_int_eq(out.status, FRIX_STATUS_CONVERGED);
    ck_assert_msg(calls >= 1 || out.iterations == 0, "%s: the callback was never called", name);

    /* Warm start from the solution: at most one iteration. */
    out = run(p, o, r, u);
    ck_assert_msg(out.status == FRIX_STATUS_CONVERGED && out.iterations <= 1,
                  "%s: warm start from the solution took %lld iterations (%s)", name,
                  (long long)out.iterations, frix_status_string(out.status));

    /* Tolerance 0 cannot be met: the iteration limit, the callback or the clock stops. */
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 0.0), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_MAX_ITER, 1), FRIX_OK);
    ck_assert_int_eq(frix_options_set_callback(o, NULL, NULL), FRIX_OK);
    memset(r, 0, sizeof r);
    out = run(p, o, r, u);
    ck_assert_msg(out.status == FRIX_STATUS_MAX_ITER || out.status == FRIX_STATUS_STAGNATED,
                  "%s: max_iter 1 gave %s", name, frix_status_string(out.status));
    ck_assert_msg(out.iterations <= 1, "%s: max_iter 1 but %lld iterations", name, (long long)out.iterations);

    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_MAX_ITER, 1000000000), FRIX_OK);
    int stops = 0;
    ck_assert_int_eq(frix_options_set_callback(o, stop_at_once, &stops), FRIX_OK);
    memset(r, 0, sizeof r);
    out = run(p, o, r, u);
    ck_assert_msg(out.status == FRIX_STATUS_STOPPED_BY_CALLBACK || out.status == FRIX_STATUS_STAGNATED,
                  "%s: the callback did not stop the solve (%s)", name, frix_status_string(out.status));
    ck_assert_msg(stops == 1 || (stops == 0 && out.status == FRIX_STATUS_STAGNATED),
                  "%s: the callback was called %d times (once expected: it asked to stop)", name, stops);

    ck_assert_int_eq(frix_options_set_callback(o, NULL, NULL), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TIME_LIMIT, 0.05), FRIX_OK);
    memset(r, 0, sizeof r);
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_solve(p, o, r, u, NULL, info), FRIX_OK);
    ck_assert_msg(frix_info_status(info) == FRIX_STATUS_TIME_LIMIT || frix_info_status(info) == FRIX_STATUS_STAGNATED,
                  "%s: time limit gave %s", name, frix_status_string(frix_info_status(info)));
    ck_assert_msg(frix_info_solve_time(info) < 1.0, "%s: stopped after %g s", name, frix_info_solve_time(info));
    frix_info_free(info);
done:
    frix_options_free(o);
    frix_problem_free(p);
    frix_matrix_free(W);
}
END_TEST

/* Deterministic: the same call twice gives the same bits. */
START_TEST(every_solver_is_deterministic) {
    const int id = frix_solver_id_at(_i);
    known_problem k;
    make_boxes(&k, 6.0);
    frix_matrix *W = NULL;
    frix_problem *p = build(&k, &W);
    frix_options *o = options_for(id, 1e-6);
    double r1[24] = {0}, r2[24] = {0}, u[24];
    const outcome a = run(p, o, r1, u);
    if (a.rc == FRIX_OK) {
        run(p, o, r2, u);
        ck_assert_msg(memcmp(r1, r2, sizeof r1) == 0, "%s is not deterministic", frix_solver_name(id));
    }
    frix_options_free(o);
    frix_problem_free(p);
    frix_matrix_free(W);
}
END_TEST

/* ---- The first-order family on FCLIB problems (the slow ones belong to tools/bench). */


typedef struct {
    int id;
    const char *file;
} fclib_case;

/* Each solver of the issue on problems it solves to 1e-8 in well under a second (0.1 s at
 * most: the suite also runs under valgrind). */
static const fclib_case kFclibCases[] = {
    {FRIX_SOLVER_VI_FPP, "converted/Rover4613.from_dat.hdf5"},
    {FRIX_SOLVER_VI_FPP, "local/LMGC_100_PR_PerioBox-i00361-60-03000.hdf5"},
    {FRIX_SOLVER_VI_EG, "converted/NESpheres_10_1.from_dat.hdf5"},
    {FRIX_SOLVER_VI_EG, "converted/Confeti-ex03-Fc3D-SBM.from_dat.hdf5"},
    {FRIX_SOLVER_HP, "converted/GFC3D_TwoRods1.from_dat.hdf5"},
    {FRIX_SOLVER_HP, "converted/Box_Stacks-i0035-31-0.reduced.hdf5"},
    {FRIX_SOLVER_TFP, "converted/OneObject-i100000-316.from_dat.hdf5"},
    {FRIX_SOLVER_TFP, "local/LMGC_100_PR_PerioBox-i00361-60-03000.hdf5"},
    {FRIX_SOLVER_ACLM, "converted/Capsules-i101-404.from_dat.hdf5"},
    {FRIX_SOLVER_ACLM, "converted/OneObject-i1028-138.from_dat.hdf5"},
    {FRIX_SOLVER_ADMM, "local/local_problem_test.hdf5"},
    {FRIX_SOLVER_ADMM, "converted/OneObject-i100000-316.from_dat.hdf5"},
    {FRIX_SOLVER_ADMM, "converted/Confeti-ex03-Fc3D-SBM.from_dat.hdf5"},
    {FRIX_SOLVER_NSGS_VELOCITY, "local/Capsules-i125-1213.hdf5"},
    {FRIX_SOLVER_NSGS_VELOCITY, "converted/Rover1040.from_dat.hdf5"},
};
#define N_FCLIB_CASES ((int)(sizeof kFclibCases / sizeof kFclibCases[0]))

START_TEST(first_order_solvers_on_fclib) {
    const fclib_case c = kFclibCases[_i];
    frix_problem *p = load(c.file);
    if (!p) return;
    const int64_t m = frix_problem_contact_dofs(p);
    double *r = calloc((size_t)m, sizeof *r), *u = calloc((size_t)m, sizeof *u);
    frix_options *o = options_for(c.id, 1e-8);
    const outcome out = run(p, o, r, u);
    ck_assert_int_eq(out.rc, FRIX_OK);
    ck_assert_msg(out.status == FRIX_STATUS_CONVERGED && out.error <= 1e-8, "%s on %s: %s, error %g",
                  frix_solver_name(c.id), c.file, frix_status_string(out.status), out.error);
    frix_options_free(o);
    frix_problem_free(p);
    free(r);
    free(u);
}
END_TEST

/* nsgs-v follows nsgs sweep for sweep (the same local solves, another way to form the
 * local q); freezing and the error frequency change the work, never the accuracy. */
START_TEST(nsgs_variants) {
    frix_problem *p = load("local/Capsules-i125-1213.hdf5");
    if (!p) return;
    const int64_t m = frix_problem_contact_dofs(p);
    double *r = calloc((size_t)m, sizeof *r), *u = calloc((size_t)m, sizeof *u);
    frix_options *o = options_for(FRIX_SOLVER_NSGS, 1e-8);
    const outcome plain = run(p, o, r, u);
    ck_assert_int_eq(plain.status, FRIX_STATUS_CONVERGED);
    frix_options_free(o);

    o = options_for(FRIX_SOLVER_NSGS_VELOCITY, 1e-8);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_FREEZING, 0), FRIX_OK);
    memset(r, 0, (size_t)m * sizeof *r);
    const outcome velocity = run(p, o, r, u);
    ck_assert_int_eq(velocity.status, FRIX_STATUS_CONVERGED);
    ck_assert(velocity.error <= 1e-8);
    ck_assert_int_eq(velocity.iterations, plain.iterations);

    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_FREEZING, 10), FRIX_OK);
    memset(r, 0, (size_t)m * sizeof *r);
    const outcome frozen = run(p, o, r, u);
    ck_assert_int_eq(frozen.status, FRIX_STATUS_CONVERGED);
    ck_assert(frozen.error <= 1e-8);
    frix_options_free(o);

    o = options_for(FRIX_SOLVER_NSGS, 1e-8);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_FREEZING, 10), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_ERROR_FREQUENCY, 5), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_RELAXATION, 1.2), FRIX_OK);
    memset(r, 0, (size_t)m * sizeof *r);
    const outcome psor = run(p, o, r, u);
    ck_assert_msg(psor.status == FRIX_STATUS_CONVERGED && psor.error <= 1e-8, "PSOR + freezing: %s, %g",
                  frix_status_string(psor.status), psor.error);
    ck_assert_int_eq(psor.iterations % 5, 0); /* the test runs every fifth sweep */
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_ERROR_FREQUENCY, 0), FRIX_ERR_OPTION_RANGE);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_FREEZING, -1), FRIX_ERR_OPTION_RANGE);
    frix_options_free(o);
    frix_problem_free(p);
    free(r);
    free(u);
}
END_TEST

/* Options of the first-order solvers: fixed steps, no acceleration, inner limits. */
START_TEST(first_order_options) {
    frix_problem *p = load("converted/Rover1039.from_dat.hdf5");
    if (!p) return;
    const int64_t m = frix_problem_contact_dofs(p);
    double *r = calloc((size_t)m, sizeof *r), *u = calloc((size_t)m, sizeof *u);
    /* Up to two settings per run (key 0: none). */
    struct {
        int id;
        frix_option_key key[2];
        double value[2];
    } settings[] = {
        {FRIX_SOLVER_VI_FPP, {FRIX_OPT_RHO_ADAPTIVE, FRIX_OPT_RHO}, {0, 0.5}},
        {FRIX_SOLVER_VI_EG, {FRIX_OPT_RHO_ADAPTIVE, FRIX_OPT_RHO}, {0, 0.3}},
        {FRIX_SOLVER_HP, {FRIX_OPT_RHO, (frix_option_key)0}, {2.0, 0}},
        {FRIX_SOLVER_ADMM, {FRIX_OPT_ACCELERATION, (frix_option_key)0}, {0, 0}},
        {FRIX_SOLVER_ADMM, {FRIX_OPT_RHO_ADAPTIVE, FRIX_OPT_RHO}, {0, 0.1}},
        {FRIX_SOLVER_TFP, {FRIX_OPT_INNER_MAX_ITER, (frix_option_key)0}, {5, 0}},
        {FRIX_SOLVER_ACLM, {FRIX_OPT_INNER_TOLERANCE_RATIO, FRIX_OPT_LOCAL_MAX_ITER}, {0.5, 5}},
    };
    for (size_t k = 0; k < sizeof settings / sizeof settings[0]; ++k) {
        frix_options *o = options_for(settings[k].id, 1e-8);
        for (int j = 0; j < 2 && settings[k].key[j]; ++j) {
            const frix_option_key key = settings[k].key[j];
            double lo, hi;
            int is_int;
            ck_assert_int_eq(frix_options_bounds(o, key, &lo, &hi, &is_int), FRIX_OK);
            if (is_int) ck_assert_int_eq(frix_options_set_int(o, key, (int64_t)settings[k].value[j]), FRIX_OK);
            else ck_assert_int_eq(frix_options_set_double(o, key, settings[k].value[j]), FRIX_OK);
        }
        memset(r, 0, (size_t)m * sizeof *r);
        const outcome out = run(p, o, r, u);
        ck_assert_msg(out.status == FRIX_STATUS_CONVERGED && out.error <= 1e-8, "%s with %s = %g: %s, %g",
                      frix_solver_name(settings[k].id), frix_option_name(settings[k].key[0]),
                      settings[k].value[0], frix_status_string(out.status), out.error);
        frix_options_free(o);
    }
    /* Keys a solver does not read are refused. */
    frix_options *o = options_for(FRIX_SOLVER_VI_FPP, 1e-8);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_ACCELERATION, 0), FRIX_ERR_UNKNOWN_OPTION);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_RHO_ADAPTIVE, 2), FRIX_ERR_OPTION_RANGE);
    frix_options_free(o);
    frix_problem_free(p);
    free(r);
    free(u);
}
END_TEST

/* ADMM's per-contact penalty (rho_strategy 1): on a problem whose contacts are in units that
 * differ by decades (OneObject-i100000 rescaled per contact by 10^[-2, 2]: |W_aa| over 8 more
 * decades) one penalty for all contacts stalls (2e-5 after 10^6 iterations) while the
 * penalties scaled by |W_aa| converge in a few hundred iterations (343 measured); on the
 * problem as it is, rho_strategy 0 is the default and leaves the iterates unchanged. */
START_TEST(admm_per_contact_penalty) {
    scaled_problem sp;
    if (!scaled_problem_load(&sp, "converted/OneObject-i100000-316.from_dat.hdf5", 2.0)) return;
    const int64_t m = frix_problem_contact_dofs(sp.p);
    double *r = calloc((size_t)m, sizeof *r), *u = calloc((size_t)m, sizeof *u);
    frix_options *o = options_for(FRIX_SOLVER_ADMM, 1e-8);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_MAX_ITER, 3000), FRIX_OK);
    const outcome one = run(sp.p, o, r, u);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_RHO_STRATEGY, FRIX_RHO_SPECTRAL), FRIX_OK);
    memset(r, 0, (size_t)m * sizeof *r);
    const outcome scaled = run(sp.p, o, r, u);
    ck_assert_msg(scaled.status == FRIX_STATUS_CONVERGED && scaled.error <= 1e-8, "per-contact penalty: %s, %g",
                  frix_status_string(scaled.status), scaled.error);
    ck_assert_msg(one.status != FRIX_STATUS_CONVERGED && one.error > 100.0 * scaled.error,
                  "one penalty: %s, %g after %lld iterations", frix_status_string(one.status), one.error,
                  (long long)one.iterations);
    /* rho_strategy 0 is the default: the same iterates as without the key. */
    frix_options *d = options_for(FRIX_SOLVER_ADMM, 1e-8);
    frix_options *c = options_for(FRIX_SOLVER_ADMM, 1e-8);
    ck_assert_int_eq(frix_options_set_int(c, FRIX_OPT_RHO_STRATEGY, FRIX_RHO_CONSTANT), FRIX_OK);
    memset(r, 0, (size_t)m * sizeof *r);
    const outcome by_default = run(sp.original, d, r, u);
    double *r2 = calloc((size_t)m, sizeof *r2);
    const outcome constant = run(sp.original, c, r2, u);
    ck_assert_int_eq(by_default.status, FRIX_STATUS_CONVERGED);
    ck_assert_int_eq(constant.iterations, by_default.iterations);
    ck_assert_int_eq(memcmp(r, r2, (size_t)m * sizeof *r), 0);
    frix_options_free(o);
    frix_options_free(d);
    frix_options_free(c);
    scaled_problem_free(&sp);
    free(r);
    free(r2);
    free(u);
}
END_TEST

/* The solvers are found by their names and ids, the Siconos spellings included. */
START_TEST(names_and_ids) {
    const struct {
        const char *name;
        int id;
    } names[] = {{"nsgs-v", FRIX_SOLVER_NSGS_VELOCITY},
                 {"tfp", FRIX_SOLVER_TFP},
                 {"vi-fpp", FRIX_SOLVER_VI_FPP},
                 {"vi-eg", FRIX_SOLVER_VI_EG},
                 {"hp", FRIX_SOLVER_HP},
                 {"aclm", FRIX_SOLVER_ACLM},
                 {"admm", FRIX_SOLVER_ADMM},
                 {"FRICTION_3D_VI_FPP", FRIX_SOLVER_VI_FPP},
                 {"FC3D_ACLMFP", FRIX_SOLVER_ACLM},
                 {"SICONOS_FRICTION_3D_ADMM", FRIX_SOLVER_ADMM},
                 {"FC3D_NSGSV", FRIX_SOLVER_NSGS_VELOCITY},
                 {"FC3D_TFP", FRIX_SOLVER_TFP},
                 {"FC3D_HP", FRIX_SOLVER_HP}};
    for (size_t k = 0; k < sizeof names / sizeof names[0]; ++k) {
        int id = 0;
        ck_assert_msg(frix_solver_by_name(names[k].name, &id) == FRIX_OK, "%s", names[k].name);
        ck_assert_int_eq(id, names[k].id);
        ck_assert_ptr_nonnull(frix_solver_describe(id));
    }
}
END_TEST

int main(void) {
    Suite *s = suite_create("first_order");
    TCase *tc = tcase_create("core");
    tcase_set_timeout(tc, 300);
    const int n = (int)frix_solver_count();
    tcase_add_loop_test(tc, every_solver_finds_the_known_solutions, 0, n);
    tcase_add_loop_test(tc, every_solver_honours_the_common_options, 0, n);
    tcase_add_loop_test(tc, every_solver_is_deterministic, 0, n);
    tcase_add_loop_test(tc, first_order_solvers_on_fclib, 0, N_FCLIB_CASES);
    tcase_add_test(tc, nsgs_variants);
    tcase_add_test(tc, first_order_options);
    tcase_add_test(tc, admm_per_contact_penalty);
    tcase_add_test(tc, names_and_ids);
    suite_add_tcase(s, tc);
    return frix_run_suite(s);
}
