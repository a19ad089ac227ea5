// What the auto solver (900) learns about a problem before it solves it: sizes, the spread of
// the diagonal blocks and of mu, and the islands, the connected components of the contact
// graph (contacts a and b are linked when W_ab != 0), which it solves separately.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "problem.hpp"

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

// Global problems: what the reduction W = H^T M^-1 H would cost, from the structure of M and H
// alone, in O(n + nnz(M) + nnz(H) log nnz(H)). M^-1 couples any two dofs of a connected
// component of M's graph (a rigid body: its 6 dofs; a deformable body: all of its nodes), so
// W_ij can be non-zero only when columns i and j of H touch a common component: the bound is
// the sum over components of (columns of H touching it)^2, at most (3nc)^2, exact but for
// cancellations. A deformable body makes W dense among its contacts.
struct ReductionSize {
    double w_entries = 0.0;      // the bound on W's non-zero entries
    double w_blocks = 0.0;       // the bound on its non-zero 3x3 blocks (contacts, squared)
    double input_entries = 0.0;  // non-zero entries of M and H
};
ReductionSize reduction_size(const frix_problem &p);

// The sub-problem of the contacts `island` (increasing order): W's blocks among them, their q
// and mu. Owns its data.
frix_error extract_island(const frix_problem &p, const std::vector<int64_t> &island,
                          std::unique_ptr<frix_problem, void (*)(frix_problem *)> &out);

}  // namespace autosolve
}  // namespace frix
