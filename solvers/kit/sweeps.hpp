// Nonsmooth Gauss-Seidel: sweeps over the contacts of a local problem, each solved exactly or
// nearly so by a one-contact solver. Ids 500 (NSGS: local q from W's block rows), 501
// (velocity-based NSGS: u = W r + q kept up to date by W's block columns) and 902 (global
// problems of rigid bodies: v kept up to date by M^-1 H, gnsgs.cpp). The sweep is also
// the inner solver of the fixed points (fixed_points.cpp), which pass their own local step.
#pragma once

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include "solvers/kit/local3x3.hpp"
#include "solvers/kit/rigid_bodies.hpp"
#include "solvers/kit/single_columns.hpp"
#include "src/matrix.hpp"
#include "src/memory.hpp"
#include "src/problem.hpp"
#include "src/solver_api.hpp"
#include "src/thread_team.hpp"

namespace frix {


namespace nsgs {

struct Settings {
    local::Params local;
    double relaxation = 1.0;
    int shuffle = 0;  // frix_shuffle
    uint64_t seed = 0;
    // A contact whose reaction moved by less than the freeze threshold in a sweep is skipped
    // for this many sweeps (0: never).
    int64_t freezing = 0;
};

// The sweep settings an options object (of solver 500 or 501) asks for.
Settings settings_from(const frix_options &o);

// Contacts grouped by colour: the contacts of colour k are contacts[ptr[k] .. ptr[k+1]), in
// increasing order; no two of one colour share a body (a block of M, or of W's rows).
struct Colouring {
    std::vector<int64_t> ptr, contacts;
    int64_t colours() const { return ptr.empty() ? 0 : (int64_t)ptr.size() - 1; }
};

// Greedy colouring: contact a, in increasing order, takes the smallest colour that no earlier
// contact sharing one of its groups has. groups_of(a, out) appends a's group ids (< groups).
template <class GroupsOf>
Colouring greedy_colouring(int64_t nc, int64_t groups, GroupsOf &&groups_of) {
    std::vector<int64_t> colour((size_t)nc), mark, mine;
    std::vector<std::vector<int64_t>> used((size_t)groups);  // colours taken in each group
    int64_t colours = 0;
    for (int64_t a = 0; a < nc; ++a) {
        mine.clear();
        groups_of(a, mine);
        for (const int64_t g : mine)
            for (const int64_t c : used[(size_t)g]) {
                if ((int64_t)mark.size() <= c) mark.resize((size_t)c + 1, -1);
                mark[(size_t)c] = a;
            }
        int64_t c = 0;
        while (c < (int64_t)mark.size() && mark[(size_t)c] == a) ++c;
        colour[(size_t)a] = c;
        colours = std::max(colours, c + 1);
        for (const int64_t g : mine) used[(size_t)g].push_back(c);
    }
    Colouring out;
    out.ptr.assign((size_t)colours + 1, 0);
    for (int64_t a = 0; a < nc; ++a) ++out.ptr[(size_t)colour[(size_t)a] + 1];
    for (int64_t k = 0; k < colours; ++k) out.ptr[(size_t)k + 1] += out.ptr[(size_t)k];
    out.contacts.resize((size_t)nc);
    std::vector<int64_t> next(out.ptr.begin(), out.ptr.end() - 1);
    for (int64_t a = 0; a < nc; ++a) out.contacts[(size_t)next[(size_t)colour[(size_t)a]]++] = a;
    return out;
}

// Contacts cut into domains for threaded sweeps. The contacts are put in a breadth-first
// order of the contact graph (two contacts are neighbours when they share a group) and cut
// into runs of domain_size; the domains are coloured greedily so that no two of one colour
// share a group. A thread sweeps a whole domain in order and the domains of a colour run in
// parallel: one wait per colour, and each thread works on groups of its own, mostly apart
// from the other threads' ones. The order depends on the problem and domain_size only, never
// on the number of threads.
struct Domains {
    std::vector<int64_t> contacts;    // the sweep order: colour by colour, domain by domain
    std::vector<int64_t> domain_ptr;  // domain d is contacts[domain_ptr[d] .. domain_ptr[d+1])
    std::vector<int64_t> colour_ptr;  // colour k is domains colour_ptr[k] .. colour_ptr[k+1]
    int64_t domains() const { return domain_ptr.empty() ? 0 : (int64_t)domain_ptr.size() - 1; }
    int64_t colours() const { return colour_ptr.empty() ? 0 : (int64_t)colour_ptr.size() - 1; }
};

template <class GroupsOf>
Domains make_domains(int64_t nc, int64_t groups, int64_t domain_size, GroupsOf &&groups_of) {
    // Each contact's groups, and each group's contacts. Reserved for two groups a contact (two
    // bodies): grown by doubling, each copy would touch fresh pages.
    std::vector<int64_t> group_ptr, group_list;
    reserve_advised(group_ptr, (size_t)nc + 1);
    group_ptr.push_back(0);
    reserve_advised(group_list, 2 * (size_t)nc);
    for (int64_t a = 0; a < nc; ++a) {
        groups_of(a, group_list);
        group_ptr.push_back((int64_t)group_list.size());
    }
    std::vector<int64_t> contact_ptr((size_t)groups + 1, 0), contact_list;
    assign_advised(contact_list, group_list.size());
    for (const int64_t g : group_list) ++contact_ptr[(size_t)g + 1];
    for (int64_t g = 0; g < groups; ++g) contact_ptr[(size_t)g + 1] += contact_ptr[(size_t)g];
    {
        std::vector<int64_t> next(contact_ptr.begin(), contact_ptr.end() - 1);
        for (int64_t a = 0; a < nc; ++a)
            for (int64_t i = group_ptr[(size_t)a]; i < group_ptr[(size_t)a + 1]; ++i)
                contact_list[(size_t)next[(size_t)group_list[(size_t)i]]++] = a;
    }
    // Breadth first, each component from its first contact; a group is expanded once.
    std::vector<int64_t> order;
    reserve_advised(order, (size_t)nc);
    std::vector<char> seen((size_t)nc, 0), expanded((size_t)groups, 0);
    for (int64_t start = 0; start < nc; ++start) {
        if (seen[(size_t)start]) continue;
        seen[(size_t)start] = 1;
        order.push_back(start);
        for (size_t head = order.size() - 1; head < order.size(); ++head) {
            const int64_t a = order[head];
            for (int64_t i = group_ptr[(size_t)a]; i < group_ptr[(size_t)a + 1]; ++i) {
                const int64_t g = group_list[(size_t)i];
                if (expanded[(size_t)g]) continue;
                expanded[(size_t)g] = 1;
                for (int64_t j = contact_ptr[(size_t)g]; j < contact_ptr[(size_t)g + 1]; ++j)
                    if (!seen[(size_t)contact_list[(size_t)j]]) {
                        seen[(size_t)contact_list[(size_t)j]] = 1;
                        order.push_back(contact_list[(size_t)j]);
                    }
            }
        }
    }
    const int64_t size = std::max<int64_t>(domain_size, 1), count = (nc + size - 1) / size;
    const Colouring colouring = greedy_colouring(count, groups, [&](int64_t d, std::vector<int64_t> &out) {
        const size_t from = out.size();
        for (int64_t k = d * size; k < std::min(nc, (d + 1) * size); ++k) {
            const int64_t a = order[(size_t)k];
            out.insert(out.end(), group_list.begin() + group_ptr[(size_t)a], group_list.begin() + group_ptr[(size_t)a + 1]);
        }
        std::sort(out.begin() + (std::ptrdiff_t)from, out.end());
        out.erase(std::unique(out.begin() + (std::ptrdiff_t)from, out.end()), out.end());
    });
    Domains out;
    reserve_advised(out.contacts, (size_t)nc);
    out.domain_ptr.assign(1, 0);
    out.colour_ptr.assign(1, 0);
    for (int64_t k = 0; k < colouring.colours(); ++k) {
        for (int64_t i = colouring.ptr[(size_t)k]; i < colouring.ptr[(size_t)k + 1]; ++i) {
            const int64_t d = colouring.contacts[(size_t)i];
            out.contacts.insert(out.contacts.end(), order.begin() + d * size, order.begin() + std::min(nc, (d + 1) * size));
            out.domain_ptr.push_back((int64_t)out.contacts.size());
        }
        out.colour_ptr.push_back(out.domains());
    }
    return out;
}

struct SweepStats {
    double dr2 = 0.0;        // sum over contacts of |r_a,new - r_a,old|^2
    double r2 = 0.0;         // |r|^2 after the sweep
    int64_t rejected = 0;    // non-finite local results discarded
    int64_t unsolved = 0;    // local solves that stopped short of the local tolerance
    int64_t frozen = 0;      // contacts skipped because frozen
    void add(const SweepStats &o) {
        dr2 += o.dr2, r2 += o.r2, rejected += o.rejected, unsolved += o.unsolved, frozen += o.frozen;
    }
};

// Everything a sweep needs, prepared once per solve; sweeps allocate nothing.
class Workspace {
   public:
    Workspace(const frix_problem &p, const Settings &s);
    // Without W (the product form): the diagonal blocks W_aa (9 each, column-major) and mu;
    // only sweep_loop runs on it.
    Workspace(const double *diagonal_blocks, const double *mu, int64_t nc, const Settings &s);
    // One pass over the contacts with the settings' one-contact solver, updating r in place.
    SweepStats sweep(double *r);
    // The same pass over contacts[0 .. count) only, in that order (the settings' shuffle does
    // not apply): a distributed sweep runs its contacts in parts between its messages.
    SweepStats sweep_part(double *r, const int64_t *contacts, int64_t count);
    // sweep_part with the local q and the updates of a form that keeps something (as
    // sweep_loop's local_q and moved).
    template <class LocalQ, class Moved>
    SweepStats sweep_part(double *r, const int64_t *contacts, int64_t count, LocalQ &&local_q, Moved &&moved) {
        const local::Params lp = s_.local;
        return sweep_contacts(
            r, contacts, count, local_q,
            [&lp](int64_t, local::Contact &c, const double *ql, double *rn) { return local::solve_contact(c, ql, rn, lp); },
            moved);
    }
    // The same pass with another one-contact step: step(a, contact, q_local, r_a) receives
    // the local q (q_a + sum_{b!=a} W_ab r_b) and r_a (3 values: the current reaction in, the
    // new one out) and returns a local::Outcome. Used by the fixed points, whose inner
    // problems (Tresca, second-order cone) differ from Coulomb's only in the local step.
    template <class Step>
    SweepStats sweep_with(double *r, Step &&step);
    // Velocity-based pass: the local q is u_a - W_aa r_a, and each change of r_a is pushed
    // into u through W's block column a, so that u = W r + q holds after the sweep (up to
    // rounding, see resync) and a contact whose reaction does not change costs O(1).
    SweepStats sweep_velocity(double *r, double *u);
    // u += W's block column a times dr: what sweep_velocity does after each change of r_a.
    void push_velocity(int64_t a, const double *dr, double *u);
    // The pushes go through `columns` (a single-precision copy of W's columns; null: W's
    // own), which must outlive the sweeps. With a team of as many threads as the columns have
    // panels (more than one), sweep_velocity runs on them as a pipeline (below); the team
    // must outlive the sweeps too.
    void push_through(const SingleColumns *columns, ThreadTeam *team = nullptr);

    // Freezing: a contact whose |r_a,new - r_a,old|^2 is <= dr2 is then skipped for
    // settings.freezing sweeps. thaw() releases every frozen contact.
    void set_freeze_threshold(double dr2) { freeze_dr2_ = dr2; }
    void thaw();

    local::Contact &contact(int64_t a) { return contacts_[(size_t)a]; }
    int64_t contacts() const { return (int64_t)contacts_.size(); }

    // The loop of every sweep: contact order, freezing, statistics. local_q(a, contact, ql)
    // gives contact a's local q; moved(a, dr) is told of each accepted change dr of r_a.
    template <class LocalQ, class Step, class Moved>
    SweepStats sweep_loop(double *r, LocalQ &&local_q, Step &&step, Moved &&moved);
    // sweep_loop's pass over `count` contacts: contacts[k] for k < count, or k itself when
    // contacts is null.
    template <class LocalQ, class Step, class Moved>
    SweepStats sweep_contacts(double *r, const int64_t *contacts, int64_t count, LocalQ &&local_q, Step &&step,
                              Moved &&moved);
    // Sweeps domain by domain in the domains' order, the domains of a colour shared among the
    // team's threads. The contacts are numbered in sweep order: domain d is contacts
    // domains.domain_ptr[d] .. domain_ptr[d+1], and domains.contacts is not read. local_q and
    // moved of two contacts of one colour's domains must touch disjoint data. The iterates and the statistics (summed domain by domain, in order) do
    // not depend on the number of threads. The settings' shuffle does not apply.
    template <class LocalQ, class Moved>
    SweepStats sweep_domains(double *r, const Domains &domains, ThreadTeam &team, LocalQ &&local_q, Moved &&moved);
    // sweep_loop with the settings' one-contact solver.
    template <class LocalQ, class Moved>
    SweepStats sweep_loop(double *r, LocalQ &&local_q, Moved &&moved) {
        const local::Params lp = s_.local;
        return sweep_loop(
            r, local_q, [&lp](int64_t, local::Contact &c, const double *ql, double *rn) {
                return local::solve_contact(c, ql, rn, lp);
            },
            moved);
    }

   private:
    // Contact a's turn in a sweep, the body every sweep shares: skipped while frozen, else its
    // local q, the step and accept(), moved told of an accepted change; its counts added to st.
    template <class LocalQ, class Step, class Moved>
    void sweep_contact(int64_t a, double *r, int64_t *frozen, LocalQ &local_q, Step &step, Moved &moved,
                       SweepStats &st);
    // sweep_velocity on the team: thread t owns the contacts of panel t (their local solves,
    // their r, u and freezing) and pushes every change into panel t's rows of u, in the
    // sweep's order; each owner publishes a contact's change before it pushes it, and the
    // other threads wait for it. Every row of u receives the same pushes in the same order as
    // on one thread, and the statistics are summed in the sweep's order: the same iterates
    // whatever the number of threads.
    SweepStats sweep_velocity_pipelined(double *r, double *u);
    void order_and_freezing(int64_t nc);
    void reshuffle();
    void build_columns();
    // Local q of contact a: q_a + sum_{b != a} W_ab r_b, in one pass over the block row that
    // steps over the diagonal block instead of subtracting it (no cancellation).
    void local_q(int64_t a, const double *r, double *ql) const {
        ql[0] = q_[3 * a];
        ql[1] = q_[3 * a + 1];
        ql[2] = q_[3 * a + 2];
        const int64_t *col = W_->block_col.data();
        const double *val = W_->block_val.data();
        const int64_t beg = W_->row_ptr[a], end = W_->row_ptr[a + 1], d = W_->diag_index[a];
        const int64_t mid = d >= 0 ? d : end;
        for (int64_t b = beg; b < mid; ++b) block_gemv_add(val + 9 * b, r + 3 * col[b], ql);
        for (int64_t b = d >= 0 ? d + 1 : end; b < end; ++b)
            block_gemv_add(val + 9 * b, r + 3 * col[b], ql);
    }
    // Accepts rn as contact a's new reaction (relaxation, finiteness, freezing), dr2 set to
    // |r_a,new - r_a,old|^2; returns false (ra unchanged) if it was rejected (not finite).
    bool accept(int64_t a, double *ra, double *rn, double &dr2);

    const frix_matrix *W_;  // null in the product form
    const double *q_;
    Settings s_;
    std::vector<local::Contact> contacts_;
    std::vector<int64_t> order_;
    uint64_t rng_;
    std::vector<int64_t> frozen_;  // sweeps left to skip, per contact (empty: no freezing)
    double freeze_dr2_ = 0.0;
    // Block columns of W (velocity sweeps): for block column a, the blocks (row, index into
    // block_val) at col_ptr_[a] .. col_ptr_[a+1].
    std::vector<int64_t> col_ptr_, col_row_, col_block_;
    const SingleColumns *single_ = nullptr;  // the pushes' columns in single precision, if any
    // The pipelined velocity sweeps: the team, each contact's published change (its sweep
    // number, whether it moved and by how much) and its statistics.
    struct alignas(64) PublishedChange {
        std::atomic<int64_t> sweep{-1};
        bool moved = false;
        double dr[3] = {0.0, 0.0, 0.0};
    };
    ThreadTeam *team_ = nullptr;
    std::unique_ptr<PublishedChange[]> published_;
    std::vector<SweepStats> contact_stats_;
    int64_t pipelined_sweeps_ = 0;
    std::vector<double> domain_dr2_, domain_r2_;  // domain sweeps: per domain, summed after
};

template <class LocalQ, class Step, class Moved>
SweepStats Workspace::sweep_loop(double *r, LocalQ &&local_q, Step &&step, Moved &&moved) {
    if (s_.shuffle == FRIX_SHUFFLE_EACH_SWEEP) reshuffle();
    return sweep_contacts(r, order_.empty() ? nullptr : order_.data(), (int64_t)contacts_.size(), local_q, step,
                          moved);
}

template <class LocalQ, class Step, class Moved>
void Workspace::sweep_contact(int64_t a, double *r, int64_t *frozen, LocalQ &local_q, Step &step, Moved &moved,
                              SweepStats &st) {
    double *ra = r + 3 * a;
    if (frozen && frozen[a] > 0) {
        --frozen[a];
        ++st.frozen;
    } else {
        local::Contact &c = contacts_[(size_t)a];
        double ql[3];
        local_q(a, (const local::Contact &)c, ql);
        double rn[3] = {ra[0], ra[1], ra[2]};
        const local::Outcome out = step(a, c, (const double *)ql, rn);
        if (out == local::Outcome::NotConverged || out == local::Outcome::NoSolution) ++st.unsolved;
        const double old[3] = {ra[0], ra[1], ra[2]};
        double dr2 = 0.0;
        if (accept(a, ra, rn, dr2)) {
            st.dr2 += dr2;
            const double dr[3] = {ra[0] - old[0], ra[1] - old[1], ra[2] - old[2]};
            if (dr[0] != 0.0 || dr[1] != 0.0 || dr[2] != 0.0) moved(a, dr);
        } else {
            ++st.rejected;
        }
    }
    st.r2 += ra[0] * ra[0] + ra[1] * ra[1] + ra[2] * ra[2];
}

template <class LocalQ, class Step, class Moved>
SweepStats Workspace::sweep_contacts(double *r, const int64_t *order, int64_t count, LocalQ &&local_q, Step &&step,
                                     Moved &&moved) {
    SweepStats st;
    int64_t *frozen = frozen_.empty() ? nullptr : frozen_.data();
    for (int64_t k = 0; k < count; ++k) sweep_contact(order ? order[k] : k, r, frozen, local_q, step, moved, st);
    return st;
}

template <class LocalQ, class Moved>
SweepStats Workspace::sweep_domains(double *r, const Domains &domains, ThreadTeam &team, LocalQ &&local_q,
                                    Moved &&moved) {
    domain_dr2_.assign((size_t)domains.domains(), 0.0);
    domain_r2_.assign((size_t)domains.domains(), 0.0);
    int64_t *frozen = frozen_.empty() ? nullptr : frozen_.data();
    const local::Params lp = s_.local;
    const auto step = [&lp](int64_t, local::Contact &c, const double *ql, double *rn) {
        return local::solve_contact(c, ql, rn, lp);
    };
    std::atomic<int64_t> rejected{0}, unsolved{0}, skipped{0};
    // Domain d's sweep; its sums go to its own slots (counts: exact in any order).
    const auto sweep_domain = [&](int64_t d) {
        SweepStats st;
        for (int64_t a = domains.domain_ptr[(size_t)d]; a < domains.domain_ptr[(size_t)d + 1]; ++a)
            sweep_contact(a, r, frozen, local_q, step, moved, st);
        domain_dr2_[(size_t)d] = st.dr2;
        domain_r2_[(size_t)d] = st.r2;
        rejected += st.rejected, unsolved += st.unsolved, skipped += st.frozen;
    };
    for (int64_t k = 0; k < domains.colours(); ++k) {
        const int64_t first = domains.colour_ptr[(size_t)k];
        team.for_chunks(domains.colour_ptr[(size_t)k + 1] - first, 1, [&](int64_t begin, int64_t end) {
            for (int64_t d = first + begin; d < first + end; ++d) sweep_domain(d);
        });
    }
    SweepStats st;
    st.rejected = rejected.load();
    st.unsolved = unsolved.load();
    st.frozen = skipped.load();
    for (int64_t d = 0; d < domains.domains(); ++d) {  // in domain order, whatever the threads
        st.dr2 += domain_dr2_[(size_t)d];
        st.r2 += domain_r2_[(size_t)d];
    }
    return st;
}

template <class Step>
SweepStats Workspace::sweep_with(double *r, Step &&step) {
    return sweep_loop(
        r, [this, r](int64_t a, const local::Contact &, double *ql) { local_q(a, r, ql); },
        step, [](int64_t, const double *) {});
}

// What the sweeps run on: W's block rows (nsgs), W's block columns with u kept up to date
// (nsgs-v), or H and M^-1 H with v kept up to date (gnsgs). run_sweeps stops them all alike.
class SweepForm {
   public:
    virtual ~SweepForm() = default;
    virtual SweepStats sweep(Workspace &ws, double *r, double *u) = 0;
    // The measures at r, computed afresh (which also resynchronises what the form keeps up
    // to date, drifting by rounding); u receives the velocities.
    virtual Measures exact(const double *r, double *u) = 0;
    // The measures from what the form keeps up to date, without a product: false where it
    // keeps nothing, or nothing close enough to measure by (then only exact() measures).
    virtual bool kept(const double *r, double *u, Measures &m) {
        (void)r, (void)u, (void)m;
        return false;
    }
    // kept() also where what the form keeps drifts beyond rounding (nsgs-v's single-precision
    // pushes), for a check that only asks whether the error is still far above the tolerance.
    virtual bool kept_drifting(const double *r, double *u, Measures &m) { return kept(r, u, m); }
    // r changed other than by a sweep (a drift jump, or the start): the kept state follows.
    virtual void restart(const double *r, double *u) { (void)r, (void)u; }
    // Whether exact()'s measures are the local ones the driver would compute (and may take).
    virtual bool measures_are_local() const { return true; }
    // Whether run_sweeps may put an earlier r back (its best) and restart() from it; not
    // where r's ghosts are other processes' (a distributed solve).
    virtual bool restores() const { return true; }
    // What the form keeps affine in r (u of nsgs-v, v of gnsgs), for the accelerations that
    // combine iterates (run_sweeps's momentum and Anderson's mix): the same combination of its
    // past values follows r, plus push_change() of what the projection on the cones moved,
    // without a product. Values and their count; `combines` false where the form cannot follow
    // such a combination (then momentum recomputes it by restart(), and Anderson's mix is off).
    struct AffineState {
        double *values = nullptr;
        size_t size = 0;
        bool combines = false;
    };
    virtual AffineState affine_state(double *u) {
        (void)u;
        return {};
    }
    // Adds contact a's change d of r to the affine state.
    virtual void push_change(Workspace &ws, int64_t a, const double *d, double *u) { (void)ws, (void)a, (void)d, (void)u; }
    // Whether exact() corrects the affine state by more than rounding (nsgs-v's
    // single-precision pushes): momentum's copy of it then moves by the same correction.
    virtual bool state_drifts() const { return false; }
    // A form whose contacts are shared among processes (a distributed solve): the bitwise or
    // of `flags` over them, so that each decision taken on one process's own data (a warm
    // start, the callback, the clock) is taken by all of them alike.
    virtual unsigned agree(unsigned flags) { return flags; }
    // The number of contacts of the whole problem, of which the workspace holds `held`.
    virtual int64_t all_contacts(int64_t held) const { return held; }
};

// After r moved from `line` to its projection y on the cones (m values): each contact's change
// pushed into the form's affine state (SweepForm::push_change).
void push_projection(SweepForm &form, Workspace &ws, const double *line, const double *y, size_t m, double *u);

// The NSGS iteration on `form` (kit/sweeps.cpp): sweeps, the light error calibrated by
// full checks, drift extrapolation, freezing, the monitor's limits and callback; ctx.info gets
// the status and the sweeps.
frix_error run_sweeps(SolveContext &ctx, Workspace &ws, SweepForm &form, const char *name);

// nsgs-v's solve (nsgs.cpp), its pushes through single-precision columns where W suits
// them at single_min_bytes (SingleColumns::suits): its entry passes kSingleColumnsMinBytes,
// a test may pass less.
frix_error solve_velocity_at(SolveContext &ctx, double single_min_bytes);
// nsgs-v's sweeps on ctx (nsgs.cpp), pushing through `columns` where given (a single-precision
// copy of ctx's W, on as many threads as it has panels; null: W's own columns in double).
frix_error run_velocity_sweeps(SolveContext &ctx, const SingleColumns *columns, const char *name);
// nsgs-v's active part (active_part.cpp): in a persistent solve (ctx.cache) on a W that suits
// single-precision columns, from a warm start that misses the tolerance (measured into `start`
// where ctx has no measured start) with a quarter or more of its contacts open, the sweeps on
// the contacts in touch, their answer then in ctx.r (ctx.measured_start cleared): their
// sweeps and status. False where it does not apply (ctx.r unchanged).
bool sweep_active_part(SolveContext &ctx, double single_min_bytes, Measures &start, int64_t *sweeps,
                       frix_status *status);

// The sweeps momentum (option acceleration) is given to halve its best error before it is off
// for the rest of a run; its error rises and falls meanwhile, so a watch on its rate waits as
// long.
constexpr int64_t kMomentumPatience = 2000;

// The weights of Nesterov's momentum on sweeps (option acceleration), shared by every NSGS:
// after the k-th sweep since the last restart, r = x_k moves to P_K(x_k + beta_k (x_k -
// x_{k-1})), beta_k = (k - 1) / (k + 2) (O'Donoghue and Candes's adaptive restart). It
// restarts (beta = 0) whenever a sweep moved r more than each of the two before (a sweep's
// displacement often alternates from one sweep to the next), and when asked (r jumped). Once
// the full checks' best error has not halved within a stall's patience, it is off for the rest
// of a run (nsgs: where its extrapolation holds the error on a plateau, the plain sweep and its
// freezing go on), or (a stall's growth g > 0) it restarts only where a sweep moved r more than
// sqrt(g) times each of the two before (rolling-nsgs's product form, which has no freezing).
struct MomentumStall {
    int64_t patience = kMomentumPatience;
    double growth = 0.0;  // 0: off at a stall
};

class MomentumSchedule {
   public:
    explicit MomentumSchedule(bool on, MomentumStall stall = {}) : on_(on), stall_(stall) {}
    bool on() const { return on_; }
    // beta for the sweep that moved r by |dr|^2 = dr2 (restart: r jumped ahead of the sweep).
    double next(double dr2, bool restart) {
        if (restart || !(dr2 <= growth_ * std::max(last_dr2_[0], last_dr2_[1]))) k_ = 0;
        last_dr2_[1] = last_dr2_[0];
        last_dr2_[0] = dr2;
        ++k_;
        return (double)(k_ - 1) / (double)(k_ + 2);
    }
    // A full check's error e after `sweep` sweeps.
    void judge(int64_t sweep, double e) {
        if (!on_) return;
        if (e < 0.5 * best_) {
            best_ = e;
            since_ = sweep;
        } else if (sweep - since_ >= stall_.patience) {
            if (stall_.growth > 0.0)
                growth_ = stall_.growth;
            else
                on_ = false;
        }
    }

   private:
    bool on_;
    const MomentumStall stall_;
    double growth_ = 1.0;  // a sweep restarts momentum where |dr|^2 exceeds this times the last two
    double last_dr2_[2] = {INFINITY, INFINITY};  // the last two sweeps' |dr|^2
    int64_t k_ = 0;
    double best_ = INFINITY;  // the best full error at a halving, and its sweep
    int64_t since_ = 0;
};

// gnsgs's limit on a rigid body's dofs (rigid_bodies.hpp).
using frix::kMaxRigidBodyDofs;

// The options of every NSGS entry, and nsgs-v's defaults (also gnsgs's: both keep velocities
// up to date, where a frozen contact costs nothing).
extern const frix_option_key kExtraKeys[];
extern const OptionDefault kVelocityDefaults[];

}  // namespace nsgs
}  // namespace frix
