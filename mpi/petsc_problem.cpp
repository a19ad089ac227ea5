// frix_mpi_problem_petsc: a distributed local problem from the host's PETSc objects (W's rows
// regrouped into 3 x 3 blocks, q's entries), then as frix_mpi_problem_local.
#include <frix/frix_mpi_petsc.h>

#include <algorithm>
#include <vector>

#include "mpi/distributed.hpp"
#include "mpi/petsc_support.hpp"
#include "src/error_state.hpp"

namespace frix {
namespace mpi {
namespace {

frix_error petsc(PetscErrorCode rc, const char *what) {
    return petsc_call(rc, FRIX_ERR_INVALID_ARGUMENT, "frix_mpi_problem_petsc", what);
}

// This rank's rows of W as 3 x 3 block rows (block columns increasing, 9 values column-major
// each) and its q; first and owned in contacts.
frix_error read_rows(MPI_Comm comm, Mat W, Vec q, int64_t &first, int64_t &owned, std::vector<int64_t> &row_ptr,
                     std::vector<int64_t> &block_col, std::vector<double> &block_val, std::vector<double> &q_values) {
    PetscBool initialised = PETSC_FALSE;
    PetscInitialized(&initialised);
    if (!initialised) return fail(FRIX_ERR_INVALID_ARGUMENT, "frix_mpi_problem_petsc: PETSc is not initialised");
    if (!W || !q) return fail(FRIX_ERR_INVALID_ARGUMENT, "frix_mpi_problem_petsc: W and q are required");
    int same = MPI_UNEQUAL;
    MPI_Comm_compare(PetscObjectComm((PetscObject)W), comm, &same);
    if (same != MPI_IDENT && same != MPI_CONGRUENT)
        return fail(FRIX_ERR_INVALID_ARGUMENT, "frix_mpi_problem_petsc: W lives on another communicator than the context");
    PetscInt r0 = 0, r1 = 0, rows = 0, cols = 0, v0 = 0, v1 = 0;
    if (frix_error e = petsc(MatGetOwnershipRange(W, &r0, &r1), "MatGetOwnershipRange")) return e;
    if (frix_error e = petsc(MatGetSize(W, &rows, &cols), "MatGetSize")) return e;
    if (frix_error e = petsc(VecGetOwnershipRange(q, &v0, &v1), "VecGetOwnershipRange")) return e;
    if (rows != cols || rows % 3 != 0 || r0 % 3 != 0 || r1 % 3 != 0)
        return fail(FRIX_ERR_DIMENSION,
                    "frix_mpi_problem_petsc: W must be square with its rows 3 to a contact (%lld x %lld, this rank's rows "
                    "%lld .. %lld)",
                    (long long)rows, (long long)cols, (long long)r0, (long long)r1);
    if (v0 != r0 || v1 != r1)
        return fail(FRIX_ERR_DIMENSION, "frix_mpi_problem_petsc: q's layout is not W's rows'");
    first = r0 / 3;
    owned = (r1 - r0) / 3;
    row_ptr.assign(1, 0);
    std::vector<std::pair<int64_t, int>> entries;  // (block column, place in the block) per value
    std::vector<double> values;
    for (int64_t a = 0; a < owned; ++a) {
        entries.clear();
        values.clear();
        for (int i = 0; i < 3; ++i) {
            const PetscInt row = (PetscInt)(3 * (first + a) + i);
            PetscInt n = 0;
            const PetscInt *c = nullptr;
            const PetscScalar *v = nullptr;
            if (frix_error e = petsc(MatGetRow(W, row, &n, &c, &v), "MatGetRow")) return e;
            for (PetscInt k = 0; k < n; ++k) {
                entries.emplace_back((int64_t)(c[k] / 3), i + 3 * (int)(c[k] % 3));
                values.push_back((double)v[k]);
            }
            MatRestoreRow(W, row, &n, &c, &v);
        }
        std::vector<size_t> order(entries.size());
        for (size_t k = 0; k < order.size(); ++k) order[k] = k;
        std::sort(order.begin(), order.end(), [&](size_t x, size_t y) { return entries[x] < entries[y]; });
        for (const size_t k : order) {
            if (block_col.empty() || (int64_t)block_col.size() == row_ptr.back() ||
                block_col.back() != entries[k].first) {
                block_col.push_back(entries[k].first);
                block_val.insert(block_val.end(), 9, 0.0);
            }
            block_val[block_val.size() - 9 + (size_t)entries[k].second] += values[k];
        }
        row_ptr.push_back((int64_t)block_col.size());
    }
    const PetscScalar *x = nullptr;
    if (frix_error e = petsc(VecGetArrayRead(q, &x), "VecGetArrayRead")) return e;
    q_values.assign(x, x + 3 * owned);
    VecRestoreArrayRead(q, &x);
    return FRIX_OK;
}

// This rank's rows of A in CSR (global columns, increasing, as PETSc's MatGetRow gives them).
frix_error read_csr(Mat A, std::vector<int64_t> &row_ptr, std::vector<int64_t> &col, std::vector<double> &val) {
    PetscInt r0 = 0, r1 = 0;
    if (frix_error e = petsc(MatGetOwnershipRange(A, &r0, &r1), "MatGetOwnershipRange")) return e;
    row_ptr.assign(1, 0);
    for (PetscInt row = r0; row < r1; ++row) {
        PetscInt n = 0;
        const PetscInt *c = nullptr;
        const PetscScalar *v = nullptr;
        if (frix_error e = petsc(MatGetRow(A, row, &n, &c, &v), "MatGetRow")) return e;
        col.insert(col.end(), c, c + n);
        val.insert(val.end(), v, v + n);
        MatRestoreRow(A, row, &n, &c, &v);
        row_ptr.push_back((int64_t)col.size());
    }
    return FRIX_OK;
}

// A vector's entries on this rank, which must be the rows [r0, r1) of its matrix.
frix_error read_entries(Vec x, PetscInt r0, PetscInt r1, const char *name, std::vector<double> &out) {
    PetscInt v0 = 0, v1 = 0;
    if (frix_error e = petsc(VecGetOwnershipRange(x, &v0, &v1), "VecGetOwnershipRange")) return e;
    if (v0 != r0 || v1 != r1)
        return fail(FRIX_ERR_DIMENSION, "frix_mpi_problem_petsc_global: %s's layout is not its matrix's rows'", name);
    const PetscScalar *a = nullptr;
    if (frix_error e = petsc(VecGetArrayRead(x, &a), "VecGetArrayRead")) return e;
    out.assign(a, a + (r1 - r0));
    VecRestoreArrayRead(x, &a);
    return FRIX_OK;
}

// The parts of frix_mpi_problem_global from M, f, H^T and w.
struct GlobalRowsRead {
    int64_t dof_first = 0, dofs = 0, first = 0, owned = 0;
    std::vector<int64_t> m_ptr, m_col, h_ptr, h_col;
    std::vector<double> m_val, f, h_val, w;
};

frix_error read_global(MPI_Comm comm, Mat M, Vec f, Mat Ht, Vec w, GlobalRowsRead &out) {
    PetscBool initialised = PETSC_FALSE;
    PetscInitialized(&initialised);
    const char *where = "frix_mpi_problem_petsc_global";
    if (!initialised) return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: PETSc is not initialised", where);
    if (!M || !f || !Ht || !w) return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: M, f, Ht and w are required", where);
    for (Mat A : {M, Ht}) {
        int same = MPI_UNEQUAL;
        MPI_Comm_compare(PetscObjectComm((PetscObject)A), comm, &same);
        if (same != MPI_IDENT && same != MPI_CONGRUENT)
            return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: M or Ht lives on another communicator than the context", where);
    }
    PetscInt m0 = 0, m1 = 0, n = 0, n2 = 0, h0 = 0, h1 = 0, rows = 0, cols = 0;
    if (frix_error e = petsc(MatGetSize(M, &n, &n2), "MatGetSize")) return e;
    if (frix_error e = petsc(MatGetSize(Ht, &rows, &cols), "MatGetSize")) return e;
    if (frix_error e = petsc(MatGetOwnershipRange(M, &m0, &m1), "MatGetOwnershipRange")) return e;
    if (frix_error e = petsc(MatGetOwnershipRange(Ht, &h0, &h1), "MatGetOwnershipRange")) return e;
    if (n != n2 || cols != n)
        return fail(FRIX_ERR_DIMENSION, "%s: M must be square and Ht have its columns (M %lld x %lld, Ht %lld x %lld)",
                    where, (long long)n, (long long)n2, (long long)rows, (long long)cols);
    if (rows % 3 != 0 || h0 % 3 != 0 || h1 % 3 != 0)
        return fail(FRIX_ERR_DIMENSION, "%s: Ht's rows must go 3 to a contact (this rank's rows %lld .. %lld)", where,
                    (long long)h0, (long long)h1);
    out.dof_first = m0;
    out.dofs = m1 - m0;
    out.first = h0 / 3;
    out.owned = (h1 - h0) / 3;
    if (frix_error e = read_csr(M, out.m_ptr, out.m_col, out.m_val)) return e;
    if (frix_error e = read_csr(Ht, out.h_ptr, out.h_col, out.h_val)) return e;
    if (frix_error e = read_entries(f, m0, m1, "f", out.f)) return e;
    return read_entries(w, h0, h1, "w", out.w);
}

}  // namespace
}  // namespace mpi
}  // namespace frix

extern "C" {

FRIX_API frix_error frix_mpi_problem_petsc(frix_mpi_context *ctx, Mat W, Vec q, const double *mu, frix_mpi_problem **out) {
    return frix::guard("frix_mpi_problem_petsc", [&]() -> frix_error {
        using frix::fail;
        const char *where = "frix_mpi_problem_petsc";
        if (!ctx) return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: ctx is NULL", where);
        if (out) *out = nullptr;
        int64_t first = 0, owned = 0;
        std::vector<int64_t> row_ptr, block_col;
        std::vector<double> block_val, q_values;
        frix_error e = out ? frix::mpi::read_rows(ctx->comm, W, q, first, owned, row_ptr, block_col, block_val, q_values)
                           : fail(FRIX_ERR_INVALID_ARGUMENT, "%s: out is NULL", where);
        if (frix_error agreed = frix::mpi::agree(ctx->comm, e, where)) return agreed;
        return frix::mpi::make(ctx, first, owned, row_ptr.data(), block_col.data(), block_val.data(), q_values.data(), mu,
                               nullptr, out, where);
    });
}

FRIX_API frix_error frix_mpi_problem_petsc_global(frix_mpi_context *ctx, Mat M, Vec f, Mat Ht, Vec w, const double *mu,
                                                  frix_mpi_problem **out) {
    return frix::guard("frix_mpi_problem_petsc_global", [&]() -> frix_error {
        using frix::fail;
        const char *where = "frix_mpi_problem_petsc_global";
        if (!ctx) return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: ctx is NULL", where);
        if (out) *out = nullptr;
        frix::mpi::GlobalRowsRead in;
        frix_error e = out ? frix::mpi::read_global(ctx->comm, M, f, Ht, w, in)
                           : fail(FRIX_ERR_INVALID_ARGUMENT, "%s: out is NULL", where);
        if (frix_error agreed = frix::mpi::agree(ctx->comm, e, where)) return agreed;
        return frix_mpi_problem_global(ctx, in.dof_first, in.dofs, in.m_ptr.data(), in.m_col.data(), in.m_val.data(),
                                       in.f.data(), in.first, in.owned, in.h_ptr.data(), in.h_col.data(),
                                       in.h_val.data(), in.w.data(), mu, out);
    });
}

}  // extern "C"
