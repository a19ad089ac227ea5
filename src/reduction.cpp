#include "reduction.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <new>

#include "disjoint_sets.hpp"
#include "memory.hpp"
#include "monitor.hpp"
#include "random.hpp"

namespace frix {

namespace {

// Where W could take more than kStructureAbove, its structure is looked at for a tighter
// bound (forming W reserves that much address space).
constexpr double kStructureAbove = 256e6;

}  // namespace

frix_error to_csc(const frix_matrix &A, Csc &out) {
    out.rows = A.rows;
    out.cols = A.cols;
    int64_t nnz = 0;
    if (frix_error e = frix_matrix_to_csc(&A, &nnz, nullptr, nullptr, nullptr)) return e;
    out.colptr.resize(A.cols + 1);
    assign_advised(out.rowind, (size_t)std::max<int64_t>(nnz, 1));
    assign_advised(out.val, (size_t)std::max<int64_t>(nnz, 1));
    return frix_matrix_to_csc(&A, &nnz, out.colptr.data(), out.rowind.data(), out.val.data());
}

namespace {

// f(i, j, m_ij, m_ji) once for every pair of mirrored places off the diagonal where M stores
// an entry (a mirror not stored is 0; an entry below a square part has none), in one pass:
// each entry above the diagonal, (i, j) with i < j, meets its mirror (j, i) below the diagonal
// of column i, and in increasing j those are read in order, from next[i] on (column i's first
// row past i); one passed over, or left at the end, has no entry above.
template <class F>
void for_each_mirrored_pair(const linalg::CscView &M, F &&f) {
    std::vector<int64_t> next((size_t)M.cols);
    for (int64_t i = 0; i < M.cols; ++i)
        next[(size_t)i] = std::upper_bound(M.rowind + M.colptr[i], M.rowind + M.colptr[i + 1], i) - M.rowind;
    for (int64_t j = 0; j < M.cols; ++j)
        for (int64_t e = M.colptr[j]; e < M.colptr[j + 1]; ++e) {
            const int64_t i = M.rowind[e];
            if (i >= j) {
                if (i >= M.cols) f(i, j, M.values[e], 0.0);  // below a square part
                continue;
            }
            int64_t &k = next[(size_t)i];
            for (; k < M.colptr[i + 1] && M.rowind[k] < j; ++k) f(i, M.rowind[k], 0.0, M.values[k]);
            const bool mirrored = k < M.colptr[i + 1] && M.rowind[k] == j;
            f(i, j, M.values[e], mirrored ? M.values[k++] : 0.0);
        }
    for (int64_t i = 0; i < M.cols; ++i)
        for (int64_t k = next[(size_t)i]; k < M.colptr[i + 1] && M.rowind[k] < M.cols; ++k)
            f(i, M.rowind[k], 0.0, M.values[k]);
}

}  // namespace

double relative_asymmetry(const linalg::CscView &M) {
    double amax = 0.0, skew = 0.0;
    for (int64_t e = 0; e < M.nnz(); ++e) amax = std::max(amax, std::fabs(M.values[e]));
    for_each_mirrored_pair(M, [&](int64_t, int64_t, double a, double b) { skew = std::max(skew, std::fabs(a - b)); });
    return amax > 0.0 ? skew / amax : 0.0;
}

namespace {

// The pairwise test: every mirrored pair within kRoundOff sqrt(|W_ii W_jj|). Where a diagonal
// entry is zero, the one-pass test's scaling has nothing to divide by.
bool mirrored_pairs_agree(const linalg::CscView &W, const std::vector<double> &diag) {
    bool symmetric = true;
    for_each_mirrored_pair(W, [&](int64_t i, int64_t j, double a, double b) {
        symmetric = symmetric && std::fabs(a - b) <= kRoundOff * std::sqrt(diag[(size_t)i] * diag[(size_t)j]);
    });
    return symmetric;
}

// The seed of the one-pass test's vector: a fixed one, so that the verdict is the same on
// every run.
constexpr uint64_t kSymmetrySeed = 0x5EED5EEDull;

}  // namespace

bool symmetric_at_every_scale(const linalg::CscView &W, const double *diagonal) {
    if (W.rows != W.cols) return false;
    const int64_t n = W.cols;
    std::vector<double> diag((size_t)n, 0.0);
    bool positive = true;
    for (int64_t j = 0; j < n; ++j) {
        if (diagonal) {
            diag[(size_t)j] = std::fabs(diagonal[j]);
        } else {
            const int64_t *first = W.rowind + W.colptr[j], *last = W.rowind + W.colptr[j + 1];
            const int64_t *at = std::lower_bound(first, last, j);
            if (at != last && *at == j) diag[(size_t)j] = std::fabs(W.values[at - W.rowind]);
        }
        positive = positive && diag[(size_t)j] > 0.0 && std::isfinite(diag[(size_t)j]);
    }
    if (!positive) return mirrored_pairs_agree(W, diag);
    // x_j = +-[1/2, 1) / sqrt(W_jj): y = W x and z = W^T x in one pass by columns, and each
    // row's terms' magnitudes beside them.
    std::vector<double> x((size_t)n), y((size_t)n, 0.0), z((size_t)n), size((size_t)n, 0.0);
    uint64_t state = kSymmetrySeed;
    for (int64_t j = 0; j < n; ++j) {
        const double u = next_uniform(state);  // its half gives the sign, its value the size
        x[(size_t)j] = (u < 0.5 ? -(0.5 + u) : u) / std::sqrt(diag[(size_t)j]);
    }
    bool bounded = true;  // every |W_ij| <= sqrt(W_ii W_jj), as where W is positive semidefinite
    for (int64_t j = 0; j < n; ++j) {
        const double xj = x[(size_t)j], bound = (1.0 + 1e-8) * std::sqrt(diag[(size_t)j]);
        double zj = 0.0, size_j = 0.0, largest = 0.0;
        for (int64_t e = W.colptr[j]; e < W.colptr[j + 1]; ++e) {
            const int64_t i = W.rowind[e];
            const double w = W.values[e], xi = x[(size_t)i];
            y[(size_t)i] += w * xj;
            size[(size_t)i] += std::fabs(w * xj);
            zj += w * xi;
            size_j += std::fabs(w * xi);
            largest = std::max(largest, std::fabs(w * xi));  // |x_i| < 1 / sqrt(W_ii)
        }
        z[(size_t)j] = zj;
        size[(size_t)j] += size_j;
        bounded = bounded && largest <= bound;
    }
    // Unbounded entries would loosen their rows' tolerance without limit.
    if (!bounded) return mirrored_pairs_agree(W, diag);
    for (int64_t i = 0; i < n; ++i)
        if (!(std::fabs(y[(size_t)i] - z[(size_t)i]) <= kRoundOff * size[(size_t)i])) return false;
    return true;
}

frix_error MassSolver::solve_load(const double *f, int64_t n, double *x, bool keep_loads) {
    if ((int64_t)load_.size() == n && std::equal(f, f + n, load_.begin())) {
        std::copy(load_x_.begin(), load_x_.end(), x);
        return FRIX_OK;
    }
    load_.clear();
    const bool span =
        keep_loads && use_chol_ && !empty_ && chol_.cost().factor_entries >= 2.0 * (double)csc_.view().nnz();
    bool answered = false;
    // The span only saves solves: where it cannot allocate, it is forgotten and M solves.
    try {
        answered = span && span_.answer(f, csc_.view(), x);
    } catch (const std::bad_alloc &) {
        span_.clear();
    }
    if (!answered) {
        if (frix_error e = solve(f, x)) return e;
        try {
            if (span) span_.add(f, x, n);
        } catch (const std::bad_alloc &) {
            span_.clear();
        }
    }
    load_.assign(f, f + n);
    load_x_.assign(x, x + n);
    return FRIX_OK;
}

frix_error MassSolver::analyse_counted(const frix_matrix &M) {
    load_.clear();
    span_.clear();
    factored_ = false;
    refused_ = FRIX_STATUS_NOT_RUN;
    empty_ = M.rows == 0;  // no dofs: M^-1 is the empty map, W = 0 and q = w
    if (empty_) {
        factored_ = true;
        return FRIX_OK;
    }
    if (frix_error e = to_csc(M, csc_)) return e;
    symmetric_ = is_symmetric(csc_);
    use_chol_ = false;
    if (symmetric_) {
        linalg::FactorCost cost;
        if (chol_.analyze(csc_.view(), &cost) == FRIX_OK) {
            use_chol_ = true;
            return FRIX_OK;
        }
        clear_error();  // LU's analysis may still take it
    }
    return factor_lu();
}

frix_error MassSolver::numeric_counted() {
    if (use_chol_) {
        const frix_error e = chol_.factor(csc_.view());
        refused_ = chol_.refused();
        if (e == FRIX_OK || refused_) {
            use_chol_ = e == FRIX_OK;
            factored_ = e == FRIX_OK;
            return e;
        }
    }
    return factor_lu();
}

// UMFPACK's LU, where M is not symmetric or no Cholesky factorisation takes it.
frix_error MassSolver::factor_lu() {
    use_chol_ = false;
    if (frix_error e = lu_.analyze(csc_.view())) return e;
    if (frix_error e = lu_.factor(csc_.view())) {
        refused_ = lu_.refused();
        if (refused_) return e;
        // A copy: fail() writes the buffer frix_last_error_message() points to.
        const std::string why = frix_last_error_message();
        return fail(e, "global problem: M cannot be factorised (%s)", why.c_str());
    }
    factored_ = true;
    return FRIX_OK;
}

frix_error MassSolver::not_factored() {
    return fail(FRIX_ERR_INTERNAL, "global problem: M was analysed, not factorised, before a solve with it");
}

frix_error MassSolver::inverse_diagonal(const Csc &B, std::vector<double> &diag) {
    const int64_t n = B.rows, k = B.cols;
    diag.assign(k, 0.0);
    if (empty_) return FRIX_OK;
    if (!factored_) return not_factored();
    if (use_chol_) {
        std::vector<int64_t> colptr, rowind;
        std::vector<double> values;
        if (frix_error e = chol_.inverse_congruence(B.view(), colptr, rowind, values)) return e;
        for (int64_t j = 0; j < k; ++j)
            for (int64_t e = colptr[j]; e < colptr[j + 1]; ++e)
                if (rowind[e] == j) diag[j] = values[e];
        return FRIX_OK;
    }
    std::vector<double> b(n), x(n);
    for (int64_t j = 0; j < k; ++j) {
        std::fill(b.begin(), b.end(), 0.0);
        for (int64_t e = B.colptr[j]; e < B.colptr[j + 1]; ++e) b[B.rowind[e]] = B.val[e];
        if (frix_error e = solve(b.data(), x.data())) return e;
        for (int64_t e = B.colptr[j]; e < B.colptr[j + 1]; ++e) diag[j] += B.val[e] * x[B.rowind[e]];
    }
    return FRIX_OK;
}

bool is_symmetric(const linalg::CscView &M) { return relative_asymmetry(M) <= kRoundOff; }

ReductionSize reduction_size(const frix_problem &p) {
    ReductionSize size;
    size.structural = true;
    DisjointSets components(p.n);
    // Exact zeros (of a stored 3x3 block) couple nothing.
    for_each_entry(*p.M, [&](int64_t i, int64_t j, double v) {
        if (v == 0.0) return;
        components.unite(i, j);
        size.input_entries += 1.0;
    });
    // The (component, column of H) pairs, each counted once: H's columns bucketed by the
    // component of the entry's row (a counting sort, O(nnz(H)): sorting the pairs was the
    // largest serial cost of a solve at 10^6 contacts), each bucket in column order.
    std::vector<int64_t> root_of((size_t)p.n), start((size_t)p.n + 1, 0);
    for (int64_t i = 0; i < p.n; ++i) root_of[(size_t)i] = components.find(i);
    if (p.nc > 0)
        for_each_entry(*p.H, [&](int64_t i, int64_t, double v) {
            if (v != 0.0) ++start[(size_t)root_of[(size_t)i] + 1];
        });
    for (int64_t i = 0; i < p.n; ++i) start[(size_t)i + 1] += start[(size_t)i];
    std::vector<int64_t> columns((size_t)start[(size_t)p.n]);
    if (p.nc > 0) {
        std::vector<int64_t> next(start.begin(), start.end() - 1);
        for_each_entry(*p.H, [&](int64_t i, int64_t c, double v) {
            if (v != 0.0) columns[(size_t)next[(size_t)root_of[(size_t)i]]++] = c;
        });
    }
    size.input_entries += (double)columns.size();
    for (int64_t i = 0; i < p.n; ++i)
        if (root_of[(size_t)i] == i) size.largest_component = std::max(size.largest_component, components.size_of_root(i));
    // Per component, the columns and the contacts (3 columns each, in order) touching it.
    double bound = 0.0, block_bound = 0.0;
    for (int64_t root = 0; root < p.n; ++root) {
        const auto first = columns.begin() + start[(size_t)root], last = columns.begin() + start[(size_t)root + 1];
        if (first == last) continue;
        if (!std::is_sorted(first, last)) std::sort(first, last);
        double touching = 0.0, contacts = 0.0;
        for (auto it = first; it != last; ++it) {
            if (it != first && *it == *(it - 1)) continue;
            touching += 1.0;
            size.product_entries += (double)components.size_of_root(root);
            if (it == first || *it / 3 != *(it - 1) / 3) contacts += 1.0;
        }
        bound += touching * touching;
        block_bound += contacts * contacts;
    }
    const double full = 3.0 * (double)p.nc;
    size.w_entries = std::min(bound, full * full);
    size.w_blocks = std::min(block_bound, (double)p.nc * (double)p.nc);
    return size;
}

ReductionSize reduction_bound(const frix_problem &p) {
    // W has at most nc^2 blocks: the structure is looked at only where that much could be
    // worth it (above 1800 contacts or so; on rigid bodies W has far fewer).
    ReductionSize size;
    size.w_blocks = (double)p.nc * (double)p.nc;
    size.w_entries = 9.0 * size.w_blocks;
    if (kBytesPerReducedBlock * size.w_blocks >= kStructureAbove) size = reduction_size(p);
    return size;
}

ReductionMemory reduction_memory(const ReductionSize &size, const Monitor &monitor) {
    ReductionMemory m;
    m.needed = kBytesPerReducedBlock * size.w_blocks;
    m.fits = monitor.fits_memory(m.needed);
    if (!m.fits) m.available = monitor.memory_left();
    return m;
}

frix_error recover_velocity(const frix_problem &p, const MassSolver &ms, const double *r, double *v) {
    std::vector<double> b(p.f, p.f + p.n);
    if (p.nc > 0) matrix_gemv(*p.H, 1.0, r, 1.0, b.data());
    return ms.solve(b.data(), v);
}

}  // namespace frix
