/* Spheres poured into a box with rolling resistance: the granular client's scene (pour.c) as
 * rolling-friction problems (five entries a contact, frix_problem.h), solved every step by
 * frix_solve in the global form; it reports how fast the pile comes to rest, and writes a
 * step's problem for the side-by-side with Siconos (tools/siconos: frix-siconos --solver
 * RFC3D_NSGS takes the local form). Public API only.
 *
 *   rolling_pour [scene options] [--rolling MU_R] [--solver NAME] [--dump-step K]
 *                [--dump GLOBAL.hdf5] [--dump-local LOCAL.hdf5] [--quiet]
 *
 * One line per step: step, contacts, iterations, error, seconds, the largest speed over
 * radius (1/s: the pile is at rest when every sphere is below 0.1) and the kinetic energy;
 * at the end, whether and since when the pile is at rest, and its angle of repose (physics.h;
 * --floor F leaves the heap room to spread).
 * --rolling 0 keeps the rolling rows with mu_r = 0 (free rolling), the model without
 * resistance. */
#include <frix/frix.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "physics.h"
#include "pour.h"

typedef struct {
    scene_settings scene;
    double mu_r;
    const char *solver, *dump, *dump_local;
    int64_t dump_step;
    int quiet;
} settings;

static int usage(const char *why, const char *what) {
    fprintf(stderr, "rolling_pour: %s%s%s\n", why, what ? ": " : "", what ? what : "");
    return 2;
}

static int parse(int argc, char **argv, settings *st) {
    scene_defaults(&st->scene);
    st->mu_r = 1e-3;
    st->solver = "auto";
    st->dump = st->dump_local = NULL;
    st->dump_step = -1;
    st->quiet = 0;
    for (int i = 1; i < argc; ++i) {
        const char *o = argv[i];
        if (!strcmp(o, "--help")) {
            fputs("usage: rolling_pour [scene options] [--rolling MU_R] [--solver NAME] [--dump-step K]\n"
                  "                    [--dump GLOBAL.hdf5] [--dump-local LOCAL.hdf5] [--quiet]\n"
                  "  --rolling MU_R   rolling resistance of every contact, metres (default 1e-3)\n",
                  stdout);
            scene_help(stdout);
            return 3;
        }
        if (!strcmp(o, "--quiet")) {
            st->quiet = 1;
            continue;
        }
        if (i + 1 >= argc) return usage("missing value", o);
        const char *a = argv[++i];
        int ok = 1;
        if (parse_scene_option(o, a, &st->scene, &ok)) {
        } else if (!strcmp(o, "--rolling")) {
            ok = parse_double(a, &st->mu_r) && st->mu_r >= 0.0;
        } else if (!strcmp(o, "--solver")) {
            st->solver = a;
        } else if (!strcmp(o, "--dump")) {
            st->dump = a;
        } else if (!strcmp(o, "--dump-local")) {
            st->dump_local = a;
        } else if (!strcmp(o, "--dump-step")) {
            ok = parse_int(a, &st->dump_step) && st->dump_step >= 0 && st->dump_step < st->scene.steps;
        } else {
            return usage("unknown option", o);
        }
        if (!ok) return usage("bad value", a);
    }
    if ((st->dump || st->dump_local) != (st->dump_step >= 0)) return usage("--dump-step goes with --dump or --dump-local", NULL);
    return 0;
}

/* Contact a's 5 x 6 block of H^T on each side (rows: normal, tangents, rolling tangents). */
static void blocks5(const world *w, const contact *c, double B[60]) {
    double G[36], R[24];
    contact_blocks(w, c, G);
    rolling_blocks(w, c, R);
    for (int side = 0; side < 2; ++side)
        for (int q = 0; q < 6; ++q) {
            for (int e = 0; e < 3; ++e) B[30 * side + 6 * e + q] = G[18 * side + 6 * e + q];
            for (int k = 0; k < 2; ++k) B[30 * side + 6 * (3 + k) + q] = R[12 * side + 6 * k + q];
        }
}

/* The local form W = H^T M^-1 H, q = H^T M^-1 f + w (M diagonal), written with frix. */
static frix_error write_local(const world *w, const contacts *cs, const double *mdiag, const double *f,
                              const double *wv, const double *mu, const double *mu_r, const char *path) {
    const int64_t nc = cs->count, n = w->n;
    /* The contacts of each sphere, with the side it is on. */
    int64_t *deg = calloc((size_t)n + 1, sizeof *deg), *list = malloc(sizeof *list * 2 * (size_t)(nc + 1));
    double *q = calloc(5 * (size_t)nc + 1, sizeof *q);
    if (!deg || !list || !q) return FRIX_ERR_OUT_OF_MEMORY;
    for (int64_t a = 0; a < nc; ++a)
        for (int side = 0; side < 2; ++side) {
            const int64_t s = side ? cs->c[a].b : cs->c[a].a;
            if (s < n) ++deg[s + 1];
        }
    int64_t pairs = 0;
    for (int64_t s = 0; s < n; ++s) pairs += deg[s + 1] * deg[s + 1], deg[s + 1] += deg[s];
    int64_t *next = malloc(sizeof *next * (size_t)(n + 1));
    int64_t *rows = malloc(sizeof *rows * 25 * (size_t)(pairs + 1)), *cols = malloc(sizeof *cols * 25 * (size_t)(pairs + 1));
    double *vals = malloc(sizeof *vals * 25 * (size_t)(pairs + 1)), *blocks = malloc(sizeof *blocks * 60 * (size_t)(nc + 1));
    if (!next || !rows || !cols || !vals || !blocks) return FRIX_ERR_OUT_OF_MEMORY;
    memcpy(next, deg, sizeof *next * (size_t)n);
    for (int64_t a = 0; a < nc; ++a) {
        blocks5(w, &cs->c[a], &blocks[60 * a]);
        for (int side = 0; side < 2; ++side) {
            const int64_t s = side ? cs->c[a].b : cs->c[a].a;
            if (s < n) list[next[s]++] = 2 * a + side;
        }
    }
    int64_t k = 0;
    for (int64_t s = 0; s < n; ++s)
        for (int64_t i = deg[s]; i < deg[s + 1]; ++i)
            for (int64_t j = deg[s]; j < deg[s + 1]; ++j) {
                const int64_t a = list[i] / 2, b = list[j] / 2;
                const double *Ba = &blocks[60 * a + 30 * (list[i] % 2)], *Bb = &blocks[60 * b + 30 * (list[j] % 2)];
                for (int e = 0; e < 5; ++e)
                    for (int g = 0; g < 5; ++g) {
                        double sum = 0.0;
                        for (int d = 0; d < 6; ++d) sum += Ba[6 * e + d] * Bb[6 * g + d] / mdiag[6 * s + d];
                        rows[k] = 5 * a + e, cols[k] = 5 * b + g, vals[k++] = sum;
                    }
            }
    for (int64_t a = 0; a < nc; ++a) {
        for (int e = 0; e < 5; ++e) q[5 * a + e] = wv[5 * a + e];
        for (int side = 0; side < 2; ++side) {
            const int64_t s = side ? cs->c[a].b : cs->c[a].a;
            if (s >= n) continue;
            for (int e = 0; e < 5; ++e)
                for (int d = 0; d < 6; ++d) q[5 * a + e] += blocks[60 * a + 30 * side + 6 * e + d] * f[6 * s + d] / mdiag[6 * s + d];
        }
    }
    frix_matrix *W = NULL;
    frix_problem *p = NULL;
    frix_error e = frix_matrix_from_triplets(5 * nc, 5 * nc, k, rows, cols, vals, &W);
    if (!e) e = frix_problem_rolling_local(W, q, mu, mu_r, nc, &p);
    if (!e) e = frix_problem_set_title(p, "rolling_pour: local form");
    if (!e) e = frix_fclib_write(path, p, NULL, NULL, NULL, 0, NULL, NULL, NULL);
    frix_problem_free(p);
    frix_matrix_free(W);
    free(deg), free(list), free(q), free(next), free(rows), free(cols), free(vals), free(blocks);
    return e;
}

static int fail(const char *what, frix_error e) {
    fprintf(stderr, "rolling_pour: %s: %s\n", what, e ? frix_last_error_message() : "out of memory");
    return 2;
}

int main(int argc, char **argv) {
    settings st;
    const int parsed = parse(argc, argv, &st);
    if (parsed) return parsed == 3 ? 0 : parsed;
    int solver_id = 0;
    if (frix_solver_by_name(st.solver, &solver_id) != FRIX_OK) return usage("unknown solver", st.solver);
    world w;
    memset(&w, 0, sizeof w);
    if (!make_world(&st.scene, &w)) return fail("world", 0);
    const int64_t n = w.n, dofs = 6 * n;
    int64_t *idx = malloc(sizeof *idx * (size_t)dofs), *order = malloc(sizeof *order * (size_t)n), *cell_start = NULL,
            cells_capacity = 0;
    double *mdiag = malloc(sizeof *mdiag * (size_t)dofs), *f = malloc(sizeof *f * (size_t)dofs);
    double *v = malloc(sizeof *v * (size_t)dofs), *reach = malloc(sizeof *reach * (size_t)n);
    if (!idx || !order || !mdiag || !f || !v || !reach) return fail("setup", 0);
    for (int64_t i = 0; i < n; ++i)
        for (int q = 0; q < 6; ++q) mdiag[6 * i + q] = q < 3 ? w.mass[i] : w.inertia[i];
    for (int64_t k = 0; k < dofs; ++k) idx[k] = k;
    frix_matrix *M = NULL;
    frix_options *opts = NULL;
    frix_info *info = NULL;
    frix_error e;
    if ((e = frix_matrix_from_triplets(dofs, dofs, dofs, idx, idx, mdiag, &M)) ||
        (e = frix_options_create(solver_id, &opts)) ||
        (e = frix_options_set_double(opts, FRIX_OPT_TOLERANCE, st.scene.tol)) ||
        (st.scene.max_iter && (e = frix_options_set_int(opts, FRIX_OPT_MAX_ITER, st.scene.max_iter))) ||
        (e = frix_info_create(&info)))
        return fail("setup", e);
    contacts now = {0}, before = {0};
    double *r = NULL, *u = NULL, *r_before = NULL, *wv = NULL, *mu = NULL, *mu_r = NULL, *hv = NULL;
    int64_t *hr = NULL, *hc = NULL;
    if (!st.quiet) printf("# step contacts iterations error time_s max_speed_over_radius_per_s kinetic_J\n");
    int64_t unconverged = 0, at_rest_from = -1;
    for (int64_t step = 0; step < st.scene.steps; ++step) {
        step_reach(&w, st.scene.h, reach);
        contacts t = before;
        before = now;
        now = t;
        if (!find_contacts(&w, 0.05 * w.rmin, reach, &now, &cell_start, &order, &cells_capacity)) return fail("contacts", 0);
        const int64_t nc = now.count;
        if (!grow_doubles(&r, 5 * nc + 1) || !grow_doubles(&u, 5 * nc + 1) || !grow_doubles(&wv, 5 * nc + 1) ||
            !grow_doubles(&mu, nc + 1) || !grow_doubles(&mu_r, nc + 1) || !grow_indices(&hr, 60 * nc + 1) ||
            !grow_indices(&hc, 60 * nc + 1) || !grow_doubles(&hv, 60 * nc + 1))
            return fail("contacts", 0);
        int64_t entries = 0;
        double B[60];
        for (int64_t a = 0; a < nc; ++a) {
            blocks5(&w, &now.c[a], B);
            for (int side = 0; side < 2; ++side) {
                const int64_t s = side ? now.c[a].b : now.c[a].a;
                if (s >= n) continue;
                for (int k = 0; k < 5; ++k)
                    for (int q = 0; q < 6; ++q) hr[entries] = 6 * s + q, hc[entries] = 5 * a + k, hv[entries++] = B[30 * side + 6 * k + q];
            }
            for (int k = 0; k < 5; ++k) wv[5 * a + k] = k == 0 ? fmax(now.c[a].gap, 0.0) / st.scene.h : 0.0;
            mu[a] = st.scene.mu;
            mu_r[a] = st.mu_r;
            r[5 * a] = r[5 * a + 1] = r[5 * a + 2] = r[5 * a + 3] = r[5 * a + 4] = 0.0;
        }
        /* Warm start: last step's impulse of the same pair (both lists sorted by pair). */
        for (int64_t a = 0, b = 0; a < nc && r_before; ++a) {
            while (b < before.count && (before.c[b].a < now.c[a].a || (before.c[b].a == now.c[a].a && before.c[b].b < now.c[a].b))) ++b;
            if (b < before.count && before.c[b].a == now.c[a].a && before.c[b].b == now.c[a].b)
                memcpy(&r[5 * a], &r_before[5 * b], 5 * sizeof *r);
        }
        for (int64_t i = 0; i < n; ++i)
            for (int q = 0; q < 6; ++q) f[6 * i + q] = mdiag[6 * i + q] * w.v[6 * i + q] - (q == 2 ? st.scene.h * w.mass[i] * GRAVITY : 0.0);
        frix_matrix *H = NULL;
        frix_problem *p = NULL;
        if ((e = frix_matrix_from_triplets(dofs, 5 * nc, entries, hr, hc, hv, &H)) ||
            (e = frix_problem_rolling_global(M, H, f, wv, mu, mu_r, nc, &p)) || (e = frix_solve(p, opts, r, u, v, info)))
            return fail("the step's solve", e);
        if (st.dump_step == step) {
            if (st.dump && (e = frix_fclib_write(st.dump, p, r, u, v, 0, NULL, NULL, NULL))) return fail("--dump", e);
            if (st.dump_local && (e = write_local(&w, &now, mdiag, f, wv, mu, mu_r, st.dump_local))) return fail("--dump-local", e);
        }
        frix_problem_free(p);
        frix_matrix_free(H);
        memcpy(w.v, v, sizeof *v * (size_t)dofs);
        for (int64_t i = 0; i < n; ++i)
            for (int q = 0; q < 3; ++q) w.x[3 * i + q] += st.scene.h * w.v[6 * i + q];
        const pile_state pile = measure_pile(&w, &now);
        const double fastest = pile.max_rate, kinetic = pile.kinetic;
        if (!grow_doubles(&r_before, 5 * nc + 1)) return fail("contacts", 0);
        memcpy(r_before, r, sizeof *r * 5 * (size_t)nc);
        const frix_status s = frix_info_status(info);
        if (s != FRIX_STATUS_CONVERGED) ++unconverged;
        at_rest_from = fastest < REST_RATE ? (at_rest_from < 0 ? step : at_rest_from) : -1;
        if (!st.quiet && (step % st.scene.every == 0 || step == st.scene.steps - 1))
            printf("%lld %lld %lld %.3e %.4f %.4g %.4g\n", (long long)step, (long long)nc,
                   (long long)frix_info_iterations(info), frix_info_error(info), frix_info_solve_time(info), fastest,
                   kinetic);
    }
    printf("# %lld of %lld steps unconverged; ", (long long)unconverged, (long long)st.scene.steps);
    if (at_rest_from >= 0)
        printf("at rest (every sphere below 0.1 radius/s) from step %lld\n", (long long)at_rest_from);
    else
        printf("not at rest at the last step\n");
    printf("# angle of repose %.1f degrees\n", angle_of_repose(&w));
    frix_matrix_free(M);
    frix_options_free(opts);
    frix_info_free(info);
    free(idx), free(order), free(cell_start), free(mdiag), free(f), free(v), free(reach), free(now.c), free(before.c);
    free(r), free(u), free(r_before), free(wv), free(mu), free(mu_r), free(hv), free(hr), free(hc);
    free_world(&w);
    return unconverged > 0;
}
