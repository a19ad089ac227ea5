/* Small global problems in a chosen system of units (unit_cases.h). */
#include "unit_cases.h"

#include <stdlib.h>

const units kUnits[3] = {{"m/kg/s", 1, 1, 1}, {"mm/kg/s", 1000, 1, 1}, {"m/g/ms", 1, 1000, 1000}};

static void case_alloc(dense_case *c, int64_t n, int64_t nc) {
    c->n = n, c->nc = nc;
    c->Mm = c->Hm = NULL;
    c->p = NULL;
    c->M = calloc((size_t)(n * n), sizeof(double));
    c->H = calloc((size_t)(n * 3 * nc), sizeof(double));
    c->f = calloc((size_t)n, sizeof(double));
    c->w = calloc((size_t)(3 * nc), sizeof(double));
    c->mu = calloc((size_t)nc, sizeof(double));
}

static frix_error case_make(dense_case *c) {
    frix_error e = frix_matrix_from_dense(c->n, c->n, c->M, c->n, &c->Mm);
    if (!e) e = frix_matrix_from_dense(c->n, 3 * c->nc, c->H, c->n, &c->Hm);
    if (!e) e = frix_problem_global(c->Mm, c->Hm, c->f, c->w, c->mu, c->nc, &c->p);
    if (e) case_free(c);
    return e;
}

void case_free(dense_case *c) {
    frix_problem_free(c->p);
    frix_matrix_free(c->Mm);
    frix_matrix_free(c->Hm);
    free(c->M), free(c->H), free(c->f), free(c->w), free(c->mu);
}

frix_error rigid_cube(dense_case *c, units u) {
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
    return case_make(c);
}

frix_error elastic_block(dense_case *c, int nx, int ny, int nz, int clamp, double fx, double fz, units u) {
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
    return case_make(c);
}

