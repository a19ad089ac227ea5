// gnsgs (902): NSGS on a global problem whose M is block-diagonal with small blocks (rigid
// bodies), in product form: W is never formed. The sweep keeps v = M^-1 (H r + f) up to date;
// contact a reads u_a = H_a^T v + w_a and, after its one-contact solve, adds M^-1 H_a dr_a to
// v. Each sweep costs O(nnz(H) + nnz(M^-1 H)); memory is, per contact, the dofs of the bodies
// it touches with H_a and M^-1 H_a on them (3 values a dof each), and the blocks of M^-1. The iterates are those of nsgs-v on
// W = H^T M^-1 H up to rounding; the stopping logic is nsgs's (run_sweeps), on the global
// measure (its scale |w|, as Siconos's).
#include <algorithm>
#include <cmath>
#include <vector>

#include "solvers/nsgs.hpp"
#include "src/disjoint_sets.hpp"
#include "src/error_state.hpp"
#include "src/measures.hpp"
#include "src/reduction.hpp"

namespace frix {
namespace nsgs {
namespace {

// M^-1 as dense blocks, one per body, and each contact's H_a and M^-1 H_a on its bodies' dofs.
class ProductForm : public SweepForm {
   public:
    ProductForm(const frix_problem &p, double *v, int threads)
        : p_(p), v_(v), norm_w_(norm2(p.w, 3 * p.nc)), threads_(threads) {}

    frix_error setup() {
        if (frix_error e = to_csc(*p_.M, M_)) return e;
        if (frix_error e = to_csc(*p_.H, H_)) return e;
        if (frix_error e = find_bodies()) return e;
        if (frix_error e = invert_bodies()) return e;
        form_contacts();
        v0_.resize((size_t)p_.n);
        apply_inverse(p_.f, v0_.data());
        M_ = Csc{};  // the sweeps read only the per-contact copies
        H_ = Csc{};
        // Contacts of one colour share no body: their sweeps touch disjoint parts of v.
        colouring_ = greedy_colouring(p_.nc, (int64_t)body_ptr_.size() - 1, [this](int64_t a, std::vector<int64_t> &out) {
            out.insert(out.end(), contact_bodies_.begin() + bodies_ptr_[a], contact_bodies_.begin() + bodies_ptr_[a + 1]);
        });
        return FRIX_OK;
    }
    // W_aa = H_a^T M^-1 H_a, 9 per contact, column-major.
    std::vector<double> diagonal_blocks() const {
        std::vector<double> blocks(9 * (size_t)p_.nc, 0.0);
        for (int64_t a = 0; a < p_.nc; ++a) {
            const double *h = hd_.data() + 3 * dof_ptr_[a], *g = gd_.data() + 3 * dof_ptr_[a];
            for (int64_t t = 0; t < dof_ptr_[a + 1] - dof_ptr_[a]; ++t)
                for (int f = 0; f < 3; ++f)
                    for (int e = 0; e < 3; ++e) blocks[9 * a + e + 3 * f] += h[3 * t + e] * g[3 * t + f];
        }
        return blocks;
    }

    SweepStats sweep(Workspace &ws, double *r, double *) override {
        double *v = v_;
        const auto local_q = [this, r, v](int64_t a, const local::Contact &c, double *ql) {
            const double *Wd = c.W, *ra = r + 3 * a;
            double s[3];
            contact_velocity(a, v, s);
            for (int e = 0; e < 3; ++e) ql[e] = s[e] - (Wd[e] * ra[0] + Wd[e + 3] * ra[1] + Wd[e + 6] * ra[2]);
        };
        const auto moved = [this, v](int64_t a, const double *dr) {
            const int64_t *dofs = dofs_.data() + dof_ptr_[a];
            const double *g = gd_.data() + 3 * dof_ptr_[a];
            for (int64_t t = 0; t < dof_ptr_[a + 1] - dof_ptr_[a]; ++t)
                v[dofs[t]] += g[3 * t] * dr[0] + g[3 * t + 1] * dr[1] + g[3 * t + 2] * dr[2];
        };
        return ws.sweep_coloured(r, colouring_, threads_, local_q, moved);
    }
    Measures exact(const double *r, double *u) override {
        restart(r, u);
        return measures_from_v(r, u);
    }
    bool kept(const double *r, double *u, Measures &m) override {
        m = measures_from_v(r, u);
        return true;
    }
    // v = M^-1 f + M^-1 H r.
    void restart(const double *r, double *) override {
        std::copy(v0_.begin(), v0_.end(), v_);
        for (int64_t a = 0; a < p_.nc; ++a) {
            const double *ra = r + 3 * a;
            if (ra[0] == 0.0 && ra[1] == 0.0 && ra[2] == 0.0) continue;
            const int64_t *dofs = dofs_.data() + dof_ptr_[a];
            const double *g = gd_.data() + 3 * dof_ptr_[a];
            for (int64_t t = 0; t < dof_ptr_[a + 1] - dof_ptr_[a]; ++t)
                v_[dofs[t]] += g[3 * t] * ra[0] + g[3 * t + 1] * ra[1] + g[3 * t + 2] * ra[2];
        }
    }
    bool measures_are_local() const override { return false; }

   private:
    // u_a = H_a^T v + w_a.
    void contact_velocity(int64_t a, const double *v, double *s) const {
        const int64_t *dofs = dofs_.data() + dof_ptr_[a];
        const double *h = hd_.data() + 3 * dof_ptr_[a];
        s[0] = p_.w[3 * a];
        s[1] = p_.w[3 * a + 1];
        s[2] = p_.w[3 * a + 2];
        for (int64_t t = 0; t < dof_ptr_[a + 1] - dof_ptr_[a]; ++t) {
            const double x = v[dofs[t]];
            s[0] += h[3 * t] * x;
            s[1] += h[3 * t + 1] * x;
            s[2] += h[3 * t + 2] * x;
        }
    }
    Measures measures_from_v(const double *r, double *u) const {
        for (int64_t a = 0; a < p_.nc; ++a) contact_velocity(a, v_, u + 3 * a);
        return measures_from_ru(r, u, p_.mu, p_.nc, norm_w_);
    }

    frix_error find_bodies() {
        const int64_t n = p_.n;
        DisjointSets sets(n);
        for (int64_t c = 0; c < n; ++c)
            for (int64_t k = M_.colptr[c]; k < M_.colptr[c + 1]; ++k) sets.unite(M_.rowind[k], c);
        body_of_.assign((size_t)n, -1);
        std::vector<int64_t> body_of_root((size_t)n, -1);
        int64_t bodies = 0;
        for (int64_t i = 0; i < n; ++i) {
            const int64_t root = sets.find(i);
            if (body_of_root[root] < 0) {
                if (sets.size_of_root(root) > kMaxRigidBodyDofs)
                    return fail(FRIX_ERR_UNSUPPORTED,
                                "gnsgs: M couples %lld dofs in one block (more than %lld: a deformable body); "
                                "gadmm or auto solve this problem",
                                (long long)sets.size_of_root(root), (long long)kMaxRigidBodyDofs);
                body_of_root[root] = bodies++;
            }
            body_of_[i] = body_of_root[root];
        }
        // The dofs of each body in increasing order, and each dof's place in its body.
        body_ptr_.assign((size_t)bodies + 1, 0);
        for (int64_t i = 0; i < n; ++i) ++body_ptr_[body_of_[i] + 1];
        for (int64_t b = 0; b < bodies; ++b) body_ptr_[b + 1] += body_ptr_[b];
        body_dofs_.resize((size_t)n);
        place_.resize((size_t)n);
        std::vector<int64_t> next(body_ptr_.begin(), body_ptr_.end() - 1);
        for (int64_t i = 0; i < n; ++i) {
            const int64_t k = next[body_of_[i]]++;
            body_dofs_[k] = i;
            place_[i] = k - body_ptr_[body_of_[i]];
        }
        return FRIX_OK;
    }

    // Each body's block of M inverted by Gauss-Jordan with partial pivoting (M need not be
    // symmetric).
    frix_error invert_bodies() {
        const int64_t bodies = (int64_t)body_ptr_.size() - 1;
        inverse_ptr_.assign((size_t)bodies + 1, 0);
        for (int64_t b = 0; b < bodies; ++b) {
            const int64_t k = body_ptr_[b + 1] - body_ptr_[b];
            inverse_ptr_[b + 1] = inverse_ptr_[b] + k * k;
        }
        inverse_.assign((size_t)inverse_ptr_[bodies], 0.0);
        std::vector<double> a;
        for (int64_t b = 0; b < bodies; ++b) {
            const int64_t k = body_ptr_[b + 1] - body_ptr_[b];
            a.assign((size_t)(k * k), 0.0);  // column-major
            double *inv = &inverse_[inverse_ptr_[b]];
            double scale = 0.0;
            for (int64_t j = 0; j < k; ++j) {
                const int64_t col = body_dofs_[body_ptr_[b] + j];
                for (int64_t e = M_.colptr[col]; e < M_.colptr[col + 1]; ++e) {
                    a[place_[M_.rowind[e]] + k * j] += M_.val[e];
                    scale = std::max(scale, std::fabs(M_.val[e]));
                }
                inv[j + k * j] = 1.0;
            }
            for (int64_t c = 0; c < k; ++c) {
                int64_t piv = c;
                for (int64_t i = c + 1; i < k; ++i)
                    if (std::fabs(a[i + k * c]) > std::fabs(a[piv + k * c])) piv = i;
                if (!(std::fabs(a[piv + k * c]) > 1e-14 * scale))
                    return fail(FRIX_ERR_NUMERICAL, "gnsgs: M is singular (its block of dofs %lld..%lld)",
                                (long long)body_dofs_[body_ptr_[b]], (long long)body_dofs_[body_ptr_[b + 1] - 1]);
                if (piv != c)
                    for (int64_t j = 0; j < k; ++j) {
                        std::swap(a[c + k * j], a[piv + k * j]);
                        std::swap(inv[c + k * j], inv[piv + k * j]);
                    }
                const double d = 1.0 / a[c + k * c];
                for (int64_t j = 0; j < k; ++j) {
                    a[c + k * j] *= d;
                    inv[c + k * j] *= d;
                }
                for (int64_t i = 0; i < k; ++i) {
                    const double f = a[i + k * c];
                    if (i == c || f == 0.0) continue;
                    for (int64_t j = 0; j < k; ++j) {
                        a[i + k * j] -= f * a[c + k * j];
                        inv[i + k * j] -= f * inv[c + k * j];
                    }
                }
            }
        }
        return FRIX_OK;
    }

    // y = M^-1 x, body by body.
    void apply_inverse(const double *x, double *y) const {
        const int64_t bodies = (int64_t)body_ptr_.size() - 1;
        for (int64_t b = 0; b < bodies; ++b) {
            const int64_t k = body_ptr_[b + 1] - body_ptr_[b], *dofs = &body_dofs_[body_ptr_[b]];
            const double *inv = &inverse_[inverse_ptr_[b]];
            for (int64_t i = 0; i < k; ++i) {
                double s = 0.0;
                for (int64_t j = 0; j < k; ++j) s += inv[i + k * j] * x[dofs[j]];
                y[dofs[i]] = s;
            }
        }
    }

    // Per contact, the dofs of the bodies its three columns of H touch (bodies in increasing
    // order, each whole), and on them H_a and M^-1 H_a, 3 values per dof (one per column).
    void form_contacts() {
        dof_ptr_.assign((size_t)p_.nc + 1, 0);
        bodies_ptr_.assign(1, 0);
        std::vector<int64_t> touched;
        for (int pass = 0; pass < 2; ++pass) {
            int64_t at = 0;
            for (int64_t a = 0; a < p_.nc; ++a) {
                touched.clear();
                for (int64_t c = 3 * a; c < 3 * a + 3; ++c)
                    for (int64_t e = H_.colptr[c]; e < H_.colptr[c + 1]; ++e) touched.push_back(body_of_[H_.rowind[e]]);
                std::sort(touched.begin(), touched.end());
                touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
                if (pass == 0) {
                    contact_bodies_.insert(contact_bodies_.end(), touched.begin(), touched.end());
                    bodies_ptr_.push_back((int64_t)contact_bodies_.size());
                }
                for (const int64_t b : touched) {
                    const int64_t k = body_ptr_[b + 1] - body_ptr_[b];
                    if (pass == 1) {
                        double *h = &hd_[3 * at], *g = &gd_[3 * at];
                        for (int64_t i = 0; i < k; ++i) dofs_[at + i] = body_dofs_[body_ptr_[b] + i];
                        for (int64_t c = 3 * a; c < 3 * a + 3; ++c)
                            for (int64_t e = H_.colptr[c]; e < H_.colptr[c + 1]; ++e)
                                if (body_of_[H_.rowind[e]] == b) h[3 * place_[H_.rowind[e]] + (c - 3 * a)] += H_.val[e];
                        const double *inv = &inverse_[inverse_ptr_[b]];
                        for (int64_t i = 0; i < k; ++i)
                            for (int f = 0; f < 3; ++f) {
                                double s = 0.0;
                                for (int64_t j = 0; j < k; ++j) s += inv[i + k * j] * h[3 * j + f];
                                g[3 * i + f] = s;
                            }
                    }
                    at += k;
                }
                if (pass == 0) dof_ptr_[a + 1] = at;
            }
            if (pass == 0) {
                dofs_.resize((size_t)at);
                hd_.assign(3 * (size_t)at, 0.0);
                gd_.assign(3 * (size_t)at, 0.0);
            }
        }
    }

    const frix_problem &p_;
    double *v_;
    double norm_w_;
    Csc M_, H_;
    std::vector<int64_t> body_of_, body_ptr_, body_dofs_, place_, inverse_ptr_;
    std::vector<double> inverse_, v0_;
    std::vector<int64_t> dof_ptr_, dofs_;
    std::vector<double> hd_, gd_;
    std::vector<int64_t> bodies_ptr_, contact_bodies_;  // the bodies of each contact
    Colouring colouring_;
    int threads_;
};

frix_error solve(SolveContext &ctx) {
    const frix_problem &p = ctx.problem;
    if (p.kind != FRIX_PROBLEM_GLOBAL)
        return fail(FRIX_ERR_UNSUPPORTED, "gnsgs: solves global problems only");
    ProductForm form(p, ctx.v, (int)ctx.options.i(FRIX_OPT_THREADS));
    if (frix_error e = form.setup()) return e;
    const std::vector<double> blocks = form.diagonal_blocks();
    Workspace ws(blocks.data(), p.mu, p.nc, settings_from(ctx.options));
    return run_sweeps(ctx, ws, form, "gnsgs");
}

// nsgs-v's keys but shuffle and seed (the colouring fixes the order), and threads.
const frix_option_key kProductKeys[] = {FRIX_OPT_LOCAL_SOLVER, FRIX_OPT_LOCAL_TOLERANCE, FRIX_OPT_LOCAL_MAX_ITER,
                                        FRIX_OPT_RELAXATION,    FRIX_OPT_FREEZING,        FRIX_OPT_ERROR_FREQUENCY,
                                        FRIX_OPT_DRIFT_WINDOW,  FRIX_OPT_THREADS,         (frix_option_key)0};

}  // namespace
}  // namespace nsgs

const SolverEntry kGlobalNsgsEntry = {
    FRIX_SOLVER_GLOBAL_NSGS,
    "gnsgs",
    nullptr,
    "Nonsmooth Gauss-Seidel on a global problem whose M is block-diagonal with small blocks "
    "(rigid bodies, at most 64 dofs a block), without W: the sweep keeps v = M^-1 (H r + f) up "
    "to date, reads u_a = H_a^T v + w_a and adds M^-1 H_a dr_a to v after each contact's "
    "one-contact solve. A sweep costs O(nnz(H)) where nsgs's costs W's blocks; memory is H, "
    "M^-1 H (H's pattern filled to whole bodies) and M's inverse blocks. The iterates are "
    "nsgs-v's on W = H^T M^-1 H, in another order: contacts are coloured (greedily, so that "
    "no two of one colour share a body) and swept colour by colour, each colour's contacts "
    "split among the threads; r does not depend on the number of threads. Stopped by the "
    "global measure. Refuses a deformable M (FRIX_ERR_UNSUPPORTED). Options: threads, and "
    "those of nsgs-v but shuffle and seed (local_solver, local_tolerance, local_max_iter, "
    "relaxation, freezing, error_frequency, drift_window).",
    nsgs::solve,
    false,
    true,
    nsgs::kProductKeys,
    nsgs::kVelocityDefaults,
};

}  // namespace frix
