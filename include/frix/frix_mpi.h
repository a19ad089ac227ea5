/* frix — distributed solves under MPI: libfrix_mpi, built with -DFRIX_WITH_MPI=ON.
 *
 * For host codes that already run under MPI with their contacts partitioned. Each process
 * (rank of the host's communicator) passes the contacts it owns, a contiguous block of the
 * global numbering, and their block rows of W; the processes then solve together, each
 * receiving the reactions of its own contacts. The serial library (libfrix) is unchanged;
 * options, info and whole problems are its handles (frix_options_create, frix_info_create,
 * frix_problem_local, ...), and the error and status codes are its own.
 *
 * One release. libfrix and libfrix_mpi must come from the same release (the same version,
 * built from the same source): libfrix_mpi reads libfrix's handles by their internal layout,
 * which changes between releases. Every call that receives a handle (frix_mpi_solve's options and
 * info, the problem of frix_mpi_partition, frix_mpi_problem_scatter and
 * frix_mpi_problem_scatter_global) first checks that it comes from a libfrix of its own
 * release, and otherwise returns FRIX_ERR_UNSUPPORTED, on every rank, with a message naming
 * both versions; nothing of the handle is read or written then.
 *
 *   frix_mpi_context *ctx;                    (the host's communicator, duplicated)
 *   frix_mpi_context_create(host_comm, &ctx);
 *   frix_mpi_problem *p;                      (this rank: contacts first .. first+owned-1)
 *   frix_mpi_problem_local(ctx, first, owned, row_ptr, block_col, block_val, q, mu, &p);
 *   frix_mpi_solve(p, options, r, u, info);   (r, u: 3*owned values; r is the warm start)
 *   frix_mpi_problem_free(p);
 *   frix_mpi_context_free(ctx);
 *
 * Collective calls. Every function that takes a context or a problem, except the getters
 * and the frees, is collective over the context's communicator: all its ranks call it, in
 * the same order, and all of them return the same frix_error. When one rank's input is
 * refused, every rank gets the error, with the refusing rank's message.
 *
 * Communicator. The context works on its own duplicate of the communicator given and never
 * on MPI_COMM_WORLD: separate contexts (on the halves of a split communicator, say) solve at
 * once without interfering. MPI must be initialised before create and finalised after free;
 * the library never initialises or finalises it. Calls on one context come from one thread.
 *
 * The solve. frix_mpi_solve runs nsgs (FRIX_SOLVER_NSGS, 500), or for local problems the
 * semismooth Newton nsn-ac (FRIX_SOLVER_NSN_AC, 504; see below), or for global problems with
 * the host's M (frix_mpi_problem_global) the global Newton gnsn-ac (607). nsgs is a nonsmooth Gauss-Seidel
 * whose sweep is a Gauss-Seidel over all contacts in an order fixed by the partition. The
 * processes are coloured so that no two neighbours (ranks whose contacts are coupled through
 * W) share a colour; in a sweep a rank sweeps its interior contacts (coupled to its own
 * contacts only) while its boundary contacts wait for the reactions of its neighbours of
 * lower colours. For a fixed partition the results are the same bits on every run; with one
 * rank they are those of frix_solve with the same options. With more ranks the order of the
 * sweep differs, and so do the iterates: the answer meets the same tolerance. The error
 * measure is computed over all contacts, in a fixed order. Options drift_window,
 * acceleration, anderson and shuffle are refused (they steer the whole iterate at once).
 *
 * nsn-ac solves Alart-Curnier's equations over all ranks: each Newton system, a matrix of
 * 3 x 3 blocks over the ranks' rows, by PETSc (KSP, MUMPS's LU), with Armijo's backtracking on
 * 1/2 |Phi|^2 (line_search none: full steps). Options: tolerance, max_iter, time_limit,
 * rho_strategy and rho, line_search, line_search_max_iter, hybrid and hybrid_sweeps (where
 * Newton stagnates, NSGS sweeps of the distributed form, then Newton again); the serial
 * solver's watchdog is not used. On one rank a run gives the same
 * bits every time; on more, MUMPS schedules its factorisation's tasks as they come, and the
 * last bits may change from run to run (nsgs's do not). PETSc is started on the first such
 * solve if the host has not started it (PETSC_COMM_WORLD then a duplicate of the context's
 * communicator, never MPI_COMM_WORLD), and finalised when the last context that needed it
 * is freed; a PETSc the host started is the host's to finalise.
 *
 * Messages. The last failing call's message in this thread: frix_mpi_last_error_message()
 * (libfrix's frix_last_error_message() reports libfrix's own calls only).
 */
#ifndef FRIX_MPI_H
#define FRIX_MPI_H

#include <mpi.h>
#include <stdint.h>
#include "frix_export.h"
#include "frix_errors.h"
#include "frix_options.h"
#include "frix_info.h"
#include "frix_problem.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct frix_mpi_context frix_mpi_context;
typedef struct frix_mpi_problem frix_mpi_problem;

/* A context on a duplicate of `comm` (collective over comm). FRIX_ERR_INVALID_ARGUMENT for
 * MPI_COMM_NULL, a NULL out, or MPI not initialised. */
FRIX_API frix_error frix_mpi_context_create(MPI_Comm comm, frix_mpi_context **out);
/* Frees the duplicate (collective). Free the context's problems first. */
FRIX_API void frix_mpi_context_free(frix_mpi_context *ctx);
/* This process's rank in the context's communicator, and the number of its ranks (not
 * collective); -1 and 0 for a NULL context. */
FRIX_API int frix_mpi_context_rank(const frix_mpi_context *ctx);
FRIX_API int frix_mpi_context_size(const frix_mpi_context *ctx);

/* This rank's part of a local problem (u = W r + q) of n contacts in all: contacts first ..
 * first+owned-1 (owned may be 0), the ranks' blocks in rank order and covering 0 .. n-1.
 * Their block rows of W in 3x3 block-CSR: block row i (contact first+i) holds the blocks
 * row_ptr[i] .. row_ptr[i+1]-1, block k in block column block_col[k] (a global contact
 * index, increasing within the row) with its 9 values column-major at block_val[9k]; q
 * (3*owned values) and mu (owned values). The data are copied. Checked as frix_problem_local
 * checks a whole problem (sizes, finite values, mu >= 0, columns in range), and the blocks
 * against the ranks' blocks. */
FRIX_API frix_error frix_mpi_problem_local(frix_mpi_context *ctx, int64_t first, int64_t owned,
                                           const int64_t *row_ptr, const int64_t *block_col,
                                           const double *block_val, const double *q, const double *mu,
                                           frix_mpi_problem **out);
/* This rank's part of a global problem of rigid bodies (M v = H r + f, u = H^T v + w; M
 * block-diagonal with one 6 x 6 block a body), in product form: W is never formed. The rank
 * owns contacts first .. first+owned-1 (contiguous in rank order, as for
 * frix_mpi_problem_local); contact i acts on bodies bodies[2i] and bodies[2i+1] (global body
 * ids >= 0; -1 for a side without a body, a fixed obstacle), its velocity
 * u_i = G_i0 v_bodies[2i] + G_i1 v_bodies[2i+1] + w_i, with G_is the 3 x 6 block of H^T at
 * G[36i + 18s + 6k + j] (row k, column j: normal first, then the two tangents; the body's 6
 * velocities, translation then rotation, in any fixed convention of the host's). The rank also
 * gives every body its contacts act on (and may give more): `held` bodies, body_ids[b] with its
 * 6 x 6 mass block M[36b ..] (symmetric positive definite) and its f[6b ..]. Ranks that give one
 * body must give it the same M and f. The data are copied. A rank learns which other ranks'
 * contacts act on its bodies by itself (collectively). The error is frix_solve's measure of
 * this global problem, equilibrium included; frix_mpi_problem_velocities gives v after a
 * solve. */
FRIX_API frix_error frix_mpi_problem_rigid(frix_mpi_context *ctx, int64_t first, int64_t owned,
                                           const int64_t *bodies, const double *G, const double *w,
                                           const double *mu, int64_t held, const int64_t *body_ids,
                                           const double *M, const double *f, frix_mpi_problem **out);
/* After frix_mpi_solve of a problem of rigid bodies: v = M^-1 (H r + f) of the bodies this rank
 * gave, 6 values each in the order of body_ids; of a global problem with the host's M: v of
 * this rank's dofs (not collective). FRIX_ERR_INVALID_ARGUMENT for a local problem or before
 * a solve. */
FRIX_API frix_error frix_mpi_problem_velocities(const frix_mpi_problem *p, double *v);

/* This rank's part of a global problem M v = H r + f, u = H^T v + w, whose M is the host's own
 * distributed matrix (deformable bodies, FEM: any sparse M with M v = H r + f solvable), on
 * its rows: W = H^T M^-1 H is never formed and M never factorised alone. The rank owns dofs
 * dof_first .. dof_first+dofs-1 and contacts first .. first+owned-1, each a contiguous block in
 * rank order from 0, as for frix_mpi_problem_local (either count may be 0). It gives its
 * rows of M in CSR: row i (dof dof_first+i) holds the values M_val[k] in the columns M_col[k]
 * (global dofs, increasing), k = M_row_ptr[i] .. M_row_ptr[i+1]-1, and f (dofs values); its
 * contacts' rows of H^T in CSR, 3 a contact (normal first, then the two tangents): row j holds
 * Ht_val[k] in columns Ht_col[k] (global dofs, increasing), k = Ht_row_ptr[j] ..
 * Ht_row_ptr[j+1]-1; w (3*owned values) and mu (owned). The data are copied. frix_mpi_solve
 * runs the global Newton gnsn-ac (FRIX_SOLVER_GLOBAL_NSN_AC, 607) on it, with MUMPS on its
 * Jacobian over the ranks' rows of (v, r); the error's scale is |w|, as in frix_solve, and
 * converged means the equilibrium residual |M v - H r - f| (relative) meets the tolerance
 * too. frix_mpi_problem_velocities gives the owned dofs' v. */
FRIX_API frix_error frix_mpi_problem_global(frix_mpi_context *ctx, int64_t dof_first, int64_t dofs,
                                            const int64_t *M_row_ptr, const int64_t *M_col, const double *M_val,
                                            const double *f, int64_t first, int64_t owned, const int64_t *Ht_row_ptr,
                                            const int64_t *Ht_col, const double *Ht_val, const double *w,
                                            const double *mu, frix_mpi_problem **out);
/* A whole global problem held by rank `root` (read there only), sent to the ranks as
 * frix_mpi_problem_global's parts without reducing it: the dofs in blocks of equal size in
 * their order (the first ranks one more), the contacts by `part` as frix_mpi_problem_scatter
 * sends them (NULL: blocks). FRIX_ERR_INVALID_ARGUMENT for a local problem. */
FRIX_API frix_error frix_mpi_problem_scatter_global(frix_mpi_context *ctx, int root, const frix_problem *problem,
                                                    const int *part, frix_mpi_problem **out);

/* A whole problem held by rank `root` (`problem` is read on root only; NULL elsewhere), sent
 * to the ranks: rank k receives the contacts a with part[a] == k (`part`: one rank per
 * contact, read on root, as frix_mpi_partition gives; NULL for blocks of equal size in the
 * problem's order, the first ranks one contact more). The ranks' contacts are numbered rank
 * after rank, each rank's in their order in the problem; frix_mpi_problem_ids tells which
 * contacts a rank holds, and frix_mpi_gather puts them back in the problem's order. A local
 * problem's W must be stored in 3x3 blocks, as problems read from files are. A global problem
 * is reduced on the root (W = H^T M^-1 H, q = H^T M^-1 f + w, as frix_solve reduces it for
 * nsgs) and its answer is measured as frix_solve measures the global problem's. */
FRIX_API frix_error frix_mpi_problem_scatter(frix_mpi_context *ctx, int root, const frix_problem *problem,
                                             const int *part, frix_mpi_problem **out);
/* A part (rank) for each contact of a whole problem held by rank `root` (collective; part:
 * nc values, written on root), so that each rank gets about as much work and as few
 * contacts coupled to other ranks' as Scotch finds on the contact graph: contacts coupled by
 * W, or for a global problem acting on a common dof. Scotch runs on the root, deterministic:
 * the same parts for the same problem and number of ranks on every run. With one rank, all
 * zeros. */
FRIX_API frix_error frix_mpi_partition(frix_mpi_context *ctx, int root, const frix_problem *problem, int *part);
FRIX_API void frix_mpi_problem_free(frix_mpi_problem *p);

/* What a distributed problem holds (not collective). */
typedef enum frix_mpi_key FRIX_ENUM_BASE {
    FRIX_MPI_CONTACTS = 1,        /* contacts of the whole problem */
    FRIX_MPI_FIRST = 2,           /* this rank's first contact */
    FRIX_MPI_OWNED = 3,           /* this rank's contacts */
    FRIX_MPI_GHOSTS = 4,          /* other ranks' contacts that this rank's rows couple to */
    FRIX_MPI_BOUNDARY = 5,        /* this rank's contacts coupled to another rank's */
    FRIX_MPI_NEIGHBOURS = 6,      /* ranks this rank exchanges reactions with */
    FRIX_MPI_COLOUR = 7,          /* this rank's colour in the sweep's order */
    FRIX_MPI_COLOURS = 8,         /* colours of all ranks */
    FRIX_MPI_MESSAGES_SENT = 9,   /* messages this rank sends in one sweep */
    FRIX_MPI_DOF_FIRST = 10,      /* a global problem with the host's M: this rank's first dof */
    FRIX_MPI_DOFS = 11            /* and its dofs (0 for other problems) */
} frix_mpi_key;
FRIX_API frix_error frix_mpi_problem_get_int(const frix_mpi_problem *p, frix_mpi_key key, int64_t *value);
/* The index in the whole problem of each of this rank's contacts (owned values): first ..
 * first+owned-1, unless frix_mpi_problem_scatter renumbered them by part. */
FRIX_API frix_error frix_mpi_problem_ids(const frix_mpi_problem *p, int64_t *ids);

/* Solves (collective). r: this rank's 3*owned reactions, the warm start in (0 for a cold
 * start; non-finite entries are started from 0) and the result out; u: 3*owned, receives
 * W r + q (H^T v + w for global problems). options: NULL for nsgs's defaults (gnsn-ac's for a
 * global problem with the host's M), else options of FRIX_SOLVER_NSGS or (for a problem with
 * W) FRIX_SOLVER_NSN_AC, or for a global problem with the host's M FRIX_SOLVER_GLOBAL_NSN_AC
 * (options tolerance, max_iter, time_limit, rho_strategy, rho, line_search,
 * line_search_max_iter, as for frix_solve); the same on
 * every rank (the tolerance, the limits), except the callback and log sink, which each rank
 * may set or not. A callback asking to stop, or a time limit reached, on any rank stops all.
 * Only rank 0 logs. info (may be NULL) receives what frix_solve reports: status,
 * iterations (sweeps), the error measures over all contacts, solve time. */
FRIX_API frix_error frix_mpi_solve(frix_mpi_problem *p, const frix_options *options, double *r, double *u,
                                   frix_info *info);

/* Gathers a per-contact vector (3 values a contact) to rank `root` (collective): each rank
 * gives its 3*owned values, root receives all 3*n in x_all (ignored elsewhere), each contact's
 * at its index in the whole problem (frix_mpi_problem_ids). */
FRIX_API frix_error frix_mpi_gather(const frix_mpi_problem *p, int root, const double *x_owned, double *x_all);

/* The message of this thread's last failing frix_mpi_* call. */
FRIX_API const char *frix_mpi_last_error_message(void);

#ifdef __cplusplus
}
#endif

#endif /* FRIX_MPI_H */
