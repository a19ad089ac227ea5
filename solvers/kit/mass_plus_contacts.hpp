// What the solvers of global problems that never form W = H^T M^-1 H share (gadmm.cpp,
// gnsn_al.cpp): the symmetric positive definite matrix M + H S H^T, S block-diagonal
// (one symmetric 3x3 block per contact), in a pattern fixed for the solve, factorised by CHOLMOD
// with one symbolic analysis for every S; and the scale of W seen by one contact, from a few of
// W's diagonal blocks computed alone with M's factorisation.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "src/linalg/linalg.hpp"
#include "src/reduction.hpp"
#include "src/solve_cache.hpp"
#include "src/solver_api.hpp"

namespace frix {

// M's asymmetry (relative_asymmetry) up to which M + H S H^T is factorised with M's symmetric
// part, the skew part K = (M - M^T) / 2 left to the solvers (on the right-hand side, at the
// previous iterate: exact at a fixed point): a matrix written with 7 significant digits.
constexpr double kMassSkewMax = 1e-6;

// The contacts' blocks S_a a solver factorises with: any symmetric 3x3 block, or only
// multiples of the identity (an ADMM's rho I), whose H_a S_a H_a^T is zero wherever two rows of
// H_a share no column.
enum class ContactBlocks { kAny, kMultiplesOfIdentity };

class MassPlusContacts {
   public:
    // The pattern: M's (both triangles, folded onto the upper one) and, for every contact a,
    // the pairs of rows of H's columns 3a..3a+2 that H_a S_a H_a^T can couple for the blocks
    // given: every pair (kAny, S_a's zeros kept so that no S changes the pattern), or the pairs
    // that share a nonzero column of H_a (kMultiplesOfIdentity: an entry no S_a = s I can fill
    // would only add fill, tenfold on a body whose displacement components M leaves apart).
    // Where the pattern lies within M's (and the diagonal), its analysis takes M's fill-reducing
    // ordering `mass_ordering` (MassSolver::ordering; empty: none), which fills it no more than
    // M's, instead of finding one again (METIS on a 3D body: as long as the numeric
    // factorisation). Fails with FRIX_ERR_UNSUPPORTED when M's asymmetry is above kMassSkewMax
    // (there is no Cholesky of it).
    frix_error build(const Csc &M, const Csc &H, int64_t nc, const char *solver, ContactBlocks blocks,
                     std::vector<int64_t> mass_ordering);
    // Whether M is not exactly symmetric: the factorised matrix is then (M + M^T) / 2 + H S H^T,
    // and the solver must apply K = (M - M^T) / 2 itself (matrix_skew_gemv).
    bool skewed() const { return skewed_; }
    // What factorising M + H S H^T costs, from the symbolic analysis of its pattern, which the
    // system keeps for its first factorisation (linalg::SparseCholesky::analyze).
    frix_error analyse(linalg::FactorCost *cost) { return chol_.analyze(A_.view(), cost); }
    // What a factorisation on the analysis held costs (zero: none yet).
    linalg::FactorCost cost() const { return chol_.cost(); }
    // The entries of H it holds (three a row of each contact's columns): what a product
    // with H or H^T costs, in multiply-adds.
    double contact_entries() const { return (double)hrows_.size(); }
    // The ordering of the analysis held (empty: none yet).
    std::vector<int64_t> ordering() const { return chol_.ordering(); }
    // Factorises M + H S H^T, S = 9 nc values (column-major 3x3 blocks, symmetric, each a
    // multiple of the identity where the system was built for those), asking `budget` first
    // (see linalg::FactorBudget); refused() then says which limit.
    frix_error factor(const double *S, const linalg::FactorBudget &budget);
    // x = (M + H S H^T)^-1 b with the last factorisation.
    frix_error solve(const double *b, double *x) const { return chol_.solve(b, x); }
    // Keeps a single-precision copy of the last factorisation for solve_near, where it is
    // supernodal and `budget` affords the copy's bytes, and unless solve_near dropped a copy of
    // this factorisation already; false where it keeps none.
    bool keep_single_copy(const linalg::FactorBudget &budget);
    // x = (M + H S H^T)^-1 b from x's value on entry, an iterate near the answer: the residual
    // b - A x solved through the single-precision copy, where one is kept, and the step taken
    // where the residual it leaves, computed in double, is below kSingleContraction of the one
    // solved; otherwise a solve in double finishes x (and after kSingleMisses such solves in a
    // row the copy is dropped). Without a copy, solve(). An iterative solver's next solve lies
    // near its last: the error a step leaves is a share of the step, not of x.
    frix_error solve_near(const double *b, double *x);
    bool uses_single_copy() const { return chol_.has_single_copy(); }
    // solve_near's solves through the copy, and those of them finished in double, since the
    // system was built.
    int64_t single_solves() const { return single_solves_; }
    int64_t solves_finished_in_double() const { return finished_in_double_; }
    frix_status refused() const { return chol_.refused(); }
    const linalg::FactorStats &stats() const { return chol_.stats(); }

   private:
    Csc A_;                                // M + H S H^T, upper triangle
    bool skewed_ = false;
    std::vector<int64_t> m_slot_;          // M's upper entries: their slot in A_
    std::vector<double> m_val_;            // ... and their values
    // Contact a: its rows of H (rows_[row_start_[a] .. row_start_[a + 1])), H restricted to
    // them (3 per row, hrows_), and its pairs of rows (i <= j, indices into rows_) in the
    // pattern with their slots: pairs_[pair_start_[a] .. pair_start_[a + 1]).
    struct Pair {
        int64_t i, j, slot;
    };
    std::vector<int64_t> row_start_, rows_, pair_start_;
    std::vector<Pair> pairs_;
    std::vector<double> hrows_;
    linalg::SparseCholesky chol_{linalg::SparseCholesky::Layout::kForSolves};
    bool single_dropped_ = false;  // solve_near dropped the copy of this factorisation
    int misses_in_a_row_ = 0;
    int64_t single_solves_ = 0, finished_in_double_ = 0;
    std::vector<double> residual_, step_, left_;  // solve_near's workspace
};

// What these solvers keep between the solves of a persistent solver: M + H S H^T's pattern and
// symbolic analysis, rho's unit, and (gadmm) the factorisation at the last rho, while M's and
// H's values stay.
struct KeptMassPlusContacts : CachedState {
    uint64_t m_values = 0, h_values = 0;  // the versions they were built from (0: none)
    MassPlusContacts system;
    double scale = NAN;        // rho's unit (sampled_delassus_scale; NAN: not sampled yet)
    double factored_rho = NAN;  // the rho of the factorisation the system holds (NAN: none usable)
    // The work done on a system handed over (offer_mass_plus_contacts: its analysis), which the
    // taker's solve reports as its own.
    linalg::FactorStats handed;
};
// Makes `kept` current for ctx's problem: built anew (pattern, rho's unit from `samples`
// sampled contacts, by W's diagonal where ctx.mass is factorised, else by its Jacobi estimate)
// unless ctx's cache shows it was built from the same M and H (then only
// rho's unit where it was not sampled). *before: the system's counters from which this solve's
// work counts. Fails as MassPlusContacts::build does.
frix_error prepare_mass_plus_contacts(const SolveContext &ctx, KeptMassPlusContacts &kept, const char *solver,
                                      int samples, ContactBlocks blocks, linalg::FactorStats *before);
// Hands `offered` (its system built, and analysed, for the M and H of the cache's current
// versions) to the solver that next runs on `cache` and keeps its state under `key`: that
// solver's prepare_mass_plus_contacts then neither builds nor analyses it again. Where the
// cache holds that solver's state built from the same M and H (a persistent solver's, with its
// factorisation at the last rho) that state stays and `offered` is dropped.
void offer_mass_plus_contacts(SolveCache &cache, int key, std::unique_ptr<KeptMassPlusContacts> offered);

// The De Saxce term of the global solvers without W from u = H^T v + w: shift[3a] =
// mu_a |u_T,a| (the normal entry of each contact; the tangential ones are not written).
void de_saxce_shift(const frix_problem &p, const double *u, double *shift);

// The selected error measure of (r, v), equilibrium included (selected_error), u = H^T v + w
// computed into u and the plain equilibrium residual into *equilibrium: what a solver of
// global problems stops on.
double global_error(const frix_problem &p, int64_t measure, const double *r, const double *v, double *u,
                    double *equilibrium);
// The same, and where it is above tol, also the errors of r with v corrected towards r's own
// velocity M^-1 (H r + f) by up to kVelocityRefinements steps v += M^-1 (H r + f - M v) with the
// driver's factorisation of M (`mass`; none where it is null or holds the analysis alone), while
// they lower the error: v and u then hold the best. Where rho H H^T dwarfs M (a stiff body) an iterate's equilibrium stalls at rho
// times rounding; one solve with M's factor alone stalls at its condition times rounding, which
// the refinement removes.
constexpr int kVelocityRefinements = 3;
double global_error_or_recovered(const frix_problem &p, const MassSolver *mass, int64_t measure, double tol,
                                 const double *r, double *v, double *u, double *equilibrium);

// The normal entry of W_aa = H_a^T M^-1 H_a averaged over up to `samples` contacts spread over
// the problem, from M's factorisation: the scale a penalty on the contacts is measured in, with
// W never formed. NaN when it cannot be computed.
double sampled_delassus_scale(const frix_problem &p, const Csc &H, MassSolver &mass, int samples);
// The same scale where M is not factorised (a one-shot route that never solves with M): the
// normal entry of H_a^T diag(M)^-1 H_a (the contacts' weights) over the same contacts, W_aa's
// where M is diagonal and an estimate elsewhere, which the residual balance corrects. NaN where
// there is none.
double sampled_jacobi_scale(const frix_problem &p, int samples);

// Sampled diagonals of W_aa = H_a^T M^-1 H_a, of up to `samples` contacts a spread over the
// problem, as (a, sum) pairs: the sum of W_aa's first `components` diagonal entries (3: its
// trace; 1: its normal entry), from M's factorisation (MassSolver::inverse_diagonal). Empty
// where that fails.
std::vector<std::pair<int64_t, double>> sampled_delassus_diagonals(const frix_problem &p, const Csc &H,
                                                                   MassSolver &mass, int samples, int components);

}  // namespace frix
