// Construction, products and export of frix_matrix (3x3 block-CSR or general CSC).
#include "matrix.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numeric>

#include "error_state.hpp"
#include "memory.hpp"

namespace {

using frix::fail;

// Larger dimensions are certainly a caller's mistake (or garbage) and would only fail later
// in an allocation; refusing them up front gives a clear message.
constexpr int64_t kMaxDimension = int64_t(1) << 40;

frix_error check_dimensions(const char *where, int64_t nrows, int64_t ncols) {
    if (nrows < 0 || ncols < 0 || nrows > kMaxDimension || ncols > kMaxDimension)
        return fail(FRIX_ERR_DIMENSION, "%s: invalid matrix size %lld x %lld", where,
                    (long long)nrows, (long long)ncols);
    return FRIX_OK;
}

// Builds the block-CSR storage from entries already checked for range and finiteness.
// Duplicates are summed; a block exists where at least one entry falls.
void build_blocks(frix_matrix &A, int64_t nentries, const int64_t *rows, const int64_t *cols,
                  const double *vals) {
    A.block = true;
    A.block_rows = A.rows / 3;
    A.block_cols = A.cols / 3;
    // Bucket the entries by block row (counting sort keeps the work linear).
    std::vector<int64_t> start(A.block_rows + 1, 0);
    for (int64_t e = 0; e < nentries; ++e) ++start[rows[e] / 3 + 1];
    std::partial_sum(start.begin(), start.end(), start.begin());
    std::vector<int64_t> order;
    frix::assign_advised(order, (size_t)nentries);
    {
        std::vector<int64_t> next(start.begin(), start.end() - 1);
        for (int64_t e = 0; e < nentries; ++e) order[next[rows[e] / 3]++] = e;
    }
    std::vector<int64_t> mark(A.block_cols, -1);
    std::vector<int64_t> row_cols;
    A.row_ptr.assign(A.block_rows + 1, 0);
    A.block_col.clear();
    for (int64_t br = 0; br < A.block_rows; ++br) {
        row_cols.clear();
        for (int64_t k = start[br]; k < start[br + 1]; ++k) {
            int64_t bc = cols[order[k]] / 3;
            if (mark[bc] != br) {
                mark[bc] = br;
                row_cols.push_back(bc);
            }
        }
        std::sort(row_cols.begin(), row_cols.end());
        A.block_col.insert(A.block_col.end(), row_cols.begin(), row_cols.end());
        A.row_ptr[br + 1] = (int64_t)A.block_col.size();
    }
    frix::assign_advised(A.block_val, 9 * A.block_col.size(), 0.0);
    // Second pass: slot[bc] is the index of block (br, bc) while row br is being filled.
    std::vector<int64_t> slot(A.block_cols, 0);
    for (int64_t br = 0; br < A.block_rows; ++br) {
        for (int64_t b = A.row_ptr[br]; b < A.row_ptr[br + 1]; ++b) slot[A.block_col[b]] = b;
        for (int64_t k = start[br]; k < start[br + 1]; ++k) {
            int64_t e = order[k];
            int64_t b = slot[cols[e] / 3];
            A.block_val[9 * b + 3 * (cols[e] % 3) + rows[e] % 3] += vals[e];
        }
    }
    frix::index_diagonal_blocks(A);
}

// Builds CSC storage (rows sorted per column, duplicates summed) from checked entries.
void build_csc(frix_matrix &A, int64_t nentries, const int64_t *rows, const int64_t *cols,
               const double *vals) {
    A.block = false;
    std::vector<int64_t> start(A.cols + 1, 0);
    for (int64_t e = 0; e < nentries; ++e) ++start[cols[e] + 1];
    std::partial_sum(start.begin(), start.end(), start.begin());
    std::vector<int64_t> order;
    frix::assign_advised(order, (size_t)nentries);
    {
        std::vector<int64_t> next(start.begin(), start.end() - 1);
        for (int64_t e = 0; e < nentries; ++e) order[next[cols[e]]++] = e;
    }
    A.col_ptr.assign(A.cols + 1, 0);
    A.row_ind.clear();
    A.val.clear();
    A.row_ind.reserve(nentries);
    A.val.reserve(nentries);
    for (int64_t c = 0; c < A.cols; ++c) {
        auto first = order.begin() + start[c], last = order.begin() + start[c + 1];
        // Stable: equal rows keep input order, so duplicate sums are deterministic.
        std::stable_sort(first, last, [&](int64_t a, int64_t b) { return rows[a] < rows[b]; });
        for (auto it = first; it != last; ++it) {
            int64_t r = rows[*it];
            if ((int64_t)A.row_ind.size() > A.col_ptr[c] && A.row_ind.back() == r)
                A.val.back() += vals[*it];
            else {
                A.row_ind.push_back(r);
                A.val.push_back(vals[*it]);
            }
        }
        A.col_ptr[c + 1] = (int64_t)A.row_ind.size();
    }
}

// Entry e, at (row, col) with value v, of an nrows x ncols matrix: inside it and finite.
frix_error check_entry(const char *where, int64_t nrows, int64_t ncols, int64_t e, int64_t row, int64_t col,
                       double v) {
    if (row < 0 || row >= nrows || col < 0 || col >= ncols)
        return fail(FRIX_ERR_DIMENSION, "%s: entry %lld at (%lld, %lld) is outside the %lld x %lld matrix", where,
                    (long long)e, (long long)row, (long long)col, (long long)nrows, (long long)ncols);
    if (!std::isfinite(v))
        return fail(FRIX_ERR_NOT_FINITE, "%s: entry (%lld, %lld) is not finite", where, (long long)row,
                    (long long)col);
    return FRIX_OK;
}

// Checks entries and builds the storage the dimensions call for.
frix_error build(const char *where, int64_t nrows, int64_t ncols, int64_t n, const int64_t *rows,
                 const int64_t *cols, const double *vals, frix_matrix **out) {
    for (int64_t e = 0; e < n; ++e)
        if (frix_error err = check_entry(where, nrows, ncols, e, rows[e], cols[e], vals[e])) return err;
    auto A = std::make_unique<frix_matrix>();
    A->rows = nrows;
    A->cols = ncols;
    if (nrows % 3 == 0 && ncols % 3 == 0)
        build_blocks(*A, n, rows, cols, vals);
    else
        build_csc(*A, n, rows, cols, vals);
    // Duplicates are summed: finite terms can overflow (1.7e308 + 1.7e308), and every product
    // with A would then be Inf or NaN.
    int64_t bad_row = -1, bad_col = -1;
    frix::for_each_entry(*A, [&](int64_t r, int64_t c, double x) {
        if (bad_row < 0 && !std::isfinite(x)) bad_row = r, bad_col = c;
    });
    if (bad_row >= 0)
        return fail(FRIX_ERR_NOT_FINITE, "%s: the entries given at (%lld, %lld) sum to a value that is not finite",
                    where, (long long)bad_row, (long long)bad_col);
    *out = A.release();
    return FRIX_OK;
}

// Compressed pointers (CSC columns or CSR rows): from 0, never decreasing, and the index and
// value arrays given where there are entries.
frix_error check_pointers(const char *where, int64_t nouter, const int64_t *ptr, const int64_t *inner,
                          const double *values, const char *outer_name) {
    if (!ptr) return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: the %s pointer array is NULL", where, outer_name);
    if (ptr[0] != 0)
        return fail(FRIX_ERR_DIMENSION, "%s: %s pointers must start at 0 (got %lld)", where,
                    outer_name, (long long)ptr[0]);
    for (int64_t k = 0; k < nouter; ++k)
        if (ptr[k + 1] < ptr[k])
            return fail(FRIX_ERR_DIMENSION, "%s: %s pointers decrease at %s %lld", where,
                        outer_name, outer_name, (long long)k);
    if (ptr[nouter] > 0 && (!inner || !values))
        return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: index or value array is NULL", where);
    return FRIX_OK;
}

// Expands pointers that check_pointers passed into explicit indices.
std::vector<int64_t> expand_pointers(int64_t nouter, const int64_t *ptr) {
    std::vector<int64_t> outer_of;
    frix::assign_advised(outer_of, (size_t)ptr[nouter]);
    for (int64_t k = 0; k < nouter; ++k)
        for (int64_t e = ptr[k]; e < ptr[k + 1]; ++e) outer_of[(size_t)e] = k;
    return outer_of;
}

// A CSC matrix stored by columns (its dimensions not both multiples of 3) whose rows strictly
// increase in every column, as FCLIB's and CHOLMOD's do: its arrays taken as they are, with
// build()'s checks, and no expansion, sort or merge (those cost more than the copy, and three
// more copies of the entries). false: not such a matrix (nothing built, no error set), for
// build() to take; true: *out built, or err set. Where `taken` holds the caller's vectors of
// colptr, rowind and values, the matrix takes them (left empty) instead of copying them.
struct TakenCsc {
    std::vector<int64_t> *colptr, *rowind;
    std::vector<double> *values;
};
bool build_sorted_csc(const char *where, int64_t nrows, int64_t ncols, const int64_t *colptr, const int64_t *rowind,
                      const double *values, frix_matrix **out, frix_error &err, const TakenCsc *taken = nullptr) {
    if (nrows % 3 == 0 && ncols % 3 == 0) return false;
    // In input order, as build() checks: the first bad entry is the same either way.
    for (int64_t c = 0; c < ncols; ++c)
        for (int64_t e = colptr[c]; e < colptr[c + 1]; ++e) {
            if (e > colptr[c] && rowind[e] <= rowind[e - 1]) return false;
            if ((err = check_entry(where, nrows, ncols, e, rowind[e], c, values[e]))) return true;
        }
    auto A = std::make_unique<frix_matrix>();
    A->rows = nrows;
    A->cols = ncols;
    A->block = false;
    const int64_t nnz = colptr[ncols];
    if (taken) {
        taken->rowind->resize((size_t)nnz);
        taken->values->resize((size_t)nnz);
        A->col_ptr = std::move(*taken->colptr);
        A->row_ind = std::move(*taken->rowind);
        A->val = std::move(*taken->values);
    } else {
        A->col_ptr.assign(colptr, colptr + ncols + 1);
        frix::copy_advised(A->row_ind, rowind, (size_t)nnz);
        frix::copy_advised(A->val, values, (size_t)nnz);
    }
    *out = A.release();
    return true;
}

// frix_matrix_from_csc past its checks of out and the dimensions: the pointers checked, then
// the sorted columns taken as they are (taken: the caller's vectors, which must hold every
// entry the pointers count), else the general build.
frix_error from_csc(const char *where, int64_t nrows, int64_t ncols, const int64_t *colptr, const int64_t *rowind,
                    const double *values, frix_matrix **out, const TakenCsc *taken = nullptr) {
    if (frix_error e = check_pointers(where, ncols, colptr, rowind, values, "column")) return e;
    const int64_t nnz = colptr[ncols];
    if (taken && ((int64_t)taken->rowind->size() < nnz || (int64_t)taken->values->size() < nnz))
        return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: fewer entries than the column pointers' %lld", where,
                    (long long)nnz);
    frix_error err = FRIX_OK;
    if (build_sorted_csc(where, nrows, ncols, colptr, rowind, values, out, err, taken)) return err;
    const std::vector<int64_t> col_of = expand_pointers(ncols, colptr);
    return build(where, nrows, ncols, (int64_t)col_of.size(), rowind, col_of.data(), values, out);
}

// The export's arrays: colptr always (it has cols + 1 >= 1 entries); rowind and values may be
// NULL when there are no entries, as a caller's empty std::vector hands out NULL.
frix_error check_csc_arrays(int64_t nnz, const int64_t *colptr, const int64_t *rowind,
                            const double *values) {
    if (colptr && ((rowind && values) || nnz == 0)) return FRIX_OK;
    return fail(FRIX_ERR_INVALID_ARGUMENT,
                "frix_matrix_to_csc: give colptr, rowind and values (rowind and values may be NULL "
                "when the matrix has no entries), or all three NULL to learn nnz");
}

}  // namespace

namespace frix {

void block_graph(int64_t block_rows, const int64_t *row_ptr, const int64_t *block_col, std::vector<int64_t> &colptr,
                 std::vector<int64_t> &rowind) {
    std::vector<std::pair<int64_t, int64_t>> e;  // (column, row), row <= column
    e.reserve((size_t)(row_ptr[block_rows] + block_rows));
    for (int64_t br = 0; br < block_rows; ++br) {
        e.emplace_back(br, br);
        for (int64_t b = row_ptr[br]; b < row_ptr[br + 1]; ++b)
            e.emplace_back(std::max(br, block_col[b]), std::min(br, block_col[b]));
    }
    std::sort(e.begin(), e.end());
    e.erase(std::unique(e.begin(), e.end()), e.end());
    colptr.assign((size_t)block_rows + 1, 0);
    rowind.clear();
    rowind.reserve(e.size());
    for (const auto &x : e) {
        ++colptr[(size_t)x.first + 1];
        rowind.push_back(x.second);
    }
    for (int64_t j = 0; j < block_rows; ++j) colptr[(size_t)j + 1] += colptr[(size_t)j];
}

void block_graph(const frix_matrix &W, std::vector<int64_t> &colptr, std::vector<int64_t> &rowind) {
    block_graph(W.block_rows, W.row_ptr.data(), W.block_col.data(), colptr, rowind);
}

frix_error block_cholesky_cost(const frix_matrix &W, linalg::FactorCost *cost) {
    const double nb = (double)W.block_rows;
    if ((double)W.nblocks() == nb * nb) {  // every block stored (a deformable body's W): dense
        const linalg::FactorCost dense = linalg::dense_cholesky_cost(W.block_rows);
        *cost = {27.0 * dense.flops, 9.0 * dense.factor_entries, 9.0 * dense.bytes};
        return FRIX_OK;
    }
    std::vector<int64_t> colptr, rowind;
    block_graph(W, colptr, rowind);
    linalg::FactorCost blocks;
    const frix_error e = linalg::cholesky_cost({W.block_rows, W.block_rows, colptr.data(), rowind.data(), nullptr}, &blocks);
    *cost = {27.0 * blocks.flops, 9.0 * blocks.factor_entries, 9.0 * blocks.bytes};
    return e;
}

bool same_pattern(const frix_matrix &a, const frix_matrix &b) {
    return a.rows == b.rows && a.cols == b.cols && a.block == b.block && a.row_ptr == b.row_ptr &&
           a.block_col == b.block_col && a.col_ptr == b.col_ptr && a.row_ind == b.row_ind;
}

frix_matrix pattern_of(const frix_matrix &A) {
    frix_matrix p;
    p.rows = A.rows;
    p.cols = A.cols;
    p.block = A.block;
    p.block_rows = A.block_rows;
    p.block_cols = A.block_cols;
    p.row_ptr = A.row_ptr;
    p.block_col = A.block_col;
    p.col_ptr = A.col_ptr;
    p.row_ind = A.row_ind;
    return p;
}

void index_diagonal_blocks(frix_matrix &A) {
    A.diag_index.assign((size_t)A.block_rows, -1);
    if (A.block_rows != A.block_cols) return;
    for (int64_t br = 0; br < A.block_rows; ++br) {
        const auto first = A.block_col.begin() + A.row_ptr[(size_t)br];
        const auto last = A.block_col.begin() + A.row_ptr[(size_t)br + 1];
        const auto it = std::lower_bound(first, last, br);
        if (it != last && *it == br) A.diag_index[(size_t)br] = it - A.block_col.begin();
    }
}

std::vector<double> matrix_diagonal(const frix_matrix &A) {
    std::vector<double> diag((size_t)std::min(A.rows, A.cols), 0.0);
    // A square block matrix's diagonal lies in its diagonal blocks: read those, not every
    // entry (a deformable body's dense W holds millions).
    if (A.block && A.block_rows == A.block_cols && (int64_t)A.diag_index.size() == A.block_rows) {
        for (int64_t k = 0; k < A.block_rows; ++k) {
            const int64_t b = A.diag_index[(size_t)k];
            if (b < 0) continue;
            for (int i = 0; i < 3; ++i) diag[(size_t)(3 * k + i)] = A.block_val[(size_t)(9 * b + 4 * i)];
        }
        return diag;
    }
    for_each_entry(A, [&](int64_t i, int64_t j, double v) {
        if (i == j) diag[(size_t)i] += v;
    });
    return diag;
}

void matrix_gemv_block_rows(const frix_matrix &A, double alpha, const double *x, double beta, double *y,
                            int64_t first, int64_t end) {
    for (int64_t k = first; k < end; ++k) {
        double t[3];
        block_row_product(A, k, x, t);
        for (int i = 0; i < 3; ++i) y[3 * k + i] = alpha * t[i] + (beta == 0.0 ? 0.0 : beta * y[3 * k + i]);
    }
}

void matrix_gemv(const frix_matrix &A, double alpha, const double *x, double beta, double *y) {
    if (A.block) {
        matrix_gemv_block_rows(A, alpha, x, beta, y, 0, A.block_rows);
        return;
    }
    for (int64_t i = 0; i < A.rows; ++i) y[i] = beta == 0.0 ? 0.0 : beta * y[i];
    for (int64_t c = 0; c < A.cols; ++c) {
        double xc = alpha * x[c];
        for (int64_t e = A.col_ptr[c]; e < A.col_ptr[c + 1]; ++e) y[A.row_ind[e]] += A.val[e] * xc;
    }
}

void matrix_skew_gemv(const frix_matrix &A, const double *x, double *y, double *work) {
    matrix_gemv(A, 0.5, x, 0.0, y);
    matrix_gemv_transposed(A, 0.5, x, 0.0, work);
    for (int64_t i = 0; i < A.rows; ++i) y[i] -= work[i];
}

void matrix_gemv_transposed(const frix_matrix &A, double alpha, const double *x, double beta,
                            double *y) {
    if (A.block) {
        for (int64_t j = 0; j < A.cols; ++j) y[j] = beta == 0.0 ? 0.0 : beta * y[j];
        for (int64_t k = 0; k < A.block_rows; ++k) {
            const double *xk = &x[3 * k];
            for (int64_t b = A.row_ptr[k]; b < A.row_ptr[k + 1]; ++b) {
                const double *B = &A.block_val[9 * b];
                double *yj = &y[3 * A.block_col[b]];
                for (int c = 0; c < 3; ++c)
                    yj[c] += alpha * (B[3 * c] * xk[0] + B[3 * c + 1] * xk[1] + B[3 * c + 2] * xk[2]);
            }
        }
        return;
    }
    for (int64_t c = 0; c < A.cols; ++c) {
        double s = 0.0;
        for (int64_t e = A.col_ptr[c]; e < A.col_ptr[c + 1]; ++e) s += A.val[e] * x[A.row_ind[e]];
        y[c] = alpha * s + (beta == 0.0 ? 0.0 : beta * y[c]);
    }
}

}  // namespace frix

extern "C" {

FRIX_API frix_error frix_matrix_from_csc(int64_t nrows, int64_t ncols, const int64_t *colptr,
                                         const int64_t *rowind, const double *values,
                                         frix_matrix **out) {
    return frix::guard("frix_matrix_from_csc", [&]() -> frix_error {
        const char *where = "frix_matrix_from_csc";
        if (!out) return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: out is NULL", where);
        *out = nullptr;
        if (frix_error e = check_dimensions(where, nrows, ncols)) return e;
        return from_csc(where, nrows, ncols, colptr, rowind, values, out);
    });
}

}  // extern "C"

namespace frix {

frix_error matrix_from_csc_taking(int64_t nrows, int64_t ncols, std::vector<int64_t> &colptr,
                                  std::vector<int64_t> &rowind, std::vector<double> &values, frix_matrix **out) {
    return guard("frix_matrix_from_csc", [&]() -> frix_error {
        const char *where = "frix_matrix_from_csc";
        *out = nullptr;
        if (frix_error e = check_dimensions(where, nrows, ncols)) return e;
        if ((int64_t)colptr.size() != ncols + 1)
            return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: %lld column pointers for %lld columns", where,
                        (long long)colptr.size(), (long long)ncols);
        const TakenCsc taken{&colptr, &rowind, &values};
        return from_csc(where, nrows, ncols, colptr.data(), rowind.data(), values.data(), out, &taken);
    });
}

}  // namespace frix

extern "C" {

FRIX_API frix_error frix_matrix_from_csr(int64_t nrows, int64_t ncols, const int64_t *rowptr,
                                         const int64_t *colind, const double *values,
                                         frix_matrix **out) {
    return frix::guard("frix_matrix_from_csr", [&]() -> frix_error {
        const char *where = "frix_matrix_from_csr";
        if (!out) return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: out is NULL", where);
        *out = nullptr;
        if (frix_error e = check_dimensions(where, nrows, ncols)) return e;
        if (frix_error e = check_pointers(where, nrows, rowptr, colind, values, "row")) return e;
        const std::vector<int64_t> row_of = expand_pointers(nrows, rowptr);
        return build(where, nrows, ncols, (int64_t)row_of.size(), row_of.data(), colind, values, out);
    });
}

FRIX_API frix_error frix_matrix_from_triplets(int64_t nrows, int64_t ncols, int64_t nnz,
                                              const int64_t *rows, const int64_t *cols,
                                              const double *values, frix_matrix **out) {
    return frix::guard("frix_matrix_from_triplets", [&]() -> frix_error {
        const char *where = "frix_matrix_from_triplets";
        if (!out) return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: out is NULL", where);
        *out = nullptr;
        if (frix_error e = check_dimensions(where, nrows, ncols)) return e;
        if (nnz < 0) return fail(FRIX_ERR_DIMENSION, "%s: negative entry count %lld", where, (long long)nnz);
        if (nnz > 0 && (!rows || !cols || !values))
            return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: index or value array is NULL", where);
        return build(where, nrows, ncols, nnz, rows, cols, values, out);
    });
}

FRIX_API frix_error frix_matrix_from_dense(int64_t nrows, int64_t ncols, const double *values,
                                           int64_t ld, frix_matrix **out) {
    return frix::guard("frix_matrix_from_dense", [&]() -> frix_error {
        const char *where = "frix_matrix_from_dense";
        if (!out) return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: out is NULL", where);
        *out = nullptr;
        if (frix_error e = check_dimensions(where, nrows, ncols)) return e;
        if (ld < std::max<int64_t>(nrows, 1))
            return fail(FRIX_ERR_DIMENSION, "%s: leading dimension %lld < rows %lld", where,
                        (long long)ld, (long long)nrows);
        if (nrows > 0 && ncols > 0 && !values)
            return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: values is NULL", where);
        std::vector<int64_t> r, c;
        std::vector<double> x;
        for (int64_t j = 0; j < ncols; ++j)
            for (int64_t i = 0; i < nrows; ++i) {
                double a = values[i + j * ld];
                if (a != 0.0 || !std::isfinite(a)) {
                    r.push_back(i);
                    c.push_back(j);
                    x.push_back(a);
                }
            }
        return build(where, nrows, ncols, (int64_t)x.size(), r.data(), c.data(), x.data(), out);
    });
}

FRIX_API frix_error frix_matrix_from_blocks(int64_t nblock_rows, int64_t nblock_cols,
                                            int64_t nblocks, const int64_t *block_rows,
                                            const int64_t *block_cols, const double *values,
                                            frix_matrix **out) {
    return frix::guard("frix_matrix_from_blocks", [&]() -> frix_error {
        const char *where = "frix_matrix_from_blocks";
        if (!out) return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: out is NULL", where);
        *out = nullptr;
        if (nblock_rows < 0 || nblock_cols < 0 || nblock_rows > kMaxDimension / 3 ||
            nblock_cols > kMaxDimension / 3)
            return fail(FRIX_ERR_DIMENSION, "%s: invalid block size %lld x %lld", where,
                        (long long)nblock_rows, (long long)nblock_cols);
        if (nblocks < 0) return fail(FRIX_ERR_DIMENSION, "%s: negative block count", where);
        if (nblocks > 0 && (!block_rows || !block_cols || !values))
            return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: index or value array is NULL", where);
        for (int64_t k = 0; k < nblocks; ++k)
            if (block_rows[k] < 0 || block_rows[k] >= nblock_rows || block_cols[k] < 0 ||
                block_cols[k] >= nblock_cols)
                return fail(FRIX_ERR_DIMENSION, "%s: block %lld at (%lld, %lld) is outside the %lld x %lld block matrix",
                            where, (long long)k, (long long)block_rows[k], (long long)block_cols[k],
                            (long long)nblock_rows, (long long)nblock_cols);
        // Every value of a given block is kept (explicit zeros too), so expand all 9.
        std::vector<int64_t> r(9 * nblocks), c(9 * nblocks);
        for (int64_t k = 0; k < nblocks; ++k)
            for (int j = 0; j < 3; ++j)
                for (int i = 0; i < 3; ++i) {
                    r[9 * k + 3 * j + i] = 3 * block_rows[k] + i;
                    c[9 * k + 3 * j + i] = 3 * block_cols[k] + j;
                }
        return build(where, 3 * nblock_rows, 3 * nblock_cols, 9 * nblocks, r.data(), c.data(),
                     values, out);
    });
}

FRIX_API void frix_matrix_free(frix_matrix *m) { delete m; }

FRIX_API int64_t frix_matrix_rows(const frix_matrix *m) { return m ? m->rows : 0; }
FRIX_API int64_t frix_matrix_cols(const frix_matrix *m) { return m ? m->cols : 0; }
FRIX_API int64_t frix_matrix_nnz(const frix_matrix *m) {
    if (!m) return 0;
    return m->block ? 9 * m->nblocks() : (int64_t)m->val.size();
}
FRIX_API int64_t frix_matrix_block_count(const frix_matrix *m) { return m ? m->nblocks() : 0; }
FRIX_API int frix_matrix_is_block(const frix_matrix *m) { return m && m->block ? 1 : 0; }

FRIX_API frix_error frix_matrix_gemv(const frix_matrix *m, double alpha, const double *x,
                                     double beta, double *y) {
    if (!m || (!x && m->cols > 0) || (!y && m->rows > 0))
        return fail(FRIX_ERR_INVALID_ARGUMENT, "frix_matrix_gemv: NULL matrix or vector");
    frix::matrix_gemv(*m, alpha, x, beta, y);
    return FRIX_OK;
}

FRIX_API frix_error frix_matrix_gemv_transposed(const frix_matrix *m, double alpha,
                                                const double *x, double beta, double *y) {
    if (!m || (!x && m->rows > 0) || (!y && m->cols > 0))
        return fail(FRIX_ERR_INVALID_ARGUMENT, "frix_matrix_gemv_transposed: NULL matrix or vector");
    frix::matrix_gemv_transposed(*m, alpha, x, beta, y);
    return FRIX_OK;
}

FRIX_API frix_error frix_matrix_diagonal_block(const frix_matrix *m, int64_t k, double *out) {
    if (!m || !out) return fail(FRIX_ERR_INVALID_ARGUMENT, "frix_matrix_diagonal_block: NULL argument");
    if (!m->block || m->block_rows != m->block_cols)
        return fail(FRIX_ERR_UNSUPPORTED, "frix_matrix_diagonal_block: the matrix is not a square block matrix");
    if (k < 0 || k >= m->block_rows)
        return fail(FRIX_ERR_DIMENSION, "frix_matrix_diagonal_block: block row %lld out of range [0, %lld)",
                    (long long)k, (long long)m->block_rows);
    int64_t b = m->diag_index[k];
    for (int i = 0; i < 9; ++i) out[i] = b >= 0 ? m->block_val[9 * b + i] : 0.0;
    return FRIX_OK;
}

FRIX_API frix_error frix_matrix_to_csc(const frix_matrix *m, int64_t *nnz, int64_t *colptr,
                                       int64_t *rowind, double *values) {
    return frix::guard("frix_matrix_to_csc", [&]() -> frix_error {
        if (!m || !nnz) return fail(FRIX_ERR_INVALID_ARGUMENT, "frix_matrix_to_csc: NULL matrix or nnz");
        if (!m->block) {
            *nnz = (int64_t)m->val.size();
            if (!colptr && !rowind && !values) return FRIX_OK;
            if (frix_error e = check_csc_arrays(*nnz, colptr, rowind, values)) return e;
            std::copy(m->col_ptr.begin(), m->col_ptr.end(), colptr);
            std::copy(m->row_ind.begin(), m->row_ind.end(), rowind);
            std::copy(m->val.begin(), m->val.end(), values);
            return FRIX_OK;
        }
        // Count the non-zero entries of each column, then fill by increasing block row:
        // rows of a column then arrive in increasing order.
        std::vector<int64_t> start(m->cols + 1, 0);
        for (int64_t b = 0; b < m->nblocks(); ++b)
            for (int j = 0; j < 3; ++j)
                for (int i = 0; i < 3; ++i)
                    if (m->block_val[9 * b + 3 * j + i] != 0.0) ++start[3 * m->block_col[b] + j + 1];
        std::partial_sum(start.begin(), start.end(), start.begin());
        *nnz = start[m->cols];
        if (!colptr && !rowind && !values) return FRIX_OK;
        if (frix_error e = check_csc_arrays(*nnz, colptr, rowind, values)) return e;
        std::copy(start.begin(), start.end(), colptr);
        for (int64_t k = 0; k < m->block_rows; ++k)
            for (int i = 0; i < 3; ++i)
                for (int64_t b = m->row_ptr[k]; b < m->row_ptr[k + 1]; ++b)
                    for (int j = 0; j < 3; ++j) {
                        double a = m->block_val[9 * b + 3 * j + i];
                        if (a == 0.0) continue;
                        int64_t c = 3 * m->block_col[b] + j;
                        rowind[start[c]] = 3 * k + i;
                        values[start[c]++] = a;
                    }
        return FRIX_OK;
    });
}

}  // extern "C"
