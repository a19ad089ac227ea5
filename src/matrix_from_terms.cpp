// BlockMatrixFromTerms: a symmetric block-CSR matrix summed from dense terms (see matrix.hpp).
#include <algorithm>
#include <cmath>

#include "error_state.hpp"
#include "matrix.hpp"
#include "memory.hpp"

namespace frix {

BlockMatrixFromTerms::BlockMatrixFromTerms(int64_t n, const char *what) : A_(std::make_unique<frix_matrix>()), what_(what) {
    A_->rows = A_->cols = n;
    A_->block = true;
    A_->block_rows = A_->block_cols = n / 3;
    A_->row_ptr.assign((size_t)(n / 3) + 1, 0);
}

std::vector<std::vector<int64_t>> contact_sets(const std::vector<std::vector<int64_t>> &groups) {
    std::vector<std::vector<int64_t>> contacts(groups.size());
    for (size_t g = 0; g < groups.size(); ++g)
        for (int64_t j : groups[g])
            if (contacts[g].empty() || contacts[g].back() != j / 3) contacts[g].push_back(j / 3);
    std::sort(contacts.begin(), contacts.end());
    contacts.erase(std::unique(contacts.begin(), contacts.end()), contacts.end());
    return contacts;
}

frix_error BlockMatrixFromTerms::pattern(const std::vector<std::vector<int64_t>> &groups) {
    frix_matrix &A = *A_;
    const int64_t nb = A.block_rows;
    for (const auto &g : groups)
        for (int64_t j : g)
            if (j < 0 || j >= A.cols)
                return fail(FRIX_ERR_INTERNAL, "%s: column %lld outside the %lld", what_, (long long)j, (long long)A.cols);
    // Every contact's row takes all the contacts of its sets.
    const std::vector<std::vector<int64_t>> contacts = contact_sets(groups);
    std::vector<int64_t> groups_of((size_t)nb, 0);  // how many groups each contact is in
    for (const auto &c : contacts)
        for (int64_t b : c) {
            A.row_ptr[(size_t)b + 1] += (int64_t)c.size();
            ++groups_of[(size_t)b];
        }
    for (int64_t b = 0; b < nb; ++b) A.row_ptr[(size_t)b + 1] += A.row_ptr[(size_t)b];
    assign_advised(A.block_col, (size_t)A.row_ptr[(size_t)nb]);
    std::vector<int64_t> next(A.row_ptr.begin(), A.row_ptr.end() - 1);
    for (const auto &c : contacts)
        for (int64_t b : c) next[(size_t)b] = std::copy(c.begin(), c.end(), A.block_col.begin() + next[(size_t)b]) - A.block_col.begin();
    // A contact in several groups (a contact between two bodies) has their union; one in a
    // single group has that group's contacts, in order already.
    int64_t kept = 0;
    for (int64_t b = 0; b < nb; ++b) {
        const auto first = A.block_col.begin() + A.row_ptr[(size_t)b], last = A.block_col.begin() + A.row_ptr[(size_t)b + 1];
        if (groups_of[(size_t)b] > 1) std::sort(first, last);
        const auto end = std::unique(first, last);
        A.row_ptr[(size_t)b] = kept;
        kept = std::copy(first, end, A.block_col.begin() + kept) - A.block_col.begin();
    }
    A.row_ptr[(size_t)nb] = kept;
    A.block_col.resize((size_t)kept);
    A.block_col.shrink_to_fit();
    assign_advised(A.block_val, 9 * (size_t)kept, 0.0);
    return FRIX_OK;
}

frix_error BlockMatrixFromTerms::add(int64_t count, const int64_t *cols, int64_t width, const double *T, int64_t ld) {
    frix_matrix &A = *A_;
    // Entry (cols[a], cols[b]), a >= b, goes to row cols[b] / 3 (the upper blocks): along a
    // tile column the rows a increase, and so do their blocks within that row.
    for (int64_t b = 0; b < width; ++b) {
        const int64_t j = cols[b], row = j / 3;
        int64_t p = A.row_ptr[(size_t)row];
        const int64_t end = A.row_ptr[(size_t)row + 1];
        for (int64_t a = b; a < count; ++a) {
            const int64_t i = cols[a], block = i / 3;
            while (p < end && A.block_col[(size_t)p] < block) ++p;
            if (p == end || A.block_col[(size_t)p] != block)
                return fail(FRIX_ERR_INTERNAL, "%s: entry (%lld, %lld) outside its pattern", what_, (long long)j,
                            (long long)i);
            A.block_val[9 * (size_t)p + (size_t)(j % 3 + 3 * (i % 3))] += T[a + ld * b];
        }
    }
    return FRIX_OK;
}

frix_error BlockMatrixFromTerms::finish(std::unique_ptr<frix_matrix> &out) {
    frix_matrix &A = *A_;
    // Block (c, r) of row c, for the rows r in increasing order: each row's cursor only
    // moves forward.
    std::vector<int64_t> cursor(A.row_ptr.begin(), A.row_ptr.end() - 1);
    for (int64_t r = 0; r < A.block_rows; ++r)
        for (int64_t p = A.row_ptr[(size_t)r]; p < A.row_ptr[(size_t)r + 1]; ++p) {
            const int64_t c = A.block_col[(size_t)p];
            double *upper = &A.block_val[9 * (size_t)p];
            for (int e = 0; e < 9; ++e)
                if (!std::isfinite(upper[e]))
                    return fail(FRIX_ERR_NOT_FINITE, "%s: entry (%lld, %lld) is not finite", what_,
                                (long long)(3 * r + e % 3), (long long)(3 * c + e / 3));
            if (c < r) continue;
            if (c == r) {
                upper[1] = upper[3];
                upper[2] = upper[6];
                upper[5] = upper[7];
                continue;
            }
            // Block (c, r) is block (r, c) transposed.
            int64_t &q = cursor[(size_t)c];
            const int64_t end = A.row_ptr[(size_t)c + 1];
            while (q < end && A.block_col[(size_t)q] < r) ++q;
            if (q == end || A.block_col[(size_t)q] != r)
                return fail(FRIX_ERR_INTERNAL, "%s: block (%lld, %lld) without its mirror", what_, (long long)r, (long long)c);
            double *lower = &A.block_val[9 * (size_t)q];
            for (int i = 0; i < 3; ++i)
                for (int k = 0; k < 3; ++k) lower[i + 3 * k] = upper[k + 3 * i];
        }
    index_diagonal_blocks(A);
    A.symmetric = true;
    out = std::move(A_);
    return FRIX_OK;
}

}  // namespace frix
