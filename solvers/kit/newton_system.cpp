// The local Newton's linear algebra (newton.hpp's Engine): the active contacts, the pattern of
// their Jacobian A + B (W + shift I) from W's 3 x 3 blocks, its assembly and factorisation
// (UMFPACK, or a dense LU for small systems), and the Newton direction.
#include <cmath>

#include "solvers/kit/newton.hpp"
#include "solvers/kit/nsn_functions.hpp"
#include "src/matrix.hpp"

namespace frix {
namespace newton {

namespace {

// Active systems up to this size are factorised dense (LAPACK): a 60 x 60 LU costs less than
// UMFPACK's fixed overhead.
constexpr int64_t kDenseMax = 60;

}  // namespace

linalg::FactorStats Engine::total_stats() const {
    linalg::FactorStats s = lu_.stats();
    s.numeric += dense_lu_.stats().numeric;
    s.seconds += dense_lu_.stats().seconds;
    return s;
}

linalg::FactorStats Engine::factor_stats() const { return total_stats() - stats_before_; }

Engine::Engine(const frix_matrix &W, const double *mu, int64_t nc, const Settings &s)
    : W_(&W), nc_(nc), m_(3 * nc), rho_n_(nc), rho_t_(nc), A_(9 * nc), B_(9 * nc) {
    index_.assign(nc, 0);
    rebind(W, mu, s);
}

void Engine::rebind(const frix_matrix &W, const double *mu, const Settings &s) {
    static const double kZero[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
    W_ = &W;
    mu_ = mu;
    s_ = s;
    double scale = 0.0;
    for (int64_t a = 0; a < nc_; ++a) {
        const int64_t d = W.diag_index[a];
        const double *Waa = d >= 0 ? &W.block_val[9 * d] : kZero;
        nsn::contact_rho(s.rho_strategy, s.rho, Waa, &rho_n_[a], &rho_t_[a]);
        double fro = 0.0;
        for (int i = 0; i < 9; ++i) fro += Waa[i] * Waa[i];
        scale += std::sqrt(fro);
    }
    w_scale_ = nc_ > 0 && scale > 0.0 ? scale / (double)nc_ : 1.0;
    counters = Counters();
    full_step_on_failure = false;
    analysed_ = false;  // the active set is found afresh, as by a new engine
    stats_before_ = total_stats();
}

// Contacts whose Phi does not depend on u (B_a = 0, A_a = I: separating ones) have the
// Newton step d_a = -Phi_a outright and drop out of the linear system; the others are
// "active". The system's pattern is W's block pattern on the active contacts plus their
// diagonal blocks: it changes only when contacts join the active set, and is analysed again
// only then. On granular scenes, where many contacts separate, the system is much smaller
// than W.
bool Engine::update_active() {
    bool changed = !analysed_;
    for (int64_t a = 0; a < nc_; ++a) {
        const double *A = &A_[9 * a], *B = &B_[9 * a];
        bool free = A[0] == 1.0 && A[4] == 1.0 && A[8] == 1.0;
        for (int i = 0; i < 9 && free; ++i) free = B[i] == 0.0 && (i % 4 == 0 || A[i] == 0.0);
        // Only joining contacts change the pattern: one that separates stays in the system
        // (its rows are then the identity), so that the active set, and with it the
        // analysis, settles after a few steps instead of following every change.
        if (!analysed_) {
            index_[a] = free ? -1 : 0;
        } else if (!free && index_[a] < 0) {
            changed = true;
            index_[a] = 0;
        }
    }
    if (!changed) return false;
    int64_t k = 0;
    for (int64_t a = 0; a < nc_; ++a)
        if (index_[a] >= 0) index_[a] = k++;
    n_active_ = k;
    build_pattern();
    return true;
}

void Engine::build_pattern() {
    const int64_t nb = W_->nblocks();
    const int64_t na = n_active_;
    std::vector<int64_t> count(na, 0);  // blocks per active block column
    for (int64_t a = 0; a < nc_; ++a) {
        if (index_[a] < 0) continue;
        if (W_->diag_index[a] < 0) ++count[index_[a]];
        for (int64_t b = W_->row_ptr[a]; b < W_->row_ptr[a + 1]; ++b)
            if (index_[W_->block_col[b]] >= 0) ++count[index_[W_->block_col[b]]];
    }
    std::vector<int64_t> start(na + 1, 0);
    for (int64_t c = 0; c < na; ++c) start[c + 1] = start[c] + 9 * count[c];
    colptr_.assign(3 * na + 1, 0);
    for (int64_t c = 0; c < na; ++c)
        for (int j = 0; j < 3; ++j) colptr_[3 * c + j + 1] = start[c] + (j + 1) * 3 * count[c];
    rowind_.assign(start[na], 0);
    values_.assign(start[na], 0.0);
    block_pos_.assign(nb, -1);
    block_stride_.assign(nb, 0);
    diag_pos_.assign(nc_, -1);
    diag_stride_.assign(nc_, 0);
    // Active block rows in increasing order: each column's list of block rows comes out sorted.
    std::vector<int64_t> fill(na, 0);
    auto place = [&](int64_t ia, int64_t ic) {
        const int64_t pos = start[ic] + 3 * fill[ic]++, stride = 3 * count[ic];
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 3; ++i) rowind_[pos + j * stride + i] = 3 * ia + i;
        return pos;
    };
    for (int64_t a = 0; a < nc_; ++a) {
        const int64_t ia = index_[a];
        if (ia < 0) continue;
        bool placed_diag = W_->diag_index[a] >= 0;
        for (int64_t b = W_->row_ptr[a]; b < W_->row_ptr[a + 1]; ++b) {
            const int64_t c = W_->block_col[b], ic = index_[c];
            if (ic < 0) continue;
            if (!placed_diag && c > a) {
                diag_pos_[a] = place(ia, ia);
                diag_stride_[a] = 3 * count[ia];
                placed_diag = true;
            }
            block_pos_[b] = place(ia, ic);
            block_stride_[b] = 3 * count[ic];
        }
        if (!placed_diag) {
            diag_pos_[a] = place(ia, ia);
            diag_stride_[a] = 3 * count[ia];
        }
    }
}

void Engine::evaluate(const double *r, const double *u, bool jacobian, double *phi) {
    for (int64_t a = 0; a < nc_; ++a)
        nsn::contact_function(s_.formulation, r + 3 * a, u + 3 * a, mu_[a], rho_n_[a], rho_t_[a],
                              phi + 3 * a, jacobian ? &A_[9 * a] : nullptr,
                              jacobian ? &B_[9 * a] : nullptr);
}

void Engine::assemble(double shift) {
    double *val = values_.data();
    for (int64_t a = 0; a < nc_; ++a) {
        if (index_[a] < 0) continue;
        const double *A = &A_[9 * a], *B = &B_[9 * a];
        // J_aa = A + shift B + B W_aa (the last term added with W's diagonal block below).
        double D[9];
        for (int i = 0; i < 9; ++i) D[i] = A[i] + shift * B[i];
        if (W_->diag_index[a] < 0) {
            const int64_t pos = diag_pos_[a], st = diag_stride_[a];
            for (int j = 0; j < 3; ++j)
                for (int i = 0; i < 3; ++i) val[pos + j * st + i] = D[i + 3 * j];
        }
        for (int64_t b = W_->row_ptr[a]; b < W_->row_ptr[a + 1]; ++b) {
            const int64_t pos = block_pos_[b], st = block_stride_[b];
            if (pos < 0) continue;  // column of a separating contact
            const double *Wb = &W_->block_val[9 * b];
            const bool diag = W_->block_col[b] == a;
            for (int j = 0; j < 3; ++j)
                for (int i = 0; i < 3; ++i) {
                    double v = B[i] * Wb[3 * j] + B[i + 3] * Wb[3 * j + 1] + B[i + 6] * Wb[3 * j + 2];
                    if (diag) v += D[i + 3 * j];
                    val[pos + j * st + i] = v;
                }
        }
    }
}

// The Newton step d from the factorised active system: d_a = -Phi_a on separating contacts,
// then the active ones with those moved to the right-hand side.
frix_error Engine::step(const double *phi, double *d, double *rhs, double *x) {
    for (int64_t a = 0; a < nc_; ++a)
        if (index_[a] < 0)
            for (int i = 0; i < 3; ++i) d[3 * a + i] = -phi[3 * a + i];
    if (n_active_ == 0) return FRIX_OK;
    for (int64_t a = 0; a < nc_; ++a) {
        const int64_t ia = index_[a];
        if (ia < 0) continue;
        double t[3] = {0.0, 0.0, 0.0};
        for (int64_t b = W_->row_ptr[a]; b < W_->row_ptr[a + 1]; ++b)
            if (index_[W_->block_col[b]] < 0)
                block_gemv_add(&W_->block_val[9 * b], &d[3 * W_->block_col[b]], t);
        const double *B = &B_[9 * a];
        for (int i = 0; i < 3; ++i)
            rhs[3 * ia + i] = -phi[3 * a + i] - (B[i] * t[0] + B[i + 3] * t[1] + B[i + 6] * t[2]);
    }
    if (frix_error e = use_dense_ ? dense_lu_.solve(rhs, x) : lu_.solve(rhs, x)) return e;
    for (int64_t a = 0; a < nc_; ++a)
        if (index_[a] >= 0)
            for (int i = 0; i < 3; ++i) d[3 * a + i] = x[3 * index_[a] + i];
    return FRIX_OK;
}

frix_error Engine::prepare(double shift) {
    const bool new_pattern = update_active();
    const int64_t ma = 3 * n_active_;
    use_dense_ = ma <= kDenseMax;
    // A persistent solver's engine keeps the analysis of the active set it last analysed:
    // when a later solve finds the same set, the analysis still holds.
    if (ma > 0 && new_pattern && !use_dense_ && index_ != analysed_index_) {
        assemble(shift);
        analysed_index_.clear();
        if (frix_error e = lu_.analyze(linalg::CscView{ma, ma, colptr_.data(), rowind_.data(), values_.data()}))
            return e;
        analysed_index_ = index_;
    }
    return FRIX_OK;
}

frix_error Engine::factor(double shift, kit::Factorisation &f) {
    const int64_t ma = 3 * n_active_;
    if (ma == 0) {  // every contact separates: d = -Phi
        f.factored = true;
        return FRIX_OK;
    }
    assemble(shift);
    frix_error e;
    if (use_dense_) {
        dense_.assign((size_t)(ma * ma), 0.0);
        for (int64_t j = 0; j < ma; ++j)
            for (int64_t k = colptr_[j]; k < colptr_[j + 1]; ++k) dense_[(size_t)(rowind_[k] + ma * j)] = values_[k];
        e = dense_lu_.factor(ma, dense_.data(), ma);
        f.factored = e == FRIX_OK && dense_lu_.rcond() > 1e-15;
    } else {
        e = lu_.factor(linalg::CscView{ma, ma, colptr_.data(), rowind_.data(), values_.data()});
        f.factored = e == FRIX_OK && lu_.rcond() > 1e-15;
        f.refused = lu_.refused();
    }
    return e == FRIX_ERR_OUT_OF_MEMORY ? e : FRIX_OK;
}

}  // namespace newton
}  // namespace frix
