// The distributed gnsn-ac's PETSc side (mpi/distributed_global_newton.cpp): M and H^T as the
// ranks gave them, the Jacobian [[M, -H], [B H^T, A]] of a fixed pattern over the ranks' rows
// and MUMPS's LU of it, and the products with this rank's parts of v and r.
#pragma once

#include <petscksp.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "mpi/distributed_forms.hpp"
#include "mpi/petsc_support.hpp"
#include "src/error_state.hpp"
#include "src/vec.hpp"

namespace frix {
namespace mpi {
namespace global_newton {

inline frix_error petsc(PetscErrorCode rc, const char *what) { return petsc_call(rc, FRIX_ERR_INTERNAL, "gnsn-ac", what); }

inline double dot_all(MPI_Comm comm, const double *x, const double *y, int64_t n) {
    double s = 0.0;
    for (int64_t i = 0; i < n; ++i) s += x[i] * y[i];
    reduce_all(comm, &s, 1, "s");
    return s;
}

// The PETSc side: M and H^T as the ranks gave them, the Jacobian of a fixed pattern, and the
// products with this rank's parts of v (dofs) and r (3 a contact).
class GlobalSystem {
   public:
    explicit GlobalSystem(const frix_mpi_problem &p) : p_(p), g_(*p.global), comm_(p.ctx->comm) {}
    ~GlobalSystem() {
        KSPDestroy(&ksp_);
        KSPDestroy(&mass_ksp_);
        for (Vec *v : {&dofs_in_, &dofs_out_, &rows_in_, &rows_out_, &rhs_, &step_}) VecDestroy(v);
        for (Mat *m : {&M_, &Ht_, &J_}) MatDestroy(m);
    }

    frix_error setup() {
        const int64_t n = g_.dofs, m = 3 * p_.owned;
        // Each rank's rows of (v, r) start at offset_[k]: its dofs, then its contacts'.
        const int ranks = p_.ctx->size, me = p_.ctx->rank;
        offset_.assign((size_t)ranks + 1, 0);
        for (int k = 0; k <= ranks; ++k) offset_[(size_t)k] = g_.dof_starts[(size_t)k] + 3 * p_.starts[(size_t)k];
        contact_row_ = offset_[(size_t)me] + n;
        // PETSc's indices (PetscInt) must hold the unknowns and each rank's entries: agreed
        // before any collective PETSc call.
        const int64_t largest = std::max({offset_.back(), g_.m_ptr.back(), g_.ht_ptr.back()});
        if (or_all(comm_, largest > (int64_t)PETSC_MAX_INT ? 1u : 0u))
            return fail(FRIX_ERR_DIMENSION, "gnsn-ac: the problem exceeds PETSc's indices (PetscInt, at most %lld)",
                        (long long)PETSC_MAX_INT);
        std::vector<PetscInt> ptr(g_.m_ptr.begin(), g_.m_ptr.end()), col(g_.m_col.begin(), g_.m_col.end());
        if (frix_error e = petsc(MatCreateMPIAIJWithArrays(comm_, (PetscInt)n, (PetscInt)n, PETSC_DETERMINE,
                                                           PETSC_DETERMINE, ptr.data(), col.data(), g_.m_val.data(), &M_),
                                 "MatCreateMPIAIJWithArrays (M)"))
            return e;
        ptr.assign(g_.ht_ptr.begin(), g_.ht_ptr.end());
        col.assign(g_.ht_col.begin(), g_.ht_col.end());
        if (frix_error e = petsc(MatCreateMPIAIJWithArrays(comm_, (PetscInt)m, (PetscInt)n, PETSC_DETERMINE,
                                                           (PetscInt)g_.dof_total, ptr.data(), col.data(),
                                                           g_.ht_val.data(), &Ht_),
                                 "MatCreateMPIAIJWithArrays (H^T)"))
            return e;
        if (frix_error e = petsc(MatCreateVecs(Ht_, &dofs_in_, &rows_out_), "MatCreateVecs")) return e;
        if (frix_error e = petsc(MatCreateVecs(Ht_, &dofs_out_, &rows_in_), "MatCreateVecs")) return e;
        // Contact a's row i of the Jacobian: B_a H_a^T over the dofs of its rows of H^T (their
        // union, with the 3 values of H^T there), then A_a + delta B_a over its own r.
        cols_ptr_.assign(1, 0);
        for (int64_t a = 0; a < p_.owned; ++a) {
            std::vector<int64_t> dofs;
            for (int64_t k = g_.ht_ptr[3 * (size_t)a]; k < g_.ht_ptr[3 * (size_t)a + 3]; ++k)
                dofs.push_back(g_.ht_col[(size_t)k]);
            std::sort(dofs.begin(), dofs.end());
            dofs.erase(std::unique(dofs.begin(), dofs.end()), dofs.end());
            for (const int64_t j : dofs) {
                cols_.push_back(row_of_dof(j));
                double h[3] = {0.0, 0.0, 0.0};
                for (int c = 0; c < 3; ++c) {
                    const size_t k0 = (size_t)g_.ht_ptr[3 * (size_t)a + c], k1 = (size_t)g_.ht_ptr[3 * (size_t)a + c + 1];
                    const auto it = std::lower_bound(g_.ht_col.begin() + k0, g_.ht_col.begin() + k1, j);
                    if (it != g_.ht_col.begin() + k1 && *it == j) h[c] = g_.ht_val[(size_t)(it - g_.ht_col.begin())];
                }
                h_.insert(h_.end(), h, h + 3);
            }
            for (int c = 0; c < 3; ++c) cols_.push_back((PetscInt)(contact_row_ + 3 * a + c));
            cols_ptr_.push_back((int64_t)cols_.size());
        }
        // The pattern, preallocated; then M and -H, which stay.
        const PetscInt local = (PetscInt)(n + m);
        Mat pattern = nullptr;
        if (frix_error e = petsc(MatCreate(comm_, &pattern), "MatCreate")) return e;
        frix_error e = petsc(MatSetType(pattern, MATPREALLOCATOR), "MatSetType");
        if (!e) e = petsc(MatSetSizes(pattern, local, local, PETSC_DETERMINE, PETSC_DETERMINE), "MatSetSizes");
        if (!e) e = petsc(MatSetUp(pattern), "MatSetUp");
        if (!e) e = insert_fixed(pattern);
        if (!e) e = insert_contacts(pattern, nullptr, nullptr, 0.0);
        if (!e) e = petsc(MatAssemblyBegin(pattern, MAT_FINAL_ASSEMBLY), "MatAssemblyBegin");
        if (!e) e = petsc(MatAssemblyEnd(pattern, MAT_FINAL_ASSEMBLY), "MatAssemblyEnd");
        if (!e) e = petsc(MatCreate(comm_, &J_), "MatCreate");
        if (!e) e = petsc(MatSetSizes(J_, local, local, PETSC_DETERMINE, PETSC_DETERMINE), "MatSetSizes");
        if (!e) e = petsc(MatSetType(J_, MATAIJ), "MatSetType");
        if (!e) e = petsc(MatPreallocatorPreallocate(pattern, PETSC_TRUE, J_), "MatPreallocatorPreallocate");
        MatDestroy(&pattern);
        if (e) return e;
        if (frix_error e2 = insert_fixed(J_)) return e2;
        if (frix_error e2 = petsc(MatCreateVecs(J_, &step_, &rhs_), "MatCreateVecs")) return e2;
        // M's pattern is a mesh's on a deformable body: nested dissection, as the serial gnsn-ac.
        return mumps_lu(comm_, J_, ksp_, "gnsn-ac", kMumpsMetis);
    }

    // out = M x, x and out on this rank's dofs.
    frix_error mult_M(const double *x, double *out) { return apply(M_, false, dofs_in_, dofs_out_, x, out); }
    // out = H x = (H^T)^T x: x on this rank's contacts, out on its dofs.
    frix_error mult_H(const double *x, double *out) { return apply(Ht_, true, rows_in_, dofs_out_, x, out); }
    // out = H^T x: x on this rank's dofs, out on its contacts.
    frix_error mult_Ht(const double *x, double *out) { return apply(Ht_, false, dofs_in_, rows_out_, x, out); }

    // The lumped Delassus blocks H_a^T diag(M)^-1 H_a of the owned contacts (9 values each,
    // column-major), as the serial gnsn-ac takes them (1 / M_jj for M_jj > 0, else 0).
    frix_error lumped_blocks(std::vector<double> &blocks) {
        blocks.assign(9 * (size_t)p_.owned, 0.0);
        Vec scale = nullptr;
        Mat scaled = nullptr;
        frix_error e = petsc(MatCreateVecs(M_, &scale, nullptr), "MatCreateVecs");
        if (!e) e = petsc(MatGetDiagonal(M_, scale), "MatGetDiagonal");
        if (!e) {
            PetscScalar *d = nullptr;
            e = petsc(VecGetArray(scale, &d), "VecGetArray");
            for (int64_t j = 0; !e && j < g_.dofs; ++j) d[j] = d[j] > 0.0 ? std::sqrt(1.0 / d[j]) : 0.0;
            if (!e) VecRestoreArray(scale, &d);
        }
        if (!e) e = petsc(MatDuplicate(Ht_, MAT_COPY_VALUES, &scaled), "MatDuplicate");
        if (!e) e = petsc(MatDiagonalScale(scaled, nullptr, scale), "MatDiagonalScale");
        const PetscInt row0 = (PetscInt)(3 * p_.first);
        for (int64_t a = 0; !e && a < p_.owned; ++a) {
            std::vector<std::vector<std::pair<PetscInt, double>>> rows(3);
            for (int c = 0; c < 3 && !e; ++c) {
                const PetscInt row = row0 + (PetscInt)(3 * a + c);
                PetscInt count = 0;
                const PetscInt *cols = nullptr;
                const PetscScalar *vals = nullptr;
                e = petsc(MatGetRow(scaled, row, &count, &cols, &vals), "MatGetRow");
                if (e) break;
                for (PetscInt k = 0; k < count; ++k) rows[(size_t)c].emplace_back(cols[k], vals[k]);
                MatRestoreRow(scaled, row, &count, &cols, &vals);
            }
            for (int c1 = 0; c1 < 3 && !e; ++c1)
                for (int c2 = 0; c2 < 3; ++c2) {
                    const auto &x = rows[(size_t)c1], &y = rows[(size_t)c2];
                    double sum = 0.0;
                    for (size_t i = 0, k = 0; i < x.size() && k < y.size();) {
                        if (x[i].first < y[k].first) ++i;
                        else if (y[k].first < x[i].first) ++k;
                        else sum += x[i++].second * y[k++].second;
                    }
                    blocks[9 * (size_t)a + (size_t)c1 + 3 * (size_t)c2] = sum;
                }
        }
        MatDestroy(&scaled);
        VecDestroy(&scale);
        return e;
    }

    // trace(H_a^T M^-1 H_a) for contact a of the whole problem (every rank calls it with the
    // same a), by MUMPS's LU of M; NaN when M does not factorise.
    frix_error exact_trace(int64_t a, double &trace) {
        trace = 0.0;
        std::vector<double> unit(3 * (size_t)p_.owned), b((size_t)g_.dofs), x((size_t)g_.dofs);
        for (int c = 0; c < 3; ++c) {
            std::fill(unit.begin(), unit.end(), 0.0);
            if (a >= p_.first && a < p_.first + p_.owned) unit[3 * (size_t)(a - p_.first) + (size_t)c] = 1.0;
            if (frix_error e = mult_H(unit.data(), b.data())) return e;
            bool solved = false;
            if (frix_error e = solve_mass(b.data(), x.data(), solved)) return e;
            if (!solved) {
                trace = NAN;
                return FRIX_OK;
            }
            trace += dot_all(comm_, b.data(), x.data(), g_.dofs);
        }
        return FRIX_OK;
    }

    // x = M^-1 b over this rank's dofs, by MUMPS's LU of M (made on the first call); solved:
    // false where M does not factorise (on every rank).
    frix_error solve_mass(const double *b, double *x, bool &solved) {
        if (!mass_ksp_)
            if (frix_error e = mumps_lu(comm_, M_, mass_ksp_, "gnsn-ac", kMumpsMetis)) return e;
        return solve_with(M_, mass_ksp_, b, x, dofs_in_, dofs_out_, solved);
    }

    // The contacts' rows of J at A, B (9 values a contact each, column-major) and delta.
    frix_error assemble(const std::vector<double> &A, const std::vector<double> &B, double delta) {
        if (frix_error e = insert_contacts(J_, A.data(), B.data(), delta)) return e;
        if (frix_error e = petsc(MatAssemblyBegin(J_, MAT_FINAL_ASSEMBLY), "MatAssemblyBegin")) return e;
        return petsc(MatAssemblyEnd(J_, MAT_FINAL_ASSEMBLY), "MatAssemblyEnd");
    }

    // x = J^-1 b over this rank's rows (dofs, then contacts); solved as mumps_solve's.
    frix_error solve(const double *b, double *x, bool &solved) {
        return solve_with(J_, ksp_, b, x, rhs_, step_, solved);
    }

   private:
    PetscInt row_of_dof(int64_t j) const {
        const int k = owner_of(g_.dof_starts, j);
        return (PetscInt)(offset_[(size_t)k] + j - g_.dof_starts[(size_t)k]);
    }
    // M's rows and -H (in the rows of the dofs of H^T's columns, any rank's).
    frix_error insert_fixed(Mat target) {
        for (int64_t i = 0; i < g_.dofs; ++i) {
            const PetscInt row = row_of_dof(g_.dof_first + i);
            for (int64_t k = g_.m_ptr[(size_t)i]; k < g_.m_ptr[(size_t)i + 1]; ++k) {
                const PetscInt col = row_of_dof(g_.m_col[(size_t)k]);
                if (frix_error e = petsc(MatSetValue(target, row, col, g_.m_val[(size_t)k], INSERT_VALUES), "MatSetValue"))
                    return e;
            }
        }
        for (int64_t k = 0; k < 3 * p_.owned; ++k) {
            const PetscInt col = (PetscInt)(contact_row_ + k);
            for (int64_t e = g_.ht_ptr[(size_t)k]; e < g_.ht_ptr[(size_t)k + 1]; ++e)
                if (frix_error err = petsc(MatSetValue(target, row_of_dof(g_.ht_col[(size_t)e]), col,
                                                       -g_.ht_val[(size_t)e], INSERT_VALUES),
                                           "MatSetValue"))
                    return err;
        }
        return FRIX_OK;
    }
    // The contacts' rows (zeros without A and B: the pattern).
    frix_error insert_contacts(Mat target, const double *A, const double *B, double delta) {
        std::vector<double> vals;
        for (int64_t a = 0; a < p_.owned; ++a) {
            const int64_t c0 = cols_ptr_[(size_t)a], c1 = cols_ptr_[(size_t)a + 1], dofs = c1 - c0 - 3;
            const double *Aa = A ? A + 9 * a : nullptr, *Ba = B ? B + 9 * a : nullptr;
            for (int i = 0; i < 3; ++i) {
                vals.assign((size_t)(c1 - c0), 0.0);
                if (Ba) {
                    const double *h = &h_[3 * (size_t)(c0 - 3 * a)];
                    for (int64_t d = 0; d < dofs; ++d)
                        vals[(size_t)d] = Ba[i] * h[3 * d] + Ba[i + 3] * h[3 * d + 1] + Ba[i + 6] * h[3 * d + 2];
                    for (int c = 0; c < 3; ++c) vals[(size_t)(dofs + c)] = Aa[i + 3 * c] + delta * Ba[i + 3 * c];
                }
                const PetscInt row = (PetscInt)(contact_row_ + 3 * a + i);
                if (frix_error e = petsc(MatSetValues(target, 1, &row, (PetscInt)(c1 - c0), &cols_[(size_t)c0],
                                                      vals.data(), INSERT_VALUES),
                                         "MatSetValues"))
                    return e;
            }
        }
        return FRIX_OK;
    }
    // (A rank with no rows passes no array: PETSc is given a place that it never reads.)
    frix_error apply(Mat A, bool transposed, Vec in, Vec out, const double *x, double *y) {
        double none[1];
        if (frix_error e = petsc(VecPlaceArray(in, x ? x : none), "VecPlaceArray")) return e;
        frix_error e = petsc(VecPlaceArray(out, y ? y : none), "VecPlaceArray");
        if (!e) {
            e = petsc(transposed ? MatMultTranspose(A, in, out) : MatMult(A, in, out), "MatMult");
            VecResetArray(out);
        }
        VecResetArray(in);
        return e;
    }
    frix_error solve_with(Mat A, KSP &ksp, const double *b, double *x, Vec in, Vec out, bool &solved) {
        double none[1];
        if (frix_error e = petsc(VecPlaceArray(in, b ? b : none), "VecPlaceArray")) return e;
        frix_error e = petsc(VecPlaceArray(out, x ? x : none), "VecPlaceArray");
        if (!e) {
            e = mumps_solve(comm_, A, ksp, in, out, solved, "gnsn-ac", kMumpsMetis);
            VecResetArray(out);
        }
        VecResetArray(in);
        return e;
    }

    const frix_mpi_problem &p_;
    const frix_mpi_global_rows &g_;
    MPI_Comm comm_;
    Mat M_ = nullptr, Ht_ = nullptr, J_ = nullptr;
    Vec dofs_in_ = nullptr, dofs_out_ = nullptr, rows_in_ = nullptr, rows_out_ = nullptr, rhs_ = nullptr,
        step_ = nullptr;
    KSP ksp_ = nullptr, mass_ksp_ = nullptr;
    std::vector<int64_t> offset_;
    int64_t contact_row_ = 0;
    // Contact a's columns cols_[cols_ptr_[a] ..]: its dofs, then its own 3; h_: H^T's 3 values
    // at each of the dofs (3 per column, in the same order as cols_ less the own 3 a contact).
    std::vector<int64_t> cols_ptr_;
    std::vector<PetscInt> cols_;
    std::vector<double> h_;
};

}  // namespace global_newton
}  // namespace mpi
}  // namespace frix
