/* A host that loads frix at run time, as an FEM code loads a contact-solver plugin: it is not
 * linked against libfrix, only compiled with <frix/frix_plugin.h> for the table's type.
 *
 *   plugin_host [LIBRARY]      (default "libfrix.so.0", found by the dynamic loader's path)
 *
 * It opens the library by name, looks up frix_plugin_api, asks for the table version it was
 * built with, checks the library's major version, solves a small problem through the table
 * and reports. Exit status 0 if everything worked and the solve converged. */
#include <frix/frix_plugin.h>

#include <dlfcn.h>
#include <stdio.h>
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
        ok = solve_one(fx);
    }
    dlclose(lib);
    return ok ? 0 : 1;
}
