/* The hard-case set: scenes pushed to what makes solvers fail (mass ratios up to 1e6,
 * redundant contacts, every friction regime, extreme scales, nearly singular W, all
 * contacts separating, solutions on the cone boundary), plus two small algebraic cases.
 * Used by tests/test_hard_cases.c, and written as FCLIB files by `frix_scene hard-set DIR`
 * for `frix bench`. */
#include "scenes.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum modifier {
    MOD_NONE,
    MOD_SCALE_W,    /* local W x factor (r scales by 1/factor) */
    MOD_SCALE_Q,    /* local q x factor (r scales by factor) */
    MOD_SCALE_M,    /* global M and f x factor (v unchanged, r scales by factor) */
    MOD_MIXED_MU,   /* mu cycles through 0, 1e-3, 0.3, 1, 2 */
    MOD_SEPARATING, /* every body moves up, each faster than the one below */
    ALG_CONE_BOUNDARY, /* one contact whose solution sticks exactly on the cone boundary */
    ALG_ILL            /* one contact with W of condition number 2e10 */
};

typedef struct {
    const char *name, *what;
    int scene; /* frix_scene_kind, or -1 for an algebraic case */
    int count;
    double ratio, mu;
    int per_face;
    double angle, speed, scale, spread;
    int global;
    int modifier;
    double factor;
} case_def;

#define SCENE(kind, count, ratio, mu, pf) kind, count, ratio, mu, pf

static const case_def kCases[] = {
    {"stack_mass1e6", "4 cubes, each heavier up to 1e6 times the bottom one, 4 contacts per face",
     SCENE(FRIX_SCENE_STACK, 4, 1e6, 0.5, 4), 0, 0, 1, 1, 0, MOD_NONE, 1},
    {"stack_mass1e6_global", "the same as a global problem",
     SCENE(FRIX_SCENE_STACK, 4, 1e6, 0.5, 4), 0, 0, 1, 1, 1, MOD_NONE, 1},
    {"chain_mass1e6", "8 hanging rods, the bottom one 1e6 times the top one, pushed sideways",
     SCENE(FRIX_SCENE_CHAIN, 8, 1e6, 0.3, 1), 0, 0, 1, 1, 0, MOD_NONE, 1},
    {"chain_mass1e6_global", "the same as a global problem",
     SCENE(FRIX_SCENE_CHAIN, 8, 1e6, 0.3, 1), 0, 0, 1, 1, 1, MOD_NONE, 1},
    {"spheres_mass1e6", "3-layer pyramid of spheres, top layer 1e6 times the bottom one",
     SCENE(FRIX_SCENE_SPHERES, 3, 1e6, 0.5, 1), 0, 0, 1, 1, 0, MOD_NONE, 1},
    {"stack_8perface", "3 cubes with 8 contacts per face (corners and edge midpoints)",
     SCENE(FRIX_SCENE_STACK, 3, 1, 0.5, 8), 0, 0, 1, 1, 0, MOD_NONE, 1},
    {"stack_8perface_global", "the same as a global problem",
     SCENE(FRIX_SCENE_STACK, 3, 1, 0.5, 8), 0, 0, 1, 1, 1, MOD_NONE, 1},
    {"spheres_mu0", "2-layer pyramid of spheres, frictionless",
     SCENE(FRIX_SCENE_SPHERES, 2, 1, 0.0, 1), 0, 0, 1, 1, 0, MOD_NONE, 1},
    {"spheres_mu1e-3", "2-layer pyramid of spheres, mu = 1e-3",
     SCENE(FRIX_SCENE_SPHERES, 2, 1, 1e-3, 1), 0, 0, 1, 1, 0, MOD_NONE, 1},
    {"spheres_mu0.3", "2-layer pyramid of spheres, mu = 0.3",
     SCENE(FRIX_SCENE_SPHERES, 2, 1, 0.3, 1), 0, 0, 1, 1, 0, MOD_NONE, 1},
    {"spheres_mu1", "2-layer pyramid of spheres, mu = 1",
     SCENE(FRIX_SCENE_SPHERES, 2, 1, 1.0, 1), 0, 0, 1, 1, 0, MOD_NONE, 1},
    {"spheres_mu2", "2-layer pyramid of spheres, mu = 2",
     SCENE(FRIX_SCENE_SPHERES, 2, 1, 2.0, 1), 0, 0, 1, 1, 0, MOD_NONE, 1},
    {"stack_mixed_mu", "3 cubes, mu per contact cycling through 0, 1e-3, 0.3, 1, 2",
     SCENE(FRIX_SCENE_STACK, 3, 1, 0.5, 4), 0, 0, 1, 1, 0, MOD_MIXED_MU, 1},
    {"spheres_mixed_mu_global", "3-layer pyramid, mixed mu, global problem",
     SCENE(FRIX_SCENE_SPHERES, 3, 1, 0.5, 1), 0, 0, 1, 1, 1, MOD_MIXED_MU, 1},
    {"stack_W_x1e8", "3 cubes, W scaled by 1e8",
     SCENE(FRIX_SCENE_STACK, 3, 1, 0.5, 4), 0, 0, 1, 1, 0, MOD_SCALE_W, 1e8},
    {"stack_W_x1e-8", "3 cubes, W scaled by 1e-8",
     SCENE(FRIX_SCENE_STACK, 3, 1, 0.5, 4), 0, 0, 1, 1, 0, MOD_SCALE_W, 1e-8},
    {"stack_q_x1e8", "3 cubes, q scaled by 1e8",
     SCENE(FRIX_SCENE_STACK, 3, 1, 0.5, 4), 0, 0, 1, 1, 0, MOD_SCALE_Q, 1e8},
    {"stack_q_x1e-8", "3 cubes, q scaled by 1e-8",
     SCENE(FRIX_SCENE_STACK, 3, 1, 0.5, 4), 0, 0, 1, 1, 0, MOD_SCALE_Q, 1e-8},
    {"stack_M_x1e8_global", "3 cubes, M and f scaled by 1e8 (global)",
     SCENE(FRIX_SCENE_STACK, 3, 1, 0.5, 4), 0, 0, 1, 1, 1, MOD_SCALE_M, 1e8},
    {"stack_M_x1e-8_global", "3 cubes, M and f scaled by 1e-8 (global)",
     SCENE(FRIX_SCENE_STACK, 3, 1, 0.5, 4), 0, 0, 1, 1, 1, MOD_SCALE_M, 1e-8},
    {"stack_size1e-4", "3 cubes of side 1e-4 (masses 1e-12)",
     SCENE(FRIX_SCENE_STACK, 3, 1, 0.5, 4), 0, 0, 1e-4, 1, 0, MOD_NONE, 1},
    {"stack_size1e3_global", "3 cubes of side 1e3 (masses 1e9), global",
     SCENE(FRIX_SCENE_STACK, 3, 1, 0.5, 4), 0, 0, 1e3, 1, 1, MOD_NONE, 1},
    {"stack_near_coincident", "3 cubes whose 4 face contacts lie within 1e-6 of each other",
     SCENE(FRIX_SCENE_STACK, 3, 1, 0.5, 4), 0, 0, 1, 1e-6, 0, MOD_NONE, 1},
    {"slope_near_coincident_global", "a cube on a slope on 8 contacts within 1e-6 (global)",
     SCENE(FRIX_SCENE_SLOPE, 1, 1, 0.5, 8), 0.3, 0, 1, 1e-6, 1, MOD_NONE, 1},
    {"single_ill_conditioned", "one contact, W with eigenvalues 1, 2 and 1e-10",
     -1, 1, 1, 0.5, 1, 0, 0, 1, 1, 0, ALG_ILL, 1},
    {"stack_separating", "3 cubes all moving apart: r = 0 at once",
     SCENE(FRIX_SCENE_STACK, 3, 1, 0.5, 4), 0, 0, 1, 1, 0, MOD_SEPARATING, 1},
    {"stack_separating_global", "the same as a global problem",
     SCENE(FRIX_SCENE_STACK, 3, 1, 0.5, 4), 0, 0, 1, 1, 1, MOD_SEPARATING, 1},
    {"single_cone_boundary", "one contact sticking exactly on the cone boundary (u = 0)",
     -1, 1, 1, 0.5, 1, 0, 0, 1, 1, 0, ALG_CONE_BOUNDARY, 1},
    {"slope_at_threshold", "a cube on a slope with tan(angle) = mu exactly: every contact on the boundary",
     SCENE(FRIX_SCENE_SLOPE, 1, 1, 0.5, 4), 0.4636476090008061, 0, 1, 1, 0, MOD_NONE, 1},
    {"slope_sliding_global", "a cube sliding down a slope steeper than atan(mu) (global)",
     SCENE(FRIX_SCENE_SLOPE, 1, 1, 0.5, 4), 0.6, 1.0, 1, 1, 1, MOD_NONE, 1},
    {"chain_long", "30 hanging rods",
     SCENE(FRIX_SCENE_CHAIN, 30, 1, 0.3, 1), 0, 0, 1, 1, 0, MOD_NONE, 1},
    {"spheres_4layers", "4-layer pyramid of 30 spheres, 112 contacts",
     SCENE(FRIX_SCENE_SPHERES, 4, 1, 0.3, 1), 0, 0, 1, 1, 0, MOD_NONE, 1},
    {"stack_tall_global", "10 cubes, mass ratio 10, global",
     SCENE(FRIX_SCENE_STACK, 10, 10, 0.5, 4), 0, 0, 1, 1, 1, MOD_NONE, 1},
};

int frix_hard_case_count(void) { return (int)(sizeof kCases / sizeof kCases[0]); }

const char *frix_hard_case_name(int index) {
    return index >= 0 && index < frix_hard_case_count() ? kCases[index].name : NULL;
}

/* The local W scaled by `factor` (a new matrix). */
static frix_error scaled_copy(const frix_matrix *A, double factor, frix_matrix **out) {
    int64_t nnz = 0, cols = frix_matrix_cols(A);
    frix_error err = frix_matrix_to_csc(A, &nnz, NULL, NULL, NULL);
    if (err) return err;
    int64_t *p = calloc((size_t)cols + 1, sizeof *p), *i = calloc((size_t)nnz + 1, sizeof *i);
    double *x = calloc((size_t)nnz + 1, sizeof *x);
    if (!p || !i || !x) err = FRIX_ERR_OUT_OF_MEMORY;
    if (!err) err = frix_matrix_to_csc(A, &nnz, p, i, x);
    if (!err) {
        for (int64_t k = 0; k < nnz; ++k) x[k] *= factor;
        err = frix_matrix_from_csc(frix_matrix_rows(A), cols, p, i, x, out);
    }
    free(p);
    free(i);
    free(x);
    return err;
}

static frix_error algebraic(const case_def *d, frix_hard_case *c) {
    double W[9];
    c->q = calloc(3, sizeof *c->q);
    c->mu = calloc(1, sizeof *c->mu);
    if (!c->q || !c->mu) return FRIX_ERR_OUT_OF_MEMORY;
    c->mu[0] = d->mu;
    if (d->modifier == ALG_CONE_BOUNDARY) {
        /* r* = (1, mu cos phi, mu sin phi) on the boundary, q = -W r*: then u = 0. */
        const double Wd[9] = {2, 0.5, 0, 0.5, 1, 0.25, 0, 0.25, 1.5}, phi = 0.7;
        const double rs[3] = {1, d->mu * cos(phi), d->mu * sin(phi)};
        memcpy(W, Wd, sizeof W);
        for (int i = 0; i < 3; ++i) {
            c->q[i] = 0;
            for (int j = 0; j < 3; ++j) c->q[i] -= W[i + 3 * j] * rs[j];
        }
    } else {
        const double e = 1e-10;
        const double Wd[9] = {1, 0, 0, 0, 1, 1 - e, 0, 1 - e, 1};
        const double q[3] = {-1, 0.3, 0.2};
        memcpy(W, Wd, sizeof W);
        memcpy(c->q, q, sizeof q);
    }
    frix_error err = frix_matrix_from_dense(3, 3, W, 3, &c->W);
    if (!err) err = frix_problem_local(c->W, c->q, c->mu, 1, &c->own);
    c->problem = c->own;
    return err;
}

frix_error frix_hard_case_make(int index, frix_hard_case *c) {
    memset(c, 0, sizeof *c);
    if (index < 0 || index >= frix_hard_case_count()) return FRIX_ERR_INVALID_ARGUMENT;
    const case_def *d = &kCases[index];
    c->name = d->name;
    c->what = d->what;
    c->all_separating = d->modifier == MOD_SEPARATING;
    frix_error err;
    if (d->scene < 0) {
        err = algebraic(d, c);
    } else {
        frix_scene_params p;
        frix_scene_defaults((frix_scene_kind)d->scene, &p);
        p.count = d->count;
        p.mass_ratio = d->ratio;
        p.mu = d->mu;
        p.per_face = d->per_face;
        if (d->scene == FRIX_SCENE_SLOPE) {
            p.angle = d->angle;
            p.speed = d->speed;
        }
        p.scale = d->scale;
        p.spread = d->spread;
        err = frix_scene_build(&p, &c->scene, NULL);
        if (err) return err;
        frix_scene *s = &c->scene;
        if (d->modifier == MOD_MIXED_MU) {
            static const double cycle[5] = {0, 1e-3, 0.3, 1, 2};
            for (int64_t a = 0; a < s->nc; ++a) s->mu[a] = cycle[a % 5];
        } else if (d->modifier == MOD_SCALE_M) {
            for (int64_t j = 0; j < s->n; ++j) {
                s->minv[j] /= d->factor;
                s->f[j] *= d->factor;
            }
        } else if (d->modifier == MOD_SEPARATING) {
            for (int64_t b = 0; b < s->bodies; ++b) s->f[6 * b + 2] += (double)(b + 1) / s->minv[6 * b + 2];
        }
        err = frix_scene_problems_make(s, &c->forms);
        if (err) return err;
        c->problem = d->global ? c->forms.global : c->forms.local;
        if (d->modifier == MOD_SCALE_W || d->modifier == MOD_SCALE_Q) {
            const int64_t m = 3 * s->nc;
            c->q = calloc((size_t)m + 1, sizeof *c->q);
            if (!c->q) return FRIX_ERR_OUT_OF_MEMORY;
            for (int64_t i = 0; i < m; ++i)
                c->q[i] = c->forms.q[i] * (d->modifier == MOD_SCALE_Q ? d->factor : 1.0);
            err = d->modifier == MOD_SCALE_W ? scaled_copy(c->forms.W, d->factor, &c->W)
                                             : scaled_copy(c->forms.W, 1.0, &c->W);
            if (!err) err = frix_problem_local(c->W, c->q, s->mu, s->nc, &c->own);
            c->problem = c->own;
        }
    }
    if (!err) err = frix_problem_set_title(c->problem, d->what);
    return err;
}

void frix_hard_case_free(frix_hard_case *c) {
    if (!c) return;
    frix_problem_free(c->own);
    frix_scene_problems_free(&c->forms);
    frix_scene_free(&c->scene);
    frix_matrix_free(c->W);
    free(c->q);
    free(c->mu);
    memset(c, 0, sizeof *c);
}
