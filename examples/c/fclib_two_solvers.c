/* Reads a problem file (FCLIB .hdf5, or Siconos .dat), solves it with two solvers from r = 0,
 * and writes the problem with the better solution to a new FCLIB file.
 *
 *   fclib_two_solvers IN OUT.hdf5 [SOLVER_A [SOLVER_B]]
 *
 * Solvers are named as in `frix solvers` (or by their Siconos spelling or id). The defaults
 * are nsgs, and nsgs again with its iterated-projection local solver in place of the
 * closed-form one. Exit status 0 if the better run converged. */
#include <frix/frix.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct run {
    const char *label;
    double *r, *u, *v;
    frix_status status;
    double error;
} run;

/* Solves `p` with the named solver (local_solver > 0 overrides its one-contact solver). */
static frix_error solve_with(const frix_problem *p, const char *solver, int local_solver, run *out) {
    int id = 0;
    frix_options *opts = NULL;
    frix_info *info = NULL;
    frix_error err = frix_solver_by_name(solver, &id);
    if (!err) err = frix_options_create(id, &opts);
    if (!err && local_solver > 0) err = frix_options_set_int(opts, FRIX_OPT_LOCAL_SOLVER, local_solver);
    if (!err) err = frix_info_create(&info);
    if (!err) err = frix_solve(p, opts, out->r, out->u, out->v, info);
    if (!err) {
        out->status = frix_info_status(info);
        out->error = frix_info_error(info);
        printf("%-28s %-28s %6lld iterations  error %.2e  %.3f s\n", out->label,
               frix_status_string(out->status), (long long)frix_info_iterations(info), out->error,
               frix_info_solve_time(info));
    }
    frix_info_free(info);
    frix_options_free(opts);
    return err;
}

int main(int argc, char **argv) {
    if (argc < 3 || argc > 5) {
        fprintf(stderr, "usage: %s IN OUT.hdf5 [SOLVER_A [SOLVER_B]]\n", argv[0]);
        return 2;
    }
    const char *a = argc > 3 ? argv[3] : "nsgs", *b = argc > 4 ? argv[4] : a;
    /* With one solver name for both runs, the second changes the local solver instead. */
    const int b_local = strcmp(a, b) == 0 ? FRIX_LOCAL_PROJECTION_ITERATED : 0;
    frix_problem *p = NULL;
    if (frix_read_problem(argv[1], &p) != FRIX_OK) {
        fprintf(stderr, "%s\n", frix_last_error_message());
        return 2;
    }
    size_t m = (size_t)frix_problem_contact_dofs(p), n = (size_t)frix_problem_dofs(p);
    char label_b[64];
    snprintf(label_b, sizeof label_b, "%s%s", b, b_local ? " (local solver 553)" : "");
    run runs[2] = {{a, NULL, NULL, NULL, FRIX_STATUS_NOT_RUN, 0}, {label_b, NULL, NULL, NULL, FRIX_STATUS_NOT_RUN, 0}};
    frix_error err = FRIX_OK;
    for (int k = 0; k < 2 && !err; ++k) {
        runs[k].r = calloc(m + 1, sizeof(double)); /* r = 0: a cold start */
        runs[k].u = calloc(m + 1, sizeof(double));
        runs[k].v = n ? calloc(n, sizeof(double)) : NULL;
        if (!runs[k].r || !runs[k].u || (n && !runs[k].v)) {
            fprintf(stderr, "out of memory\n");
            return 2;
        }
        err = solve_with(p, k == 0 ? a : b, k == 0 ? 0 : b_local, &runs[k]);
    }
    int best = -1;
    if (err) {
        fprintf(stderr, "%s\n", frix_last_error_message());
    } else {
        best = runs[1].error < runs[0].error ? 1 : 0;
        err = frix_fclib_write(argv[2], p, runs[best].r, runs[best].u, runs[best].v, 0, NULL, NULL, NULL);
        if (err)
            fprintf(stderr, "%s\n", frix_last_error_message());
        else
            printf("wrote %s with the solution of %s\n", argv[2], runs[best].label);
    }
    for (int k = 0; k < 2; ++k) {
        free(runs[k].r);
        free(runs[k].u);
        free(runs[k].v);
    }
    frix_problem_free(p);
    return !err && runs[best].status == FRIX_STATUS_CONVERGED ? 0 : 1;
}
