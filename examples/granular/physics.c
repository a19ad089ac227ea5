/* The pile's physics for the granular clients' reports (physics.h). */
#include "physics.h"

#include <math.h>
#include <stdlib.h>

pile_state measure_pile(const world *w, const contacts *cs) {
    pile_state p = {0.0, 0.0, 0.0};
    for (int64_t i = 0; i < w->n; ++i) {
        const double *v = &w->v[6 * i];
        const double speed2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
        p.kinetic += 0.5 * w->mass[i] * speed2 + 0.5 * w->inertia[i] * (v[3] * v[3] + v[4] * v[4] + v[5] * v[5]);
        p.max_rate = fmax(p.max_rate, sqrt(speed2) / w->radius[i]);
    }
    for (int64_t a = 0; a < cs->count; ++a) p.penetration = fmax(p.penetration, -cs->c[a].gap / w->rmin);
    return p;
}

double angle_of_repose(const world *w) {
    double cx = 0.0, cy = 0.0;
    for (int64_t i = 0; i < w->n; ++i) cx += w->x[3 * i], cy += w->x[3 * i + 1];
    cx /= (double)w->n;
    cy /= (double)w->n;
    const double bin = 2.0 * w->rmax;
    const double reach = 0.5 * sqrt(w->box[0] * w->box[0] + w->box[1] * w->box[1]);
    const int64_t bins = (int64_t)(reach / bin) + 2;
    /* Per bin: the highest top and its grain's distance from the axis. */
    double *top = malloc(sizeof *top * 2 * (size_t)bins), *at = top + bins;
    if (!top) return NAN;
    for (int64_t b = 0; b < bins; ++b) top[b] = -1.0;
    for (int64_t i = 0; i < w->n; ++i) {
        const double dx = w->x[3 * i] - cx, dy = w->x[3 * i + 1] - cy, rho = sqrt(dx * dx + dy * dy);
        int64_t b = (int64_t)(rho / bin);
        if (b >= bins) b = bins - 1;
        if (w->x[3 * i + 2] + w->radius[i] > top[b]) top[b] = w->x[3 * i + 2] + w->radius[i], at[b] = rho;
    }
    int64_t edge = -1;
    for (int64_t b = 0; b < bins; ++b)
        if (top[b] > 2.0 * bin) edge = b;
    double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0;
    int64_t used = 0;
    for (int64_t b = 0; b <= edge; ++b) {
        const double x = at[b];
        if (top[b] < 0.0 || x < 0.15 * (double)(edge + 1) * bin || x > 0.85 * (double)(edge + 1) * bin) continue;
        sx += x, sy += top[b], sxx += x * x, sxy += x * top[b];
        ++used;
    }
    free(top);
    if (used < 3) return NAN;
    const double m = (double)used, slope = (m * sxy - sx * sy) / (m * sxx - sx * sx);
    return atan(fmax(0.0, -slope)) * 180.0 / M_PI;
}
