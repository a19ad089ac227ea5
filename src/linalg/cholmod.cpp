// SparseCholesky on CHOLMOD (the SuiteSparse_long "l" interface). The
// cholmod_common lives in the object: no state is shared between solves.
#include <cholmod.h>

#include <algorithm>
#include <chrono>
#include <mutex>
#include <vector>

#include "error_state.hpp"
#include "linalg.hpp"
#include "memory.hpp"
#include "ordering.hpp"

extern "C" {
void dtrsm_(const char *side, const char *uplo, const char *transa, const char *diag, const int *m, const int *n,
            const double *alpha, const double *a, const int *lda, double *b, const int *ldb, size_t, size_t, size_t,
            size_t);
void dgemm_(const char *transa, const char *transb, const int *m, const int *n, const int *k, const double *alpha,
            const double *a, const int *lda, const double *b, const int *ldb, const double *beta, double *c,
            const int *ldc, size_t, size_t);
}

// The OpenMP runtime CHOLMOD brings along, when it was built with one. Weak: a CHOLMOD
// without OpenMP leaves them null and needs nothing.
extern "C" {
int omp_get_max_active_levels(void) __attribute__((weak));
void omp_set_max_active_levels(int) __attribute__((weak));
}

namespace frix::linalg {

namespace {

using Clock = std::chrono::steady_clock;

// Flops per entry of L up to which a factor for solves is simplicial: below it the simplicial
// solves are faster (no BLAS call per supernode) and so is the factorisation (no OpenMP region
// per supernode and per update); on the 2D-like factors of thin elastic grids (100-120 flops
// per entry) both by 1.2-2x, on 3D bodies (350+) the supernodal one by 3-20x.
constexpr double kSimplicialFlopsPerEntry = 150.0;
// CHOLMOD's relaxed amalgamation for a factor for solves, refactorised as its values change
// (nrelax: supernodes of up to 16, 64 and 128 columns merge whatever zeros that adds, then up
// to zrelax's shares of zeros), four times its defaults: its supernodal factorisation opens an
// OpenMP region per supernode and per update, whose cost outweighs the flops of small
// supernodes (a refactorisation 2.6x faster on a thin grid). A first factorisation is bound by
// touching L's memory, which padding only adds to: the other layout keeps the defaults.
constexpr size_t kRelaxedColumns[3] = {16, 64, 128};

// CHOLMOD's supernodal factorisation asks OpenMP for a fixed 4 threads, whatever
// OMP_NUM_THREADS says, for loops that copy values into the supernodes; waking those threads
// costs more than the copies (its arithmetic is BLAS, threaded by the BLAS library). While
// it lives, this thread's OpenMP regions run on this thread alone. max-active-levels is a
// per-thread setting (libgomp from GCC 11 on): other threads are not touched.
class OpenMPRegionsOnThisThread {
public:
    OpenMPRegionsOnThisThread() {
        if (!omp_get_max_active_levels || !omp_set_max_active_levels) return;
        saved_ = omp_get_max_active_levels();
        omp_set_max_active_levels(0);
    }
    ~OpenMPRegionsOnThisThread() {
        if (saved_ >= 0) omp_set_max_active_levels(saved_);
    }
    OpenMPRegionsOnThisThread(const OpenMPRegionsOnThisThread &) = delete;
    OpenMPRegionsOnThisThread &operator=(const OpenMPRegionsOnThisThread &) = delete;

private:
    int saved_ = -1;
};

// Columns of C per term handed to a CongruenceSink: a tile of X^T X the size of a few
// megabytes, not the whole of it.
constexpr int64_t kTermColumns = 256;

// The flops of a supernode's share of B^T A^-1 B: for its nk columns, the triangular solve
// with its ncol x ncol diagonal block and the update of its nbelow rows below, then its
// term X^T X.
double supernode_flops(double nk, double ncol, double nbelow) {
    return nk * (ncol * ncol + 2.0 * nbelow * ncol) + nk * nk * ncol;
}

// The memory a numeric factorisation on analysis L will hold: its values (supernodal: the
// dense supernodes, padding included) and indices, and CHOLMOD's workspace of a few vectors.
double factor_bytes(const cholmod_factor &L, const cholmod_common &c) {
    const double n = (double)L.n;
    const double values = L.is_super ? (double)L.xsize : c.lnz;
    const double indices = L.is_super ? (double)L.ssize : c.lnz;
    return 8.0 * (values + indices) + 8.0 * 8.0 * n;
}

// The arrays of a supernodal L as CHOLMOD's "l" interface holds them.
SupernodalLayout layout_of(const cholmod_factor &L) {
    const auto ints = [](const void *p) { return static_cast<const int64_t *>(p); };
    return {(int64_t)L.n, (int64_t)L.nsuper, ints(L.super), ints(L.pi), ints(L.px), ints(L.s), ints(L.Perm),
            static_cast<const double *>(L.x), (int64_t)L.xsize};
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
    double entries = 0.0;  // of L on that analysis
    double bytes = 0.0;  // of L's values and indices on that analysis
    bool numeric = false;  // L holds a numeric factorisation (not only the analysis)
    double last_seconds = NAN;  // of the last numeric factorisation on that analysis
    std::vector<int64_t> given;  // set_ordering's, for the next analysis
    // cholmod_l_solve2's result and workspace, kept from one solve to the next: iterative
    // solvers solve once an iteration, and a fresh allocation each time costs page faults.
    cholmod_dense *X = nullptr, *Y = nullptr, *E = nullptr;
    SingleSupernodalFactor single;  // keep_single_copy's copy of L (empty: none)
    void drop_factor() {  // frees L and what was made from it
        if (L) cholmod_l_free_factor(&L, &c);
        numeric = false;
        single.clear();
    }
    bool same_pattern(const CscView &A) const {
        return L && A.rows == rows && std::equal(colptr.begin(), colptr.end(), A.colptr) &&
               (int64_t)rowind.size() == A.nnz() && std::equal(rowind.begin(), rowind.end(), A.rowind);
    }
    Impl() {
        cholmod_l_start(&c);
        c.print = 0;  // the library never prints
        c.error_handler = nullptr;
        c.final_ll = 1;
    }
    ~Impl() {
        cholmod_l_free_dense(&X, &c);
        cholmod_l_free_dense(&Y, &c);
        cholmod_l_free_dense(&E, &c);
        if (L) cholmod_l_free_factor(&L, &c);
        cholmod_l_finish(&c);
    }
};

SparseCholesky::SparseCholesky(Layout layout) : impl_(std::make_unique<Impl>()) {
    // kForSolves: simplicial where L has few flops per entry, supernodal elsewhere (CHOLMOD's
    // own rule, at a switch of kSimplicialFlopsPerEntry rather than its 40).
    impl_->c.supernodal = layout == Layout::kSupernodal ? CHOLMOD_SUPERNODAL : CHOLMOD_AUTO;
    impl_->c.supernodal_switch = kSimplicialFlopsPerEntry;
    if (layout == Layout::kForSolves)
        for (int k = 0; k < 3; ++k) impl_->c.nrelax[k] = kRelaxedColumns[k];
}
SparseCholesky::~SparseCholesky() = default;

// Fails where A is not square with rows, dropping the analysis held.
frix_error SparseCholesky::refuse_unless_square(const CscView &A) {
    Impl &m = *impl_;
    if (A.rows == A.cols && A.rows > 0) return FRIX_OK;
    m.drop_factor();
    return fail(FRIX_ERR_DIMENSION, "sparse Cholesky: the matrix is %lld x %lld, not square", (long long)A.rows,
                (long long)A.cols);
}

// Analyses A's pattern unless it is the one L holds; false where CHOLMOD fails (m.L null).
bool SparseCholesky::analyse_pattern(const CscView &A) {
    Impl &m = *impl_;
    if (m.same_pattern(A)) return true;
    m.drop_factor();
    cholmod_sparse a = view_of(A, 1);
    if ((int64_t)m.given.size() == A.rows) {
        const int nmethods = m.c.nmethods, ordering = m.c.method[0].ordering;
        m.c.nmethods = 1;
        m.c.method[0].ordering = CHOLMOD_GIVEN;
        m.L = cholmod_l_analyze_p(&a, m.given.data(), nullptr, 0, &m.c);
        m.c.nmethods = nmethods;
        m.c.method[0].ordering = ordering;
    } else {
        const std::lock_guard<std::mutex> lock(metis_mutex());  // may try METIS on large M
        m.L = analyze_symmetric(a, m.c);
    }
    if (!m.L) return false;
    ++stats_.symbolic;
    m.rows = A.rows;
    m.colptr.assign(A.colptr, A.colptr + A.cols + 1);
    m.rowind.assign(A.rowind, A.rowind + A.nnz());
    m.flops = m.c.fl;
    m.entries = m.c.lnz;
    m.bytes = factor_bytes(*m.L, m.c);
    m.last_seconds = NAN;
    return true;
}

frix_error SparseCholesky::analyze(const CscView &A, FactorCost *cost) {
    Impl &m = *impl_;
    *cost = FactorCost{};
    if (frix_error e = refuse_unless_square(A)) return e;
    const auto t0 = Clock::now();
    const bool ok = analyse_pattern(A);
    stats_.seconds += std::chrono::duration<double>(Clock::now() - t0).count();
    if (!ok) {
        if (m.c.status == CHOLMOD_OUT_OF_MEMORY) return fail(FRIX_ERR_OUT_OF_MEMORY, "sparse Cholesky: out of memory");
        return fail(FRIX_ERR_NUMERICAL, "sparse Cholesky: symbolic analysis failed (CHOLMOD status %d)", m.c.status);
    }
    *cost = FactorCost{m.flops, m.entries, m.bytes};
    return FRIX_OK;
}

FactorCost SparseCholesky::cost() const {
    const Impl &m = *impl_;
    return m.L ? FactorCost{m.flops, m.entries, m.bytes} : FactorCost{};
}

frix_error SparseCholesky::factor(const CscView &A) {
    Impl &m = *impl_;
    if (frix_error e = refuse_unless_square(A)) return e;
    const auto t0 = Clock::now();
    cholmod_sparse a = view_of(A, 1);
    analyse_pattern(A);
    // A factorisation on an analysis whose L already holds values refactorises in place: it
    // takes no memory the process does not hold already.
    const double bytes = m.L && m.L->xtype != CHOLMOD_PATTERN ? 0.0 : m.bytes;
    m.numeric = false;
    m.single.clear();
    refused_ = m.L && budget_ ? budget_(FactorPrice{m.flops, m.last_seconds, bytes}) : FRIX_STATUS_NOT_RUN;
    if (refused_) {
        stats_.seconds += std::chrono::duration<double>(Clock::now() - t0).count();
        return fail(FRIX_ERR_NUMERICAL, "sparse Cholesky: not started: it would overrun the %s limit",
                    refused_ == FRIX_STATUS_MEMORY_LIMIT ? "memory" : "time");
    }
    const auto t1 = Clock::now();
    bool ok = false;
    if (m.L) {
        const OpenMPRegionsOnThisThread serial;
        // L's values taken here rather than by the factorisation, so that they are advised
        // before their first touch (the same call CHOLMOD makes for a symbolic L).
        if (m.L->is_super && m.L->xtype == CHOLMOD_PATTERN &&
            cholmod_l_change_factor(CHOLMOD_REAL, true, true, true, true, m.L, &m.c))
            advise_huge_pages(m.L->x, m.L->xsize * sizeof(double));
        ok = cholmod_l_factorize(&a, m.L, &m.c);
    }
    m.numeric = ok && m.c.status == CHOLMOD_OK;
    m.last_seconds = std::chrono::duration<double>(Clock::now() - t1).count();
    stats_.seconds += std::chrono::duration<double>(Clock::now() - t0).count();
    if (m.L) ++stats_.numeric;
    if (!ok || m.c.status != CHOLMOD_OK) {
        const int status = m.c.status;
        m.drop_factor();
        if (status == CHOLMOD_OUT_OF_MEMORY)
            return fail(FRIX_ERR_OUT_OF_MEMORY, "sparse Cholesky: out of memory");
        if (status == CHOLMOD_NOT_POSDEF)
            return fail(FRIX_ERR_NUMERICAL, "sparse Cholesky: the matrix is not positive definite");
        return fail(FRIX_ERR_NUMERICAL, "sparse Cholesky: factorisation failed (CHOLMOD status %d)",
                    status);
    }
    return FRIX_OK;
}

frix_error cholesky_cost(const CscView &A, FactorCost *cost, Orderings orderings) {
    *cost = FactorCost{};
    if (A.rows != A.cols)
        return fail(FRIX_ERR_DIMENSION, "Cholesky cost: the matrix is %lld x %lld, not square", (long long)A.rows,
                    (long long)A.cols);
    if (A.rows == 0) return FRIX_OK;
    cholmod_common c;
    cholmod_l_start(&c);
    c.print = 0;
    c.error_handler = nullptr;
    // The ordering a factorisation would get (analyze_symmetric), so that the count is the
    // one it will do; a simplicial analysis: the counts need no supernodes.
    c.supernodal = CHOLMOD_SIMPLICIAL;
    c.postorder = 0;
    cholmod_sparse a = view_of(A, 1);
    a.xtype = CHOLMOD_PATTERN;
    a.x = nullptr;
    cholmod_factor *L = nullptr;
    {
        const std::lock_guard<std::mutex> lock(metis_mutex());
        L = analyze_symmetric(a, c, orderings);
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

bool SparseCholesky::supernodal() const { return impl_->L && impl_->L->is_super; }

std::vector<int64_t> SparseCholesky::ordering() const {
    const cholmod_factor *L = impl_->L;
    if (!L || !L->Perm) return {};
    const int64_t *perm = static_cast<const int64_t *>(L->Perm);
    return std::vector<int64_t>(perm, perm + L->n);
}

void SparseCholesky::set_ordering(std::vector<int64_t> perm) { impl_->given = std::move(perm); }

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
    if (!cholmod_l_solve2(CHOLMOD_A, m.L, &B, nullptr, &m.X, nullptr, &m.Y, &m.E, &m.c) || !m.X) {
        if (m.c.status == CHOLMOD_OUT_OF_MEMORY) return fail(FRIX_ERR_OUT_OF_MEMORY, "sparse Cholesky: solve: out of memory");
        return fail(FRIX_ERR_NUMERICAL, "sparse Cholesky: solve failed (CHOLMOD status %d)", m.c.status);
    }
    const double *xv = static_cast<const double *>(m.X->x);
    std::copy(xv, xv + n, x);
    return FRIX_OK;
}

bool SparseCholesky::keep_single_copy(const FactorBudget &budget) {
    Impl &m = *impl_;
    if (!m.L || !m.numeric || !m.L->is_super || m.L->xtype == CHOLMOD_PATTERN) return false;
    return m.single.holds() || m.single.copy(layout_of(*m.L), budget);
}

bool SparseCholesky::has_single_copy() const { return impl_->single.holds(); }
void SparseCholesky::drop_single_copy() { impl_->single.clear(); }

frix_error SparseCholesky::solve_with_single_copy(const double *b, double *x) const {
    const Impl &m = *impl_;
    if (!m.L || !m.numeric || !m.single.holds()) return fail(FRIX_ERR_NUMERICAL, "sparse Cholesky: no single copy");
    m.single.solve(layout_of(*m.L), b, x);
    return FRIX_OK;
}

namespace {

// C as CSC: the pattern from the groups, the terms added where their entries fall.
class CscCongruence : public CongruenceSink {
   public:
    CscCongruence(int64_t k, std::vector<int64_t> &colptr, std::vector<int64_t> &rowind, std::vector<double> &values)
        : k_(k), colptr_(colptr), rowind_(rowind), values_(values) {}
    frix_error pattern(const std::vector<std::vector<int64_t>> &groups) override {
        std::vector<std::vector<int64_t>> rows((size_t)k_);
        for (const auto &g : groups)
            for (int64_t j : g) rows[(size_t)j].insert(rows[(size_t)j].end(), g.begin(), g.end());
        colptr_.assign(1, 0);
        rowind_.clear();
        for (auto &r : rows) {
            std::sort(r.begin(), r.end());
            r.erase(std::unique(r.begin(), r.end()), r.end());
            rowind_.insert(rowind_.end(), r.begin(), r.end());
            colptr_.push_back((int64_t)rowind_.size());
        }
        values_.assign(rowind_.size(), 0.0);
        return FRIX_OK;
    }
    frix_error add(int64_t count, const int64_t *cols, int64_t width, const double *T, int64_t ld) override {
        for (int64_t b = 0; b < width; ++b)
            for (int64_t a = b; a < count; ++a) {
                const double t = T[a + ld * b];
                at(cols[a], cols[b]) += t;
                if (a != b) at(cols[b], cols[a]) += t;
            }
        return FRIX_OK;
    }

   private:
    double &at(int64_t i, int64_t j) {
        const auto first = rowind_.begin() + colptr_[(size_t)j], last = rowind_.begin() + colptr_[(size_t)j + 1];
        return values_[(size_t)(std::lower_bound(first, last, i) - rowind_.begin())];
    }
    int64_t k_;
    std::vector<int64_t> &colptr_, &rowind_;
    std::vector<double> &values_;
};

}  // namespace

namespace {

// What forming B^T A^-1 B on a supernodal factor L involves, from L's and B's patterns
// alone (see SparseCholesky::inverse_congruence): L's supernodal tree, B's entries by
// supernode, and the columns of B reaching each supernode, with the flops of their work.
struct CongruencePlan {
    struct Entry {
        int64_t col, row;  // B's column; the row of P B
        double value;
    };
    int64_t n, k, nsuper;
    const int64_t *super, *pi, *px, *Ls;
    std::vector<int64_t> col_super, parent, child_ptr, children, own_ptr;
    std::vector<Entry> own;
    std::vector<std::vector<int64_t>> cols;  // per supernode, increasing
    double flops = 0.0;
    // The entries of the terms handed to the sink: the lower part of each supernode's X^T X.
    double summed = 0.0;
    // The most entries held at once besides C: a supernode's dense block and term tile, with
    // the updates its children and the supernodes still waiting for their parent hand on.
    double workspace = 0.0;

    int64_t nscol(int64_t s) const { return super[s + 1] - super[s]; }
    int64_t nsrow(int64_t s) const { return pi[s + 1] - pi[s]; }
    // C's pattern: the columns reaching each root (a root's columns are all its subtree's).
    std::vector<std::vector<int64_t>> groups() const {
        std::vector<std::vector<int64_t>> g;
        for (int64_t s = 0; s < nsuper; ++s)
            if (parent[(size_t)s] < 0 && !cols[(size_t)s].empty()) g.push_back(cols[(size_t)s]);
        return g;
    }

    CongruencePlan(const cholmod_factor &L, const CscView &B)
        : n((int64_t)L.n), k(B.cols), nsuper((int64_t)L.nsuper), super(static_cast<const int64_t *>(L.super)),
          pi(static_cast<const int64_t *>(L.pi)), px(static_cast<const int64_t *>(L.px)),
          Ls(static_cast<const int64_t *>(L.s)) {
        const int64_t *perm = static_cast<const int64_t *>(L.Perm);
        // The tree: each supernode's parent (the one holding its first row below), children
        // before parents in the numbering.
        col_super.resize((size_t)n);
        parent.assign((size_t)nsuper, -1);
        for (int64_t s = 0; s < nsuper; ++s)
            for (int64_t c = super[s]; c < super[s + 1]; ++c) col_super[(size_t)c] = s;
        for (int64_t s = 0; s < nsuper; ++s)
            if (nsrow(s) > nscol(s)) parent[(size_t)s] = col_super[(size_t)Ls[pi[s] + nscol(s)]];
        child_ptr.assign((size_t)nsuper + 1, 0);
        children.resize((size_t)nsuper);
        for (int64_t s = 0; s < nsuper; ++s)
            if (parent[(size_t)s] >= 0) ++child_ptr[(size_t)parent[(size_t)s] + 1];
        for (int64_t s = 0; s < nsuper; ++s) child_ptr[(size_t)s + 1] += child_ptr[(size_t)s];
        {
            std::vector<int64_t> next(child_ptr.begin(), child_ptr.end() - 1);
            for (int64_t s = 0; s < nsuper; ++s)
                if (parent[(size_t)s] >= 0) children[(size_t)next[(size_t)parent[(size_t)s]]++] = s;
        }
        // B's non-zero entries, as rows of P B, by supernode (and by column within one).
        std::vector<int64_t> inverse((size_t)n);
        for (int64_t i = 0; i < n; ++i) inverse[(size_t)(perm ? perm[i] : i)] = i;
        own_ptr.assign((size_t)nsuper + 1, 0);
        for (int64_t j = 0; j < k; ++j)
            for (int64_t e = B.colptr[j]; e < B.colptr[j + 1]; ++e)
                if (B.values[e] != 0.0) ++own_ptr[(size_t)col_super[(size_t)inverse[(size_t)B.rowind[e]]] + 1];
        for (int64_t s = 0; s < nsuper; ++s) own_ptr[(size_t)s + 1] += own_ptr[(size_t)s];
        own.resize((size_t)own_ptr[(size_t)nsuper]);
        {
            std::vector<int64_t> next(own_ptr.begin(), own_ptr.end() - 1);
            for (int64_t j = 0; j < k; ++j)
                for (int64_t e = B.colptr[j]; e < B.colptr[j + 1]; ++e)
                    if (B.values[e] != 0.0) {
                        const int64_t row = inverse[(size_t)B.rowind[e]];
                        own[(size_t)next[(size_t)col_super[(size_t)row]]++] = {j, row, B.values[e]};
                    }
        }
        // Per supernode s, the columns reaching it: its own and its children's.
        cols.resize((size_t)nsuper);
        std::vector<int64_t> mark((size_t)k, -1);
        double pending = 0.0;  // the updates handed on and not yet taken
        for (int64_t s = 0; s < nsuper; ++s) {
            std::vector<int64_t> &K = cols[(size_t)s];
            for (int64_t e = own_ptr[(size_t)s]; e < own_ptr[(size_t)s + 1]; ++e)
                if (mark[(size_t)own[(size_t)e].col] != s) mark[(size_t)own[(size_t)e].col] = s, K.push_back(own[(size_t)e].col);
            for (int64_t c = child_ptr[(size_t)s]; c < child_ptr[(size_t)s + 1]; ++c)
                for (int64_t j : cols[(size_t)children[(size_t)c]])
                    if (mark[(size_t)j] != s) mark[(size_t)j] = s, K.push_back(j);
            std::sort(K.begin(), K.end());
            const double nk = (double)K.size(), nbelow = (double)(nsrow(s) - nscol(s));
            flops += supernode_flops(nk, (double)nscol(s), nbelow);
            summed += nk * (nk + 1.0) / 2.0;
            workspace = std::max(workspace, pending + nk * ((double)nsrow(s) + (double)kTermColumns));
            for (int64_t c = child_ptr[(size_t)s]; c < child_ptr[(size_t)s + 1]; ++c) {
                const int64_t ch = children[(size_t)c];
                pending -= (double)cols[(size_t)ch].size() * (double)(nsrow(ch) - nscol(ch));
            }
            pending += nk * nbelow;
        }
    }
};

}  // namespace

frix_error SparseCholesky::congruence_cost(const CscView &B, CongruenceCost *cost) const {
    Impl &m = *impl_;
    *cost = CongruenceCost{};
    // L's supernodal pattern alone: the analysis is enough.
    if (!m.L) return fail(FRIX_ERR_NUMERICAL, "sparse Cholesky: no analysis");
    if ((size_t)B.rows != m.L->n)
        return fail(FRIX_ERR_DIMENSION, "sparse Cholesky: B has %lld rows, the factor %lld", (long long)B.rows,
                    (long long)m.L->n);
    if (!m.L->is_super) return fail(FRIX_ERR_NUMERICAL, "sparse Cholesky: B^T A^-1 B needs a supernodal factor");
    const CongruencePlan plan(*m.L, B);
    *cost = CongruenceCost{plan.flops, 8.0 * plan.workspace, plan.groups(), plan.summed};
    return FRIX_OK;
}

frix_error SparseCholesky::inverse_congruence(const CscView &B, std::vector<int64_t> &colptr,
                                              std::vector<int64_t> &rowind, std::vector<double> &values,
                                              const std::function<bool()> &stop, bool *stopped, double questions,
                                              double min_flops_per_question) {
    CscCongruence sink(B.cols, colptr, rowind, values);
    bool was_stopped = false;
    const frix_error e = inverse_congruence(B, sink, stop, &was_stopped, questions, min_flops_per_question);
    if (stopped) *stopped = was_stopped;
    if (e != FRIX_OK || was_stopped) {
        colptr.clear();
        rowind.clear();
        values.clear();
    }
    return e;
}

frix_error SparseCholesky::inverse_congruence(const CscView &B, CongruenceSink &sink,
                                              const std::function<bool()> &stop, bool *stopped, double questions,
                                              double min_flops_per_question) {
    Impl &m = *impl_;
    if (stopped) *stopped = false;
    if (!m.L || !m.numeric) return fail(FRIX_ERR_NUMERICAL, "sparse Cholesky: no factorisation");
    const cholmod_factor &L = *m.L;
    if ((size_t)B.rows != L.n)
        return fail(FRIX_ERR_DIMENSION, "sparse Cholesky: B has %lld rows, the factor %lld", (long long)B.rows,
                    (long long)L.n);
    if (!L.is_super || !L.is_ll)
        return fail(FRIX_ERR_NUMERICAL, "sparse Cholesky: B^T A^-1 B needs a supernodal L L^T factor");
    CongruencePlan plan(L, B);
    const int64_t n = plan.n, k = plan.k, nsuper = plan.nsuper;
    const int64_t *super = plan.super, *pi = plan.pi, *px = plan.px, *Ls = plan.Ls;
    const double *Lx = static_cast<const double *>(L.x);
    const std::vector<int64_t> &child_ptr = plan.child_ptr, &children = plan.children, &own_ptr = plan.own_ptr;
    std::vector<std::vector<int64_t>> &cols = plan.cols;
    using Entry = CongruencePlan::Entry;
    if (frix_error e = sink.pattern(plan.groups())) return e;
    const double pace = std::max(plan.flops / questions, min_flops_per_question);
    // Up the tree: per supernode, the dense block F of its rows of Z (the first nscol rows,
    // then the update of the rows below, kept in below[s] for the parent).
    std::vector<std::vector<double>> below((size_t)nsuper);
    std::vector<int64_t> position((size_t)k), local_row((size_t)n);
    std::vector<double> F, T;
    double flops = 0.0;
    for (int64_t s = 0; s < nsuper; ++s) {
        const std::vector<int64_t> &K = cols[(size_t)s];
        if (K.empty()) continue;
        const int64_t nk = (int64_t)K.size(), ncol = plan.nscol(s), nrow = plan.nsrow(s), nbelow = nrow - ncol;
        for (int64_t a = 0; a < nk; ++a) position[(size_t)K[(size_t)a]] = a;
        for (int64_t r = 0; r < nrow; ++r) local_row[(size_t)Ls[pi[s] + r]] = r;
        assign_advised(F, (size_t)(nrow * nk), 0.0);
        for (int64_t e = own_ptr[(size_t)s]; e < own_ptr[(size_t)s + 1]; ++e) {
            const Entry &x = plan.own[(size_t)e];
            F[(size_t)((x.row - super[s]) + nrow * position[(size_t)x.col])] += x.value;
        }
        // The children's updates, added where their rows and columns fall in F.
        for (int64_t c = child_ptr[(size_t)s]; c < child_ptr[(size_t)s + 1]; ++c) {
            const int64_t ch = children[(size_t)c];
            const std::vector<int64_t> &Kc = cols[(size_t)ch];
            if (Kc.empty()) continue;
            const int64_t first = pi[ch] + plan.nscol(ch), cb = plan.nsrow(ch) - plan.nscol(ch);
            const std::vector<double> &U = below[(size_t)ch];
            for (size_t jj = 0; jj < Kc.size(); ++jj) {
                double *f = &F[(size_t)(nrow * position[(size_t)Kc[jj]])];
                const double *u = &U[(size_t)cb * jj];
                for (int64_t t = 0; t < cb; ++t) f[local_row[(size_t)Ls[first + t]]] += u[t];
            }
            std::vector<int64_t>().swap(cols[(size_t)ch]);
            std::vector<double>().swap(below[(size_t)ch]);
        }
        // X = L_ss^-1 F(0:ncol, :); F(ncol:, :) -= L_below X.
        const double *Ld = Lx + px[s];
        {
            const int m_ = (int)ncol, n_ = (int)nk, ld = (int)nrow;
            const double one = 1.0;
            dtrsm_("L", "L", "N", "N", &m_, &n_, &one, Ld, &ld, F.data(), &ld, 1, 1, 1, 1);
        }
        if (nbelow > 0) {
            const int m_ = (int)nbelow, n_ = (int)nk, kk = (int)ncol, ld = (int)nrow;
            const double minus = -1.0, one = 1.0;
            dgemm_("N", "N", &m_, &n_, &kk, &minus, Ld + ncol, &ld, F.data(), &ld, &one, F.data() + ncol, &ld, 1, 1);
            std::vector<double> &U = below[(size_t)s];
            assign_advised(U, (size_t)(nbelow * nk));
            for (int64_t j = 0; j < nk; ++j)
                std::copy(&F[(size_t)(ncol + nrow * j)], &F[(size_t)(nrow + nrow * j)], &U[(size_t)(nbelow * j)]);
        }
        // C += X^T X, by tiles of columns: the lower part of each, from its diagonal down.
        for (int64_t b0 = 0; b0 < nk; b0 += kTermColumns) {
            const int64_t width = std::min(kTermColumns, nk - b0), count = nk - b0;
            T.resize((size_t)(count * width));
            const int m_ = (int)count, n_ = (int)width, kk = (int)ncol, ld = (int)nrow, ldt = (int)count;
            const double one = 1.0, zero = 0.0;
            dgemm_("T", "N", &m_, &n_, &kk, &one, F.data() + nrow * b0, &ld, F.data() + nrow * b0, &ld, &zero,
                   T.data(), &ldt, 1, 1);
            if (frix_error e = sink.add(count, K.data() + b0, width, T.data(), count)) return e;
        }
        flops += supernode_flops((double)nk, (double)ncol, (double)nbelow);
        if (stop && flops >= pace && s + 1 < nsuper) {
            flops = 0.0;
            if (stop()) {
                if (stopped) *stopped = true;
                return FRIX_OK;
            }
        }
    }
    return FRIX_OK;
}

}  // namespace frix::linalg
