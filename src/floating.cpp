// Singular M: the free-motion test and the shifted M (floating.hpp).
#include "floating.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "error_state.hpp"
#include "random.hpp"

namespace frix {

namespace {

// D_ii, the diagonal entry of M the measures weigh dof i by (frix_problem::dof_weight).
double diagonal_of(const frix_problem &p, int64_t i) {
    const double w = (int64_t)p.dof_weight.size() == p.n ? p.dof_weight[(size_t)i] : 1.0;
    return 1.0 / (w * w);
}

}  // namespace

double free_motion_quotient(const frix_problem &p, const MassSolver &ms) {
    const int64_t n = p.n;
    if (n == 0) return INFINITY;
    std::vector<double> b(n), x(n), mx(n);
    uint64_t seed = 0x5eed;
    for (int64_t i = 0; i < n; ++i) b[i] = (next_random(seed) & 1 ? 1.0 : -1.0) * std::sqrt(diagonal_of(p, i));
    if (ms.solve(b.data(), x.data()) != FRIX_OK) {
        clear_error();
        return NAN;
    }
    // x rescaled first: its entries may be near overflow where M is singular.
    double big = 0.0;
    for (double xi : x) big = std::max(big, std::fabs(xi));
    if (!(big > 0.0) || !std::isfinite(big)) return big > 0.0 ? 0.0 : NAN;
    for (double &xi : x) xi /= big;
    matrix_gemv(*p.M, 1.0, x.data(), 0.0, mx.data());
    double xmx = 0.0, xdx = 0.0;
    for (int64_t i = 0; i < n; ++i) {
        xmx += x[i] * mx[i];
        xdx += diagonal_of(p, i) * x[i] * x[i];
    }
    return xmx / xdx;
}

std::vector<double> mass_shift(const frix_problem &p, double eps) {
    std::vector<double> shift((size_t)p.n);
    for (int64_t i = 0; i < p.n; ++i) shift[(size_t)i] = eps * diagonal_of(p, i);
    return shift;
}

std::unique_ptr<frix_matrix> shifted_mass(const frix_problem &p, double eps) {
    auto out = std::make_unique<frix_matrix>(*p.M);
    frix_matrix &A = *out;
    const int64_t n = p.n;
    if (A.block) {
        // The diagonal blocks; a block row without one (massless, uncoupled dofs) gets no
        // shift, and such an M stays singular: its solve fails as it did before.
        for (int64_t k = 0; k < A.block_rows; ++k) {
            const int64_t b = A.diag_index[(size_t)k];
            if (b < 0) continue;
            for (int c = 0; c < 3; ++c) A.block_val[(size_t)(9 * b + 4 * c)] += eps * diagonal_of(p, 3 * k + c);
        }
        return out;
    }
    // CSC: rebuilt with a diagonal entry in every column.
    std::vector<int64_t> colptr(1, 0), rowind;
    std::vector<double> val;
    rowind.reserve(A.row_ind.size() + (size_t)n);
    val.reserve(A.val.size() + (size_t)n);
    for (int64_t j = 0; j < n; ++j) {
        const double shift = eps * diagonal_of(p, j);
        bool placed = false;
        for (int64_t e = A.col_ptr[(size_t)j]; e < A.col_ptr[(size_t)j + 1]; ++e) {
            const int64_t i = A.row_ind[(size_t)e];
            if (!placed && i > j) {
                rowind.push_back(j);
                val.push_back(shift);
                placed = true;
            }
            rowind.push_back(i);
            val.push_back(i == j ? A.val[(size_t)e] + shift : A.val[(size_t)e]);
            placed = placed || i == j;
        }
        if (!placed) {
            rowind.push_back(j);
            val.push_back(shift);
        }
        colptr.push_back((int64_t)rowind.size());
    }
    A.col_ptr = std::move(colptr);
    A.row_ind = std::move(rowind);
    A.val = std::move(val);
    return out;
}

}  // namespace frix
