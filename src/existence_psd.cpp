// The check behind the existence check's witnesses on local problems: a strictly feasible z
// proves a solution only when W's symmetric part is positive semidefinite (existence.cpp).
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include "error_state.hpp"
#include "existence.hpp"
#include "linalg/linalg.hpp"
#include "matrix.hpp"
#include "reduction.hpp"

namespace frix {

namespace {

// The factorisation is tried when it costs at most this many flops (about a second) and
// bytes; larger ones keep the search's own tests.
constexpr double kPsdCheckMaxFlops = 1e9, kPsdCheckMaxBytes = 256e6;

// Whether the factorisation of W's symmetric part would surely cost more than the limits
// above, told from W's pattern alone before anything is built: column k of L holds at least
// the rows below k of the symmetric part's column k, and those count at least half the
// stored nonzero entries (i, j) of W with min(i, j) = k < max(i, j) (an entry and its mirror
// may both be stored); a factorisation takes at least the squares of its columns' counts.
// (A dense W of thousands of contacts: the terms and the analysis alone took tens of seconds.)
bool surely_too_costly(const frix_matrix &W, int64_t m) {
    std::vector<double> below((size_t)m, 1.0);  // the diagonal, at least
    for_each_entry(W, [&](int64_t i, int64_t j, double v) {
        if (i != j && v != 0.0) below[(size_t)std::min(i, j)] += 0.5;
    });
    double flops = 0.0, entries = 0.0;
    for (const double c : below) flops += c * c, entries += c;
    return flops > kPsdCheckMaxFlops || 8.0 * entries > kPsdCheckMaxBytes;
}

}  // namespace

Psd symmetric_part_psd(const frix_problem &p, double tolerance) {
    const frix_matrix &W = *p.W;
    const int64_t m = 3 * p.nc;
    if (surely_too_costly(W, m)) return Psd::Unknown;
    const std::vector<double> diag = matrix_diagonal(W);
    std::vector<double> d((size_t)m);
    for (int64_t i = 0; i < m; ++i) d[(size_t)i] = diag[(size_t)i] > 0.0 ? 1.0 / std::sqrt(diag[(size_t)i]) : 1.0;
    // D (W + W^T)/2 D as terms, each entry half at (i, j) and half at (j, i) (the triplet
    // builder sums them), then the shift on the diagonal; CHOLMOD reads the upper triangle.
    std::vector<int64_t> rows, cols;
    std::vector<double> values, row_sum((size_t)m, 0.0);
    for_each_entry(W, [&](int64_t i, int64_t j, double v) {
        const double half = 0.5 * v * d[(size_t)i] * d[(size_t)j];
        rows.insert(rows.end(), {i, j});
        cols.insert(cols.end(), {j, i});
        values.insert(values.end(), {half, half});
        // The bound counts a diagonal entry twice, an off-diagonal one once in each row.
        const double entry = i == j ? 2.0 * half : half;
        row_sum[(size_t)i] += std::fabs(entry);
        row_sum[(size_t)j] += std::fabs(entry);
    });
    const double bound = m > 0 ? *std::max_element(row_sum.begin(), row_sum.end()) : 0.0;
    if (!std::isfinite(bound)) return Psd::Unknown;
    const double shift = tolerance * std::max(bound, DBL_MIN);
    for (int64_t i = 0; i < m; ++i) {
        rows.push_back(i);
        cols.push_back(i);
        values.push_back(shift);
    }
    frix_matrix *raw = nullptr;
    const frix_error built = frix_matrix_from_triplets(m, m, (int64_t)values.size(), rows.data(), cols.data(),
                                                       values.data(), &raw);
    const std::unique_ptr<frix_matrix> S_blocks(raw);
    Csc S;
    if (built != FRIX_OK || to_csc(*S_blocks, S) != FRIX_OK) {
        clear_error();
        return Psd::Unknown;
    }
    linalg::SparseCholesky cholesky;
    cholesky.set_budget([](const linalg::FactorPrice &price) {
        if (!(price.bytes <= kPsdCheckMaxBytes)) return FRIX_STATUS_MEMORY_LIMIT;
        return price.flops <= kPsdCheckMaxFlops ? FRIX_STATUS_NOT_RUN : FRIX_STATUS_TIME_LIMIT;
    });
    const frix_error e = cholesky.factor(S.view());
    clear_error();
    if (e == FRIX_OK) return Psd::Yes;
    return e == FRIX_ERR_NUMERICAL && !cholesky.refused() ? Psd::No : Psd::Unknown;
}

}  // namespace frix
