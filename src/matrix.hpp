// Internal layout of frix_matrix and the inner kernels the solvers use directly.
#pragma once

#include <frix/frix_matrix.h>

#include <cstdint>
#include <vector>

struct frix_matrix {
    int64_t rows = 0;
    int64_t cols = 0;
    bool block = false;  // true: 3x3 block-CSR below; false: general CSC below

    // ---- 3x3 block-CSR (rows and cols multiples of 3)
    int64_t block_rows = 0;              // rows / 3
    int64_t block_cols = 0;              // cols / 3
    std::vector<int64_t> row_ptr;        // block_rows + 1
    std::vector<int64_t> block_col;      // per block: its block column, sorted within a row
    std::vector<double> block_val;       // 9 per block, column-major
    std::vector<int64_t> diag_index;     // per block row: index of its diagonal block, -1 if none

    // ---- general CSC
    std::vector<int64_t> col_ptr;        // cols + 1
    std::vector<int64_t> row_ind;        // sorted within each column
    std::vector<double> val;

    int64_t nblocks() const { return block ? (int64_t)block_col.size() : 0; }
};

namespace frix {

// y(3) += B(3x3 column-major) * x(3)
inline void block_gemv_add(const double *B, const double *x, double *y) {
    y[0] += B[0] * x[0] + B[3] * x[1] + B[6] * x[2];
    y[1] += B[1] * x[0] + B[4] * x[1] + B[7] * x[2];
    y[2] += B[2] * x[0] + B[5] * x[1] + B[8] * x[2];
}

// y_k = sum over the blocks of block row k of A_kj x_j (y_k overwritten). Block matrix only.
inline void block_row_product(const frix_matrix &A, int64_t k, const double *x, double *y) {
    y[0] = y[1] = y[2] = 0.0;
    for (int64_t b = A.row_ptr[k]; b < A.row_ptr[k + 1]; ++b)
        block_gemv_add(&A.block_val[9 * b], &x[3 * A.block_col[b]], y);
}

// f(row, col, value) for every stored entry of A, in either storage (a stored 3x3 block gives
// its 9 entries, zeros included).
template <class F>
void for_each_entry(const frix_matrix &A, F &&f) {
    if (A.block) {
        for (int64_t k = 0; k < A.block_rows; ++k)
            for (int64_t b = A.row_ptr[k]; b < A.row_ptr[k + 1]; ++b)
                for (int c = 0; c < 3; ++c)
                    for (int r = 0; r < 3; ++r)
                        f(3 * k + r, 3 * A.block_col[b] + c, A.block_val[9 * b + r + 3 * c]);
        return;
    }
    for (int64_t c = 0; c < A.cols; ++c)
        for (int64_t e = A.col_ptr[c]; e < A.col_ptr[c + 1]; ++e) f(A.row_ind[e], c, A.val[e]);
}

// y = alpha*A*x + beta*y for either storage; no argument checks (internal callers).
void matrix_gemv(const frix_matrix &A, double alpha, const double *x, double beta, double *y);
void matrix_gemv_transposed(const frix_matrix &A, double alpha, const double *x, double beta,
                            double *y);

}  // namespace frix
