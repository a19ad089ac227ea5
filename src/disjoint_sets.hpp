// Union-find, shared by the islands of auto and the components of M in the reduction's bound.
#pragma once

#include <cstdint>
#include <numeric>
#include <utility>
#include <vector>

namespace frix {

// Union-find with path halving and union by size: islands in O(blocks · α(nc)).
class DisjointSets {
   public:
    explicit DisjointSets(int64_t n) : parent_((size_t)n), size_((size_t)n, 1) {
        std::iota(parent_.begin(), parent_.end(), 0);
    }
    int64_t find(int64_t a) {
        while (parent_[(size_t)a] != a) {
            parent_[(size_t)a] = parent_[(size_t)parent_[(size_t)a]];
            a = parent_[(size_t)a];
        }
        return a;
    }
    void unite(int64_t a, int64_t b) {
        a = find(a), b = find(b);
        if (a == b) return;
        if (size_[(size_t)a] < size_[(size_t)b]) std::swap(a, b);
        parent_[(size_t)b] = a;
        size_[(size_t)a] += size_[(size_t)b];
    }

   private:
    std::vector<int64_t> parent_, size_;
};

}  // namespace frix
