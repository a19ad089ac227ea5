/* frix — sparse matrices.
 *
 * A frix_matrix is immutable once built. A matrix whose two dimensions are multiples of 3
 * is stored as a sparse-block matrix of 3x3 blocks (block-CSR, each block column-major);
 * any other matrix (e.g. a global M with n not a multiple of 3) is stored as general CSC.
 * Every constructor copies the caller's arrays into that storage (the conversion is the
 * copy), checks them (sizes, index ranges, NaN/Inf) and sums duplicate entries.
 * Indices are 0-based.
 */
#ifndef FRIX_MATRIX_H
#define FRIX_MATRIX_H

#include <stdint.h>
#include "frix_export.h"
#include "frix_errors.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct frix_matrix frix_matrix;

/* Compressed sparse columns: colptr has ncols+1 entries, rowind and values colptr[ncols]. */
FRIX_API frix_error frix_matrix_from_csc(int64_t nrows, int64_t ncols, const int64_t *colptr,
                                         const int64_t *rowind, const double *values,
                                         frix_matrix **out);
/* Compressed sparse rows: rowptr has nrows+1 entries, colind and values rowptr[nrows]. */
FRIX_API frix_error frix_matrix_from_csr(int64_t nrows, int64_t ncols, const int64_t *rowptr,
                                         const int64_t *colind, const double *values,
                                         frix_matrix **out);
/* Triplets (coordinate form), any order; duplicates are summed. */
FRIX_API frix_error frix_matrix_from_triplets(int64_t nrows, int64_t ncols, int64_t nnz,
                                              const int64_t *rows, const int64_t *cols,
                                              const double *values, frix_matrix **out);
/* Dense column-major, leading dimension ld >= nrows. Exact zeros are not stored; a 3x3
 * block with any non-zero entry is stored whole. */
FRIX_API frix_error frix_matrix_from_dense(int64_t nrows, int64_t ncols, const double *values,
                                           int64_t ld, frix_matrix **out);
/* 3x3 blocks: nblocks blocks, block k at block row block_rows[k], block column block_cols[k],
 * its 9 values column-major at values[9k .. 9k+8]. Sizes are in blocks: the matrix is
 * (3*nblock_rows) x (3*nblock_cols). Duplicate blocks are summed. */
FRIX_API frix_error frix_matrix_from_blocks(int64_t nblock_rows, int64_t nblock_cols,
                                            int64_t nblocks, const int64_t *block_rows,
                                            const int64_t *block_cols, const double *values,
                                            frix_matrix **out);

FRIX_API void frix_matrix_free(frix_matrix *m);

FRIX_API int64_t frix_matrix_rows(const frix_matrix *m);
FRIX_API int64_t frix_matrix_cols(const frix_matrix *m);
/* Stored scalar entries: 9 per stored block for block storage (explicit zeros inside a
 * block included), the CSC entry count otherwise. */
FRIX_API int64_t frix_matrix_nnz(const frix_matrix *m);
/* Stored 3x3 blocks, or 0 when the matrix is not block-stored. */
FRIX_API int64_t frix_matrix_block_count(const frix_matrix *m);
FRIX_API int frix_matrix_is_block(const frix_matrix *m);

/* y = alpha*A*x + beta*y (x has cols entries, y rows). beta == 0 ignores y's content. */
FRIX_API frix_error frix_matrix_gemv(const frix_matrix *m, double alpha, const double *x,
                                     double beta, double *y);
/* y = alpha*A^T*x + beta*y (x has rows entries, y cols). */
FRIX_API frix_error frix_matrix_gemv_transposed(const frix_matrix *m, double alpha,
                                                const double *x, double beta, double *y);
/* The 3x3 diagonal block of block row k of a square block matrix, column-major into
 * out[9] (zeros if not stored). */
FRIX_API frix_error frix_matrix_diagonal_block(const frix_matrix *m, int64_t k, double *out);

/* Export to CSC. Call with NULL arrays to learn *nnz; then with colptr (cols+1),
 * rowind and values (nnz each; these two may be NULL when *nnz is 0). Exact zeros inside
 * stored blocks are not exported.
 * Row indices are sorted within each column. */
FRIX_API frix_error frix_matrix_to_csc(const frix_matrix *m, int64_t *nnz, int64_t *colptr,
                                       int64_t *rowind, double *values);

#ifdef __cplusplus
}
#endif

#endif /* FRIX_MATRIX_H */
