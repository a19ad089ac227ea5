// Union-find, shared by the islands of auto and the components of M in the reduction's bound.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

namespace frix {

// Union-find with path halving and union by size: islands in O(blocks · α(nc)).
class DisjointSets {
   public:
    // Up to kInline elements live inside the object: auto analyses small problems at every
    // call, where an allocation would cost as much as the analysis.
    explicit DisjointSets(int64_t n) {
        if (n > kInline) heap_.resize(2 * (size_t)n);
        parent_ = n > kInline ? heap_.data() : inline_;
        size_ = parent_ + n;
        for (int64_t i = 0; i < n; ++i) parent_[i] = i, size_[i] = 1;
    }
    DisjointSets(const DisjointSets &) = delete;
    DisjointSets &operator=(const DisjointSets &) = delete;
    // The number of elements in the set of `root` (a root: find(root) == root).
    int64_t size_of_root(int64_t root) const { return size_[(size_t)root]; }
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
    static constexpr int64_t kInline = 64;
    int64_t inline_[2 * kInline];
    std::vector<int64_t> heap_;
    int64_t *parent_, *size_;
};

}  // namespace frix
