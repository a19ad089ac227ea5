#include "solvers/kit/rigid_bodies.hpp"

#include <algorithm>
#include <cmath>

#include "src/disjoint_sets.hpp"
#include "src/error_state.hpp"
#include "src/memory.hpp"

namespace frix {

frix_error RigidBodies::setup(const Csc &M, const char *who) {
    const int64_t n = M.rows;
    DisjointSets sets(n);
    for (int64_t c = 0; c < n; ++c)
        for (int64_t k = M.colptr[c]; k < M.colptr[c + 1]; ++k)
            if (M.val[k] != 0.0) sets.unite(M.rowind[k], c);  // a stored zero couples nothing
    assign_advised(body_of, (size_t)n, (int64_t)-1);
    std::vector<int64_t> body_of_root;
    assign_advised(body_of_root, (size_t)n, (int64_t)-1);
    int64_t bodies = 0;
    for (int64_t i = 0; i < n; ++i) {
        const int64_t root = sets.find(i);
        if (body_of_root[root] < 0) {
            if (sets.size_of_root(root) > kMaxRigidBodyDofs)
                return fail(FRIX_ERR_UNSUPPORTED,
                            "%s: M couples %lld dofs in one block (more than %lld: a deformable body); "
                            "gadmm or auto solve this problem",
                            who, (long long)sets.size_of_root(root), (long long)kMaxRigidBodyDofs);
            body_of_root[root] = bodies++;
        }
        body_of[i] = body_of_root[root];
    }
    // The dofs of each body in increasing order, and each dof's place in its body.
    body_ptr.assign((size_t)bodies + 1, 0);
    for (int64_t i = 0; i < n; ++i) ++body_ptr[body_of[i] + 1];
    for (int64_t b = 0; b < bodies; ++b) body_ptr[b + 1] += body_ptr[b];
    assign_advised(body_dofs, (size_t)n);
    assign_advised(place, (size_t)n);
    std::vector<int64_t> next(body_ptr.begin(), body_ptr.end() - 1);
    for (int64_t i = 0; i < n; ++i) {
        const int64_t k = next[body_of[i]]++;
        body_dofs[k] = i;
        place[i] = k - body_ptr[body_of[i]];
    }
    // Each body's block of M inverted by Gauss-Jordan with partial pivoting (M need not be
    // symmetric).
    inverse_ptr.assign((size_t)bodies + 1, 0);
    for (int64_t b = 0; b < bodies; ++b) inverse_ptr[b + 1] = inverse_ptr[b] + size(b) * size(b);
    assign_advised(inverse, (size_t)inverse_ptr[bodies], 0.0);
    std::vector<double> a;
    for (int64_t b = 0; b < bodies; ++b) {
        const int64_t k = size(b);
        a.assign((size_t)(k * k), 0.0);  // column-major
        double *inv = &inverse[inverse_ptr[b]];
        double scale = 0.0;
        for (int64_t j = 0; j < k; ++j) {
            const int64_t col = body_dofs[body_ptr[b] + j];
            for (int64_t e = M.colptr[col]; e < M.colptr[col + 1]; ++e) {
                a[place[M.rowind[e]] + k * j] += M.val[e];
                scale = std::max(scale, std::fabs(M.val[e]));
            }
            inv[j + k * j] = 1.0;
        }
        if (!linalg::invert_small(k, a.data(), inv, scale))
            return fail(FRIX_ERR_NUMERICAL, "%s: M is singular (its block of dofs %lld..%lld)", who,
                        (long long)body_dofs[body_ptr[b]], (long long)body_dofs[body_ptr[b + 1] - 1]);
    }
    return FRIX_OK;
}

void RigidBodies::apply_inverse(const double *x, double *y) const {
    for (int64_t b = 0; b < count(); ++b) {
        const int64_t k = size(b), *dofs = &body_dofs[body_ptr[b]];
        const double *inv = &inverse[inverse_ptr[b]];
        for (int64_t i = 0; i < k; ++i) {
            double s = 0.0;
            for (int64_t j = 0; j < k; ++j) s += inv[i + k * j] * x[dofs[j]];
            y[dofs[i]] = s;
        }
    }
}

}  // namespace frix
