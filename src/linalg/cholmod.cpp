// SparseCholesky on CHOLMOD (the SuiteSparse_long "l" interface), supernodal. The
// cholmod_common lives in the object: no state is shared between solves.
#include <cholmod.h>

#include <algorithm>
#include <chrono>
#include <mutex>
#include <vector>

#include "error_state.hpp"
#include "linalg.hpp"

namespace frix::linalg {

namespace {

using Clock = std::chrono::steady_clock;

// A non-owning cholmod_sparse header over a CscView (CHOLMOD only reads it).
cholmod_sparse view_of(const CscView &A, int stype) {
    cholmod_sparse s{};
    s.nrow = (size_t)A.rows;
    s.ncol = (size_t)A.cols;
    s.nzmax = (size_t)A.nnz();
    s.p = const_cast<int64_t *>(A.colptr);
    s.i = const_cast<int64_t *>(A.rowind);
    s.nz = nullptr;
    s.x = const_cast<double *>(A.values);
    s.z = nullptr;
    s.stype = stype;
    s.itype = CHOLMOD_LONG;
    s.xtype = CHOLMOD_REAL;
    s.dtype = CHOLMOD_DOUBLE;
    s.sorted = 1;
    s.packed = 1;
    return s;
}

// Columns [first, last) of A, as a view whose column pointers (kept in ptr) start at 0.
CscView column_block(const CscView &A, int64_t first, int64_t last, std::vector<int64_t> &ptr) {
    const int64_t base = A.colptr[first];
    ptr.resize((size_t)(last - first + 1));
    for (int64_t j = first; j <= last; ++j) ptr[(size_t)(j - first)] = A.colptr[j] - base;
    return {A.rows, last - first, ptr.data(), A.rowind + base, A.values + base};
}

// Appends the columns of the packed CHOLMOD matrix S to the CSC arrays (colptr holds at least
// its leading 0).
void append_columns(const cholmod_sparse &S, std::vector<int64_t> &colptr, std::vector<int64_t> &rowind,
                    std::vector<double> &values) {
    const int64_t *p = static_cast<const int64_t *>(S.p);
    const int64_t *i = static_cast<const int64_t *>(S.i);
    const double *x = static_cast<const double *>(S.x);
    const int64_t base = colptr.back(), nnz = p[S.ncol];
    rowind.insert(rowind.end(), i, i + nnz);
    values.insert(values.end(), x, x + nnz);
    for (size_t j = 1; j <= S.ncol; ++j) colptr.push_back(base + p[j]);
}

// The memory a numeric factorisation on analysis L will hold: its values (supernodal: the
// dense supernodes, padding included) and indices, and CHOLMOD's workspace of a few vectors.
double factor_bytes(const cholmod_factor &L, const cholmod_common &c) {
    const double n = (double)L.n;
    const double values = L.is_super ? (double)L.xsize : c.lnz;
    const double indices = L.is_super ? (double)L.ssize : c.lnz;
    return 8.0 * (values + indices) + 8.0 * 8.0 * n;
}

}  // namespace

struct SparseCholesky::Impl {
    cholmod_common c;
    cholmod_factor *L = nullptr;
    // The pattern L was analysed for: a matrix with the same one is factorised on that
    // analysis (CHOLMOD's ordering depends on the pattern alone).
    int64_t rows = -1;
    std::vector<int64_t> colptr, rowind;
    double flops = 0.0;  // of a numeric factorisation on that analysis
    double bytes = 0.0;  // of L's values and indices on that analysis
    bool numeric = false;  // L holds a numeric factorisation (not only the analysis)
    double last_seconds = NAN;  // of the last numeric factorisation on that analysis
    bool same_pattern(const CscView &A) const {
        return L && A.rows == rows && std::equal(colptr.begin(), colptr.end(), A.colptr) &&
               (int64_t)rowind.size() == A.nnz() && std::equal(rowind.begin(), rowind.end(), A.rowind);
    }
    Impl() {
        cholmod_l_start(&c);
        c.print = 0;  // the library never prints
        c.error_handler = nullptr;
        c.supernodal = CHOLMOD_SUPERNODAL;
        c.final_ll = 1;
    }
    ~Impl() {
        if (L) cholmod_l_free_factor(&L, &c);
        cholmod_l_finish(&c);
    }
    // Frees a CHOLMOD sparse result whatever happens.
    struct Sparse {
        cholmod_sparse *s = nullptr;
        cholmod_common *c = nullptr;
        ~Sparse() {
            if (s) cholmod_l_free_sparse(&s, c);
        }
    };
};

SparseCholesky::SparseCholesky() : impl_(std::make_unique<Impl>()) {}
SparseCholesky::~SparseCholesky() = default;

frix_error SparseCholesky::factor(const CscView &A) {
    Impl &m = *impl_;
    if (A.rows != A.cols || A.rows <= 0) {
        if (m.L) cholmod_l_free_factor(&m.L, &m.c);
        return fail(FRIX_ERR_DIMENSION, "sparse Cholesky: the matrix is %lld x %lld, not square",
                    (long long)A.rows, (long long)A.cols);
    }
    const auto t0 = Clock::now();
    cholmod_sparse a = view_of(A, 1);
    if (!m.same_pattern(A)) {
        if (m.L) cholmod_l_free_factor(&m.L, &m.c);
        {
            const std::lock_guard<std::mutex> lock(metis_mutex());  // may try METIS on large M
            m.L = cholmod_l_analyze(&a, &m.c);
        }
        if (m.L) {
            ++stats_.symbolic;
            m.rows = A.rows;
            m.colptr.assign(A.colptr, A.colptr + A.cols + 1);
            m.rowind.assign(A.rowind, A.rowind + A.nnz());
            m.flops = m.c.fl;
            m.bytes = factor_bytes(*m.L, m.c);
            m.last_seconds = NAN;
        }
    }
    // A factorisation on an analysis whose L already holds values refactorises in place: it
    // takes no memory the process does not hold already.
    const double bytes = m.L && m.L->xtype != CHOLMOD_PATTERN ? 0.0 : m.bytes;
    m.numeric = false;
    refused_ = m.L && budget_ ? budget_(FactorPrice{m.flops, m.last_seconds, bytes}) : FRIX_STATUS_NOT_RUN;
    if (refused_) {
        stats_.seconds += std::chrono::duration<double>(Clock::now() - t0).count();
        return fail(FRIX_ERR_NUMERICAL, "sparse Cholesky: not started: it would overrun the %s limit",
                    refused_ == FRIX_STATUS_MEMORY_LIMIT ? "memory" : "time");
    }
    const auto t1 = Clock::now();
    const bool ok = m.L && cholmod_l_factorize(&a, m.L, &m.c);
    m.numeric = ok && m.c.status == CHOLMOD_OK;
    m.last_seconds = std::chrono::duration<double>(Clock::now() - t1).count();
    stats_.seconds += std::chrono::duration<double>(Clock::now() - t0).count();
    if (m.L) ++stats_.numeric;
    if (!ok || m.c.status != CHOLMOD_OK) {
        const int status = m.c.status;
        if (m.L) cholmod_l_free_factor(&m.L, &m.c);
        if (status == CHOLMOD_OUT_OF_MEMORY)
            return fail(FRIX_ERR_OUT_OF_MEMORY, "sparse Cholesky: out of memory");
        if (status == CHOLMOD_NOT_POSDEF)
            return fail(FRIX_ERR_NUMERICAL, "sparse Cholesky: the matrix is not positive definite");
        return fail(FRIX_ERR_NUMERICAL, "sparse Cholesky: factorisation failed (CHOLMOD status %d)",
                    status);
    }
    return FRIX_OK;
}

frix_error cholesky_cost(const CscView &A, FactorCost *cost) {
    *cost = FactorCost{};
    if (A.rows != A.cols)
        return fail(FRIX_ERR_DIMENSION, "Cholesky cost: the matrix is %lld x %lld, not square", (long long)A.rows,
                    (long long)A.cols);
    if (A.rows == 0) return FRIX_OK;
    cholmod_common c;
    cholmod_l_start(&c);
    c.print = 0;
    c.error_handler = nullptr;
    // AMD alone and a simplicial analysis: the counts need no supernodes, and the price must
    // cost little next to what it prices.
    c.supernodal = CHOLMOD_SIMPLICIAL;
    c.nmethods = 1;
    c.method[0].ordering = CHOLMOD_AMD;
    c.postorder = 0;
    cholmod_sparse a = view_of(A, 1);
    a.xtype = CHOLMOD_PATTERN;
    a.x = nullptr;
    cholmod_factor *L = nullptr;
    {
        const std::lock_guard<std::mutex> lock(metis_mutex());
        L = cholmod_l_analyze(&a, &c);
    }
    const bool ok = L != nullptr && c.status == CHOLMOD_OK;
    if (ok) *cost = FactorCost{c.fl, c.lnz, factor_bytes(*L, c)};
    const int status = c.status;
    if (L) cholmod_l_free_factor(&L, &c);
    cholmod_l_finish(&c);
    if (ok) return FRIX_OK;
    if (status == CHOLMOD_OUT_OF_MEMORY) return fail(FRIX_ERR_OUT_OF_MEMORY, "Cholesky cost: out of memory");
    return fail(FRIX_ERR_NUMERICAL, "Cholesky cost: symbolic analysis failed (CHOLMOD status %d)", status);
}

frix_error SparseCholesky::solve(const double *b, double *x) const {
    Impl &m = *impl_;
    if (!m.L || !m.numeric) return fail(FRIX_ERR_NUMERICAL, "sparse Cholesky: solve() without a factorisation");
    const size_t n = m.L->n;
    cholmod_dense B{};
    B.nrow = n;
    B.ncol = 1;
    B.nzmax = n;
    B.d = n;
    B.x = const_cast<double *>(b);
    B.xtype = CHOLMOD_REAL;
    B.dtype = CHOLMOD_DOUBLE;
    cholmod_dense *X = cholmod_l_solve(CHOLMOD_A, m.L, &B, &m.c);
    if (!X) return fail(FRIX_ERR_NUMERICAL, "sparse Cholesky: solve failed (CHOLMOD status %d)", m.c.status);
    const double *xv = static_cast<const double *>(X->x);
    for (size_t i = 0; i < n; ++i) x[i] = xv[i];
    cholmod_l_free_dense(&X, &m.c);
    return FRIX_OK;
}

frix_error SparseCholesky::inverse_congruence(const CscView &B, std::vector<int64_t> &colptr,
                                              std::vector<int64_t> &rowind, std::vector<double> &values,
                                              const std::function<bool()> &stop, bool *stopped,
                                              int64_t block_cols) {
    colptr.assign(1, 0);
    rowind.clear();
    values.clear();
    const ColumnSink append = [&](int64_t count, const int64_t *rows, const double *vals) {
        rowind.insert(rowind.end(), rows, rows + count);
        values.insert(values.end(), vals, vals + count);
        colptr.push_back((int64_t)rowind.size());
        return FRIX_OK;
    };
    const frix_error e = inverse_congruence(B, append, stop, stopped, block_cols);
    if (e != FRIX_OK || (stopped && *stopped)) {
        colptr.clear();
        rowind.clear();
        values.clear();
    }
    return e;
}

frix_error SparseCholesky::inverse_congruence(const CscView &B, const ColumnSink &sink,
                                              const std::function<bool()> &stop, bool *stopped,
                                              int64_t block_cols) {
    Impl &m = *impl_;
    if (stopped) *stopped = false;
    if (!m.L || !m.numeric) return fail(FRIX_ERR_NUMERICAL, "sparse Cholesky: no factorisation");
    if ((size_t)B.rows != m.L->n)
        return fail(FRIX_ERR_DIMENSION, "sparse Cholesky: B has %lld rows, the factor %lld",
                    (long long)B.rows, (long long)m.L->n);
    // CHOLMOD's spsolve solves 4 columns at a time: blocks of a multiple of 4 group the
    // columns as one call would, which keeps C's bits.
    block_cols = block_cols <= 0 ? kCongruenceBlockColumns : (block_cols + 3) / 4 * 4;
    const auto t0 = Clock::now();
    const int64_t k = B.cols;
    auto failed = [&](const char *what) {
        stats_.seconds += std::chrono::duration<double>(Clock::now() - t0).count();
        if (m.c.status == CHOLMOD_OUT_OF_MEMORY)
            return fail(FRIX_ERR_OUT_OF_MEMORY, "sparse Cholesky: out of memory forming %s", what);
        return fail(FRIX_ERR_NUMERICAL, "sparse Cholesky: forming %s failed (CHOLMOD status %d)", what,
                    m.c.status);
    };
    auto interrupted = [&]() {
        if (!stop || !stop()) return false;
        stats_.seconds += std::chrono::duration<double>(Clock::now() - t0).count();
        if (stopped) *stopped = true;
        return true;
    };
    // Z = L^-1 P B, a block of columns at a time.
    std::vector<int64_t> zp{0}, zi, ptr;
    std::vector<double> zx;
    for (int64_t first = 0; first < k; first += block_cols) {
        const int64_t last = std::min(k, first + block_cols);
        cholmod_sparse b = view_of(column_block(B, first, last, ptr), 0);
        Impl::Sparse pb{cholmod_l_spsolve(CHOLMOD_P, m.L, &b, &m.c), &m.c};
        Impl::Sparse z{pb.s ? cholmod_l_spsolve(CHOLMOD_L, m.L, pb.s, &m.c) : nullptr, &m.c};
        if (!z.s) return failed("L^-1 P B");
        append_columns(*z.s, zp, zi, zx);
        if (interrupted()) return FRIX_OK;
    }
    const CscView Z{B.rows, k, zp.data(), zi.data(), zx.data()};
    cholmod_sparse z = view_of(Z, 0);
    Impl::Sparse zt{cholmod_l_transpose(&z, 1, &m.c), &m.c};
    if (!zt.s) return failed("Z^T");
    // C = Z^T Z, a block of its columns at a time. (C_ij sums Z_ri Z_rj over r in increasing
    // order, as CHOLMOD's ssmult goes down column j of Z: C_ji has the same bits.)
    for (int64_t first = 0; first < k; first += block_cols) {
        const int64_t last = std::min(k, first + block_cols);
        cholmod_sparse zj = view_of(column_block(Z, first, last, ptr), 0);
        Impl::Sparse c{cholmod_l_ssmult(zt.s, &zj, 0, 1, 1, &m.c), &m.c};
        if (!c.s) return failed("B^T A^-1 B");
        const int64_t *cp = static_cast<const int64_t *>(c.s->p), *ci = static_cast<const int64_t *>(c.s->i);
        const double *cx = static_cast<const double *>(c.s->x);
        for (size_t j = 0; j < c.s->ncol; ++j)
            if (frix_error e = sink(cp[j + 1] - cp[j], ci + cp[j], cx + cp[j])) {
                stats_.seconds += std::chrono::duration<double>(Clock::now() - t0).count();
                return e;
            }
        if (last < k && interrupted()) return FRIX_OK;
    }
    stats_.seconds += std::chrono::duration<double>(Clock::now() - t0).count();
    return FRIX_OK;
}

}  // namespace frix::linalg
