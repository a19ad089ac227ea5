/* The tests' deterministic pseudo-random stream: a 64-bit linear congruential generator (Knuth's
 * MMIX constants), the same draws on every machine and C library, so that a failure reproduces
 * (rand() would not). Header only: each test keeps its own state. */
#ifndef FRIX_TEST_LCG_H
#define FRIX_TEST_LCG_H

#include <stdint.h>

/* The next draw of the stream *state, uniform in [0, 1) (the state's top 53 bits). */
static inline double lcg_uniform(uint64_t *state) {
    *state = *state * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(*state >> 11) / 9007199254740992.0;
}

#endif
