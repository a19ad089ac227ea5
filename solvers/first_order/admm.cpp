// ADMM (id 523) on the splitting r = z of
//   min 1/2 r'W r + (q + s)'r + I_K(z),   s_a = mu_a |u_T,a| e_N (the De Saxce term),
// in scaled form, with W + rho I factorised once per value of rho:
//   (W + rho I) x = -(q + s) + rho (z^ - y^)
//   z = P_K(x + y^),   y = y^ + x - z
// where (z^, y^) are Nesterov's extrapolations of (z, y), restarted whenever the combined
// residual does not decrease (Goldstein, O'Donoghue, Setzer, Baraniuk 2014); u = W x + q comes
// free from the linear system (W x + q = -s + rho (z^ - y^ - x)) and gives the next s. At a
// fixed point x = z = r solves the Coulomb problem with u^ = -rho y.
// rho (in units of mean_a |W_aa|_2) follows the residual balance (the ratio of the relative
// primal and dual residuals, as OSQP does), checked every kBalancePeriod iterations and
// changed only by a factor >= 5, each change costing one factorisation.
// W + rho I is factorised by Cholesky when W is symmetric (dense LAPACK up to kDenseMax
// unknowns, CHOLMOD above), by LU otherwise (dense LAPACK or UMFPACK): an unsymmetric W (e.g.
// written with 7 significant digits) would otherwise move the fixed point.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numeric>
#include <utility>
#include <vector>

#include "solvers/kit/first_order.hpp"
#include "solvers/kit/local3x3.hpp"
#include "src/coulomb.hpp"
#include "src/error_state.hpp"
#include "src/linalg/linalg.hpp"
#include "src/log.hpp"
#include "src/matrix.hpp"
#include "src/monitor.hpp"
#include "solvers/entries.hpp"

namespace frix {
namespace admm {

namespace {

constexpr int64_t kDenseMax = 240;        // unknowns factorised dense at most
constexpr double kSymmetryTol = 1e-12;    // relative to max |W_ij|: symmetric
constexpr double kSkewMax = 1e-2;         // relative to max |W_ij|: Cholesky of the symmetric part
constexpr int64_t kBalancePeriod = 25;
constexpr double kBalanceFactor = 5.0;    // rho changes only by this factor or more
constexpr double kRhoMin = 1e-6, kRhoMax = 1e6;  // relative to mean |W_aa|
constexpr double kZeroPrimalStep = 100.0;  // rho's fall where the primal residual is 0
constexpr int64_t kFullCheckPeriod = 32;

// W + rho I and its factorisation through the linear-algebra interface. W = S + K with S
// symmetric and K skew: when K = 0 (to rounding) S + rho I is factorised by Cholesky; when K
// is small (|K_ij| <= kSkewMax max |W_ij|: e.g. W written with 7 significant digits, or
// rigid-body W with slightly unsymmetric blocks) Cholesky still factorises S + rho I and the
// ADMM step moves K x to the right-hand side, taken at the previous x (exact at the fixed
// point, a contraction since |K| << rho); a larger K gets an LU of W + rho I.
class ShiftedSystem {
   public:
    explicit ShiftedSystem(const frix_matrix &W) { build(W); }

    // W's next values (a persistent solver's next step): the analyses are kept when the
    // pattern of the matrix factorised, and the kind of factorisation, stay.
    void refill(const frix_matrix &W) {
        const std::vector<int64_t> colptr = colptr_, rowind = rowind_;
        const bool lu = lu_, skew = skew_, dense = dense_;
        build(W);
        if (lu != lu_ || skew != skew_ || dense != dense_ || colptr != colptr_ || rowind != rowind_)
            analysed_ = false;
    }

   private:
    void build(const frix_matrix &W) {
        m_ = W.rows;
        factored_ = false;
        base_.clear();
        colptr_.clear();
        rowind_.clear();
        diag_.clear();
        measure_asymmetry(W);
        lu_ = asym_ > kSkewMax;
        skew_ = !lu_ && asym_ > kSymmetryTol;
        dense_ = m_ <= kDenseMax;
        // Triplets of the matrix factorised: W itself (LU) or S = (W + W^T) / 2.
        std::vector<Entry> e;
        e.reserve((size_t)(lu_ ? 9 : 18) * W.block_col.size() + (size_t)m_);
        for (int64_t br = 0; br < W.block_rows; ++br)
            for (int64_t b = W.row_ptr[br]; b < W.row_ptr[br + 1]; ++b)
                for (int j = 0; j < 3; ++j)
                    for (int i = 0; i < 3; ++i) {
                        const int64_t row = 3 * br + i, col = 3 * W.block_col[b] + j;
                        const double v = W.block_val[9 * b + i + 3 * j];
                        if (lu_) {
                            e.push_back({col, row, v});
                        } else {
                            e.push_back({col, row, 0.5 * v});
                            e.push_back({row, col, 0.5 * v});
                        }
                    }
        for (int64_t i = 0; i < m_; ++i) e.push_back({i, i, 0.0});  // every diagonal entry
        sort_by_column(e, m_);
        if (dense_) {
            base_.assign((size_t)(m_ * m_), 0.0);
            for (const Entry &x : e) base_[(size_t)(x.row + x.col * m_)] += x.val;
            return;
        }
        colptr_.assign((size_t)m_ + 1, 0);
        diag_.assign((size_t)m_, -1);
        for (size_t k = 0; k < e.size(); ++k) {
            if (k > 0 && e[k].col == e[k - 1].col && e[k].row == e[k - 1].row) {
                base_.back() += e[k].val;
                continue;
            }
            rowind_.push_back(e[k].row);
            base_.push_back(e[k].val);
            ++colptr_[(size_t)e[k].col + 1];
            if (e[k].row == e[k].col) diag_[(size_t)e[k].col] = (int64_t)base_.size() - 1;
        }
        for (int64_t j = 0; j < m_; ++j) colptr_[(size_t)j + 1] += colptr_[(size_t)j];
    }

   public:
    bool skew() const { return skew_; }
    bool dense() const { return dense_; }
    // Every sparse factorisation first asks the budget (the solve's time and memory limits);
    // refused(): the limit the last one would have overrun (FRIX_STATUS_NOT_RUN: none).
    void set_budget(const linalg::FactorBudget &budget) {
        schol_.set_budget(budget);
        slu_.set_budget(budget);
    }
    frix_status refused() const {
        return dense_ ? FRIX_STATUS_NOT_RUN : lu_ ? slu_.refused() : schol_.refused();
    }
    const char *kind() const { return lu_ ? "LU" : skew_ ? "Cholesky of the symmetric part" : "Cholesky"; }

    // Factorises W + rho R, R = diag(weight_a I_3) (contact a's penalty is rho weight_a).
    frix_error factor(double rho, const std::vector<double> &weight) {
        // The factorisation held is of these values already (a persistent solver's next solve).
        if (factored_ && rho == factored_rho_ && weight == factored_weight_) return FRIX_OK;
        factored_ = false;
        const frix_error e = factor_values(rho, weight);
        if (e == FRIX_OK) {
            factored_ = true;
            factored_rho_ = rho;
            factored_weight_ = weight;
        }
        return e;
    }

   private:
    frix_error factor_values(double rho, const std::vector<double> &weight) {
        if (dense_) {
            work_ = base_;
            for (int64_t i = 0; i < m_; ++i) work_[(size_t)(i + i * m_)] += rho * weight[(size_t)(i / 3)];
            return lu_ ? dlu_.factor(m_, work_.data(), m_) : dchol_.factor(m_, work_.data(), m_);
        }
        values_ = base_;
        for (int64_t i = 0; i < m_; ++i) values_[(size_t)diag_[(size_t)i]] += rho * weight[(size_t)(i / 3)];
        linalg::CscView A{m_, m_, colptr_.data(), rowind_.data(), values_.data()};
        if (!lu_) return schol_.factor(A);
        if (!analysed_) {
            if (frix_error e = slu_.analyze(A)) return e;
            analysed_ = true;
        }
        return slu_.factor(A);
    }

   public:
    frix_error solve(const double *b, double *x) const {
        if (dense_) return lu_ ? dlu_.solve(b, x) : dchol_.solve(b, x);
        return lu_ ? slu_.solve(b, x) : schol_.solve(b, x);
    }

    // kx = K x = (W x - W^T x) / 2 for the W the system holds the values of (passed, not
    // kept: a persistent solver's W may be another object with the same values); work (m) is
    // scratch.
    void skew_product(const frix_matrix &W, const double *x, double *kx, double *work) const {
        matrix_skew_gemv(W, x, kx, work);
    }

    linalg::FactorStats stats() const { return dchol_.stats() + dlu_.stats() + schol_.stats() + slu_.stats(); }

   private:
    struct Entry {
        int64_t col, row;
        double val;
    };
    // Orders e by (col, row): bucketed by column (a counting pass), then each column sorted
    // on its own; columns hold tens of entries, so this is linear in practice where one sort
    // of all entries is not.
    static void sort_by_column(std::vector<Entry> &e, int64_t cols) {
        std::vector<int64_t> start((size_t)cols + 1, 0);
        for (const Entry &x : e) ++start[(size_t)x.col + 1];
        for (int64_t j = 0; j < cols; ++j) start[(size_t)j + 1] += start[(size_t)j];
        std::vector<Entry> out(e.size());
        std::vector<int64_t> next(start.begin(), start.end() - 1);
        for (const Entry &x : e) out[(size_t)next[(size_t)x.col]++] = x;
        for (int64_t j = 0; j < cols; ++j)
            std::sort(out.begin() + start[(size_t)j], out.begin() + start[(size_t)j + 1],
                      [](const Entry &x, const Entry &y) { return x.row < y.row; });
        e.swap(out);
    }

    // max |W_ab - W_ba^T| / max |W_ij| over the blocks.
    void measure_asymmetry(const frix_matrix &W) {
        double wmax = 0.0;
        for (double v : W.block_val) wmax = std::max(wmax, std::fabs(v));
        asym_ = 0.0;
        if (!(wmax > 0.0)) return;
        for (int64_t a = 0; a < W.block_rows; ++a)
            for (int64_t k = W.row_ptr[a]; k < W.row_ptr[a + 1]; ++k) {
                const int64_t b = W.block_col[k];
                const int64_t *beg = &W.block_col[W.row_ptr[b]], *end = &W.block_col[W.row_ptr[b + 1]];
                const int64_t *f = std::lower_bound(beg, end, a);
                const double *B = &W.block_val[9 * k];
                if (f == end || *f != a) {
                    for (int i = 0; i < 9; ++i) asym_ = std::max(asym_, std::fabs(B[i]) / wmax);
                    continue;
                }
                const double *T = &W.block_val[9 * (W.row_ptr[b] + (f - beg))];
                for (int i = 0; i < 3; ++i)
                    for (int j = 0; j < 3; ++j)
                        asym_ = std::max(asym_, std::fabs(B[i + 3 * j] - T[j + 3 * i]) / wmax);
            }
    }

    int64_t m_ = 0;
    double asym_ = 0.0;
    bool factored_ = false;
    double factored_rho_ = 0.0;
    std::vector<double> factored_weight_;
    bool lu_ = false, skew_ = false, dense_ = false, analysed_ = false;
    std::vector<double> base_, work_, values_;  // dense: base_ m x m; sparse: base_ nnz
    std::vector<int64_t> colptr_, rowind_, diag_;
    linalg::DenseCholesky dchol_;
    linalg::DenseLU dlu_;
    linalg::SparseCholesky schol_{linalg::SparseCholesky::Layout::kForSolves};
    linalg::SparseLU slu_;
};

// What a persistent solver keeps (see solve()): W + rho I at the starting rho and at the last
// rho adapted to, each with the version of W's values it holds.
struct KeptSystem : CachedState {
    std::unique_ptr<ShiftedSystem> start, adapted;
    uint64_t start_values = 0, adapted_values = 0;
    int64_t nc = -1;
};

// The sums of squares over the contacts one iteration's residuals come from (update_z_and_y).
struct Residuals {
    double prim2 = 0.0, dual2 = 0.0, nz2 = 0.0, ny2 = 0.0, comb = 0.0;
};

// One solve: the iterates, the systems W + rho R and the steps of the iteration.
class Solver {
   public:
    Solver(SolveContext &ctx, KeptSystem &kept);
    // Runs the solve into ctx.info and ctx.r; false when the kept systems are not worth
    // keeping (the first factorisation was refused or failed).
    bool run();

   private:
    void set_weights();
    void start_dual(bool warm);
    frix_status prepare_systems();
    ShiftedSystem *current(std::unique_ptr<ShiftedSystem> &system, uint64_t &values);
    frix_status iterate();
    bool update_x();
    Residuals update_z_and_y();
    frix_status stop_test(double light, double prim, double dual);
    frix_status balance_rho(double prim, double dual);
    frix_status refactor();
    void finish(frix_status status);

    SolveContext &ctx_;
    const first_order::Loop L_;
    const frix_problem &p_;
    const int64_t nc_, m_;
    KeptSystem &kept_;
    const Monitor monitor_;
    const bool adaptive_, accelerate_;
    const uint64_t w_values_;
    double wmax_ = 0.0, wmean_ = 0.0, rho_ = 0.0;
    // Contact a's penalty is rho * weight[a] (see set_weights).
    std::vector<double> weight_;
    std::vector<double> u_, x_, z_, y_, rhs_, s_;
    first_order::RestartedNesterov momentum_;
    ShiftedSystem *sys_ = nullptr;
    linalg::FactorStats start_before_, adapted_before_;
    bool skew_ = false;
    std::vector<double> kx_, kx_prev_, work_;  // K x (previous x), K x_prev, scratch
    double err_ = 0.0, tol_light_ = 0.0;
    int64_t it_ = 0, changes_ = 0, since_change_ = 0;
};

Solver::Solver(SolveContext &ctx, KeptSystem &kept)
    : ctx_(ctx),
      L_(ctx, "admm"),
      p_(ctx.problem),
      nc_(ctx.problem.nc),
      m_(L_.m),
      kept_(kept),
      monitor_(ctx),
      adaptive_(L_.o.i(FRIX_OPT_RHO_ADAPTIVE) != 0),
      accelerate_(L_.o.i(FRIX_OPT_ACCELERATION) != 0),
      w_values_(ctx.cache ? ctx.cache->w_values : 0),
      u_(m_), x_(m_), z_(m_), y_(m_), rhs_(m_), s_(nc_, 0.0),
      momentum_(accelerate_, m_) {
    first_order::diagonal_scales(p_, &wmax_, &wmean_);
    rho_ = L_.o.d(FRIX_OPT_RHO) * wmean_;
    set_weights();
}

// Contact a's penalty is rho * weight[a]: 1 (FRIX_RHO_CONSTANT), or |W_aa|_2 / mean_a |W_aa|_2
// (per contact): the same as ADMM with one rho on the problem scaled so that every |W_aa|_2
// is equal, which is what keeps it working when contacts differ in stiffness by decades.
void Solver::set_weights() {
    weight_.assign((size_t)nc_, 1.0);
    if (L_.o.i(FRIX_OPT_RHO_STRATEGY) == FRIX_RHO_CONSTANT) return;
    for (int64_t a = 0; a < nc_; ++a) {
        const double n = first_order::contact_diagonal_norm(p_, a);
        if (n > 0.0 && std::isfinite(n)) weight_[(size_t)a] = n / wmean_;
    }
}

bool Solver::run() {
    frix_info &info = ctx_.info;
    double *r = ctx_.r;
    // Warm start: z = P_K(r), y = -u^(r) / rho (the fixed point if r is a solution).
    std::copy(r, r + m_, z_.begin());
    first_order::project_on_cones(p_, z_.data());
    err_ = L_.error(z_.data(), u_.data());
    if (L_.warm(r) && err_ <= L_.tol) {
        std::copy(z_.begin(), z_.end(), r);
        info.status = FRIX_STATUS_CONVERGED;
        info.iterations = 0;
        return true;
    }
    start_dual(L_.warm(r));
    if (const frix_status refused = prepare_systems()) {
        info.status = refused;
        info.iterations = 0;
        return false;
    }
    momentum_.reset(z_.data(), y_.data());
    finish(iterate());
    return true;
}

// s = |u_T| (the De Saxce term is mu s) and y = -u^ / rho at a warm start (0 otherwise).
void Solver::start_dual(bool warm) {
    for (int64_t a = 0; a < nc_; ++a) {
        const double *ua = &u_[3 * a];
        s_[a] = std::sqrt(ua[1] * ua[1] + ua[2] * ua[2]);
        for (int i = 0; i < 3; ++i)
            y_[3 * a + i] = warm ? -(ua[i] + (i == 0 ? p_.mu[a] * s_[a] : 0.0)) / (rho_ * weight_[(size_t)a]) : 0.0;
    }
}

// Two systems: every solve starts at the same rho, and a persistent solver keeps that
// factorisation in `start` apart from the one rho adapts to (the solve after would otherwise
// find the last solve's rho factorised, not the one it starts with). Each is refilled with
// W's values when they changed, its analyses kept while the pattern stays. Returns the limit
// the first factorisation would overrun, or its failure; FRIX_STATUS_NOT_RUN when factorised.
frix_status Solver::prepare_systems() {
    if (!ctx_.cache || kept_.nc != nc_) {
        kept_.start.reset();
        kept_.adapted.reset();
        kept_.nc = nc_;
    }
    // Under a time or memory limit the first factorisation is priced before W + rho I is
    // even assembled (on a large W that and the ordering take long too): one that would
    // overrun a limit is not started.
    if (!kept_.start && m_ > kDenseMax && (monitor_.time_limited() || monitor_.memory_limited())) {
        linalg::FactorCost cost;
        if (block_cholesky_cost(*p_.W, &cost) != FRIX_OK) clear_error();
        else if (const frix_status over = monitor_.affords({cost.flops, NAN, cost.bytes})) return over;
    }
    sys_ = current(kept_.start, kept_.start_values);
    start_before_ = kept_.start->stats();
    adapted_before_ = kept_.adapted ? kept_.adapted->stats() : linalg::FactorStats();
    skew_ = sys_->skew();
    if (skew_) {
        kx_.assign(m_, 0.0);
        kx_prev_.assign(m_, 0.0);
        work_.assign(m_, 0.0);
        sys_->skew_product(*p_.W, z_.data(), kx_.data(), work_.data());  // x_prev ~ z for the first step
    }
    return refactor();
}

// The system for this solve: W's values, and this solve's time limit as the budget of its
// factorisations.
ShiftedSystem *Solver::current(std::unique_ptr<ShiftedSystem> &system, uint64_t &values) {
    if (!system) system = std::make_unique<ShiftedSystem>(*p_.W);
    else if (values != w_values_) system->refill(*p_.W);
    values = w_values_;
    system->set_budget(monitor_.budget());
    return system.get();
}

// Factorises the system at the current rho: FRIX_STATUS_NOT_RUN, or the limit it would
// overrun, or a numerical failure.
frix_status Solver::refactor() {
    if (sys_->factor(rho_, weight_) == FRIX_OK) return FRIX_STATUS_NOT_RUN;
    return sys_->refused() ? sys_->refused() : FRIX_STATUS_NUMERICAL_FAILURE;
}

frix_status Solver::iterate() {
    tol_light_ = L_.tol;
    frix_status status = FRIX_STATUS_NOT_RUN;
    while (status == FRIX_STATUS_NOT_RUN) {
        ++it_;
        ++since_change_;
        if (!update_x()) return FRIX_STATUS_NUMERICAL_FAILURE;
        const Residuals res = update_z_and_y();
        if (!std::isfinite(res.prim2 + res.dual2 + res.nz2 + res.ny2)) return FRIX_STATUS_DIVERGED;
        // Relative residuals: primal against |z|, dual against max(|u^| = rho |R y|, |q|).
        const double nz = std::max(std::sqrt(res.nz2), 1e-300);
        const double nu = std::max({rho_ * std::sqrt(res.ny2), L_.norm_q, 1e-300});
        const double prim = std::sqrt(res.prim2) / nz, dual = rho_ * std::sqrt(res.dual2) / nu;
        momentum_.advance(res.comb, z_.data(), y_.data());
        status = stop_test(std::max(prim, dual), prim, dual);
        if (status == FRIX_STATUS_NOT_RUN) status = balance_rho(prim, dual);
    }
    return status;
}

// x-update: (W + rho I) x = -(q + s) + rho (z^ - y^), with K x at the previous x when only
// S + rho I is factorised; then K x at the new x. False if the solve failed.
bool Solver::update_x() {
    const double *zh = momentum_.x_hat(), *yh = momentum_.y_hat();
    for (int64_t a = 0; a < nc_; ++a)
        for (int i = 0; i < 3; ++i) {
            const int64_t k = 3 * a + i;
            rhs_[k] = -(p_.q[k] + (i == 0 ? p_.mu[a] * s_[a] : 0.0)) + rho_ * weight_[(size_t)a] * (zh[k] - yh[k]);
            if (skew_) rhs_[k] -= kx_[k];
        }
    if (sys_->solve(rhs_.data(), x_.data()) != FRIX_OK) return false;
    if (skew_) {
        for (int64_t k = 0; k < m_; ++k) kx_prev_[k] = kx_[k];
        sys_->skew_product(*p_.W, x_.data(), kx_.data(), work_.data());
    }
    return true;
}

// z-update and dual update, and s from u = W x + q = -(mu s e_N) + rho (z^ - y^ - x)
// + K (x - x_prev).
Residuals Solver::update_z_and_y() {
    const double *zh = momentum_.x_hat(), *yh = momentum_.y_hat();
    Residuals res;
    for (int64_t a = 0; a < nc_; ++a) {
        double *za = &z_[3 * a];
        for (int i = 0; i < 3; ++i) za[i] = x_[3 * a + i] + yh[3 * a + i];
        coulomb::project_on_cone(za, p_.mu[a]);
        const double w = weight_[(size_t)a];
        double ua[3];
        for (int i = 0; i < 3; ++i) {
            const int64_t k = 3 * a + i;
            y_[k] = yh[k] + x_[k] - z_[k];
            ua[i] = rho_ * w * (zh[k] - yh[k] - x_[k]) - (i == 0 ? p_.mu[a] * s_[a] : 0.0);
            if (skew_) ua[i] += kx_[k] - kx_prev_[k];
            const double dz = w * (z_[k] - zh[k]), wy = w * y_[k];
            res.prim2 += (x_[k] - z_[k]) * (x_[k] - z_[k]);
            res.dual2 += dz * dz;
            res.comb += w * ((y_[k] - yh[k]) * (y_[k] - yh[k]) + (z_[k] - zh[k]) * (z_[k] - zh[k]));
            res.nz2 += z_[k] * z_[k];
            res.ny2 += wy * wy;
        }
        s_[a] = std::sqrt(ua[1] * ua[1] + ua[2] * ua[2]);
    }
    return res;
}

// Stopping: the full error of z, confirmed by the measures module, when the light error
// (the relative residuals) passes its tolerance, recalibrated on each full check, or every
// kFullCheckPeriod iterations.
frix_status Solver::stop_test(double light, double prim, double dual) {
    const bool full = light <= tol_light_ || it_ % kFullCheckPeriod == 0;
    if (full) {
        err_ = L_.error(z_.data(), u_.data());
        if (!(err_ <= L_.tol) && std::isfinite(err_) && light > 0.0) tol_light_ = light / err_ * L_.tol;
    }
    if (L_.verbosity >= 2 || (L_.verbosity >= 1 && full))
        log_line(&L_.o, "admm: iteration %lld rho %.3e primal %.3e dual %.3e%s%.3e", (long long)it_, rho_ / wmean_,
                 prim, dual, full ? " full " : " tol_light ", full ? err_ : tol_light_);
    return full ? L_.verdict(it_, err_, z_.data()) : L_.limits(it_, light, z_.data());
}

// Residual balancing: rho <- rho sqrt(primal / dual) when that changes it 5-fold. A primal
// residual of exactly 0 (x inside the cones, y = 0: the iteration is a plain proximal step,
// as slow as rho is large) lowers rho by kZeroPrimalStep. FRIX_STATUS_NOT_RUN to go on.
frix_status Solver::balance_rho(double prim, double dual) {
    if (!adaptive_ || since_change_ < kBalancePeriod || !(dual > 0.0)) return FRIX_STATUS_NOT_RUN;
    const double balanced = prim == 0.0 ? rho_ / kZeroPrimalStep : rho_ * std::sqrt(prim / dual);
    const double target = std::clamp(balanced, kRhoMin * wmean_, kRhoMax * wmean_);
    if (!(target > kBalanceFactor * rho_ || target * kBalanceFactor < rho_)) return FRIX_STATUS_NOT_RUN;
    const double ratio = rho_ / target;
    for (int64_t k = 0; k < m_; ++k) y_[k] *= ratio;  // the unscaled dual rho y stays
    momentum_.reset(z_.data(), y_.data());
    rho_ = target;
    since_change_ = 0;
    ++changes_;
    // The start's factorisation stays for the next solve.
    if (ctx_.cache) sys_ = current(kept_.adapted, kept_.adapted_values);
    return refactor();
}

// z (in K) is the result; after a failure the last z is still finite.
void Solver::finish(frix_status status) {
    frix_info &info = ctx_.info;
    bool finite = true;
    for (int64_t k = 0; k < m_ && finite; ++k) finite = std::isfinite(z_[k]);
    if (finite) std::copy(z_.begin(), z_.end(), ctx_.r);
    info.status = status;
    info.iterations = it_;
    const linalg::FactorStats fs = (kept_.start->stats() - start_before_) +
                                   (kept_.adapted ? kept_.adapted->stats() - adapted_before_ : linalg::FactorStats());
    Monitor::record_factorizations(info, fs);
    if (L_.verbosity >= 1)
        log_line(&L_.o, "admm: %s after %lld iterations (%s %s, %lld rho changes, %lld restarts)",
                 frix_status_string(status), (long long)it_, sys_->dense() ? "dense" : "sparse", sys_->kind(),
                 (long long)changes_, (long long)momentum_.restarts());
}

frix_error solve(SolveContext &ctx) {
    if (!ctx.problem.W || !ctx.problem.W->block) return fail(FRIX_ERR_INTERNAL, "admm: W is not stored as 3x3 blocks");
    Kept<KeptSystem> kept(ctx.cache, FRIX_SOLVER_ADMM);
    if (Solver(ctx, *kept).run()) kept.keep();
    return FRIX_OK;
}

const frix_option_key kExtraKeys[] = {FRIX_OPT_RHO, FRIX_OPT_RHO_ADAPTIVE, FRIX_OPT_ACCELERATION,
                                      FRIX_OPT_RHO_STRATEGY, (frix_option_key)0};

const OptionDefault kDefaults[] = {{FRIX_OPT_MAX_ITER, 100000},
                                   {FRIX_OPT_RHO, 1.0},
                                   {FRIX_OPT_RHO_ADAPTIVE, 1},
                                   {FRIX_OPT_ACCELERATION, 1},
                                   {FRIX_OPT_RHO_STRATEGY, FRIX_RHO_CONSTANT},
                                   {(frix_option_key)0, 0}};

}  // namespace
}  // namespace admm

const SolverEntry kAdmmEntry = {
    FRIX_SOLVER_ADMM, "admm", "FRICTION_3D_ADMM",
    "ADMM on the splitting r = z of min 1/2 r'W r + (q + s)'r over the cones, the De Saxce "
    "term s = mu |u_T| e_N updated every iteration (Siconos' ADMM): one solve with the "
    "factorised W + rho I and one projection per iteration, Nesterov acceleration with "
    "restart, rho balanced between the relative primal and dual residuals (checked every 25 "
    "iterations, changed only 5-fold or more: each change refactorises). W + rho I is "
    "factorised by Cholesky (dense LAPACK up to 240 unknowns, CHOLMOD above); an unsymmetric "
    "W is split into its symmetric part, factorised, and a skew part applied at the previous "
    "iterate (exact at the fixed point), or LU when the skew part exceeds 1% of W. W + rho I is "
    "regular even where W is rank-deficient; memory O(nnz of the factor). Options: rho "
    "(initial penalty, in units of mean_a |W_aa|_2), rho_strategy (0: one penalty for all "
    "contacts; 1 or 2: contact a's penalty scaled by |W_aa|_2 / mean, i.e. ADMM on the "
    "problem scaled to equal |W_aa|, for contacts whose stiffness differs by decades), "
    "rho_adaptive (0: keep rho), acceleration (0: plain ADMM).",
    admm::solve, true, false, admm::kExtraKeys, admm::kDefaults};

}  // namespace frix
