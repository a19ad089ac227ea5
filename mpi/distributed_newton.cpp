// The distributed semismooth Newton (nsn-ac, 504): Alart-Curnier's Phi(r, W r + q) = 0 over
// all ranks, on the Newton loop of the serial solvers (solvers/kit/newton_engine.hpp): each
// Newton system J dr = -Phi solved by PETSc (a block matrix of 3 x 3 blocks over the ranks'
// rows, KSP with MUMPS's LU), Armijo's backtracking on the merit 1/2 |Phi|^2, and where Newton
// stagnates the NSGS sweeps of the distributed form (option hybrid, as the serial nsn-ac).
#include <petscksp.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "mpi/distributed_forms.hpp"
#include "mpi/petsc_support.hpp"
#include "solvers/kit/newton_engine.hpp"
#include "solvers/kit/sweeps.hpp"
#include "solvers/kit/nsn_functions.hpp"
#include "src/error_state.hpp"
#include "src/log.hpp"
#include "src/monitor.hpp"

namespace frix {
namespace mpi {
namespace {

frix_error petsc(PetscErrorCode rc, const char *what) { return petsc_call(rc, FRIX_ERR_INTERNAL, "nsn-ac", what); }

// The Newton system over the ranks: J (3 x 3 blocks, this rank's rows), Phi and the step.
class PetscSystem {
   public:
    explicit PetscSystem(const frix_mpi_problem &p) : p_(p) {}
    ~PetscSystem() {
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

// The distributed nsn-ac as kit::NewtonLoop's system: Alart-Curnier's Phi(r, W r + q) over the
// ranks, r (owned then ghosts, the ghosts current) in place, u = W r + q of the owned contacts.
class RanksSystem : public kit::SystemDefaults {
   public:
    using Point = std::vector<double>;
    RanksSystem(frix_mpi_problem &p, DistributedForm &form, PetscSystem &petsc, const frix_options &o, double *r,
                double *u)
        : p_(p), form_(form), petsc_(petsc), comm_(p.ctx->comm), r_(r), u_(u), m_(3 * p.owned),
          held_(3 * (p.owned + p.ghosts.size())), measure_(o.i(FRIX_OPT_ERROR_MEASURE)),
          verbosity_(o.i(FRIX_OPT_VERBOSITY)), o_(o), rho_(2 * (size_t)p.owned), phi_((size_t)m_ + 1), dr_(held_, 0.0),
          trial_(held_), u_trial_((size_t)m_ + 1), phi_trial_((size_t)m_ + 1) {
        static const double kZero[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
        double diag_sum = 0.0;
        for (int64_t a = 0; a < p.owned; ++a) {
            const int64_t d = p.W.diag_index[(size_t)a];
            nsn::contact_rho((int)o.i(FRIX_OPT_RHO_STRATEGY), o.d(FRIX_OPT_RHO), d >= 0 ? &p.W.block_val[9 * (size_t)d] : kZero,
                             &rho_[2 * (size_t)a], &rho_[2 * (size_t)a + 1]);
            if (d >= 0)
                for (int i = 0; i < 3; ++i) diag_sum += std::fabs(p.W.block_val[9 * (size_t)d + 4 * i]) / 3.0;
        }
        // The scale of delta: the mean |W_aa| (the diagonal's mean magnitude) over all contacts.
        reduce_all(comm_, &diag_sum, 1, "s");
        w_scale_ = p.total > 0 ? diag_sum / (double)p.total : 0.0;
    }
    frix_error evaluate(double &psi, double &err) {
        err = selected_error(form_.exact(r_, u_), measure_);
        phi_at(p_, r_, u_, rho_, phi_.data());  // u = W r + q: form.exact() has just formed it
        psi = theta_ = merit(comm_, phi_.data(), m_);
        return FRIX_OK;
    }
    frix_error factor(double delta, kit::Factorisation &f) {
        if (frix_error e = mpi::agree(comm_, petsc_.assemble(r_, u_, rho_, delta * w_scale_, phi_.data()), "frix_mpi_solve"))
            return e;
        return mpi::agree(comm_, petsc_.solve(phi_.data(), dr_.data(), f.factored), "frix_mpi_solve");
    }
    frix_error solve(bool &finite) {
        form_.exchange(dr_.data());  // the ghosts' steps, from their owners
        bool mine = true;
        for (int64_t i = 0; i < m_ && mine; ++i) mine = std::isfinite(dr_[(size_t)i]);
        finite = or_all(comm_, mine ? 0u : 1u) == 0;
        return FRIX_OK;
    }
    // The slope of 1/2 |Phi|^2 along an exact Newton step (its search writes the test with it).
    frix_error directional(double &slope) {
        slope = -2.0 * theta_;
        return FRIX_OK;
    }
    double merit_at(double t) {
        for (size_t i = 0; i < held_; ++i) trial_[i] = r_[i] + t * dr_[i];
        if (p_.owned > 0) {
            matrix_gemv(p_.W, 1.0, trial_.data(), 0.0, u_trial_.data());
            for (int64_t i = 0; i < m_; ++i) u_trial_[(size_t)i] += p_.q[(size_t)i];
            phi_at(p_, trial_.data(), u_trial_.data(), rho_, phi_trial_.data());
        }
        return merit(comm_, phi_trial_.data(), m_);
    }
    void move(double t) {
        for (size_t i = 0; i < held_; ++i) r_[i] += t * dr_[i];
    }
    void save(Point &x) const { x.assign(r_, r_ + held_); }
    void load(const Point &x) { std::copy(x.begin(), x.end(), r_); }
    Monitor::Agree agree() const { return over_ranks(comm_); }
    void log_step(int64_t step, double t, double err, double, double) const {
        if (verbosity_ >= 1) log_line(&o_, "nsn-ac (distributed): step %lld, t %.3g, error %.3e", (long long)step, t, err);
    }

   private:
    frix_mpi_problem &p_;
    DistributedForm &form_;
    PetscSystem &petsc_;
    const MPI_Comm comm_;
    double *r_, *u_;
    const int64_t m_;
    const size_t held_;
    const int64_t measure_, verbosity_;
    const frix_options &o_;
    std::vector<double> rho_, phi_, dr_, trial_, u_trial_, phi_trial_;
    double w_scale_ = 0.0, theta_ = 0.0;
};

// The hybrid's rounds (kit::newton_with_sweeps) over the ranks: Newton, and NSGS sweeps of the
// distributed form with the closed-form one-contact solver, as the serial nsn-ac's.
class RanksRounds {
   public:
    RanksRounds(RanksSystem &system, const kit::Rules &rules, kit::Steps &steps, kit::Counters &counters,
                frix_mpi_problem &p, DistributedForm &form, const frix_options &o, double *r, double *u)
        : system_(system), rules_(rules), steps_(steps), counters_(counters), p_(p), form_(form), o_(o), r_(r), u_(u) {}
    frix_error newton(kit::RunResult &res) { return kit::newton(system_, steps_, rules_, counters_, res); }
    void keep() {
        if (!ws_) {
            nsgs::Settings gss;
            gss.local.solver = local::kClosedForm;
            ws_ = std::make_unique<nsgs::Workspace>(p_.view, gss);
        }
        system_.save(kept_);
    }
    void restore() { system_.load(kept_); }
    void sweep() { form_.sweep(*ws_, r_, u_); }
    double error() { return selected_error(form_.exact(r_, u_), o_.i(FRIX_OPT_ERROR_MEASURE)); }
    void log_sweeps(double before, double after) const {
        if (o_.i(FRIX_OPT_VERBOSITY) >= 1)
            log_line(&o_, "nsn-ac (distributed): stalled at %.3e, %lld NSGS sweeps -> %.3e", before,
                     (long long)o_.i(FRIX_OPT_HYBRID_SWEEPS), after);
    }
    Monitor::Agree agree() const { return system_.agree(); }

   private:
    RanksSystem &system_;
    const kit::Rules &rules_;
    kit::Steps &steps_;
    kit::Counters &counters_;
    frix_mpi_problem &p_;
    DistributedForm &form_;
    const frix_options &o_;
    double *r_, *u_;
    std::unique_ptr<nsgs::Workspace> ws_;
    RanksSystem::Point kept_;
};

// The distributed nsn-ac's rules. Its line search is Armijo's in the Newton-merit form whatever
// line_search asks (but none); and, where it is not the serial nsn-ac's, its results are kept
// as they were: the last iterate, no stall test, stagnated where J does not factorise however
// regularised or no step lowers the merit however short (delta above kit::kDeltaMax). No
// watchdog: on this path nsn-ac's default one loses converging runs
// (notes/2026-11-28-newton-kit.md).
kit::Rules rules_of(const frix_options &o) {
    kit::Rules rules;
    rules.search = kit::newton_merit_search_of(o.i(FRIX_OPT_LINE_SEARCH), o.i(FRIX_OPT_LINE_SEARCH_MAX_ITER));
    rules.keep_best = false;
    rules.stall = false;
    rules.singular = FRIX_STATUS_STAGNATED;
    rules.stagnate_above_cap = true;
    return rules;
}

}  // namespace

frix_error run_newton(frix_mpi_problem &p, SolveContext &ctx, DistributedForm &form) {
    const MPI_Comm comm = p.ctx->comm;
    const frix_options &o = ctx.options;
    double *r = ctx.r, *u = ctx.u;
    if (frix_error e = agree(comm, use_petsc(*p.ctx), "frix_mpi_solve")) return e;
    PetscSystem petsc(p);
    if (frix_error e = agree(comm, petsc.setup(), "frix_mpi_solve")) return e;
    RanksSystem system(p, form, petsc, o, r, u);
    const kit::Rules rules = rules_of(o);
    kit::Steps steps{Monitor(ctx)};  // r watched on this rank's contacts, the stop agreed
    kit::Counters counters;
    kit::RunResult res;
    RanksRounds rounds(system, rules, steps, counters, p, form, o, r, u);
    if (frix_error e = kit::newton_with_sweeps(rounds, steps, o.i(FRIX_OPT_HYBRID) == FRIX_HYBRID_NSGS,
                                               o.i(FRIX_OPT_HYBRID_SWEEPS), counters, res))
        return e;
    kit::record(ctx.info, res, steps, counters);
    return FRIX_OK;
}

}  // namespace mpi
}  // namespace frix
