/* A rolling-friction test problem: a side x side x layers cubic stack of spheres (diameter 1,
 * touching their neighbours) on the ground, one time step of gravity with a small random
 * horizontal push, masses drawn in [1, 2]. Five entries a contact (frix_problem.h): normal,
 * two tangents (turned by a random angle about the normal), the relative rolling velocity on
 * those tangents. Both forms: global (M diagonal with 6 dofs a sphere, H) and local (W = H^T
 * M^-1 H formed densely: small piles only). Deterministic for a seed. */
#ifndef FRIX_TEST_ROLLING_PILE_H
#define FRIX_TEST_ROLLING_PILE_H

#include <frix/frix.h>
#include <stdint.h>

typedef struct {
    int64_t bodies, n, nc;
    frix_matrix *M, *H, *W;
    double *f, *w, *q, *mu, *mu_r;
    frix_problem *global, *local;
} rolling_pile;

/* 0 on success. */
int rolling_pile_make(int side, int layers, double mu, double mu_r, uint64_t seed, rolling_pile *out);
void rolling_pile_free(rolling_pile *p);

#endif
