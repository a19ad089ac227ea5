/* A granular time-stepping client of frix: polydisperse spheres poured into a box under
 * gravity, one frictional contact problem per step solved by a persistent solver.
 *
 *   granular [--spheres N] [--aspect A] [--steps S] [--step H] [--mu MU] [--radius R] [--seed K]
 *            [--solver NAME] [--tol T] [--threads T] [--max-iter I] [--time-limit SEC]
 *            [--set NAME=VALUE ...] [--dump-step K --dump FILE.hdf5] [--every K] [--check] [--quiet]
 *
 * Bodies: N spheres of radii in [0.7 R, R] (density 2500), set on a loose lattice A times as
 * tall as wide (default 2) over the floor of a box with four walls, with small random
 * velocities. Each step (Moreau-Jean, theta = 1):
 *   - broad phase on a uniform grid of cells of one sphere's span; a contact is a pair (or a
 *     sphere and a wall) closer than a margin no step can cross: a floor of 5 % of the
 *     smallest radius plus, for each sphere, twice what it can move in a step;
 *   - contact frames (normal into the first sphere, two tangents) and the global problem
 *     M v = H r + f, u = H^T v + w: M diagonal (mass, inertia), f = M v_k + h F_ext, and
 *     w_N = max(gap, 0) / h, so that u_N >= 0 closes the gap no further than to touching;
 *   - the persistent solver, given the step's contacts (frix_persistent_set_contacts_global)
 *     and warm-started from last step's impulses of the same pairs;
 *   - positions x += h v.
 * One line per step: step, contacts, solver, iterations, error, solve time, energy. --dump
 * writes step K's problem (and its solution) as an FCLIB file. --check exits with 1 unless
 * every step converged and the energy (kinetic + potential) never grew by more than the
 * tolerance of the step's solve allows. Exit status 2 for a usage or library error.
 */
#include <frix/frix.h>

#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define GRAVITY 9.81
#define DENSITY 2500.0
#define WALLS 5 /* floor, x = 0, x = Lx, y = 0, y = Ly */

typedef struct {
    int64_t spheres, steps, seed, threads, max_iter, dump_step, every;
    double h, mu, radius, tol, time_limit, aspect;
    const char *solver, *dump;
    const char *set[16]; /* --set NAME=VALUE: any other solver option, by name */
    int sets, check, quiet;
} settings;

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

/* xorshift64*: the scene is the same on every machine for a seed. */
static double uniform(uint64_t *s) {
    *s ^= *s >> 12;
    *s ^= *s << 25;
    *s ^= *s >> 27;
    return (double)((*s * 2685821657736338717ULL) >> 11) * (1.0 / 9007199254740992.0);
}

static int usage(const char *msg, const char *arg) {
    fprintf(stderr, "granular: %s%s%s\n", msg, arg ? ": " : "", arg ? arg : "");
    fprintf(stderr, "usage: granular [--spheres N] [--aspect A] [--steps S] [--step H] [--mu MU] [--radius R] [--seed K]\n"
                    "         [--solver NAME] [--tol T] [--threads T] [--max-iter I] [--time-limit SEC]\n"
                    "         [--set NAME=VALUE ...] [--dump-step K --dump FILE.hdf5] [--every K] [--check] [--quiet]\n");
    return 2;
}

static int parse_double(const char *s, double *out) {
    char *end = NULL;
    errno = 0;
    const double v = strtod(s, &end);
    if (!*s || *end || errno || !isfinite(v)) return 0;
    *out = v;
    return 1;
}

static int parse_int(const char *s, int64_t *out) {
    char *end = NULL;
    errno = 0;
    const long long v = strtoll(s, &end, 10);
    if (!*s || *end || errno) return 0;
    *out = (int64_t)v;
    return 1;
}

static int parse(int argc, char **argv, settings *st) {
    *st = (settings){.spheres = 1000, .steps = 200, .seed = 1, .threads = 1, .max_iter = 0, .dump_step = -1,
                     .every = 1, .h = 2e-3, .mu = 0.5, .radius = 0.01, .tol = 1e-4, .time_limit = 0.0, .aspect = 2.0,
                     .solver = "auto", .dump = NULL, .check = 0, .quiet = 0};
    for (int i = 1; i < argc; ++i) {
        const char *o = argv[i], *a = i + 1 < argc ? argv[i + 1] : NULL;
        int ok = 1, takes = 1;
        if (!strcmp(o, "--check")) st->check = 1, takes = 0;
        else if (!strcmp(o, "--quiet")) st->quiet = 1, takes = 0;
        else if (!a) return usage("missing value after", o);
        else if (!strcmp(o, "--spheres")) ok = parse_int(a, &st->spheres) && st->spheres >= 1;
        else if (!strcmp(o, "--steps")) ok = parse_int(a, &st->steps) && st->steps >= 0;
        else if (!strcmp(o, "--seed")) ok = parse_int(a, &st->seed) && st->seed >= 0;
        else if (!strcmp(o, "--threads")) ok = parse_int(a, &st->threads) && st->threads >= 1;
        else if (!strcmp(o, "--max-iter")) ok = parse_int(a, &st->max_iter) && st->max_iter >= 1;
        else if (!strcmp(o, "--dump-step")) ok = parse_int(a, &st->dump_step) && st->dump_step >= 0;
        else if (!strcmp(o, "--every")) ok = parse_int(a, &st->every) && st->every >= 1;
        else if (!strcmp(o, "--step")) ok = parse_double(a, &st->h) && st->h > 0.0;
        else if (!strcmp(o, "--mu")) ok = parse_double(a, &st->mu) && st->mu >= 0.0;
        else if (!strcmp(o, "--radius")) ok = parse_double(a, &st->radius) && st->radius > 0.0;
        else if (!strcmp(o, "--aspect")) ok = parse_double(a, &st->aspect) && st->aspect >= 0.01 && st->aspect <= 100.0;
        else if (!strcmp(o, "--tol")) ok = parse_double(a, &st->tol) && st->tol > 0.0;
        else if (!strcmp(o, "--time-limit")) ok = parse_double(a, &st->time_limit) && st->time_limit >= 0.0;
        else if (!strcmp(o, "--solver")) st->solver = a;
        else if (!strcmp(o, "--dump")) st->dump = a;
        else if (!strcmp(o, "--set")) {
            if (st->sets == (int)(sizeof st->set / sizeof st->set[0])) return usage("too many --set", a);
            st->set[st->sets++] = a;
        }
        else return usage("unknown option", o);
        if (!ok) return usage("bad value", a);
        i += takes;
    }
    if ((st->dump != NULL) != (st->dump_step >= 0)) return usage("--dump and --dump-step go together", NULL);
    return 0;
}

static int fail(const char *what, frix_error e) {
    fprintf(stderr, "granular: %s: %s (%s)\n", what, frix_error_string(e), frix_last_error_message());
    return 2;
}

/* --set NAME=VALUE: the option of that name, its value read as its type asks; 0, or 2 after
 * saying why not. */
static int set_option(frix_options *opts, const char *assignment) {
    const char *eq = strchr(assignment, '=');
    char name[64];
    if (!eq || eq == assignment || (size_t)(eq - assignment) >= sizeof name) return usage("--set takes NAME=VALUE", assignment);
    memcpy(name, assignment, (size_t)(eq - assignment));
    name[eq - assignment] = '\0';
    frix_option_key key;
    double lower, upper, value;
    int is_int;
    int64_t n;
    frix_error e;
    if ((e = frix_option_by_name(name, &key)) || (e = frix_options_bounds(opts, key, &lower, &upper, &is_int)))
        return fail(assignment, e);
    if (is_int ? !parse_int(eq + 1, &n) : !parse_double(eq + 1, &value)) return usage("bad value", assignment);
    if ((e = is_int ? frix_options_set_int(opts, key, n) : frix_options_set_double(opts, key, value)))
        return fail(assignment, e);
    return 0;
}

/* The initial state: a lattice filling the box's floor, aspect times as tall as wide (to the
 * last layer), each site jittered. */
static int make_world(const settings *st, world *w) {
    const int64_t n = st->spheres;
    w->n = n;
    w->x = malloc(sizeof *w->x * 3 * (size_t)n);
    w->v = malloc(sizeof *w->v * 6 * (size_t)n);
    w->radius = malloc(sizeof *w->radius * (size_t)n);
    w->mass = malloc(sizeof *w->mass * (size_t)n);
    w->inertia = malloc(sizeof *w->inertia * (size_t)n);
    if (!w->x || !w->v || !w->radius || !w->mass || !w->inertia) return 0;
    uint64_t rng = 0x9E3779B97F4A7C15ULL ^ (uint64_t)(st->seed + 1) * 0xBF58476D1CE4E5B9ULL;
    const double R = st->radius, spacing = 2.2 * R;
    int64_t side = 1;
    while (st->aspect * (double)(side * side * side) < (double)n) ++side;
    w->rmax = R;
    w->rmin = 0.7 * R;
    w->box[0] = w->box[1] = (double)side * spacing;
    for (int64_t i = 0; i < n; ++i) {
        const int64_t ix = i % side, iy = (i / side) % side, iz = i / (side * side);
        const double r = R * (0.7 + 0.3 * uniform(&rng));
        w->radius[i] = r;
        w->mass[i] = DENSITY * 4.0 / 3.0 * M_PI * r * r * r;
        w->inertia[i] = 0.4 * w->mass[i] * r * r;
        const double slack = 0.5 * spacing - r;
        w->x[3 * i] = ((double)ix + 0.5) * spacing + slack * (2.0 * uniform(&rng) - 1.0);
        w->x[3 * i + 1] = ((double)iy + 0.5) * spacing + slack * (2.0 * uniform(&rng) - 1.0);
        w->x[3 * i + 2] = ((double)iz + 0.5) * spacing;
        for (int k = 0; k < 6; ++k) w->v[6 * i + k] = k < 3 ? 0.05 * (2.0 * uniform(&rng) - 1.0) : 0.0;
    }
    return 1;
}

static void free_world(world *w) {
    free(w->x);
    free(w->v);
    free(w->radius);
    free(w->mass);
    free(w->inertia);
}

static double energy(const world *w) {
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

/* The contacts closer than their margin (floor + reach[a] + reach[b]; a wall has no reach),
 * sorted by (a, b): a counting sort of the spheres into grid cells of one sphere's span plus
 * the largest margin, then each sphere against the spheres of its
 * 27 cells with a larger index, and against the walls. */
static int find_contacts(const world *w, double floor_margin, const double *reach, contacts *cs,
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
    qsort(cs->c, (size_t)cs->count, sizeof *cs->c, by_pair);
    return 1;
}

/* H's entries for the contacts (3 columns each; 18 rows of each sphere's 6 dofs): the row of
 * H^T for frame vector e on sphere s with lever arm l (contact point - centre) is
 * sign (e, l x e). */
static int64_t assemble_h(const world *w, const contacts *cs, int64_t *rows, int64_t *cols, double *vals) {
    int64_t k = 0;
    for (int64_t a = 0; a < cs->count; ++a) {
        const contact *c = &cs->c[a];
        for (int side = 0; side < 2; ++side) {
            const int64_t s = side ? c->b : c->a;
            if (s >= w->n) continue; /* a wall: no dofs */
            const double sign = side ? -1.0 : 1.0;
            /* The contact point is radius s along -n from sphere a's centre, +n from b's. */
            double l[3];
            for (int q = 0; q < 3; ++q) l[q] = -sign * w->radius[s] * c->frame[q];
            for (int e = 0; e < 3; ++e) {
                const double *t = &c->frame[3 * e];
                const double lxt[3] = {l[1] * t[2] - l[2] * t[1], l[2] * t[0] - l[0] * t[2], l[0] * t[1] - l[1] * t[0]};
                for (int q = 0; q < 6; ++q) {
                    rows[k] = 6 * s + q;
                    cols[k] = 3 * a + e;
                    vals[k] = sign * (q < 3 ? t[q] : lxt[q - 3]);
                    ++k;
                }
            }
        }
    }
    return k;
}

/* Last step's impulse of the same pair, found by binary search in last step's sorted
 * contacts (zero for a new pair). */
static void warm_start(const contacts *now, const contacts *before, const double *r_before, double *r) {
    for (int64_t a = 0; a < now->count; ++a) {
        int64_t lo = 0, hi = before->count;
        r[3 * a] = r[3 * a + 1] = r[3 * a + 2] = 0.0;
        while (lo < hi) {
            const int64_t mid = lo + (hi - lo) / 2;
            const int cmp = by_pair(&before->c[mid], &now->c[a]);
            if (cmp == 0) {
                for (int q = 0; q < 3; ++q) r[3 * a + q] = r_before[3 * mid + q];
                break;
            }
            if (cmp < 0) lo = mid + 1;
            else hi = mid;
        }
    }
}

/* *p reallocated to n entries (kept as it was when that fails). */
static int grow_doubles(double **p, int64_t n) {
    double *q = realloc(*p, sizeof *q * (size_t)n);
    if (q) *p = q;
    return q != NULL;
}

static int grow_indices(int64_t **p, int64_t n) {
    int64_t *q = realloc(*p, sizeof *q * (size_t)n);
    if (q) *p = q;
    return q != NULL;
}

int main(int argc, char **argv) {
    settings st;
    if (parse(argc, argv, &st)) return 2;
    int solver_id = 0;
    if (frix_solver_by_name(st.solver, &solver_id) != FRIX_OK) return usage("unknown solver", st.solver);

    world w;
    memset(&w, 0, sizeof w);
    if (!make_world(&st, &w)) {
        free_world(&w);
        fprintf(stderr, "granular: out of memory\n");
        return 2;
    }
    const int64_t n = w.n, dofs = 6 * n;
    int status = 0;
    frix_error e = FRIX_OK;
    const char *failed = NULL;

    /* M: diagonal, the same every step. */
    int64_t *idx = malloc(sizeof *idx * (size_t)dofs);
    double *mdiag = malloc(sizeof *mdiag * (size_t)dofs), *f = malloc(sizeof *f * (size_t)dofs);
    double *v_new = malloc(sizeof *v_new * (size_t)dofs), *reach = malloc(sizeof *reach * (size_t)n);
    contacts now = {0}, before = {0};
    int64_t *cell_start = NULL, cells_capacity = 0, *order = malloc(sizeof *order * (size_t)n);
    int64_t *hr = NULL, *hc = NULL;
    double *hv = NULL, *wv = NULL, *mu = NULL, *r = NULL, *u = NULL, *r_before = NULL;
    int64_t c_capacity = 0;
    frix_matrix *M = NULL, *H = NULL, *H_next = NULL;
    frix_problem *problem = NULL;
    frix_persistent *ps = NULL;
    frix_options *opts = NULL;
    frix_info *info = NULL;
    if (!idx || !mdiag || !f || !v_new || !reach || !order) {
        fprintf(stderr, "granular: out of memory\n");
        status = 2;
        goto done;
    }
    for (int64_t i = 0; i < n; ++i)
        for (int q = 0; q < 6; ++q) mdiag[6 * i + q] = q < 3 ? w.mass[i] : w.inertia[i];
    for (int64_t k = 0; k < dofs; ++k) idx[k] = k;
    if ((e = frix_matrix_from_triplets(dofs, dofs, dofs, idx, idx, mdiag, &M))) {
        failed = "M";
        goto done;
    }
    if ((e = frix_options_create(solver_id, &opts)) || (e = frix_options_set_double(opts, FRIX_OPT_TOLERANCE, st.tol)) ||
        (e = frix_options_set_double(opts, FRIX_OPT_TIME_LIMIT, st.time_limit)) ||
        (st.threads > 1 && (e = frix_options_set_int(opts, FRIX_OPT_THREADS, st.threads))) ||
        (st.max_iter && (e = frix_options_set_int(opts, FRIX_OPT_MAX_ITER, st.max_iter))) ||
        (e = frix_info_create(&info))) {
        failed = "options";
        goto done;
    }
    for (int i = 0; i < st.sets && status == 0; ++i) status = set_option(opts, st.set[i]);
    if (status) goto done;
    if (!st.quiet) printf("# step contacts solver iterations error time_s energy_J\n");
    const double e0 = energy(&w);
    double e_before = e0;
    for (int64_t step = 0; step <= st.steps; ++step) {
        /* A sphere moves by at most h |v| + h^2 g in a step (and |v| changes little): its reach
         * is twice that. */
        for (int64_t i = 0; i < n; ++i) {
            const double *vi = &w.v[6 * i];
            reach[i] = 2.0 * st.h * (sqrt(vi[0] * vi[0] + vi[1] * vi[1] + vi[2] * vi[2]) + st.h * GRAVITY);
        }
        contacts t = before;
        before = now;
        now = t;
        if (!find_contacts(&w, 0.05 * w.rmin, reach, &now, &cell_start, &order, &cells_capacity)) {
            fprintf(stderr, "granular: out of memory\n");
            status = 2;
            goto done;
        }
        const int64_t nc = now.count;
        if (nc > c_capacity || !r) {
            const int64_t cap = nc > 2 * c_capacity ? nc : 2 * c_capacity + 1;
            if (!grow_doubles(&wv, 3 * cap) || !grow_doubles(&mu, cap) || !grow_doubles(&r, 3 * cap) ||
                !grow_doubles(&u, 3 * cap) || !grow_doubles(&r_before, 3 * cap) || !grow_indices(&hr, 36 * cap) ||
                !grow_indices(&hc, 36 * cap) || !grow_doubles(&hv, 36 * cap)) {
                fprintf(stderr, "granular: out of memory\n");
                status = 2;
                goto done;
            }
            c_capacity = cap;
        }
        const int64_t entries = assemble_h(&w, &now, hr, hc, hv);
        if ((e = frix_matrix_from_triplets(dofs, 3 * nc, entries, hr, hc, hv, &H_next))) {
            failed = "H";
            goto done;
        }
        for (int64_t a = 0; a < nc; ++a) {
            wv[3 * a] = fmax(now.c[a].gap, 0.0) / st.h;
            wv[3 * a + 1] = wv[3 * a + 2] = 0.0;
            mu[a] = st.mu;
        }
        for (int64_t i = 0; i < n; ++i)
            for (int q = 0; q < 6; ++q) f[6 * i + q] = mdiag[6 * i + q] * w.v[6 * i + q] - (q == 2 ? st.h * w.mass[i] * GRAVITY : 0.0);
        warm_start(&now, &before, r_before, r);
        if (!ps) {
            if ((e = frix_problem_global(M, H_next, f, wv, mu, nc, &problem)) ||
                (e = frix_persistent_create(problem, opts, &ps))) {
                failed = "the persistent solver";
                goto done;
            }
            frix_problem_free(problem); /* the persistent solver keeps its own views */
            problem = NULL;
        } else if ((e = frix_persistent_set_contacts_global(ps, H_next, wv, mu, nc))) {
            failed = "the step's contacts";
            goto done;
        }
        /* The solver borrows H until the next one replaces it. */
        frix_matrix_free(H);
        H = H_next;
        H_next = NULL;
        if ((e = frix_persistent_solve(ps, r, u, v_new, info))) {
            failed = "the solve";
            goto done;
        }
        const frix_status s = frix_info_status(info);
        const double err = frix_info_error(info);
        if (st.dump_step == step) {
            frix_problem *dumped = NULL;
            if ((e = frix_problem_global(M, H, f, wv, mu, nc, &dumped))) {
                failed = "the dumped problem";
                goto done;
            }
            char title[96];
            snprintf(title, sizeof title, "granular: %lld spheres, step %lld, seed %lld", (long long)n, (long long)step,
                     (long long)st.seed);
            frix_problem_set_title(dumped, title);
            e = frix_fclib_write(st.dump, dumped, r, u, v_new, 0, NULL, NULL, NULL);
            frix_problem_free(dumped);
            if (e) {
                failed = "--dump";
                goto done;
            }
        }
        memcpy(w.v, v_new, sizeof *v_new * (size_t)dofs);
        for (int64_t i = 0; i < n; ++i)
            for (int q = 0; q < 3; ++q) w.x[3 * i + q] += st.h * w.v[6 * i + q];
        memcpy(r_before, r, sizeof *r * 3 * (size_t)nc);
        const double en = energy(&w);
        if (!st.quiet && step % st.every == 0)
            printf("%lld %lld %s %lld %.3e %.4f %.9g\n", (long long)step, (long long)nc, st.solver,
                   (long long)frix_info_iterations(info), err, frix_info_solve_time(info), en);
        if (st.check) {
            /* The impulses' work is <= 0 for an exact answer; a solve to tolerance tol may add
             * up to about tol of the step's contact energy scale, here bounded by e0. */
            if (s != FRIX_STATUS_CONVERGED) {
                fprintf(stderr, "granular: step %lld did not converge: %s, error %.3e\n", (long long)step,
                        frix_status_string(s), err);
                status = 1;
            }
            if (en > e_before + 10.0 * st.tol * fabs(e0)) {
                fprintf(stderr, "granular: step %lld: the energy grew from %.9g to %.9g J\n", (long long)step, e_before,
                        en);
                status = 1;
            }
        }
        e_before = en;
    }
done:
    if (failed) {
        status = fail(failed, e);
    }
    frix_persistent_free(ps);
    frix_problem_free(problem);
    frix_matrix_free(H);
    frix_matrix_free(H_next);
    frix_matrix_free(M);
    frix_options_free(opts);
    frix_info_free(info);
    free(idx);
    free(mdiag);
    free(f);
    free(v_new);
    free(reach);
    free(now.c);
    free(before.c);
    free(cell_start);
    free(order);
    free(hr);
    free(hc);
    free(hv);
    free(wv);
    free(mu);
    free(r);
    free(u);
    free(r_before);
    free_world(&w);
    return status;
}
