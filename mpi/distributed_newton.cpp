// The distributed semismooth Newton (nsn-ac, 504): Alart-Curnier's Phi(r, W r + q) = 0 over
// all ranks, each Newton system J dr = -Phi solved by PETSc (a block matrix of 3 x 3 blocks
// over the ranks' rows, KSP with MUMPS's LU), Armijo's backtracking on the merit 1/2 |Phi|^2.
#include <petscksp.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "mpi/distributed_forms.hpp"
#include "mpi/petsc_support.hpp"
#include "solvers/nsn_functions.hpp"
#include "src/error_state.hpp"
#include "src/log.hpp"
#include "src/monitor.hpp"

namespace frix {
namespace mpi {
namespace {

frix_error petsc(PetscErrorCode rc, const char *what) { return petsc_call(rc, FRIX_ERR_INTERNAL, "nsn-ac", what); }

// Armijo's sufficient decrease, as the serial line search's.
constexpr double kArmijoSigma = 1e-4;
// J = A + B (W + delta w_scale I), as the serial nsn-ac regularises it: rank-deficient W
// (rigid scenes) makes J singular on the sticking contacts. delta starts at kDeltaStart, grows
// a hundredfold while J does not factorise, and falls tenfold after each full step, to 0 below
// kDeltaFloor; a step without any decrease of the merit raises it tenfold.
constexpr double kDeltaStart = 1e-6, kDeltaFloor = 1e-8, kDeltaMax = 1e6;
constexpr unsigned kStopAsked = 1u, kOutOfTime = 2u;

// The Newton system over the ranks: J (3 x 3 blocks, this rank's rows), Phi and the step.
class System {
   public:
    explicit System(const frix_mpi_problem &p) : p_(p) {}
    ~System() {
        KSPDestroy(&ksp_);
        VecDestroy(&rhs_);
        VecDestroy(&step_);
        MatDestroy(&J_);
    }
    frix_error setup() {
        const MPI_Comm comm = p_.ctx->comm;
        const PetscInt rows = (PetscInt)(3 * p_.owned);
        std::vector<PetscInt> d_nnz((size_t)p_.owned + 1, 0), o_nnz((size_t)p_.owned + 1, 0);
        for (int64_t a = 0; a < p_.owned; ++a) {
            for (int64_t k = p_.W.row_ptr[(size_t)a]; k < p_.W.row_ptr[(size_t)a + 1]; ++k)
                ++(p_.W.block_col[(size_t)k] < p_.owned ? d_nnz : o_nnz)[(size_t)a];
            if (p_.W.diag_index[(size_t)a] < 0) ++d_nnz[(size_t)a];
        }
        if (frix_error e = petsc(MatCreateBAIJ(comm, 3, rows, rows, PETSC_DETERMINE, PETSC_DETERMINE, 0, d_nnz.data(), 0,
                                               o_nnz.data(), &J_),
                                 "MatCreateBAIJ"))
            return e;
        // The blocks are given column-major, as frix stores them.
        if (frix_error e = petsc(MatSetOption(J_, MAT_ROW_ORIENTED, PETSC_FALSE), "MatSetOption")) return e;
        if (frix_error e = petsc(MatCreateVecs(J_, &step_, &rhs_), "MatCreateVecs")) return e;
        return make_ksp();
    }
    frix_error make_ksp() { return mumps_lu(p_.ctx->comm, J_, ksp_, "nsn-ac", kMumpsAmd); }
    // J = A + B (W + shift I) at (r, u) with the contacts' rho; phi receives Phi (3 per owned
    // contact).
    frix_error assemble(const double *r, const double *u, const std::vector<double> &rho, double shift, double *phi) {
        double A[9], B[9], J[9];
        for (int64_t a = 0; a < p_.owned; ++a) {
            nsn::contact_function(nsn::kAlartCurnier, r + 3 * a, u + 3 * a, p_.mu[(size_t)a], rho[2 * (size_t)a],
                                  rho[2 * (size_t)a + 1], phi + 3 * a, A, B);
            const PetscInt row = (PetscInt)(p_.first + a);
            bool diagonal = false;
            for (int64_t k = p_.W.row_ptr[(size_t)a]; k < p_.W.row_ptr[(size_t)a + 1]; ++k) {
                const int64_t b = p_.W.block_col[(size_t)k];
                const double *Wab = &p_.W.block_val[9 * (size_t)k];
                for (int j = 0; j < 3; ++j)
                    for (int i = 0; i < 3; ++i) {
                        double s = b == a ? A[i + 3 * j] + shift * B[i + 3 * j] : 0.0;
                        for (int l = 0; l < 3; ++l) s += B[i + 3 * l] * Wab[l + 3 * j];
                        J[i + 3 * j] = s;
                    }
                diagonal = diagonal || b == a;
                const PetscInt col = (PetscInt)(b < p_.owned ? p_.first + b : p_.ghosts[(size_t)(b - p_.owned)]);
                if (frix_error e = petsc(MatSetValuesBlocked(J_, 1, &row, 1, &col, J, INSERT_VALUES), "MatSetValuesBlocked"))
                    return e;
            }
            if (!diagonal) {
                for (int i = 0; i < 9; ++i) J[i] = A[i] + shift * B[i];
                if (frix_error e = petsc(MatSetValuesBlocked(J_, 1, &row, 1, &row, J, INSERT_VALUES), "MatSetValuesBlocked"))
                    return e;
            }
        }
        if (frix_error e = petsc(MatAssemblyBegin(J_, MAT_FINAL_ASSEMBLY), "MatAssemblyBegin")) return e;
        return petsc(MatAssemblyEnd(J_, MAT_FINAL_ASSEMBLY), "MatAssemblyEnd");
    }
    // dr = -J^-1 phi (this rank's 3 per owned contact); factored: false when J did not
    // factorise (the same on every rank).
    frix_error solve(const double *phi, double *dr, bool &factored) {
        PetscScalar *x = nullptr;
        if (frix_error e = petsc(VecGetArray(rhs_, &x), "VecGetArray")) return e;
        for (int64_t i = 0; i < 3 * p_.owned; ++i) x[i] = -phi[i];
        VecRestoreArray(rhs_, &x);
        if (frix_error e = mumps_solve(p_.ctx->comm, J_, ksp_, rhs_, step_, factored, "nsn-ac", kMumpsAmd)) return e;
        if (!factored) return FRIX_OK;
        const PetscScalar *y = nullptr;
        if (frix_error e = petsc(VecGetArrayRead(step_, &y), "VecGetArrayRead")) return e;
        std::copy(y, y + 3 * p_.owned, dr);
        VecRestoreArrayRead(step_, &y);
        return FRIX_OK;
    }

   private:
    const frix_mpi_problem &p_;
    Mat J_ = nullptr;
    Vec rhs_ = nullptr, step_ = nullptr;
    KSP ksp_ = nullptr;
};

// 1/2 |Phi|^2 over the ranks.
double merit(MPI_Comm comm, const double *phi, int64_t n) {
    double s = 0.0;
    for (int64_t i = 0; i < n; ++i) s += phi[i] * phi[i];
    reduce_all(comm, &s, 1, "s");
    return 0.5 * s;
}

// Phi at (r, u) of the owned contacts.
void phi_at(const frix_mpi_problem &p, const double *r, const double *u, const std::vector<double> &rho, double *phi) {
    for (int64_t a = 0; a < p.owned; ++a)
        nsn::contact_function(nsn::kAlartCurnier, r + 3 * a, u + 3 * a, p.mu[(size_t)a], rho[2 * (size_t)a],
                              rho[2 * (size_t)a + 1], phi + 3 * a, nullptr, nullptr);
}

// Phi at r (owned and ghosts current); u receives W r + q of the owned contacts.
void residual(const frix_mpi_problem &p, const double *r, const std::vector<double> &rho, double *u, double *phi) {
    if (p.owned == 0) return;
    matrix_gemv(p.W, 1.0, r, 0.0, u);
    for (int64_t i = 0; i < 3 * p.owned; ++i) u[i] += p.q[(size_t)i];
    phi_at(p, r, u, rho, phi);
}

}  // namespace

frix_error run_newton(frix_mpi_problem &p, const frix_options &o, DistributedForm &form, double *r, double *u,
                      frix_info &info, const Stopwatch &clock) {
    const MPI_Comm comm = p.ctx->comm;
    const Monitor monitor(o, clock);
    const double tol = monitor.tolerance();
    const int64_t max_iter = monitor.max_iterations(), m = 3 * p.owned;
    const int64_t verbosity = o.i(FRIX_OPT_VERBOSITY), measure = o.i(FRIX_OPT_ERROR_MEASURE);
    const bool line_search = o.i(FRIX_OPT_LINE_SEARCH) != FRIX_LINE_SEARCH_NONE;
    const int64_t backtracks = std::max<int64_t>(o.i(FRIX_OPT_LINE_SEARCH_MAX_ITER), 1);
    if (frix_error e = agree(comm, use_petsc(*p.ctx), "frix_mpi_solve")) return e;
    System system(p);
    if (frix_error e = agree(comm, system.setup(), "frix_mpi_solve")) return e;
    std::vector<double> rho(2 * (size_t)p.owned);
    for (int64_t a = 0; a < p.owned; ++a) {
        const int64_t d = p.W.diag_index[(size_t)a];
        static const double kZero[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
        nsn::contact_rho((int)o.i(FRIX_OPT_RHO_STRATEGY), o.d(FRIX_OPT_RHO), d >= 0 ? &p.W.block_val[9 * (size_t)d] : kZero,
                         &rho[2 * (size_t)a], &rho[2 * (size_t)a + 1]);
    }
    // The scale of delta: the mean |W_aa| (the diagonal's mean magnitude) over all contacts.
    double diag_sum = 0.0;
    for (int64_t a = 0; a < p.owned; ++a) {
        const int64_t d = p.W.diag_index[(size_t)a];
        if (d >= 0)
            for (int i = 0; i < 3; ++i) diag_sum += std::fabs(p.W.block_val[9 * (size_t)d + 4 * i]) / 3.0;
    }
    reduce_all(comm, &diag_sum, 1, "s");
    const double w_scale = p.total > 0 ? diag_sum / (double)p.total : 0.0;
    double delta = kDeltaStart;
    const size_t held = 3 * (p.owned + p.ghosts.size());
    std::vector<double> phi((size_t)m + 1), dr(held, 0.0), trial(held), u_trial((size_t)m + 1), phi_trial((size_t)m + 1);
    info.status = FRIX_STATUS_MAX_ITER;
    double error = selected_error(form.exact(r, u), measure);
    int64_t it = 0;
    for (; it < max_iter && !(error <= tol); ++it) {
        phi_at(p, r, u, rho, phi.data());  // u = W r + q: form.exact() has just formed it
        const double theta = merit(comm, phi.data(), m);
        bool factored = false;
        while (!factored) {
            if (frix_error e = agree(comm, system.assemble(r, u, rho, delta * w_scale, phi.data()), "frix_mpi_solve"))
                return e;
            if (frix_error e = agree(comm, system.solve(phi.data(), dr.data(), factored), "frix_mpi_solve")) return e;
            if (!factored) delta = delta == 0.0 ? kDeltaStart : 100.0 * delta;
            if (!factored && delta > kDeltaMax) break;
        }
        if (!factored) {  // singular however regularised: no step is left to take
            info.status = FRIX_STATUS_STAGNATED;
            break;
        }
        form.exchange(dr.data());  // the ghosts' steps, from their owners
        // Armijo: theta(r + t dr) <= (1 - 2 sigma t) theta(r), t halved from 1. Without it, the
        // step that lowered theta most is taken; without any decrease, none, and J is
        // regularised further (a shorter, safer step), as the serial nsn-ac does.
        double t = 1.0, best_t = 0.0, best_theta = theta;
        bool accepted = !line_search;
        for (int64_t k = 0; k < backtracks && !accepted; ++k, t *= 0.5) {
            for (size_t i = 0; i < held; ++i) trial[i] = r[i] + t * dr[i];
            residual(p, trial.data(), rho, u_trial.data(), phi_trial.data());
            const double theta_t = merit(comm, phi_trial.data(), m);
            if (theta_t <= (1.0 - 2.0 * kArmijoSigma * t) * theta) {
                accepted = true;
                break;
            }
            if (theta_t < best_theta) best_theta = theta_t, best_t = t;
        }
        if (!accepted && best_t > 0.0) t = best_t, accepted = true;
        if (accepted) {
            for (size_t i = 0; i < held; ++i) r[i] += t * dr[i];
            if (t == 1.0) delta = delta < kDeltaFloor ? 0.0 : 0.1 * delta;
        } else {
            delta = std::max(10.0 * delta, kDeltaStart);
            if (delta > kDeltaMax) {  // no step lowers the merit, however short
                info.status = FRIX_STATUS_STAGNATED;
                ++it;
                break;
            }
        }
        error = selected_error(form.exact(r, u), measure);
        info.newton_iterations = it + 1;
        if (verbosity >= 1) log_line(&o, "nsn-ac (distributed): step %lld, t %.3g, error %.3e", (long long)(it + 1), t, error);
        if (!std::isfinite(error)) {
            info.status = FRIX_STATUS_DIVERGED;
            ++it;
            break;
        }
        const bool stop = monitor.report(it + 1, error);
        const unsigned flags = or_all(comm, (stop ? kStopAsked : 0u) | (monitor.out_of_time() ? kOutOfTime : 0u));
        if (error <= tol) continue;
        if (flags & kStopAsked) {
            info.status = FRIX_STATUS_STOPPED_BY_CALLBACK;
            ++it;
            break;
        }
        if (flags & kOutOfTime) {
            info.status = FRIX_STATUS_TIME_LIMIT;
            ++it;
            break;
        }
    }
    if (error <= tol) info.status = FRIX_STATUS_CONVERGED;
    info.iterations = it;
    return FRIX_OK;
}

}  // namespace mpi
}  // namespace frix
