#include "solvers/kit/mass_plus_contacts.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "src/error_state.hpp"
#include "src/measures.hpp"
#include "src/vec.hpp"

namespace frix {

frix_error MassPlusContacts::build(const Csc &M, const Csc &H, int64_t nc, const char *solver, ContactBlocks blocks,
                                   std::vector<int64_t> mass_ordering) {
    const double asymmetry = relative_asymmetry(M);
    if (asymmetry > kMassSkewMax)
        return fail(FRIX_ERR_UNSUPPORTED,
                    "%s factorises M + H S H^T by Cholesky and needs a symmetric M (here max |M_ij - M_ji| is "
                    "%.3g of max |M_ij|); gnsn-ac (607) solves a problem whose M is not",
                    solver, asymmetry);
    skewed_ = asymmetry > 0.0;
    chol_.drop_single_copy();  // of a factorisation of the matrix built before
    single_dropped_ = false;
    misses_in_a_row_ = 0;
    const int64_t n = M.rows;
    // Every contact's rows: the union over its 3 columns of H, sorted.
    row_start_.assign(nc + 1, 0);
    rows_.clear();
    std::vector<int64_t> mark(n, -1);
    for (int64_t a = 0; a < nc; ++a) {
        const size_t first = rows_.size();
        for (int c = 0; c < 3; ++c)
            for (int64_t e = H.colptr[3 * a + c]; e < H.colptr[3 * a + c + 1]; ++e)
                if (mark[H.rowind[e]] != a) {
                    mark[H.rowind[e]] = a;
                    rows_.push_back(H.rowind[e]);
                }
        std::sort(rows_.begin() + first, rows_.end());
        row_start_[a + 1] = (int64_t)rows_.size();
    }
    hrows_.assign(3 * rows_.size(), 0.0);
    for (int64_t a = 0; a < nc; ++a) {
        const int64_t *first = rows_.data() + row_start_[a], *last = rows_.data() + row_start_[a + 1];
        for (int c = 0; c < 3; ++c)
            for (int64_t e = H.colptr[3 * a + c]; e < H.colptr[3 * a + c + 1]; ++e) {
                const int64_t i = std::lower_bound(first, last, H.rowind[e]) - rows_.data();
                hrows_[3 * i + c] = H.val[e];
            }
    }
    // Every contact's pairs of rows (i <= j) that its blocks can couple.
    const auto couples = [&](int64_t i, int64_t j) {
        if (blocks == ContactBlocks::kAny || i == j) return true;
        for (int c = 0; c < 3; ++c)
            if (hrows_[3 * i + c] != 0.0 && hrows_[3 * j + c] != 0.0) return true;
        return false;
    };
    pair_start_.assign(nc + 1, 0);
    pairs_.clear();
    for (int64_t a = 0; a < nc; ++a) {
        for (int64_t i = row_start_[a]; i < row_start_[a + 1]; ++i)
            for (int64_t j = i; j < row_start_[a + 1]; ++j)
                if (couples(i, j)) pairs_.push_back({i, j, 0});
        pair_start_[a + 1] = (int64_t)pairs_.size();
    }
    // The pattern, upper triangle: M's entries (row <= column after folding), every contact's
    // pairs and every diagonal entry (so that the pattern holds one even where M's is missing),
    // bucketed by column (counted, then placed: no sort of all entries), each column then
    // sorted and its duplicates dropped.
    const auto each_entry = [&](const auto &emit) {
        for (int64_t j = 0; j < n; ++j)
            for (int64_t e = M.colptr[j]; e < M.colptr[j + 1]; ++e)
                emit(std::min(j, M.rowind[e]), std::max(j, M.rowind[e]));
        for (const Pair &pair : pairs_) emit(rows_[pair.i], rows_[pair.j]);  // rows_ ascends
        for (int64_t j = 0; j < n; ++j) emit(j, j);
    };
    std::vector<int64_t> start(n + 1, 0);
    each_entry([&](int64_t, int64_t col) { ++start[col + 1]; });
    for (int64_t j = 0; j < n; ++j) start[j + 1] += start[j];
    std::vector<int64_t> rows(start[n]), next(start.begin(), start.end() - 1);
    each_entry([&](int64_t row, int64_t col) { rows[next[col]++] = row; });
    A_.rows = A_.cols = n;
    A_.colptr.assign(n + 1, 0);
    A_.rowind.clear();
    for (int64_t j = 0; j < n; ++j) {
        const auto first = rows.begin() + start[j], last = rows.begin() + start[j + 1];
        std::sort(first, last);
        A_.rowind.insert(A_.rowind.end(), first, std::unique(first, last));
        A_.colptr[j + 1] = (int64_t)A_.rowind.size();
    }
    A_.val.assign(A_.rowind.size(), 0.0);
    auto slot = [&](int64_t row, int64_t col) {
        const int64_t *first = A_.rowind.data() + A_.colptr[col], *last = A_.rowind.data() + A_.colptr[col + 1];
        return std::lower_bound(first, last, row) - A_.rowind.data();
    };
    m_slot_.clear();
    m_val_.clear();
    // The symmetric part (M + M^T) / 2: every entry adds half its value to the upper one of
    // its pair (the diagonal all of it); for a symmetric M the halves add up to M's values.
    for (int64_t j = 0; j < n; ++j)
        for (int64_t e = M.colptr[j]; e < M.colptr[j + 1]; ++e) {
            const int64_t i = M.rowind[e];
            m_slot_.push_back(slot(std::min(i, j), std::max(i, j)));
            m_val_.push_back(i == j ? M.val[e] : 0.5 * M.val[e]);
        }
    for (Pair &pair : pairs_) pair.slot = slot(rows_[pair.i], rows_[pair.j]);
    // Within M's pattern: every entry M's or diagonal (the last of its upper column).
    std::vector<char> from_mass(A_.rowind.size(), 0);
    for (int64_t s : m_slot_) from_mass[s] = 1;
    for (int64_t j = 0; j < n; ++j) from_mass[A_.colptr[j + 1] - 1] = 1;
    const bool within_mass = std::all_of(from_mass.begin(), from_mass.end(), [](char c) { return c != 0; });
    chol_.set_ordering(within_mass ? std::move(mass_ordering) : std::vector<int64_t>{});
    return FRIX_OK;
}

frix_error MassPlusContacts::factor(const double *S, const linalg::FactorBudget &budget) {
    single_dropped_ = false;  // chol_ drops the last factorisation's copy with it
    misses_in_a_row_ = 0;
    std::fill(A_.val.begin(), A_.val.end(), 0.0);
    for (size_t e = 0; e < m_slot_.size(); ++e) A_.val[m_slot_[e]] += m_val_[e];
    const int64_t nc = (int64_t)row_start_.size() - 1;
    std::vector<double> G;  // H_a S_a, row-major (3 per row)
    for (int64_t a = 0; a < nc; ++a) {
        const int64_t first = row_start_[a], k = row_start_[a + 1] - first;
        const double *h = hrows_.data() + 3 * first, *Sa = S + 9 * a;  // k = 0 may sit at the end
        G.resize(3 * k);
        for (int64_t i = 0; i < k; ++i)
            for (int c = 0; c < 3; ++c)
                G[3 * i + c] = h[3 * i] * Sa[3 * c] + h[3 * i + 1] * Sa[1 + 3 * c] + h[3 * i + 2] * Sa[2 + 3 * c];
        for (int64_t s = pair_start_[a]; s < pair_start_[a + 1]; ++s) {
            const Pair &pair = pairs_[s];
            const double *g = G.data() + 3 * (pair.i - first), *hj = h + 3 * (pair.j - first);
            A_.val[pair.slot] += g[0] * hj[0] + g[1] * hj[1] + g[2] * hj[2];
        }
    }
    chol_.set_budget(budget);
    const frix_error e = chol_.factor(A_.view());
    chol_.set_budget(nullptr);  // it refers to the caller's limits
    return e;
}

namespace {

// solve_near's test of a single-precision step: the residual it leaves below this share of the
// one it solved (single precision's 6e-8 times the system's condition: a contraction that keeps
// the iterates' error a small share of each step); and the misses in a row that drop the copy.
constexpr double kSingleContraction = 1e-2;
constexpr int kSingleMisses = 2;

// y = A x for a symmetric A given by its upper triangle (CSC).
void symmetric_upper_product(const Csc &A, const double *x, double *y) {
    std::fill(y, y + A.rows, 0.0);
    for (int64_t j = 0; j < A.cols; ++j) {
        double yj = 0.0;
        for (int64_t e = A.colptr[j]; e < A.colptr[j + 1]; ++e) {
            const int64_t i = A.rowind[e];
            yj += A.val[e] * x[i];
            if (i != j) y[i] += A.val[e] * x[j];
        }
        y[j] += yj;
    }
}

}  // namespace

bool MassPlusContacts::keep_single_copy(const linalg::FactorBudget &budget) {
    return !single_dropped_ && chol_.keep_single_copy(budget);
}

frix_error MassPlusContacts::solve_near(const double *b, double *x) {
    if (!uses_single_copy()) return chol_.solve(b, x);
    const int64_t n = A_.rows;
    residual_.resize(n);
    step_.resize(n);
    left_.resize(n);
    symmetric_upper_product(A_, x, left_.data());
    for (int64_t i = 0; i < n; ++i) residual_[i] = b[i] - left_[i];
    if (!vec::all_finite(residual_.data(), n)) return chol_.solve(b, x);
    if (vec::all_zero(residual_.data(), n)) return FRIX_OK;
    ++single_solves_;
    if (frix_error e = chol_.solve_with_single_copy(residual_.data(), step_.data())) return e;
    symmetric_upper_product(A_, step_.data(), left_.data());
    for (int64_t i = 0; i < n; ++i) left_[i] = residual_[i] - left_[i];
    // norm2 scales against overflow and underflow: a problem may come in any units.
    if (vec::all_finite(step_.data(), n) && norm2(left_.data(), n) <= kSingleContraction * norm2(residual_.data(), n)) {
        misses_in_a_row_ = 0;
        for (int64_t i = 0; i < n; ++i) x[i] += step_[i];
        return FRIX_OK;
    }
    ++finished_in_double_;
    if (++misses_in_a_row_ >= kSingleMisses) {
        chol_.drop_single_copy();
        single_dropped_ = true;
    }
    if (frix_error e = chol_.solve(residual_.data(), step_.data())) return e;
    for (int64_t i = 0; i < n; ++i) x[i] += step_[i];
    return FRIX_OK;
}

frix_error prepare_mass_plus_contacts(const SolveContext &ctx, KeptMassPlusContacts &kept, const char *solver,
                                      int samples, ContactBlocks blocks, linalg::FactorStats *before) {
    const frix_problem &p = ctx.problem;
    *before = kept.system.stats() - kept.handed;
    kept.handed = {};
    const bool built = ctx.cache && kept.m_values == ctx.cache->m_values && kept.h_values == ctx.cache->h_values;
    if (built && !std::isnan(kept.scale)) return FRIX_OK;
    if (!built) {
        kept.m_values = kept.h_values = 0;  // until built
        kept.factored_rho = kept.scale = NAN;
    }
    if (!ctx.mass) return fail(FRIX_ERR_INTERNAL, "%s: no factorisation of M was given", solver);
    Csc M, H;
    if (frix_error e = to_csc(*p.H, H)) return e;
    if (!built) {
        if (frix_error e = to_csc(*p.M, M)) return e;
        if (frix_error e = kept.system.build(M, H, p.nc, solver, blocks, ctx.mass->ordering())) return e;
    }
    kept.scale = ctx.mass->factored() ? sampled_delassus_scale(p, H, *ctx.mass, samples)
                                      : sampled_jacobi_scale(p, samples);
    if (!(kept.scale > 0.0) || !std::isfinite(kept.scale)) kept.scale = 1.0;
    if (ctx.cache) kept.m_values = ctx.cache->m_values, kept.h_values = ctx.cache->h_values;
    return FRIX_OK;
}

void offer_mass_plus_contacts(SolveCache &cache, int key, std::unique_ptr<KeptMassPlusContacts> offered) {
    std::unique_ptr<CachedState> held = cache.take(key);
    const auto *kept = static_cast<const KeptMassPlusContacts *>(held.get());
    if (kept && kept->m_values == cache.m_values && kept->h_values == cache.h_values) {
        cache.give_back(key, std::move(held));
        return;
    }
    offered->m_values = cache.m_values;
    offered->h_values = cache.h_values;
    offered->factored_rho = offered->scale = NAN;
    offered->handed = offered->system.stats();
    cache.give_back(key, std::move(offered));
}

void de_saxce_shift(const frix_problem &p, const double *u, double *shift) {
    for (int64_t a = 0; a < p.nc; ++a) shift[3 * a] = p.mu[a] * std::hypot(u[3 * a + 1], u[3 * a + 2]);
}

double global_error(const frix_problem &p, int64_t measure, const double *r, const double *v, double *u,
                    double *equilibrium) {
    return selected_error(global_measures(p, r, v, u, equilibrium), measure);
}

double global_error_or_recovered(const frix_problem &p, const MassSolver *mass, int64_t measure, double tol,
                                 const double *r, double *v, double *u, double *equilibrium) {
    double best = global_error(p, measure, r, v, u, equilibrium);
    if (!(best > tol) || !mass || !mass->factored()) return best;
    const int64_t n = p.n, m = 3 * p.nc;
    std::vector<double> candidate(v, v + n), residual(n), delta(n), u_candidate(m);
    for (int step = 0; step < kVelocityRefinements; ++step) {
        // residual = H r + f - M v, then v += M^-1 residual.
        std::copy(p.f, p.f + n, residual.begin());
        if (m > 0) matrix_gemv(*p.H, 1.0, r, 1.0, residual.data());
        matrix_gemv(*p.M, -1.0, candidate.data(), 1.0, residual.data());
        if (mass->solve(residual.data(), delta.data()) != FRIX_OK) {
            clear_error();
            break;
        }
        for (int64_t j = 0; j < n; ++j) candidate[j] += delta[j];
        double eq = 0.0;
        const double error = global_error(p, measure, r, candidate.data(), u_candidate.data(), &eq);
        if (!(error < best)) break;
        best = error;
        *equilibrium = eq;
        std::copy(candidate.begin(), candidate.end(), v);
        std::copy(u_candidate.begin(), u_candidate.end(), u);
        if (!(best > tol)) break;
    }
    return best;
}

namespace {

// The k-th of `count` contacts sampled evenly from nc (count <= nc): the contacts
// sampled_delassus_diagonals and sampled_jacobi_scale read alike.
int64_t sampled_contact(int k, int count, int64_t nc) { return (int64_t)k * nc / count; }

}  // namespace

std::vector<std::pair<int64_t, double>> sampled_delassus_diagonals(const frix_problem &p, const Csc &H,
                                                                   MassSolver &mass, int samples, int components) {
    std::vector<std::pair<int64_t, double>> out;
    const int64_t nc = p.nc;
    const int count = (int)std::min<int64_t>(samples, nc);
    // B: the sampled contacts' first `components` columns of H.
    Csc B;
    B.rows = H.rows;
    B.colptr.push_back(0);
    for (int k = 0; k < count; ++k)
        for (int c = 0; c < components; ++c) {
            const int64_t col = 3 * sampled_contact(k, count, nc) + c;
            B.rowind.insert(B.rowind.end(), H.rowind.begin() + H.colptr[col], H.rowind.begin() + H.colptr[col + 1]);
            B.val.insert(B.val.end(), H.val.begin() + H.colptr[col], H.val.begin() + H.colptr[col + 1]);
            B.colptr.push_back((int64_t)B.rowind.size());
        }
    B.cols = (int64_t)B.colptr.size() - 1;
    std::vector<double> diag;
    if (mass.inverse_diagonal(B, diag) != FRIX_OK) {
        clear_error();
        return out;
    }
    for (int k = 0; k < count; ++k) {
        double trace = 0.0;
        for (int c = 0; c < components; ++c) trace += diag[(size_t)(k * components + c)];
        out.emplace_back(sampled_contact(k, count, nc), trace);
    }
    return out;
}

double sampled_jacobi_scale(const frix_problem &p, int samples) {
    const int count = (int)std::min<int64_t>(samples, p.nc);
    if (count == 0 || (int64_t)p.weight.size() != p.nc) return NAN;
    double sum = 0.0;
    for (int k = 0; k < count; ++k) sum += p.weight[(size_t)sampled_contact(k, count, p.nc)];
    return sum / count;
}

double sampled_delassus_scale(const frix_problem &p, const Csc &H, MassSolver &mass, int samples) {
    double sum = 0.0;
    int count = 0;
    for (const auto &sample : sampled_delassus_diagonals(p, H, mass, samples, 1))
        if (sample.second > 0.0 && std::isfinite(sample.second)) sum += sample.second, ++count;
    return count > 0 ? sum / count : NAN;
}

}  // namespace frix
