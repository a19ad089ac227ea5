// What the auto solver (900) learns about a problem before it solves it: sizes, the spread of
// the diagonal blocks and of mu, and the islands, the connected components of the contact
// graph (contacts a and b are linked when W_ab != 0), which it solves separately.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "src/problem.hpp"

namespace frix {
namespace autosolve {

struct Analysis {
    int64_t contacts = 0;
    int64_t contact_dofs = 0;
    double diag_min = 0.0;      // min and max over contacts of |W_aa| (Frobenius)
    double diag_max = 0.0;
    double mu_min = 0.0, mu_max = 0.0;
    int64_t blocks = 0;         // stored 3x3 blocks of W
    // Islands, largest first; each lists its contacts in increasing order.
    std::vector<std::vector<int64_t>> islands;
};

// The units auto solves separately: each island of at least min_size contacts, largest
// first, then the smaller ones merged into one unit (contacts in increasing order). Takes
// the islands over (moved, not copied).
std::vector<std::vector<int64_t>> group_small_islands(std::vector<std::vector<int64_t>> islands, int64_t min_size);

// Local problems only (W block-CSR). O(nc + blocks).
Analysis analyse_local(const frix_problem &p);

// The sub-problem of the contacts `island` (increasing order): W's blocks among them, their q
// and mu. Owns its data.
frix_error extract_island(const frix_problem &p, const std::vector<int64_t> &island,
                          std::unique_ptr<frix_problem, void (*)(frix_problem *)> &out);

}  // namespace autosolve
}  // namespace frix
