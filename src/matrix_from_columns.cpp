// BlockMatrixFromColumns: a block-CSR matrix assembled from its columns (see matrix.hpp).
#include <algorithm>
#include <cmath>
#include <cstring>

#include "error_state.hpp"
#include "matrix.hpp"

namespace frix {

BlockMatrixFromColumns::BlockMatrixFromColumns(int64_t n, const char *what, double expected_blocks)
    : nb_(n / 3), what_(what), slot_((size_t)(n / 3), -1) {
    if (expected_blocks > 0.0) {
        block_row_.reserve((size_t)expected_blocks);
        values_.reserve(9 * (size_t)expected_blocks);
    }
}

frix_error BlockMatrixFromColumns::add_column(int64_t count, const int64_t *rows, const double *values) {
    if (column_ >= 3 * nb_) return fail(FRIX_ERR_INTERNAL, "%s: more than %lld columns", what_, (long long)(3 * nb_));
    const int col = (int)(column_ % 3);
    for (int64_t e = 0; e < count; ++e) {
        if (rows[e] < 0 || rows[e] >= 3 * nb_)
            return fail(FRIX_ERR_INTERNAL, "%s: row %lld outside the %lld rows", what_, (long long)rows[e],
                        (long long)(3 * nb_));
        if (!std::isfinite(values[e]))
            return fail(FRIX_ERR_NOT_FINITE, "%s: entry (%lld, %lld) is not finite", what_, (long long)rows[e],
                        (long long)column_);
        pending_.push_back({rows[e], col, values[e]});
    }
    if (++column_ % 3 == 0) flush_block_column();
    return FRIX_OK;
}

void BlockMatrixFromColumns::flush_block_column() {
    // The block rows the three columns touch, in increasing order.
    const size_t first = block_row_.size();
    for (const Entry &e : pending_) {
        const int64_t br = e.row / 3;
        if (slot_[(size_t)br] < 0) {
            slot_[(size_t)br] = 0;
            block_row_.push_back(br);
        }
    }
    std::sort(block_row_.begin() + (std::ptrdiff_t)first, block_row_.end());
    for (size_t k = first; k < block_row_.size(); ++k) slot_[(size_t)block_row_[k]] = (int64_t)k;
    col_ptr_.push_back((int64_t)block_row_.size());
    // Their values, zeros where no entry falls.
    values_.resize(9 * block_row_.size(), 0.0);
    for (const Entry &e : pending_)
        values_[9 * (size_t)slot_[(size_t)(e.row / 3)] + (size_t)(3 * e.col + e.row % 3)] = e.value;
    for (size_t k = first; k < block_row_.size(); ++k) slot_[(size_t)block_row_[k]] = -1;
    pending_.clear();
}

// Whether block (b, a) of column a is block (a, b) of column b transposed, bit for bit, for
// every block: then the block columns, each block transposed, are the block rows.
bool BlockMatrixFromColumns::symmetric() const {
    int64_t matched = 0;  // blocks with their partner: every block, when symmetric
    for (int64_t a = 0; a < nb_; ++a)
        for (int64_t s = col_ptr_[(size_t)a]; s < col_ptr_[(size_t)a + 1]; ++s) {
            const int64_t b = block_row_[(size_t)s];
            if (b < a) continue;  // (a pair is checked once, from its lower block)
            const auto first = block_row_.begin() + col_ptr_[(size_t)b], last = block_row_.begin() + col_ptr_[(size_t)b + 1];
            const auto it = std::lower_bound(first, last, a);
            if (it == last || *it != a) return false;
            const double *lower = &values_[9 * (size_t)s];  // W_ba
            const double *upper = &values_[9 * (size_t)(it - block_row_.begin())];  // W_ab
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 3; ++c)
                    if (std::memcmp(&lower[3 * c + r], &upper[3 * r + c], sizeof(double)) != 0) return false;
            matched += b == a ? 1 : 2;
        }
    return matched == col_ptr_.back();  // (an upper block without its lower one: not symmetric)
}

frix_error BlockMatrixFromColumns::finish(std::unique_ptr<frix_matrix> &out) {
    if (column_ != 3 * nb_)
        return fail(FRIX_ERR_INTERNAL, "%s: %lld columns of %lld", what_, (long long)column_, (long long)(3 * nb_));
    auto A = std::make_unique<frix_matrix>();
    A->rows = A->cols = 3 * nb_;
    A->block = true;
    A->block_rows = A->block_cols = nb_;
    const int64_t nblocks = col_ptr_.back();
    in_place_ = symmetric();
    if (in_place_) {
        // Row a's blocks are column a's, each transposed: no second copy of the values.
        for (int64_t s = 0; s < nblocks; ++s) {
            double *v = &values_[9 * (size_t)s];
            std::swap(v[1], v[3]);
            std::swap(v[2], v[6]);
            std::swap(v[5], v[7]);
        }
        A->row_ptr = std::move(col_ptr_);
        A->block_col = std::move(block_row_);
        A->block_val = std::move(values_);
    } else {
        // Blocks by rows: a counting sort on the block row; going through the columns in
        // order leaves every row's blocks sorted by column.
        A->row_ptr.assign((size_t)nb_ + 1, 0);
        for (int64_t br : block_row_) ++A->row_ptr[(size_t)br + 1];
        for (int64_t r = 0; r < nb_; ++r) A->row_ptr[(size_t)r + 1] += A->row_ptr[(size_t)r];
        std::vector<int64_t> next(A->row_ptr.begin(), A->row_ptr.end() - 1);
        A->block_col.resize((size_t)nblocks);
        A->block_val.resize(9 * (size_t)nblocks);
        for (int64_t bc = 0; bc < nb_; ++bc)
            for (int64_t b = col_ptr_[(size_t)bc]; b < col_ptr_[(size_t)bc + 1]; ++b) {
                const int64_t to = next[(size_t)block_row_[(size_t)b]]++;
                A->block_col[(size_t)to] = bc;
                std::copy(&values_[9 * (size_t)b], &values_[9 * (size_t)b] + 9, &A->block_val[9 * (size_t)to]);
            }
        std::vector<double>().swap(values_);
        std::vector<int64_t>().swap(block_row_);
    }
    index_diagonal_blocks(*A);
    A->symmetric = in_place_;
    out = std::move(A);
    return FRIX_OK;
}

}  // namespace frix
