/* The granular client's physics report (examples/granular/physics.h): the kinetic energy, the
 * fastest grain over its radius and the deepest overlap of a hand-made pile, and the angle of
 * repose of a heap built at a known slope, of a flat layer and of no heap at all. */
#include <math.h>
#include <stdlib.h>

#include "check_main.h"
#include "physics.h"

enum { kMaxGrains = 20000 };

/* Room for kMaxGrains spheres of radius R, no velocities; the caller fills x and sets n. */
static world empty_world(double R, double box) {
    world w = {0};
    w.x = calloc(3 * kMaxGrains, sizeof *w.x);
    w.v = calloc(6 * kMaxGrains, sizeof *w.v);
    w.radius = calloc(kMaxGrains, sizeof *w.radius);
    w.mass = calloc(kMaxGrains, sizeof *w.mass);
    w.inertia = calloc(kMaxGrains, sizeof *w.inertia);
    ck_assert(w.x && w.v && w.radius && w.mass && w.inertia);
    for (int i = 0; i < kMaxGrains; ++i) w.radius[i] = R, w.mass[i] = 1.0, w.inertia[i] = 0.4 * R * R;
    w.rmax = w.rmin = R;
    w.box[0] = w.box[1] = box;
    return w;
}

/* Spheres on a square lattice of spacing 2R centred in the box, stacked at every site under
 * the surface z = height - tan(slope) * (distance from the box's centre). */
static void build_heap(world *w, double slope_degrees, double height) {
    const double R = w->rmax, d = 2.0 * R, c = 0.5 * w->box[0], t = tan(slope_degrees * M_PI / 180.0);
    const int sites = (int)(w->box[0] / d);
    w->n = 0;
    for (int ix = 0; ix < sites; ++ix)
        for (int iy = 0; iy < sites; ++iy) {
            const double x = (ix + 0.5) * d, y = (iy + 0.5) * d, rho = hypot(x - c, y - c);
            for (int iz = 0; R + iz * d + R <= height - t * rho && w->n < kMaxGrains; ++iz) {
                double *p = &w->x[3 * w->n++];
                p[0] = x, p[1] = y, p[2] = R + iz * d;
            }
        }
    ck_assert_int_lt(w->n, kMaxGrains);
}

static void free_test_world(world *w) {
    free(w->x);
    free(w->v);
    free(w->radius);
    free(w->mass);
    free(w->inertia);
}

START_TEST(test_pile_state) {
    world w = empty_world(0.01, 1.0);
    w.n = 2;
    w.radius[1] = 0.005;
    w.mass[1] = 2.0;
    w.inertia[1] = 1e-5;
    const double v[12] = {0.3, 0.0, 0.4, 0.0, 0.0, 2.0, /* 0.5 m/s on radius 0.01 */
                          0.0, 0.1, 0.0, 1.0, 0.0, 0.0}; /* 0.1 m/s on radius 0.005 */
    for (int k = 0; k < 12; ++k) w.v[k] = v[k];
    contact c[2] = {{.a = 0, .b = 1, .gap = -1e-4}, {.a = 0, .b = 2, .gap = 3e-3}};
    const contacts cs = {c, 2, 2};
    const pile_state p = measure_pile(&w, &cs);
    const double kinetic = 0.5 * 1.0 * 0.25 + 0.5 * w.inertia[0] * 4.0 + 0.5 * 2.0 * 0.01 + 0.5 * 1e-5 * 1.0;
    ck_assert_double_eq_tol(p.kinetic, kinetic, 1e-15);
    ck_assert_double_eq_tol(p.max_rate, 50.0, 1e-12);
    ck_assert_double_eq_tol(p.penetration, 1e-4 / 0.01, 1e-14);
    free_test_world(&w);
}
END_TEST

START_TEST(test_angle_of_a_built_heap) {
    const double slopes[] = {25.0, 32.0, 40.0};
    for (int k = 0; k < 3; ++k) {
        world w = empty_world(0.025, 3.0);
        build_heap(&w, slopes[k], 0.6);
        const double angle = angle_of_repose(&w);
        ck_assert_msg(fabs(angle - slopes[k]) < 3.0, "a heap at %g degrees measures %g", slopes[k], angle);
        free_test_world(&w);
    }
}
END_TEST

START_TEST(test_flat_layer_and_no_heap) {
    world w = empty_world(0.01, 1.0);
    build_heap(&w, 0.0, 0.081); /* four layers over the whole floor */
    ck_assert_msg(angle_of_repose(&w) < 1.0, "a flat layer measures %g degrees", angle_of_repose(&w));
    w.n = 1;
    ck_assert(isnan(angle_of_repose(&w)));
    free_test_world(&w);
}
END_TEST

int main(void) {
    Suite *s = suite_create("granular_physics");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, test_pile_state);
    tcase_add_test(tc, test_angle_of_a_built_heap);
    tcase_add_test(tc, test_flat_layer_and_no_heap);
    suite_add_tcase(s, tc);
    return frix_run_suite(s);
}
