/* The deformable grid of elastic_grid.h. */
#include "elastic_grid.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void frix_elastic_grid_free(frix_elastic_grid *g) {
    if (!g) return;
    frix_problem_free(g->problem);
    frix_matrix_free(g->M);
    frix_matrix_free(g->H);
    free(g->f);
    free(g->w);
    free(g->mu);
    memset(g, 0, sizeof *g);
}

/* The grid with nodal masses `mass` and the load `load` at every node. */
static frix_error make_grid(int nx, int ny, int nz, double gap, double stiffness, double mass, const double load[3],
                            frix_elastic_grid *out) {
    const double h = 0.01, k = stiffness, mu = 0.3;
    memset(out, 0, sizeof *out);
    if (nx < 1 || ny < 1 || nz < 1 || !(gap >= 0.0) || !isfinite(gap) || !(k > 0.0) || !isfinite(k) ||
        3.0 * nx * ny * (double)nz >= 2147483648.0)
        return FRIX_ERR_INVALID_ARGUMENT;
    const int64_t nodes = (int64_t)nx * ny * nz, n = 3 * nodes, nc = (int64_t)nx * ny;
    /* M: at most 7 entries per row (6 neighbours and the diagonal); H: 3 per contact. */
    int64_t *rows = malloc(sizeof *rows * (size_t)(7 * n)), *cols = malloc(sizeof *cols * (size_t)(7 * n));
    double *vals = malloc(sizeof *vals * (size_t)(7 * n));
    out->f = malloc(sizeof *out->f * (size_t)n);
    out->w = calloc((size_t)(3 * nc), sizeof *out->w);
    out->mu = malloc(sizeof *out->mu * (size_t)nc);
    frix_error err = FRIX_OK;
    if (!rows || !cols || !vals || !out->f || !out->w || !out->mu) err = FRIX_ERR_OUT_OF_MEMORY;
    int64_t e = 0;
    for (int l = 0; !err && l < nz; ++l)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) {
                const int64_t a = ((int64_t)l * ny + j) * nx + i;
                const int nb[6][3] = {{i - 1, j, l}, {i + 1, j, l}, {i, j - 1, l},
                                      {i, j + 1, l}, {i, j, l - 1}, {i, j, l + 1}};
                int degree = 0;
                for (int t = 0; t < 6; ++t) {
                    const int I = nb[t][0], J = nb[t][1], L = nb[t][2];
                    if (I < 0 || J < 0 || L < 0 || I >= nx || J >= ny || L >= nz) continue;
                    const int64_t b = ((int64_t)L * ny + J) * nx + I;
                    ++degree;
                    for (int d = 0; d < 3; ++d) rows[e] = 3 * a + d, cols[e] = 3 * b + d, vals[e++] = -h * h * k;
                }
                for (int d = 0; d < 3; ++d) rows[e] = 3 * a + d, cols[e] = 3 * a + d, vals[e++] = mass + h * h * k * degree;
                for (int d = 0; d < 3; ++d) out->f[3 * a + d] = load[d];
            }
    if (!err) err = frix_matrix_from_triplets(n, n, e, rows, cols, vals, &out->M);
    e = 0;
    unsigned state = 12345u; /* a fixed linear congruential sequence: the same file everywhere */
    for (int64_t a = 0; !err && a < nc; ++a) {
        /* node a of the bottom layer: normal z, tangents x and y */
        rows[e] = 3 * a + 2, cols[e] = 3 * a, vals[e++] = 1.0;
        rows[e] = 3 * a, cols[e] = 3 * a + 1, vals[e++] = 1.0;
        rows[e] = 3 * a + 1, cols[e] = 3 * a + 2, vals[e++] = 1.0;
        state = state * 1103515245u + 12345u;
        const int64_t i = a % nx, j = a / nx;
        out->w[3 * a] = gap * (double)((state >> 8) % 10000u) / 10000.0;
        out->w[3 * a + 1] = 0.2 * gap * ((double)i - nx / 2.0);
        out->w[3 * a + 2] = 0.1 * gap * ((double)j - ny / 2.0);
        out->mu[a] = mu;
    }
    if (!err) err = frix_matrix_from_triplets(n, 3 * nc, e, rows, cols, vals, &out->H);
    if (!err) err = frix_problem_global(out->M, out->H, out->f, out->w, out->mu, nc, &out->problem);
    if (!err) err = frix_problem_set_title(out->problem, "elastic grid pressed on a plane (frix_scene elastic-grid)");
    free(rows);
    free(cols);
    free(vals);
    if (err) frix_elastic_grid_free(out);
    return err;
}

frix_error frix_elastic_grid_make(int nx, int ny, int nz, double gap, double stiffness, frix_elastic_grid *out) {
    const double mass = 1.0, h = 0.01, gravity = 9.81;
    const double load[3] = {0.5 * mass, 0.1 * mass, -1.0 * mass - h * gravity * mass};
    return make_grid(nx, ny, nz, gap, stiffness, mass, load, out);
}

frix_error frix_elastic_grid_make_floating(int nx, int ny, int nz, double fx, double fz, frix_elastic_grid *out) {
    const double load[3] = {fx, 0.0, fz};
    if (!isfinite(fx) || !isfinite(fz)) {
        memset(out, 0, sizeof *out);
        return FRIX_ERR_INVALID_ARGUMENT;
    }
    return make_grid(nx, ny, nz, 0.0, 1e4, 0.0, load, out);
}
