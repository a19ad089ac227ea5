// The distributed global Newton (gnsn-ac, 607) on a global problem with the host's M: the
// serial gnsn-ac's Newton (solvers/global/gnsn_ac.cpp, on solvers/kit/newton_engine.hpp's
// loop) over the ranks' rows of (v, r), each
// rank holding its dofs' rows of M v - H r - f = 0 and its contacts' rows of
// Phi(r, H^T v + w) = 0. The Jacobian [[M, -H], [B H^T, A]] is one PETSc matrix over the
// ranks' rows (rank k's dofs, then its contacts' 3 rows each), solved by MUMPS's LU.
#include <petscksp.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "mpi/distributed_forms.hpp"
#include "mpi/petsc_support.hpp"
#include "solvers/kit/global_newton.hpp"
#include "solvers/kit/newton.hpp"
#include "solvers/kit/nsn_functions.hpp"
#include "src/error_state.hpp"
#include "src/log.hpp"
#include "src/monitor.hpp"
#include "src/vec.hpp"

namespace frix {
namespace mpi {
namespace {

using namespace gnsn_ac;

frix_error petsc(PetscErrorCode rc, const char *what) { return petsc_call(rc, FRIX_ERR_INTERNAL, "gnsn-ac", what); }

double dot_all(MPI_Comm comm, const double *x, const double *y, int64_t n) {
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

// The contacts' rho from the lumped blocks, corrected where they underrate W's (as the serial
// gnsn-ac), and their scale (mean |W_aa| over all contacts), delta's unit.
struct RanksRho {
    std::vector<double> rho_n, rho_t;
    double scale = 1.0;
};
frix_error lumped_rho(frix_mpi_problem &p, const newton::Settings &s, GlobalSystem &sys, const frix_options &o,
                      RanksRho &out) {
    const MPI_Comm comm = p.ctx->comm;
    const int64_t nc = p.owned;
    std::vector<double> lumped;
    if (frix_error e = agree(comm, sys.lumped_blocks(lumped), "frix_mpi_solve")) return e;
    double underrate = 1.0;
    if (s.rho_strategy != FRIX_RHO_CONSTANT && p.total > 0) {
        const int count = (int)std::min<int64_t>(kRhoSamples, p.total);
        std::vector<double> ratios;
        for (int k = 0; k < count; ++k) {
            const int64_t a = (int64_t)k * p.total / count;
            double exact = 0.0, lumped_trace = 0.0;
            if (frix_error e = agree(comm, sys.exact_trace(a, exact), "frix_mpi_solve")) return e;
            if (a >= p.first && a < p.first + nc) {
                const double *Wd = &lumped[9 * (size_t)(a - p.first)];
                lumped_trace = Wd[0] + Wd[4] + Wd[8];
            }
            reduce_all(comm, &lumped_trace, 1, "s");
            if (lumped_trace > 0.0 && std::isfinite(exact)) ratios.push_back(exact / lumped_trace);
        }
        if (!ratios.empty()) {
            std::nth_element(ratios.begin(), ratios.begin() + ratios.size() / 2, ratios.end());
            underrate = ratios[ratios.size() / 2];
        }
    }
    const double correction = underrate > kUnderrateToCorrect ? underrate : 1.0;
    if (s.verbosity >= 1 && underrate != 1.0)
        log_line(&o, "global newton (distributed): the lumped blocks underrate W's by %.3g%s", underrate,
                 correction != 1.0 ? ": rho corrected" : "");
    out.rho_n.resize((size_t)nc), out.rho_t.resize((size_t)nc);
    double wscale = 0.0;
    for (int64_t a = 0; a < nc; ++a) {
        double Wd[9], fro = 0.0;
        for (int k = 0; k < 9; ++k) Wd[k] = correction * lumped[9 * (size_t)a + (size_t)k], fro += Wd[k] * Wd[k];
        nsn::contact_rho(s.rho_strategy, s.rho, Wd, &out.rho_n[(size_t)a], &out.rho_t[(size_t)a]);
        wscale += std::sqrt(fro);
    }
    reduce_all(comm, &wscale, 1, "s");
    out.scale = p.total > 0 && wscale > 0.0 ? wscale / (double)p.total : 1.0;
    return FRIX_OK;
}

// The newton's iterate (v, r) with what the steps and measures read.
struct State {
    std::vector<double> v, r, u, res, mv, hr, phi, A, B;
};

// The distributed gnsn-ac as kit::NewtonLoop's system: the serial gnsn-ac's (v, r) over the
// ranks' rows, the products and the Jacobian's solves by PETSc.
class RanksVrSystem : public kit::SystemDefaults {
   public:
    struct Point {
        std::vector<double> v, r;
    };
    RanksVrSystem(frix_mpi_problem &p, GlobalSystem &sys, RanksRho rho, const newton::Settings &s, const frix_options &o,
                  const RanksWeights &weights, const double *r)
        : p_(p), g_(*p.global), sys_(sys), comm_(p.ctx->comm), n_(g_.dofs), nc_(p.owned), m_(3 * p.owned),
          rho_(std::move(rho)), s_(s), o_(o), weights_(weights), norm_w_(norm2_all(comm_, p.w.data(), m_)),
          norm_f_(norm2_all(comm_, g_.f.data(), n_)), rhs_((size_t)(n_ + m_)), dx_((size_t)(n_ + m_)), Mdv_((size_t)n_),
          Hdr_((size_t)n_), Htdv_((size_t)m_), scaled_res_((size_t)n_), scaled_hr_((size_t)n_) {
        for (int64_t j = 0; j < n_; ++j) scaled_res_[(size_t)j] = weights_.dof[(size_t)j] * g_.f[(size_t)j];
        norm_df_ = norm2_all(comm_, scaled_res_.data(), n_);
        x_.v.assign((size_t)n_, 0.0);  // v from 0, as the serial gnsn-ac
        x_.r.assign(r, r + m_);
        x_.u.resize((size_t)m_);
        x_.res.resize((size_t)n_);
        x_.mv.resize((size_t)n_);
        x_.hr.resize((size_t)n_);
        x_.phi.resize((size_t)m_);
        x_.A.resize(9 * (size_t)nc_);
        x_.B.resize(9 * (size_t)nc_);
        trial_ = x_;
    }
    frix_error evaluate(double &psi, double &err) {
        psi = merit(x_, true);
        if (frix_error e = stopped()) return e;
        err = error_of(x_);
        return FRIX_OK;
    }
    frix_error factor(double delta, kit::Factorisation &f) {
        if (frix_error e = mpi::agree(comm_, sys_.assemble(x_.A, x_.B, delta * rho_.scale), "frix_mpi_solve")) return e;
        for (int64_t j = 0; j < n_; ++j) rhs_[(size_t)j] = -x_.res[(size_t)j];
        for (int64_t i = 0; i < m_; ++i) rhs_[(size_t)(n_ + i)] = -x_.phi[(size_t)i];
        return mpi::agree(comm_, sys_.solve(rhs_.data(), dx_.data(), f.factored), "frix_mpi_solve");
    }
    frix_error solve(bool &finite) {
        bool mine = true;
        for (size_t i = 0; i < dx_.size() && mine; ++i) mine = std::isfinite(dx_[i]);
        finite = or_all(comm_, mine ? 0u : 1u) == 0;
        return FRIX_OK;
    }
    // Slope of the merit: res . (M dv - H dr) + Phi . (A dr + B H^T dv), over the ranks.
    frix_error directional(double &slope) {
        const double *dv = dx_.data(), *dr = dx_.data() + n_;
        failed_ = sys_.mult_M(dv, Mdv_.data());
        if (!failed_) failed_ = sys_.mult_H(dr, Hdr_.data());
        if (!failed_) failed_ = sys_.mult_Ht(dv, Htdv_.data());
        if (frix_error e = stopped()) return e;
        slope = 0.0;
        for (int64_t j = 0; j < n_; ++j) slope += x_.res[(size_t)j] * (Mdv_[(size_t)j] - Hdr_[(size_t)j]);
        slope = nsn::add_merit_slope(slope, x_.phi.data(), x_.A.data(), x_.B.data(), dr, Htdv_.data(), nc_);
        reduce_all(comm_, &slope, 1, "s");
        return FRIX_OK;
    }
    // The merit over the ranks at (v, r) + t (dv, dr); the equilibrium rows are linear.
    double merit_at(double t) {
        const double *dr = dx_.data() + n_;
        double both[2] = {0.0, 0.0};
        for (int64_t j = 0; j < n_; ++j) {
            const double d = x_.res[(size_t)j] + t * (Mdv_[(size_t)j] - Hdr_[(size_t)j]);
            both[0] += d * d;
        }
        for (int64_t i = 0; i < m_; ++i) {
            trial_.r[(size_t)i] = x_.r[(size_t)i] + t * dr[i];
            trial_.u[(size_t)i] = x_.u[(size_t)i] + t * Htdv_[(size_t)i];
        }
        contacts(trial_, false);
        for (const double d : trial_.phi) both[1] += d * d;
        reduce_all(comm_, both, 2, "ss");
        return 0.5 * (both[0] + both[1]);
    }
    void move(double t) {
        for (int64_t j = 0; j < n_; ++j) x_.v[(size_t)j] += t * dx_[(size_t)j];
        for (int64_t i = 0; i < m_; ++i) x_.r[(size_t)i] += t * dx_[(size_t)(n_ + i)];
    }
    void save(Point &x) const {
        x.v = x_.v;
        x.r = x_.r;
    }
    void load(const Point &x) {  // in place: reactions() stays where it points
        std::copy(x.v.begin(), x.v.end(), x_.v.begin());
        std::copy(x.r.begin(), x.r.end(), x_.r.begin());
    }
    // This rank's reactions of the iterate (3 a contact), where they stay during the run.
    double *reactions() { return x_.r.data(); }
    // The best iterate's measures, for the driver.
    frix_error restored_best() {
        merit(x_, false);
        if (frix_error e = stopped()) return e;
        error_of(x_);
        return FRIX_OK;
    }
    frix_error rejected(int64_t taken, bool &changed, double &psi) {  // gnsn_ac::RhoCuts
        if (!(changed = cuts_.cut(taken))) return FRIX_OK;
        for (int64_t a = 0; a < nc_; ++a) rho_.rho_n[(size_t)a] *= kRhoCut, rho_.rho_t[(size_t)a] *= kRhoCut;
        psi = merit(x_, true);
        return stopped();
    }
    Monitor::Agree agree() const { return over_ranks(comm_); }
    void log_step(int64_t step, double t, double err, double, double delta) const {
        if (s_.verbosity >= 2)
            log_line(&o_, "global newton (distributed): step %lld t %.3g error %.3e equilibrium %.3e delta %.1e",
                     (long long)step, t, err, equilibrium_, delta);
    }
    // The iterate into the caller's r, u and p.v; its measures.
    Measures hand_over(double *r, double *u) {
        std::copy(x_.r.begin(), x_.r.end(), r);
        std::copy(x_.u.begin(), x_.u.end(), u);
        p_.v = x_.v;
        p_.solved = true;
        return measures_;
    }
    // The measures of the answer r (this rank's reactions) with v = M^-1 (H r + f) (collective):
    // into u, v and out (not finite where M does not factorise).
    frix_error measure_answer(const double *r, double *u, double *v, Measures &out) {
        State st = x_;
        st.r.assign(r, r + m_);
        bool solved = false;
        failed_ = sys_.mult_H(st.r.data(), st.hr.data());
        for (int64_t j = 0; j < n_; ++j) st.hr[(size_t)j] += g_.f[(size_t)j];
        if (!failed_) failed_ = sys_.solve_mass(st.hr.data(), st.v.data(), solved);
        merit(st, false);  // (no product once one failed)
        if (frix_error e = stopped()) return e;
        error_of(st);
        out = measures_;
        if (!solved) out.relative = out.scaled = NAN;
        std::copy(st.u.begin(), st.u.end(), u);
        std::copy(st.v.begin(), st.v.end(), v);
        return FRIX_OK;
    }

   private:
    // res = M v - H r - f, u = H^T v + w, Phi (A and B when asked); the merit over the ranks.
    double merit(State &st, bool jacobian) {
        if (!failed_) failed_ = sys_.mult_M(st.v.data(), st.mv.data());
        if (!failed_) failed_ = sys_.mult_H(st.r.data(), st.hr.data());
        if (!failed_) failed_ = sys_.mult_Ht(st.v.data(), st.u.data());
        for (int64_t j = 0; j < n_; ++j) st.res[(size_t)j] = st.mv[(size_t)j] - st.hr[(size_t)j] - g_.f[(size_t)j];
        for (int64_t i = 0; i < m_; ++i) st.u[(size_t)i] += p_.w[(size_t)i];
        contacts(st, jacobian);
        double both[2] = {0.0, 0.0};
        for (const double d : st.res) both[0] += d * d;
        for (const double d : st.phi) both[1] += d * d;
        reduce_all(comm_, both, 2, "ss");
        return 0.5 * (both[0] + both[1]);
    }
    void contacts(State &st, bool jacobian) {
        for (int64_t a = 0; a < nc_; ++a)
            nsn::contact_function(nsn::kAlartCurnier, &st.r[3 * (size_t)a], &st.u[3 * (size_t)a], p_.mu[(size_t)a],
                                  rho_.rho_n[(size_t)a], rho_.rho_t[(size_t)a], &st.phi[3 * (size_t)a],
                                  jacobian ? &st.A[9 * (size_t)a] : nullptr, jacobian ? &st.B[9 * (size_t)a] : nullptr);
    }
    // The measures of (r, v) over all ranks, as global_measures takes them on the whole
    // problem (the same weights: RanksWeights), and the error selected_error takes of them.
    double error_of(const State &st) {
        measures_ = measures_over_ranks(comm_, st.r.data(), st.u.data(), p_.mu.data(), weights_.contact, nc_, norm_w_,
                                        weights_.free);
        for (int64_t j = 0; j < n_; ++j) {
            scaled_res_[(size_t)j] = weights_.dof[(size_t)j] * st.res[(size_t)j];
            scaled_hr_[(size_t)j] = weights_.dof[(size_t)j] * st.hr[(size_t)j];
        }
        measures_.global = true;
        const double norm_mv = norm2_all(comm_, st.mv.data(), n_), norm_hr = norm2_all(comm_, st.hr.data(), n_);
        measures_.equilibrium = relative_equilibrium(norm2_all(comm_, st.res.data(), n_), norm_f_, norm_mv, norm_hr);
        measures_.equilibrium_scaled = scaled_equilibrium(norm2_all(comm_, scaled_res_.data(), n_), norm_df_,
                                                          norm2_all(comm_, scaled_hr_.data(), n_));
        equilibrium_ = measures_.equilibrium;
        return selected_error(measures_, s_.measure);
    }
    frix_error stopped() { return mpi::agree(comm_, failed_, "frix_mpi_solve"); }

    frix_mpi_problem &p_;
    const frix_mpi_global_rows &g_;
    GlobalSystem &sys_;
    const MPI_Comm comm_;
    const int64_t n_, nc_, m_;
    RanksRho rho_;
    const newton::Settings &s_;
    const frix_options &o_;
    const RanksWeights weights_;
    const double norm_w_, norm_f_;
    double norm_df_ = 0.0;  // |D f|
    State x_, trial_;
    std::vector<double> rhs_, dx_, Mdv_, Hdr_, Htdv_;
    std::vector<double> scaled_res_, scaled_hr_;  // D (M v - H r - f) and D H r
    frix_error failed_ = FRIX_OK;
    RhoCuts cuts_;
    Measures measures_;
    double equilibrium_ = 0.0;
};

}  // namespace

frix_error run_global_newton(frix_mpi_problem &p, const frix_options &o, const std::vector<double> &warm_start,
                             double *r_io, double *u_out, frix_info &info, const Stopwatch &clock) {
    const MPI_Comm comm = p.ctx->comm;
    const newton::Settings s = newton::settings_from(o, FRIX_SOLVER_NSN_AC);
    if (frix_error e = agree(comm, use_petsc(*p.ctx), "frix_mpi_solve")) return e;
    GlobalSystem sys(p);
    if (frix_error e = agree(comm, sys.setup(), "frix_mpi_solve")) return e;
    RanksRho rho;
    if (frix_error e = lumped_rho(p, s, sys, o, rho)) return e;
    const RanksWeights weights = ranks_weights(p);
    RanksVrSystem system(p, sys, std::move(rho), s, o, weights, r_io);
    // Watched for a runaway past the serial bound (of free_velocity) on this rank's contacts.
    const frix_problem watched = watched_contacts(p, weights);
    const double bound = runaway_bound(weights.free);
    SolveContext ctx = SolveContext::global(watched, o, system.reactions(), u_out, nullptr, info, clock, nullptr);
    ctx.runaway_bound = bound;
    kit::Steps steps{Monitor(ctx)};
    kit::Counters counters;
    kit::RunResult res;
    if (frix_error e = kit::newton(system, steps, rules_of(s.line_search, s.ls_max_iter), counters, res)) return e;
    Measures meas = system.hand_over(r_io, u_out);
    kit::record(info, res, steps, counters);
    const bool broken = !finite_measures(meas) || !vec::all_finite(r_io, 3 * p.owned) ||
                        !vec::all_finite(p.v.data(), p.global->dofs);
    const MeasureAnswer at = [&system](const double *x, double *ux, double *vx, Measures &out) {
        return system.measure_answer(x, ux, vx, out);
    };
    if (frix_error e = fall_back_on_divergence(watched, s.measure, warm_start, broken, bound, at, r_io, u_out,
                                               p.v.data(), meas, info, over_ranks(comm)))
        return e;
    if (!finite_measures(meas))  // the start, r = 0, has no finite velocity either
        return fail(FRIX_ERR_NUMERICAL, "frix_mpi_solve: gnsn-ac diverged, and M^-1 f is not finite: M is singular "
                                        "or too ill-conditioned");
    record_measures(info, meas, s.measure);
    if (info.status == FRIX_STATUS_CONVERGED && !(res.error <= steps.monitor.tolerance()))
        info.status = FRIX_STATUS_STAGNATED;
    if (s.verbosity >= 1)
        log_line(&o, "global newton (distributed): %s after %lld steps", frix_status_string(info.status),
                 (long long)steps.done);
    return FRIX_OK;
}

}  // namespace mpi
}  // namespace frix
