// Unique (key, value) pairs bucketed by key, as CSR: key k's values, increasing and each once,
// are values[ptr[k] .. ptr[k+1]). For structures found by walking a matrix's entries in its own
// storage (the contacts' bodies of H, the blocks of W's rows): a counting sort into one flat
// array, then each bucket sorted and made unique in place; no vector per key.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "src/memory.hpp"

namespace frix {

// each(emit) calls emit(key, value) for every pair (keys in [0, nkeys)), the same pairs each
// time it is called (twice: to count, then to fill). A pair equal to the one emitted just
// before it is counted once.
template <class Each>
void unique_pairs_by_key(int64_t nkeys, Each &&each, std::vector<int64_t> &ptr, std::vector<int64_t> &values) {
    ptr.assign((size_t)nkeys + 1, 0);
    int64_t last_key = -1, last_value = -1;
    each([&](int64_t key, int64_t value) {
        if (key == last_key && value == last_value) return;
        last_key = key, last_value = value;
        ++ptr[(size_t)key + 1];
    });
    for (int64_t k = 0; k < nkeys; ++k) ptr[(size_t)k + 1] += ptr[(size_t)k];
    assign_advised(values, (size_t)ptr[(size_t)nkeys]);
    std::vector<int64_t> fill(ptr.begin(), ptr.end() - 1);
    last_key = last_value = -1;
    each([&](int64_t key, int64_t value) {
        if (key == last_key && value == last_value) return;
        last_key = key, last_value = value;
        values[(size_t)fill[(size_t)key]++] = value;
    });
    int64_t kept = 0, begin = 0;
    for (int64_t k = 0; k < nkeys; ++k) {
        const int64_t end = ptr[(size_t)k + 1];
        std::sort(values.begin() + begin, values.begin() + end);
        const auto last = std::unique(values.begin() + begin, values.begin() + end);
        kept = std::copy(values.begin() + begin, last, values.begin() + kept) - values.begin();
        ptr[(size_t)k + 1] = kept;
        begin = end;
    }
    // Only what is kept, in storage advised as the first (shrink_to_fit's would not be).
    if ((size_t)kept < values.size()) {
        std::vector<int64_t> tight;
        copy_advised(tight, values.data(), (size_t)kept);
        values.swap(tight);
    }
}

}  // namespace frix
