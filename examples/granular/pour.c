/* The scene of the granular clients (granular.c, granular_mpi.c): spheres in a box, the
 * broad phase, the contacts' frames and their blocks of H^T. Public frix API only. */
#include "pour.h"

#include <errno.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* xorshift64*: the scene is the same on every machine for a seed. */
static double uniform(uint64_t *s) {
    *s ^= *s >> 12;
    *s ^= *s << 25;
    *s ^= *s >> 27;
    return (double)((*s * 2685821657736338717ULL) >> 11) * (1.0 / 9007199254740992.0);
}

/* The initial state: a lattice aspect times as tall as wide (to the last layer), each site
 * jittered, in the middle of a floor `floor` times as wide (the walls stand at its edges). */
int make_world(const scene_settings *s, world *w) {
    const int64_t n = s->spheres, seed = s->seed;
    const double aspect = s->aspect, radius = s->radius;
    w->n = n;
    w->x = malloc(sizeof *w->x * 3 * (size_t)n);
    w->v = malloc(sizeof *w->v * 6 * (size_t)n);
    w->radius = malloc(sizeof *w->radius * (size_t)n);
    w->mass = malloc(sizeof *w->mass * (size_t)n);
    w->inertia = malloc(sizeof *w->inertia * (size_t)n);
    if (!w->x || !w->v || !w->radius || !w->mass || !w->inertia) return 0;
    uint64_t rng = 0x9E3779B97F4A7C15ULL ^ (uint64_t)(seed + 1) * 0xBF58476D1CE4E5B9ULL;
    const double R = radius, spacing = 2.2 * R;
    int64_t side = 1;
    while (aspect * (double)(side * side * side) < (double)n) ++side;
    w->rmax = R;
    w->rmin = 0.7 * R;
    w->box[0] = w->box[1] = s->floor * (double)side * spacing;
    const double offset = 0.5 * (s->floor - 1.0) * (double)side * spacing;
    for (int64_t i = 0; i < n; ++i) {
        const int64_t ix = i % side, iy = (i / side) % side, iz = i / (side * side);
        const double r = R * (0.7 + 0.3 * uniform(&rng));
        w->radius[i] = r;
        w->mass[i] = DENSITY * 4.0 / 3.0 * M_PI * r * r * r;
        w->inertia[i] = 0.4 * w->mass[i] * r * r;
        const double slack = 0.5 * spacing - r;
        w->x[3 * i] = offset + ((double)ix + 0.5) * spacing + slack * (2.0 * uniform(&rng) - 1.0);
        w->x[3 * i + 1] = offset + ((double)iy + 0.5) * spacing + slack * (2.0 * uniform(&rng) - 1.0);
        w->x[3 * i + 2] = ((double)iz + 0.5) * spacing;
        for (int k = 0; k < 6; ++k) w->v[6 * i + k] = k < 3 ? 0.05 * (2.0 * uniform(&rng) - 1.0) : 0.0;
    }
    return 1;
}

void free_world(world *w) {
    free(w->x);
    free(w->v);
    free(w->radius);
    free(w->mass);
    free(w->inertia);
}

double energy(const world *w) {
    double e = 0.0;
    for (int64_t i = 0; i < w->n; ++i) {
        const double *v = &w->v[6 * i];
        e += 0.5 * w->mass[i] * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) +
             0.5 * w->inertia[i] * (v[3] * v[3] + v[4] * v[4] + v[5] * v[5]) + w->mass[i] * GRAVITY * w->x[3 * i + 2];
    }
    return e;
}

/* Tangents of normal n: t1 across the axis least aligned with n, t2 = n x t1. */
static void make_frame(const double n[3], double frame[9]) {
    double a[3] = {0.0, 0.0, 0.0};
    const double ax = fabs(n[0]), ay = fabs(n[1]), az = fabs(n[2]);
    a[ax <= ay && ax <= az ? 0 : (ay <= az ? 1 : 2)] = 1.0;
    double t1[3] = {n[1] * a[2] - n[2] * a[1], n[2] * a[0] - n[0] * a[2], n[0] * a[1] - n[1] * a[0]};
    const double len = sqrt(t1[0] * t1[0] + t1[1] * t1[1] + t1[2] * t1[2]);
    for (int k = 0; k < 3; ++k) t1[k] /= len;
    const double t2[3] = {n[1] * t1[2] - n[2] * t1[1], n[2] * t1[0] - n[0] * t1[2], n[0] * t1[1] - n[1] * t1[0]};
    for (int k = 0; k < 3; ++k) {
        frame[k] = n[k];
        frame[3 + k] = t1[k];
        frame[6 + k] = t2[k];
    }
}

static int push(contacts *cs, int64_t a, int64_t b, double gap, const double n[3]) {
    if (cs->count == cs->capacity) {
        const int64_t cap = cs->capacity ? 2 * cs->capacity : 1024;
        contact *c = realloc(cs->c, sizeof *c * (size_t)cap);
        if (!c) return 0;
        cs->c = c;
        cs->capacity = cap;
    }
    contact *c = &cs->c[cs->count++];
    c->a = a;
    c->b = b;
    c->gap = gap;
    make_frame(n, c->frame);
    return 1;
}

static int by_pair(const void *p, const void *q) {
    const contact *x = p, *y = q;
    if (x->a != y->a) return x->a < y->a ? -1 : 1;
    return x->b < y->b ? -1 : x->b > y->b;
}

void step_reach(const world *w, double h, double *reach) {
    for (int64_t i = 0; i < w->n; ++i) {
        const double *vi = &w->v[6 * i];
        reach[i] = 2.0 * h * (sqrt(vi[0] * vi[0] + vi[1] * vi[1] + vi[2] * vi[2]) + h * GRAVITY);
    }
}

/* The contacts closer than their margin (floor + reach[a] + reach[b]; a wall has no reach),
 * sorted by (a, b): a counting sort of the spheres into grid cells of one sphere's span plus
 * the largest margin, then each sphere against the spheres of its
 * 27 cells with a larger index, and against the walls. */
int find_contacts(const world *w, double floor_margin, const double *reach, contacts *cs,
                         int64_t **cell_start, int64_t **order,
                         int64_t *cells_capacity) {
    cs->count = 0;
    const int64_t n = w->n;
    double reach_max = 0.0;
    for (int64_t i = 0; i < n; ++i) reach_max = fmax(reach_max, reach[i]);
    const double cell = 2.0 * w->rmax + floor_margin + 2.0 * reach_max;
    double zmax = 0.0;
    for (int64_t i = 0; i < n; ++i) zmax = fmax(zmax, w->x[3 * i + 2]);
    const int64_t nx = (int64_t)(w->box[0] / cell) + 1, ny = (int64_t)(w->box[1] / cell) + 1;
    const int64_t nz = (int64_t)(fmax(zmax, 0.0) / cell) + 1;
    const int64_t cells = nx * ny * nz;
    if (cells + 1 > *cells_capacity) {
        int64_t *s = realloc(*cell_start, sizeof *s * (size_t)(cells + 1));
        if (!s) return 0;
        *cell_start = s;
        *cells_capacity = cells + 1;
    }
    int64_t *start = *cell_start;
#define CLAMPED(v, hi) ((v) < 0 ? 0 : ((v) >= (hi) ? (hi) - 1 : (v)))
#define CELL_OF(i)                                                                                 \
    (CLAMPED((int64_t)(w->x[3 * (i)] / cell), nx) + nx * (CLAMPED((int64_t)(w->x[3 * (i) + 1] / cell), ny) + \
                                                             ny * CLAMPED((int64_t)(w->x[3 * (i) + 2] / cell), nz)))
    memset(start, 0, sizeof *start * (size_t)(cells + 1));
    for (int64_t i = 0; i < n; ++i) ++start[CELL_OF(i) + 1];
    for (int64_t c = 0; c < cells; ++c) start[c + 1] += start[c];
    for (int64_t i = 0; i < n; ++i) (*order)[start[CELL_OF(i)]++] = i;
    for (int64_t c = cells; c > 0; --c) start[c] = start[c - 1];
    start[0] = 0;
    for (int64_t i = 0; i < n; ++i) {
        const double *xi = &w->x[3 * i];
        const double ri = w->radius[i];
        const int64_t cx = CLAMPED((int64_t)(xi[0] / cell), nx), cy = CLAMPED((int64_t)(xi[1] / cell), ny);
        const int64_t cz = CLAMPED((int64_t)(xi[2] / cell), nz);
        for (int64_t dz = -1; dz <= 1; ++dz)
            for (int64_t dy = -1; dy <= 1; ++dy)
                for (int64_t dx = -1; dx <= 1; ++dx) {
                    const int64_t x = cx + dx, y = cy + dy, z = cz + dz;
                    if (x < 0 || y < 0 || z < 0 || x >= nx || y >= ny || z >= nz) continue;
                    const int64_t c = x + nx * (y + ny * z);
                    for (int64_t k = start[c]; k < start[c + 1]; ++k) {
                        const int64_t j = (*order)[k];
                        if (j <= i) continue;
                        const double *xj = &w->x[3 * j];
                        double d[3] = {xi[0] - xj[0], xi[1] - xj[1], xi[2] - xj[2]};
                        const double dist = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
                        const double gap = dist - ri - w->radius[j];
                        if (gap >= floor_margin + reach[i] + reach[j] || dist == 0.0) continue;
                        for (int q = 0; q < 3; ++q) d[q] /= dist;
                        if (!push(cs, i, j, gap, d)) return 0;
                    }
                }
        /* The walls: normals into the sphere. */
        const double normals[WALLS][3] = {{0, 0, 1}, {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
        const double gaps[WALLS] = {xi[2] - ri, xi[0] - ri, w->box[0] - xi[0] - ri, xi[1] - ri, w->box[1] - xi[1] - ri};
        for (int k = 0; k < WALLS; ++k)
            if (gaps[k] < floor_margin + reach[i] && !push(cs, i, n + k, gaps[k], normals[k])) return 0;
    }
#undef CELL_OF
#undef CLAMPED
    if (cs->count > 1) qsort(cs->c, (size_t)cs->count, sizeof *cs->c, by_pair);
    return 1;
}

void contact_blocks(const world *w, const contact *c, double G[36]) {
    for (int side = 0; side < 2; ++side) {
        const int64_t s = side ? c->b : c->a;
        double *g = &G[18 * side];
        if (s >= w->n) { /* a wall: no dofs */
            for (int k = 0; k < 18; ++k) g[k] = 0.0;
            continue;
        }
        const double sign = side ? -1.0 : 1.0;
        /* The contact point is radius s along -n from sphere a's centre, +n from b's. */
        double l[3];
        for (int q = 0; q < 3; ++q) l[q] = -sign * w->radius[s] * c->frame[q];
        for (int e = 0; e < 3; ++e) {
            const double *t = &c->frame[3 * e];
            const double lxt[3] = {l[1] * t[2] - l[2] * t[1], l[2] * t[0] - l[0] * t[2], l[0] * t[1] - l[1] * t[0]};
            for (int q = 0; q < 6; ++q) g[6 * e + q] = sign * (q < 3 ? t[q] : lxt[q - 3]);
        }
    }
}

void angular_blocks(const world *w, const contact *c, double R[36]) {
    /* Rows 0 and 1 on the tangents (frame vectors 1 and 2), row 2 on the normal (frame vector 0). */
    for (int side = 0; side < 2; ++side) {
        const int64_t s = side ? c->b : c->a;
        const double sign = side ? -1.0 : 1.0;
        for (int k = 0; k < 3; ++k) {
            const double *axis = &c->frame[3 * (k < 2 ? k + 1 : 0)];
            for (int q = 0; q < 6; ++q) R[18 * side + 6 * k + q] = s < w->n && q >= 3 ? sign * axis[q - 3] : 0.0;
        }
    }
}

void contact_blocks_of(const world *w, const contact *c, int dim, double B[72]) {
    double G[36], R[36];
    contact_blocks(w, c, G);
    if (dim == 3) {
        memcpy(B, G, sizeof G);
        return;
    }
    angular_blocks(w, c, R);
    for (int side = 0; side < 2; ++side)
        for (int q = 0; q < 6; ++q) {
            for (int e = 0; e < 3; ++e) B[6 * dim * side + 6 * e + q] = G[18 * side + 6 * e + q];
            for (int k = 0; k < dim - 3; ++k) B[6 * dim * side + 6 * (3 + k) + q] = R[18 * side + 6 * k + q];
        }
}

int64_t assemble_h(const world *w, const contacts *cs, int dim, int64_t *rows, int64_t *cols, double *vals) {
    int64_t k = 0;
    double B[72];
    for (int64_t a = 0; a < cs->count; ++a) {
        const contact *c = &cs->c[a];
        contact_blocks_of(w, c, dim, B);
        for (int side = 0; side < 2; ++side) {
            const int64_t s = side ? c->b : c->a;
            if (s >= w->n) continue;
            for (int e = 0; e < dim; ++e)
                for (int q = 0; q < 6; ++q) {
                    rows[k] = 6 * s + q;
                    cols[k] = dim * a + e;
                    vals[k] = B[6 * dim * side + 6 * e + q];
                    ++k;
                }
        }
    }
    return k;
}

/* Last step's impulse of the same pair, found by binary search in last step's sorted
 * contacts (zero for a new pair). */
void warm_start(const contacts *now, const contacts *before, int dim, const double *r_before, double *r) {
    for (int64_t a = 0; a < now->count; ++a) {
        int64_t lo = 0, hi = before->count;
        for (int q = 0; q < dim; ++q) r[dim * a + q] = 0.0;
        while (lo < hi) {
            const int64_t mid = lo + (hi - lo) / 2;
            const int cmp = by_pair(&before->c[mid], &now->c[a]);
            if (cmp == 0) {
                for (int q = 0; q < dim; ++q) r[dim * a + q] = r_before[dim * mid + q];
                break;
            }
            if (cmp < 0) lo = mid + 1;
            else hi = mid;
        }
    }
}

/* W's entries, block by block: each sphere couples every pair of its contacts' blocks. */
frix_error write_local_form(const world *w, const contacts *cs, int dim, const double *mdiag, const double *f,
                            const double *wv, const double *mu, const double *mu_r, const double *mu_s,
                            const char *title, const double *r, const double *u, const double *r0,
                            const char *path) {
    const int64_t nc = cs->count, n = w->n, bs = 6 * dim; /* a block of H^T: dim x 6 */
    /* The contacts of each sphere, with the side it is on. */
    int64_t *deg = calloc((size_t)n + 1, sizeof *deg), *list = malloc(sizeof *list * 2 * (size_t)(nc + 1));
    int64_t *next = malloc(sizeof *next * (size_t)(n + 1)), *rows = NULL, *cols = NULL;
    double *q = calloc((size_t)(dim * nc) + 1, sizeof *q), *u0 = malloc(sizeof *u0 * ((size_t)(dim * nc) + 1));
    double *vals = NULL;
    double *blocks = malloc(sizeof *blocks * 2 * (size_t)bs * (size_t)(nc + 1));
    frix_matrix *W = NULL;
    frix_problem *p = NULL;
    frix_error e = deg && list && next && q && u0 && blocks ? FRIX_OK : FRIX_ERR_OUT_OF_MEMORY;
    int64_t pairs = 0, k = 0;
    for (int64_t a = 0; !e && a < nc; ++a)
        for (int side = 0; side < 2; ++side) {
            const int64_t s = side ? cs->c[a].b : cs->c[a].a;
            if (s < n) ++deg[s + 1];
        }
    for (int64_t s = 0; !e && s < n; ++s) pairs += deg[s + 1] * deg[s + 1], deg[s + 1] += deg[s];
    if (!e) {
        rows = malloc(sizeof *rows * (size_t)(dim * dim) * (size_t)(pairs + 1));
        cols = malloc(sizeof *cols * (size_t)(dim * dim) * (size_t)(pairs + 1));
        vals = malloc(sizeof *vals * (size_t)(dim * dim) * (size_t)(pairs + 1));
        if (!rows || !cols || !vals) e = FRIX_ERR_OUT_OF_MEMORY;
    }
    if (!e) {
        memcpy(next, deg, sizeof *next * (size_t)n);
        for (int64_t a = 0; a < nc; ++a) {
            contact_blocks_of(w, &cs->c[a], dim, &blocks[2 * bs * a]);
            for (int side = 0; side < 2; ++side) {
                const int64_t s = side ? cs->c[a].b : cs->c[a].a;
                if (s < n) list[next[s]++] = 2 * a + side;
            }
        }
        for (int64_t s = 0; s < n; ++s)
            for (int64_t i = deg[s]; i < deg[s + 1]; ++i)
                for (int64_t j = deg[s]; j < deg[s + 1]; ++j) {
                    const int64_t a = list[i] / 2, b = list[j] / 2;
                    const double *Ba = &blocks[2 * bs * a + bs * (list[i] % 2)];
                    const double *Bb = &blocks[2 * bs * b + bs * (list[j] % 2)];
                    for (int x = 0; x < dim; ++x)
                        for (int y = 0; y < dim; ++y) {
                            double sum = 0.0;
                            for (int d = 0; d < 6; ++d) sum += Ba[6 * x + d] * Bb[6 * y + d] / mdiag[6 * s + d];
                            rows[k] = dim * a + x, cols[k] = dim * b + y, vals[k++] = sum;
                        }
                }
        for (int64_t a = 0; a < nc; ++a) {
            for (int x = 0; x < dim; ++x) q[dim * a + x] = wv[dim * a + x];
            for (int side = 0; side < 2; ++side) {
                const int64_t s = side ? cs->c[a].b : cs->c[a].a;
                if (s >= n) continue;
                for (int x = 0; x < dim; ++x)
                    for (int d = 0; d < 6; ++d)
                        q[dim * a + x] += blocks[2 * bs * a + bs * side + 6 * x + d] * f[6 * s + d] / mdiag[6 * s + d];
            }
        }
        e = frix_matrix_from_triplets(dim * nc, dim * nc, k, rows, cols, vals, &W);
    }
    if (!e)
        e = dim == 6   ? frix_problem_spinning_local(W, q, mu, mu_r, mu_s, nc, &p)
            : dim == 5 ? frix_problem_rolling_local(W, q, mu, mu_r, nc, &p)
                       : frix_problem_local(W, q, mu, nc, &p);
    if (!e) e = frix_problem_set_title(p, title);
    if (!e) {
        memcpy(u0, q, sizeof *u0 * (size_t)(dim * nc));
        e = frix_matrix_gemv(W, 1.0, r0, 1.0, u0);
    }
    if (!e) e = frix_fclib_write(path, p, r, u, NULL, 1, r0, u0, NULL);
    frix_problem_free(p);
    frix_matrix_free(W);
    free(deg), free(list), free(q), free(u0), free(next), free(rows), free(cols), free(vals), free(blocks);
    return e;
}

/* *p reallocated to n entries (kept as it was when that fails). */
int grow_doubles(double **p, int64_t n) {
    double *q = realloc(*p, sizeof *q * (size_t)n);
    if (q) *p = q;
    return q != NULL;
}

int grow_indices(int64_t **p, int64_t n) {
    int64_t *q = realloc(*p, sizeof *q * (size_t)n);
    if (q) *p = q;
    return q != NULL;
}


int parse_double(const char *s, double *out) {
    char *end = NULL;
    errno = 0;
    const double v = strtod(s, &end);
    if (!*s || *end || errno || !isfinite(v)) return 0;
    *out = v;
    return 1;
}

int parse_int(const char *s, int64_t *out) {
    char *end = NULL;
    errno = 0;
    const long long v = strtoll(s, &end, 10);
    if (!*s || *end || errno) return 0;
    *out = (int64_t)v;
    return 1;
}

void scene_defaults(scene_settings *s) {
    *s = (scene_settings){.spheres = 1000, .steps = 200, .seed = 1, .max_iter = 0, .every = 1, .h = 2e-3, .mu = 0.5,
                          .radius = 0.01, .tol = 1e-4, .aspect = 2.0, .floor = 1.0};
}

void scene_help(FILE *out) {
    fputs("  --spheres N      spheres poured (default 1000)\n"
          "  --aspect A       the lattice they start on is A times as tall as wide (0.01 to 100, default 2)\n"
          "  --floor F        the box's floor is F times as wide as the lattice (1 to 100, default 1: the\n"
          "                   walls hold the lattice; wider leaves room for a heap and its angle of repose)\n"
          "  --steps S        time steps run, numbered 0 to S-1 (default 200)\n"
          "  --step H         time step, seconds (default 2e-3)\n"
          "  --mu MU          friction coefficient of every contact (default 0.5)\n"
          "  --radius R       largest radius, metres; radii are in [0.7 R, R] (default 0.01)\n"
          "  --seed K         seed of the lattice jitter and the velocities (default 1)\n"
          "  --tol T          tolerance of every step's solve (default 1e-4)\n"
          "  --max-iter I     iteration limit of every step's solve (default: the solver's)\n"
          "  --every K        print a line every K steps, and for the last step (default 1)\n",
          out);
}

int parse_scene_option(const char *o, const char *a, scene_settings *s, int *ok) {
    if (!strcmp(o, "--spheres")) *ok = parse_int(a, &s->spheres) && s->spheres >= 1;
    else if (!strcmp(o, "--steps")) *ok = parse_int(a, &s->steps) && s->steps >= 0;
    else if (!strcmp(o, "--seed")) *ok = parse_int(a, &s->seed) && s->seed >= 0;
    else if (!strcmp(o, "--max-iter")) *ok = parse_int(a, &s->max_iter) && s->max_iter >= 1;
    else if (!strcmp(o, "--every")) *ok = parse_int(a, &s->every) && s->every >= 1;
    else if (!strcmp(o, "--step")) *ok = parse_double(a, &s->h) && s->h > 0.0;
    else if (!strcmp(o, "--mu")) *ok = parse_double(a, &s->mu) && s->mu >= 0.0;
    else if (!strcmp(o, "--radius")) *ok = parse_double(a, &s->radius) && s->radius > 0.0;
    else if (!strcmp(o, "--aspect")) *ok = parse_double(a, &s->aspect) && s->aspect >= 0.01 && s->aspect <= 100.0;
    else if (!strcmp(o, "--floor")) *ok = parse_double(a, &s->floor) && s->floor >= 1.0 && s->floor <= 100.0;
    else if (!strcmp(o, "--tol")) *ok = parse_double(a, &s->tol) && s->tol > 0.0;
    else return 0;
    return 1;
}

void keep_freed_memory(void) {
#ifdef __GLIBC__
    mallopt(M_MMAP_MAX, 0);
    mallopt(M_TRIM_THRESHOLD, -1);
#endif
}
