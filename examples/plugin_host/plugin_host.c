/* A host that loads frix at run time, as an FEM code loads a contact-solver plugin: it is not
 * linked against libfrix, only compiled with <frix/frix_plugin.h> for the table's type.
 *
 *   plugin_host [LIBRARY [PROBLEM]]   (LIBRARY: default "libfrix.so.0", found by the dynamic
 *                                      loader's path)
 *
 * It opens the library by name, looks up frix_plugin_api, asks for the table version it was
 * built with, checks the library's major version, solves a small problem through the table
 * and reports. Given a PROBLEM file (FCLIB, global form: M, H, f, w and mu as a FEM code
 * assembles them, e.g. by examples/getfem/block_on_plane.py --fclib), it solves that
 * instead, as a FEM code solves each load step: a persistent solver, which keeps M's
 * factorisation for the next steps. Where the file holds a solution, the answer must match
 * it: the same contact states (open, stick, slide) and the same v and r to 1e-6.
 * Exit status 0 if everything worked and the solve converged. */
#include <frix/frix_plugin.h>

#include <dlfcn.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The SONAME major this host was built for: another major may change any signature. */
#define HOST_WANTS_MAJOR FRIX_VERSION_MAJOR

static int solve_one(const frix_plugin_table *fx) {
    /* Two contacts on a block-diagonal W (column-major 3x3 blocks): one sticks, one slides. */
    double W[36] = {0};
    double q[6] = {-1.0, 0.1, 0.0, -1.0, 2.0, 0.0}, mu[2] = {0.5, 0.5};
    double r[6] = {0}, u[6];
    for (int i = 0; i < 6; ++i) W[i + 6 * i] = 1.0;
    frix_matrix *Wm = NULL;
    frix_problem *p = NULL;
    frix_info *info = NULL;
    int ok = fx->matrix_from_dense(6, 6, W, 6, &Wm) == FRIX_OK &&
             fx->problem_local(Wm, q, mu, 2, &p) == FRIX_OK && fx->info_create(&info) == FRIX_OK &&
             fx->solve(p, NULL, r, u, NULL, info) == FRIX_OK;
    if (!ok) {
        fprintf(stderr, "plugin_host: %s\n", fx->last_error_message());
    } else {
        printf("solve: %s in %lld iterations, error %.1e\n", fx->status_string(fx->info_status(info)),
               (long long)fx->info_iterations(info), fx->info_error(info));
        printf("r = (%g, %g, %g | %g, %g, %g)\n", r[0], r[1], r[2], r[3], r[4], r[5]);
        ok = fx->info_status(info) == FRIX_STATUS_CONVERGED;
        /* A member appended after the first table: present only in newer libraries. */
        if (FRIX_PLUGIN_HAS(fx, info_trace)) {
            const char *trace = fx->info_trace(info);
            printf("trace: %.*s\n", (int)strcspn(trace, "\n"), trace);
            ok = ok && strncmp(trace, "analysis:", 9) == 0;
        }
    }
    fx->info_free(info);
    fx->problem_free(p);
    fx->matrix_free(Wm);
    return ok;
}

/* The largest |x_i|. */
static double largest(const double *x, int64_t n) {
    double m = 0.0;
    for (int64_t i = 0; i < n; ++i) m = fmax(m, fabs(x[i]));
    return m;
}

/* The largest |x_i - y_i| over the largest |y_i|. */
static double relative_difference(const double *x, const double *y, int64_t n) {
    double d = 0.0;
    for (int64_t i = 0; i < n; ++i) d = fmax(d, fabs(x[i] - y[i]));
    const double scale = largest(y, n);
    return scale > 0.0 ? d / scale : d;
}

enum { OPEN, STICK, SLIDE };

/* A contact's state from (r, u, normal first): open where r_N is below 1e-7 of the largest
 * r_N; of the closed ones, sliding where the tangential velocity is above 1e-7 of the
 * largest |v| (the displacement of a static FEM problem). */
static int contact_state(const double *r, const double *u, double largest_rn, double largest_v) {
    if (r[0] <= 1e-7 * largest_rn) return OPEN;
    return hypot(u[1], u[2]) > 1e-7 * largest_v ? SLIDE : STICK;
}

/* Contacts whose states differ between two answers (r, u, v) and (r_ref, u_ref, v_ref). */
static int64_t state_differences(int64_t nc, int64_t n, const double *r, const double *u,
                                 const double *v, const double *r_ref, const double *u_ref,
                                 const double *v_ref, int64_t counts[3]) {
    double rn = 0.0, rn_ref = 0.0;
    for (int64_t a = 0; a < nc; ++a) {
        rn = fmax(rn, r[3 * a]);
        rn_ref = fmax(rn_ref, r_ref[3 * a]);
    }
    const double vmax = largest(v, n), vmax_ref = largest(v_ref, n);
    int64_t differ = 0;
    counts[OPEN] = counts[STICK] = counts[SLIDE] = 0;
    for (int64_t a = 0; a < nc; ++a) {
        const int s = contact_state(r + 3 * a, u + 3 * a, rn, vmax);
        ++counts[s];
        differ += s != contact_state(r_ref + 3 * a, u_ref + 3 * a, rn_ref, vmax_ref);
    }
    return differ;
}

/* A FEM-assembled problem from a file, solved by a persistent solver and, where the file
 * has a solution, checked against it. */
static int solve_file(const frix_plugin_table *fx, const char *path) {
    if (!FRIX_PLUGIN_HAS(fx, persistent_solve)) {
        fprintf(stderr, "plugin_host: this frix has no persistent solver (table v%d)\n", fx->abi_version);
        return 0;
    }
    frix_problem *p = NULL;
    frix_options *opts = NULL;
    frix_persistent *ps = NULL;
    frix_info *info = NULL;
    if (fx->read_problem(path, &p) != FRIX_OK) {
        fprintf(stderr, "plugin_host: %s\n", fx->last_error_message());
        return 0;
    }
    if (fx->problem_get_kind(p) != FRIX_PROBLEM_GLOBAL) {
        fprintf(stderr, "plugin_host: %s holds a local problem; a FEM host passes M and H\n", path);
        fx->problem_free(p);
        return 0;
    }
    const int64_t nc = fx->problem_contacts(p), n = fx->problem_dofs(p), m = 3 * nc;
    /* r, u, v, then the file's r, u, v. */
    double *work = calloc((size_t)(4 * m + 2 * n + 1), sizeof(double));
    if (work == NULL) {
        fprintf(stderr, "plugin_host: out of memory\n");
        fx->problem_free(p);
        return 0;
    }
    double *r = work, *u = r + m, *v = u + m, *r_ref = v + n, *u_ref = r_ref + m, *v_ref = u_ref + m;
    /* The host's tolerance: tighter than the default, as a comparison with another solver
     * wants. */
    int ok = fx->options_create(FRIX_SOLVER_AUTO, &opts) == FRIX_OK &&
             fx->options_set_double(opts, FRIX_OPT_TOLERANCE, 1e-10) == FRIX_OK &&
             fx->persistent_create(p, opts, &ps) == FRIX_OK && fx->info_create(&info) == FRIX_OK &&
             fx->persistent_solve(ps, r, u, v, info) == FRIX_OK;
    if (!ok) {
        fprintf(stderr, "plugin_host: %s: %s\n", path, fx->last_error_message());
    } else {
        printf("%s: %s\n", path, fx->problem_title(p));
        printf("solve: %lld dofs, %lld contacts: %s in %.3f s, error %.1e\n", (long long)n,
               (long long)nc, fx->status_string(fx->info_status(info)), fx->info_solve_time(info),
               fx->info_error(info));
        ok = fx->info_status(info) == FRIX_STATUS_CONVERGED;
        if (fx->fclib_read_solution(path, p, r_ref, u_ref, v_ref) == FRIX_OK) {
            int64_t counts[3];
            const int64_t differ = state_differences(nc, n, r, u, v, r_ref, u_ref, v_ref, counts);
            const double dv = relative_difference(v, v_ref, n), dr = relative_difference(r, r_ref, m);
            printf("against the file's solution: %lld open, %lld stick, %lld slide, %lld contacts in "
                   "another state; |v - v_file| / |v_file| %.1e, |r - r_file| / |r_file| %.1e\n",
                   (long long)counts[OPEN], (long long)counts[STICK], (long long)counts[SLIDE],
                   (long long)differ, dv, dr);
            ok = ok && differ == 0 && dv <= 1e-6 && dr <= 1e-6;
        }
    }
    fx->info_free(info);
    fx->persistent_free(ps);
    fx->options_free(opts);
    fx->problem_free(p);
    free(work);
    return ok;
}

int main(int argc, char **argv) {
    const char *name = argc > 1 ? argv[1] : "libfrix.so.0";
    void *lib = dlopen(name, RTLD_NOW | RTLD_LOCAL);
    if (!lib) {
        fprintf(stderr, "plugin_host: cannot load %s: %s\n", name, dlerror());
        return 1;
    }
    /* dlsym returns void *; going through a union avoids the object-to-function pointer cast
     * ISO C leaves undefined (POSIX guarantees the representation). */
    union {
        void *object;
        frix_plugin_api_fn function;
    } entry;
    entry.object = dlsym(lib, "frix_plugin_api");
    if (!entry.object) {
        fprintf(stderr, "plugin_host: %s has no frix_plugin_api: %s\n", name, dlerror());
        dlclose(lib);
        return 1;
    }
    const frix_plugin_table *fx = entry.function(FRIX_PLUGIN_ABI_VERSION);
    int ok = fx != NULL;
    if (!ok) {
        fprintf(stderr, "plugin_host: %s does not serve table version %d\n", name,
                FRIX_PLUGIN_ABI_VERSION);
    } else if (fx->abi_version != FRIX_PLUGIN_ABI_VERSION || fx->version_number / 10000 != HOST_WANTS_MAJOR ||
               !FRIX_PLUGIN_HAS(fx, solve)) {
        fprintf(stderr, "plugin_host: %s is frix %s (table v%d, %zu bytes): not usable by this host\n",
                name, fx->version_string(), fx->abi_version, fx->size);
        ok = 0;
    } else {
        printf("loaded %s: frix %s, plugin table v%d (%zu bytes; this host knows %zu)\n", name,
               fx->version_string(), fx->abi_version, fx->size, sizeof(frix_plugin_table));
        ok = argc > 2 ? solve_file(fx, argv[2]) : solve_one(fx);
    }
    dlclose(lib);
    return ok ? 0 : 1;
}
