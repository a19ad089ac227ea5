// Problems: validation at the boundary, borrowed and owned data, accessors.
#include "problem.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>

#include "disjoint_sets.hpp"
#include "error_state.hpp"
#include "measures.hpp"
#include "memory.hpp"

namespace frix {

frix_error check_vector(const char *where, const char *name, const double *x, int64_t n) {
    if (n > 0 && !x) return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: %s is NULL", where, name);
    for (int64_t i = 0; i < n; ++i)
        if (!std::isfinite(x[i]))
            return fail(FRIX_ERR_NOT_FINITE, "%s: %s[%lld] is not finite", where, name, (long long)i);
    return FRIX_OK;
}

frix_error check_mu(const char *where, const double *mu, int64_t nc, const char *name) {
    if (frix_error e = check_vector(where, name, mu, nc)) return e;
    for (int64_t a = 0; a < nc; ++a)
        if (mu[a] < 0.0)
            return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: %s[%lld] = %g is negative", where, name,
                        (long long)a, mu[a]);
    return FRIX_OK;
}

frix_error refuse_rolling(const frix_problem &p, const char *where) {
    if (!is_rolling(p)) return FRIX_OK;
    return fail(FRIX_ERR_UNSUPPORTED, "%s: rolling-friction problems%s are not supported here (see frix_problem.h)",
                where, p.spinning ? " (this one with spinning friction)" : "");
}

}  // namespace frix

namespace {

using frix::check_mu;
using frix::check_vector;
using frix::fail;

frix_error check_nc(const char *where, int64_t nc) {
    if (nc < 0 || nc > (int64_t(1) << 40))
        return fail(FRIX_ERR_DIMENSION, "%s: invalid number of contacts %lld", where, (long long)nc);
    return FRIX_OK;
}

using Law = frix::ContactLaw;
using OwnedLaw = frix::OwnedContactLaw;

// The kind and the public constructor's name (in messages) of a law's problems in one form.
frix_problem_kind kind_of(bool local, const Law &law) {
    if (local) return law.dim == 3 ? FRIX_PROBLEM_LOCAL : FRIX_PROBLEM_ROLLING_LOCAL;
    return law.dim == 3 ? FRIX_PROBLEM_GLOBAL : FRIX_PROBLEM_ROLLING_GLOBAL;
}
const char *constructor_of(bool local, const Law &law) {
    if (law.dim == 6) return local ? "frix_problem_spinning_local" : "frix_problem_spinning_global";
    if (law.dim == 5) return local ? "frix_problem_rolling_local" : "frix_problem_rolling_global";
    return local ? "frix_problem_local" : "frix_problem_global";
}

frix_error check_law(const char *where, const Law &law, int64_t nc) {
    if (law.dim >= 5)
        if (frix_error e = check_mu(where, law.mu_r, nc, "mu_r")) return e;
    if (law.dim == 6)
        if (frix_error e = check_mu(where, law.mu_s, nc, "mu_s")) return e;
    return FRIX_OK;
}

frix_error check_local(const char *where, const frix_matrix *W, const double *q, const double *mu, const Law &law,
                       int64_t nc) {
    const int dim = law.dim;
    if (frix_error e = check_nc(where, nc)) return e;
    if (!W) {
        if (nc == 0) return FRIX_OK;
        return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: W is NULL", where);
    }
    if (W->rows != W->cols)
        return fail(FRIX_ERR_DIMENSION, "%s: W is %lld x %lld, not square", where,
                    (long long)W->rows, (long long)W->cols);
    if (W->rows % dim != 0)
        return fail(FRIX_ERR_DIMENSION, "%s: W has %lld rows, not a multiple of %d", where,
                    (long long)W->rows, dim);
    if (W->rows != dim * nc)
        return fail(FRIX_ERR_DIMENSION, "%s: W is %lld x %lld but %lld contacts need %lld x %lld",
                    where, (long long)W->rows, (long long)W->cols, (long long)nc,
                    (long long)(dim * nc), (long long)(dim * nc));
    if (frix_error e = check_vector(where, "q", q, dim * nc)) return e;
    if (frix_error e = check_law(where, law, nc)) return e;
    return check_mu(where, mu, nc);
}

frix_error check_global(const char *where, const frix_matrix *M, const frix_matrix *H,
                        const double *f, const double *w, const double *mu, const Law &law, int64_t nc) {
    const int dim = law.dim;
    if (frix_error e = check_nc(where, nc)) return e;
    if (!M) return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: M is NULL", where);
    if (M->rows != M->cols)
        return fail(FRIX_ERR_DIMENSION, "%s: M is %lld x %lld, not square", where,
                    (long long)M->rows, (long long)M->cols);
    int64_t n = M->rows;
    if (!H && nc > 0) return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: H is NULL", where);
    if (H && (H->rows != n || H->cols != dim * nc))
        return fail(FRIX_ERR_DIMENSION, "%s: H is %lld x %lld but must be %lld x %lld (dofs x %d*contacts)",
                    where, (long long)H->rows, (long long)H->cols, (long long)n, (long long)(dim * nc), dim);
    if (frix_error e = check_vector(where, "f", f, n)) return e;
    if (frix_error e = check_vector(where, "w", w, dim * nc)) return e;
    if (frix_error e = check_law(where, law, nc)) return e;
    return check_mu(where, mu, nc);
}

void set_law(frix_problem &p, const Law &law) {
    p.mu_r = law.dim >= 5 ? law.mu_r : nullptr;
    p.spinning = law.dim == 6;
    p.mu_s = p.spinning ? law.mu_s : nullptr;
}

// The borrowing constructors of every kind: checks, then the views and the weights.
frix_error make_local_kind(frix_problem_kind kind, const char *where, const frix_matrix *W, const double *q,
                           const double *mu, const Law &law, int64_t nc, frix_problem **out) {
    if (!out) return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: out is NULL", where);
    *out = nullptr;
    if (frix_error e = check_local(where, W, q, mu, law, nc)) return e;
    auto p = std::make_unique<frix_problem>();
    p->kind = kind;
    p->nc = nc;
    p->W = W;
    p->q = q;
    p->mu = mu;
    set_law(*p, law);
    frix::set_contact_weights(*p);
    *out = p.release();
    return FRIX_OK;
}

frix_error make_global_kind(frix_problem_kind kind, const char *where, const frix_matrix *M, const frix_matrix *H,
                            const double *f, const double *w, const double *mu, const Law &law, int64_t nc,
                            frix_problem **out) {
    if (!out) return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: out is NULL", where);
    *out = nullptr;
    if (frix_error e = check_global(where, M, H, f, w, mu, law, nc)) return e;
    auto p = std::make_unique<frix_problem>();
    p->kind = kind;
    p->nc = nc;
    p->n = M->rows;
    p->M = M;
    p->H = H;
    p->f = f;
    p->w = w;
    p->mu = mu;
    set_law(*p, law);
    frix::set_contact_weights(*p);
    *out = p.release();
    return FRIX_OK;
}

// Their sizes against the number of contacts; the law that points at them.
frix_error check_owned_law(const char *where, const OwnedLaw &law, int64_t nc) {
    if (law.dim >= 5 && (int64_t)law.mu_r.size() != nc)
        return fail(FRIX_ERR_DIMENSION, "%s: mu_r has %lld entries but mu has %lld", where,
                    (long long)law.mu_r.size(), (long long)nc);
    if (law.dim == 6 && (int64_t)law.mu_s.size() != nc)
        return fail(FRIX_ERR_DIMENSION, "%s: mu_s has %lld entries but mu has %lld", where,
                    (long long)law.mu_s.size(), (long long)nc);
    return FRIX_OK;
}
Law views_of(const OwnedLaw &law) { return {law.mu_r.data(), law.mu_s.data(), law.dim}; }

void own_law(frix_problem &p, OwnedLaw law) {
    const int dim = law.dim;
    p.owned_mu_r = std::move(law.mu_r);
    p.owned_mu_s = std::move(law.mu_s);
    set_law(p, {p.owned_mu_r.data(), p.owned_mu_s.data(), dim});
}

// The owning forms: sizes checked against each other first (the borrowing checks trust them).
frix_error make_owned_local_kind(frix_problem_kind kind, const char *where, std::unique_ptr<frix_matrix> W,
                                 std::vector<double> q, std::vector<double> mu, OwnedLaw law, frix_problem **out) {
    int64_t nc = (int64_t)mu.size();
    if (W && (int64_t)q.size() != W->rows)
        return fail(FRIX_ERR_DIMENSION, "%s: q has %lld entries but W has %lld rows", where,
                    (long long)q.size(), (long long)W->rows);
    if (frix_error e = check_owned_law(where, law, nc)) return e;
    if (frix_error e = make_local_kind(kind, where, W.get(), q.data(), mu.data(), views_of(law), nc, out)) return e;
    frix_problem &p = **out;
    p.owned_W = std::move(W);
    p.owned_q = std::move(q);
    p.owned_mu = std::move(mu);
    // Moving a vector keeps its buffer, but re-point anyway so the invariant is explicit.
    p.W = p.owned_W.get();
    p.q = p.owned_q.data();
    p.mu = p.owned_mu.data();
    own_law(p, std::move(law));
    return FRIX_OK;
}

frix_error make_owned_global_kind(frix_problem_kind kind, const char *where, std::unique_ptr<frix_matrix> M,
                                  std::unique_ptr<frix_matrix> H, std::vector<double> f, std::vector<double> w,
                                  std::vector<double> mu, OwnedLaw law, frix_problem **out) {
    int64_t nc = (int64_t)mu.size();
    const int dim = law.dim;
    if (M && (int64_t)f.size() != M->rows)
        return fail(FRIX_ERR_DIMENSION, "%s: f has %lld entries but M has %lld rows", where,
                    (long long)f.size(), (long long)M->rows);
    if ((int64_t)w.size() != dim * nc)
        return fail(FRIX_ERR_DIMENSION, "%s: w has %lld entries but %lld contacts need %lld", where,
                    (long long)w.size(), (long long)nc, (long long)(dim * nc));
    if (frix_error e = check_owned_law(where, law, nc)) return e;
    if (frix_error e = make_global_kind(kind, where, M.get(), H.get(), f.data(), w.data(), mu.data(), views_of(law),
                                        nc, out))
        return e;
    frix_problem &p = **out;
    p.owned_M = std::move(M);
    p.owned_H = std::move(H);
    p.owned_f = std::move(f);
    p.owned_w = std::move(w);
    p.owned_mu = std::move(mu);
    p.M = p.owned_M.get();
    p.H = p.owned_H.get();
    p.f = p.owned_f.data();
    p.w = p.owned_w.data();
    p.mu = p.owned_mu.data();
    own_law(p, std::move(law));
    return FRIX_OK;
}

}  // namespace

namespace frix {

frix_error make_local_problem_of(const ContactLaw &law, const frix_matrix *W, const double *q, const double *mu,
                                 int64_t nc, frix_problem **out) {
    return make_local_kind(kind_of(true, law), constructor_of(true, law), W, q, mu, law, nc, out);
}

frix_error make_global_problem_of(const ContactLaw &law, const frix_matrix *M, const frix_matrix *H, const double *f,
                                  const double *w, const double *mu, int64_t nc, frix_problem **out) {
    return make_global_kind(kind_of(false, law), constructor_of(false, law), M, H, f, w, mu, law, nc, out);
}

frix_error check_problem_of(const frix_problem &p) {
    const Law law = law_of(p);
    if (is_local_form(p)) return check_local(constructor_of(true, law), p.W, p.q, p.mu, law, p.nc);
    return check_global(constructor_of(false, law), p.M, p.H, p.f, p.w, p.mu, law, p.nc);
}

frix_error make_owned_local_problem_of(OwnedContactLaw law, std::unique_ptr<frix_matrix> W, std::vector<double> q,
                                       std::vector<double> mu, frix_problem **out) {
    const Law views = views_of(law);
    return make_owned_local_kind(kind_of(true, views), constructor_of(true, views), std::move(W), std::move(q),
                                 std::move(mu), std::move(law), out);
}

frix_error make_owned_global_problem_of(OwnedContactLaw law, std::unique_ptr<frix_matrix> M,
                                        std::unique_ptr<frix_matrix> H, std::vector<double> f,
                                        std::vector<double> w, std::vector<double> mu, frix_problem **out) {
    const Law views = views_of(law);
    return make_owned_global_kind(kind_of(false, views), constructor_of(false, views), std::move(M), std::move(H),
                                  std::move(f), std::move(w), std::move(mu), std::move(law), out);
}

frix_error make_local_problem(const frix_matrix *W, const double *q, const double *mu, int64_t nc,
                              frix_problem **out) {
    return make_local_problem_of({}, W, q, mu, nc, out);
}

frix_error make_global_problem(const frix_matrix *M, const frix_matrix *H, const double *f,
                               const double *w, const double *mu, int64_t nc,
                               frix_problem **out) {
    return make_global_problem_of({}, M, H, f, w, mu, nc, out);
}

frix_error make_rolling_local_problem(const frix_matrix *W, const double *q, const double *mu, const double *mu_r,
                                      int64_t nc, frix_problem **out) {
    return make_local_problem_of({mu_r, nullptr, 5}, W, q, mu, nc, out);
}

frix_error make_spinning_local_problem(const frix_matrix *W, const double *q, const double *mu, const double *mu_r,
                                       const double *mu_s, int64_t nc, frix_problem **out) {
    return make_local_problem_of({mu_r, mu_s, 6}, W, q, mu, nc, out);
}

frix_error make_rolling_global_problem(const frix_matrix *M, const frix_matrix *H, const double *f, const double *w,
                                       const double *mu, const double *mu_r, int64_t nc, frix_problem **out) {
    return make_global_problem_of({mu_r, nullptr, 5}, M, H, f, w, mu, nc, out);
}

frix_error make_spinning_global_problem(const frix_matrix *M, const frix_matrix *H, const double *f, const double *w,
                                        const double *mu, const double *mu_r, const double *mu_s, int64_t nc,
                                        frix_problem **out) {
    return make_global_problem_of({mu_r, mu_s, 6}, M, H, f, w, mu, nc, out);
}

frix_error make_owned_local_problem(std::unique_ptr<frix_matrix> W, std::vector<double> q,
                                    std::vector<double> mu, frix_problem **out) {
    return make_owned_local_problem_of({}, std::move(W), std::move(q), std::move(mu), out);
}

frix_error make_owned_global_problem(std::unique_ptr<frix_matrix> M, std::unique_ptr<frix_matrix> H,
                                     std::vector<double> f, std::vector<double> w,
                                     std::vector<double> mu, frix_problem **out) {
    return make_owned_global_problem_of({}, std::move(M), std::move(H), std::move(f), std::move(w), std::move(mu),
                                        out);
}

frix_error make_owned_rolling_local_problem(std::unique_ptr<frix_matrix> W, std::vector<double> q,
                                            std::vector<double> mu, std::vector<double> mu_r, frix_problem **out) {
    return make_owned_local_problem_of({std::move(mu_r), {}, 5}, std::move(W), std::move(q), std::move(mu), out);
}

frix_error make_owned_spinning_local_problem(std::unique_ptr<frix_matrix> W, std::vector<double> q,
                                             std::vector<double> mu, std::vector<double> mu_r,
                                             std::vector<double> mu_s, frix_problem **out) {
    return make_owned_local_problem_of({std::move(mu_r), std::move(mu_s), 6}, std::move(W), std::move(q),
                                       std::move(mu), out);
}

frix_error make_owned_rolling_global_problem(std::unique_ptr<frix_matrix> M, std::unique_ptr<frix_matrix> H,
                                             std::vector<double> f, std::vector<double> w, std::vector<double> mu,
                                             std::vector<double> mu_r, frix_problem **out) {
    return make_owned_global_problem_of({std::move(mu_r), {}, 5}, std::move(M), std::move(H), std::move(f),
                                        std::move(w), std::move(mu), out);
}

frix_error make_owned_spinning_global_problem(std::unique_ptr<frix_matrix> M, std::unique_ptr<frix_matrix> H,
                                              std::vector<double> f, std::vector<double> w, std::vector<double> mu,
                                              std::vector<double> mu_r, std::vector<double> mu_s,
                                              frix_problem **out) {
    return make_owned_global_problem_of({std::move(mu_r), std::move(mu_s), 6}, std::move(M), std::move(H),
                                        std::move(f), std::move(w), std::move(mu), out);
}

double inverse_mass(double m_ii, double otherwise) {
    return m_ii > 0.0 && std::isfinite(1.0 / m_ii) ? 1.0 / m_ii : otherwise;
}

void PositiveMean::add(const std::vector<double> &x) {
    for (double v : x)
        if (v > 0.0 && std::isfinite(v)) {
            sum += v;
            count += 1.0;
        }
}

double PositiveMean::fill() const { return count > 0.0 && std::isfinite(sum / count) ? sum / count : 1.0; }

void fill_not_positive(std::vector<double> &x, double fill) {
    for (double &v : x)
        if (!(v > 0.0 && std::isfinite(v))) v = fill;
}

double load_velocity_of(double mean_weight, int64_t nc, double load_norm, int64_t load_dofs) {
    if (load_dofs == 0) return 0.0;
    // The load's root mean square at each of the nc contacts.
    const double v = std::sqrt(mean_weight * (double)nc / (double)load_dofs) * load_norm;
    return std::isfinite(v) ? v : 0.0;
}

double free_velocity_of(double norm_w, double norm_jacobi, double load_velocity) {
    return std::max({norm_w, std::isfinite(norm_jacobi) ? norm_jacobi : 0.0, load_velocity});
}

std::vector<double> inverse_mass_diagonal(const frix_problem &p, double otherwise) {
    std::vector<double> inverse = p.M ? matrix_diagonal(*p.M) : std::vector<double>((size_t)p.n, 0.0);
    for (double &x : inverse) x = inverse_mass(x, otherwise);
    return inverse;
}

std::vector<double> delassus_diagonal(const frix_problem &p, const std::vector<double> &inverse_mass) {
    const int64_t m = contact_size(p) * p.nc;
    if (is_local_form(p)) return p.W ? matrix_diagonal(*p.W) : std::vector<double>((size_t)m, 0.0);
    std::vector<double> diag((size_t)m, 0.0);
    if (p.H)
        for_each_entry(*p.H, [&](int64_t i, int64_t j, double v) { diag[(size_t)j] += v * v * inverse_mass[(size_t)i]; });
    return diag;
}

namespace {

// Every value that is not positive and finite becomes the mean of those that are (1 if none).
void fill_with_mean(std::vector<double> &x) {
    PositiveMean mean;
    mean.add(x);
    fill_not_positive(x, mean.fill());
}

// p.dof_weight and p.load_weight of a global problem (problem.hpp), from 1 / M_ii.
void set_dof_weights(frix_problem &p, const std::vector<double> &inverse_mass) {
    p.dof_weight = inverse_mass;
    for (double &x : p.dof_weight) x = std::sqrt(x);
    fill_with_mean(p.dof_weight);
    // The bodies: components of M's graph; those with an entry of H are in contact.
    DisjointSets bodies(p.n);
    if (p.M)
        for_each_entry(*p.M, [&](int64_t i, int64_t j, double x) {
            if (x != 0.0) bodies.unite(i, j);
        });
    std::vector<char> touched((size_t)p.n, 0), reached((size_t)p.n, 0);
    if (p.H)
        for_each_entry(*p.H, [&](int64_t i, int64_t, double x) {
            if (x == 0.0) return;
            reached[(size_t)i] = 1;
            touched[(size_t)bodies.find(i)] = 1;
        });
    p.load_weight.assign((size_t)p.n, 0.0);
    for (int64_t i = 0; i < p.n; ++i)
        if (!reached[(size_t)i] && touched[(size_t)bodies.find(i)]) p.load_weight[(size_t)i] = p.dof_weight[(size_t)i];
}

}  // namespace

std::vector<double> unfilled_contact_weights(const frix_problem &p, const std::vector<double> &inverse_mass) {
    const std::vector<double> diag = delassus_diagonal(p, inverse_mass);
    std::vector<double> w((size_t)p.nc, 0.0);
    const int dim = contact_size(p);
    for (int64_t a = 0; a < p.nc; ++a) w[(size_t)a] = diag[(size_t)(dim * a)];
    return w;
}

void set_contact_weights(frix_problem &p) {
    // A dof whose mass is not positive moves nothing here (0), unlike the existence check's
    // metric, which gives it 1.
    const std::vector<double> inverse_mass =
        is_local_form(p) ? std::vector<double>() : inverse_mass_diagonal(p, 0.0);
    p.weight = unfilled_contact_weights(p, inverse_mass);
    fill_with_mean(p.weight);
    p.dof_weight.clear();
    p.load_weight.clear();
    if (!is_local_form(p)) set_dof_weights(p, inverse_mass);
}

double free_velocity(const frix_problem &p) {
    const int64_t m = contact_size(p) * p.nc;
    if (is_local_form(p) || !p.M) return is_local_form(p) ? norm2(p.q, m) : 0.0;
    // w + H^T D^-1 f, D = diag(M) (0 where a mass is not positive), by one product with H^T:
    // the division once a dof, not once an entry of H.
    std::vector<double> load = matrix_diagonal(*p.M);
    for (int64_t i = 0; i < p.n; ++i) load[(size_t)i] = load[(size_t)i] > 0.0 ? p.f[i] / load[(size_t)i] : 0.0;
    std::vector<double> free;
    copy_advised(free, p.w, (size_t)m);
    if (p.H && m > 0) matrix_gemv_transposed(*p.H, 1.0, load.data(), 1.0, free.data());
    return free_velocity_of(norm2(p.w, m), norm2(free.data(), m), load_velocity(p));
}

double load_velocity(const frix_problem &p) {
    if (p.kind != FRIX_PROBLEM_GLOBAL || p.nc == 0 || (int64_t)p.load_weight.size() != p.n) return 0.0;
    std::vector<double> load;
    for (int64_t i = 0; i < p.n; ++i)
        if (p.load_weight[(size_t)i] > 0.0) load.push_back(p.f[i] * p.load_weight[(size_t)i]);
    double mean_weight = 0.0;
    for (double x : p.weight) mean_weight += x / (double)p.nc;
    return load_velocity_of(mean_weight, p.nc, norm2(load.data(), (int64_t)load.size()), (int64_t)load.size());
}

frix_error check_problem_vectors(const frix_problem &p) {
    const char *where = "frix_solve";
    const int64_t m = contact_size(p) * p.nc;
    if (is_local_form(p)) {
        if (frix_error e = check_vector(where, "q", p.q, m)) return e;
    } else {
        if (frix_error e = check_vector(where, "f", p.f, p.n)) return e;
        if (frix_error e = check_vector(where, "w", p.w, m)) return e;
    }
    if (is_rolling(p))
        if (frix_error e = check_mu(where, p.mu_r, p.nc, "mu_r")) return e;
    if (p.spinning)
        if (frix_error e = check_mu(where, p.mu_s, p.nc, "mu_s")) return e;
    return check_mu(where, p.mu, p.nc);
}

}  // namespace frix

namespace {
// The setters of a problem's texts (NULL: empty).
frix_error set_text(const char *where, frix_problem *p, std::string frix_problem::*field,
                    const char *text) {
    return frix::guard(where, [&]() -> frix_error {
        if (!p) return frix::fail(FRIX_ERR_INVALID_ARGUMENT, "%s: problem is NULL", where);
        const size_t length = text ? std::strlen(text) : 0;
        if (length > frix::kMaxProblemText)
            return frix::fail(FRIX_ERR_INVALID_ARGUMENT, "%s: the text has %zu bytes, more than %zu",
                        where, length, frix::kMaxProblemText);
        (p->*field).assign(text ? text : "", length);
        return FRIX_OK;
    });
}
}  // namespace

extern "C" {

FRIX_API frix_error frix_problem_local(const frix_matrix *W, const double *q, const double *mu,
                                       int64_t nc, frix_problem **out) {
    return frix::guard("frix_problem_local",
                       [&] { return frix::make_local_problem(W, q, mu, nc, out); });
}

FRIX_API frix_error frix_problem_global(const frix_matrix *M, const frix_matrix *H,
                                        const double *f, const double *w, const double *mu,
                                        int64_t nc, frix_problem **out) {
    return frix::guard("frix_problem_global",
                       [&] { return frix::make_global_problem(M, H, f, w, mu, nc, out); });
}

FRIX_API frix_error frix_problem_rolling_local(const frix_matrix *W, const double *q, const double *mu,
                                               const double *mu_r, int64_t nc, frix_problem **out) {
    return frix::guard("frix_problem_rolling_local",
                       [&] { return frix::make_rolling_local_problem(W, q, mu, mu_r, nc, out); });
}

FRIX_API frix_error frix_problem_rolling_global(const frix_matrix *M, const frix_matrix *H, const double *f,
                                                const double *w, const double *mu, const double *mu_r, int64_t nc,
                                                frix_problem **out) {
    return frix::guard("frix_problem_rolling_global",
                       [&] { return frix::make_rolling_global_problem(M, H, f, w, mu, mu_r, nc, out); });
}

FRIX_API frix_error frix_problem_spinning_local(const frix_matrix *W, const double *q, const double *mu,
                                                const double *mu_r, const double *mu_s, int64_t nc,
                                                frix_problem **out) {
    return frix::guard("frix_problem_spinning_local",
                       [&] { return frix::make_spinning_local_problem(W, q, mu, mu_r, mu_s, nc, out); });
}

FRIX_API frix_error frix_problem_spinning_global(const frix_matrix *M, const frix_matrix *H, const double *f,
                                                 const double *w, const double *mu, const double *mu_r,
                                                 const double *mu_s, int64_t nc, frix_problem **out) {
    return frix::guard("frix_problem_spinning_global",
                       [&] { return frix::make_spinning_global_problem(M, H, f, w, mu, mu_r, mu_s, nc, out); });
}

FRIX_API void frix_problem_free(frix_problem *p) { delete p; }

FRIX_API frix_problem_kind frix_problem_get_kind(const frix_problem *p) {
    return p ? p->kind : FRIX_PROBLEM_LOCAL;
}
FRIX_API int64_t frix_problem_contacts(const frix_problem *p) { return p ? p->nc : 0; }
FRIX_API int64_t frix_problem_contact_dofs(const frix_problem *p) {
    return p ? frix::contact_size(*p) * p->nc : 0;
}
FRIX_API int64_t frix_problem_dofs(const frix_problem *p) { return p ? p->n : 0; }
FRIX_API const frix_matrix *frix_problem_W(const frix_problem *p) { return p ? p->W : nullptr; }
FRIX_API const frix_matrix *frix_problem_M(const frix_problem *p) { return p ? p->M : nullptr; }
FRIX_API const frix_matrix *frix_problem_H(const frix_problem *p) { return p ? p->H : nullptr; }
FRIX_API const double *frix_problem_q(const frix_problem *p) { return p ? p->q : nullptr; }
FRIX_API const double *frix_problem_f(const frix_problem *p) { return p ? p->f : nullptr; }
FRIX_API const double *frix_problem_w(const frix_problem *p) { return p ? p->w : nullptr; }
FRIX_API const double *frix_problem_mu(const frix_problem *p) { return p ? p->mu : nullptr; }
FRIX_API const double *frix_problem_mu_r(const frix_problem *p) { return p ? p->mu_r : nullptr; }
FRIX_API const double *frix_problem_mu_s(const frix_problem *p) { return p ? p->mu_s : nullptr; }

FRIX_API frix_error frix_problem_set_title(frix_problem *p, const char *title) {
    return set_text("frix_problem_set_title", p, &frix_problem::title, title);
}
FRIX_API const char *frix_problem_title(const frix_problem *p) { return p ? p->title.c_str() : ""; }

FRIX_API frix_error frix_problem_set_description(frix_problem *p, const char *description) {
    return set_text("frix_problem_set_description", p, &frix_problem::description, description);
}
FRIX_API const char *frix_problem_description(const frix_problem *p) {
    return p ? p->description.c_str() : "";
}

FRIX_API frix_error frix_problem_set_math_info(frix_problem *p, const char *math_info) {
    return set_text("frix_problem_set_math_info", p, &frix_problem::math_info, math_info);
}
FRIX_API const char *frix_problem_math_info(const frix_problem *p) {
    return p ? p->math_info.c_str() : "";
}

}  // extern "C"
