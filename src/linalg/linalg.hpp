// The one internal interface for linear solves: sparse LU (UMFPACK), sparse Cholesky
// (CHOLMOD, supernodal or simplicial) and dense LU / Cholesky (LAPACK). Every factorisation
// lives in its own object (no global state), every failure comes back as a frix_error with a
// message (frix::fail), never as a crash or a print.
//
// Sparse matrices here are plain CSC views (column pointers, sorted row indices, values) over
// arrays the caller owns and keeps alive while the object uses them.
#pragma once

#include <frix/frix_errors.h>

#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <utility>
#include <vector>

namespace frix::linalg {

// Held around every call that may run METIS (UMFPACK's METIS ordering, cholmod_analyze).
std::mutex &metis_mutex();

struct CscView {
    int64_t rows = 0, cols = 0;
    const int64_t *colptr = nullptr;  // cols + 1
    const int64_t *rowind = nullptr;  // colptr[cols], sorted within each column
    const double *values = nullptr;   // colptr[cols]
    int64_t nnz() const { return cols > 0 ? colptr[cols] : 0; }
};

// Counters every factorising solver reports in its frix_info.
struct FactorStats {
    int64_t symbolic = 0;      // symbolic analyses (orderings) done
    int64_t numeric = 0;       // numeric factorisations done
    double seconds = 0.0;      // time in analysis + factorisation (not in solves)
};

// The work counted between two readings of the same counters (a kept factorisation object
// counts over all the solves it served; a solve reports its own part).
inline FactorStats operator-(const FactorStats &now, const FactorStats &before) {
    return {now.symbolic - before.symbolic, now.numeric - before.numeric, now.seconds - before.seconds};
}
inline FactorStats operator+(const FactorStats &a, const FactorStats &b) {
    return {a.symbolic + b.symbolic, a.numeric + b.numeric, a.seconds + b.seconds};
}

// What a numeric factorisation will cost, known before it starts: the flop count and peak
// memory of its symbolic analysis, and the seconds the last numeric factorisation on the
// same analysis took (NaN before the first). The analyses' counts are upper bounds that can
// be loose by orders of magnitude; a measured time is not. bytes is what it adds to the
// process: a repeat on the same analysis adds less (UMFPACK: its last measured peak less the
// factorisation it replaces; CHOLMOD: nothing, it refactorises in place).
struct FactorPrice {
    double flops = 0.0;
    double seconds = NAN;
    double bytes = 0.0;
    // UMFPACK's estimate (an upper bound) of a small LU; not CHOLMOD's count (exact), nor the
    // count of a large LU's symmetrised pattern (SparseLU).
    bool flops_upper_bound = false;
    // Entries written outside the BLAS, priced at the machine's rate of such writes (forming
    // W: its blocks' entries, first touched, and the terms summed into them). Where the flops
    // run on small blocks these cost more than the flops.
    double writes = 0.0;
};
// Asked before each numeric factorisation: FRIX_STATUS_NOT_RUN lets it start; any other status
// (FRIX_STATUS_TIME_LIMIT, FRIX_STATUS_MEMORY_LIMIT: a caller's limit it would overrun) refuses
// it, and the factorisation then fails with refused() giving that status, having done no
// numeric work.
using FactorBudget = std::function<frix_status(const FactorPrice &price)>;

// Sparse LU of a square matrix with UMFPACK. The symbolic analysis (ordering, strategy) is
// kept and reused by every factor() while the sparsity pattern is the one of the last
// analyze(): Newton-type solvers assemble their Jacobian in a fixed pattern (explicit zeros
// kept), so they analyse once per solve and factor once per iteration.
class SparseLU {
   public:
    SparseLU();
    ~SparseLU();
    SparseLU(const SparseLU &) = delete;
    SparseLU &operator=(const SparseLU &) = delete;

    // Symbolic analysis of A's pattern (values are used only as hints). Discards any
    // previous analysis and factorisation.
    frix_error analyze(const CscView &A);
    // Numeric factorisation of A, which must have the pattern given to analyze() (same
    // pointers or same content). FRIX_ERR_NUMERICAL if A is singular (the factorisation is
    // then unusable) or if no analysis was done.
    frix_error factor(const CscView &A);
    // x = A^-1 b (or A^-T b) with the last factorisation; x and b may not alias.
    frix_error solve(const double *b, double *x, bool transposed = false) const;

    // The fill-reducing ordering of the next analyze(): AMD (the default; the least fill on
    // the clustered patterns of a local W) or METIS's nested dissection (far less on
    // mesh-like patterns, such as the (v, r) Jacobian of an FEM body).
    enum class Ordering { kAmd, kNestedDissection };
    void set_ordering(Ordering ordering);
    // Where UMFPACK analysed A for its symmetric strategy (pivots on the diagonal, chosen where
    // the first A's diagonal is nonzero) and a factorisation then pivoted off the diagonal
    // enough to do `excess` times the symmetric count, the next factor() analyses A again for
    // the unsymmetric strategy (once). Newton's (v, r) Jacobians start with every contact open
    // (diagonal 1) and gain zero diagonals as contacts stick: on large soft bodies the
    // symmetric strategy then does 1.65-2.8 times the count, the unsymmetric one 1.5-1.7.
    static constexpr double kOffDiagonalExcess = 1.5;
    void set_strategy_by_pivoting(bool on, double excess = kOffDiagonalExcess) {
        strategy_by_pivoting_ = on;
        excess_ = excess;
    }

    // min |U_ii| / max |U_ii| of the last factorisation (UMFPACK's cheap estimate).
    double rcond() const { return rcond_; }
    // The flops the last numeric factorisation did (UMFPACK's count): what its price foretold.
    double flops_done() const { return flops_done_; }
    bool factored() const { return numeric_ != nullptr; }
    const FactorStats &stats() const { return stats_; }
    // Every factor() first asks the budget (none: always factorise).
    void set_budget(FactorBudget budget) { budget_ = std::move(budget); }
    // Why the budget refused the last factor(): FRIX_STATUS_NOT_RUN if it did not.
    frix_status refused() const { return refused_; }

   private:
    // analyze(), taking known_count (where finite) for the symmetric count of A's pattern: it
    // depends on the pattern alone, and the strategy's second analysis of it knows it already.
    frix_error analyze_counted(const CscView &A, double known_count);
    void free_numeric();
    void free_symbolic();
    CscView A_;
    void *symbolic_ = nullptr;
    void *numeric_ = nullptr;
    double rcond_ = 0.0;
    double flops_done_ = 0.0;
    // Of a numeric factorisation: UMFPACK's estimate from the analysis (an upper bound), or
    // where that is large the count of the symmetrised pattern (flops_counted_).
    double flops_ = 0.0;
    bool flops_counted_ = false;
    double last_seconds_ = NAN;  // of the last numeric factorisation on this analysis
    double bytes_ = 0.0;  // peak memory of a numeric factorisation: estimated, then the last one's
    double numeric_bytes_ = 0.0;  // the size of the last numeric factorisation
    FactorBudget budget_;
    frix_status refused_ = FRIX_STATUS_NOT_RUN;
    FactorStats stats_;
    std::vector<double> control_;
    bool strategy_by_pivoting_ = false, symmetric_strategy_ = false, reanalyse_ = false;
    double excess_ = kOffDiagonalExcess;
};

// Columns of B per block of the work that forming B^T A^-1 B by LU does between two
// questions to its caller: 128 contacts.
constexpr int64_t kCongruenceBlockColumns = 384;

// Forming B^T A^-1 B by Cholesky asks its caller whether to stop about this many times
// over its work (see SparseCholesky::inverse_congruence), and not after less than a
// millisecond or so of dense work.
constexpr double kCongruenceQuestions = 32, kCongruenceMinFlopsPerQuestion = 2e7;

// Receives C = B^T A^-1 B (k x k, symmetric) as SparseCholesky::inverse_congruence forms it:
// first its pattern, then a sum of dense symmetric terms. The receiver stores C as it needs
// (a dense C is large: no other copy is made).
class CongruenceSink {
   public:
    virtual ~CongruenceSink() = default;
    // Once, first: groups of B's columns, each sorted; C_ij can be non-zero only where
    // columns i and j share a group (a column may be in several, or in none: C_jj = 0).
    virtual frix_error pattern(const std::vector<std::vector<int64_t>> &groups) = 0;
    // Then any number of times: C(cols[a], cols[b]) += T[a + ld * b] and, for a > b, the same
    // to C(cols[b], cols[a]), for b < width and b <= a < count; cols is increasing and T's
    // entries above its diagonal (a < b) are not read. Every entry of C gets its terms in the
    // same order as its mirror: C is symmetric to the last bit.
    virtual frix_error add(int64_t count, const int64_t *cols, int64_t width, const double *T, int64_t ld) = 0;
};

// What a Cholesky factorisation of a symmetric matrix costs, from its symbolic analysis alone
// (cholesky_cost, SparseCholesky::analyze).
struct FactorCost {
    double flops = 0.0;           // of the numeric factorisation
    double factor_entries = 0.0;  // entries of L (each solve reads them twice)
    double bytes = 0.0;           // L's values and indices, and the workspace
};

// The arrays of a supernodal Cholesky factor L L^T = P A P^T as CHOLMOD holds it: supernode
// s has columns super[s] .. super[s + 1] - 1 and the rows rows[pi[s] .. pi[s + 1]) (its own
// columns first), its values column-major at values + px[s]; row k of L is row perm[k] of A.
struct SupernodalLayout {
    int64_t n = 0, nsuper = 0;
    const int64_t *super = nullptr, *pi = nullptr, *px = nullptr, *rows = nullptr, *perm = nullptr;
    const double *values = nullptr;
    int64_t value_count = 0;
};

// A single-precision copy of a supernodal factor's values, and solves with it: they read half
// the bytes of solves in double, which reading L bounds. The copy holds L times a power of two
// and each solve scales its right-hand side by another, so that neither leaves float's range.
// Not reentrant: a solve writes the copy's workspace.
class SingleSupernodalFactor {
   public:
    // Copies L's values, asking `budget` (when given) for the copy's bytes first; false (no
    // copy) where it refuses, or where L's values do not fit single precision at one scale
    // (a value not finite, a diagonal entry that rounds below float's normal range).
    bool copy(const SupernodalLayout &L, const FactorBudget &budget);
    bool holds() const { return !values_.empty(); }
    void clear();
    // x = A^-1 b for a finite b with the copy (L: the layout it was copied from); x may come
    // back not finite where the solve overflows single precision: the caller checks it.
    void solve(const SupernodalLayout &L, const double *b, double *x) const;

   private:
    std::vector<float> values_;        // L's values times 2^exponent_
    int exponent_ = 0;
    mutable std::vector<float> work_;  // the permuted vector and a supernode's rows below
};

class SparseCholesky {
   public:
    // kSupernodal: L is always supernodal (inverse_congruence needs it). kForSolves: simplicial
    // where L is sparse, whose solves then run without a BLAS call per supernode (several
    // times faster on the small factors of iterative solvers), supernodal elsewhere.
    enum class Layout { kSupernodal, kForSolves };
    explicit SparseCholesky(Layout layout = Layout::kSupernodal);
    ~SparseCholesky();
    SparseCholesky(const SparseCholesky &) = delete;
    SparseCholesky &operator=(const SparseCholesky &) = delete;

    // Analyses A's pattern (unless it is the one of the last successful factorisation: the
    // ordering depends on the pattern alone) and factorises.
    frix_error factor(const CscView &A);
    // The analysis alone, as factor() would run it (same rule for a pattern analysed last):
    // the next factor() of a matrix with A's pattern starts from it. *cost: what that
    // factorisation will cost, counted as cholesky_cost counts it (bytes: of this layout).
    frix_error analyze(const CscView &A, FactorCost *cost);
    // What a factorisation on the analysis held costs (zero: none held).
    FactorCost cost() const;
    // x = A^-1 b for one dense right-hand side.
    frix_error solve(const double *b, double *x) const;
    // Keeps a single-precision copy of the supernodal factor held (SingleSupernodalFactor), for
    // solves whose answers the caller refines in double: such a solve reads half the bytes of
    // solve(), which reading L bounds. Asks `budget` for the copy's bytes first; false (no
    // copy) where it refuses, where no numeric supernodal factor is held, or where L does not
    // fit single precision. Dropped with the factor (a new factor(), a new pattern, a failure).
    bool keep_single_copy(const FactorBudget &budget);
    bool has_single_copy() const;
    void drop_single_copy();
    // x = A^-1 b for a finite b through the copy: its accuracy is single precision's times A's
    // condition, and x may come back not finite (the caller checks both); fails without a copy.
    frix_error solve_with_single_copy(const double *b, double *x) const;
    // The fill-reducing ordering of the analysis held (L's permutation; empty: none).
    std::vector<int64_t> ordering() const;
    // The ordering the next analysis takes instead of choosing one (empty: choose; it is
    // kept until replaced): a matrix whose pattern lies within one analysed already gets no
    // more fill from that one's ordering, without the cost of finding it again.
    void set_ordering(std::vector<int64_t> perm);
    // Whether the factor held is supernodal (false: simplicial, or none).
    bool supernodal() const;
    // C = B^T A^-1 B for a sparse B (n x k), handed to sink. With L L^T = P A P^T (supernodal)
    // and Z = L^-1 P B, C = Z^T Z = sum over L's supernodes s of Z_s^T Z_s, Z_s the rows of Z
    // in s and only the columns of B whose elimination paths pass through s (B's column j
    // reaches the supernodes from its rows' ones up to the root). Z_s comes from a forward
    // solve that goes up L's supernodal tree, each supernode handing its parent the update of
    // its rows below (multifrontal): dense BLAS-3 work on blocks that hold only the columns
    // that reach them, and nothing for the subtrees no column of B reaches. Where C is dense (a
    // deformable body couples all its contacts) this is minutes of work less than a sparse solve
    // per column. stop, when given, is asked between supernodes, about `questions` times
    // over the work (counted in flops before it starts) but not more often than every
    // min_flops_per_question flops: when it answers true, *stopped is set and the work ends,
    // with the sink holding part of the sum.
    frix_error inverse_congruence(const CscView &B, CongruenceSink &sink, const std::function<bool()> &stop = nullptr,
                                  bool *stopped = nullptr, double questions = kCongruenceQuestions,
                                  double min_flops_per_question = kCongruenceMinFlopsPerQuestion);
    // What inverse_congruence(B) will cost, from the patterns of L and B alone: its flops, the
    // bytes of its dense blocks besides C, C's pattern (the groups it hands its sink) and the
    // entries of the terms it hands it (each added into C by the sink, outside the BLAS).
    struct CongruenceCost {
        double flops = 0.0, workspace_bytes = 0.0;
        std::vector<std::vector<int64_t>> groups;
        double summed = 0.0;
    };
    frix_error congruence_cost(const CscView &B, CongruenceCost *cost) const;
    // The same, C as CSC (k x k, rows sorted); left empty when stopped.
    frix_error inverse_congruence(const CscView &B, std::vector<int64_t> &colptr, std::vector<int64_t> &rowind,
                                  std::vector<double> &values, const std::function<bool()> &stop = nullptr,
                                  bool *stopped = nullptr, double questions = kCongruenceQuestions,
                                  double min_flops_per_question = kCongruenceMinFlopsPerQuestion);

    const FactorStats &stats() const { return stats_; }
    // Every factor() first asks the budget (none: always factorise).
    void set_budget(FactorBudget budget) { budget_ = std::move(budget); }
    // Why the budget refused the last factor(): FRIX_STATUS_NOT_RUN if it did not.
    frix_status refused() const { return refused_; }

   private:
    frix_error refuse_unless_square(const CscView &A);
    bool analyse_pattern(const CscView &A);
    struct Impl;
    std::unique_ptr<Impl> impl_;
    FactorStats stats_;
    FactorBudget budget_;
    frix_status refused_ = FRIX_STATUS_NOT_RUN;
};

// The orderings an analysis may choose from: analyze_symmetric's rule (AMD, or METIS where it
// pays), or AMD alone.
enum class Orderings { kAmdOrNested, kAmdOnly };
// What a Cholesky factorisation of a symmetric matrix with A's pattern would cost, from
// the symbolic analysis alone (by default the ordering a SparseCholesky of it picks; no numeric
// work): a stage can be priced before it is paid. Only A's pattern is read (values may be
// null), and of it the upper triangle.
frix_error cholesky_cost(const CscView &A, FactorCost *cost, Orderings orderings = Orderings::kAmdOrNested);
// inv = A^-1 for a small dense k x k matrix A (column-major, overwritten; inv must hold the
// identity on entry), by Gauss-Jordan elimination with partial pivoting: a rigid body's mass
// block. False when a pivot is not above 1e-14 scale (A singular at that scale).
bool invert_small(int64_t k, double *a, double *inv, double scale);
// b = A^-1 b for a small dense N x N matrix A (column-major, overwritten), by Gaussian
// elimination with partial pivoting; N known at compile time, so the loops unroll: a one-contact
// Newton's direction, where invert_small's inverse costs three times the flops. False (b
// unchanged) when a pivot is not above 1e-14 scale, as invert_small.
template <int N>
bool solve_small(double *a, double *b, double scale) {
    double x[N];
    for (int i = 0; i < N; ++i) x[i] = b[i];
    for (int c = 0; c < N; ++c) {
        int piv = c;
        for (int i = c + 1; i < N; ++i)
            if (std::fabs(a[i + N * c]) > std::fabs(a[piv + N * c])) piv = i;
        if (!(std::fabs(a[piv + N * c]) > 1e-14 * scale)) return false;
        if (piv != c) {
            for (int j = c; j < N; ++j) std::swap(a[c + N * j], a[piv + N * j]);
            std::swap(x[c], x[piv]);
        }
        const double d = 1.0 / a[c + N * c];
        for (int i = c + 1; i < N; ++i) {
            const double f = a[i + N * c] * d;
            if (f == 0.0) continue;
            for (int j = c + 1; j < N; ++j) a[i + N * j] -= f * a[c + N * j];
            x[i] -= f * x[c];
        }
    }
    for (int i = N - 1; i >= 0; --i) {
        double s = x[i];
        for (int j = i + 1; j < N; ++j) s -= a[i + N * j] * x[j];
        x[i] = s / a[i + N * i];
    }
    for (int i = 0; i < N; ++i) b[i] = x[i];
    return true;
}

// What cholesky_cost gives for a dense matrix of size n, in closed form: the analysis of a
// complete graph would cost more than pricing is worth.
FactorCost dense_cholesky_cost(int64_t n);

// Dense LU with partial pivoting (LAPACK dgetrf/dgetrs), column-major n x n.
class DenseLU {
   public:
    frix_error factor(int64_t n, const double *A, int64_t lda);
    frix_error solve(const double *b, double *x) const;
    const FactorStats &stats() const { return stats_; }
    // min |U_ii| / max |U_ii| (the same cheap estimate as SparseLU::rcond).
    double rcond() const { return rcond_; }

   private:
    int n_ = 0;
    double rcond_ = 0.0;
    std::vector<double> lu_;
    std::vector<int> piv_;
    bool ok_ = false;
    FactorStats stats_;
};

// Dense Cholesky A = L L^T (LAPACK dpotrf/dpotrs), column-major n x n, lower triangle read.
class DenseCholesky {
   public:
    frix_error factor(int64_t n, const double *A, int64_t lda);
    frix_error solve(const double *b, double *x) const;
    const FactorStats &stats() const { return stats_; }

   private:
    int n_ = 0;
    std::vector<double> l_;
    bool ok_ = false;
    FactorStats stats_;
};

}  // namespace frix::linalg
