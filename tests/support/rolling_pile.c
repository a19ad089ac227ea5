#include "rolling_pile.h"

#include <check.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "lcg.h"

static void cross(const double *a, const double *b, double *c) {
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

/* The contact frame: normal n, tangents t1, t2 turned by angle about n. */
static void frame(const double *n, double angle, double *t1, double *t2) {
    double a[3] = {1, 0, 0};
    if (fabs(n[0]) > 0.9) a[0] = 0, a[1] = 1;
    double e1[3], e2[3];
    cross(n, a, e1);
    double l = sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
    for (int i = 0; i < 3; ++i) e1[i] /= l;
    cross(n, e1, e2);
    for (int i = 0; i < 3; ++i) {
        t1[i] = cos(angle) * e1[i] + sin(angle) * e2[i];
        t2[i] = -sin(angle) * e1[i] + cos(angle) * e2[i];
    }
}

/* Column size*c+k of H on body b's dofs (sign +1 for the body the normal points to, -1 for the
 * other): u = v_b - v_a - (w_a + w_b) x (R n) at the contact point, w_R = w_b - w_a on the
 * tangents and, with a sixth entry, w_S = (w_b - w_a) . n. */
static void body_columns(double *H, int64_t n, int size, int64_t c, int64_t b, double sign, const double *nrm,
                         const double *t1, const double *t2, double radius) {
    const double *e[3] = {nrm, t1, t2};
    for (int k = 0; k < 3; ++k) {
        double *col = H + n * (size * c + k) + 6 * b;
        double exn[3];
        cross(e[k], nrm, exn);
        for (int i = 0; i < 3; ++i) col[i] += sign * e[k][i];
        for (int i = 0; i < 3; ++i) col[3 + i] += radius * exn[i];
    }
    for (int k = 0; k < size - 3; ++k) {
        double *col = H + n * (size * c + 3 + k) + 6 * b;
        for (int i = 0; i < 3; ++i) col[3 + i] += sign * e[(1 + k) % 3][i];
    }
}

/* mu_s < 0: no spinning friction (five entries a contact). */
static int make(int side, int layers, double mu, double mu_r, double mu_s, uint64_t seed, rolling_pile *out) {
    memset(out, 0, sizeof *out);
    const int size = mu_s >= 0.0 ? 6 : 5;
    const int64_t bodies = (int64_t)side * side * layers, n = 6 * bodies;
    /* Contacts: the ground under the bottom layer, then each pair of neighbours (+x, +y, +z). */
    int64_t nc = (int64_t)side * side + 3 * bodies;
    const double radius = 0.5, h = 0.01, g = 9.81;
    double *H = calloc((size_t)(n * size * nc), sizeof(double));
    double *Mdiag = malloc((size_t)n * sizeof(double)), *vfree = malloc((size_t)n * sizeof(double));
    out->mu = malloc((size_t)nc * sizeof(double));
    out->mu_r = malloc((size_t)nc * sizeof(double));
    if (size == 6) out->mu_s = malloc((size_t)nc * sizeof(double));
    if (!H || !Mdiag || !vfree || !out->mu || !out->mu_r || (size == 6 && !out->mu_s)) return 1;
    uint64_t s = seed * 2654435761ULL + 1;
    for (int64_t b = 0; b < bodies; ++b) {
        const double m = 1.0 + lcg_uniform(&s), inertia = 0.4 * m * radius * radius;
        for (int i = 0; i < 3; ++i) Mdiag[6 * b + i] = m, Mdiag[6 * b + 3 + i] = inertia;
        vfree[6 * b] = 0.05 * (lcg_uniform(&s) - 0.5);
        vfree[6 * b + 1] = 0.05 * (lcg_uniform(&s) - 0.5);
        vfree[6 * b + 2] = -h * g;
        for (int i = 3; i < 6; ++i) vfree[6 * b + i] = 0.1 * (lcg_uniform(&s) - 0.5);
    }
    int64_t c = 0;
#define BODY(x, y, z) ((int64_t)(z) * side * side + (int64_t)(y) * side + (x))
    for (int y = 0; y < side; ++y)
        for (int x = 0; x < side; ++x) {
            const double nrm[3] = {0, 0, 1};
            double t1[3], t2[3];
            frame(nrm, 6.283185307179586 * lcg_uniform(&s), t1, t2);
            body_columns(H, n, size, c, BODY(x, y, 0), 1.0, nrm, t1, t2, radius);
            ++c;
        }
    for (int z = 0; z < layers; ++z)
        for (int y = 0; y < side; ++y)
            for (int x = 0; x < side; ++x)
                for (int d = 0; d < 3; ++d) {
                    const int xb = x + (d == 0), yb = y + (d == 1), zb = z + (d == 2);
                    if (xb >= side || yb >= side || zb >= layers) continue;
                    const double nrm[3] = {d == 0, d == 1, d == 2};
                    double t1[3], t2[3];
                    frame(nrm, 6.283185307179586 * lcg_uniform(&s), t1, t2);
                    body_columns(H, n, size, c, BODY(xb, yb, zb), 1.0, nrm, t1, t2, radius);
                    body_columns(H, n, size, c, BODY(x, y, z), -1.0, nrm, t1, t2, radius);
                    ++c;
                }
#undef BODY
    nc = c;
    for (int64_t a = 0; a < nc; ++a) {
        out->mu[a] = mu, out->mu_r[a] = mu_r;
        if (size == 6) out->mu_s[a] = mu_s;
    }
    out->bodies = bodies, out->n = n, out->nc = nc, out->size = size;
    const int64_t m = size * nc;
    out->f = malloc((size_t)n * sizeof(double));
    out->w = calloc((size_t)m, sizeof(double));
    out->q = calloc((size_t)m, sizeof(double));
    double *W = calloc((size_t)(m * m), sizeof(double));
    if (!out->f || !out->w || !out->q || !W) return 1;
    for (int64_t i = 0; i < n; ++i) out->f[i] = Mdiag[i] * vfree[i];
    for (int64_t j = 0; j < m; ++j) {
        const double *hj = H + n * j;
        for (int64_t i = 0; i < n; ++i) out->q[j] += hj[i] * vfree[i];
        for (int64_t k = 0; k <= j; ++k) {
            const double *hk = H + n * k;
            double sum = 0.0;
            for (int64_t i = 0; i < n; ++i) sum += hj[i] * hk[i] / Mdiag[i];
            W[j + m * k] = W[k + m * j] = sum;
        }
    }
    double *Md = calloc((size_t)(n * n), sizeof(double));
    if (!Md) return 1;
    for (int64_t i = 0; i < n; ++i) Md[i + n * i] = Mdiag[i];
    int rc = frix_matrix_from_dense(n, n, Md, n, &out->M) || frix_matrix_from_dense(n, m, H, n, &out->H) ||
             frix_matrix_from_dense(m, m, W, m, &out->W);
    if (!rc && size == 5)
        rc = frix_problem_rolling_global(out->M, out->H, out->f, out->w, out->mu, out->mu_r, nc, &out->global) ||
             frix_problem_rolling_local(out->W, out->q, out->mu, out->mu_r, nc, &out->local);
    else if (!rc)
        rc = frix_problem_spinning_global(out->M, out->H, out->f, out->w, out->mu, out->mu_r, out->mu_s, nc,
                                          &out->global) ||
             frix_problem_spinning_local(out->W, out->q, out->mu, out->mu_r, out->mu_s, nc, &out->local);
    free(Md);
    free(W);
    free(H);
    free(Mdiag);
    free(vfree);
    return rc;
}

int rolling_pile_make(int side, int layers, double mu, double mu_r, uint64_t seed, rolling_pile *out) {
    return make(side, layers, mu, mu_r, -1.0, seed, out);
}

int rolling_pile_make_spinning(int side, int layers, double mu, double mu_r, double mu_s, uint64_t seed,
                               rolling_pile *out) {
    return mu_s >= 0.0 ? make(side, layers, mu, mu_r, mu_s, seed, out) : 1;
}

void rolling_pile_free(rolling_pile *p) {
    frix_problem_free(p->global);
    frix_problem_free(p->local);
    frix_matrix_free(p->M);
    frix_matrix_free(p->H);
    frix_matrix_free(p->W);
    free(p->f);
    free(p->w);
    free(p->q);
    free(p->mu);
    free(p->mu_r);
    free(p->mu_s);
    memset(p, 0, sizeof *p);
}

/* rolling_check_no_solution's check of one problem p (n dofs, 0 for the local form) from start. */
static void check_diverges(frix_problem *p, int size, int64_t n, const double *start) {
    const int solvers[3] = {FRIX_SOLVER_ROLLING_NSGS, FRIX_SOLVER_ROLLING_NSN, FRIX_SOLVER_AUTO};
    double scale = 1.0; /* |q|_inf, |w|_inf */
    for (int i = 0; i < size; ++i) scale = fmax(scale, fabs(start[i]));
    for (int k = 0; k < 3; ++k) {
        double r[6], u[6], v[6] = {0};
        ck_assert_int_le(size, 6);
        ck_assert_int_le(n, 6);
        memcpy(r, start, (size_t)size * sizeof(double));
        frix_options *o = NULL;
        frix_info *info = NULL;
        ck_assert_int_eq(frix_options_create(solvers[k], &o), FRIX_OK);
        ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
        ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_MAX_ITER, 100000), FRIX_OK);
        ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_EXISTENCE_CHECK, 0), FRIX_OK);
        ck_assert_int_eq(frix_solve(p, o, r, u, n > 0 ? v : NULL, info), FRIX_OK);
        ck_assert_msg(frix_info_status(info) == FRIX_STATUS_DIVERGED, "solver %d: status %s", solvers[k],
                      frix_status_string(frix_info_status(info)));
        ck_assert_int_lt(frix_info_iterations(info), 100);
        ck_assert(isfinite(frix_info_error(info)));
        for (int i = 0; i < size; ++i) {
            ck_assert(isfinite(r[i]) && isfinite(u[i]));
            ck_assert_double_le(fabs(r[i]), scale);
        }
        for (int64_t j = 0; j < n; ++j) ck_assert(isfinite(v[j]));
        frix_info_free(info);
        frix_options_free(o);
    }
}

void rolling_check_no_solution(int size) {
    const double mu = 0.5, mu_r = 0.1, mu_s = 0.05, q[6] = {-1, 0, 0, 0, 0, 0}, cold[6] = {0};
    const double warm[6] = {0.5, 0.1, 0, 0.01, 0, 0.01}; /* inside every cone */
    double Wd[36] = {0}, Hd[36] = {0}, Md[36] = {0}, f[6] = {0};
    ck_assert(size == 5 || size == 6);
    for (int i = 0; i < 6; ++i) Md[i + 6 * i] = 1.0;
    for (int i = 1; i < size; ++i) Wd[i + size * i] = 1.0, Hd[i + 6 * i] = 1.0;
    frix_matrix *W = NULL, *H = NULL, *M = NULL;
    ck_assert_int_eq(frix_matrix_from_dense(size, size, Wd, size, &W), FRIX_OK);
    ck_assert_int_eq(frix_matrix_from_dense(6, size, Hd, 6, &H), FRIX_OK);
    ck_assert_int_eq(frix_matrix_from_dense(6, 6, Md, 6, &M), FRIX_OK);
    frix_problem *local = NULL, *global = NULL;
    if (size == 5) {
        ck_assert_int_eq(frix_problem_rolling_local(W, q, &mu, &mu_r, 1, &local), FRIX_OK);
        ck_assert_int_eq(frix_problem_rolling_global(M, H, f, q, &mu, &mu_r, 1, &global), FRIX_OK);
    } else {
        ck_assert_int_eq(frix_problem_spinning_local(W, q, &mu, &mu_r, &mu_s, 1, &local), FRIX_OK);
        ck_assert_int_eq(frix_problem_spinning_global(M, H, f, q, &mu, &mu_r, &mu_s, 1, &global), FRIX_OK);
    }
    check_diverges(local, size, 0, cold);
    check_diverges(local, size, 0, warm);
    check_diverges(global, size, 6, cold);
    check_diverges(global, size, 6, warm);
    frix_problem_free(local);
    frix_problem_free(global);
    frix_matrix_free(W);
    frix_matrix_free(M);
    frix_matrix_free(H);
}
