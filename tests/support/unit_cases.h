/* Small global problems posed in a chosen system of units (a length, a mass and a time unit),
 * for the tests of the default measure's freedom from units: a rigid cube on a plane and a
 * static elastic block of springs. Dense M and H, made into a frix_problem. Public API only. */
#ifndef FRIX_UNIT_CASES_H
#define FRIX_UNIT_CASES_H

#include <frix/frix.h>
#include <stdint.h>

/* Units: a length, a mass and a time unit, as factors from m, kg, s (mm: L = 1000). A value
 * of dimension mass^a length^b time^c is multiplied by Mu^a L^b T^-c. */
typedef struct {
    const char *name;
    double L, Mu, T;
} units;
/* m/kg/s, mm/kg/s and m/g/ms. */
extern const units kUnits[3];

typedef struct {
    int64_t n, nc;
    double *M, *H, *f, *w, *mu; /* M n x n and H n x 3nc dense, column-major */
    frix_matrix *Mm, *Hm;
    frix_problem *p;
} dense_case;

/* A rigid cube (3 translations, 3 rotations) of 2 kg and side 0.1 m falling (1 m/s) and
 * sliding (0.1 m/s) onto a plane at its 4 bottom corners, a time step of 1 ms, in units u:
 * translations and rotations scale apart, which a measure that mixes them does not survive.
 * FRIX_OK, or the error of making the problem (c is then freed). */
frix_error rigid_cube(dense_case *c, units u);

/* A static elastic block of nx x ny x nz nodes joined by springs of stiffness k (the same in
 * each direction: a stiffness matrix whose free motions are the 3 translations), standing on
 * a plane at its bottom nodes (contact frame: normal z, tangents x, y; gaps 0), loaded on its
 * top nodes by (fx, 0, fz) in all. clamp: the top nodes are also held by springs to the
 * ground (M positive definite); else the contacts alone hold the block. In units u: M is a
 * stiffness (mass / time^2), v a displacement, f and r forces, w a length. */
frix_error elastic_block(dense_case *c, int nx, int ny, int nz, int clamp, double fx, double fz, units u);

void case_free(dense_case *c);

#endif
