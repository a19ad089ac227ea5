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
    int64_t islands = 0;
    int64_t largest_island = 0;
    // Where there are several islands, numbered in the order of their first contact: each
    // contact's island, and each island's size (empty for one island). Lists of contacts are
    // made only for the units that need them (solve_units).
    std::vector<int64_t> island_of;
    std::vector<int64_t> island_size;
};

// The units auto solves separately: each island of at least min_size contacts, largest
// first (ties in island order), then the smaller ones merged into one unit; contacts in
// increasing order. A problem that is one unit gets the one list 0 .. nc-1.
std::vector<std::vector<int64_t>> solve_units(const Analysis &a, int64_t min_size);

// Local problems only (W block-CSR). O(nc + blocks).
Analysis analyse_local(const frix_problem &p);

// The sub-problem of the contacts `island` (increasing order): W's blocks among them, their q
// and mu. Owns its data.
frix_error extract_island(const frix_problem &p, const std::vector<int64_t> &island,
                          std::unique_ptr<frix_problem, void (*)(frix_problem *)> &out);

}  // namespace autosolve
}  // namespace frix
