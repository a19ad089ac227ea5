/* Rigid-body scenes (scenes.h): geometry, contact frames, H, M, f, w, mu, and the two forms. */
#include "scenes.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const double kPi = 3.14159265358979323846;

void frix_scene_defaults(frix_scene_kind kind, frix_scene_params *p) {
    memset(p, 0, sizeof *p);
    p->kind = kind;
    p->count = kind == FRIX_SCENE_SLOPE ? 1 : kind == FRIX_SCENE_SPHERES ? 3 : 3;
    if (kind == FRIX_SCENE_CHAIN) p->count = 5;
    p->mass_ratio = 1.0;
    p->mu = 0.5;
    p->step = 0.01;
    p->scale = 1.0;
    p->per_face = 4;
    p->angle = 0.2;
    p->speed = 0.0;
    p->load = kind == FRIX_SCENE_STACK ? 0.4 : kind == FRIX_SCENE_CHAIN ? 0.1 : 0.0;
    p->frame_angle = 0.0;
    p->spread = 1.0;
}

/* ------------------------------------------------------------------ small vectors */

static void cross(const double a[3], const double b[3], double out[3]) {
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

static double dot(const double a[3], const double b[3]) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void normalize(double a[3]) {
    double n = sqrt(dot(a, a));
    for (int k = 0; k < 3; ++k) a[k] /= n;
}

/* ------------------------------------------------------------------ building */

typedef struct {
    frix_scene *s;
    double *center; /* 3 per body */
    int64_t next;   /* contacts added so far */
} builder;

/* Body b: mass m, principal moments (about the world axes) I[3], initial velocity v0, and
 * an external force F (gravity is added here). */
static void set_body(builder *b, int64_t body, const double c[3], double m, const double I[3],
                     const double v0[3], const double F[3]) {
    frix_scene *s = b->s;
    const double h = s->params.step;
    for (int k = 0; k < 3; ++k) {
        b->center[3 * body + k] = c[k];
        s->minv[6 * body + k] = 1.0 / m;
        s->minv[6 * body + 3 + k] = 1.0 / I[k];
        double g = k == 2 ? -FRIX_SCENE_GRAVITY * m : 0.0;
        s->f[6 * body + k] = m * v0[k] + h * (g + F[k]);
        s->f[6 * body + 3 + k] = 0.0; /* no initial spin */
    }
}

/* A contact at `point` with normal n pointing into body `pos` (away from body `neg`, -1 for
 * the ground). t1 (may be NULL) fixes the first tangent, which must be orthogonal to n. */
static void add_contact(builder *b, int64_t pos, int64_t neg, const double point[3],
                        const double normal[3], const double *t1_hint) {
    frix_scene *s = b->s;
    const int64_t a = b->next++;
    double n[3] = {normal[0], normal[1], normal[2]}, t1[3], t2[3];
    normalize(n);
    if (t1_hint) {
        memcpy(t1, t1_hint, sizeof t1);
    } else {
        const double ey[3] = {0, 1, 0}, ez[3] = {0, 0, 1};
        cross(fabs(n[2]) > 0.9 ? ey : ez, n, t1);
    }
    normalize(t1);
    cross(n, t1, t2);
    /* Turn the tangent pair by frame_angle about n. */
    const double c = cos(s->params.frame_angle), sn = sin(s->params.frame_angle);
    double *fr = &s->frame[9 * a];
    for (int k = 0; k < 3; ++k) {
        fr[k] = n[k];
        fr[3 + k] = c * t1[k] + sn * t2[k];
        fr[6 + k] = -sn * t1[k] + c * t2[k];
    }
    s->mu[a] = s->params.mu;
    s->body[2 * a] = pos;
    s->body[2 * a + 1] = neg;
    for (int side = 0; side < 2; ++side) {
        double *G = &s->G[36 * a + 18 * side];
        const int64_t body = s->body[2 * a + side];
        if (body < 0) {
            memset(G, 0, 18 * sizeof *G);
            continue;
        }
        const double sign = side == 0 ? 1.0 : -1.0;
        double d[3], dxe[3];
        for (int k = 0; k < 3; ++k) d[k] = point[k] - b->center[3 * body + k];
        for (int i = 0; i < 3; ++i) {
            cross(d, &fr[3 * i], dxe); /* e . (omega x d) = omega . (d x e) */
            for (int k = 0; k < 3; ++k) {
                G[6 * i + k] = sign * fr[3 * i + k];
                G[6 * i + 3 + k] = sign * dxe[k];
            }
        }
    }
    for (int i = 0; i < 3; ++i) s->w[3 * a + i] = 0.0; /* closed contacts, no gap */
}

/* The in-plane offsets (x, y) of contact k of `per_face` on a square face, unit half side. */
static void face_offset(int per_face, int k, double out[2]) {
    static const double pts[8][2] = {{-1, -1}, {1, 1}, {1, -1}, {-1, 1},
                                     {0, -1},  {0, 1}, {-1, 0}, {1, 0}};
    if (per_face == 1) {
        out[0] = out[1] = 0.0;
    } else {
        out[0] = pts[k][0];
        out[1] = pts[k][1];
    }
}

static double mass_at(const frix_scene_params *p, int64_t i, int64_t last) {
    double t = last > 0 ? (double)i / (double)last : 1.0;
    return pow(p->mass_ratio, t) * p->scale * p->scale * p->scale;
}

static frix_error allocate(frix_scene *s, int64_t bodies, int64_t nc) {
    s->bodies = bodies;
    s->nc = nc;
    s->n = 6 * bodies;
    s->minv = calloc((size_t)s->n + 1, sizeof *s->minv);
    s->f = calloc((size_t)s->n + 1, sizeof *s->f);
    s->w = calloc(3 * (size_t)nc + 1, sizeof *s->w);
    s->mu = calloc((size_t)nc + 1, sizeof *s->mu);
    s->body = calloc(2 * (size_t)nc + 1, sizeof *s->body);
    s->G = calloc(36 * (size_t)nc + 1, sizeof *s->G);
    s->frame = calloc(9 * (size_t)nc + 1, sizeof *s->frame);
    if (!s->minv || !s->f || !s->w || !s->mu || !s->body || !s->G || !s->frame)
        return FRIX_ERR_OUT_OF_MEMORY;
    return FRIX_OK;
}

static void build_stack(builder *b) {
    frix_scene *s = b->s;
    const frix_scene_params *p = &s->params;
    const double side = p->scale, half = p->spread * side / 2;
    const int64_t boxes = p->count;
    for (int64_t k = 0; k < boxes; ++k) {
        const double m = mass_at(p, k, boxes - 1), I = m * side * side / 6.0;
        const double c[3] = {0, 0, side / 2 + (double)k * side}, In[3] = {I, I, I}, v0[3] = {0, 0, 0};
        double F[3] = {0, 0, 0};
        if (k == boxes - 1) F[0] = p->load * p->mu * m * FRIX_SCENE_GRAVITY;
        set_body(b, k, c, m, In, v0, F);
    }
    const double up[3] = {0, 0, 1}, ex[3] = {1, 0, 0};
    for (int64_t k = 0; k < boxes; ++k)
        for (int j = 0; j < p->per_face; ++j) {
            double off[2];
            face_offset(p->per_face, j, off);
            const double pt[3] = {off[0] * half, off[1] * half, (double)k * side};
            add_contact(b, k, k - 1, pt, up, ex);
        }
}

static void build_chain(builder *b) {
    frix_scene *s = b->s;
    const frix_scene_params *p = &s->params;
    const double L = p->scale, a = 0.2 * L;
    const int64_t rods = p->count;
    for (int64_t k = 0; k < rods; ++k) {
        const double m = mass_at(p, k, rods - 1);
        const double c[3] = {0, 0, -((double)k + 0.5) * L};
        const double I[3] = {m * (a * a + L * L) / 12, m * (a * a + L * L) / 12, m * a * a / 6};
        double v0[3] = {0, 0, 0}, F[3] = {0, 0, 0};
        if (k == rods - 1) {
            v0[0] = p->speed;
            F[0] = p->load * m * FRIX_SCENE_GRAVITY;
        }
        set_body(b, k, c, m, I, v0, F);
    }
    const double up[3] = {0, 0, 1}, ex[3] = {1, 0, 0};
    for (int64_t k = 0; k < rods; ++k) {
        const double pt[3] = {0, 0, -(double)k * L};
        add_contact(b, k, k - 1, pt, up, ex); /* rod k hangs on rod k-1 (the hook for k = 0) */
    }
}

static int64_t sphere_index(int64_t layers, int64_t k, int64_t i, int64_t j) {
    int64_t base = 0;
    for (int64_t l = 0; l < k; ++l) base += (layers - l) * (layers - l);
    return base + i * (layers - k) + j;
}

static void build_spheres(builder *b) {
    frix_scene *s = b->s;
    const frix_scene_params *p = &s->params;
    const double R = p->scale / 2;
    const int64_t L = p->count;
    for (int64_t k = 0; k < L; ++k)
        for (int64_t i = 0; i < L - k; ++i)
            for (int64_t j = 0; j < L - k; ++j) {
                const double m = mass_at(p, k, L - 1), I = 0.4 * m * R * R;
                const double c[3] = {(double)(2 * i + k) * R, (double)(2 * j + k) * R,
                                     R + (double)k * R * sqrt(2.0)};
                const double In[3] = {I, I, I}, zero[3] = {0, 0, 0};
                set_body(b, sphere_index(L, k, i, j), c, m, In, zero, zero);
            }
    for (int64_t k = 0; k < L; ++k) {
        const int64_t nk = L - k;
        for (int64_t i = 0; i < nk; ++i)
            for (int64_t j = 0; j < nk; ++j) {
                const int64_t me = sphere_index(L, k, i, j);
                const double *c = &b->center[3 * me];
                if (k == 0) {
                    const double pt[3] = {c[0], c[1], 0}, up[3] = {0, 0, 1};
                    add_contact(b, me, -1, pt, up, NULL);
                } else {
                    for (int64_t di = 0; di < 2; ++di)
                        for (int64_t dj = 0; dj < 2; ++dj) {
                            const int64_t low = sphere_index(L, k - 1, i + di, j + dj);
                            const double *cl = &b->center[3 * low];
                            double n[3], pt[3];
                            for (int e = 0; e < 3; ++e) {
                                n[e] = c[e] - cl[e];
                                pt[e] = (c[e] + cl[e]) / 2;
                            }
                            add_contact(b, me, low, pt, n, NULL);
                        }
                }
                /* Neighbours in the layer: towards +x and +y. */
                for (int dir = 0; dir < 2; ++dir) {
                    const int64_t ni = i + (dir == 0), nj = j + (dir == 1);
                    if (ni >= nk || nj >= nk) continue;
                    const int64_t other = sphere_index(L, k, ni, nj);
                    const double *co = &b->center[3 * other];
                    double n[3], pt[3];
                    for (int e = 0; e < 3; ++e) {
                        n[e] = co[e] - c[e];
                        pt[e] = (c[e] + co[e]) / 2;
                    }
                    add_contact(b, other, me, pt, n, NULL);
                }
            }
    }
}

static void build_slope(builder *b) {
    frix_scene *s = b->s;
    const frix_scene_params *p = &s->params;
    const double side = p->scale, half = p->spread * side / 2, th = p->angle;
    const double n[3] = {sin(th), 0, cos(th)}, d[3] = {cos(th), 0, -sin(th)}, ey[3] = {0, 1, 0};
    const double m = p->mass_ratio * side * side * side, I = m * side * side / 6;
    double c[3], v0[3];
    /* One contact: a particle, its centre of mass at the contact (else friction would tip
     * it over the single point). */
    for (int k = 0; k < 3; ++k) {
        c[k] = p->per_face == 1 ? 0.0 : n[k] * side / 2;
        v0[k] = p->speed * d[k];
    }
    const double In[3] = {I, I, I}, zero[3] = {0, 0, 0};
    set_body(b, 0, c, m, In, v0, zero);
    for (int j = 0; j < p->per_face; ++j) {
        double off[2], pt[3];
        face_offset(p->per_face, j, off);
        for (int k = 0; k < 3; ++k) pt[k] = off[0] * half * d[k] + off[1] * half * ey[k];
        add_contact(b, 0, -1, pt, n, d);
    }
}

frix_error frix_scene_build(const frix_scene_params *params, frix_scene *s, const char **why) {
    const char *dummy;
    if (!why) why = &dummy;
    *why = "";
    memset(s, 0, sizeof *s);
    if (!params) {
        *why = "no parameters";
        return FRIX_ERR_INVALID_ARGUMENT;
    }
    const frix_scene_params *p = params;
    if (p->kind < FRIX_SCENE_STACK || p->kind > FRIX_SCENE_SLOPE) *why = "unknown scene kind";
    else if (p->count < 1 || p->count > (p->kind == FRIX_SCENE_SPHERES ? 30 : 10000))
        *why = "count out of range (1..10000, spheres 1..30 layers)";
    else if (!(p->mass_ratio >= 1.0 && p->mass_ratio <= 1e12)) *why = "mass ratio outside [1, 1e12]";
    else if (!(p->mu >= 0.0 && p->mu <= 100.0)) *why = "mu outside [0, 100]";
    else if (!(p->step > 0.0 && p->step <= 10.0)) *why = "time step outside (0, 10]";
    else if (!(p->scale >= 1e-12 && p->scale <= 1e12)) *why = "scale outside [1e-12, 1e12]";
    else if (p->per_face < 1 || p->per_face > 8) *why = "per_face outside 1..8";
    else if (!(p->angle >= 0.0 && p->angle < kPi / 2)) *why = "angle outside [0, pi/2)";
    else if (!isfinite(p->speed) || !isfinite(p->load) || !isfinite(p->frame_angle))
        *why = "speed, load and frame angle must be finite";
    else if (!(p->spread > 0.0 && p->spread <= 1.0)) *why = "spread outside (0, 1]";
    if (**why) return FRIX_ERR_INVALID_ARGUMENT;
    s->params = *p;

    int64_t bodies = 0, nc = 0;
    const int64_t L = p->count;
    switch (p->kind) {
    case FRIX_SCENE_STACK:
        bodies = L;
        nc = L * p->per_face;
        break;
    case FRIX_SCENE_CHAIN:
        bodies = nc = L;
        break;
    case FRIX_SCENE_SPHERES:
        for (int64_t k = 0; k < L; ++k) {
            const int64_t nk = L - k;
            bodies += nk * nk;
            nc += 2 * nk * (nk - 1) + (k == 0 ? nk * nk : 4 * nk * nk);
        }
        break;
    case FRIX_SCENE_SLOPE:
        bodies = 1;
        nc = p->per_face;
        break;
    }
    frix_error err = allocate(s, bodies, nc);
    builder b = {s, calloc(3 * (size_t)bodies + 1, sizeof(double)), 0};
    if (!err && !b.center) err = FRIX_ERR_OUT_OF_MEMORY;
    if (err) {
        free(b.center);
        frix_scene_free(s);
        *why = "out of memory";
        return err;
    }
    static const char *const names[] = {"stack of cubes", "hanging chain", "pile of spheres",
                                        "cube on a slope"};
    switch (p->kind) {
    case FRIX_SCENE_STACK: build_stack(&b); break;
    case FRIX_SCENE_CHAIN: build_chain(&b); break;
    case FRIX_SCENE_SPHERES: build_spheres(&b); break;
    case FRIX_SCENE_SLOPE: build_slope(&b); break;
    }
    free(b.center);
    snprintf(s->title, sizeof s->title,
             "frix scene: %s, count %d, mass ratio %g, mu %g, h %g, scale %g, %lld contacts",
             names[p->kind], p->count, p->mass_ratio, p->mu, p->step, p->scale, (long long)nc);
    return FRIX_OK;
}

void frix_scene_free(frix_scene *s) {
    if (!s) return;
    free(s->minv);
    free(s->f);
    free(s->w);
    free(s->mu);
    free(s->body);
    free(s->G);
    free(s->frame);
    memset(s, 0, sizeof *s);
}

/* ------------------------------------------------------------------ the two forms */

frix_error frix_scene_problems_make(const frix_scene *s, frix_scene_problems *out) {
    memset(out, 0, sizeof *out);
    const int64_t nc = s->nc, nb = s->bodies;
    /* Contacts of each body (CSR-like): at most 2 nc entries in all. */
    int64_t *start = calloc((size_t)nb + 2, sizeof *start);
    int64_t *list = calloc(2 * (size_t)nc + 1, sizeof *list); /* 2a + side */
    int64_t *fill = calloc((size_t)nb + 1, sizeof *fill);
    int64_t nblocks = 0;
    frix_error err = start && list && fill ? FRIX_OK : FRIX_ERR_OUT_OF_MEMORY;
    if (!err) {
        for (int64_t e = 0; e < 2 * nc; ++e)
            if (s->body[e] >= 0) ++start[s->body[e] + 1];
        for (int64_t b = 0; b < nb; ++b) {
            nblocks += start[b + 1] * start[b + 1];
            start[b + 1] += start[b];
        }
        for (int64_t e = 0; e < 2 * nc; ++e)
            if (s->body[e] >= 0) list[start[s->body[e]] + fill[s->body[e]]++] = e;
    }
    /* W by blocks: for each body, every pair of its contacts. H by blocks: 2 per side. */
    int64_t *wr = NULL, *wc = NULL, *hr = NULL, *hc = NULL, *mr = NULL;
    double *wv = NULL, *hv = NULL, *mv = NULL;
    if (!err) {
        wr = calloc((size_t)nblocks + 1, sizeof *wr);
        wc = calloc((size_t)nblocks + 1, sizeof *wc);
        wv = calloc(9 * (size_t)nblocks + 1, sizeof *wv);
        hr = calloc(4 * (size_t)nc + 1, sizeof *hr);
        hc = calloc(4 * (size_t)nc + 1, sizeof *hc);
        hv = calloc(36 * (size_t)nc + 1, sizeof *hv);
        mr = calloc(2 * (size_t)nb + 1, sizeof *mr);
        mv = calloc(18 * (size_t)nb + 1, sizeof *mv);
        out->q = calloc(3 * (size_t)nc + 1, sizeof *out->q);
        if (!wr || !wc || !wv || !hr || !hc || !hv || !mr || !mv || !out->q) err = FRIX_ERR_OUT_OF_MEMORY;
    }
    if (!err) {
        int64_t k = 0;
        for (int64_t b = 0; b < nb; ++b) {
            const double *mi = &s->minv[6 * b];
            for (int64_t x = start[b]; x < start[b + 1]; ++x)
                for (int64_t y = start[b]; y < start[b + 1]; ++y) {
                    const int64_t ea = list[x], ec = list[y];
                    const double *Ga = &s->G[18 * ea], *Gc = &s->G[18 * ec]; /* 36a + 18 side */
                    double *blk = &wv[9 * k];
                    for (int i = 0; i < 3; ++i)
                        for (int j = 0; j < 3; ++j) {
                            double sum = 0;
                            for (int d = 0; d < 6; ++d) sum += Ga[6 * i + d] * mi[d] * Gc[6 * j + d];
                            blk[i + 3 * j] = sum;
                        }
                    wr[k] = ea / 2;
                    wc[k] = ec / 2;
                    ++k;
                }
        }
        int64_t nh = 0;
        for (int64_t e = 0; e < 2 * nc; ++e) {
            const int64_t b = s->body[e];
            if (b < 0) continue;
            const double *G = &s->G[18 * e];
            for (int half = 0; half < 2; ++half) {
                double *blk = &hv[9 * nh];
                for (int i = 0; i < 3; ++i)
                    for (int d = 0; d < 3; ++d) blk[d + 3 * i] = G[6 * i + 3 * half + d];
                hr[nh] = 2 * b + half;
                hc[nh] = e / 2;
                ++nh;
            }
        }
        for (int64_t b = 0; b < 2 * nb; ++b) {
            mr[b] = b;
            for (int d = 0; d < 3; ++d) mv[9 * b + 4 * d] = 1.0 / s->minv[3 * b + d];
        }
        /* q = H^T M^-1 f + w */
        for (int64_t e = 0; e < 2 * nc; ++e) {
            const int64_t b = s->body[e];
            if (b < 0) continue;
            const double *G = &s->G[18 * e];
            for (int i = 0; i < 3; ++i)
                for (int d = 0; d < 6; ++d) out->q[3 * (e / 2) + i] += G[6 * i + d] * s->minv[6 * b + d] * s->f[6 * b + d];
        }
        for (int64_t i = 0; i < 3 * nc; ++i) out->q[i] += s->w[i];
        err = frix_matrix_from_blocks(nc, nc, k, wr, wc, wv, &out->W);
        if (!err) err = frix_matrix_from_blocks(2 * nb, nc, nh, hr, hc, hv, &out->H);
        if (!err) err = frix_matrix_from_blocks(2 * nb, 2 * nb, 2 * nb, mr, mr, mv, &out->M);
        if (!err) err = frix_problem_local(out->W, out->q, s->mu, nc, &out->local);
        if (!err) err = frix_problem_global(out->M, out->H, s->f, s->w, s->mu, nc, &out->global);
        if (!err) err = frix_problem_set_title(out->local, s->title);
        if (!err) err = frix_problem_set_title(out->global, s->title);
    }
    free(start);
    free(list);
    free(fill);
    free(wr);
    free(wc);
    free(wv);
    free(hr);
    free(hc);
    free(hv);
    free(mr);
    free(mv);
    if (err) frix_scene_problems_free(out);
    return err;
}

void frix_scene_problems_free(frix_scene_problems *p) {
    if (!p) return;
    frix_problem_free(p->local);
    frix_problem_free(p->global);
    frix_matrix_free(p->W);
    frix_matrix_free(p->H);
    frix_matrix_free(p->M);
    free(p->q);
    memset(p, 0, sizeof *p);
}

void frix_scene_velocity(const frix_scene *s, const double *r, double *v) {
    for (int64_t j = 0; j < s->n; ++j) v[j] = s->f[j];
    for (int64_t e = 0; e < 2 * s->nc; ++e) {
        const int64_t b = s->body[e];
        if (b < 0) continue;
        const double *G = &s->G[18 * e], *ra = &r[3 * (e / 2)];
        for (int i = 0; i < 3; ++i)
            for (int d = 0; d < 6; ++d) v[6 * b + d] += G[6 * i + d] * ra[i];
    }
    for (int64_t j = 0; j < s->n; ++j) v[j] *= s->minv[j];
}

void frix_scene_world_impulse(const frix_scene *s, int64_t a, const double *r, double out[3]) {
    const double *fr = &s->frame[9 * a], *ra = &r[3 * a];
    for (int k = 0; k < 3; ++k) out[k] = ra[0] * fr[k] + ra[1] * fr[3 + k] + ra[2] * fr[6 + k];
}
