/* A rolling-friction test problem: a side x side x layers cubic stack of spheres (diameter 1,
 * touching their neighbours) on the ground, one time step of gravity with a small random
 * horizontal push and spin, masses drawn in [1, 2]. Five entries a contact (frix_problem.h):
 * normal, two tangents (turned by a random angle about the normal), the relative rolling
 * velocity on those tangents; with spinning friction a sixth, the relative angular velocity
 * about the normal. Both forms: global (M diagonal with 6 dofs a sphere, H) and local (W = H^T
 * M^-1 H formed densely: small piles only). Deterministic for a seed, and the same pile (the
 * same draws) with or without spinning friction. */
#ifndef FRIX_TEST_ROLLING_PILE_H
#define FRIX_TEST_ROLLING_PILE_H

#include <frix/frix.h>
#include <stdint.h>

typedef struct {
    int64_t bodies, n, nc;
    int size; /* entries a contact: 5, or 6 with spinning friction */
    frix_matrix *M, *H, *W;
    double *f, *w, *q, *mu, *mu_r, *mu_s; /* mu_s: NULL without spinning friction */
    frix_problem *global, *local;
} rolling_pile;

/* 0 on success. */
int rolling_pile_make(int side, int layers, double mu, double mu_r, uint64_t seed, rolling_pile *out);
/* The same pile with spinning friction mu_s at every contact. */
int rolling_pile_make_spinning(int side, int layers, double mu, double mu_r, double mu_s, uint64_t seed,
                               rolling_pile *out);
void rolling_pile_free(rolling_pile *p);

/* One contact (size entries: 5, or 6 with spinning friction) that nothing holds in the normal
 * direction, pressed (q_N = -1, or w_N = -1 with the body's normal column of H zero), in both
 * forms: no solution, r_N grows without end. Every solver of rolling problems (rolling-nsgs,
 * rolling-nsn, auto) ends it diverged from a cold and a warm start, early (the Monitor watches
 * the iterate), and answers with a finite r on the scale of its start and of q, never the
 * runaway; u (and v) finite. Check assertions. */
void rolling_check_no_solution(int size);

#endif
