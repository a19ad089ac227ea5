// frix_persistent: the solve driver with a SolveCache kept between calls. The persistent
// solver tells the cache which matrices changed (by version numbers, bumped by each update
// that replaces one) and whether a sparsity pattern did (against a copy of the pattern it
// keeps, since the old matrix may already be freed when the new one arrives).
#include <frix/frix_persistent.h>
#include <frix/frix_solve.h>

#include <memory>
#include <new>

#include "error_state.hpp"
#include "info.hpp"
#include "log.hpp"
#include "matrix.hpp"
#include "options.hpp"
#include "problem.hpp"
#include "secant_start.hpp"
#include "solver_api.hpp"

struct frix_persistent {
    std::unique_ptr<frix_options> options;
    frix_problem problem;    // views of the borrowed data, as last updated
    frix_matrix W_pattern;   // local problems: W's pattern, to tell a new one from new values
    frix::SolveCache cache;
    frix::SecantStart secant;  // option secant_start: the last two solves' data and answers
};

namespace {

using frix::fail;

void copy_views(const frix_problem &from, frix_problem &to) {
    to.kind = from.kind;
    to.nc = from.nc;
    to.n = from.n;
    to.W = from.W;
    to.q = from.q;
    to.M = from.M;
    to.H = from.H;
    to.f = from.f;
    to.w = from.w;
    to.mu = from.mu;
    to.mu_r = from.mu_r;
    to.spinning = from.spinning;
    to.mu_s = from.mu_s;
    to.weight = from.weight;
    to.dof_weight = from.dof_weight;
    to.load_weight = from.load_weight;
}

frix_error create(const frix_problem *problem, const frix_options *options, frix_persistent **out) {
    if (!out) return fail(FRIX_ERR_INVALID_ARGUMENT, "frix_persistent_create: out is NULL");
    *out = nullptr;
    if (!problem) return fail(FRIX_ERR_INVALID_ARGUMENT, "frix_persistent_create: problem is NULL");
    auto ps = std::make_unique<frix_persistent>();
    frix_options *copy = nullptr;
    const frix_error e = options ? frix_options_copy(options, &copy) : frix_options_create(frix::kDefaultSolver, &copy);
    if (e) return e;
    ps->options.reset(copy);
    const frix::SolverEntry *entry = frix::find_solver(copy->solver_id);
    if (!entry)
        return fail(FRIX_ERR_UNKNOWN_SOLVER, "frix_persistent_create: no solver has id %d", copy->solver_id);
    if (frix_error err = frix::check_solver_takes("frix_persistent_create", *entry, *problem)) return err;
    if (frix_error err = frix::check_problem_vectors(*problem)) return err;
    copy_views(*problem, ps->problem);
    if (problem->W) ps->W_pattern = frix::pattern_of(*problem->W);
    *out = ps.release();
    return FRIX_OK;
}

}  // namespace

extern "C" {

FRIX_API frix_error frix_persistent_create(const frix_problem *problem, const frix_options *options,
                                           frix_persistent **out) {
    return frix::guard("frix_persistent_create", [&] { return create(problem, options, out); });
}

FRIX_API void frix_persistent_free(frix_persistent *ps) { delete ps; }

FRIX_API frix_error frix_persistent_solve(frix_persistent *ps, double *r, double *u, double *v, frix_info *info) {
    return frix::guard("frix_persistent_solve", [&]() -> frix_error {
        if (!ps) return fail(FRIX_ERR_INVALID_ARGUMENT, "frix_persistent_solve: the persistent solver is NULL");
        const bool secant = ps->options->i(FRIX_OPT_SECANT_START) != 0 && r;
        frix_info local_info;
        frix_info &out = info ? *info : local_info;
        bool predicted = false;
        if (secant) {
            try {
                predicted = ps->secant.predict(ps->problem, ps->cache, r);
            } catch (const std::bad_alloc &) {  // no room for the prediction: r as given
            }
        }
        if (predicted && ps->options->i(FRIX_OPT_VERBOSITY) >= 1)
            frix::log_line(ps->options.get(), "persistent solve: from the secant of the last two answers");
        const frix_error e =
            frix::solve_problem("frix_persistent_solve", &ps->problem, ps->options.get(), r, u, v, &out, &ps->cache);
        // A refused call hands the caller's r back (the last answer, which the prediction
        // replaced) and leaves the history as it was.
        if (e != FRIX_OK && predicted) ps->secant.restore_last_answer(r);
        if (secant && e == FRIX_OK) {
            try {
                ps->secant.record(ps->problem, ps->cache, r, out.status == FRIX_STATUS_CONVERGED);
            } catch (const std::bad_alloc &) {  // the history is forgotten; the solve stands
            }
        }
        return e;
    });
}

FRIX_API frix_error frix_persistent_update_local(frix_persistent *ps, const frix_matrix *W, const double *q,
                                                 const double *mu) {
    return frix::guard("frix_persistent_update_local", [&]() -> frix_error {
        if (!ps) return fail(FRIX_ERR_INVALID_ARGUMENT, "frix_persistent_update_local: the persistent solver is NULL");
        if (!frix::is_local_form(ps->problem))
            return fail(FRIX_ERR_INVALID_ARGUMENT,
                        "frix_persistent_update_local: the problem is global (use frix_persistent_update_global)");
        frix_problem next;
        copy_views(ps->problem, next);
        if (W) next.W = W;
        if (q) next.q = q;
        if (mu) next.mu = mu;
        if (frix_error e = frix::check_problem_of(next)) return e;
        if (W) {
            ps->problem.W = W;
            ++ps->cache.w_values;
            if (!frix::same_pattern(*W, ps->W_pattern)) {
                ps->W_pattern = frix::pattern_of(*W);
                ++ps->cache.w_pattern;
            }
        }
        ps->problem.q = next.q;
        ps->problem.mu = next.mu;
        if (W) frix::set_contact_weights(ps->problem);
        return FRIX_OK;
    });
}

FRIX_API frix_error frix_persistent_update_global(frix_persistent *ps, const frix_matrix *M, const frix_matrix *H,
                                                  const double *f, const double *w, const double *mu) {
    return frix::guard("frix_persistent_update_global", [&]() -> frix_error {
        if (!ps) return fail(FRIX_ERR_INVALID_ARGUMENT, "frix_persistent_update_global: the persistent solver is NULL");
        if (frix::is_local_form(ps->problem))
            return fail(FRIX_ERR_INVALID_ARGUMENT,
                        "frix_persistent_update_global: the problem is local (use frix_persistent_update_local)");
        frix_problem next;
        copy_views(ps->problem, next);
        if (M) next.M = M;
        if (H) next.H = H;
        if (f) next.f = f;
        if (w) next.w = w;
        if (mu) next.mu = mu;
        if (frix_error e = frix::check_problem_of(next)) return e;
        if (M && M->rows != ps->problem.n)
            return fail(FRIX_ERR_DIMENSION, "frix_persistent_update_global: M is %lld x %lld, the problem has %lld dofs",
                        (long long)M->rows, (long long)M->cols, (long long)ps->problem.n);
        // The driver's states follow M's and H's versions; a change of their patterns shows
        // in the W it forms from them, and M's factorisation analyses its own.
        if (M) {
            ps->problem.M = M;
            ++ps->cache.m_values;
        }
        if (H) {
            ps->problem.H = H;
            ++ps->cache.h_values;
        }
        ps->problem.f = next.f;
        ps->problem.w = next.w;
        ps->problem.mu = next.mu;
        if (M || H) frix::set_contact_weights(ps->problem);
        return FRIX_OK;
    });
}

}  // extern "C"

namespace {

using frix::ContactLaw;

// The call that sets a problem's contacts in its form and law (law.dim).
const char *set_contacts_call(bool local, const ContactLaw &law) {
    if (law.dim == 6)
        return local ? "frix_persistent_set_contacts_spinning_local" : "frix_persistent_set_contacts_spinning_global";
    if (law.dim == 5)
        return local ? "frix_persistent_set_contacts_rolling_local" : "frix_persistent_set_contacts_rolling_global";
    return local ? "frix_persistent_set_contacts_local" : "frix_persistent_set_contacts_global";
}

const char *law_name(const ContactLaw &law) {
    if (law.dim == 6) return "rolling and spinning friction";
    return law.dim == 5 ? "rolling friction" : "Coulomb friction alone";
}

// The call's form and law against the solver's problem: a problem keeps both for its whole life.
frix_error check_call(const char *where, const frix_persistent *ps, bool local, const ContactLaw &law) {
    if (!ps) return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: the persistent solver is NULL", where);
    const bool is_local = frix::is_local_form(ps->problem);
    const ContactLaw has = frix::law_of(ps->problem);
    if (is_local == local && has.dim == law.dim) return FRIX_OK;
    return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: the problem is %s with %s (use %s)", where,
                is_local ? "local" : "global", law_name(has), set_contacts_call(is_local, has));
}

// The next step's contacts of a local problem, with the call's law.
frix_error set_contacts_local(const char *where, frix_persistent *ps, const frix_matrix *W, const double *q,
                              const double *mu, const ContactLaw &law, int64_t nc) {
    if (frix_error e = check_call(where, ps, true, law)) return e;
    frix_problem *check = nullptr;
    if (frix_error e = frix::make_local_problem_of(law, W, q, mu, nc, &check)) return e;
    copy_views(*check, ps->problem);
    frix_problem_free(check);
    // Every kept state was built for the old contacts: the versions say they are stale.
    ps->W_pattern = W ? frix::pattern_of(*W) : frix_matrix{};
    ++ps->cache.w_values;
    ++ps->cache.w_pattern;
    return FRIX_OK;
}

// The same for a global problem: M, its factorisation and f stay.
frix_error set_contacts_global(const char *where, frix_persistent *ps, const frix_matrix *H, const double *w,
                               const double *mu, const ContactLaw &law, int64_t nc) {
    if (frix_error e = check_call(where, ps, false, law)) return e;
    const frix_problem &p = ps->problem;
    frix_problem *check = nullptr;
    if (frix_error e = frix::make_global_problem_of(law, p.M, H, p.f, w, mu, nc, &check)) return e;
    copy_views(*check, ps->problem);
    frix_problem_free(check);
    // M's factorisation follows M's version, which stays; what was formed from H does not.
    ++ps->cache.h_values;
    return FRIX_OK;
}

// Replaces the coefficients `field` (nc values, named `name`) of a problem whose law has them
// (at least `needs` entries a contact: 5 for mu_r, 6 for mu_s).
frix_error update_coefficients(const char *where, frix_persistent *ps, const double *x, const char *name,
                               const double *frix_problem::*field, int needs) {
    if (!ps) return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: the persistent solver is NULL", where);
    if (frix::law_of(ps->problem).dim < needs)
        return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: the problem has no %s", where,
                    needs == 6 ? "spinning friction" : "rolling friction");
    if (frix_error e = frix::check_mu(where, x, ps->problem.nc, name)) return e;
    ps->problem.*field = x;
    return FRIX_OK;
}

}  // namespace

extern "C" {

FRIX_API frix_error frix_persistent_set_contacts_local(frix_persistent *ps, const frix_matrix *W, const double *q,
                                                       const double *mu, int64_t nc) {
    const char *where = "frix_persistent_set_contacts_local";
    return frix::guard(where, [&] { return set_contacts_local(where, ps, W, q, mu, {}, nc); });
}

FRIX_API frix_error frix_persistent_set_contacts_global(frix_persistent *ps, const frix_matrix *H, const double *w,
                                                        const double *mu, int64_t nc) {
    const char *where = "frix_persistent_set_contacts_global";
    return frix::guard(where, [&] { return set_contacts_global(where, ps, H, w, mu, {}, nc); });
}

FRIX_API frix_error frix_persistent_set_contacts_rolling_local(frix_persistent *ps, const frix_matrix *W,
                                                               const double *q, const double *mu, const double *mu_r,
                                                               int64_t nc) {
    const char *where = "frix_persistent_set_contacts_rolling_local";
    return frix::guard(where, [&] { return set_contacts_local(where, ps, W, q, mu, {mu_r, nullptr, 5}, nc); });
}

FRIX_API frix_error frix_persistent_set_contacts_rolling_global(frix_persistent *ps, const frix_matrix *H,
                                                                const double *w, const double *mu,
                                                                const double *mu_r, int64_t nc) {
    const char *where = "frix_persistent_set_contacts_rolling_global";
    return frix::guard(where, [&] { return set_contacts_global(where, ps, H, w, mu, {mu_r, nullptr, 5}, nc); });
}

FRIX_API frix_error frix_persistent_set_contacts_spinning_local(frix_persistent *ps, const frix_matrix *W,
                                                                const double *q, const double *mu,
                                                                const double *mu_r, const double *mu_s, int64_t nc) {
    const char *where = "frix_persistent_set_contacts_spinning_local";
    return frix::guard(where, [&] { return set_contacts_local(where, ps, W, q, mu, {mu_r, mu_s, 6}, nc); });
}

FRIX_API frix_error frix_persistent_set_contacts_spinning_global(frix_persistent *ps, const frix_matrix *H,
                                                                 const double *w, const double *mu,
                                                                 const double *mu_r, const double *mu_s,
                                                                 int64_t nc) {
    const char *where = "frix_persistent_set_contacts_spinning_global";
    return frix::guard(where,
                       [&] { return set_contacts_global(where, ps, H, w, mu, {mu_r, mu_s, 6}, nc); });
}

FRIX_API frix_error frix_persistent_update_mu_r(frix_persistent *ps, const double *mu_r) {
    const char *where = "frix_persistent_update_mu_r";
    return frix::guard(where,
                       [&] { return update_coefficients(where, ps, mu_r, "mu_r", &frix_problem::mu_r, 5); });
}

FRIX_API frix_error frix_persistent_update_mu_s(frix_persistent *ps, const double *mu_s) {
    const char *where = "frix_persistent_update_mu_s";
    return frix::guard(where, [&] {
        return update_coefficients(where, ps, mu_s, "mu_s", &frix_problem::mu_s, 6);
    });
}

}  // extern "C"
