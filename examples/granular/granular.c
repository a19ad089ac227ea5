/* A granular time-stepping client of frix: polydisperse spheres poured into a box under
 * gravity, one frictional contact problem per step solved by a persistent solver.
 *
 *   granular [--spheres N] [--aspect A] [--steps S] [--step H] [--mu MU] [--radius R] [--seed K]
 *            [--solver NAME] [--tol T] [--threads T] [--max-iter I] [--time-limit SEC]
 *            [--set NAME=VALUE ...] [--dump-step K --dump FILE.hdf5 --dump-local FILE.hdf5]
 *            [--every K] [--settle] [--floor F] [--rolling MU_R] [--spinning MU_S] [--check] [--quiet]
 *
 * Bodies: N spheres of radii in [0.7 R, R] (density 2500), set on a loose lattice A times as
 * tall as wide (default 2) in the middle of the floor (F times as wide as the lattice) of a box
 * with four walls, with small random velocities. Each step (Moreau-Jean, theta = 1):
 *   - broad phase on a uniform grid of cells of one sphere's span; a contact is a pair (or a
 *     sphere and a wall) closer than a margin no step can cross: a floor of 5 % of the
 *     smallest radius plus, for each sphere, twice what it can move in a step;
 *   - contact frames (normal into the first sphere, two tangents) and the global problem
 *     M v = H r + f, u = H^T v + w: M diagonal (mass, inertia), f = M v_k + h F_ext, and
 *     w_N = max(gap, 0) / h, so that u_N >= 0 closes the gap no further than to touching;
 *     with --rolling MU_R, a rolling-friction problem (frix_problem.h): two more rows a
 *     contact, the relative angular velocity of the two spheres on the tangents, whose moment
 *     is at most MU_R (a length) times the normal impulse; with --spinning MU_S as well, a sixth
 *     row, the relative angular velocity about the normal, whose moment is at most MU_S (a
 *     length) times the normal impulse (spinning friction);
 *   - the persistent solver, given the step's contacts (frix_persistent_set_contacts_global,
 *     _rolling_global or _spinning_global) and warm-started from last step's impulses of the same pairs;
 *   - positions x += h v.
 * --steps S runs steps 0 to S-1. One line per step (every K-th with --every, and the last):
 * step, contacts, solver, iterations, the error in the default measure and in Siconos's, solve
 * time, energy, and the pile's physics (physics.h): kinetic energy, the largest grain speed over
 * its radius, the largest overlap over the smallest radius. --settle stops after the first step
 * at which the pile is at rest (every grain slower than 0.1 radius per second). The last lines
 * say whether the pile is at rest at the end, from which step on, and its angle of repose. A step whose solve did not
 * converge is reported on stderr, and their count at the end. --dump writes step K's problem,
 * its solution and, as guess 1, the warm start the step's solve began from, as an FCLIB file;
 * --dump-local writes the same in the local form (W = H^T M^-1 H formed: what solvers of local
 * problems, Siconos's rolling NSGS among them, take). --dump-step rest writes the first step
 * after which the pile is at rest (exit 1 where it never is).
 * --check exits with 1 unless every step converged and the energy (kinetic + potential) never
 * grew by more than the tolerance of the step's solve allows. Exit status 2 for a usage or
 * library error; --help prints the options.
 */
#include <frix/frix.h>

#include "physics.h"
#include "pour.h"

#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>


typedef struct {
    scene_settings scene;
    int64_t threads, dump_step; /* DUMP_AT_REST for --dump-step rest */
    double time_limit, mu_r, mu_s; /* mu_r < 0: no rolling resistance (three rows a contact); mu_s < 0: no spin row */
    const char *solver, *dump, *dump_local;
    const char *set[16]; /* --set NAME=VALUE: any other solver option, by name */
    int sets, check, quiet, settle;
} settings;


static const char kUsage[] =
    "usage: granular [--spheres N] [--aspect A] [--steps S] [--step H] [--mu MU] [--radius R] [--seed K]\n"
    "         [--solver NAME] [--tol T] [--threads T] [--max-iter I] [--time-limit SEC]\n"
    "         [--set NAME=VALUE ...] [--dump-step K --dump FILE.hdf5 --dump-local FILE.hdf5]\n"
    "         [--every K] [--settle] [--floor F] [--rolling MU_R] [--spinning MU_S] [--check] [--quiet]\n";

static int usage(const char *msg, const char *arg) {
    fprintf(stderr, "granular: %s%s%s\n%s", msg, arg ? ": " : "", arg ? arg : "", kUsage);
    return 2;
}

static void help(void) {
    fputs(kUsage, stdout);
    fputs("Pours spheres into a box under gravity; every step's frictional contact problem is solved by\n"
          "one persistent frix solver, warm-started from the last step.\n",
          stdout);
    scene_help(stdout);
    fputs("  --solver NAME    solver of every step, by name or id (default auto)\n"
          "  --threads T      threads of the solver (default 1)\n"
          "  --time-limit SEC time limit of every step's solve (default 0: none)\n"
          "  --set NAME=VALUE any other solver option, by name (frix solvers NAME lists them)\n"
          "  --dump-step K    with --dump or --dump-local: write step K (0 to S-1) as an FCLIB problem;\n"
          "                   K = rest: the first step after which every grain is slower than 0.1\n"
          "                   radius/s (exit 1 where the pile does not come to rest)\n"
          "  --dump FILE.hdf5 the file --dump-step writes: the global problem with its solution (the\n"
          "                   step's warm start as guess 1)\n"
          "  --dump-local FILE.hdf5 the same step's problem in the local form (W = H^T M^-1 H formed)\n"
          "  --settle         stop after the first step at which every grain is slower than 0.1 radius/s\n"
          "  --rolling MU_R   rolling resistance of every contact, metres (>= 0; 0 rolls freely with the\n"
          "                   rolling rows kept); default: none, three rows a contact\n"
          "  --spinning MU_S  with --rolling, spinning friction of every contact, metres (>= 0): a sixth\n"
          "                   row, the moment about the normal at most MU_S times the normal impulse\n"
          "  --check          exit 1 unless every step converged and the energy never grew\n"
          "  --quiet          no line per step (unconverged steps are still reported on stderr)\n"
          "  --help           this text\n"
          "Exit status: 0 done (with --check: and the checks held), 1 a check failed, 2 usage or library error.\n",
          stdout);
}

/* --dump-step rest: the first step after which the pile is at rest. */
#define DUMP_AT_REST (-2)

/* The step's global problem of the law that dim entries a contact carry (3, 5 or 6). */
static frix_error global_problem(const frix_matrix *M, const frix_matrix *H, const double *f, const double *wv,
                                 const double *mu, const double *mu_r, const double *mu_s, int64_t nc, int dim,
                                 frix_problem **out) {
    if (dim == 6) return frix_problem_spinning_global(M, H, f, wv, mu, mu_r, mu_s, nc, out);
    if (dim == 5) return frix_problem_rolling_global(M, H, f, wv, mu, mu_r, nc, out);
    return frix_problem_global(M, H, f, wv, mu, nc, out);
}

static int parse(int argc, char **argv, settings *st) {
    *st = (settings){.threads = 1, .dump_step = -1, .time_limit = 0.0, .mu_r = -1.0, .mu_s = -1.0, .solver = "auto", .dump = NULL,
                     .check = 0, .quiet = 0};
    scene_defaults(&st->scene);
    for (int i = 1; i < argc; ++i) {
        const char *o = argv[i], *a = i + 1 < argc ? argv[i + 1] : NULL;
        int ok = 1, takes = 1;
        if (!strcmp(o, "--help") || !strcmp(o, "-h")) return help(), 3;
        if (!strcmp(o, "--check")) st->check = 1, takes = 0;
        else if (!strcmp(o, "--settle")) st->settle = 1, takes = 0;
        else if (!strcmp(o, "--quiet")) st->quiet = 1, takes = 0;
        else if (!a) return usage("missing value after", o);
        else if (parse_scene_option(o, a, &st->scene, &ok)) {
            /* a scene option; ok: whether its value is valid */
        }
        else if (!strcmp(o, "--threads")) ok = parse_int(a, &st->threads) && st->threads >= 1;
        else if (!strcmp(o, "--dump-step"))
            ok = !strcmp(a, "rest") ? (st->dump_step = DUMP_AT_REST, 1) : parse_int(a, &st->dump_step) && st->dump_step >= 0;
        else if (!strcmp(o, "--time-limit")) ok = parse_double(a, &st->time_limit) && st->time_limit >= 0.0;
        else if (!strcmp(o, "--rolling")) ok = parse_double(a, &st->mu_r) && st->mu_r >= 0.0;
        else if (!strcmp(o, "--spinning")) ok = parse_double(a, &st->mu_s) && st->mu_s >= 0.0;
        else if (!strcmp(o, "--solver")) st->solver = a;
        else if (!strcmp(o, "--dump")) st->dump = a;
        else if (!strcmp(o, "--dump-local")) st->dump_local = a;
        else if (!strcmp(o, "--set")) {
            if (st->sets == (int)(sizeof st->set / sizeof st->set[0])) return usage("too many --set", a);
            st->set[st->sets++] = a;
        }
        else return usage("unknown option", o);
        if (!ok) return usage("bad value", a);
        i += takes;
    }
    if (st->mu_s >= 0.0 && st->mu_r < 0.0) return usage("--spinning goes with --rolling", NULL);
    if ((st->dump || st->dump_local) != (st->dump_step != -1))
        return usage("--dump-step goes with --dump or --dump-local, and they with it", NULL);
    /* A dump that would never happen is a mistake, not a no-op: the file would silently be missing. */
    if (st->dump_step >= st->scene.steps) {
        char why[128];
        snprintf(why, sizeof why, "--dump-step %lld is past the last step (--steps %lld runs steps 0 to %lld)",
                 (long long)st->dump_step, (long long)st->scene.steps, (long long)st->scene.steps - 1);
        return usage(why, NULL);
    }
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

/* The dumped step: its problem, its solution and, as guess 1, the warm start r0 its solve began
 * from, with the v and u that r0 gives (M v = H r0 + f with M = diag(mdiag), u = H^T v + w), so
 * that a benchmark can start where the time stepping did. */
static frix_error dump_with_warm_start(const char *path, const frix_problem *p, const double *mdiag, const double *r,
                                       const double *u, const double *v, const double *r0) {
    const int64_t m = frix_problem_contact_dofs(p), dofs = frix_problem_dofs(p);
    double *v0 = malloc(sizeof *v0 * (size_t)(dofs > 0 ? dofs : 1)), *u0 = malloc(sizeof *u0 * (size_t)(m > 0 ? m : 1));
    frix_error e = v0 && u0 ? FRIX_OK : FRIX_ERR_OUT_OF_MEMORY;
    if (!e) {
        memcpy(v0, frix_problem_f(p), sizeof *v0 * (size_t)dofs);
        memcpy(u0, frix_problem_w(p), sizeof *u0 * (size_t)m);
        e = frix_matrix_gemv(frix_problem_H(p), 1.0, r0, 1.0, v0);
    }
    for (int64_t k = 0; !e && k < dofs; ++k) v0[k] /= mdiag[k];
    if (!e) e = frix_matrix_gemv_transposed(frix_problem_H(p), 1.0, v0, 1.0, u0);
    if (!e) e = frix_fclib_write(path, p, r, u, v, 1, r0, u0, v0);
    free(v0);
    free(u0);
    return e;
}

int main(int argc, char **argv) {
    settings st;
    const int parsed = parse(argc, argv, &st);
    if (parsed) return parsed == 3 ? 0 : 2; /* 3: --help */
    int solver_id = 0;
    if (frix_solver_by_name(st.solver, &solver_id) != FRIX_OK) return usage("unknown solver", st.solver);
    keep_freed_memory();

    world w;
    memset(&w, 0, sizeof w);
    if (!make_world(&st.scene, &w)) {
        free_world(&w);
        fprintf(stderr, "granular: out of memory\n");
        return 2;
    }
    const int64_t n = w.n, dofs = 6 * n;
    const int dim = st.mu_s >= 0.0 ? 6 : st.mu_r >= 0.0 ? 5 : 3; /* entries of r a contact */
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
    double *hv = NULL, *wv = NULL, *mu = NULL, *mu_r = NULL, *mu_s = NULL, *r = NULL, *u = NULL, *r_before = NULL, *r_warm = NULL;
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
    if ((e = frix_options_create(solver_id, &opts)) || (e = frix_options_set_double(opts, FRIX_OPT_TOLERANCE, st.scene.tol)) ||
        (e = frix_options_set_double(opts, FRIX_OPT_TIME_LIMIT, st.time_limit)) ||
        (st.threads > 1 && (e = frix_options_set_int(opts, FRIX_OPT_THREADS, st.threads))) ||
        (st.scene.max_iter && (e = frix_options_set_int(opts, FRIX_OPT_MAX_ITER, st.scene.max_iter))) ||
        (e = frix_info_create(&info))) {
        failed = "options";
        goto done;
    }
    for (int i = 0; i < st.sets && status == 0; ++i) status = set_option(opts, st.set[i]);
    if (status) goto done;
    if (!st.quiet)
        printf("# step contacts solver iterations error error_siconos time_s energy_J kinetic_J max_speed_per_radius_1/s "
               "max_overlap_per_rmin\n");
    const double e0 = energy(&w);
    double e_before = e0;
    /* at_rest: the step from which every step so far left the pile at rest (-1: the last did not). */
    int64_t unconverged = 0, at_rest = -1, step = 0;
    int dumped_at_rest = 0; /* --dump-step rest: written */
    pile_state pile = {0.0, 0.0, 0.0};
    for (; step < st.scene.steps && !(st.settle && at_rest >= 0); ++step) {
        step_reach(&w, st.scene.h, reach);
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
            if (!grow_doubles(&wv, dim * cap) || !grow_doubles(&mu, cap) || !grow_doubles(&mu_r, cap) ||
                !grow_doubles(&mu_s, cap) ||
                !grow_doubles(&r, dim * cap) || !grow_doubles(&u, dim * cap) || !grow_doubles(&r_before, dim * cap) ||
                !grow_doubles(&r_warm, dim * cap) || !grow_indices(&hr, 12 * dim * cap) ||
                !grow_indices(&hc, 12 * dim * cap) || !grow_doubles(&hv, 12 * dim * cap)) {
                fprintf(stderr, "granular: out of memory\n");
                status = 2;
                goto done;
            }
            c_capacity = cap;
        }
        const int64_t entries = assemble_h(&w, &now, dim, hr, hc, hv);
        if ((e = frix_matrix_from_triplets(dofs, dim * nc, entries, hr, hc, hv, &H_next))) {
            failed = "H";
            goto done;
        }
        for (int64_t a = 0; a < nc; ++a) {
            for (int k = 0; k < dim; ++k) wv[dim * a + k] = 0.0;
            wv[dim * a] = fmax(now.c[a].gap, 0.0) / st.scene.h;
            mu[a] = st.scene.mu;
            mu_r[a] = st.mu_r;
            mu_s[a] = st.mu_s;
        }
        for (int64_t i = 0; i < n; ++i)
            for (int q = 0; q < 6; ++q) f[6 * i + q] = mdiag[6 * i + q] * w.v[6 * i + q] - (q == 2 ? st.scene.h * w.mass[i] * GRAVITY : 0.0);
        warm_start(&now, &before, dim, r_before, r);
        /* The step's warm start, for the dump (at rest: every step's, until one is dumped). */
        if (st.dump_step == step || (st.dump_step == DUMP_AT_REST && !dumped_at_rest))
            memcpy(r_warm, r, sizeof *r * (size_t)(dim * nc));
        if (!ps) {
            if ((e = global_problem(M, H_next, f, wv, mu, mu_r, mu_s, nc, dim, &problem)) ||
                (e = frix_persistent_create(problem, opts, &ps))) {
                failed = "the persistent solver";
                goto done;
            }
            frix_problem_free(problem); /* the persistent solver keeps its own views */
            problem = NULL;
        } else if ((e = dim == 6   ? frix_persistent_set_contacts_spinning_global(ps, H_next, wv, mu, mu_r, mu_s, nc)
                        : dim == 5 ? frix_persistent_set_contacts_rolling_global(ps, H_next, wv, mu, mu_r, nc)
                                   : frix_persistent_set_contacts_global(ps, H_next, wv, mu, nc))) {
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
        memcpy(w.v, v_new, sizeof *v_new * (size_t)dofs);
        /* The pile's state after the step (velocities and the step's overlaps), before the
         * dump: --dump-step rest writes the step that left the pile at rest. */
        pile = measure_pile(&w, &now);
        at_rest = pile.max_rate < REST_RATE ? (at_rest < 0 ? step : at_rest) : -1;
        if (st.dump_step == step || (st.dump_step == DUMP_AT_REST && !dumped_at_rest && at_rest == step)) {
            dumped_at_rest = st.dump_step == DUMP_AT_REST;
            frix_problem *dumped = NULL;
            if ((e = global_problem(M, H, f, wv, mu, mu_r, mu_s, nc, dim, &dumped))) {
                failed = "the dumped problem";
                goto done;
            }
            char title[96];
            snprintf(title, sizeof title, "granular: %lld spheres, step %lld, seed %lld", (long long)n, (long long)step,
                     (long long)st.scene.seed);
            frix_problem_set_title(dumped, title);
            e = st.dump ? dump_with_warm_start(st.dump, dumped, mdiag, r, u, v_new, r_warm) : FRIX_OK;
            frix_problem_free(dumped);
            if (e) {
                failed = "--dump";
                goto done;
            }
            if (st.dump_local && (e = write_local_form(&w, &now, dim, mdiag, f, wv, mu, mu_r, mu_s, title, r, u, r_warm,
                                                        st.dump_local))) {
                failed = "--dump-local";
                goto done;
            }
        }
        for (int64_t i = 0; i < n; ++i)
            for (int q = 0; q < 3; ++q) w.x[3 * i + q] += st.scene.h * w.v[6 * i + q];
        memcpy(r_before, r, sizeof *r * (size_t)(dim * nc));
        const double en = energy(&w);
        double err_siconos = NAN;
        frix_info_get_double(info, FRIX_INFO_ERROR_RELATIVE, &err_siconos);
        if (!st.quiet && (step % st.scene.every == 0 || step == st.scene.steps - 1 || (st.settle && at_rest == step)))
            printf("%lld %lld %s %lld %.3e %.3e %.4f %.9g %.4e %.4e %.3e\n", (long long)step, (long long)nc, st.solver,
                   (long long)frix_info_iterations(info), err, err_siconos, frix_info_solve_time(info), en,
                   pile.kinetic, pile.max_rate, pile.penetration);
        /* Always said: the next steps start from an inexact answer. */
        if (s != FRIX_STATUS_CONVERGED) {
            fprintf(stderr, "granular: step %lld did not converge: %s, error %.3e\n", (long long)step,
                    frix_status_string(s), err);
            ++unconverged;
            if (st.check) status = 1;
        }
        if (st.check) {
            /* The impulses' work is <= 0 for an exact answer; a solve to tolerance tol may add
             * up to about tol of the step's contact energy scale, here bounded by e0. */
            if (en > e_before + 10.0 * st.scene.tol * fabs(e0)) {
                fprintf(stderr, "granular: step %lld: the energy grew from %.9g to %.9g J\n", (long long)step, e_before,
                        en);
                status = 1;
            }
        }
        e_before = en;
    }
    if (unconverged > 0)
        fprintf(stderr, "granular: %lld of %lld steps did not converge\n", (long long)unconverged, (long long)step);
    if (st.dump_step == DUMP_AT_REST && !dumped_at_rest) {
        fprintf(stderr, "granular: --dump-step rest: the pile did not come to rest in %lld steps, nothing was written\n",
                (long long)step);
        status = 1;
    }
    if (!st.quiet) {
        if (at_rest >= 0) printf("# at rest after step %lld\n", (long long)at_rest);
        else printf("# not at rest after %lld steps: the fastest grain moves %.3g radius/s\n", (long long)step, pile.max_rate);
        const double angle = angle_of_repose(&w);
        if (isnan(angle)) printf("# angle of repose: none (no heap two diameters high to fit a slope to)\n");
        else printf("# angle of repose %.1f degrees\n", angle);
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
    free(mu_r);
    free(mu_s);
    free(r);
    free(u);
    free(r_before);
    free(r_warm);
    free_world(&w);
    return status;
}
