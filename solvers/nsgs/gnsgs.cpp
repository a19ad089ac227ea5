// gnsgs (902): NSGS on a global problem whose M is block-diagonal with small blocks (rigid
// bodies), in product form: W is never formed. The sweep keeps v = M^-1 (H r + f) up to date;
// contact a reads u_a = H_a^T v + w_a and, after its one-contact solve, adds M^-1 H_a dr_a to
// v. Each sweep costs O(nnz(H) + nnz(M^-1 H)); memory is, per contact, the dofs of the bodies
// it touches with H_a and M^-1 H_a on them (3 values a dof each), and the blocks of M^-1.
// Contacts are cut into domains (runs of a breadth-first order of the contact graph) and the
// domains coloured (no two of a colour share a body); a thread sweeps a whole domain, the
// domains of a colour run in parallel, and v's dofs are renumbered in sweep order so that a
// domain works on a compact part of it. The stopping logic is nsgs's (run_sweeps), on the global
// measure (its scale |w|, as Siconos's).
#include <algorithm>
#include <cmath>
#include <vector>

#include "solvers/kit/contact_products.hpp"
#include "solvers/kit/sweeps.hpp"
#include "src/error_state.hpp"
#include "src/log.hpp"
#include "src/measures.hpp"
#include "src/reduction.hpp"
#include "solvers/entries.hpp"

namespace frix {
namespace gnsgs {
using namespace nsgs;  // the sweeps and their forms (kit/sweeps.hpp)
namespace {

// Domains: about kDomains of them, enough for the threads to share each colour's evenly, and
// none under kMinDomain contacts (a domain's sweep must outweigh handing it to a thread).
constexpr int64_t kDomains = 128;
constexpr int64_t kMinDomain = 256;

// M^-1 as dense blocks, one per body, and each contact's H_a and M^-1 H_a on its bodies' dofs.
class ProductForm : public SweepForm {
   public:
    ProductForm(const frix_problem &p, int threads)
        : p_(p), norm_w_(norm2(p.w, 3 * p.nc)), free_(free_velocity(p)), team_(threads) {}

    frix_error setup() {
        if (frix_error e = to_csc(*p_.M, M_)) return e;
        if (frix_error e = bodies_.setup(M_, "gnsgs")) return e;
        ContactBodies cb;  // the bodies of each contact, until the slots' data is built
        cb.find(*p_.H, bodies_, 3, p_.nc);
        // The domains of one colour share no body: their sweeps touch disjoint parts of v. The
        // sweeps run on the contacts renumbered in sweep order (slots), so that a sweep reads
        // the per-contact data front to back.
        Domains domains = make_domains(
            p_.nc, bodies_.count(), std::max(kMinDomain, (p_.nc + kDomains - 1) / kDomains),
            [&cb](int64_t a, std::vector<int64_t> &out) {
                out.insert(out.end(), cb.bodies.begin() + cb.ptr[a], cb.bodies.begin() + cb.ptr[a + 1]);
            });
        contact_of_slot_ = std::move(domains.contacts);
        slots_ = std::move(domains);  // its ranges are of slots; its contacts moved out
        cp_.build(*p_.H, bodies_, cb, 3, p_.nc, contact_of_slot_.data(), true);
        w_.resize(3 * (size_t)p_.nc);
        mu_.resize((size_t)p_.nc);
        weight_.resize((size_t)p_.nc);
        for (int64_t k = 0; k < p_.nc; ++k) {
            const int64_t a = contact_of_slot_[(size_t)k];
            std::copy(p_.w + 3 * a, p_.w + 3 * a + 3, &w_[3 * (size_t)k]);
            mu_[(size_t)k] = p_.mu[a];
            weight_[(size_t)k] = p_.weight.empty() ? 1.0 : p_.weight[(size_t)a];
        }
        cp_.renumber_dofs(p_.n, nullptr, p_.nc, slot_of_dof_);
        std::vector<double> v0((size_t)p_.n);
        bodies_.apply_inverse(p_.f, v0.data());
        v0_.resize((size_t)p_.n);
        for (int64_t d = 0; d < p_.n; ++d) v0_[(size_t)slot_of_dof_[(size_t)d]] = v0[(size_t)d];
        v_.resize((size_t)p_.n);
        M_ = Csc{};  // the sweeps read only the per-contact copies
        return FRIX_OK;
    }
    // v in the problem's numbering of the dofs.
    void copy_v(double *v) const {
        for (int64_t d = 0; d < p_.n; ++d) v[d] = v_[(size_t)slot_of_dof_[(size_t)d]];
    }
    // Slot k of the sweeps is contact contact_of_slot()[k] of the problem; w and mu by slot.
    const std::vector<int64_t> &contact_of_slot() const { return contact_of_slot_; }
    const double *slot_w() const { return w_.data(); }
    const double *slot_mu() const { return mu_.data(); }
    const std::vector<double> &slot_weight() const { return weight_; }
    int64_t colours() const { return slots_.colours(); }
    int64_t domains() const { return slots_.domains(); }
    // W_aa = H_a^T M^-1 H_a, 9 per contact, column-major.
    std::vector<double> diagonal_blocks() const {
        std::vector<double> blocks(9 * (size_t)p_.nc, 0.0);
        for (int64_t a = 0; a < p_.nc; ++a) cp_.add_diagonal_block(a, &blocks[9 * (size_t)a]);
        return blocks;
    }

    SweepStats sweep(Workspace &ws, double *r, double *) override {
        double *v = v_.data();
        const auto local_q = [this, r, v](int64_t a, const local::Contact &c, double *ql) {
            const double *Wd = c.W, *ra = r + 3 * a;
            double s[3];
            contact_velocity(a, v, s);
            for (int e = 0; e < 3; ++e) ql[e] = s[e] - (Wd[e] * ra[0] + Wd[e + 3] * ra[1] + Wd[e + 6] * ra[2]);
        };
        const auto moved = [this, v](int64_t a, const double *dr) { add_g(a, dr, v); };
        return ws.sweep_domains(r, slots_, team_, local_q, moved);
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
        std::copy(v0_.begin(), v0_.end(), v_.begin());
        for (int64_t a = 0; a < p_.nc; ++a) {
            const double *ra = r + 3 * a;
            if (ra[0] != 0.0 || ra[1] != 0.0 || ra[2] != 0.0) add_g(a, ra, v_.data());
        }
    }
    bool measures_are_local() const override { return false; }
    AffineState affine_state(double *) override { return {v_.data(), v_.size(), true}; }
    void push_change(Workspace &, int64_t a, const double *d, double *) override { add_g(a, d, v_.data()); }

   private:
    // v += M^-1 H_a x: from H_a and M's diagonal where every body of the contact is one dof
    // (M diagonal there: half the data a sweep reads), from M^-1 H_a stored otherwise.
    void add_g(int64_t a, const double *x, double *v) const {
        const int64_t *dofs = cp_.dofs.data() + cp_.dof_ptr[a];
        const int64_t count = cp_.dof_ptr[a + 1] - cp_.dof_ptr[a];
        if (cp_.g_ptr[a] < 0) {
            const double *h = cp_.hd.data() + 3 * cp_.dof_ptr[a], *d = cp_.minv.data() + cp_.dof_ptr[a];
            for (int64_t t = 0; t < count; ++t)
                v[dofs[t]] += d[t] * (h[3 * t] * x[0] + h[3 * t + 1] * x[1] + h[3 * t + 2] * x[2]);
            return;
        }
        const double *g = cp_.gd.data() + 3 * cp_.g_ptr[a];
        for (int64_t t = 0; t < count; ++t) v[dofs[t]] += g[3 * t] * x[0] + g[3 * t + 1] * x[1] + g[3 * t + 2] * x[2];
    }
    // u_a = H_a^T v + w_a.
    void contact_velocity(int64_t a, const double *v, double *s) const {
        const int64_t *dofs = cp_.dofs.data() + cp_.dof_ptr[a];
        const double *h = cp_.hd.data() + 3 * cp_.dof_ptr[a];
        s[0] = w_[3 * (size_t)a];
        s[1] = w_[3 * (size_t)a + 1];
        s[2] = w_[3 * (size_t)a + 2];
        for (int64_t t = 0; t < cp_.dof_ptr[a + 1] - cp_.dof_ptr[a]; ++t) {
            const double x = v[dofs[t]];
            s[0] += h[3 * t] * x;
            s[1] += h[3 * t + 1] * x;
            s[2] += h[3 * t + 2] * x;
        }
    }
    // u = H^T v + w and the measures' parts domain by domain on the team, the parts combined
    // in domain order (the same numbers on any number of threads).
    Measures measures_from_v(const double *r, double *u) {
        parts_.assign((size_t)slots_.domains(), MeasureParts{});
        team_.for_chunks(slots_.domains(), 1, [this, r, u](int64_t begin, int64_t end) {
            for (int64_t d = begin; d < end; ++d) {
                const int64_t first = slots_.domain_ptr[(size_t)d], last = slots_.domain_ptr[(size_t)d + 1];
                for (int64_t a = first; a < last; ++a) contact_velocity(a, v_.data(), u + 3 * a);
                parts_[(size_t)d] = measure_parts(r, u, mu_.data(), weight_.data(), first, last);
            }
        });
        MeasureParts all;
        for (const MeasureParts &part : parts_) all.add(part);
        return measures_from_parts(all, r, u, mu_.data(), p_.nc, norm_w_, free_);
    }

    const frix_problem &p_;
    std::vector<double> v_;       // in the sweeps' numbering of the dofs
    std::vector<int64_t> slot_of_dof_;  // the sweeps' numbering of v (two threads seldom share a cache line)
    double norm_w_, free_;
    Csc M_;
    RigidBodies bodies_;
    std::vector<double> v0_;
    ContactProducts cp_;   // by slot: its dofs, H_a and M^-1 H_a
    std::vector<int64_t> contact_of_slot_;
    Domains slots_;  // the domains and colours as ranges of slots
    std::vector<double> w_, mu_, weight_;
    std::vector<MeasureParts> parts_;  // per domain, for measures_from_v
    ThreadTeam team_;
};

frix_error solve(SolveContext &ctx) {
    const frix_problem &p = ctx.problem;
    if (p.kind != FRIX_PROBLEM_GLOBAL)
        return fail(FRIX_ERR_UNSUPPORTED, "gnsgs: solves global problems only");
    ProductForm form(p, (int)ctx.options.i(FRIX_OPT_THREADS));
    if (frix_error e = form.setup()) return e;
    // The sweeps see the contacts by slot: r, u, w and mu renumbered, and back at the end.
    const std::vector<int64_t> &contact = form.contact_of_slot();
    const int64_t m = 3 * p.nc;
    std::vector<double> r((size_t)m), u((size_t)m);
    for (int64_t k = 0; k < p.nc; ++k) std::copy(ctx.r + 3 * contact[k], ctx.r + 3 * contact[k] + 3, &r[3 * k]);
    frix_problem slots;
    slots.kind = FRIX_PROBLEM_GLOBAL;
    slots.nc = p.nc;
    slots.n = p.n;
    slots.M = p.M;
    slots.f = p.f;
    slots.w = form.slot_w();
    slots.mu = form.slot_mu();
    slots.weight = form.slot_weight();
    SolveContext inner =
        SolveContext::global(slots, ctx.options, r.data(), u.data(), ctx.v, ctx.info, ctx.clock, ctx.mass)
            .with_cache(ctx.cache);
    inner.return_best = ctx.return_best;
    inner.runaway_bound = ctx.runaway_bound;  // the same contacts renumbered: watched as the driver asked
    if (ctx.options.i(FRIX_OPT_VERBOSITY) >= 1)
        log_line(&ctx.options, "gnsgs: %lld contacts in %lld domains of %lld colours, %lld threads", (long long)p.nc,
                 (long long)form.domains(), (long long)form.colours(), (long long)ctx.options.i(FRIX_OPT_THREADS));
    const std::vector<double> blocks = form.diagonal_blocks();
    Workspace ws(blocks.data(), slots.mu, p.nc, settings_from(ctx.options));
    const frix_error e = run_sweeps(inner, ws, form, "gnsgs");
    form.copy_v(ctx.v);
    for (int64_t k = 0; k < p.nc; ++k) {
        std::copy(&r[3 * k], &r[3 * k] + 3, ctx.r + 3 * contact[k]);
        std::copy(&u[3 * k], &u[3 * k] + 3, ctx.u + 3 * contact[k]);
    }
    return e;
}

// nsgs-v's keys but shuffle and seed (the domains fix the order), and threads.
const frix_option_key kProductKeys[] = {FRIX_OPT_LOCAL_SOLVER, FRIX_OPT_LOCAL_TOLERANCE, FRIX_OPT_LOCAL_MAX_ITER,
                                        FRIX_OPT_RELAXATION,    FRIX_OPT_FREEZING,        FRIX_OPT_ERROR_FREQUENCY,
                                        FRIX_OPT_DRIFT_WINDOW,  FRIX_OPT_THREADS,         FRIX_OPT_ACCELERATION,
                                        FRIX_OPT_ANDERSON,      (frix_option_key)0};

}  // namespace
}  // namespace gnsgs

const SolverEntry kGnsgsEntry = {
    FRIX_SOLVER_GLOBAL_NSGS,
    "gnsgs",
    nullptr,
    "Nonsmooth Gauss-Seidel on a global problem whose M is block-diagonal with small blocks "
    "(rigid bodies, at most 64 dofs a block), without W: the sweep keeps v = M^-1 (H r + f) up "
    "to date, reads u_a = H_a^T v + w_a and adds M^-1 H_a dr_a to v after each contact's "
    "one-contact solve. A sweep costs O(nnz(H)) where nsgs's costs W's blocks; memory is H, "
    "M^-1 H (H's pattern filled to whole bodies) and M's inverse blocks. The iterates are "
    "nsgs-v's on W = H^T M^-1 H, in another order: contacts are cut into domains (runs of a "
    "breadth-first order of the contact graph), the domains coloured so that no two of one "
    "colour share a body; a thread sweeps a whole domain and the domains of a colour run at "
    "once; r does not depend on the number of threads. Stopped by the "
    "global measure. Refuses a deformable M (FRIX_ERR_UNSUPPORTED). Options: threads, and "
    "those of nsgs-v but shuffle and seed (local_solver, local_tolerance, local_max_iter, "
    "relaxation, freezing, error_frequency, drift_window, acceleration, anderson).",
    gnsgs::solve,
    false,
    true,
    gnsgs::kProductKeys,
    nsgs::kVelocityDefaults,
};

}  // namespace frix
