/* A deformable body, posed in the global form only: an nx x ny x nz grid of nodes (3 velocity
 * dofs each, unit spacing) joined to their 6 neighbours by springs, one implicit step of size
 * h = 0.01 with unit nodal masses and spring stiffness k (1e4 in the figures of
 * notes/2026-11-26-fem-hosts.md; 1e8 makes M ill-conditioned) as in an FEM code:
 *
 *   M = I + h^2 k L   (L the grid's graph Laplacian, for each direction),
 *   f = M v_prev + h F_ext,   v_prev = (0.5, 0.1, -1) at every node, F_ext gravity,
 *
 * its bottom layer (nx ny nodes) pressed on the plane z = 0: one contact per node, normal
 * e_z, tangents e_x and e_y, mu 0.3. With gap = 0 every node touches the plane; with gap > 0
 * node a lies gap x (a pseudo-random number in [0, 1)) above it and w_T = gap (0.2 (i - nx/2),
 * 0.1 (j - ny/2)) (a shearing plane), so that nodes stick, slide and separate.
 * M^-1 couples every node of a direction, so W = H^T M^-1 H would be dense: 3 (nx ny)^2
 * entries; `frix_scene elastic-grid` writes such problems, the global campaign of
 * docs/reports/benchmarks.md uses them.
 * Uses the public frix API only. */
#ifndef FRIX_ELASTIC_GRID_H
#define FRIX_ELASTIC_GRID_H

#include <frix/frix.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The problem borrows the other members (frix_problem_global): free them together. */
typedef struct frix_elastic_grid {
    frix_problem *problem;
    frix_matrix *M, *H;
    double *f, *w, *mu;
} frix_elastic_grid;

/* nx, ny, nz >= 1 with 3 nx ny nz < 2^31; gap >= 0; stiffness > 0, finite.
 * FRIX_ERR_INVALID_ARGUMENT otherwise, FRIX_ERR_OUT_OF_MEMORY; *out is left empty (safe to
 * free) on failure. */
frix_error frix_elastic_grid_make(int nx, int ny, int nz, double gap, double stiffness, frix_elastic_grid *out);
/* The same grid without masses, a static problem held by its contacts alone: M = h^2 k L with
 * k = 1e4 (singular: each direction's translation is free), gap 0, and the load (fx, 0, fz) at
 * every node. Fails as frix_elastic_grid_make, and where fx or fz is not finite. */
frix_error frix_elastic_grid_make_floating(int nx, int ny, int nz, double fx, double fz, frix_elastic_grid *out);
void frix_elastic_grid_free(frix_elastic_grid *grid);

#ifdef __cplusplus
}
#endif

#endif
