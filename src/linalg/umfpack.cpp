// SparseLU on UMFPACK (the SuiteSparse_long "dl" interface, whose index type is int64_t here).
#include <umfpack.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <mutex>
#include <type_traits>
#include <vector>

#include "error_state.hpp"
#include "linalg.hpp"

namespace frix::linalg {

static_assert(std::is_same<SuiteSparse_long, int64_t>::value ||
                  sizeof(SuiteSparse_long) == sizeof(int64_t),
              "frix passes int64_t index arrays to UMFPACK's dl interface");

namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

const char *umfpack_message(SuiteSparse_long status) {
    switch (status) {
        case UMFPACK_ERROR_out_of_memory: return "out of memory";
        case UMFPACK_ERROR_invalid_matrix: return "invalid matrix";
        case UMFPACK_ERROR_invalid_Symbolic_object: return "invalid symbolic object";
        case UMFPACK_ERROR_different_pattern: return "pattern changed since the analysis";
        case UMFPACK_WARNING_singular_matrix: return "singular matrix";
        default: return "UMFPACK error";
    }
}

inline const SuiteSparse_long *idx(const int64_t *p) {
    return reinterpret_cast<const SuiteSparse_long *>(p);
}

// Where UMFPACK's estimate of a factorisation is above this many flops, it is priced by the
// symbolic analysis of A + A^T instead (symmetric_lu_flops): below it, any price is small.
constexpr double kCountedAbove = 1e9;

// What an LU of A with its pivots on the diagonal costs under a fill-reducing ordering of
// A + A^T: twice the Cholesky count (L and U). UMFPACK's own estimate is a bound that allows for
// any pivoting, many times the flops it then does (notes/2026-11-28-fem-setup.md); this is the
// count of the factorisations that pivot little. NaN where it fails.
double symmetric_lu_flops(const CscView &A) {
    const int64_t n = A.cols;
    std::vector<int64_t> count((size_t)n + 1, 0);
    for (int64_t j = 0; j < n; ++j)
        for (int64_t e = A.colptr[j]; e < A.colptr[j + 1]; ++e) ++count[(size_t)std::max(A.rowind[e], j) + 1];
    for (int64_t j = 0; j < n; ++j) count[(size_t)j + 1] += count[(size_t)j];
    std::vector<int64_t> colptr(count), rowind((size_t)std::max<int64_t>(count[(size_t)n], 1));
    for (int64_t j = 0; j < n; ++j)
        for (int64_t e = A.colptr[j]; e < A.colptr[j + 1]; ++e) {
            const int64_t i = A.rowind[e];
            rowind[(size_t)count[(size_t)std::max(i, j)]++] = std::min(i, j);
        }
    // Each column sorted, duplicates (A_ij and A_ji both stored) removed, in place.
    int64_t kept = 0;
    for (int64_t j = 0; j < n; ++j) {
        const int64_t first = colptr[(size_t)j], last = colptr[(size_t)j + 1];
        std::sort(rowind.begin() + first, rowind.begin() + last);
        colptr[(size_t)j] = kept;
        for (int64_t e = first; e < last; ++e)
            if (e == first || rowind[(size_t)e] != rowind[(size_t)e - 1]) rowind[(size_t)kept++] = rowind[(size_t)e];
    }
    colptr[(size_t)n] = kept;
    FactorCost cost;
    if (cholesky_cost({n, n, colptr.data(), rowind.data(), nullptr}, &cost) != FRIX_OK) {
        clear_error();
        return NAN;
    }
    return 2.0 * cost.flops;
}

}  // namespace

std::mutex &metis_mutex() {
    static std::mutex m;
    return m;
}

SparseLU::SparseLU() : control_(UMFPACK_CONTROL) {
    umfpack_dl_defaults(control_.data());
    control_[UMFPACK_PRL] = 0;  // never print
    // One refinement step: the Jacobians of semismooth Newton are often badly scaled, and a
    // step costs one product, far less than the factorisation.
    control_[UMFPACK_IRSTEP] = 1;
    set_ordering(Ordering::kAmd);
}

void SparseLU::set_ordering(Ordering ordering) {
    control_[UMFPACK_ORDERING] = ordering == Ordering::kNestedDissection ? UMFPACK_ORDERING_METIS : UMFPACK_ORDERING_AMD;
}

SparseLU::~SparseLU() {
    free_numeric();
    free_symbolic();
}

void SparseLU::free_numeric() {
    if (numeric_) umfpack_dl_free_numeric(&numeric_);
    numeric_ = nullptr;
}

void SparseLU::free_symbolic() {
    if (symbolic_) umfpack_dl_free_symbolic(&symbolic_);
    symbolic_ = nullptr;
}

frix_error SparseLU::analyze(const CscView &A) { return analyze_counted(A, NAN); }

frix_error SparseLU::analyze_counted(const CscView &A, double known_count) {
    free_numeric();
    free_symbolic();
    if (A.rows != A.cols || A.rows <= 0)
        return fail(FRIX_ERR_DIMENSION, "sparse LU: the matrix is %lld x %lld, not square",
                    (long long)A.rows, (long long)A.cols);
    const auto t0 = Clock::now();
    double info[UMFPACK_INFO];
    // METIS (Debian's 5.1.0) draws from libc's process-wide generator, which it reseeds (4321)
    // at each call: two orderings at once interleave their draws and give other orderings.
    std::unique_lock<std::mutex> lock(metis_mutex(), std::defer_lock);
    if (control_[UMFPACK_ORDERING] == UMFPACK_ORDERING_METIS) lock.lock();
    const SuiteSparse_long st = umfpack_dl_symbolic(A.rows, A.cols, idx(A.colptr), idx(A.rowind),
                                                     A.values, &symbolic_, control_.data(), info);
    stats_.seconds += since(t0);
    if (st != UMFPACK_OK) {
        symbolic_ = nullptr;
        if (st == UMFPACK_ERROR_out_of_memory)
            return fail(FRIX_ERR_OUT_OF_MEMORY, "sparse LU: out of memory in the symbolic analysis");
        return fail(FRIX_ERR_NUMERICAL, "sparse LU: symbolic analysis failed (%s)",
                    umfpack_message(st));
    }
    ++stats_.symbolic;
    symmetric_strategy_ = info[UMFPACK_STRATEGY_USED] == UMFPACK_STRATEGY_SYMMETRIC;
    A_ = A;
    flops_ = info[UMFPACK_FLOPS_ESTIMATE];
    flops_counted_ = false;
    if (flops_ > kCountedAbove) {
        if (lock.owns_lock()) lock.unlock();  // cholesky_cost takes it
        const auto t1 = Clock::now();
        const double counted = std::isfinite(known_count) ? known_count : symmetric_lu_flops(A);
        if (counted > 0.0 && counted < flops_) flops_ = counted, flops_counted_ = true;
        stats_.seconds += since(t1);
    }
    bytes_ = info[UMFPACK_PEAK_MEMORY_ESTIMATE] * info[UMFPACK_SIZE_OF_UNIT];
    last_seconds_ = NAN;
    return FRIX_OK;
}

frix_error SparseLU::factor(const CscView &A) {
    // The factorisation it replaces is freed first: the process holds that memory already.
    const double held = numeric_ ? numeric_bytes_ : 0.0;
    free_numeric();
    if (!symbolic_) return fail(FRIX_ERR_NUMERICAL, "sparse LU: factor() before analyze()");
    if (A.rows != A_.rows || A.nnz() != A_.nnz())
        return fail(FRIX_ERR_INTERNAL, "sparse LU: the pattern changed since the analysis");
    if (reanalyse_) {
        reanalyse_ = false;
        control_[UMFPACK_STRATEGY] = UMFPACK_STRATEGY_UNSYMMETRIC;
        if (frix_error e = analyze_counted(A, flops_)) return e;
    }
    refused_ = budget_ ? budget_(FactorPrice{flops_, last_seconds_, std::max(0.0, bytes_ - held), !flops_counted_})
                       : FRIX_STATUS_NOT_RUN;
    if (refused_)
        return fail(FRIX_ERR_NUMERICAL, "sparse LU: not started: it would overrun the %s limit",
                    refused_ == FRIX_STATUS_MEMORY_LIMIT ? "memory" : "time");
    const auto t0 = Clock::now();
    double info[UMFPACK_INFO];
    const SuiteSparse_long st = umfpack_dl_numeric(idx(A.colptr), idx(A.rowind), A.values,
                                                    symbolic_, &numeric_, control_.data(), info);
    last_seconds_ = since(t0);
    stats_.seconds += last_seconds_;
    ++stats_.numeric;
    A_ = A;
    rcond_ = info[UMFPACK_RCOND];
    flops_done_ = info[UMFPACK_FLOPS];
    if (info[UMFPACK_PEAK_MEMORY] > 0.0) bytes_ = info[UMFPACK_PEAK_MEMORY] * info[UMFPACK_SIZE_OF_UNIT];
    numeric_bytes_ = info[UMFPACK_NUMERIC_SIZE] > 0.0 ? info[UMFPACK_NUMERIC_SIZE] * info[UMFPACK_SIZE_OF_UNIT] : 0.0;
    if (st == UMFPACK_OK && rcond_ > 0.0) {
        reanalyse_ = strategy_by_pivoting_ && symmetric_strategy_ && flops_counted_ && flops_done_ > excess_ * flops_;
        return FRIX_OK;
    }
    free_numeric();
    if (st == UMFPACK_ERROR_out_of_memory)
        return fail(FRIX_ERR_OUT_OF_MEMORY, "sparse LU: out of memory in the factorisation");
    return fail(FRIX_ERR_NUMERICAL, "sparse LU: factorisation failed (%s)",
                st == UMFPACK_OK ? "singular matrix" : umfpack_message(st));
}

frix_error SparseLU::solve(const double *b, double *x, bool transposed) const {
    if (!numeric_) return fail(FRIX_ERR_NUMERICAL, "sparse LU: solve() without a factorisation");
    double info[UMFPACK_INFO];
    const SuiteSparse_long st =
        umfpack_dl_solve(transposed ? UMFPACK_At : UMFPACK_A, idx(A_.colptr), idx(A_.rowind),
                         A_.values, x, b, numeric_, control_.data(), info);
    if (st != UMFPACK_OK)
        return fail(FRIX_ERR_NUMERICAL, "sparse LU: solve failed (%s)", umfpack_message(st));
    return FRIX_OK;
}

}  // namespace frix::linalg
