/* A FEM host's time steps, one-shot against persistent (a benchmark, not a test): the elastic
 * grid of tests/support/elastic_grid.h (a deformable body in global form, M = I + h^2 k L)
 * under a load that swings from step to step, f_k = f (1 + A sin(2 pi k / 8)); M and H do
 * not change, as in a host whose contact nodes stay put. Every step is solved from the
 * previous step's answer by frix_solve and by a frix_persistent updated with f_k alone, which
 * keeps M's factorisation and W = H^T M^-1 H from its first solve. Both start from the
 * one-shot's answer of the step before; f swings along one direction, so the persistent way
 * takes its secant start (frix_persistent.h; --set secant_start=0 turns it off) at the steps
 * where that answer is its own last one to the bit and the swing's step is at most twice the
 * last one.
 *
 *   fem_steps [--grid NX NY NZ] [--steps S] [--runs R] [--tol T] [--gap G] [--stiffness K]
 *             [--swing A] [--solvers auto,...] [--set KEY=VALUE ...]
 *
 * Prints per solver and step the median time of R runs of each way, with the persistent
 * way's setup and reduction times (FRIX_INFO_SETUP_TIME, FRIX_INFO_REDUCTION_TIME),
 * iterations and errors; then per solver the totals and the mean of the steps after the
 * first. The two ways alternate within each step, the first of them changing from run to run.
 */
#include <frix/frix.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "elastic_grid.h"
#include "step_timing.h"

static void die(const char *what) {
    fprintf(stderr, "fem_steps: %s: %s\n", what, frix_last_error_message());
    exit(2);
}

static double info_double(const frix_info *info, frix_info_key key) {
    double x = NAN;
    frix_info_get_double(info, key, &x);
    return x;
}

int main(int argc, char **argv) {
    int nx = 40, ny = 40, nz = 10, steps = 8, runs = 3;
    double tol = 1e-8, gap = 0.0, stiffness = 1e4, swing = 0.25;
    char solvers_arg[256] = "auto";
    const char *sets[16];  /* --set: options given to every solver, by name */
    int nsets = 0;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        const int left = argc - 1 - i;
        if (!strcmp(a, "--grid") && left >= 3) {
            nx = atoi(argv[++i]);
            ny = atoi(argv[++i]);
            nz = atoi(argv[++i]);
        } else if (!strcmp(a, "--steps") && left >= 1) steps = atoi(argv[++i]);
        else if (!strcmp(a, "--runs") && left >= 1) runs = atoi(argv[++i]);
        else if (!strcmp(a, "--tol") && left >= 1) tol = atof(argv[++i]);
        else if (!strcmp(a, "--gap") && left >= 1) gap = atof(argv[++i]);
        else if (!strcmp(a, "--stiffness") && left >= 1) stiffness = atof(argv[++i]);
        else if (!strcmp(a, "--swing") && left >= 1) swing = atof(argv[++i]);
        else if (!strcmp(a, "--solvers") && left >= 1) snprintf(solvers_arg, sizeof solvers_arg, "%s", argv[++i]);
        else if (!strcmp(a, "--set") && left >= 1 && nsets < 16 && strchr(argv[i + 1], '=')) sets[nsets++] = argv[++i];
        else {
            fprintf(stderr, "usage: fem_steps [--grid NX NY NZ] [--steps S] [--runs R] [--tol T] [--gap G] "
                            "[--stiffness K] [--swing A] [--solvers a,b,...] [--set KEY=VALUE ...]\n");
            return 2;
        }
    }
    if (steps < 1 || runs < 1 || !(tol > 0)) {
        fprintf(stderr, "fem_steps: steps, runs and tol must be positive\n");
        return 2;
    }
    frix_elastic_grid g;
    if (frix_elastic_grid_make(nx, ny, nz, gap, stiffness, &g)) die("grid");
    const int64_t m = frix_problem_contact_dofs(g.problem), n = frix_problem_dofs(g.problem);
    /* The steps' loads, and problems that borrow them with the grid's M, H, w and mu. */
    double **f = calloc((size_t)steps, sizeof *f);
    frix_problem **p = calloc((size_t)steps, sizeof *p);
    for (int k = 0; k < steps; ++k) {
        f[k] = malloc(sizeof **f * (size_t)n);
        const double scale = 1.0 + swing * sin(2.0 * 3.14159265358979323846 * k / 8.0);
        for (int64_t j = 0; j < n; ++j) f[k][j] = scale * g.f[j];
        if (frix_problem_global(g.M, g.H, f[k], g.w, g.mu, frix_problem_contacts(g.problem), &p[k])) die("problem");
    }
    printf("# elastic grid %dx%dx%d (k %.3g, gap %.3g): %lld contacts, %lld dofs; %d steps, load swinging by "
           "%.3g; tolerance %.0e; median of %d runs\n",
           nx, ny, nz, stiffness, gap, (long long)(m / 3), (long long)n, steps, swing, tol, runs);
    printf("%-8s %4s %10s %10s %6s %9s %9s %5s %5s %9s %9s\n", "solver", "step", "oneshot_s", "persist_s", "ratio",
           "p_setup_s", "p_reduc_s", "it_1", "it_p", "err_1", "err_p");
    double *r = malloc(sizeof *r * (size_t)m), *u = malloc(sizeof *u * (size_t)m), *v = malloc(sizeof *v * (size_t)n);
    double **warm = calloc((size_t)steps, sizeof *warm);
    const size_t cells = (size_t)runs * (size_t)steps;
    double *t1 = malloc(sizeof(double) * cells), *tp = malloc(sizeof(double) * cells);
    double *col = malloc(sizeof(double) * (size_t)runs);
    double *setup = malloc(sizeof(double) * (size_t)steps), *reduction = malloc(sizeof(double) * (size_t)steps);
    int64_t *it1 = malloc(sizeof(int64_t) * (size_t)steps), *itp = malloc(sizeof(int64_t) * (size_t)steps);
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
        for (int k = 0; k < nsets; ++k) {
            char key[64];
            const size_t len = (size_t)(strchr(sets[k], '=') - sets[k]);
            snprintf(key, sizeof key, "%.*s", (int)len, sets[k]);
            if (frix_options_set_by_name(o, key, sets[k] + len + 1)) die(sets[k]);
        }
        /* Warm starts: step k from the answer of step k - 1 (step 0 from r = 0), solved once. */
        memset(r, 0, sizeof *r * (size_t)m);
        for (int k = 0; k < steps; ++k) {
            if (!warm[k]) warm[k] = malloc(sizeof *r * (size_t)m);
            memcpy(warm[k], r, sizeof *r * (size_t)m);
            if (frix_solve(p[k], o, r, u, v, NULL)) die("warm start");
        }
        for (int run = 0; run < runs; ++run) {
            frix_persistent *ps = NULL;
            for (int k = 0; k < steps; ++k) {
                const size_t c = (size_t)run * (size_t)steps + (size_t)k;
                for (int way = 0; way < 2; ++way) {
                    const int persistent = (way + run) % 2;
                    memcpy(r, warm[k], sizeof *r * (size_t)m);
                    const double t0 = now();
                    if (!persistent) {
                        if (frix_solve(p[k], o, r, u, v, info)) die("frix_solve");
                    } else {
                        if (k == 0) {
                            if (frix_persistent_create(p[k], o, &ps)) die("persistent create");
                        } else if (frix_persistent_update_global(ps, NULL, NULL, f[k], NULL, NULL)) {
                            die("persistent update");
                        }
                        if (frix_persistent_solve(ps, r, u, v, info)) die("frix_persistent_solve");
                        setup[k] = info_double(info, FRIX_INFO_SETUP_TIME);
                        reduction[k] = info_double(info, FRIX_INFO_REDUCTION_TIME);
                    }
                    (persistent ? tp : t1)[c] = now() - t0;
                    (persistent ? itp : it1)[k] = frix_info_iterations(info);
                    (persistent ? ep : e1)[k] = frix_info_error(info);
                    if (frix_info_status(info) != FRIX_STATUS_CONVERGED) failed = 1;
                }
            }
            frix_persistent_free(ps);
        }
        double total1 = 0, totalp = 0, later1 = 0, laterp = 0;
        for (int k = 0; k < steps; ++k) {
            const double m1 = step_median(t1, runs, steps, k, col);
            const double mp = step_median(tp, runs, steps, k, col);
            total1 += m1;
            totalp += mp;
            if (k > 0) later1 += m1, laterp += mp;
            printf("%-8s %4d %10.4f %10.4f %6.2f %9.4f %9.4f %5lld %5lld %9.2e %9.2e\n", name, k, m1, mp, mp / m1,
                   setup[k], reduction[k], (long long)it1[k], (long long)itp[k], e1[k], ep[k]);
        }
        printf("%-8s total one-shot %.3f s, persistent %.3f s; steps after the first: one-shot %.3f s, "
               "persistent %.3f s a step\n",
               name, total1, totalp, steps > 1 ? later1 / (steps - 1) : 0.0, steps > 1 ? laterp / (steps - 1) : 0.0);
        fflush(stdout);
        frix_options_free(o);
    }
    if (failed) printf("# some solves did not converge (see the error columns)\n");
    frix_info_free(info);
    for (int k = 0; k < steps; ++k) {
        frix_problem_free(p[k]);
        free(f[k]);
        free(warm[k]);
    }
    free(p);
    free(f);
    free(warm);
    frix_elastic_grid_free(&g);
    free(r);
    free(u);
    free(v);
    free(t1);
    free(tp);
    free(col);
    free(setup);
    free(reduction);
    free(it1);
    free(itp);
    free(e1);
    free(ep);
    return failed;
}
