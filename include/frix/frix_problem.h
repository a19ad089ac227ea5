/* frix — frictional contact problems.
 *
 * Local (reduced) problem:  u = W r + q, per contact a the 3-vectors r_a, u_a (normal
 * first), u^_a = u_a + mu_a |u_T,a| e_N,  K*_mu ∋ u^_a ⟂ r_a ∈ K_mu = {|r_T| <= mu r_N}.
 * Global problem:           M v = H r + f,  u = H^T v + w,  same cone law.
 *
 * A problem built from caller data BORROWS it: the matrices and the q/f/w/mu arrays must
 * outlive the problem and are read, never written (a time-stepping code may update q in
 * place between solves; it is re-checked at every solve). frix_problem_free never frees
 * them. Problems read from files own their data.
 * Zero contacts is a valid problem: the solution is empty (and v = M^-1 f for a global one).
 *
 * Rolling friction (rolling resistance), Siconos's RollingFrictionContactProblem: per contact
 * five components, r_a = (r_N, r_T1, r_T2, m_R1, m_R2) (normal reaction, friction force, rolling
 * moment) and u_a = (u_N, u_T1, u_T2, w_R1, w_R2) (normal and sliding velocity, relative rolling
 * velocity); the cone K_a = {|r_T| <= mu_a r_N, |m_R| <= mu_r,a r_N} (mu_r a length) and
 * u^_a = u_a + (mu_a |u_T| + mu_r,a |w_R|) e_N, K*_a ∋ u^_a ⟂ r_a ∈ K_a. Local form: W is
 * 5nc x 5nc (5x5 blocks), q 5nc; global form: H is n x 5nc, w 5nc. Such problems are kinds of
 * their own: the rolling solvers (FRIX_SOLVER_ROLLING_NSGS and _NSN, and auto, which picks between
 * them) solve them;
 * every other solver refuses them (FRIX_ERR_UNSUPPORTED).
 *
 * Rolling and spinning friction (frix_problem_spinning_*): a rolling problem whose contacts have
 * a sixth component, the moment m_S about the normal and the relative angular velocity w_S about
 * it (Chrono's spinning friction; Siconos has no such problem), with |m_S| <= mu_s,a r_N in K_a
 * and mu_s,a |w_S| added to u^_a's normal entry. Its kind is the rolling one of its form;
 * frix_problem_mu_s is not NULL and frix_problem_contact_dofs is 6 nc.
 */
#ifndef FRIX_PROBLEM_H
#define FRIX_PROBLEM_H

#include <stdint.h>
#include "frix_export.h"
#include "frix_errors.h"
#include "frix_matrix.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct frix_problem frix_problem;

typedef enum frix_problem_kind FRIX_ENUM_BASE {
    FRIX_PROBLEM_LOCAL = 1,
    FRIX_PROBLEM_GLOBAL = 2,
    FRIX_PROBLEM_ROLLING_LOCAL = 3,  /* rolling friction, local form (5 components a contact, 6 with spin) */
    FRIX_PROBLEM_ROLLING_GLOBAL = 4  /* rolling friction, global form */
} frix_problem_kind;

/* W: 3nc x 3nc; q: 3nc; mu: nc, each mu >= 0. W may be NULL only when nc == 0. */
FRIX_API frix_error frix_problem_local(const frix_matrix *W, const double *q, const double *mu,
                                       int64_t nc, frix_problem **out);
/* M: n x n; H: n x 3nc; f: n; w: 3nc; mu: nc. */
FRIX_API frix_error frix_problem_global(const frix_matrix *M, const frix_matrix *H,
                                        const double *f, const double *w, const double *mu,
                                        int64_t nc, frix_problem **out);
/* Rolling friction, local form: W 5nc x 5nc; q 5nc; mu and mu_r nc, each >= 0. */
FRIX_API frix_error frix_problem_rolling_local(const frix_matrix *W, const double *q, const double *mu,
                                               const double *mu_r, int64_t nc, frix_problem **out);
/* Rolling friction, global form: M n x n; H n x 5nc; f n; w 5nc; mu and mu_r nc. */
FRIX_API frix_error frix_problem_rolling_global(const frix_matrix *M, const frix_matrix *H,
                                                const double *f, const double *w, const double *mu,
                                                const double *mu_r, int64_t nc, frix_problem **out);
/* Rolling and spinning friction, local form: W 6nc x 6nc; q 6nc; mu, mu_r and mu_s nc, each >= 0. */
FRIX_API frix_error frix_problem_spinning_local(const frix_matrix *W, const double *q, const double *mu,
                                                const double *mu_r, const double *mu_s, int64_t nc,
                                                frix_problem **out);
/* Rolling and spinning friction, global form: M n x n; H n x 6nc; f n; w 6nc; mu, mu_r, mu_s nc. */
FRIX_API frix_error frix_problem_spinning_global(const frix_matrix *M, const frix_matrix *H,
                                                 const double *f, const double *w, const double *mu,
                                                 const double *mu_r, const double *mu_s, int64_t nc,
                                                 frix_problem **out);
FRIX_API void frix_problem_free(frix_problem *p);

FRIX_API frix_problem_kind frix_problem_get_kind(const frix_problem *p);
FRIX_API int64_t frix_problem_contacts(const frix_problem *p);
/* Size of r and u: 3 * contacts (5 * contacts for a rolling problem, 6 * contacts with spinning
 * friction). */
FRIX_API int64_t frix_problem_contact_dofs(const frix_problem *p);
/* Size of v: n for a global problem, 0 for a local one. */
FRIX_API int64_t frix_problem_dofs(const frix_problem *p);

/* Views of the data (NULL where the kind has no such member). */
FRIX_API const frix_matrix *frix_problem_W(const frix_problem *p);
FRIX_API const frix_matrix *frix_problem_M(const frix_problem *p);
FRIX_API const frix_matrix *frix_problem_H(const frix_problem *p);
FRIX_API const double *frix_problem_q(const frix_problem *p);
FRIX_API const double *frix_problem_f(const frix_problem *p);
FRIX_API const double *frix_problem_w(const frix_problem *p);
FRIX_API const double *frix_problem_mu(const frix_problem *p);
/* The rolling coefficients (nc values) of a rolling problem; NULL for any other. */
FRIX_API const double *frix_problem_mu_r(const frix_problem *p);
/* The spinning coefficients (nc values) of a problem with spinning friction; NULL for any other
 * (and for one of zero contacts made with mu_s NULL). */
FRIX_API const double *frix_problem_mu_s(const frix_problem *p);

/* Free text about the problem, as FCLIB's info group holds it: a title, a description and
 * its mathematical information (each empty by default; NULL sets it empty). The string is
 * copied; FRIX_ERR_INVALID_ARGUMENT for a text over 65536 bytes (the FCLIB reader refuses
 * longer ones). The getters return the problem's copy ("" for a NULL problem), valid until
 * the next set or the problem's free. */
FRIX_API frix_error frix_problem_set_title(frix_problem *p, const char *title);
FRIX_API const char *frix_problem_title(const frix_problem *p);
FRIX_API frix_error frix_problem_set_description(frix_problem *p, const char *description);
FRIX_API const char *frix_problem_description(const frix_problem *p);
FRIX_API frix_error frix_problem_set_math_info(frix_problem *p, const char *math_info);
FRIX_API const char *frix_problem_math_info(const frix_problem *p);

#ifdef __cplusplus
}
#endif

#endif /* FRIX_PROBLEM_H */
