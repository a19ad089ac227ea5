// A dense W's block columns in single precision, for the pushes of the velocity sweeps
// (nsgs-v): a sweep over a large dense W is bound by the bytes of W it reads and the
// arithmetic on them, and this copy streams half the bytes in a layout the vectoriser takes
// whole. Only the pushes use it; every measure (the full checks, the driver's) still reads
// the double W.
#pragma once

#include <cstdint>
#include <vector>

#include "src/matrix.hpp"
#include "src/solve_cache.hpp"

namespace frix {
namespace nsgs {

// The bytes of W's stored blocks from which the velocity sweeps push through single-precision
// columns: where a sweep reads tens of megabytes and costs milliseconds, past the last-level
// cache a core of a current server processor sees. Smaller W keep the double pushes and their
// iterates. Fixed, so that a solve's iterates never depend on the machine
// (notes/2026-11-28-single-precision-sweeps.md).
constexpr double kSingleColumnsMinBytes = 32.0 * 1024.0 * 1024.0;

// W_SS of a W that stores every block (SingleColumns::suits), S increasing, into out (its
// storage kept where it suffices): the part of a dense W the sweeps of some contacts read.
void dense_restriction(const frix_matrix &W, const std::vector<int64_t> &S, frix_matrix &out);

class SingleColumns : public CachedState {
   public:
    // Whether the pushes on W go through single-precision columns: W stores every block (a
    // dense column streams contiguously) and its blocks take at least min_bytes.
    static bool suits(const frix_matrix &W, double min_bytes);
    // The bytes the copy of such a W takes.
    static double bytes_for(const frix_matrix &W);
    // Whether the copy is of W's values at these versions (SolveCache::w_values and
    // w_pattern; 0 and 0 without a cache: never kept), cut into as many panels as build()
    // would cut for `panels`.
    bool holds(const frix_matrix &W, uint64_t w_values, uint64_t w_pattern, int64_t panels = 1) const;
    // The copy of W (one that suits()), at these versions, its rows cut into `panels` runs of
    // contacts (at most one per 4 contacts), each stored apart (panel_begin).
    void build(const frix_matrix &W, uint64_t w_values, uint64_t w_pattern, int64_t panels = 1);
    int64_t panels() const { return (int64_t)panel_.size() - 1; }
    // Panel p holds the rows of contacts panel_begin(p) .. panel_begin(p + 1).
    int64_t panel_begin(int64_t p) const { return panel_[(size_t)p].contact; }
    // u += W's block column a times dr, each product and the sum of a row's three in single
    // precision, added to u in double.
    void push(int64_t a, const double *dr, double *u) const;
    // push() on panel p's rows only (u is the whole u): the same values on them, so that
    // threads pushing into their own panels agree with one thread pushing into all of them.
    void push_panel(int64_t p, int64_t a, const double *dr, double *u) const;

   private:
    // Column a's scalar rows of a panel in chunks of kChunk: its three scalar columns' values
    // on the chunk's rows, one after another (rows past the panel's last are zero), so that a
    // column is one contiguous stream and a chunk a few vector operations. A panel's columns
    // lie together: a thread that pushes into one panel streams memory of its own (two
    // threads each reading half of every column read no faster than one).
    static constexpr int64_t kChunk = 4;
    struct Panel {
        int64_t contact = 0;  // its first contact (the last entry: nc)
        int64_t stride = 0;   // floats per block column
        size_t offset = 0;    // where its columns start in values_
    };
    int64_t rows_ = 0;  // 3 nc
    std::vector<Panel> panel_;
    std::vector<float> values_;
    uint64_t w_values_ = 0, w_pattern_ = 0;
};

}  // namespace nsgs
}  // namespace frix
