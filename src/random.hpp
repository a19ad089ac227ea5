// A small, fully specified pseudo-random generator (splitmix64): a seed gives the same numbers
// on every platform and compiler, so solvers that draw (NSGS's shuffled orders, auto's random
// restarts) stay deterministic. The state is the caller's: no global state.
#pragma once

#include <cstdint>

namespace frix {

inline uint64_t next_random(uint64_t &state) {
    uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

// Uniform on [0, 1): the top 53 bits.
inline double next_uniform(uint64_t &state) { return (double)(next_random(state) >> 11) * 0x1.0p-53; }

}  // namespace frix
