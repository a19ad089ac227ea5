// SparseCholesky on CHOLMOD (the SuiteSparse_long "l" interface), supernodal. The
// cholmod_common lives in the object: no state is shared between solves.
#include <cholmod.h>

#include <chrono>

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

}  // namespace

struct SparseCholesky::Impl {
    cholmod_common c;
    cholmod_factor *L = nullptr;
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
    if (m.L) cholmod_l_free_factor(&m.L, &m.c);
    if (A.rows != A.cols || A.rows <= 0)
        return fail(FRIX_ERR_DIMENSION, "sparse Cholesky: the matrix is %lld x %lld, not square",
                    (long long)A.rows, (long long)A.cols);
    const auto t0 = Clock::now();
    cholmod_sparse a = view_of(A, 1);
    m.L = cholmod_l_analyze(&a, &m.c);
    if (m.L) ++stats_.symbolic;
    const bool ok = m.L && cholmod_l_factorize(&a, m.L, &m.c);
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

frix_error SparseCholesky::solve(const double *b, double *x) const {
    Impl &m = *impl_;
    if (!m.L) return fail(FRIX_ERR_NUMERICAL, "sparse Cholesky: solve() without a factorisation");
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
                                              std::vector<int64_t> &rowind,
                                              std::vector<double> &values) {
    Impl &m = *impl_;
    if (!m.L) return fail(FRIX_ERR_NUMERICAL, "sparse Cholesky: no factorisation");
    if ((size_t)B.rows != m.L->n)
        return fail(FRIX_ERR_DIMENSION, "sparse Cholesky: B has %lld rows, the factor %lld",
                    (long long)B.rows, (long long)m.L->n);
    const auto t0 = Clock::now();
    cholmod_sparse b = view_of(B, 0);
    Impl::Sparse pb{cholmod_l_spsolve(CHOLMOD_P, m.L, &b, &m.c), &m.c};
    Impl::Sparse z{pb.s ? cholmod_l_spsolve(CHOLMOD_L, m.L, pb.s, &m.c) : nullptr, &m.c};
    Impl::Sparse zt{z.s ? cholmod_l_transpose(z.s, 1, &m.c) : nullptr, &m.c};
    Impl::Sparse w{zt.s ? cholmod_l_ssmult(zt.s, z.s, 0, 1, 1, &m.c) : nullptr, &m.c};
    stats_.seconds += std::chrono::duration<double>(Clock::now() - t0).count();
    if (!w.s) {
        if (m.c.status == CHOLMOD_OUT_OF_MEMORY)
            return fail(FRIX_ERR_OUT_OF_MEMORY, "sparse Cholesky: out of memory forming B^T A^-1 B");
        return fail(FRIX_ERR_NUMERICAL, "sparse Cholesky: B^T A^-1 B failed (CHOLMOD status %d)",
                    m.c.status);
    }
    const int64_t k = (int64_t)w.s->ncol;
    const int64_t *p = static_cast<const int64_t *>(w.s->p);
    const int64_t *i = static_cast<const int64_t *>(w.s->i);
    const double *x = static_cast<const double *>(w.s->x);
    colptr.assign(p, p + k + 1);
    rowind.assign(i, i + p[k]);
    values.assign(x, x + p[k]);
    return FRIX_OK;
}

}  // namespace frix::linalg
