/* What the granular clients report about the pile itself, beside the solver's figures: is it
 * at rest, is it sinking into itself, what slope does it stand at. */
#ifndef FRIX_EXAMPLE_PHYSICS_H
#define FRIX_EXAMPLE_PHYSICS_H

#include "pour.h"

/* A grain is at rest below this speed over its radius, per second (Chrono's settling test). */
#define REST_RATE 0.1

typedef struct {
    double kinetic;     /* translational plus rotational kinetic energy, J */
    double max_rate;    /* max over grains of |v| / radius, 1/s: the pile is at rest below REST_RATE */
    double penetration; /* max over contacts of the overlap (-gap, at least 0) over the smallest radius */
} pile_state;

/* The state of the pile after a step: w's velocities, cs's gaps (the step's contacts). */
pile_state measure_pile(const world *w, const contacts *cs);

/* The slope of the heap's free surface, degrees: the grains' tops binned by distance from the
 * heap's vertical axis (bins one largest diameter wide), the highest top of each bin taken at
 * its grain's distance from the axis, and a least squares line through the bins between 15 % and
 * 85 % of the heap's extent (the apex and the toe's last grains left out). The heap ends at the
 * last bin whose top stands higher than two diameters. NaN when fewer than three bins qualify
 * (no heap); 0 or near it for a flat layer. */
double angle_of_repose(const world *w);

#endif
