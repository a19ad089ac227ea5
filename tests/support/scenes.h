/* Rigid-body scenes that pose one time step of a frictional contact problem, modelling only
 * what each scene needs: cubes, spheres and rods with a diagonal mass matrix, contact points
 * with their frames (normal first, then two tangents), and the free motion.
 *
 *   M v = H r + f,   u = H^T v + w        (global form: what frix_problem_global takes)
 *   u = W r + q,  W = H^T M^-1 H,  q = H^T M^-1 f + w   (local form)
 *
 * with f = M v_prev + h F_ext (r and u are impulses and velocities over the step h). Every
 * scene starts with all contacts closed (gap 0, so w = 0).
 *
 * Scenes (frix_scene_kind):
 *   STACK    `count` cubes stacked on the ground, `per_face` contacts per shared face
 *            (4 is what collision detectors report: W is rank-deficient); masses rise
 *            geometrically from 1 (bottom) to `mass_ratio` (top); a horizontal push of
 *            `load` x mu x (weight of the top cube) on the top cube.
 *   CHAIN    `count` rods hanging one below the other from a fixed hook, one contact per
 *            joint on the axis; masses rise from 1 (top) to `mass_ratio` (bottom); the
 *            bottom rod is pushed sideways by `load` x its weight and moves at `speed`.
 *   SPHERES  a square pyramid of `count` layers of spheres on the ground, each sphere in the
 *            pocket of four below it and touching its neighbours in its layer (redundant
 *            contacts, normals in every direction); masses rise from 1 (bottom layer) to
 *            `mass_ratio` (top).
 *   SLOPE    one cube on a plane inclined by `angle` (radians) about the y axis, `per_face`
 *            contacts under it, moving down the slope at `speed`. The exact answer of the
 *            step is known: it stays put iff tan(angle) <= mu (speed 0), otherwise it slides
 *            with speed + h g (sin - mu cos) and never leaves the plane. With per_face 1
 *            the cube is a particle: its centre of mass sits at the one contact.
 *
 * `scale` is the unit of length (a cube's side, a sphere's diameter, a rod's length); the
 * density is fixed, so masses scale as scale^3. `frame_angle` turns every contact's tangent
 * pair about its normal (friction must not care). Uses the public frix API only.
 */
#ifndef FRIX_SCENES_H
#define FRIX_SCENES_H

#include <frix/frix.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define FRIX_SCENE_GRAVITY 9.81

typedef enum frix_scene_kind {
    FRIX_SCENE_STACK = 0,
    FRIX_SCENE_CHAIN = 1,
    FRIX_SCENE_SPHERES = 2,
    FRIX_SCENE_SLOPE = 3
} frix_scene_kind;

typedef struct frix_scene_params {
    frix_scene_kind kind;
    int count;          /* cubes, rods or layers (>= 1) */
    double mass_ratio;  /* heaviest / lightest body, >= 1 */
    double mu;          /* friction coefficient of every contact, >= 0 */
    double step;        /* time step h, > 0 */
    double scale;       /* unit of length, > 0 */
    int per_face;       /* STACK, SLOPE: contacts per face, 1..8 (1: the centre; 2..4 corners;
                           5..8 the corners and edge midpoints) */
    double angle;       /* SLOPE: inclination, radians, in [0, pi/2) */
    double speed;       /* SLOPE: initial speed down the slope; CHAIN: of the bottom rod along x */
    double load;        /* STACK, CHAIN: sideways push, see above */
    double frame_angle; /* turns the tangent pair of every contact about its normal, radians */
    double spread;      /* STACK, SLOPE: the face contacts sit at spread x the half side from
                           the face centre, in (0, 1] (tiny: nearly coincident contacts) */
} frix_scene_params;

/* A built scene: the data of both forms, owned (free with frix_scene_free). */
typedef struct frix_scene {
    frix_scene_params params;
    int64_t bodies, nc, n; /* n = 6 bodies */
    double *minv;          /* n: the diagonal of M^-1 (M is diagonal) */
    double *f;             /* n */
    double *w;             /* 3nc */
    double *mu;            /* nc */
    /* Contact a acts on body body[2a] (the normal points into it, sign +1) and on
     * body[2a+1] (sign -1; -1 for the ground). G[36a + 18s + 6i + k] is entry (i, k) of the
     * 3x6 block of H^T for side s: u_a = sum_s G_s (v, omega) of body[2a+s]. */
    int64_t *body;
    double *G;
    double *frame; /* 9 per contact: normal, tangent 1, tangent 2 (world frame) */
    char title[160];
} frix_scene;

/* Both forms built from a scene, with the frix handles (the problems borrow the arrays). */
typedef struct frix_scene_problems {
    frix_matrix *M, *H, *W;
    double *q;
    frix_problem *global, *local;
} frix_scene_problems;

void frix_scene_defaults(frix_scene_kind kind, frix_scene_params *params);
/* Builds the scene; FRIX_ERR_INVALID_ARGUMENT for parameters out of range (message in
 * *why if non-NULL), FRIX_ERR_OUT_OF_MEMORY. */
frix_error frix_scene_build(const frix_scene_params *params, frix_scene *scene, const char **why);
void frix_scene_free(frix_scene *scene);

/* The global problem (M, H, f, w, mu) and the local one (W, q, mu). */
frix_error frix_scene_problems_make(const frix_scene *scene, frix_scene_problems *out);
void frix_scene_problems_free(frix_scene_problems *p);

/* v = M^-1 (H r + f): the body velocities after the step for contact impulses r. */
void frix_scene_velocity(const frix_scene *scene, const double *r, double *v);
/* The impulse of contact a in world coordinates: r_N n + r_T1 t1 + r_T2 t2. */
void frix_scene_world_impulse(const frix_scene *scene, int64_t a, const double *r, double out[3]);

/* ---- The hard-case set (hard_cases.c): named problems for the tests and the benchmarks. */
typedef struct frix_hard_case {
    const char *name;
    const char *what;       /* one sentence: what makes it hard */
    frix_problem *problem;  /* local or global; borrows the data below */
    int all_separating;     /* every contact separates: r = 0 is the answer */
    /* owned */
    frix_scene scene;
    frix_scene_problems forms;
    frix_problem *own;
    frix_matrix *W;
    double *q, *mu;
} frix_hard_case;

int frix_hard_case_count(void);
const char *frix_hard_case_name(int index);
frix_error frix_hard_case_make(int index, frix_hard_case *out);
void frix_hard_case_free(frix_hard_case *c);

#ifdef __cplusplus
}
#endif

#endif /* FRIX_SCENES_H */
