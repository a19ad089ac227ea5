/* Persistent solver against one-shot frix_solve over the steps of a scene (a benchmark, not a
 * test): the pyramid of spheres (tests/support/scenes.h) stepped in time, each step's problem
 * solved from the same warm start (the previous step's answer) by frix_solve and by a
 * frix_persistent updated with the step's data.
 *
 *   persistent_steps [--layers L] [--steps S] [--runs R] [--tol T] [--global]
 *                    [--solvers nsgs,nsn-ac,prox,admm,ipm,auto] [--turn RAD] [--shake G]
 *                    [--driver NAME]
 *
 * The steps: step k's contact frames are turned by k x RAD about their normals (W and H
 * change values, not pattern; --turn 0 keeps them), the ground shakes sideways (every body
 * feels a horizontal acceleration G g sin(2 pi k / 8), --shake, default 0), and
 * f = M v_{k-1} + h F_ext carries the velocities of step k-1
 * (v from the driver's answers, prox at tolerance 1e-9 by default, so that both ways solve the
 * same sequence). The
 * first step is solved from the answer of the step before it, which is not timed: every
 * timed solve is warm-started, as in a simulation. --global solves
 * the global form (M, H, f, w) instead of the local one (W, q).
 * The two ways alternate within each step, the first of them changing from run to run.
 * Prints per solver and step the median time of R runs of each way, iterations and errors;
 * then per solver the total time of each way and their ratio.
 */
#include <frix/frix.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scenes.h"
#include "step_timing.h"

/* One step of the sequence: its scene and both forms. */
typedef struct step {
    frix_scene scene;
    frix_scene_problems forms;
} step;

static void die(const char *what) {
    fprintf(stderr, "persistent_steps: %s: %s\n", what, frix_last_error_message());
    exit(2);
}

int main(int argc, char **argv) {
    int layers = 8, steps = 20, runs = 3, global = 0;
    double tol = 1e-6, turn = 0.01, shake = 0.0;
    char solvers_arg[256] = "nsgs,nsn-ac,prox,admm,ipm,auto";
    const char *driver_name = "prox";
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        const char *next = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "--global")) global = 1;
        else if (!strcmp(a, "--layers") && next) layers = atoi(argv[++i]);
        else if (!strcmp(a, "--steps") && next) steps = atoi(argv[++i]);
        else if (!strcmp(a, "--runs") && next) runs = atoi(argv[++i]);
        else if (!strcmp(a, "--tol") && next) tol = atof(argv[++i]);
        else if (!strcmp(a, "--turn") && next) turn = atof(argv[++i]);
        else if (!strcmp(a, "--shake") && next) shake = atof(argv[++i]);
        else if (!strcmp(a, "--driver") && next) driver_name = argv[++i];
        else if (!strcmp(a, "--solvers") && next) snprintf(solvers_arg, sizeof solvers_arg, "%s", argv[++i]);
        else {
            fprintf(stderr, "usage: persistent_steps [--layers L] [--steps S] [--runs R] [--tol T] [--global] "
                            "[--solvers a,b,...] [--turn RAD] [--shake G] [--driver NAME]\n");
            return 2;
        }
    }
    if (layers < 1 || steps < 1 || runs < 1 || !(tol > 0)) {
        fprintf(stderr, "persistent_steps: layers, steps, runs and tol must be positive\n");
        return 2;
    }

    /* The sequence, driven by the driver's one-shot answers (tolerance 1e-9). */
    step *all = calloc((size_t)steps + 1, sizeof *all);
    step *seq = all + 1;  /* seq[-1] is the untimed step before the first */
    frix_scene_params prm;
    frix_scene_defaults(FRIX_SCENE_SPHERES, &prm);
    prm.count = layers;
    double *v_prev = NULL, *r_prev = NULL;
    frix_options *driver = NULL;
    int driver_id;
    if (frix_solver_by_name(driver_name, &driver_id)) die(driver_name);
    if (frix_options_create(driver_id, &driver)) die("options");
    frix_options_set_double(driver, FRIX_OPT_TOLERANCE, 1e-9);
    for (int k = -1; k < steps; ++k) {
        const char *why = NULL;
        prm.frame_angle = turn * (k + 1);
        if (frix_scene_build(&prm, &seq[k].scene, &why)) {
            fprintf(stderr, "persistent_steps: scene: %s\n", why);
            return 2;
        }
        frix_scene *s = &seq[k].scene;
        if (k == -1) {
            v_prev = calloc((size_t)s->n, sizeof *v_prev);
            r_prev = calloc(3 * (size_t)s->nc, sizeof *r_prev);
        }
        for (int64_t j = 0; j < s->n; ++j) s->f[j] += v_prev[j] / s->minv[j];
        for (int64_t b = 0; b < s->bodies; ++b)
            s->f[6 * b] += prm.step * shake * FRIX_SCENE_GRAVITY * sin(2.0 * 3.14159265358979323846 * (k + 1) / 8.0) /
                           s->minv[6 * b];
        if (frix_scene_problems_make(s, &seq[k].forms)) die("problems");
        double *u = calloc(3 * (size_t)s->nc, sizeof *u), *v = calloc((size_t)s->n, sizeof *v);
        if (frix_solve(seq[k].forms.global, driver, r_prev, u, v, NULL)) die("driver solve");
        memcpy(v_prev, v, sizeof *v * (size_t)s->n);
        free(u);
        free(v);
    }
    const int64_t nc = seq[0].scene.nc, n = seq[0].scene.n;
    printf("# spheres pyramid, %d layers: %lld contacts, %lld dofs; %d steps, frames turning %.3g rad a step, "
           "shaken by %.3g g; %s form; tolerance %.0e; median of %d runs\n",
           layers, (long long)nc, (long long)n, steps, turn, shake, global ? "global" : "local", tol, runs);
    printf("%-8s %4s %10s %10s %6s %5s %5s %9s %9s %4s %4s\n", "solver", "step", "oneshot_s", "persist_s", "ratio",
           "it_1", "it_p", "err_1", "err_p", "fa_1", "fa_p");

    /* Warm starts: the driver's answers, recomputed once more per step (r_prev of step k). */
    double **warm = calloc((size_t)steps, sizeof *warm);
    {
        double *r = calloc(3 * (size_t)nc, sizeof *r), *u = calloc(3 * (size_t)nc, sizeof *u),
               *v = calloc((size_t)n, sizeof *v);
        if (frix_solve(seq[-1].forms.global, driver, r, u, v, NULL)) die("warm start");
        for (int k = 0; k < steps; ++k) {
            warm[k] = malloc(sizeof *r * 3 * (size_t)nc);
            memcpy(warm[k], r, sizeof *r * 3 * (size_t)nc);
            if (frix_solve(seq[k].forms.global, driver, r, u, v, NULL)) die("warm start");
        }
        free(r);
        free(u);
        free(v);
    }

    double *r = malloc(sizeof *r * 3 * (size_t)nc), *u = malloc(sizeof *u * 3 * (size_t)nc),
           *v = malloc(sizeof *v * (size_t)n);
    /* Per run and step: times, iterations, errors, factorisations of each way. */
    const size_t cells = (size_t)runs * (size_t)steps;
    double *t1 = malloc(sizeof(double) * cells), *tp = malloc(sizeof(double) * cells);
    double *col = malloc(sizeof(double) * (size_t)runs);
    int64_t *it1 = malloc(sizeof(int64_t) * (size_t)steps), *itp = malloc(sizeof(int64_t) * (size_t)steps);
    int64_t *fa1 = malloc(sizeof(int64_t) * (size_t)steps), *fap = malloc(sizeof(int64_t) * (size_t)steps);
    double *e1 = malloc(sizeof(double) * (size_t)steps), *ep = malloc(sizeof(double) * (size_t)steps);
    frix_info *info = NULL;
    if (frix_info_create(&info)) die("info");
    char list[256];
    snprintf(list, sizeof list, "%s", solvers_arg);
    int failed = 0;
    for (char *name = strtok(list, ","); name; name = strtok(NULL, ",")) {
        int id;
        if (frix_solver_by_name(name, &id)) die(name);
        frix_options *o = NULL;
        if (frix_options_create(id, &o)) die("options");
        frix_options_set_double(o, FRIX_OPT_TOLERANCE, tol);
        for (int run = 0; run < runs; ++run) {
            frix_persistent *ps = NULL;
            for (int k = 0; k < steps; ++k) {
                frix_problem *p = global ? seq[k].forms.global : seq[k].forms.local;
                const frix_scene_problems *f = &seq[k].forms;
                const size_t c = (size_t)run * (size_t)steps + (size_t)k;
                /* The two ways in turn, the first of them alternating from run to run: a
                 * solve can leave caches warm or cold for the next. */
                for (int way = 0; way < 2; ++way) {
                    const int persistent = (way + run) % 2;
                    memcpy(r, warm[k], sizeof *r * 3 * (size_t)nc);
                    const double t0 = now();
                    if (!persistent) {
                        if (frix_solve(p, o, r, u, v, info)) die("frix_solve");
                    } else {
                        /* Created at step 0, updated with each step's data after. */
                        frix_error e = FRIX_OK;
                        if (k == 0) e = frix_persistent_create(p, o, &ps);
                        else if (global)
                            e = frix_persistent_update_global(ps, NULL, turn != 0.0 ? f->H : NULL, seq[k].scene.f,
                                                              seq[k].scene.w, NULL);
                        else e = frix_persistent_update_local(ps, turn != 0.0 ? f->W : NULL, f->q, NULL);
                        if (e) die("persistent update");
                        if (frix_persistent_solve(ps, r, u, v, info)) die("frix_persistent_solve");
                    }
                    (persistent ? tp : t1)[c] = now() - t0;
                    (persistent ? itp : it1)[k] = frix_info_iterations(info);
                    (persistent ? ep : e1)[k] = frix_info_error(info);
                    frix_info_get_int(info, FRIX_INFO_FACTORIZATIONS, persistent ? &fap[k] : &fa1[k]);
                    if (frix_info_status(info) != FRIX_STATUS_CONVERGED) failed = 1;
                }
            }
            frix_persistent_free(ps);
        }
        double total1 = 0, totalp = 0, worst = 0;
        for (int k = 0; k < steps; ++k) {
            const double m1 = step_median(t1, runs, steps, k, col);
            const double mp = step_median(tp, runs, steps, k, col);
            total1 += m1;
            totalp += mp;
            if (mp / m1 > worst) worst = mp / m1;
            printf("%-8s %4d %10.5f %10.5f %6.2f %5lld %5lld %9.2e %9.2e %4lld %4lld\n", name, k, m1, mp, mp / m1,
                   (long long)it1[k], (long long)itp[k], e1[k], ep[k], (long long)fa1[k], (long long)fap[k]);
        }
        printf("%-8s total one-shot %.4f s, persistent %.4f s, ratio %.2f; worst step %.2f\n", name,
               total1, totalp, totalp / total1, worst);
        fflush(stdout);
        frix_options_free(o);
    }
    if (failed) printf("# some solves did not converge (see the error columns)\n");
    frix_info_free(info);
    frix_options_free(driver);
    for (int k = -1; k < steps; ++k) {
        if (k >= 0) free(warm[k]);
        frix_scene_problems_free(&seq[k].forms);
        frix_scene_free(&seq[k].scene);
    }
    free(warm);
    free(all);
    free(v_prev);
    free(r_prev);
    free(r);
    free(u);
    free(v);
    free(t1);
    free(tp);
    free(col);
    free(it1);
    free(itp);
    free(fa1);
    free(fap);
    free(e1);
    free(ep);
    return 0;
}
