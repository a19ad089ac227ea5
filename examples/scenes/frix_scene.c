/* Writes FCLIB problems built from rigid-body scenes (scenes.h), a deformable grid
 * (elastic_grid.h), or the whole hard-case set.
 *
 *   frix_scene stack|chain|spheres|slope OUT.hdf5 [--count N] [--mass-ratio R] [--mu MU]
 *              [--step H] [--scale S] [--per-face K] [--angle DEG] [--speed V] [--load L]
 *              [--frame-angle DEG] [--spread F] [--local]
 *   frix_scene elastic-grid OUT.hdf5 NX NY NZ [GAP [STIFFNESS]]   (global only: W would be dense)
 *   frix_scene hard-set DIR      (DIR/NAME.hdf5 for every case of the hard-case set)
 *   frix_scene list              (the hard-case set, one line per case)
 *
 * A scene is written as a global problem (M, H, f, w, mu), or reduced (W, q, mu) with
 * --local. Exit status 0 on success, 2 on a usage error or a failed write.
 */
#include "elastic_grid.h"
#include "scenes.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const double kDeg = 3.14159265358979323846 / 180.0;

static int usage(const char *msg, const char *arg) {
    fprintf(stderr, "frix_scene: %s%s%s\n", msg, arg ? ": " : "", arg ? arg : "");
    fprintf(stderr, "usage: frix_scene stack|chain|spheres|slope OUT.hdf5 [--count N] [--mass-ratio R]\n"
                    "         [--mu MU] [--step H] [--scale S] [--per-face K] [--angle DEG] [--speed V]\n"
                    "         [--load L] [--frame-angle DEG] [--spread F] [--local]\n"
                    "       frix_scene elastic-grid OUT.hdf5 NX NY NZ [GAP [STIFFNESS]]\n"
                    "       frix_scene hard-set DIR | frix_scene list\n");
    return 2;
}

static int number(const char *s, double *out) {
    char *end = NULL;
    errno = 0;
    double v = strtod(s, &end);
    if (!*s || *end || errno || !isfinite(v)) return 0;
    *out = v;
    return 1;
}

static int hard_set(const char *dir) {
    int failed = 0;
    for (int i = 0; i < frix_hard_case_count(); ++i) {
        frix_hard_case c;
        char path[4096];
        snprintf(path, sizeof path, "%s/%s.hdf5", dir, frix_hard_case_name(i));
        frix_error err = frix_hard_case_make(i, &c);
        if (!err) err = frix_fclib_write(path, c.problem, NULL, NULL, NULL, 0, NULL, NULL, NULL);
        if (err) {
            fprintf(stderr, "frix_scene: %s: %s\n", path, frix_last_error_message());
            failed = 1;
        }
        frix_hard_case_free(&c);
    }
    if (!failed) printf("wrote %d problems to %s\n", frix_hard_case_count(), dir);
    return failed ? 2 : 0;
}

static int elastic_grid(int argc, char **argv) {
    if (argc < 6 || argc > 8) return usage("elastic-grid takes OUT.hdf5 NX NY NZ [GAP [STIFFNESS]]", NULL);
    double size[3], gap = 0.0, stiffness = 1e4;
    for (int k = 0; k < 3; ++k)
        if (!number(argv[3 + k], &size[k]) || size[k] != floor(size[k]) || size[k] < 1 || size[k] > 1e6)
            return usage("not a grid size", argv[3 + k]);
    if (argc >= 7 && (!number(argv[6], &gap) || gap < 0)) return usage("not a gap >= 0", argv[6]);
    if (argc == 8 && (!number(argv[7], &stiffness) || stiffness <= 0)) return usage("not a stiffness > 0", argv[7]);
    frix_elastic_grid g;
    frix_error err = frix_elastic_grid_make((int)size[0], (int)size[1], (int)size[2], gap, stiffness, &g);
    if (err == FRIX_ERR_INVALID_ARGUMENT) return usage("grid too large", NULL);
    if (!err) err = frix_fclib_write(argv[2], g.problem, NULL, NULL, NULL, 0, NULL, NULL, NULL);
    if (err)
        fprintf(stderr, "frix_scene: %s\n", frix_last_error_message());
    else
        printf("wrote %s: elastic grid %dx%dx%d, %lld contacts, %lld dofs (global)\n", argv[2], (int)size[0],
               (int)size[1], (int)size[2], (long long)frix_problem_contacts(g.problem),
               (long long)frix_problem_dofs(g.problem));
    frix_elastic_grid_free(&g);
    return err ? 2 : 0;
}

int main(int argc, char **argv) {
    if (argc < 2) return usage("missing scene", NULL);
    if (strcmp(argv[1], "list") == 0) {
        for (int i = 0; i < frix_hard_case_count(); ++i) {
            frix_hard_case c;
            if (frix_hard_case_make(i, &c) == FRIX_OK)
                printf("%-30s %-6s %4lld contacts  %s\n", c.name,
                       frix_problem_get_kind(c.problem) == FRIX_PROBLEM_GLOBAL ? "global" : "local",
                       (long long)frix_problem_contacts(c.problem), c.what);
            frix_hard_case_free(&c);
        }
        return 0;
    }
    if (strcmp(argv[1], "hard-set") == 0) {
        if (argc != 3) return usage("hard-set takes one DIR", NULL);
        return hard_set(argv[2]);
    }
    if (strcmp(argv[1], "elastic-grid") == 0) return elastic_grid(argc, argv);
    static const char *const kinds[] = {"stack", "chain", "spheres", "slope"};
    int kind = -1;
    for (int k = 0; k < 4; ++k)
        if (strcmp(argv[1], kinds[k]) == 0) kind = k;
    if (kind < 0) return usage("unknown scene", argv[1]);
    if (argc < 3 || argv[2][0] == '-') return usage("missing OUT.hdf5", NULL);
    frix_scene_params p;
    frix_scene_defaults((frix_scene_kind)kind, &p);
    int local = 0;
    for (int i = 3; i < argc; ++i) {
        const char *opt = argv[i];
        if (strcmp(opt, "--local") == 0) {
            local = 1;
            continue;
        }
        double x;
        if (i + 1 >= argc) return usage("option needs a value", opt);
        if (!number(argv[++i], &x)) return usage("not a finite number", argv[i]);
        if (strcmp(opt, "--count") == 0 || strcmp(opt, "--per-face") == 0) {
            if (x != floor(x) || fabs(x) > 1e6) return usage("not an integer in range", argv[i]);
            if (opt[2] == 'c') p.count = (int)x;
            else p.per_face = (int)x;
        } else if (strcmp(opt, "--mass-ratio") == 0) p.mass_ratio = x;
        else if (strcmp(opt, "--mu") == 0) p.mu = x;
        else if (strcmp(opt, "--step") == 0) p.step = x;
        else if (strcmp(opt, "--scale") == 0) p.scale = x;
        else if (strcmp(opt, "--angle") == 0) p.angle = x * kDeg;
        else if (strcmp(opt, "--speed") == 0) p.speed = x;
        else if (strcmp(opt, "--load") == 0) p.load = x;
        else if (strcmp(opt, "--frame-angle") == 0) p.frame_angle = x * kDeg;
        else if (strcmp(opt, "--spread") == 0) p.spread = x;
        else return usage("unknown option", opt);
    }
    frix_scene s;
    frix_scene_problems forms;
    const char *why = NULL;
    frix_error err = frix_scene_build(&p, &s, &why);
    if (err) return usage(why, NULL);
    err = frix_scene_problems_make(&s, &forms);
    if (!err)
        err = frix_fclib_write(argv[2], local ? forms.local : forms.global, NULL, NULL, NULL, 0,
                               NULL, NULL, NULL);
    if (err)
        fprintf(stderr, "frix_scene: %s\n", frix_last_error_message());
    else
        printf("wrote %s: %s (%s)\n", argv[2], s.title, local ? "local" : "global");
    frix_scene_problems_free(&forms);
    frix_scene_free(&s);
    return err ? 2 : 0;
}
