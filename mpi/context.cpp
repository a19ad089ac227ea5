// The context (a duplicate of the host's communicator) and the collective helpers.
#include <algorithm>
#include <cstring>
#include <vector>
#include <memory>
#include <string>

#include "mpi/distributed.hpp"
#include "src/error_state.hpp"

namespace frix {
namespace mpi {

void check(int rc, const char *what) {
    if (rc == MPI_SUCCESS) return;
    char text[MPI_MAX_ERROR_STRING];
    int length = 0;
    if (MPI_Error_string(rc, text, &length) != MPI_SUCCESS) std::strcpy(text, "unknown MPI error");
    fail(FRIX_ERR_INTERNAL, "%s failed: %s", what, text);
    throw Failure{FRIX_ERR_INTERNAL};
}

frix_error agree(MPI_Comm comm, frix_error mine, const char *where) {
    int rank = 0, size = 1;
    check(MPI_Comm_rank(comm, &rank), "MPI_Comm_rank");
    check(MPI_Comm_size(comm, &size), "MPI_Comm_size");
    int key = mine != FRIX_OK ? rank : size, lowest = size;
    check(MPI_Allreduce(&key, &lowest, 1, MPI_INT, MPI_MIN, comm), "MPI_Allreduce");
    if (lowest == size) return FRIX_OK;
    int code = (int)mine;
    std::string message = rank == lowest ? frix_last_error_message() : "";
    int length = (int)message.size();
    check(MPI_Bcast(&code, 1, MPI_INT, lowest, comm), "MPI_Bcast");
    check(MPI_Bcast(&length, 1, MPI_INT, lowest, comm), "MPI_Bcast");
    message.resize((size_t)length);
    check(MPI_Bcast(&message[0], length, MPI_CHAR, lowest, comm), "MPI_Bcast");
    if (rank == lowest) return mine;
    return fail((frix_error)code, "%s: rank %d refused: %s", where, lowest, message.c_str());
}

void reduce_all(MPI_Comm comm, double *x, int count, const char *ops) {
    constexpr int kTag = 5004;  // the tree's messages, apart from every other exchange
    int rank = 0, size = 1;
    check(MPI_Comm_rank(comm, &rank), "MPI_Comm_rank");
    check(MPI_Comm_size(comm, &size), "MPI_Comm_size");
    std::vector<double> in((size_t)count);
    for (int step = 1; step < size; step *= 2) {
        if (rank % (2 * step) == step) {
            check(MPI_Send(x, count, MPI_DOUBLE, rank - step, kTag, comm), "MPI_Send");
            break;
        }
        if (rank + step < size) {
            check(MPI_Recv(in.data(), count, MPI_DOUBLE, rank + step, kTag, comm, MPI_STATUS_IGNORE), "MPI_Recv");
            for (int i = 0; i < count; ++i) x[i] = ops[i] == 'm' ? std::max(x[i], in[(size_t)i]) : x[i] + in[(size_t)i];
        }
    }
    check(MPI_Bcast(x, count, MPI_DOUBLE, 0, comm), "MPI_Bcast");
}

unsigned or_all(MPI_Comm comm, unsigned flags) {
    unsigned all = 0;
    check(MPI_Allreduce(&flags, &all, 1, MPI_UNSIGNED, MPI_BOR, comm), "MPI_Allreduce");
    return all;
}

}  // namespace mpi
}  // namespace frix

extern "C" {

FRIX_API frix_error frix_mpi_context_create(MPI_Comm comm, frix_mpi_context **out) {
    return frix::guard("frix_mpi_context_create", [&]() -> frix_error {
        using frix::fail;
        if (!out) return fail(FRIX_ERR_INVALID_ARGUMENT, "frix_mpi_context_create: out is NULL");
        *out = nullptr;
        int initialised = 0, finalised = 0;
        MPI_Initialized(&initialised);
        MPI_Finalized(&finalised);
        if (!initialised || finalised)
            return fail(FRIX_ERR_INVALID_ARGUMENT, "frix_mpi_context_create: MPI is not initialised (or already finalised)");
        if (comm == MPI_COMM_NULL) return fail(FRIX_ERR_INVALID_ARGUMENT, "frix_mpi_context_create: comm is MPI_COMM_NULL");
        auto ctx = std::make_unique<frix_mpi_context>();
        frix::mpi::check(MPI_Comm_dup(comm, &ctx->comm), "MPI_Comm_dup");
        // Errors come back as codes on the duplicate, and become frix_errors: never an abort.
        frix::mpi::check(MPI_Comm_set_errhandler(ctx->comm, MPI_ERRORS_RETURN), "MPI_Comm_set_errhandler");
        frix::mpi::check(MPI_Comm_rank(ctx->comm, &ctx->rank), "MPI_Comm_rank");
        frix::mpi::check(MPI_Comm_size(ctx->comm, &ctx->size), "MPI_Comm_size");
        *out = ctx.release();
        return FRIX_OK;
    });
}

FRIX_API void frix_mpi_context_free(frix_mpi_context *ctx) {
    if (!ctx) return;
    int finalised = 0;
    MPI_Finalized(&finalised);
    if (!finalised) frix::mpi::release_petsc(*ctx);
    if (!finalised && ctx->comm != MPI_COMM_NULL) MPI_Comm_free(&ctx->comm);
    delete ctx;
}

FRIX_API int frix_mpi_context_rank(const frix_mpi_context *ctx) { return ctx ? ctx->rank : -1; }
FRIX_API int frix_mpi_context_size(const frix_mpi_context *ctx) { return ctx ? ctx->size : 0; }

FRIX_API const char *frix_mpi_last_error_message(void) { return frix_last_error_message(); }

}  // extern "C"
