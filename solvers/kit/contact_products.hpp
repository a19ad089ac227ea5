// The product forms' per-contact data (gnsgs: three entries a contact, rolling-nsgs: five or six):
// for each contact, the dofs of the bodies its columns of H touch (each body whole, in
// increasing order), and on them H_a and M^-1 H_a, so that a sweep reads u_a = H_a^T v + w_a
// and adds M^-1 H_a dr_a to v without W. One builder for both forms: the layout is the sweeps'.
#pragma once

#include <cstdint>
#include <vector>

#include "solvers/kit/rigid_bodies.hpp"
#include "src/matrix.hpp"

namespace frix {

// H (n x width nc) is read in its own storage, never copied: its exact zeros couple nothing.

// The bodies each contact's `width` columns of H touch, in increasing order: contact a's are
// bodies[ptr[a] .. ptr[a+1]) (flat: a few entries a contact, not a vector each).
struct ContactBodies {
    std::vector<int64_t> ptr, bodies;
    void find(const frix_matrix &H, const RigidBodies &rigid, int width, int64_t nc);
};

// Contact order[k] at position k (the sweeps' order): its dofs dofs[dof_ptr[k] .. dof_ptr[k+1]),
// H_a on them (width values a dof, one per column), and M^-1 H_a: stored from gd[width *
// g_ptr[k]] on, or, where g_ptr[k] is -1 (every body of the contact is one dof, so M is
// diagonal there), each dof's inverse mass minv beside H_a (half the data a sweep reads).
struct ContactProducts {
    int width = 0;
    std::vector<int64_t> dof_ptr, dofs, g_ptr;
    std::vector<double> hd, gd, minv;
    // order: nc positions' contacts (nullptr: contact k at position k); one_dof_minv: keep
    // one-dof contacts as minv (else M^-1 H_a is stored for every contact).
    void build(const frix_matrix &H, const RigidBodies &rigid, const ContactBodies &cb, int width, int64_t nc,
               const int64_t *order, bool one_dof_minv);
    int64_t dof_count(int64_t k) const { return dof_ptr[(size_t)k + 1] - dof_ptr[(size_t)k]; }
    // Row t (the t-th dof) of position k's M^-1 H_a, into g (width values).
    void g_row(int64_t k, int64_t t, double *g) const;
    // W_aa = H_a^T M^-1 H_a of position k, width^2 values column-major, added to W.
    void add_diagonal_block(int64_t k, double *W) const;
    // Renumbers the n dofs in the order a sweep over positions order[0 .. count) (nullptr: 0 ..
    // count) first reaches them, a body's together, the dofs no contact touches last: a sweep
    // then reads and writes v front to back, and a domain a compact part of it. dofs is
    // rewritten; slot_of_dof[d] is dof d's new number.
    void renumber_dofs(int64_t n, const int64_t *order, int64_t count, std::vector<int64_t> &slot_of_dof);
};

}  // namespace frix
