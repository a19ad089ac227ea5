// Internal layout of the distributed handles (include/frix/frix_mpi.h) and the collective
// helpers their functions share. The MPI layer sits above the solvers: it may include them.
#pragma once

#include <frix/frix_mpi.h>

#include <cstdint>
#include <string>
#include <vector>

#include "src/matrix.hpp"
#include "src/problem.hpp"

struct frix_mpi_context {
    MPI_Comm comm = MPI_COMM_NULL;  // the duplicate; never the caller's own
    int rank = 0, size = 1;
};

// One rank's part of a distributed local problem. Its contacts are numbered locally: the
// owned ones 0 .. owned-1 (global first + i), then the ghosts, other ranks' contacts that
// the owned rows couple to, owned + g for ghosts[g] (increasing global indices, so that each
// neighbour's ghosts are one run). W holds the owned block rows over these local columns, in
// the caller's order of blocks (the order of the sums is the serial problem's).
struct frix_mpi_problem {
    const frix_mpi_context *ctx = nullptr;
    int64_t total = 0, first = 0, owned = 0;
    std::vector<int64_t> starts;  // size + 1: rank k owns starts[k] .. starts[k+1]-1
    frix_matrix W;
    std::vector<double> q, mu;
    std::vector<int64_t> ghosts;
    // The owned contacts' indices in the problem given (frix_mpi_problem_scatter may have
    // renumbered them by part): what frix_mpi_gather puts them back at.
    std::vector<int64_t> ids;
    frix_problem view;  // nc = owned, over W, q and mu: what the sweeps and measures read

    // The exchange. neighbours: the ranks coupled to this one (either way), increasing.
    // For neighbour k: the owned contacts it needs, send[send_ptr[k] .. send_ptr[k+1]), and
    // the ghosts it owns, recv_ptr[k] .. recv_ptr[k+1] (ghost slots).
    std::vector<int> neighbours;
    std::vector<int64_t> send_ptr, send, recv_ptr;
    std::vector<int> neighbour_colour;
    // The owned contacts coupled to another rank's (either way), and the others, increasing.
    std::vector<int64_t> boundary, interior;
    int colour = 0, colours = 1;
    // A reduced global problem's w (the relative error's scale is |w|, not |q|); empty for a
    // local problem.
    std::vector<double> w;
    const double *scale() const { return w.empty() ? q.data() : w.data(); }
};

namespace frix {
namespace mpi {

// A collective call's outcome, agreed: every rank returns the lowest refusing rank's error
// with its message (a rank that did not refuse reports where it came from).
frix_error agree(MPI_Comm comm, frix_error mine, const char *where);

// Throws Failure (FRIX_ERR_INTERNAL, with MPI's message) unless rc is MPI_SUCCESS: the
// contexts' communicators return MPI's errors instead of aborting.
void check(int rc, const char *what);

// Every rank's `count` doubles, rank by rank, on every rank: sums and maxima combined from
// them in rank order have the same bits everywhere, whatever MPI's own reduction order.
std::vector<double> gather_all(MPI_Comm comm, const double *mine, int count);

// The bitwise or of `flags` over the ranks.
unsigned or_all(MPI_Comm comm, unsigned flags);

}  // namespace mpi
}  // namespace frix
