// DenseLU and DenseCholesky on LAPACK (Fortran symbols, 32-bit integers as in OpenBLAS's
// default LP64 build).
#include <algorithm>
#include <chrono>
#include <climits>
#include <cmath>

#include "error_state.hpp"
#include "linalg.hpp"

extern "C" {
void dgetrf_(const int *m, const int *n, double *a, const int *lda, int *ipiv, int *info);
void dgetrs_(const char *trans, const int *n, const int *nrhs, const double *a, const int *lda,
             const int *ipiv, double *b, const int *ldb, int *info, size_t trans_len);
void dpotrf_(const char *uplo, const int *n, double *a, const int *lda, int *info, size_t uplo_len);
void dpotrs_(const char *uplo, const int *n, const int *nrhs, const double *a, const int *lda,
             double *b, const int *ldb, int *info, size_t uplo_len);
}

namespace frix::linalg {

FactorCost dense_cholesky_cost(int64_t n) {
    // Column j of L (from 0) holds n - j entries; CHOLMOD counts the sum of their squares.
    const double N = (double)n, entries = N * (N + 1.0) / 2.0;
    return FactorCost{N * (N + 1.0) * (2.0 * N + 1.0) / 6.0, entries, 8.0 * 2.0 * entries + 8.0 * 8.0 * N};
}

namespace {

using Clock = std::chrono::steady_clock;

frix_error copy_square(const char *what, int64_t n, const double *A, int64_t lda,
                       std::vector<double> &out, int &n_out) {
    if (n <= 0 || n > INT_MAX / 2 || lda < n)
        return fail(FRIX_ERR_DIMENSION, "%s: invalid size %lld (lda %lld)", what, (long long)n,
                    (long long)lda);
    out.resize((size_t)(n * n));
    for (int64_t j = 0; j < n; ++j)
        for (int64_t i = 0; i < n; ++i) out[(size_t)(i + j * n)] = A[i + j * lda];
    n_out = (int)n;
    return FRIX_OK;
}

}  // namespace

bool invert_small(int64_t k, double *a, double *inv, double scale) {
    for (int64_t c = 0; c < k; ++c) {
        int64_t piv = c;
        for (int64_t i = c + 1; i < k; ++i)
            if (std::fabs(a[i + k * c]) > std::fabs(a[piv + k * c])) piv = i;
        if (!(std::fabs(a[piv + k * c]) > 1e-14 * scale)) return false;
        if (piv != c)
            for (int64_t j = 0; j < k; ++j) {
                std::swap(a[c + k * j], a[piv + k * j]);
                std::swap(inv[c + k * j], inv[piv + k * j]);
            }
        const double d = 1.0 / a[c + k * c];
        for (int64_t j = 0; j < k; ++j) {
            a[c + k * j] *= d;
            inv[c + k * j] *= d;
        }
        for (int64_t i = 0; i < k; ++i) {
            const double f = a[i + k * c];
            if (i == c || f == 0.0) continue;
            for (int64_t j = 0; j < k; ++j) {
                a[i + k * j] -= f * a[c + k * j];
                inv[i + k * j] -= f * inv[c + k * j];
            }
        }
    }
    return true;
}

frix_error DenseLU::factor(int64_t n, const double *A, int64_t lda) {
    ok_ = false;
    if (frix_error e = copy_square("dense LU", n, A, lda, lu_, n_)) return e;
    piv_.resize((size_t)n_);
    const auto t0 = Clock::now();
    int info = 0;
    dgetrf_(&n_, &n_, lu_.data(), &n_, piv_.data(), &info);
    stats_.seconds += std::chrono::duration<double>(Clock::now() - t0).count();
    ++stats_.numeric;
    rcond_ = 0.0;
    if (info > 0) return fail(FRIX_ERR_NUMERICAL, "dense LU: singular matrix (U(%d,%d) = 0)", info, info);
    if (info < 0) return fail(FRIX_ERR_INTERNAL, "dense LU: dgetrf argument %d invalid", -info);
    double lo = INFINITY, hi = 0.0;
    for (int i = 0; i < n_; ++i) {
        const double d = std::fabs(lu_[(size_t)i * (size_t)(n_ + 1)]);
        lo = std::min(lo, d), hi = std::max(hi, d);
    }
    rcond_ = hi > 0.0 ? lo / hi : 0.0;
    ok_ = true;
    return FRIX_OK;
}

frix_error DenseLU::solve(const double *b, double *x) const {
    if (!ok_) return fail(FRIX_ERR_NUMERICAL, "dense LU: solve() without a factorisation");
    for (int i = 0; i < n_; ++i) x[i] = b[i];
    const int one = 1;
    int info = 0;
    dgetrs_("N", &n_, &one, lu_.data(), &n_, piv_.data(), x, &n_, &info, 1);
    if (info != 0) return fail(FRIX_ERR_INTERNAL, "dense LU: dgetrs failed (%d)", info);
    return FRIX_OK;
}

frix_error DenseCholesky::factor(int64_t n, const double *A, int64_t lda) {
    ok_ = false;
    if (frix_error e = copy_square("dense Cholesky", n, A, lda, l_, n_)) return e;
    const auto t0 = Clock::now();
    int info = 0;
    dpotrf_("L", &n_, l_.data(), &n_, &info, 1);
    stats_.seconds += std::chrono::duration<double>(Clock::now() - t0).count();
    ++stats_.numeric;
    if (info > 0)
        return fail(FRIX_ERR_NUMERICAL, "dense Cholesky: the matrix is not positive definite (minor %d)", info);
    if (info < 0) return fail(FRIX_ERR_INTERNAL, "dense Cholesky: dpotrf argument %d invalid", -info);
    ok_ = true;
    return FRIX_OK;
}

frix_error DenseCholesky::solve(const double *b, double *x) const {
    if (!ok_) return fail(FRIX_ERR_NUMERICAL, "dense Cholesky: solve() without a factorisation");
    for (int i = 0; i < n_; ++i) x[i] = b[i];
    const int one = 1;
    int info = 0;
    dpotrs_("L", &n_, &one, l_.data(), &n_, x, &n_, &info, 1);
    if (info != 0) return fail(FRIX_ERR_INTERNAL, "dense Cholesky: dpotrs failed (%d)", info);
    return FRIX_OK;
}

}  // namespace frix::linalg
