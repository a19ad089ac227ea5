// Semismooth Newton on the local (reduced) problem: ids 504 (Alart-Curnier), 513
// (Fischer-Burmeister), 520 (natural map). The engine below is shared with PROX (prox.cpp),
// which runs it on the shifted problem u = (W + alpha I) r + q' without touching W.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "solvers/kit/newton_engine.hpp"
#include "src/linalg/linalg.hpp"
#include "src/problem.hpp"
#include "src/solve_cache.hpp"
#include "src/solver_api.hpp"

namespace frix {


namespace newton {

struct Settings {
    int formulation = 0;        // nsn::Formulation
    int rho_strategy = 1;       // frix_rho_strategy
    double rho = 1.0;
    int line_search = 1;        // frix_line_search
    int ls_max_iter = 20;
    int hybrid = 1;             // frix_hybrid
    int64_t hybrid_sweeps = 50;
    int watchdog = 0;           // steps of a full-step excursion (option watchdog; 0: none)
    int64_t measure = 0;        // frix_error_measure
    const double *weight = nullptr;  // the problem's contact weights (frix_problem::weight)
    int verbosity = 0;
    const frix_options *log = nullptr;  // where progress lines go (null: stderr)
};

// The Newton settings of options of solver 504/513/520 (formulation from the id).
Settings settings_from(const frix_options &o, int solver_id);

// The engine's counters and a run's outcome (kit/newton_engine.hpp).
using Counters = kit::Counters;
using RunResult = kit::RunResult;

// Newton on u = (W + shift I) r + q. The Jacobian A + B (W + (shift + delta) I) has the
// block pattern of W plus its diagonal; separating contacts (B = 0) are eliminated, and the
// pattern of the rest is analysed (SparseLU) only when the set of active contacts changes,
// then factorised once per step. delta is a regularisation used only when the
// Jacobian is singular, as it is on rank-deficient W with many sticking contacts.
class Engine {
   public:
    Engine(const frix_matrix &W, const double *mu, int64_t nc, const Settings &s);
    // The next solve of a persistent solver: W with the pattern of the last one (new values),
    // mu and settings. Finds the active set afresh, as a new engine would, and keeps the
    // symbolic analysis of the last active set for when it comes back; restarts the counters
    // and the factorisation statistics.
    void rebind(const frix_matrix &W, const double *mu, const Settings &s);
    // Runs from r (updated in place; on return, the best iterate found), stopping when the
    // selected error of the problem (W + shift I, q) is <= steps.monitor.tolerance(), or at its
    // limits (on steps.done, which the run advances). scale_q (if >= 0) replaces |q| in the
    // error's denominator: PROX measures its inner problems, whose q - alpha r_k can be far
    // larger than q, on the scale of the original one.
    frix_error run(double *r, const double *q, double shift, kit::Steps &steps, RunResult &res, double scale_q = -1.0);

    // Sparse and dense factorisations together, since construction or the last rebind.
    linalg::FactorStats factor_stats() const;
    Counters counters;
    // Take the full step when the line search finds no sufficient decrease (instead of the
    // best trial step). PROX sets it: its regularised inner problems tolerate full steps,
    // and the short steps otherwise stall on degenerate contacts (spheres-in-a-box).
    bool full_step_on_failure = false;
    double w_scale() const { return w_scale_; }  // mean |W_aa|_2, the unit of shifts

   private:
    class Run;  // a run's kit::NewtonLoop system (newton.cpp)
    bool update_active();
    void build_pattern();
    void evaluate(const double *r, const double *u, bool jacobian, double *phi);
    void assemble(double shift);
    // The active set, and the symbolic analysis of its pattern when it changed (J assembled
    // with this shift for it); then J factorised.
    frix_error prepare(double shift);
    frix_error factor(double shift, kit::Factorisation &f);
    frix_error step(const double *phi, double *d, double *rhs, double *x);

    linalg::FactorStats total_stats() const;
    const frix_matrix *W_;
    const double *mu_ = nullptr;
    int64_t nc_, m_;
    Settings s_;
    std::vector<double> rho_n_, rho_t_;
    std::vector<double> A_, B_;  // 9 per contact
    // Active contacts (index_[a] = position in the system, -1 for a separating contact whose
    // step is -Phi_a) and the CSC of the active Jacobian: per block of W, the offset of its
    // (0,0) entry and the stride between its columns (-1: not in the system); diag_pos_ for
    // the diagonal blocks W lacks.
    std::vector<int64_t> index_;
    int64_t n_active_ = 0;
    std::vector<int64_t> colptr_, rowind_;
    std::vector<double> values_;
    std::vector<int64_t> block_pos_, block_stride_, diag_pos_, diag_stride_;
    linalg::SparseLU lu_;
    // Small active systems (<= kDenseMax unknowns) are factorised dense: UMFPACK's fixed
    // cost per factorisation dominates there.
    linalg::DenseLU dense_lu_;
    std::vector<double> dense_;
    bool use_dense_ = false;
    bool analysed_ = false;
    std::vector<int64_t> analysed_index_;  // index_ when lu_ was last analysed (empty: never)
    double w_scale_ = 1.0;
    linalg::FactorStats stats_before_;
};

// An engine kept by a persistent solver (solve_cache.hpp), with the pattern version of the W
// it was built on.
struct KeptEngine : CachedState {
    std::unique_ptr<Engine> engine;
    uint64_t w_pattern = 0;
    int64_t nc = -1;
};
// The engine of this solve: the kept one rebound to W when W's pattern is the one it was built
// on, a new one otherwise (and always without a cache).
Engine &engine_for(KeptEngine &kept, const SolveCache *cache, const frix_matrix &W, const double *mu,
                   int64_t nc, const Settings &s);

}  // namespace newton
}  // namespace frix
