// Distributed global problems with the host's M (deformable bodies): each rank's rows of M and
// of H^T as given (frix_mpi_problem_global), or cut from a whole problem on a root
// (frix_mpi_problem_scatter_global). Nothing is reduced: gnsn-ac solves them on (v, r).
#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "mpi/distributed.hpp"
#include "src/error_state.hpp"
#include "src/problem.hpp"
#include "src/reduction.hpp"

namespace frix {
namespace mpi {
namespace {

// A CSR part of `rows` rows over columns 0 .. cols-1: row_ptr from 0 and not decreasing,
// columns increasing within a row and in range, values finite.
frix_error check_csr(const char *where, const char *name, int64_t rows, const int64_t *row_ptr, const int64_t *col,
                     const double *val, int64_t cols) {
    if (rows == 0) return FRIX_OK;
    if (!row_ptr) return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: %s's row_ptr is required", where, name);
    if (row_ptr[0] != 0)
        return fail(FRIX_ERR_DIMENSION, "%s: %s's row_ptr[0] is %lld, not 0", where, name, (long long)row_ptr[0]);
    for (int64_t i = 0; i < rows; ++i)
        if (row_ptr[i + 1] < row_ptr[i])
            return fail(FRIX_ERR_DIMENSION, "%s: %s's row_ptr decreases at row %lld", where, name, (long long)i);
    if (row_ptr[rows] > 0 && (!col || !val))
        return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: %s's columns and values are required", where, name);
    for (int64_t i = 0; i < rows; ++i)
        for (int64_t k = row_ptr[i]; k < row_ptr[i + 1]; ++k) {
            if (col[k] < 0 || col[k] >= cols)
                return fail(FRIX_ERR_DIMENSION, "%s: %s's row %lld has column %lld, not a dof (there are %lld)", where,
                            name, (long long)i, (long long)col[k], (long long)cols);
            if (k > row_ptr[i] && col[k] <= col[k - 1])
                return fail(FRIX_ERR_DIMENSION, "%s: the columns of %s's row %lld do not increase", where, name,
                            (long long)i);
            if (!std::isfinite(val[k]))
                return fail(FRIX_ERR_NOT_FINITE, "%s: %s's row %lld has a value that is not finite", where, name,
                            (long long)i);
        }
    return FRIX_OK;
}

// The rows as one rank gives them (frix_mpi_problem_global's arguments).
struct GlobalPart {
    int64_t dof_first, dofs;
    const int64_t *m_ptr, *m_col;
    const double *m_val, *f;
    int64_t first, owned;
    const int64_t *ht_ptr, *ht_col;
    const double *ht_val, *w, *mu;
};

// Checks and copies each rank's part (collective); ids: the contacts' indices in the whole
// problem (null: first ..).
frix_error make_global(frix_mpi_context *ctx, const GlobalPart &in, const int64_t *ids, frix_mpi_problem **out,
                       const char *where) {
    frix_error e = FRIX_OK;
    if (in.dof_first < 0 || in.dofs < 0 || in.first < 0 || in.owned < 0)
        e = fail(FRIX_ERR_DIMENSION, "%s: dof_first, dofs, first and owned must be >= 0", where);
    else if (!out)
        e = fail(FRIX_ERR_INVALID_ARGUMENT, "%s: out is NULL", where);
    if (!e) e = check_vector(where, "f", in.f, in.dofs);
    if (!e) e = check_vector(where, "w", in.w, 3 * in.owned);
    if (!e) e = check_mu(where, in.mu, in.owned);
    std::unique_ptr<frix_mpi_problem> p = start_part(ctx, in.first, in.owned, e, where);
    auto g = std::make_unique<frix_mpi_global_rows>();
    const bool contiguous = gather_blocks(ctx->comm, in.dof_first, in.dofs, g->dof_starts);
    g->dof_total = g->dof_starts.back();
    if (!e && !contiguous)
        e = fail(FRIX_ERR_DIMENSION,
                 "%s: the ranks' dofs must be contiguous blocks in rank order from 0 (this rank: dof_first %lld, dofs "
                 "%lld)",
                 where, (long long)in.dof_first, (long long)in.dofs);
    if (!e) e = check_csr(where, "M", in.dofs, in.m_ptr, in.m_col, in.m_val, g->dof_total);
    if (!e) e = check_csr(where, "H^T", 3 * in.owned, in.ht_ptr, in.ht_col, in.ht_val, g->dof_total);
    if (frix_error agreed = agree(ctx->comm, e, where)) return agreed;
    g->dof_first = in.dof_first;
    g->dofs = in.dofs;
    const int64_t m_nnz = in.dofs > 0 ? in.m_ptr[in.dofs] : 0, h_nnz = in.owned > 0 ? in.ht_ptr[3 * in.owned] : 0;
    if (in.dofs > 0) g->m_ptr.assign(in.m_ptr, in.m_ptr + in.dofs + 1);
    else g->m_ptr.assign(1, 0);
    g->m_col.assign(in.m_col, in.m_col + m_nnz);
    g->m_val.assign(in.m_val, in.m_val + m_nnz);
    g->f.assign(in.f, in.f + in.dofs);
    if (in.owned > 0) g->ht_ptr.assign(in.ht_ptr, in.ht_ptr + 3 * in.owned + 1);
    else g->ht_ptr.assign(1, 0);
    g->ht_col.assign(in.ht_col, in.ht_col + h_nnz);
    g->ht_val.assign(in.ht_val, in.ht_val + h_nnz);
    p->w.assign(in.w, in.w + 3 * in.owned);
    p->mu.assign(in.mu, in.mu + in.owned);
    if (ids) p->ids.assign(ids, ids + in.owned);
    p->global = std::move(g);
    *out = p.release();
    return FRIX_OK;
}

// The root's whole problem cut for rank k: its dofs' rows of M (blocks of equal size, in
// order) and its contacts' rows of H^T (the contacts of its part, in their order).
struct Pieces {
    std::vector<std::vector<int64_t>> ints;  // per rank: dofs, owned, M's row_ptr and columns, H^T's, ids
    std::vector<std::vector<double>> reals;  // per rank: M's values, f, H^T's values, w, mu
};

frix_error cut_global(const frix_problem &g, int ranks, const int *part, Pieces &out, const char *where) {
    Csc M, H;  // M's columns are read as rows of M^T; H's columns are H^T's rows
    if (frix_error e = to_csc(*g.M, M)) return e;
    if (g.nc > 0)
        if (frix_error e = to_csc(*g.H, H)) return e;
    std::vector<int64_t> cut, order, dof_cut, no_order;
    if (frix_error e = cut_by_part(part, g.nc, ranks, cut, order, where)) return e;
    cut_by_part(nullptr, g.n, ranks, dof_cut, no_order, where);
    // M's rows: the transpose of its CSC.
    std::vector<int64_t> row_ptr((size_t)g.n + 1, 0), col(M.rowind.size());
    std::vector<double> val(M.rowind.size());
    for (const int64_t i : M.rowind) ++row_ptr[(size_t)i + 1];
    for (int64_t i = 0; i < g.n; ++i) row_ptr[(size_t)i + 1] += row_ptr[(size_t)i];
    std::vector<int64_t> next(row_ptr.begin(), row_ptr.end() - 1);
    for (int64_t j = 0; j < g.n; ++j)
        for (int64_t e = M.colptr[(size_t)j]; e < M.colptr[(size_t)j + 1]; ++e) {
            const int64_t at = next[(size_t)M.rowind[(size_t)e]]++;
            col[(size_t)at] = j;
            val[(size_t)at] = M.val[(size_t)e];
        }
    out.ints.assign((size_t)ranks, {});
    out.reals.assign((size_t)ranks, {});
    for (int k = 0; k < ranks; ++k) {
        std::vector<int64_t> &I = out.ints[(size_t)k];
        std::vector<double> &R = out.reals[(size_t)k];
        const int64_t d0 = dof_cut[(size_t)k], d1 = dof_cut[(size_t)k + 1], c0 = cut[(size_t)k], c1 = cut[(size_t)k + 1];
        I.push_back(d1 - d0);
        I.push_back(c1 - c0);
        for (int64_t i = d0; i <= d1; ++i) I.push_back(row_ptr[(size_t)i] - row_ptr[(size_t)d0]);
        I.insert(I.end(), col.begin() + row_ptr[(size_t)d0], col.begin() + row_ptr[(size_t)d1]);
        R.insert(R.end(), val.begin() + row_ptr[(size_t)d0], val.begin() + row_ptr[(size_t)d1]);
        R.insert(R.end(), g.f + d0, g.f + d1);
        int64_t at = 0;
        I.push_back(0);
        for (int64_t s = c0; s < c1; ++s) {
            const int64_t a = order.empty() ? s : order[(size_t)s];
            for (int64_t c = 3 * a; c < 3 * a + 3; ++c) {
                at += H.colptr[(size_t)c + 1] - H.colptr[(size_t)c];
                I.push_back(at);
            }
        }
        for (int64_t s = c0; s < c1; ++s) {
            const int64_t a = order.empty() ? s : order[(size_t)s];
            const size_t e0 = (size_t)H.colptr[3 * (size_t)a], e1 = (size_t)H.colptr[3 * (size_t)a + 3];
            I.insert(I.end(), H.rowind.begin() + e0, H.rowind.begin() + e1);
            R.insert(R.end(), H.val.begin() + e0, H.val.begin() + e1);
        }
        for (int64_t s = c0; s < c1; ++s) I.push_back(order.empty() ? s : order[(size_t)s]);
        for (int64_t s = c0; s < c1; ++s) {
            const int64_t a = order.empty() ? s : order[(size_t)s];
            R.insert(R.end(), g.w + 3 * a, g.w + 3 * a + 3);
        }
        for (int64_t s = c0; s < c1; ++s) R.push_back(g.mu[order.empty() ? s : order[(size_t)s]]);
    }
    return FRIX_OK;
}

}  // namespace
}  // namespace mpi
}  // namespace frix

extern "C" {

FRIX_API frix_error frix_mpi_problem_global(frix_mpi_context *ctx, int64_t dof_first, int64_t dofs,
                                            const int64_t *M_row_ptr, const int64_t *M_col, const double *M_val,
                                            const double *f, int64_t first, int64_t owned, const int64_t *Ht_row_ptr,
                                            const int64_t *Ht_col, const double *Ht_val, const double *w,
                                            const double *mu, frix_mpi_problem **out) {
    return frix::guard("frix_mpi_problem_global", [&]() -> frix_error {
        if (!ctx) return frix::fail(FRIX_ERR_INVALID_ARGUMENT, "frix_mpi_problem_global: ctx is NULL");
        if (out) *out = nullptr;
        const frix::mpi::GlobalPart in{dof_first, dofs,       M_row_ptr, M_col, M_val, f, first,
                                       owned,     Ht_row_ptr, Ht_col,    Ht_val, w,    mu};
        return frix::mpi::make_global(ctx, in, nullptr, out, "frix_mpi_problem_global");
    });
}

FRIX_API frix_error frix_mpi_problem_scatter_global(frix_mpi_context *ctx, int root, const frix_problem *problem,
                                                    const int *part, frix_mpi_problem **out) {
    return frix::guard("frix_mpi_problem_scatter_global", [&]() -> frix_error {
        using frix::fail;
        using frix::mpi::check;
        using frix::mpi::checked_count;
        const char *where = "frix_mpi_problem_scatter_global";
        if (!ctx) return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: ctx is NULL", where);
        if (out) *out = nullptr;
        if (root < 0 || root >= ctx->size)
            return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: root %d is not a rank (0 .. %d)", where, root, ctx->size - 1);
        const bool is_root = ctx->rank == root;
        frix_error e = out ? FRIX_OK : fail(FRIX_ERR_INVALID_ARGUMENT, "%s: out is NULL", where);
        frix::mpi::Pieces pieces;
        if (!e && is_root) {
            if (!problem)
                e = fail(FRIX_ERR_INVALID_ARGUMENT, "%s: problem is NULL on the root", where);
            else if (frix_error other = frix::mpi::check_release(*problem, where, "problem"))
                e = other;
            else if (frix_error rolling = frix::refuse_rolling(*problem, where))
                e = rolling;
            else if (problem->kind != FRIX_PROBLEM_GLOBAL)
                e = fail(FRIX_ERR_INVALID_ARGUMENT, "%s: the problem is not global (frix_mpi_problem_scatter takes it)",
                         where);
            else if (frix_error bad = frix::check_problem_vectors(*problem))
                e = bad;
            else
                e = frix::mpi::cut_global(*problem, ctx->size, part, pieces, where);
        }
        if (frix_error agreed = frix::mpi::agree(ctx->comm, e, where)) return agreed;
        if (!is_root) pieces.ints.assign((size_t)ctx->size, {});
        const std::vector<int64_t> ints = frix::mpi::exchange_lists(ctx->comm, pieces.ints);
        std::vector<int> counts((size_t)ctx->size, 0), at((size_t)ctx->size, 0);
        std::vector<double> flat;
        if (is_root)
            for (size_t k = 0; k < (size_t)ctx->size; ++k) {
                counts[k] = checked_count((int64_t)pieces.reals[k].size());
                at[k] = checked_count((int64_t)flat.size());
                flat.insert(flat.end(), pieces.reals[k].begin(), pieces.reals[k].end());
            }
        int mine = 0;
        check(MPI_Scatter(counts.data(), 1, MPI_INT, &mine, 1, MPI_INT, root, ctx->comm), "MPI_Scatter");
        std::vector<double> reals((size_t)mine);
        check(MPI_Scatterv(flat.data(), counts.data(), at.data(), MPI_DOUBLE, reals.data(), mine, MPI_DOUBLE, root,
                           ctx->comm),
              "MPI_Scatterv");
        // This rank's piece, laid out as cut_global packs it.
        const int64_t dofs = ints[0], owned = ints[1];
        const int64_t *m_ptr = &ints[2], *m_col = m_ptr + dofs + 1, *ht_ptr = m_col + m_ptr[dofs];
        const int64_t *ht_col = ht_ptr + 3 * owned + 1, *ids = ht_col + ht_ptr[3 * owned];
        const double *m_val = reals.data(), *f = m_val + m_ptr[dofs], *ht_val = f + dofs;
        const double *w = ht_val + ht_ptr[3 * owned], *mu = w + 3 * owned;
        int64_t firsts[2] = {0, 0};  // the first dof and contact: the counts before this rank's
        const int64_t counts2[2] = {dofs, owned};
        check(MPI_Exscan(counts2, firsts, 2, MPI_INT64_T, MPI_SUM, ctx->comm), "MPI_Exscan");
        if (ctx->rank == 0) firsts[0] = firsts[1] = 0;  // (MPI_Exscan leaves rank 0's undefined)
        const frix::mpi::GlobalPart in{firsts[0], dofs,   m_ptr,  m_col, m_val, f, firsts[1],
                                       owned,     ht_ptr, ht_col, ht_val, w,    mu};
        return frix::mpi::make_global(ctx, in, ids, out, where);
    });
}

}  // extern "C"
