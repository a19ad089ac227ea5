/* The scene of the granular clients: polydisperse spheres in a box with four walls (see
 * granular.c for the model), the grid broad phase, contact frames and their blocks of H^T. */
#ifndef FRIX_EXAMPLE_POUR_H
#define FRIX_EXAMPLE_POUR_H

#include <frix/frix.h>
#include <stdint.h>
#include <stdio.h>

#define GRAVITY 9.81
#define DENSITY 2500.0
#define WALLS 5 /* floor, x = 0, x = Lx, y = 0, y = Ly */

typedef struct {
    int64_t n;           /* spheres */
    double *x, *v;       /* 3 per sphere: position; 6 per sphere: velocity, angular velocity */
    double *radius, *mass, *inertia;
    double box[2];       /* Lx, Ly */
    double rmax, rmin;
} world;

/* One contact: sphere a and sphere b (b >= n: wall b - n), normal into a. */
typedef struct {
    int64_t a, b;
    double gap;
    double frame[9]; /* normal, tangent 1, tangent 2 */
} contact;

typedef struct {
    contact *c;
    int64_t count, capacity;
} contacts;

/* What both clients take: the scene and its steps. */
typedef struct {
    int64_t spheres, steps, seed, max_iter, every;
    double h, mu, radius, tol, aspect, floor;
} scene_settings;
void scene_defaults(scene_settings *s);
/* The process keeps the memory it frees (glibc: no mmap for large blocks, no trimming), so that
 * the next step's arrays, about as large as this step's, reuse pages already touched instead of
 * faulting fresh ones in: a step of 10^5-10^6 contacts otherwise spends a large share of its
 * time in page faults. A host's choice, made once at start; elsewhere than glibc it does nothing. */
void keep_freed_memory(void);
/* Option o with value a: 1 when it is one of these (*ok then says whether a is valid for it),
 * else 0. */
int parse_scene_option(const char *o, const char *a, scene_settings *s, int *ok);
/* The scene options, one line each with its default, for --help. */
void scene_help(FILE *out);

/* The scene's spheres (radii in [0.7 radius, radius]) on a jittered lattice `aspect` times as
 * tall as wide, centred on a floor `floor` times as wide as the lattice, small random velocities
 * (the same on every machine for a seed); 0 when out of memory. */
int make_world(const scene_settings *s, world *w);
void free_world(world *w);
/* Kinetic plus potential energy. */
double energy(const world *w);
/* reach[i]: how far sphere i may come in a step of h, twice the h |v| + h^2 g it can move (|v|
 * changes little in a step): find_contacts's margin. */
void step_reach(const world *w, double h, double *reach);
/* The contacts closer than their margin (floor + reach[a] + reach[b]), sorted by (a, b); the
 * grid's arrays are kept between calls. 0 when out of memory. */
int find_contacts(const world *w, double floor_margin, const double *reach, contacts *cs, int64_t **cell_start,
                  int64_t **order, int64_t *cells_capacity);
/* Contact c's two 3 x 6 blocks of H^T (side 0: sphere a, side 1: sphere b; zero for a wall):
 * G[18 side + 6 k + q] for frame vector k and dof q of the sphere (translation, rotation). */
void contact_blocks(const world *w, const contact *c, double G[36]);
/* Contact c's two 3 x 6 blocks of the angular rows: the relative angular velocity of sphere a to
 * sphere b on tangents 1 and 2 (rolling resistance) and on the normal (spinning friction),
 * R[18 side + 6 k + q] as for contact_blocks (zero for a wall). */
void angular_blocks(const world *w, const contact *c, double R[36]);
/* Contact c's two dim x 6 blocks of H^T, B[6 dim side + 6 row + q]: the rows of contact_blocks,
 * then with dim 5 the two rolling rows of angular_blocks, with dim 6 its three rows. */
void contact_blocks_of(const world *w, const contact *c, int dim, double B[72]);
/* H's entries (rows: dofs, 6 a sphere; columns: dim a contact, 3, 5 with the rolling rows or 6
 * with the spinning row too)
 * as triplets (at most 12 dim a contact); their count. */
int64_t assemble_h(const world *w, const contacts *cs, int dim, int64_t *rows, int64_t *cols, double *vals);
/* r: last step's impulse of each pair of `now` found in `before` (sorted), else 0; dim
 * entries a contact. */
void warm_start(const contacts *now, const contacts *before, int dim, const double *r_before, double *r);
/* The step's problem in the local form, W = H^T M^-1 H and q = H^T M^-1 f + w (M diagonal:
 * mdiag, 6 a sphere; dim entries a contact, 5 with mu_r, 6 with mu_s too), titled `title`, written to `path` as
 * an FCLIB file with the step's answer (r, u) as its solution and the warm start r0 the solve
 * began from as guess 1 (its u = W r0 + q), as --dump writes the global form. */
frix_error write_local_form(const world *w, const contacts *cs, int dim, const double *mdiag, const double *f,
                            const double *wv, const double *mu, const double *mu_r, const double *mu_s,
                            const char *title, const double *r, const double *u, const double *r0,
                            const char *path);
/* *p reallocated to n entries (kept as it was when that fails). */
int grow_doubles(double **p, int64_t n);
int grow_indices(int64_t **p, int64_t n);
/* A whole string as a finite double, or as an integer: 1, or 0 (out untouched). */
int parse_double(const char *s, double *out);
int parse_int(const char *s, int64_t *out);

#endif
