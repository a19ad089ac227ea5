// What the PETSc users of libfrix_mpi share (mpi/petsc_support.hpp): PETSc started for the
// contexts that need it (use_petsc, release_petsc), PETSc's errors as frix's, and MUMPS's LU.
#include "mpi/petsc_support.hpp"

#include <cmath>
#include <mutex>

#include "src/error_state.hpp"

namespace frix {
namespace mpi {
namespace {

// PETSc is initialised once a process, and the contexts that need it share it; its state is
// the process's, so the count of its users is too (guarded: contexts may live in different
// threads).
struct PetscShare {
    std::mutex lock;
    int users = 0;                   // contexts holding the PETSc this library started
    MPI_Comm world = MPI_COMM_NULL;  // PETSC_COMM_WORLD then: a duplicate, never MPI_COMM_WORLD
};
PetscShare &petsc_share() {
    static PetscShare share;
    return share;
}

// Starting PETSc fails a solve.
frix_error petsc(PetscErrorCode rc, const char *what) {
    return petsc_call(rc, FRIX_ERR_INTERNAL, "frix_mpi_solve", what);
}

}  // namespace

frix_error petsc_call(PetscErrorCode rc, frix_error code, const char *where, const char *what) {
    if (rc == 0) return FRIX_OK;
    const char *text = nullptr;
    PetscErrorMessage(rc, &text, nullptr);
    return fail(code, "%s: %s failed (PETSc error %d: %s)", where, what, (int)rc, text ? text : "");
}

frix_error mumps_lu(MPI_Comm comm, Mat A, KSP &ksp, const char *where, MumpsOrdering ordering) {
    const auto call = [where](PetscErrorCode rc, const char *what) { return petsc_call(rc, FRIX_ERR_INTERNAL, where, what); };
    KSPDestroy(&ksp);
    PC pc = nullptr;
    Mat factor = nullptr;
    if (frix_error e = call(KSPCreate(comm, &ksp), "KSPCreate")) return e;
    if (frix_error e = call(KSPSetType(ksp, KSPPREONLY), "KSPSetType")) return e;
    if (frix_error e = call(KSPGetPC(ksp, &pc), "KSPGetPC")) return e;
    if (frix_error e = call(PCSetType(pc, PCLU), "PCSetType")) return e;
    if (frix_error e = call(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS), "PCFactorSetMatSolverType")) return e;
    if (frix_error e = call(KSPSetOperators(ksp, A, A), "KSPSetOperators")) return e;
    if (frix_error e = call(PCFactorSetUpMatSolverType(pc), "PCFactorSetUpMatSolverType")) return e;
    if (frix_error e = call(PCFactorGetMatrix(pc, &factor), "PCFactorGetMatrix")) return e;
    // (Over 2 ranks or more MUMPS's factorisation still schedules its tasks dynamically: the
    // last bits may vary from run to run.)
    if (frix_error e = call(MatMumpsSetIcntl(factor, 28, 1), "MatMumpsSetIcntl")) return e;
    return call(MatMumpsSetIcntl(factor, 7, (PetscInt)ordering), "MatMumpsSetIcntl");
}

frix_error mumps_solve(MPI_Comm comm, Mat A, KSP &ksp, Vec b, Vec x, bool &solved, const char *where,
                       MumpsOrdering ordering) {
    const auto call = [where](PetscErrorCode rc, const char *what) { return petsc_call(rc, FRIX_ERR_INTERNAL, where, what); };
    if (frix_error e = call(KSPSetOperators(ksp, A, A), "KSPSetOperators")) return e;
    if (frix_error e = call(KSPSolve(ksp, b, x), "KSPSolve (MUMPS)")) return e;
    KSPConvergedReason reason;
    KSPGetConvergedReason(ksp, &reason);
    bool finite = reason >= 0;
    if (finite) {
        const PetscScalar *y = nullptr;
        PetscInt n = 0;
        if (frix_error e = call(VecGetLocalSize(x, &n), "VecGetLocalSize")) return e;
        if (frix_error e = call(VecGetArrayRead(x, &y), "VecGetArrayRead")) return e;
        for (PetscInt i = 0; i < n && finite; ++i) finite = std::isfinite(y[i]);
        VecRestoreArrayRead(x, &y);
    }
    solved = or_all(comm, finite ? 0u : 1u) == 0;
    if (!solved && reason < 0) return mumps_lu(comm, A, ksp, where, ordering);
    return FRIX_OK;
}

frix_error use_petsc(frix_mpi_context &ctx) {
    if (ctx.holds_petsc) return FRIX_OK;
    PetscShare &share = petsc_share();
    std::lock_guard<std::mutex> hold(share.lock);
    PetscBool initialised = PETSC_FALSE;
    PetscInitialized(&initialised);
    if (share.users == 0 && !initialised) {
        check(MPI_Comm_dup(ctx.comm, &share.world), "MPI_Comm_dup");
        PETSC_COMM_WORLD = share.world;
        // No signal handlers of PETSc's in the host's process; errors come back as codes.
        if (frix_error e = petsc(PetscOptionsSetValue(nullptr, "-no_signal_handler", nullptr), "PetscOptionsSetValue"))
            return e;
        if (frix_error e = petsc(PetscInitializeNoArguments(), "PetscInitialize")) {
            MPI_Comm_free(&share.world);
            return e;
        }
        PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
    } else if (share.users == 0) {
        return FRIX_OK;  // the host started PETSc: it is the host's to stop
    }
    ++share.users;
    ctx.holds_petsc = true;
    return FRIX_OK;
}

void release_petsc(frix_mpi_context &ctx) {
    if (!ctx.holds_petsc) return;
    ctx.holds_petsc = false;
    PetscShare &share = petsc_share();
    std::lock_guard<std::mutex> hold(share.lock);
    if (--share.users > 0) return;
    PetscPopErrorHandler();
    PetscFinalize();
    MPI_Comm_free(&share.world);
}

}  // namespace mpi
}  // namespace frix
