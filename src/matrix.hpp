// Internal layout of frix_matrix and the inner kernels the solvers use directly.
#pragma once

#include "linalg/linalg.hpp"

#include <frix/frix_matrix.h>

#include <cstdint>
#include <memory>
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
    // Symmetric to the last bit, as its builder knows (W from the reduction): block row a,
    // each block transposed, is block column a, and a solver may read columns from the rows.
    bool symmetric = false;

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

// y(3) += B^T x(3), B 3x3 column-major.
inline void block_gemv_transposed_add(const double *B, const double *x, double *y) {
    y[0] += B[0] * x[0] + B[1] * x[1] + B[2] * x[2];
    y[1] += B[3] * x[0] + B[4] * x[1] + B[5] * x[2];
    y[2] += B[6] * x[0] + B[7] * x[1] + B[8] * x[2];
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

// Builds a square 3x3 block-CSR matrix from its columns, given one at a time in order, with
// memory for its blocks and little more: W = H^T M^-1 H, dense among the contacts of a
// deformable body, arrives by columns, and a CSC copy of it converted by frix_matrix_from_csc
// costs about 40 bytes an entry at the peak (the 80x80x3 elastic grid: 7.1 GB), the blocks 8.
// The blocks are kept by columns as they arrive. When the matrix is symmetric to the last bit
// (W from CHOLMOD is), its block columns are its block rows transposed: finish() transposes
// each block in place and hands the storage over; otherwise it copies the blocks into rows.
// A block is stored where at least one entry falls (zeros included), as
// frix_matrix_from_csc does: the same blocks with the same bits either way.
class BlockMatrixFromColumns {
   public:
    // n x n, n a multiple of 3; `what` names the matrix in error messages; room is reserved
    // for expected_blocks blocks (memory counts only once written: a bound will do).
    BlockMatrixFromColumns(int64_t n, const char *what, double expected_blocks = 0.0);
    // The next column: its entries' rows, increasing, and their values.
    frix_error add_column(int64_t count, const int64_t *rows, const double *values);
    // After the n columns.
    frix_error finish(std::unique_ptr<frix_matrix> &out);
    // Whether finish() found the matrix symmetric and handed its storage over.
    bool in_place() const { return in_place_; }

   private:
    void flush_block_column();
    bool symmetric() const;
    int64_t nb_;                          // block rows = block columns
    const char *what_;
    int64_t column_ = 0;                  // columns received
    bool in_place_ = false;
    std::vector<int64_t> col_ptr_{0};     // per block column: its first block
    std::vector<int64_t> block_row_;      // per block, by columns, increasing in each
    std::vector<double> values_;          // 9 per block, column-major
    // The block column being received: its entries (row, column within the block, value).
    struct Entry {
        int64_t row;
        int col;
        double value;
    };
    std::vector<Entry> pending_;
    std::vector<int64_t> slot_;  // per block row: its block in the pending column, or -1
};

// The contacts (3 columns to a contact) of each group of columns of W, each list increasing,
// groups with the same contacts once (a body's x, y and z dofs, uncoupled in M, reach the
// same contacts): the cliques of W's block pattern (see linalg::CongruenceSink::pattern).
std::vector<std::vector<int64_t>> contact_sets(const std::vector<std::vector<int64_t>> &groups);

// Builds a square 3x3 block-CSR matrix, symmetric, from a sum of dense symmetric terms (a
// linalg::CongruenceSink): W = H^T M^-1 H as SparseCholesky::inverse_congruence forms it,
// straight into its final storage (a dense W is large: no other copy). Its blocks: every pair
// of contacts sharing one of the sink's groups, zeros included. The terms are added to the
// blocks on and above the diagonal; finish() mirrors them, so W is symmetric to the bit.
class BlockMatrixFromTerms : public linalg::CongruenceSink {
   public:
    // n x n, n a multiple of 3; `what` names the matrix in error messages.
    BlockMatrixFromTerms(int64_t n, const char *what);
    frix_error pattern(const std::vector<std::vector<int64_t>> &groups) override;
    frix_error add(int64_t count, const int64_t *cols, int64_t width, const double *T, int64_t ld) override;
    // After the last term.
    frix_error finish(std::unique_ptr<frix_matrix> &out);

   private:
    std::unique_ptr<frix_matrix> A_;
    const char *what_;
};

// Whether a and b have the same shape, storage and sparsity pattern (values aside).
bool same_pattern(const frix_matrix &a, const frix_matrix &b);
// A's shape and pattern without its values: what same_pattern compares a later matrix with
// once A itself may be gone.
frix_matrix pattern_of(const frix_matrix &A);

// The block graph of a square block-CSR W: nc x nc CSC, pattern only, the upper triangle of
// the symmetrised block pattern with every diagonal entry; what a Cholesky of a matrix with
// W's pattern fills in is priced on it (linalg::cholesky_cost).
void block_graph(const frix_matrix &W, std::vector<int64_t> &colptr, std::vector<int64_t> &rowind);
// The same from block rows of any block size: row a's block columns row_ptr[a] .. row_ptr[a + 1]
// of block_col.
void block_graph(int64_t block_rows, const int64_t *row_ptr, const int64_t *block_col, std::vector<int64_t> &colptr,
                 std::vector<int64_t> &rowind);
// The price of a scalar Cholesky of a matrix with W's block pattern (W + rho I, say), from the
// symbolic analysis of its block graph (in closed form where W stores every block): 27 flops
// per block flop, 9 entries per block entry.
frix_error block_cholesky_cost(const frix_matrix &W, linalg::FactorCost *cost);

// diag_index of a block-CSR matrix from its rows (sorted block columns); all -1 unless square.
void index_diagonal_blocks(frix_matrix &A);

// A's diagonal (min(rows, cols) values; an entry stored twice counts twice), either storage.
std::vector<double> matrix_diagonal(const frix_matrix &A);

// frix_matrix_from_csc on the caller's vectors (colptr of ncols + 1, rowind and values of at
// least colptr[ncols]): where the matrix keeps them as they are (stored by columns, rows
// strictly increasing) it takes them, leaving them empty, instead of copying them; otherwise
// they are read as frix_matrix_from_csc reads its arrays. The same checks and messages.
frix_error matrix_from_csc_taking(int64_t nrows, int64_t ncols, std::vector<int64_t> &colptr,
                                  std::vector<int64_t> &rowind, std::vector<double> &values, frix_matrix **out);

// y = alpha*A*x + beta*y for either storage; no argument checks (internal callers).
void matrix_gemv(const frix_matrix &A, double alpha, const double *x, double beta, double *y);
// matrix_gemv on block rows first .. end of a block matrix only (y's rows 3 first .. 3 end),
// with the same arithmetic: ranges of rows may be shared among threads.
void matrix_gemv_block_rows(const frix_matrix &A, double alpha, const double *x, double beta, double *y,
                            int64_t first, int64_t end);
// y = (A - A^T) x / 2 (A square), the skew part of A times x; work holds n values.
void matrix_skew_gemv(const frix_matrix &A, const double *x, double *y, double *work);
void matrix_gemv_transposed(const frix_matrix &A, double alpha, const double *x, double beta,
                            double *y);

}  // namespace frix
