/* frix — the persistent solver, for codes that solve one problem per time step.
 *
 * frix_solve starts every call from nothing. A persistent solver is created once from a
 * problem and options, then solves, is updated with the next step's data, solves again, and
 * keeps between its solves what still holds:
 *   - global problems: the factorisation of M while M is not replaced, and W = H^T M^-1 H
 *     (for solvers of local problems) while neither M nor H is;
 *   - the symbolic analyses of the Newton-type solvers' systems as long as W's sparsity
 *     pattern stays; admm's factorisations of W + rho I (two: the starting rho's, and the
 *     last one rho adapted to) while W's values stay, their analyses while its pattern does;
 *   - the Newton solvers' workspaces; for auto, all of the above for each of its parts.
 * Each solve gives the answer frix_solve would give from the same warm start, up to the
 * rounding of a reused analysis (its pivot order was chosen on earlier values), except where
 * the secant start below replaces that start.
 * Secant start (option FRIX_OPT_SECANT_START, on by default; not for rolling problems): where
 * r is the last solve's answer, passed back unchanged, M and H (or W) and mu are those of the
 * last two solves (both converged), and the data (f and w, or q) moved along a line over them
 * (for each of them |step - alpha last step| <= 0.1 |step|, 0 < |alpha| <= 2), the solve
 * starts from P_K(r_k + alpha (r_k - r_(k-1))), P_K the projection on the cones: a load path's
 * next answer while the contacts stick or stay open, and often a closer start than r_k
 * otherwise. It is measured and iterated as any start (one that meets the tolerance is the
 * answer). Any other r is the start as given; a refused call hands r back as given.
 *
 *   frix_persistent *ps;
 *   frix_persistent_create(problem, options, &ps);
 *   for (step = 0; step < steps; ++step) {
 *       ... compute the step's q (or f, w), and W (or M, H) if they moved ...
 *       frix_persistent_update_local(ps, W_step, q_step, NULL);   (NULL: unchanged)
 *       frix_persistent_solve(ps, r, u, NULL, info);              (r: the warm start)
 *   }
 *   frix_persistent_free(ps);
 *
 * Data. The persistent solver borrows the problem's matrices and vectors, as a problem
 * borrows its caller's: they must stay valid, unchanged, until an update replaces them or the
 * persistent solver is freed (the frix_problem handle itself may be freed after create).
 * Vectors (q, f, w, mu) may also be changed in place between solves; matrices are immutable,
 * so a new W (or M, H) is given by an update. An update may change a matrix's sparsity
 * pattern too: what was analysed for the old pattern is then analysed again.
 * The number of dofs is fixed. The contacts may come and go: frix_persistent_set_contacts_*
 * gives the next step's contacts whatever their number (M's factorisation is kept across it).
 *
 * Rolling friction (frix_problem.h): a rolling problem, local or global, makes a persistent
 * solver of rolling problems (with a solver that solves them: auto or rolling-nsgs). Its r and
 * u have 5 entries a contact, and so do the sizes the updates check (W 5nc x 5nc, q and w 5nc,
 * H n x 5nc); mu_r is borrowed as mu is, replaced by frix_persistent_update_mu_r, and the
 * contacts change by frix_persistent_set_contacts_rolling_*, which take the new contacts' mu_r.
 * With spinning friction (6 entries a contact), frix_persistent_update_mu_s and
 * frix_persistent_set_contacts_spinning_* carry mu_s as well. A problem keeps its law: the calls
 * of another law refuse it (FRIX_ERR_INVALID_ARGUMENT).
 *
 * Threads. One persistent solver is used by one thread at a time (solve and update change
 * it); distinct persistent solvers may run in parallel, also on the same borrowed data,
 * which they only read. The options are copied at create; the log sink and the callback
 * given there are called from the solving thread (and from auto's workers, never two at once).
 */
#ifndef FRIX_PERSISTENT_H
#define FRIX_PERSISTENT_H

#include <stdint.h>
#include "frix_export.h"
#include "frix_errors.h"
#include "frix_matrix.h"
#include "frix_problem.h"
#include "frix_options.h"
#include "frix_info.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct frix_persistent frix_persistent;

/* A persistent solver for `problem` (local or global, rolling or not) with a copy of
 * `options` (NULL: the default solver with its defaults). FRIX_ERR_INVALID_ARGUMENT for a
 * NULL problem or out, FRIX_ERR_UNKNOWN_SOLVER, FRIX_ERR_UNSUPPORTED for a solver that
 * cannot solve the problem's kind; the problem's vectors are checked as by frix_solve. */
FRIX_API frix_error frix_persistent_create(const frix_problem *problem, const frix_options *options,
                                           frix_persistent **out);
/* Frees it (NULL is accepted); never frees the borrowed data. */
FRIX_API void frix_persistent_free(frix_persistent *ps);

/* Solves the current problem: r, u, v and info as for frix_solve (r is the warm start, or the
 * secant start's above; v only for a global problem; info may be NULL). */
FRIX_API frix_error frix_persistent_solve(frix_persistent *ps, double *r, double *u, double *v,
                                          frix_info *info);

/* The next local problem: each non-NULL argument replaces the current one (W: 3nc x 3nc;
 * q: 3nc; mu: nc, each >= 0; checked as by frix_problem_local; 5nc for a rolling problem).
 * FRIX_ERR_INVALID_ARGUMENT on a global problem's solver; on any error nothing is replaced. */
FRIX_API frix_error frix_persistent_update_local(frix_persistent *ps, const frix_matrix *W,
                                                 const double *q, const double *mu);
/* The next global problem: each non-NULL argument replaces the current one (M: n x n;
 * H: n x 3nc; f: n; w: 3nc; mu: nc; checked as by frix_problem_global; 5nc for a rolling
 * problem).
 * FRIX_ERR_INVALID_ARGUMENT on a local problem's solver; on any error nothing is replaced. */
FRIX_API frix_error frix_persistent_update_global(frix_persistent *ps, const frix_matrix *M,
                                                  const frix_matrix *H, const double *f,
                                                  const double *w, const double *mu);

/* The next step's contacts, nc of them (any number, 0 included): W, q and mu together
 * replace the current ones (W: 3nc x 3nc; q: 3nc; mu: nc; checked as by frix_problem_local).
 * What was kept for the old contacts is dropped. r and u of the next solves have 3nc
 * entries. FRIX_ERR_INVALID_ARGUMENT on a global or rolling problem's solver; on any error
 * nothing is replaced. */
FRIX_API frix_error frix_persistent_set_contacts_local(frix_persistent *ps, const frix_matrix *W,
                                                       const double *q, const double *mu,
                                                       int64_t nc);
/* The same for a global problem: H (n x 3nc), w (3nc) and mu (nc) together replace the
 * current ones, checked as by frix_problem_global; M, its factorisation and f stay. */
FRIX_API frix_error frix_persistent_set_contacts_global(frix_persistent *ps, const frix_matrix *H,
                                                        const double *w, const double *mu,
                                                        int64_t nc);

/* The next step's contacts of a rolling problem, nc of them: as frix_persistent_set_contacts_*
 * with 5 entries a contact (W: 5nc x 5nc; q, w: 5nc; H: n x 5nc) and mu_r (nc values, each
 * >= 0), checked as by frix_problem_rolling_local / _global. FRIX_ERR_INVALID_ARGUMENT on a
 * solver of a problem of the other form or of another law (without rolling friction, or with
 * spinning friction); on any error nothing is replaced. */
FRIX_API frix_error frix_persistent_set_contacts_rolling_local(frix_persistent *ps, const frix_matrix *W,
                                                               const double *q, const double *mu,
                                                               const double *mu_r, int64_t nc);
FRIX_API frix_error frix_persistent_set_contacts_rolling_global(frix_persistent *ps, const frix_matrix *H,
                                                                const double *w, const double *mu,
                                                                const double *mu_r, int64_t nc);
/* The rolling coefficients of the current contacts (nc values, each >= 0) replace the current
 * ones; FRIX_ERR_INVALID_ARGUMENT on a solver of a problem without rolling friction. */
FRIX_API frix_error frix_persistent_update_mu_r(frix_persistent *ps, const double *mu_r);

/* The next step's contacts of a problem with rolling and spinning friction: as the rolling calls
 * with 6 entries a contact (W: 6nc x 6nc; q, w: 6nc; H: n x 6nc) and mu_s (nc values, each >= 0),
 * checked as by frix_problem_spinning_local / _global. FRIX_ERR_INVALID_ARGUMENT on a solver of
 * a problem of the other form or of another law; on any error nothing is replaced. */
FRIX_API frix_error frix_persistent_set_contacts_spinning_local(frix_persistent *ps, const frix_matrix *W,
                                                                const double *q, const double *mu,
                                                                const double *mu_r, const double *mu_s,
                                                                int64_t nc);
FRIX_API frix_error frix_persistent_set_contacts_spinning_global(frix_persistent *ps, const frix_matrix *H,
                                                                 const double *w, const double *mu,
                                                                 const double *mu_r, const double *mu_s,
                                                                 int64_t nc);
/* The spinning coefficients of the current contacts (nc values, each >= 0) replace the current
 * ones; FRIX_ERR_INVALID_ARGUMENT on a solver of a problem without spinning friction. */
FRIX_API frix_error frix_persistent_update_mu_s(frix_persistent *ps, const double *mu_s);

#ifdef __cplusplus
}
#endif

#endif /* FRIX_PERSISTENT_H */
