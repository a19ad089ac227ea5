// Internal layout of frix_problem. Members point either at the caller's data (borrowed) or
// at the owned_* storage (problems read from files).
#pragma once

#include <frix/frix_problem.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "handle_header.hpp"
#include "matrix.hpp"

struct frix_problem {
    frix::HandleHeader header = frix::header_of<frix_problem>();  // first, in every release
    frix_problem_kind kind = FRIX_PROBLEM_LOCAL;
    int64_t nc = 0;  // contacts; r and u have contact_size(*this) * nc entries
    int64_t n = 0;   // global: dofs (size of v); local: 0

    const frix_matrix *W = nullptr;  // local
    const double *q = nullptr;       // local
    const frix_matrix *M = nullptr;  // global
    const frix_matrix *H = nullptr;  // global
    const double *f = nullptr;       // global
    const double *w = nullptr;       // global
    const double *mu = nullptr;
    const double *mu_r = nullptr;  // rolling kinds only
    // Rolling kinds with spinning friction: a sixth entry a contact (the moment and relative
    // angular velocity about the normal) and its coefficients mu_s (nc values; may be null
    // when nc is 0).
    bool spinning = false;
    const double *mu_s = nullptr;

    // Free text (FCLIB's info group: title, description, math_info), each at most
    // frix::kMaxProblemText bytes.
    std::string title, description, math_info;

    // Per contact, the velocity a unit normal reaction produces at it (velocity / force): the
    // default error measure's unit of r (measures.hpp). Set when the problem is made or
    // updated (set_contact_weights); a view made by hand fills it or leaves it empty (1).
    std::vector<double> weight;
    // Global problems, per dof: 1 / sqrt(M_ii), the default measure's weight of a force
    // (measures.hpp): a rotation's torque and a translation's force in one unit. Set with
    // weight; empty: 1.
    std::vector<double> dof_weight;
    // dof_weight on the dofs no contact reaches (rows of H without an entry) of the bodies
    // some contact touches (components of M's graph that H reaches), 0 elsewhere:
    // load_velocity's weights. Set with weight.
    std::vector<double> load_weight;

    // Owned storage, used only by problems that own their data (see make_owned_* below).
    std::unique_ptr<frix_matrix> owned_W, owned_M, owned_H;
    std::vector<double> owned_q, owned_f, owned_w, owned_mu, owned_mu_r, owned_mu_s;
};

namespace frix {

// Rolling friction: five components a contact (frix_problem.h), six with spinning friction,
// in the local or global form.
inline bool is_rolling(const frix_problem &p) {
    return p.kind == FRIX_PROBLEM_ROLLING_LOCAL || p.kind == FRIX_PROBLEM_ROLLING_GLOBAL;
}
// Whether the problem is given by W and q (a local kind) rather than M, H, f and w.
inline bool is_local_form(const frix_problem &p) {
    return p.kind == FRIX_PROBLEM_LOCAL || p.kind == FRIX_PROBLEM_ROLLING_LOCAL;
}
// Entries of r and u a contact: 3, or 5 for a rolling problem, 6 with spinning friction.
inline int contact_size(const frix_problem &p) { return is_rolling(p) ? (p.spinning ? 6 : 5) : 3; }
// A local problem (either kind of contact) whose every contact separates at r = 0 (q_N >= 0):
// r = 0 solves it, u = q having u_N >= 0 so that u^ lies in K*. False for a global problem.
inline bool separates_at_zero(const frix_problem &p) {
    if (!is_local_form(p)) return false;
    const int dim = contact_size(p);
    for (int64_t a = 0; a < p.nc; ++a)
        if (p.q[dim * a] < 0.0) return false;
    return true;
}
// FRIX_ERR_UNSUPPORTED naming `where` for a rolling problem (a part of frix that solves or
// handles only the three-component law), FRIX_OK otherwise.
frix_error refuse_rolling(const frix_problem &p, const char *where);

// Validates and builds a problem from (borrowed) data; the checks of the public
// frix_problem_local / frix_problem_global (sizes, NaN/Inf, mu >= 0, W square 3nc x 3nc).
frix_error make_local_problem(const frix_matrix *W, const double *q, const double *mu,
                              int64_t nc, frix_problem **out);
frix_error make_global_problem(const frix_matrix *M, const frix_matrix *H, const double *f,
                               const double *w, const double *mu, int64_t nc,
                               frix_problem **out);

// Builds a problem that owns its data (used by readers): takes the matrices and vectors,
// validates exactly like the borrowing constructors, and points the views at the owned copies.
frix_error make_owned_local_problem(std::unique_ptr<frix_matrix> W, std::vector<double> q,
                                    std::vector<double> mu, frix_problem **out);
frix_error make_owned_global_problem(std::unique_ptr<frix_matrix> M,
                                     std::unique_ptr<frix_matrix> H, std::vector<double> f,
                                     std::vector<double> w, std::vector<double> mu,
                                     frix_problem **out);

// The longest title, description or math info a problem takes, in bytes: files carry them,
// so readers refuse longer ones before reading them, and setters refuse what readers would.
constexpr size_t kMaxProblemText = 65536;

// The rolling kinds (mu_r: nc values >= 0); the same checks with 5 components a contact.
frix_error make_rolling_local_problem(const frix_matrix *W, const double *q, const double *mu, const double *mu_r,
                                      int64_t nc, frix_problem **out);
frix_error make_rolling_global_problem(const frix_matrix *M, const frix_matrix *H, const double *f, const double *w,
                                       const double *mu, const double *mu_r, int64_t nc, frix_problem **out);
// The owning forms of those (readers).
frix_error make_owned_rolling_local_problem(std::unique_ptr<frix_matrix> W, std::vector<double> q,
                                            std::vector<double> mu, std::vector<double> mu_r, frix_problem **out);
frix_error make_owned_rolling_global_problem(std::unique_ptr<frix_matrix> M, std::unique_ptr<frix_matrix> H,
                                             std::vector<double> f, std::vector<double> w, std::vector<double> mu,
                                             std::vector<double> mu_r, frix_problem **out);

// The rolling kinds with spinning friction (mu_s: nc values >= 0): 6 components a contact.
frix_error make_spinning_local_problem(const frix_matrix *W, const double *q, const double *mu, const double *mu_r,
                                       const double *mu_s, int64_t nc, frix_problem **out);
frix_error make_spinning_global_problem(const frix_matrix *M, const frix_matrix *H, const double *f, const double *w,
                                        const double *mu, const double *mu_r, const double *mu_s, int64_t nc,
                                        frix_problem **out);
frix_error make_owned_spinning_local_problem(std::unique_ptr<frix_matrix> W, std::vector<double> q,
                                             std::vector<double> mu, std::vector<double> mu_r,
                                             std::vector<double> mu_s, frix_problem **out);
frix_error make_owned_spinning_global_problem(std::unique_ptr<frix_matrix> M, std::unique_ptr<frix_matrix> H,
                                              std::vector<double> f, std::vector<double> w, std::vector<double> mu,
                                              std::vector<double> mu_r, std::vector<double> mu_s,
                                              frix_problem **out);

// A contact law's coefficients beyond mu, as the constructors take them: none (Coulomb, 3
// entries a contact), mu_r (rolling friction, 5) or mu_r and mu_s (with spinning friction, 6).
struct ContactLaw {
    const double *mu_r = nullptr, *mu_s = nullptr;
    int dim = 3;
};
// The same, owned (readers).
struct OwnedContactLaw {
    std::vector<double> mu_r, mu_s;
    int dim = 3;
};
// p's law (views of its coefficients).
inline ContactLaw law_of(const frix_problem &p) { return {p.mu_r, p.mu_s, contact_size(p)}; }
// The constructors above for a law given as data: the kind (and the name in messages) follows
// law.dim.
frix_error make_local_problem_of(const ContactLaw &law, const frix_matrix *W, const double *q, const double *mu,
                                 int64_t nc, frix_problem **out);
frix_error make_global_problem_of(const ContactLaw &law, const frix_matrix *M, const frix_matrix *H, const double *f,
                                  const double *w, const double *mu, int64_t nc, frix_problem **out);
frix_error make_owned_local_problem_of(OwnedContactLaw law, std::unique_ptr<frix_matrix> W, std::vector<double> q,
                                       std::vector<double> mu, frix_problem **out);
// The checks make_local_problem_of or make_global_problem_of would make of p's views (the same
// messages), without building a problem: its weights cost passes over M, H or W.
frix_error check_problem_of(const frix_problem &p);
frix_error make_owned_global_problem_of(OwnedContactLaw law, std::unique_ptr<frix_matrix> M,
                                        std::unique_ptr<frix_matrix> H, std::vector<double> f,
                                        std::vector<double> w, std::vector<double> mu, frix_problem **out);

// x (n values, named `name` in the message) given and finite; mu (nc values) finite and >= 0.
frix_error check_vector(const char *where, const char *name, const double *x, int64_t n);
frix_error check_mu(const char *where, const double *mu, int64_t nc, const char *name = "mu");

// 1 / M_ii where M's diagonal is positive with a finite inverse, `otherwise` elsewhere: the
// diagonal that stands for M^-1 where M^-1 is not formed (a global problem).
std::vector<double> inverse_mass_diagonal(const frix_problem &p, double otherwise);

// The diagonal of W (local), or of H^T diag(inverse_mass) H (global, inverse_mass as from
// inverse_mass_diagonal): contact_size(p) nc values.
std::vector<double> delassus_diagonal(const frix_problem &p, const std::vector<double> &inverse_mass);

// The contact weights before their fill (set_contact_weights): delassus_diagonal's normal
// entries, inverse_mass as from inverse_mass_diagonal(p, 0) (empty for a local problem).
std::vector<double> unfilled_contact_weights(const frix_problem &p, const std::vector<double> &inverse_mass);

// p.weight from the problem's matrices: delassus_diagonal's normal entries (M's diagonal for
// M^-1 in a global problem: cheap, and exact for a diagonal M). A value that is not positive
// and finite (a contact W or H does not reach) takes the mean of the others, or 1. Also
// p.dof_weight (a global problem), 1 / sqrt(M_ii), where M_ii is not positive the mean of the
// others, or 1.
void set_contact_weights(frix_problem &p);

// A global problem's velocity at the contacts without contact forces, the default measure's
// floor (a local problem's is |q|): max(|w|, |H^T D^-1 f + w|, load_velocity(p)), D = M's
// diagonal. Computed when asked: f and w may change in place between solves.
double free_velocity(const frix_problem &p);
// The velocity that the load H^T D^-1 f does not see gives a contact, to its order of
// magnitude: sqrt(mean_a w_a) rms(D^-1/2 f) sqrt(nc), the root mean square over the k dofs no
// contact reaches of the bodies in contact (w_a = p.weight, D^-1/2 on them: p.load_weight):
// every contact moving at the load's typical velocity. Where the load acts away from the
// contacts (a FEM body pressed from the other side) H^T D^-1 f is 0 at them, and without this
// floor a solution's u = 0 would leave the measure 0 / 0; a rigid body's dofs are all
// reached, and it adds nothing.
double load_velocity(const frix_problem &p);

// The rules of those weights and floors, one value at a time or from their parts, so that a
// problem held by several ranks (mpi/) computes what set_contact_weights and free_velocity
// compute on the whole problem.
// 1 / m_ii where m_ii is positive with a finite inverse, `otherwise` elsewhere.
double inverse_mass(double m_ii, double otherwise);
// The sum and number of the positive finite values of some weights (ranks add theirs up):
// the value that those not positive and finite take, their mean, or 1 if there are none.
struct PositiveMean {
    double sum = 0.0, count = 0.0;
    void add(const std::vector<double> &x);
    double fill() const;
};
// x's values that are not positive and finite set to `fill`.
void fill_not_positive(std::vector<double> &x, double fill);
// load_velocity from its parts: the mean contact weight over nc contacts, and the load's
// norm |D^-1/2 f| and number of values over the load dofs.
double load_velocity_of(double mean_weight, int64_t nc, double load_norm, int64_t load_dofs);
// free_velocity from |w|, |H^T D^-1 f + w| (not finite: ignored) and load_velocity.
double free_velocity_of(double norm_w, double norm_jacobi, double load_velocity);

// Re-checks the vectors a caller may have changed in place since creation (q/f/w, mu).
frix_error check_problem_vectors(const frix_problem &p);

}  // namespace frix
