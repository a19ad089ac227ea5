// The rigid bodies of a global problem's M: its connected components (dofs coupled by a
// non-zero entry), each small enough to invert densely. The product forms of the NSGS sweeps
// (gnsgs, rolling-nsgs) keep v = M^-1 (H r + f) with these inverse blocks, never forming W.
#pragma once

#include <cstdint>
#include <vector>

#include "src/reduction.hpp"

namespace frix {

// A body (a connected component of M's graph) of more dofs than this is deformable; its dense
// inverse block would cost its dofs squared.
constexpr int64_t kMaxRigidBodyDofs = 64;

struct RigidBodies {
    std::vector<int64_t> body_of;      // per dof: its body
    std::vector<int64_t> body_ptr;     // body b's dofs are body_dofs[body_ptr[b] .. body_ptr[b+1])
    std::vector<int64_t> body_dofs;    // increasing within a body
    std::vector<int64_t> place;        // per dof: its place within its body
    std::vector<int64_t> inverse_ptr;  // body b's inverse block (column-major) at inverse[inverse_ptr[b]]
    std::vector<double> inverse;

    // Finds the bodies of M (CSC, n x n) and inverts each block; FRIX_ERR_UNSUPPORTED for a
    // body of more than kMaxRigidBodyDofs dofs, FRIX_ERR_NUMERICAL for a singular block.
    // `who` names the solver in the messages.
    frix_error setup(const Csc &M, const char *who);
    int64_t count() const { return (int64_t)body_ptr.size() - 1; }
    int64_t size(int64_t b) const { return body_ptr[b + 1] - body_ptr[b]; }
    // y = M^-1 x, body by body.
    void apply_inverse(const double *x, double *y) const;
};

}  // namespace frix
