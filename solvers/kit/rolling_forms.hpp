// What the rolling NSGS sweeps run on (n = 5 entries a contact, 6 with spinning friction): W
// where it lies or a copy of its n x n block rows (the local form), or H and M^-1 H with
// v = M^-1 (H r + f) kept up to date (the global form of rigid bodies: W is never formed; its
// contacts cut into domains, those of a colour swept at once on threads). Each gives a
// contact's diagonal block and local q, is told of each change of a reaction, and measures r
// exactly.
#pragma once

#include <algorithm>
#include <cstdint>
#include <functional>
#include <memory>
#include <type_traits>
#include <vector>

#include "solvers/kit/contact_products.hpp"
#include "solvers/kit/local_rolling.hpp"
#include "solvers/kit/rigid_bodies.hpp"
#include "solvers/kit/sweeps.hpp"
#include "src/measures.hpp"
#include "src/error_state.hpp"
#include "src/problem.hpp"
#include "src/solver_api.hpp"
#include "src/thread_team.hpp"

namespace frix::rolling {

// W by n x n block rows (n = size): row a's blocks k in [row_ptr[a], row_ptr[a + 1]), in
// increasing block column block_col[k], values val[n^2 k ..] (column-major); diag[a]: its
// diagonal block, -1 if none.
struct BlockRows {
    int size = 5;
    std::vector<int64_t> row_ptr, block_col, diag;
    std::vector<double> val;
    // y = W x (size entries a contact).
    void multiply(const double *x, double *y) const;
};

class SweepForm {
   public:
    explicit SweepForm(int size) : size_(size) {}
    virtual ~SweepForm() = default;
    // Entries a contact, n: 5, or 6 with spinning friction.
    int size() const { return size_; }
    // What the sweeps read, for the log.
    virtual const char *name() const = 0;
    // out = contact a's diagonal block W_aa (n^2 values, column-major).
    virtual void diagonal_block(int64_t a, double *out) const = 0;
    // Contact a's local q: q_a + sum_{b != a} W_ab r_b (n values).
    virtual void local_q(int64_t a, const double *r, double *ql) const = 0;
    // r_a changed by dr (n values).
    virtual void moved(int64_t a, const double *dr) { (void)a, (void)dr; }
    // The rolling measures at r (u receives the velocities), and what the form keeps
    // resynchronised with r (rounding drifts).
    virtual Measures exact(const double *r, double *u) = 0;
    // r changed other than by a sweep (momentum): what the form keeps follows.
    virtual void restart(const double *r) { (void)r; }
    // The sweep order cut into domains (kit/sweeps.hpp), the domains of a colour sharing no
    // data of the form, and the team that sweeps them at once; null: every contact in order,
    // on the caller's thread.
    virtual const nsgs::Domains *domains() const { return nullptr; }
    virtual ThreadTeam *team() { return nullptr; }

   private:
    int size_;
};

// W's block rows, taken from W in either storage (memory: its blocks).
class RowForm : public SweepForm {
   public:
    explicit RowForm(const frix_problem &p);
    const char *name() const override { return "local form, W's block rows copied"; }
    void diagonal_block(int64_t a, double *out) const override;
    void local_q(int64_t a, const double *r, double *ql) const override;
    Measures exact(const double *r, double *u) override { return local_measures(p_, r, u); }
    const BlockRows &rows() const { return w_; }

   private:
    const frix_problem &p_;
    BlockRows w_;
};

// W read where it lies, with no copy: its rows as its 3x3 block rows store them, or, where W
// is stored by columns and equals its transpose to round-off at every scale
// (symmetric_at_every_scale; W = H^T M^-1 H is symmetric), its columns read as its rows. Near
// rest a step takes a few sweeps, and a copy of W's blocks (RowForm) costs more than they do.
// Memory: two indices a column of W.
class StoredForm : public SweepForm {
   public:
    explicit StoredForm(const frix_problem &p);
    // Whether p's W can be read so: stored by block rows, or symmetric (by columns: one pass
    // over W, in the constructor).
    bool serves() const { return serves_; }
    const char *name() const override {
        return p_.W->block ? "local form, W's stored rows" : "local form, W's columns as its rows";
    }
    void diagonal_block(int64_t a, double *out) const override;
    void local_q(int64_t a, const double *r, double *ql) const override;
    Measures exact(const double *r, double *u) override { return local_measures(p_, r, u); }

   private:
    const frix_problem &p_;
    // By columns: per column of W, where its entries in the diagonal block start and end (the
    // rows of its contact: one run, rows sorted).
    std::vector<int64_t> diag_first_, diag_end_;
    bool serves_ = false;
};

// The product form: per contact, the dofs of the bodies it touches, H_a and M^-1 H_a on them
// (n values a dof); v = M^-1 (H r + f) updated by each change of r.
class BodyForm : public SweepForm {
   public:
    explicit BodyForm(const frix_problem &p) : SweepForm(contact_size(p)), p_(p) {}
    const char *name() const override { return "product (global) form"; }
    // The bodies, their inverses and the per-contact data; FRIX_ERR_UNSUPPORTED for a
    // deformable M (rigid_bodies.hpp), the message naming `who`, the solver. threads > 0:
    // the contacts are also cut into domains coloured by body, swept on that many threads
    // (0: no sweeps on this form; a problem of one domain: swept in order on one thread).
    frix_error setup(const double *r, const char *who, int threads = 0);
    void diagonal_block(int64_t a, double *out) const override {
        const size_t nn = (size_t)(size() * size());
        std::copy_n(&blocks_[nn * (size_t)at(a)], nn, out);
    }
    void local_q(int64_t a, const double *r, double *ql) const override;
    void moved(int64_t a, const double *dr) override { add_g(a, dr, v_.data()); }
    Measures exact(const double *r, double *u) override;
    void restart(const double *r) override;
    // v in the problem's numbering of the dofs.
    void copy_v(double *v) const;
    // W = H^T M^-1 H by block rows (the blocks of contacts that share a body), and the free
    // velocity q = H^T M^-1 f + w: the local form, for solvers that need W (after setup).
    // fits(W) is asked once W's pattern is known (row_ptr, block_col, diag), before its values
    // are allocated: where it says no, W is left empty and reduce returns false.
    bool reduce(BlockRows &W, double *q, const std::function<bool(const BlockRows &pattern)> &fits) const;
    const nsgs::Domains *domains() const override { return team_ ? &domains_ : nullptr; }
    ThreadTeam *team() override { return team_.get(); }

   private:
    // Contact a's position in the per-contact data (cp_, blocks_, w_): the sweep order.
    int64_t at(int64_t a) const { return position_.empty() ? a : position_[(size_t)a]; }
    // The contact at position k (loops over every contact run in this order).
    int64_t contact_at(int64_t k) const { return position_.empty() ? k : domains_.contacts[(size_t)k]; }
    // f(k) for every position k; with domains, a colour's domains at once on the team: each
    // dof of v is then written by the contacts in position order, whatever the threads.
    template <class F>
    void for_positions(F &&f);
    void add_g(int64_t a, const double *x, double *v) const;
    void contact_velocity(int64_t a, const double *v, double *s) const;
    const frix_problem &p_;
    RigidBodies bodies_;
    ContactProducts cp_;                   // by position: the contact's dofs, H_a and M^-1 H_a on them
    std::vector<double> blocks_, w_;       // by position: W_aa (n^2 a contact), w_a
    std::vector<double> v0_, v_;           // M^-1 f, v (in the sweeps' numbering of the dofs)
    double norm_w_ = 0.0, free_ = 0.0;     // |w| and free_velocity(p_): the measures' scales, set once
    std::vector<int64_t> position_;        // with domains: contact a's position (else a)
    // With domains, v's dofs renumbered in the order the sweep first reaches them (cp_'s dofs
    // too): a domain reads and writes a compact part of v. Empty: the problem's numbering.
    std::vector<int64_t> slot_of_dof_, dof_of_slot_;
    nsgs::Domains domains_;  // of the contacts, in the problem's numbering
    std::unique_ptr<ThreadTeam> team_;
};

// Each contact's one-contact data (local_rolling::contact_setup) from the form's diagonal blocks,
// in the sweep order: with domains, the k-th is that of contact domains()->contacts[k].
std::vector<local_rolling::Contact> contacts_of(const SweepForm &form, const frix_problem &p);

struct SweepStats {
    double dr2 = 0.0, r2 = 0.0;
    int64_t unsolved = 0, rejected = 0;  // local solves short of the local tolerance; non-finite ones discarded
};

// One Gauss-Seidel sweep over every contact (the rolling NSGS's): each solved with the others
// held fixed, its new reaction kept where finite, the form told of each change. On a form with
// domains, domain by domain in their order, a colour's domains at once on the form's team, the
// statistics summed in domain order: r does not depend on the number of threads.
SweepStats sweep(SweepForm &form, std::vector<local_rolling::Contact> &contacts, const local_rolling::Params &lp,
                 double *r);

// A rolling solver's entry (`name` in its messages): refuses other problems; runs run(form) on
// the local form (a StoredForm where it serves and run takes one, else a RowForm: a run names
// the form types it takes) or on the rigid bodies' product form (a BodyForm set up
// from ctx.r, with domains swept on `threads` threads if threads > 0), and then writes v of the
// final r, free of the iterations' rounding drift, by a last exact(); none where the run sets
// *measured_at_r: its last exact() was at the r it returned, into ctx.u, nothing moved since
// (exact() recomputes v from r alone: u and v are then that one's to the bit). No contacts:
// converged, v = M^-1 f.
template <class Run>
frix_error solve_on_form(SolveContext &ctx, const char *name, Run &&run, int threads = 0,
                         const bool *measured_at_r = nullptr) {
    const frix_problem &p = ctx.problem;
    if (!is_rolling(p)) return fail(FRIX_ERR_UNSUPPORTED, "%s: solves rolling-friction problems only", name);
    if (p.kind == FRIX_PROBLEM_ROLLING_LOCAL) {
        // A run on any sweep form reads W where it lies; one that needs W's block rows (the
        // Newton solver's system) is handed a copy.
        if constexpr (std::is_invocable_v<Run &, StoredForm &>) {
            StoredForm stored(p);
            if (stored.serves()) return run(stored);
        }
        RowForm rows(p);
        return run(rows);
    }
    BodyForm bodies(p);
    if (frix_error e = bodies.setup(ctx.r, name, threads)) return e;
    if (p.nc == 0)
        ctx.info.status = FRIX_STATUS_CONVERGED;
    else if (frix_error e = run(bodies))
        return e;
    if (!(measured_at_r && *measured_at_r)) bodies.exact(ctx.r, ctx.u);
    bodies.copy_v(ctx.v);
    return FRIX_OK;
}

}  // namespace frix::rolling
