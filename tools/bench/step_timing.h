/* Timing of the step benchmarks (persistent_steps, fem_steps): the clock, and the median of
 * a step's times over the runs. */
#ifndef FRIX_STEP_TIMING_H
#define FRIX_STEP_TIMING_H

#include <stdlib.h>
#include <time.h>

static inline double now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static inline int cmp_double(const void *a, const void *b) {
    const double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* The median of step k's times, times[run * steps + k] for run < runs (scratch: runs doubles). */
static inline double step_median(const double *times, int runs, int steps, int k, double *scratch) {
    for (int run = 0; run < runs; ++run) scratch[run] = times[(size_t)run * (size_t)steps + (size_t)k];
    qsort(scratch, (size_t)runs, sizeof *scratch, cmp_double);
    return runs % 2 ? scratch[runs / 2] : 0.5 * (scratch[runs / 2 - 1] + scratch[runs / 2]);
}

#endif
