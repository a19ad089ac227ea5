// Internal layout of the distributed handles (include/frix/frix_mpi.h) and the collective
// helpers their functions share. The MPI layer sits above the solvers: it may include them.
#pragma once

#include <frix/frix_mpi.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "src/matrix.hpp"
#include "src/problem.hpp"

// A global problem with the host's M (frix_mpi_problem_global): this rank's dofs dof_first ..
// dof_first+dofs-1 with their rows of M (CSR, global dof columns increasing) and f, and its
// contacts' rows of H^T (3 a contact, CSR over global dofs); dof_starts[k]: rank k's first dof.
struct frix_mpi_global_rows {
    int64_t dof_first = 0, dofs = 0, dof_total = 0;
    std::vector<int64_t> dof_starts;
    std::vector<int64_t> m_ptr, m_col, ht_ptr, ht_col;
    std::vector<double> m_val, f, ht_val;
};

struct frix_mpi_context {
    MPI_Comm comm = MPI_COMM_NULL;  // the duplicate; never the caller's own
    int rank = 0, size = 1;
    bool holds_petsc = false;  // this context counts among the users of the PETSc it started
};

// One rank's part of a distributed local problem. Its contacts are numbered locally: the
// owned ones 0 .. owned-1 (global first + i), then the ghosts, other ranks' contacts that
// the owned rows couple to, owned + g for ghosts[g] (increasing global indices, so that each
// neighbour's ghosts are one run). W holds the owned block rows over these local columns, in
// the caller's order of blocks (the order of the sums is the serial problem's).
struct frix_mpi_problem {
    frix_mpi_context *ctx = nullptr;  // a solve may start PETSc for it
    int64_t total = 0, first = 0, owned = 0;
    std::vector<int64_t> starts;  // size + 1: rank k owns starts[k] .. starts[k+1]-1
    frix_matrix W;
    std::vector<double> q, mu;
    std::vector<int64_t> ghosts;
    // The owned contacts' indices in the problem given (frix_mpi_problem_scatter may have
    // renumbered them by part): what frix_mpi_gather puts them back at.
    std::vector<int64_t> ids;
    frix_problem view;  // nc = owned, over W, q and mu: what the sweeps and measures read; its
                        // weight: the owned contacts' weights in the serial default measure
                        // of the whole problem (set_contact_weights: a local problem's W_aa
                        // normal entries; a reduced or rigid global problem's from H and
                        // diag(M)); empty, so 1, for a global problem with the host's M, whose
                        // Newton measures with RanksWeights
    // The default measure's velocity floor over all contacts (free_velocity of a reduced or
    // rigid global problem); negative: the norm of scale() (a local problem's |q|).
    double free = -1.0;

    // The exchange. neighbours: the ranks coupled to this one (either way), increasing.
    // For neighbour k: the owned contacts it needs, send[send_ptr[k] .. send_ptr[k+1]), and
    // the ghosts it owns, recv_ptr[k] .. recv_ptr[k+1] (ghost slots).
    std::vector<int> neighbours;
    std::vector<int64_t> send_ptr, send, recv_ptr;
    std::vector<int> neighbour_colour;
    // The owned contacts coupled to another rank's (either way), and the others, increasing.
    std::vector<int64_t> boundary, interior;
    int colour = 0, colours = 1;
    // Rigid bodies (frix_mpi_problem_rigid): W is empty and the sweeps keep the bodies'
    // velocities. The bodies given are held in slots, in their order: body_ids, M^-1 (36
    // values) and v0 = M^-1 f (6). Each held contact (owned, then ghosts) has two sides: a
    // slot (-1: no body, or one this rank does not hold), its block G (18 values, row-major,
    // as given) and M^-1 G^T of its body (18, column-major 6 x 3). diag: W_aa of the owned
    // contacts (9, column-major). v: the bodies' velocities after the last solve.
    // The equilibrium measure counts each body once: kept, the bodies whose lowest holding
    // rank this is; M and f of the bodies held (36 and 6 values), dof_weight the kept
    // bodies' 6 values of diag(M)^-1/2 (RanksWeights::dof, in the order of their slots).
    bool rigid = false, solved = false;
    std::vector<int64_t> body_ids, side_slot;
    std::vector<double> minv, v0, G, mg, diag, v, mass, body_f, dof_weight;
    std::vector<char> kept;
    // Set for a global problem with the host's M: W is empty, w and mu are the contacts', and a
    // solve leaves the owned dofs' velocities in v.
    std::unique_ptr<frix_mpi_global_rows> global;
    // A reduced global problem's w, or a rigid one's (the relative error's scale is |w|, not
    // |q|); empty for a local problem.
    std::vector<double> w;
    const double *scale() const { return w.empty() ? q.data() : w.data(); }
};

namespace frix {
namespace mpi {

// A collective call's outcome, agreed: every rank returns the lowest refusing rank's error
// with its message (a rank that did not refuse reports where it came from).
frix_error agree(MPI_Comm comm, frix_error mine, const char *where);

// FRIX_ERR_UNSUPPORTED, naming both releases, unless a handle the host's libfrix made (its
// header `given`) has the layout of this library's copy (`own`): read by that layout, a
// record of another release would be corrupt (src/handle_header.hpp). `what` names it.
frix_error check_release(const HandleHeader &given, const HandleHeader &own, const char *where, const char *what);
template <class Record>
frix_error check_release(const Record &handle, const char *where, const char *what) {
    return check_release(handle.header, header_of<Record>(), where, what);
}

// Throws Failure (FRIX_ERR_INTERNAL, with MPI's message) unless rc is MPI_SUCCESS: the
// contexts' communicators return MPI's errors instead of aborting.
void check(int rc, const char *what);

// x (count values) combined over the ranks, in place on every rank: x[i] summed where ops[i]
// is 's', its maximum where 'm'. The ranks' values are combined pairwise along a binary tree
// of a fixed shape (rank r takes in r + 1, then r + 2, r + 4, ...) and rank 0's result is
// broadcast: the same bits on every rank and every run, whatever MPI's own reductions do,
// in log2(ranks) messages.
void reduce_all(MPI_Comm comm, double *x, int count, const char *ops);

// The bitwise or of `flags` over the ranks.
unsigned or_all(MPI_Comm comm, unsigned flags);

// PETSc for ctx (petsc_support.cpp): started if the host has not started it (on a
// duplicate of ctx's communicator), and finalised when the last context that started it is
// freed.
frix_error use_petsc(frix_mpi_context &ctx);
void release_petsc(frix_mpi_context &ctx);

// x's values that are not positive and finite set to the mean of those of all ranks' x, or 1
// (PositiveMean's fill over the ranks: set_contact_weights' rule on a problem held by ranks).
// Collective.
void fill_over_ranks(MPI_Comm comm, std::vector<double> &x);
// The rank that owns contact g.
int owner_of(const std::vector<int64_t> &starts, int64_t g);
// n as an MPI count; throws Failure (FRIX_ERR_DIMENSION) beyond INT_MAX.
int checked_count(int64_t n);
// A problem for this rank's contacts first .. first+owned-1: the ranks' blocks gathered
// (starts, total, ids). Collective. e is set (unless already) when the blocks are not
// contiguous in rank order from 0.
std::unique_ptr<frix_mpi_problem> start_part(frix_mpi_context *ctx, int64_t first, int64_t owned, frix_error &e,
                                             const char *where);
// A local problem from each rank's block rows (frix_mpi_problem_local's input, checked here);
// scale: the vector whose norm the relative error divides by (q, or a reduced global
// problem's w; null: q). Collective.
frix_error make(frix_mpi_context *ctx, int64_t first, int64_t owned, const int64_t *row_ptr, const int64_t *block_col,
                const double *block_val, const double *q, const double *mu, const double *scale, frix_mpi_problem **out,
                const char *where);
// Rank k's block first_k .. first_k+count_k-1 of `what` (contacts, dofs) from every rank's
// (first, count): starts (size + 1 values) and whether the blocks are contiguous in rank order
// from 0 with count >= 0. Collective.
bool gather_blocks(MPI_Comm comm, int64_t first, int64_t count, std::vector<int64_t> &starts);
// Where each rank's run of n items starts (cut, ranks + 1 values) and, with parts, the items
// in the order of their parts (order: a stable sort; left empty without parts, for blocks of
// equal size, the first ranks one more). FRIX_ERR_INVALID_ARGUMENT for a part not a rank.
frix_error cut_by_part(const int *part, int64_t n, int ranks, std::vector<int64_t> &cut, std::vector<int64_t> &order,
                       const char *where);
// All-to-all of int64 lists: out[k] goes to rank k (out has a list for every rank); returns
// what the ranks sent here, rank by rank, rank k's at (*in_displs)[k] .. [k+1] when asked.
std::vector<int64_t> exchange_lists(MPI_Comm comm, const std::vector<std::vector<int64_t>> &out,
                                    std::vector<int> *in_displs = nullptr);
// The exchange of p (its ghosts set, increasing): the ghosts' owners, the send lists, the
// neighbours, boundary and interior contacts (has_ghost: the owned contacts coupled to a
// ghost) and the ranks' colours. Collective.
void plan_exchange(frix_mpi_problem &p, const std::vector<char> &has_ghost);

}  // namespace mpi
}  // namespace frix
