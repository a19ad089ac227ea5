// The distributed sweep forms (nsgs's SweepForm over the ranks) and what the solvers share:
// the exchange of ghost reactions and the measures over all ranks. A sweep is one
// Gauss-Seidel pass over all contacts in a fixed order. Ranks are coloured so that neighbours
// differ (distributed_problem.cpp); the order is: the boundary contacts of the ranks of colour
// 0, then of colour 1, ..., with each rank's interior contacts (coupled to its own contacts
// only) anywhere in between. A rank of colour 0 sweeps its boundary, sends it, then sweeps its
// interior; a rank of a higher colour sweeps its interior while its lower neighbours'
// reactions travel, then its boundary, then sends. Each rank ends a sweep with every ghost
// current, which the measures and the next sweep read.
#pragma once

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "mpi/distributed.hpp"
#include "solvers/kit/sweeps.hpp"
#include "src/error_state.hpp"
#include "src/measures.hpp"
#include "src/solver_api.hpp"

namespace frix {
namespace mpi {

inline constexpr int kTag = 5003;  // reactions of boundary contacts (one message per pair a sweep)

// |x|_2 over the ranks' parts of x (norm2's arithmetic: plain sums, rescaled out of range).
inline double norm2_all(MPI_Comm comm, const double *x, int64_t n) {
    double s = 0.0;
    for (int64_t i = 0; i < n; ++i) s += x[i] * x[i];
    reduce_all(comm, &s, 1, "s");
    if (in_safe_range(s)) return std::sqrt(s);
    double a = max_abs(x, n);
    reduce_all(comm, &a, 1, "m");
    if (a == 0.0) return 0.0;
    s = 0.0;
    for (int64_t i = 0; i < n; ++i) s += (x[i] / a) * (x[i] / a);
    reduce_all(comm, &s, 1, "s");
    return a * std::sqrt(s);
}

// frix::Agree over the ranks of comm: a flag raised on any of them.
inline Agree over_ranks(MPI_Comm comm) {
    return [comm](bool flag) { return or_all(comm, flag ? 1u : 0u) != 0; };
}

// measures_from_parts' rescue over the ranks' contacts.
class RanksRescue : public MeasureRescue {
   public:
    RanksRescue(MPI_Comm comm, const double *r, const double *u, const double *mu, int64_t nc)
        : comm_(comm), r_(r), u_(u), mu_(mu), nc_(nc) {}
    double max_abs_ru() override {
        double a = std::max(max_abs(r_, 3 * nc_), max_abs(u_, 3 * nc_));
        reduce_all(comm_, &a, 1, "m");
        return a;
    }
    void residual(double divisor, double &sum, double &cone) override {
        double both[2];
        rescaled_residual(r_, u_, mu_, 0, nc_, divisor, both[0], both[1]);
        reduce_all(comm_, both, 2, "sm");
        sum = both[0];
        cone = both[1];
    }
    double norm_r() override { return norm2_all(comm_, r_, 3 * nc_); }
    double norm_u() override { return norm2_all(comm_, u_, 3 * nc_); }

   private:
    MPI_Comm comm_;
    const double *r_, *u_, *mu_;
    int64_t nc_;
};

// The measures of the ranks' (r, u) (nc contacts on this rank) over all contacts, combined in
// a fixed order; norm_q: the norm over all contacts of the relative error's scale, free the
// scaled measure's floor over all contacts (measures_from_ru; negative: norm_q).
inline Measures measures_over_ranks(MPI_Comm comm, const double *r, const double *u, const double *mu,
                                    const std::vector<double> &weight, int64_t nc, double norm_q,
                                    double free = -1.0) {
    const MeasureParts mine = measure_parts(r, u, mu, weight.empty() ? nullptr : weight.data(), 0, nc);
    double all[7] = {mine.residual_sq, mine.cone,      mine.penetration,  mine.complementarity,
                     mine.r_sq,        mine.u_sq,      mine.scaled_scale};
    reduce_all(comm, all, 7, "smmmssm");
    MeasureParts total;
    total.residual_sq = all[0], total.cone = all[1], total.penetration = all[2];
    total.complementarity = all[3], total.r_sq = all[4], total.u_sq = all[5];
    // The scaled residual's squares, each rank's on the largest scale: then a plain sum.
    total.scaled_scale = all[6];
    double ssq = all[6] > 0.0 ? mine.scaled_ssq * (mine.scaled_scale / all[6]) * (mine.scaled_scale / all[6]) : 0.0;
    reduce_all(comm, &ssq, 1, "s");
    total.scaled_ssq = all[6] > 0.0 ? ssq : 1.0;
    RanksRescue rescue(comm, r, u, mu, nc);
    return measures_from_parts(total, rescue, norm_q, free);
}

// The sweep over the ranks and its measures; r holds the owned reactions, then the ghosts'.
// The forms differ in how a contact reads its local q and what a changed reaction updates:
// W's rows (DistributedRows) or the bodies' velocities (DistributedBodies).
class DistributedForm : public nsgs::SweepForm {
   public:
    bool restores() const override { return false; }
    explicit DistributedForm(const frix_mpi_problem &p)
        : p_(p), comm_(p.ctx->comm), norm_q_(norm2_all(comm_, p.scale(), 3 * p.owned)) {
        const size_t n = p.neighbours.size();
        send_buffer_.resize(3 * p.send.size());
        ghost_in_.resize(3 * p.ghosts.size());
        requests_.reserve(2 * n);
        for (size_t k = 0; k < n; ++k) (p.neighbour_colour[k] < p.colour ? lower_ : higher_).push_back(k);
    }

    nsgs::SweepStats sweep(nsgs::Workspace &ws, double *r, double *) override {
        requests_.clear();
        receive(lower_);
        const std::vector<int64_t> &b = p_.boundary, &in = p_.interior;
        nsgs::SweepStats st;
        if (p_.colour == 0) {
            st = sweep_part(ws, r, b.data(), (int64_t)b.size());
            send_all(r);
            receive(higher_);
            st.add(sweep_part(ws, r, in.data(), (int64_t)in.size()));
            wait();  // (colour 0 has no lower neighbour)
            take(higher_, r);
        } else {
            st = sweep_part(ws, r, in.data(), (int64_t)in.size());
            wait();
            take(lower_, r);
            st.add(sweep_part(ws, r, b.data(), (int64_t)b.size()));
            send_all(r);
            receive(higher_);
            wait();
            take(higher_, r);
        }
        // The sweep's statistics over the ranks (the counts are exact as doubles).
        double all[5] = {st.dr2, st.r2, (double)st.rejected, (double)st.unsolved, (double)st.frozen};
        reduce_all(comm_, all, 5, "sssss");
        nsgs::SweepStats total;
        total.dr2 = all[0], total.r2 = all[1];
        total.rejected = (int64_t)all[2], total.unsolved = (int64_t)all[3], total.frozen = (int64_t)all[4];
        return total;
    }

    unsigned agree(unsigned flags) override { return or_all(comm_, flags); }
    int64_t all_contacts(int64_t) const override { return p_.total; }
    // The free velocity's norm over all contacts (Measures::norm_free of combine()): what the
    // runaway bound scales with, as the serial problem's.
    double norm_free() const { return p_.free >= 0.0 ? p_.free : norm_q_; }

    // Every ghost from its owner: at the start, and after r changed outside a sweep.
    void exchange(double *r) {
        requests_.clear();
        std::vector<size_t> all(p_.neighbours.size());
        for (size_t k = 0; k < all.size(); ++k) all[k] = k;
        receive(all);
        send_all(r);
        wait();
        take(all, r);
    }

   protected:
    // Sweeps contacts[0 .. count) of this rank.
    virtual nsgs::SweepStats sweep_part(nsgs::Workspace &ws, double *r, const int64_t *contacts, int64_t count) = 0;
    // Ghost g's reaction is now r_new (3 values): r's ghost slot, and what the form keeps.
    virtual void take_ghost(int64_t g, const double *r_new, double *r) {
        std::copy(r_new, r_new + 3, r + 3 * (p_.owned + g));
    }
    // The measures of this rank's (r, u), combined over the ranks.
    Measures combine(const double *r, const double *u) {
        return measures_over_ranks(comm_, r, u, p_.mu.data(), p_.view.weight, p_.owned, norm_q_, p_.free);
    }

    const frix_mpi_problem &p_;

   private:
    // Receives the ghosts of the neighbours listed (indices into p.neighbours).
    void receive(const std::vector<size_t> &which) {
        for (const size_t k : which) {
            const int64_t from = p_.recv_ptr[k], to = p_.recv_ptr[k + 1];
            if (to == from) continue;
            requests_.emplace_back();
            check(MPI_Irecv(ghost_in_.data() + 3 * from, (int)(3 * (to - from)), MPI_DOUBLE, p_.neighbours[k], kTag,
                            comm_, &requests_.back()),
                  "MPI_Irecv");
        }
    }
    // Hands the received ghosts of the neighbours listed to the form.
    void take(const std::vector<size_t> &which, double *r) {
        for (const size_t k : which)
            for (int64_t g = p_.recv_ptr[k]; g < p_.recv_ptr[k + 1]; ++g) take_ghost(g, &ghost_in_[3 * (size_t)g], r);
    }
    void wait() {
        check(MPI_Waitall((int)requests_.size(), requests_.data(), MPI_STATUSES_IGNORE), "MPI_Waitall");
        requests_.clear();
    }
    // Sends each neighbour the owned reactions it needs.
    void send_all(const double *r) {
        for (size_t k = 0; k < p_.neighbours.size(); ++k) {
            const int64_t from = p_.send_ptr[k], to = p_.send_ptr[k + 1];
            if (to == from) continue;
            double *buffer = send_buffer_.data() + 3 * from;
            for (int64_t e = from; e < to; ++e)
                for (int i = 0; i < 3; ++i) buffer[3 * (e - from) + i] = r[3 * p_.send[(size_t)e] + i];
            requests_.emplace_back();
            check(MPI_Isend(buffer, (int)(3 * (to - from)), MPI_DOUBLE, p_.neighbours[k], kTag, comm_,
                            &requests_.back()),
                  "MPI_Isend");
        }
    }

    MPI_Comm comm_;
    double norm_q_;
    std::vector<double> send_buffer_, ghost_in_;
    std::vector<MPI_Request> requests_;
    std::vector<size_t> lower_, higher_;  // neighbours of lower and higher colours
};

// W's block rows: contact a's local q is q_a + sum_{b != a} W_ab r_b, ghosts included.
class DistributedRows : public DistributedForm {
   public:
    using DistributedForm::DistributedForm;
    Measures exact(const double *r, double *u) override {
        if (p_.owned > 0) {
            matrix_gemv(p_.W, 1.0, r, 0.0, u);
            for (int64_t i = 0; i < 3 * p_.owned; ++i) u[i] += p_.q[(size_t)i];
        }
        return combine(r, u);
    }

   protected:
    nsgs::SweepStats sweep_part(nsgs::Workspace &ws, double *r, const int64_t *contacts, int64_t count) override {
        return ws.sweep_part(r, contacts, count);
    }
};

// Rigid bodies: v = M^-1 (H r + f) kept for the bodies held; contact a reads
// u_a = sum_s G_as v_s + w_a, and a change of r_a (or of a ghost's) adds M^-1 G_as^T dr to its
// bodies' v. The measures are global_measures' of (r, v), equilibrium included.
class DistributedBodies : public DistributedForm {
   public:
    explicit DistributedBodies(frix_mpi_problem &p) : DistributedForm(p), v_(p.v0) {
        std::vector<double> f, df;
        for (size_t b = 0, i = 0; b < p.kept.size(); ++b)
            for (int j = 0; j < 6 && p.kept[b]; ++j, ++i) {
                f.push_back(p.body_f[6 * b + (size_t)j]);
                df.push_back(p.dof_weight[i] * f.back());
            }
        norm_f_ = norm2_all(p.ctx->comm, f.data(), (int64_t)f.size());
        norm_df_ = norm2_all(p.ctx->comm, df.data(), (int64_t)df.size());
    }
    Measures exact(const double *r, double *u) override {
        restart(r, u);
        for (int64_t a = 0; a < p_.owned; ++a) velocity(a, u + 3 * a);
        Measures m = combine(r, u);
        equilibrium(r, m);
        return m;
    }
    // v = M^-1 f + M^-1 H r over the held contacts (owned and ghosts).
    void restart(const double *r, double *) override {
        std::copy(p_.v0.begin(), p_.v0.end(), v_.begin());
        const int64_t contacts = p_.owned + (int64_t)p_.ghosts.size();
        for (int64_t c = 0; c < contacts; ++c) {
            const double *rc = r + 3 * c;
            if (rc[0] != 0.0 || rc[1] != 0.0 || rc[2] != 0.0) push(c, rc);
        }
    }
    const std::vector<double> &velocities() const { return v_; }
    // u of owned contact c at r = 0 (v = M^-1 f).
    void free_velocity(int64_t c, double *u) const { velocity(c, u, p_.v0); }

   protected:
    nsgs::SweepStats sweep_part(nsgs::Workspace &ws, double *r, const int64_t *contacts, int64_t count) override {
        const auto local_q = [this, r](int64_t a, const local::Contact &c, double *ql) {
            const double *Wd = c.W, *ra = r + 3 * a;
            double u[3];
            velocity(a, u);
            for (int e = 0; e < 3; ++e) ql[e] = u[e] - (Wd[e] * ra[0] + Wd[e + 3] * ra[1] + Wd[e + 6] * ra[2]);
        };
        return ws.sweep_part(r, contacts, count, local_q, [this](int64_t a, const double *dr) { push(a, dr); });
    }
    void take_ghost(int64_t g, const double *r_new, double *r) override {
        double *rg = r + 3 * (p_.owned + g);
        const double d[3] = {r_new[0] - rg[0], r_new[1] - rg[1], r_new[2] - rg[2]};
        if (d[0] != 0.0 || d[1] != 0.0 || d[2] != 0.0) push(p_.owned + g, d);
        std::copy(r_new, r_new + 3, rg);
    }

   private:
    // global_measures' equilibrium residuals of (r, v) (d = M v - H r - f: rounding), over the
    // bodies each rank keeps, H r from every held contact on them.
    void equilibrium(const double *r, Measures &m) {
        const size_t held = p_.kept.size(), contacts = (size_t)p_.owned + p_.ghosts.size();
        hr_.assign(6 * held, 0.0);
        for (size_t c = 0; c < contacts; ++c)
            for (int s = 0; s < 2; ++s) {
                const int64_t slot = p_.side_slot[2 * c + s];
                if (slot < 0 || !p_.kept[(size_t)slot]) continue;
                const double *g = &p_.G[36 * c + 18 * s], *rc = r + 3 * c;
                for (int j = 0; j < 6; ++j)
                    hr_[6 * (size_t)slot + j] += g[j] * rc[0] + g[6 + j] * rc[1] + g[12 + j] * rc[2];
            }
        std::vector<double> parts[5];  // d, M v, H r, D d, D H r over the kept dofs
        for (size_t b = 0, i = 0; b < held; ++b)
            for (int j = 0; j < 6 && p_.kept[b]; ++j, ++i) {
                double mv = 0.0;
                for (int k = 0; k < 6; ++k) mv += p_.mass[36 * b + 6 * (size_t)k + j] * v_[6 * b + (size_t)k];
                const double hr = hr_[6 * b + (size_t)j], d = mv - hr - p_.body_f[6 * b + (size_t)j];
                const double x[5] = {d, mv, hr, p_.dof_weight[i] * d, p_.dof_weight[i] * hr};
                for (int e = 0; e < 5; ++e) parts[e].push_back(x[e]);
            }
        double norms[5];
        for (int e = 0; e < 5; ++e) norms[e] = norm2_all(p_.ctx->comm, parts[e].data(), (int64_t)parts[e].size());
        m.global = true;
        m.equilibrium = relative_equilibrium(norms[0], norm_f_, norms[1], norms[2]);
        m.equilibrium_scaled = scaled_equilibrium(norms[3], norm_df_, norms[4]);
    }
    // u = sum_s G_cs v_s + w_c of owned contact c.
    void velocity(int64_t c, double *u) const { velocity(c, u, v_); }
    void velocity(int64_t c, double *u, const std::vector<double> &velocities) const {
        for (int k = 0; k < 3; ++k) u[k] = p_.w[3 * (size_t)c + k];
        for (int s = 0; s < 2; ++s) {
            const int64_t slot = p_.side_slot[2 * (size_t)c + s];
            if (slot < 0) continue;
            const double *g = &p_.G[36 * (size_t)c + 18 * s], *v = &velocities[6 * (size_t)slot];
            for (int k = 0; k < 3; ++k)
                for (int j = 0; j < 6; ++j) u[k] += g[6 * k + j] * v[j];
        }
    }
    // v += M^-1 G_cs^T dr on each side of held contact c.
    void push(int64_t c, const double *dr) {
        for (int s = 0; s < 2; ++s) {
            const int64_t slot = p_.side_slot[2 * (size_t)c + s];
            if (slot < 0) continue;
            const double *mg = &p_.mg[36 * (size_t)c + 18 * s];
            double *v = &v_[6 * (size_t)slot];
            for (int i = 0; i < 6; ++i) v[i] += mg[i] * dr[0] + mg[i + 6] * dr[1] + mg[i + 12] * dr[2];
        }
    }

    std::vector<double> v_, hr_;
    double norm_f_ = 0.0, norm_df_ = 0.0;  // |f| and |D f| over the kept bodies
};

// The default measure's weights of a global problem with the host's M, over the ranks
// (distributed_weights.cpp): what set_contact_weights and free_velocity give the whole
// problem, so that a distributed answer measures as frix_problem_measure measures it.
struct RanksWeights {
    std::vector<double> contact;  // the owned contacts' w_a (frix_problem::weight)
    std::vector<double> dof;      // the owned dofs' 1 / sqrt(M_ii) (frix_problem::dof_weight)
    double free = 0.0;            // free_velocity over all contacts
};
// Collective.
RanksWeights ranks_weights(const frix_mpi_problem &p);
// This rank's contacts of a global problem with the host's M (nc = owned, n = its dofs, mu, w),
// weighed as the whole problem weighs them (weights.contact): what the serial rules on a
// runaway (Monitor, fall_back_on_divergence) read of this rank's part.
frix_problem watched_contacts(const frix_mpi_problem &p, const RanksWeights &weights);
// RanksWeights from this rank's parts (whatever holds the problem): the owned contacts' w_a and
// the dofs' 1 / sqrt(M_ii) before their fill, f and whether load_velocity counts each dof,
// w and H^T D^-1 f + w of the owned contacts; total: the contacts of all ranks. Collective.
RanksWeights finish_weights(MPI_Comm comm, int64_t total, std::vector<double> contact, std::vector<double> dof,
                            const std::vector<double> &f, const std::vector<char> &load, const std::vector<double> &w,
                            const std::vector<double> &jacobi);

// The distributed global Newton (distributed_global_newton.cpp) on a global problem with the
// host's M, from r (this rank's reactions, finite), watched for a runaway as the serial
// native route is, with the driver's fallback of a diverged run (to warm_start,
// finite_warm_start of r); u receives H^T v + w, p.v the owned dofs' v; info gets status,
// iterations, the measures and the equilibrium residual.
frix_error run_global_newton(frix_mpi_problem &p, const frix_options &o, const std::vector<double> &warm_start,
                             double *r, double *u, frix_info &info, const Stopwatch &clock);

// The distributed Newton (distributed_newton.cpp) on a local problem, from ctx.r (owned then
// ghost reactions, the ghosts current; ctx.problem: p.view), watched for a runaway past
// ctx.runaway_bound; ctx.u receives W r + q; ctx.info gets status and iterations.
frix_error run_newton(frix_mpi_problem &p, SolveContext &ctx, DistributedForm &form);

}  // namespace mpi
}  // namespace frix
