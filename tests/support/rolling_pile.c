#include "rolling_pile.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static double uniform(uint64_t *s) {
    *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(*s >> 11) / 9007199254740992.0;
}

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

/* Column 5c+k of H on body b's dofs (sign +1 for the body the normal points to, -1 for the
 * other): u = v_b - v_a - (w_a + w_b) x (R n) at the contact point, w_R = w_b - w_a. */
static void body_columns(double *H, int64_t n, int64_t c, int64_t b, double sign, const double *nrm,
                         const double *t1, const double *t2, double radius) {
    const double *e[3] = {nrm, t1, t2};
    for (int k = 0; k < 3; ++k) {
        double *col = H + n * (5 * c + k) + 6 * b;
        double exn[3];
        cross(e[k], nrm, exn);
        for (int i = 0; i < 3; ++i) col[i] += sign * e[k][i];
        for (int i = 0; i < 3; ++i) col[3 + i] += radius * exn[i];
    }
    for (int k = 0; k < 2; ++k) {
        double *col = H + n * (5 * c + 3 + k) + 6 * b;
        for (int i = 0; i < 3; ++i) col[3 + i] += sign * e[1 + k][i];
    }
}

int rolling_pile_make(int side, int layers, double mu, double mu_r, uint64_t seed, rolling_pile *out) {
    memset(out, 0, sizeof *out);
    const int64_t bodies = (int64_t)side * side * layers, n = 6 * bodies;
    /* Contacts: the ground under the bottom layer, then each pair of neighbours (+x, +y, +z). */
    int64_t nc = (int64_t)side * side + 3 * bodies;
    const double radius = 0.5, h = 0.01, g = 9.81;
    double *H = calloc((size_t)(n * 5 * nc), sizeof(double));
    double *Mdiag = malloc((size_t)n * sizeof(double)), *vfree = malloc((size_t)n * sizeof(double));
    out->mu = malloc((size_t)nc * sizeof(double));
    out->mu_r = malloc((size_t)nc * sizeof(double));
    if (!H || !Mdiag || !vfree || !out->mu || !out->mu_r) return 1;
    uint64_t s = seed * 2654435761ULL + 1;
    for (int64_t b = 0; b < bodies; ++b) {
        const double m = 1.0 + uniform(&s), inertia = 0.4 * m * radius * radius;
        for (int i = 0; i < 3; ++i) Mdiag[6 * b + i] = m, Mdiag[6 * b + 3 + i] = inertia;
        vfree[6 * b] = 0.05 * (uniform(&s) - 0.5);
        vfree[6 * b + 1] = 0.05 * (uniform(&s) - 0.5);
        vfree[6 * b + 2] = -h * g;
        for (int i = 3; i < 6; ++i) vfree[6 * b + i] = 0.1 * (uniform(&s) - 0.5);
    }
    int64_t c = 0;
#define BODY(x, y, z) ((int64_t)(z) * side * side + (int64_t)(y) * side + (x))
    for (int y = 0; y < side; ++y)
        for (int x = 0; x < side; ++x) {
            const double nrm[3] = {0, 0, 1};
            double t1[3], t2[3];
            frame(nrm, 6.283185307179586 * uniform(&s), t1, t2);
            body_columns(H, n, c, BODY(x, y, 0), 1.0, nrm, t1, t2, radius);
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
                    frame(nrm, 6.283185307179586 * uniform(&s), t1, t2);
                    body_columns(H, n, c, BODY(xb, yb, zb), 1.0, nrm, t1, t2, radius);
                    body_columns(H, n, c, BODY(x, y, z), -1.0, nrm, t1, t2, radius);
                    ++c;
                }
#undef BODY
    nc = c;
    for (int64_t a = 0; a < nc; ++a) out->mu[a] = mu, out->mu_r[a] = mu_r;
    out->bodies = bodies, out->n = n, out->nc = nc;
    const int64_t m = 5 * nc;
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
             frix_matrix_from_dense(m, m, W, m, &out->W) ||
             frix_problem_rolling_global(out->M, out->H, out->f, out->w, out->mu, out->mu_r, nc, &out->global) ||
             frix_problem_rolling_local(out->W, out->q, out->mu, out->mu_r, nc, &out->local);
    free(Md);
    free(W);
    free(H);
    free(Mdiag);
    free(vfree);
    return rc;
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
    memset(p, 0, sizeof *p);
}
