// Global problems (M, H, f, w, mu) reduced to local ones: M's factorisation, W = H^T M^-1 H,
// the recovery of v = M^-1 (H r + f), and what forming W would cost in memory.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "error_state.hpp"
#include "linalg/linalg.hpp"
#include "load_span.hpp"
#include "matrix.hpp"
#include "problem.hpp"

namespace frix {

// W's 3x3 blocks: 9 values and a column index each (its builders keep no other copy).
constexpr double kBytesPerReducedBlock = 80.0;

// A matrix in CSC with its own arrays.
struct Csc {
    int64_t rows = 0, cols = 0;
    std::vector<int64_t> colptr, rowind;
    std::vector<double> val;
    linalg::CscView view() const { return {rows, cols, colptr.data(), rowind.data(), val.data()}; }
};

frix_error to_csc(const frix_matrix &A, Csc &out);

// max |M_ij - M_ji| / max |M_ij| (0 for M = 0), an entry without its mirror against 0.
double relative_asymmetry(const linalg::CscView &M);
inline double relative_asymmetry(const Csc &M) { return relative_asymmetry(M.view()); }
// The round-off a computed symmetric matrix's mirrored entries may differ by, relative to
// their scale (about 4,500 units of round-off: sums of many products).
constexpr double kRoundOff = 1e-12;
// Whether M equals its transpose to round-off (relative_asymmetry <= kRoundOff; CHOLMOD reads
// only the upper triangle).
bool is_symmetric(const linalg::CscView &M);
inline bool is_symmetric(const Csc &M) { return is_symmetric(M.view()); }
// Whether a square W equals its transpose to round-off at every scale: with x a fixed
// pseudo-random vector scaled by W's diagonal (x_j = +-[1/2, 1) / sqrt(W_jj)), each row of
// W x - W^T x within kRoundOff of that row's terms, sum_j |W_ij x_j| + |W_ji x_j|. One pass
// over W: a pairwise comparison reads each entry's mirror elsewhere in W. Where every
// |W_ij| <= sqrt(W_ii W_jj) (W positive semidefinite, as a Delassus W is), a pair off by more
// than 4 kRoundOff sqrt(W_ii W_jj) times its row's entries fails it, unless other pairs of its
// row cancel it; a pair within that changes a product with W only at its row's round-off. The
// scaling makes the test the same in any units: against max |W| a real asymmetry among
// entries many orders below the largest (a rolling row's, a light body's) would pass. A
// diagonal entry that is not positive, or an entry past that bound: every mirrored pair within
// kRoundOff sqrt(|W_ii W_jj|) instead. diagonal: W's diagonal where the caller has it (null:
// found here).
bool symmetric_at_every_scale(const linalg::CscView &W, const double *diagonal = nullptr);

// A factorisation of M: CHOLMOD when M is symmetric positive definite, UMFPACK otherwise.
class MassSolver {
   public:
    // The work of each factor(), analyse() and factor_analysed() is in last_stats().
    frix_error factor(const frix_matrix &M) {
        return counted([&] {
            if (frix_error e = analyse_counted(M)) return e;
            return factored_ ? FRIX_OK : numeric_counted();
        });
    }
    // The analysis alone where M is symmetric (Cholesky's ordering and symbolic factor: what
    // the price of W and the analysis of M + rho H H^T read), factor_analysed() to complete it:
    // a route that never solves with M pays only for it. An M that is not symmetric is
    // factorised at once (LU), as factor() does.
    frix_error analyse(const frix_matrix &M) {
        return counted([&] { return analyse_counted(M); });
    }
    frix_error factor_analysed() {
        return counted([&] { return factored_ ? FRIX_OK : numeric_counted(); });
    }
    // Whether M's factorisation is held (not after analyse() alone, nor after a failure).
    bool factored() const { return factored_; }
    // Every factorisation first asks the budget (the solve's limits); refused(): the limit
    // the last factor() would have overrun (FRIX_STATUS_NOT_RUN: none).
    void set_budget(const linalg::FactorBudget &budget) {
        chol_.set_budget(budget);
        lu_.set_budget(budget);
    }
    frix_status refused() const { return refused_; }
    // Whether the last M factorised was symmetric (to round-off).
    bool symmetric() const { return symmetric_; }
    frix_error solve(const double *b, double *x) const {
        if (empty_) return FRIX_OK;
        if (!factored_) return not_factored();
        return use_chol_ ? chol_.solve(b, x) : lu_.solve(b, x);
    }
    // x = M^-1 f (n values) for a load f: the last load's answer is kept, and a load equal to
    // it value for value is not solved again (the driver's setup and the global solves a
    // solver runs within it, such as auto's routes, ask for the same one). With keep_loads (a
    // persistent solver's M, solved for again at later steps), where M's factor holds at least
    // twice M's entries (a solve reads it twice, LoadSpan's test M once), nor is a load in the
    // span of the loads solved since M's factorisation (a host's load path).
    frix_error solve_load(const double *f, int64_t n, double *x, bool keep_loads);
    // W = H^T M^-1 H, block-CSR. From CHOLMOD's factor it is summed supernode by supernode
    // into its final storage (BlockMatrixFromTerms; see SparseCholesky::inverse_congruence);
    // from UMFPACK's, assembled from its columns (BlockMatrixFromColumns, told to expect up to
    // expected_blocks blocks). stop is asked every few milliseconds of that work; when it
    // answers true, stopped is set and W is null.
    frix_error congruence(const frix_matrix &H, double expected_blocks, std::unique_ptr<frix_matrix> &W,
                          const std::function<bool()> &stop, bool &stopped) {
        stopped = false;
        W.reset();
        if (!factored_) return not_factored();
        Csc h;
        if (frix_error e = to_csc(H, h)) return e;
        const int64_t n = H.rows, k = H.cols;
        if (use_chol_ && !empty_) {
            BlockMatrixFromTerms terms(k, "W = H^T M^-1 H");
            if (frix_error e = chol_.inverse_congruence(h.view(), terms, stop, &stopped)) return e;
            if (stopped) return FRIX_OK;
            return terms.finish(W);
        }
        BlockMatrixFromColumns columns(k, "W = H^T M^-1 H", expected_blocks);
        if (empty_) {
            for (int64_t j = 0; j < k; ++j)
                if (frix_error e = columns.add_column(0, nullptr, nullptr)) return e;
        } else {
            // LU: one solve per column of H; exact zeros (contacts M does not couple) are dropped.
            std::vector<double> col(n), x(n), wcol(k), values;
            std::vector<int64_t> rows;
            for (int64_t j = 0; j < k; ++j) {
                std::fill(col.begin(), col.end(), 0.0);
                for (int64_t e = h.colptr[j]; e < h.colptr[j + 1]; ++e) col[h.rowind[e]] = h.val[e];
                if (frix_error e = lu_.solve(col.data(), x.data())) return e;
                matrix_gemv_transposed(H, 1.0, x.data(), 0.0, wcol.data());
                rows.clear();
                values.clear();
                for (int64_t i = 0; i < k; ++i)
                    if (wcol[i] != 0.0) {
                        rows.push_back(i);
                        values.push_back(wcol[i]);
                    }
                if (frix_error e = columns.add_column((int64_t)rows.size(), rows.data(), values.data())) return e;
                if ((j + 1) % linalg::kCongruenceBlockColumns == 0 && j + 1 < k && stop && stop()) {
                    stopped = true;
                    return FRIX_OK;
                }
            }
        }
        return columns.finish(W);
    }
    // What congruence(H) will cost, priced as a factorisation is (linalg::FactorPrice): from
    // CHOLMOD's factor, its exact flops; its writes, W's entries (9 a block, written first
    // when zeroed) and the entries of the terms summed into them; in bytes W's blocks and the
    // dense blocks formed besides. False where it is not known (UMFPACK's factor: one solve per
    // column of H).
    bool congruence_price(const frix_matrix &H, linalg::FactorPrice *price) const {
        if (!use_chol_ || empty_) return false;
        Csc h;
        linalg::SparseCholesky::CongruenceCost cost;
        if (to_csc(H, h) != FRIX_OK || chol_.congruence_cost(h.view(), &cost) != FRIX_OK) {
            clear_error();
            return false;
        }
        double blocks = 0.0;  // at most: sets may overlap
        for (const auto &c : contact_sets(cost.groups)) blocks += (double)c.size() * (double)c.size();
        *price = linalg::FactorPrice{cost.flops, NAN, cost.workspace_bytes + kBytesPerReducedBlock * blocks, false,
                                     9.0 * blocks + cost.summed};
        return true;
    }
    // diag[j] = b_j^T M^-1 b_j for the columns b_j of B (n x k): from CHOLMOD's factor only
    // the forward solves along each column's path up L's tree (SparseCholesky's
    // inverse_congruence on B alone: a few columns cost a small part of one solve), else one
    // solve a column.
    frix_error inverse_diagonal(const Csc &B, std::vector<double> &diag);
    const linalg::FactorStats &last_stats() const { return last_; }
    // The fill-reducing ordering of M's Cholesky factorisation (empty: none, or by LU).
    std::vector<int64_t> ordering() const { return use_chol_ && !empty_ ? chol_.ordering() : std::vector<int64_t>{}; }
    // Whether M was factorised by Cholesky (symmetric positive definite, with dofs).
    bool cholesky() const { return use_chol_ && !empty_; }

   private:
    template <class F>
    frix_error counted(F &&work) {
        const linalg::FactorStats chol0 = chol_.stats(), lu0 = lu_.stats();
        const frix_error e = work();
        last_ = (chol_.stats() - chol0) + (lu_.stats() - lu0);
        return e;
    }
    frix_error analyse_counted(const frix_matrix &M);
    frix_error numeric_counted();
    frix_error factor_lu();
    static frix_error not_factored();

    linalg::FactorStats last_;
    Csc csc_;
    linalg::SparseCholesky chol_;
    linalg::SparseLU lu_;
    bool use_chol_ = false;
    frix_status refused_ = FRIX_STATUS_NOT_RUN;  // why the last factor() was not started
    bool empty_ = false;
    bool symmetric_ = false;
    bool factored_ = false;
    std::vector<double> load_, load_x_;  // solve_load: the last load and M^-1 of it
    LoadSpan span_;                       // solve_load: the loads solved, where they pay
};

// Global problems: what the reduction W = H^T M^-1 H would cost, from the structure of M and H
// alone, in O(n + nnz(M) + nnz(H) log nnz(H)). M^-1 couples any two dofs of a connected
// component of M's graph (a rigid body: its 6 dofs; a deformable body: all of its nodes), so
// W_ij can be non-zero only when columns i and j of H touch a common component: the bound is
// the sum over components of (columns of H touching it)^2, at most (3nc)^2, exact but for
// cancellations. A deformable body makes W dense among its contacts.
struct ReductionSize {
    double w_entries = 0.0;      // the bound on W's non-zero entries
    double w_blocks = 0.0;       // the bound on its non-zero 3x3 blocks (contacts, squared)
    double input_entries = 0.0;  // non-zero entries of M and H
    // Without W, in product form (gnsgs): the dofs of the components each column of H
    // touches, summed over the columns (the entries of M^-1 H), and the largest component's
    // dofs (a rigid body's 6; a deformable body's all).
    double product_entries = 0.0;
    int64_t largest_component = 0;
    bool structural = false;  // the bounds are the structure's (reduction_size), not nc^2's
};
ReductionSize reduction_size(const frix_problem &p);

// The bound the driver holds W to before forming it: nc^2 blocks, tightened by
// reduction_size where W could take more than kStructureAbove bytes.
ReductionSize reduction_bound(const frix_problem &p);

// Whether W = H^T M^-1 H would fit in memory: its 3x3 blocks (the structural bound of
// reduction_size) at 80 bytes each, against the memory the solve may still take (the
// Monitor's memory_left: the option memory_limit, or the machine's or control group's memory
// less what the process holds). A deformable body makes W dense: on a large mesh it would not
// fit, and the system would kill the process part-way through forming it. A floor: forming W
// also holds, for a while, the rows of L^-1 P H of one supernode of M's factor and the updates
// its children hand it (see SparseCholesky::inverse_congruence).
struct ReductionMemory {
    double needed = 0.0;          // bytes, at least
    double available = INFINITY;  // bytes the solve may still take
    bool fits = true;
};
class Monitor;
ReductionMemory reduction_memory(const ReductionSize &size, const Monitor &monitor);

// v = M^-1 (H r + f).
frix_error recover_velocity(const frix_problem &p, const MassSolver &ms, const double *r, double *v);

}  // namespace frix
