#include "solvers/kit/sweeps.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <thread>
#include <utility>

#include "src/coulomb.hpp"
#include "src/error_state.hpp"
#include "src/log.hpp"
#include "src/matrix.hpp"
#include "src/measures.hpp"
#include "src/monitor.hpp"
#include "src/random.hpp"
#include "solvers/entries.hpp"

namespace frix {
namespace nsgs {

namespace {

void shuffle(std::vector<int64_t> &order, uint64_t &state) {
    for (size_t i = order.size(); i > 1; --i) {
        const size_t j = (size_t)(next_random(state) % i);
        std::swap(order[i - 1], order[j]);
    }
}

// Contact a's local q in the velocity sweeps: q_a + sum_{b != a} W_ab r_b = u_a - W_aa r_a.
inline void velocity_local_q(int64_t a, const local::Contact &c, const double *r, const double *u, double *ql) {
    const double *Wd = c.W, *ra = r + 3 * a;
    ql[0] = u[3 * a] - (Wd[0] * ra[0] + Wd[3] * ra[1] + Wd[6] * ra[2]);
    ql[1] = u[3 * a + 1] - (Wd[1] * ra[0] + Wd[4] * ra[1] + Wd[7] * ra[2]);
    ql[2] = u[3 * a + 2] - (Wd[2] * ra[0] + Wd[5] * ra[1] + Wd[8] * ra[2]);
}

inline bool finite3(const double *x) {
    return std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2]);
}

}  // namespace

Workspace::Workspace(const frix_problem &p, const Settings &s)
    : W_(p.W), q_(p.q), s_(s), contacts_((size_t)p.nc), rng_(s.seed) {
    for (int64_t a = 0; a < p.nc; ++a) {
        const int64_t d = W_->diag_index[a];
        static const double kZero[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
        local::contact_setup(d >= 0 ? &W_->block_val[9 * d] : kZero, p.mu[a], contacts_[a]);
    }
    order_and_freezing(p.nc);
}

Workspace::Workspace(const double *diagonal_blocks, const double *mu, int64_t nc, const Settings &s)
    : W_(nullptr), q_(nullptr), s_(s), contacts_((size_t)nc), rng_(s.seed) {
    for (int64_t a = 0; a < nc; ++a) local::contact_setup(diagonal_blocks + 9 * a, mu[a], contacts_[a]);
    order_and_freezing(nc);
}

void Workspace::order_and_freezing(int64_t nc) {
    if (s_.shuffle != FRIX_SHUFFLE_NONE) {
        order_.resize((size_t)nc);
        for (int64_t a = 0; a < nc; ++a) order_[a] = a;
        if (s_.shuffle == FRIX_SHUFFLE_ONCE) shuffle(order_, rng_);
    }
    if (s_.freezing > 0) frozen_.assign((size_t)nc, 0);
}

void Workspace::reshuffle() { shuffle(order_, rng_); }

void Workspace::thaw() { std::fill(frozen_.begin(), frozen_.end(), 0); }

Settings settings_from(const frix_options &o) {
    Settings s;
    s.local.solver = (int)o.i(FRIX_OPT_LOCAL_SOLVER);
    s.local.tol = o.d(FRIX_OPT_LOCAL_TOLERANCE);
    s.local.max_iter = (int)o.i(FRIX_OPT_LOCAL_MAX_ITER);
    s.relaxation = o.d(FRIX_OPT_RELAXATION);
    s.shuffle = (int)o.i(FRIX_OPT_SHUFFLE);
    s.seed = (uint64_t)o.i(FRIX_OPT_SEED);
    s.freezing = o.i(FRIX_OPT_FREEZING);
    return s;
}

bool Workspace::accept(int64_t a, double *ra, double *rn, double &dr2_out) {
    const double omega = s_.relaxation;
    if (omega != 1.0) {
        for (int i = 0; i < 3; ++i) rn[i] = omega * rn[i] + (1.0 - omega) * ra[i];
        if (omega > 1.0) coulomb::project_on_cone(rn, contacts_[(size_t)a].mu);
    }
    if (!finite3(rn)) return false;
    const double d0 = rn[0] - ra[0], d1 = rn[1] - ra[1], d2 = rn[2] - ra[2];
    const double dr2 = d0 * d0 + d1 * d1 + d2 * d2;
    dr2_out = dr2;
    if (!frozen_.empty() && dr2 <= freeze_dr2_) frozen_[(size_t)a] = s_.freezing;
    ra[0] = rn[0];
    ra[1] = rn[1];
    ra[2] = rn[2];
    return true;
}

SweepStats Workspace::sweep(double *r) {
    const local::Params lp = s_.local;
    return sweep_with(r, [&lp](int64_t, local::Contact &c, const double *ql, double *rn) {
        return local::solve_contact(c, ql, rn, lp);
    });
}

SweepStats Workspace::sweep_part(double *r, const int64_t *contacts, int64_t count) {
    return sweep_part(
        r, contacts, count, [this, r](int64_t a, const local::Contact &, double *ql) { local_q(a, r, ql); },
        [](int64_t, const double *) {});
}

void Workspace::build_columns() {
    const int64_t nc = (int64_t)contacts_.size();
    const int64_t nb = W_->nblocks();
    col_ptr_.assign((size_t)nc + 1, 0);
    for (int64_t b = 0; b < nb; ++b) ++col_ptr_[(size_t)W_->block_col[b] + 1];
    for (int64_t a = 0; a < nc; ++a) col_ptr_[a + 1] += col_ptr_[a];
    col_row_.resize((size_t)nb);
    col_block_.resize((size_t)nb);
    std::vector<int64_t> next(col_ptr_.begin(), col_ptr_.end() - 1);
    for (int64_t row = 0; row < nc; ++row)
        for (int64_t b = W_->row_ptr[row]; b < W_->row_ptr[row + 1]; ++b) {
            const int64_t k = next[(size_t)W_->block_col[b]]++;
            col_row_[k] = row;
            col_block_[k] = b;
        }
}

void Workspace::push_through(const SingleColumns *columns, ThreadTeam *team) {
    single_ = columns;
    team_ = columns && team && team->size() > 1 && team->size() == columns->panels() ? team : nullptr;
    if (!team_) return;
    published_.reset(new PublishedChange[contacts_.size()]);
    contact_stats_.assign(contacts_.size(), SweepStats());
}

SweepStats Workspace::sweep_velocity(double *r, double *u) {
    if (team_) return sweep_velocity_pipelined(r, u);
    const local::Params lp = s_.local;
    const auto local_q = [r, u](int64_t a, const local::Contact &c, double *ql) { velocity_local_q(a, c, r, u, ql); };
    const auto step = [&lp](int64_t, local::Contact &c, const double *ql, double *rn) {
        return local::solve_contact(c, ql, rn, lp);
    };
    return sweep_loop(r, local_q, step, [this, u](int64_t a, const double *dr) { push_velocity(a, dr, u); });
}

SweepStats Workspace::sweep_velocity_pipelined(double *r, double *u) {
    if (s_.shuffle == FRIX_SHUFFLE_EACH_SWEEP) reshuffle();
    const int64_t nc = (int64_t)contacts_.size(), sweep = pipelined_sweeps_++;
    const int64_t *order = order_.empty() ? nullptr : order_.data();
    int64_t *frozen = frozen_.empty() ? nullptr : frozen_.data();
    const local::Params lp = s_.local;
    const auto step = [&lp](int64_t, local::Contact &c, const double *ql, double *rn) {
        return local::solve_contact(c, ql, rn, lp);
    };
    const auto local_q = [r, u](int64_t a, const local::Contact &c, double *ql) { velocity_local_q(a, c, r, u, ql); };
    team_->for_each_thread([&](int64_t t) {
        const int64_t first = single_->panel_begin(t), end = single_->panel_begin(t + 1);
        for (int64_t k = 0; k < nc; ++k) {
            const int64_t a = order ? order[k] : k;
            PublishedChange &change = published_[a];
            if (a >= first && a < end) {
                SweepStats st;
                change.moved = false;
                auto publish = [&change](int64_t, const double *dr) {
                    change.moved = true;
                    change.dr[0] = dr[0], change.dr[1] = dr[1], change.dr[2] = dr[2];
                };
                sweep_contact(a, r, frozen, local_q, step, publish, st);
                contact_stats_[(size_t)a] = st;
                change.sweep.store(sweep, std::memory_order_release);
            } else {
                // A short spin, then the core is offered to others: with more threads than
                // free cores the owner may be waiting for this one's core.
                for (int spins = 0; change.sweep.load(std::memory_order_acquire) != sweep; ++spins)
                    if (spins >= 256) std::this_thread::yield();
            }
            if (change.moved) single_->push_panel(t, a, change.dr, u);
        }
    });
    SweepStats st;
    for (int64_t k = 0; k < nc; ++k) {
        const SweepStats &c = contact_stats_[(size_t)(order ? order[k] : k)];
        st.dr2 += c.dr2;
        st.r2 += c.r2;
        st.rejected += c.rejected, st.unsolved += c.unsolved, st.frozen += c.frozen;
    }
    return st;
}

void Workspace::push_velocity(int64_t a, const double *dr, double *u) {
    if (single_) {
        single_->push(a, dr, u);
        return;
    }
    // A symmetric W's column a is its row a transposed: read in order, in place of the column
    // index (whose blocks lie a row apart in memory).
    const double *val = W_->block_val.data();
    if (W_->symmetric) {
        for (int64_t e = W_->row_ptr[a]; e < W_->row_ptr[a + 1]; ++e)
            block_gemv_transposed_add(val + 9 * e, dr, u + 3 * W_->block_col[e]);
        return;
    }
    if (col_ptr_.empty()) build_columns();
    for (int64_t e = col_ptr_[a]; e < col_ptr_[a + 1]; ++e) block_gemv_add(val + 9 * col_block_[e], dr, u + 3 * col_row_[e]);
}

namespace {

// W's block rows (nsgs): the local q from each row; nothing kept between sweeps.
class RowForm : public SweepForm {
   public:
    explicit RowForm(const frix_problem &p) : p_(p) {}
    SweepStats sweep(Workspace &ws, double *r, double *) override { return ws.sweep(r); }
    Measures exact(const double *r, double *u) override { return local_measures(p_, r, u); }
    AffineState affine_state(double *) override { return {nullptr, 0, true}; }

   private:
    const frix_problem &p_;
};

// W's block columns (nsgs-v): u = W r + q kept up to date by each change of r.
// With single-precision columns (single), the kept u drifts from W r + q by the single
// rounding of the changes since it was last computed afresh; so every full check computes
// it afresh from the double W (exact(); the first, one sweep in, only where kept_drifting()
// does not show an error far above the tolerance), which bounds the drift by the changes between two
// full checks (at most kFullCheckPeriod light-error tests, sweeps.cpp) and leaves every
// verdict to the double W. Near the end those
// changes, and the drift with them, shrink with the error: the sweeps do not stall short of
// a tight tolerance.
class VelocityForm : public SweepForm {
   public:
    // team: the threads of the pipelined sweeps (null: one), which also share u's afresh
    // computation by block rows.
    VelocityForm(const frix_problem &p, bool single, ThreadTeam *team)
        : p_(p), norm_q_(norm2(p.q, 3 * p.nc)), single_(single), team_(team) {}
    SweepStats sweep(Workspace &ws, double *r, double *u) override { return ws.sweep_velocity(r, u); }
    Measures exact(const double *r, double *u) override {
        if (!team_) return local_measures(p_, r, u);
        restart(r, u);
        return measures_from_ru(r, u, p_.mu, p_.weight.data(), p_.nc, norm_q_);
    }
    bool kept(const double *r, double *u, Measures &m) override {
        if (single_) return false;
        return kept_drifting(r, u, m);
    }
    bool kept_drifting(const double *r, double *u, Measures &m) override {
        m = measures_from_ru(r, u, p_.mu, p_.weight.data(), p_.nc, norm_q_);
        return true;
    }
    void restart(const double *r, double *u) override {
        if (!team_) {
            matrix_gemv(*p_.W, 1.0, r, 0.0, u);
            for (int64_t i = 0; i < 3 * p_.nc; ++i) u[i] += p_.q[i];
            return;
        }
        // matrix_gemv's block rows shared among the threads, then q: the same arithmetic.
        team_->for_chunks(p_.W->block_rows, kProductRows, [&](int64_t begin, int64_t end) {
            matrix_gemv_block_rows(*p_.W, 1.0, r, 0.0, u, begin, end);
            for (int64_t i = 3 * begin; i < 3 * end; ++i) u[i] += p_.q[i];
        });
    }
    AffineState affine_state(double *u) override { return {u, 3 * (size_t)p_.nc, true}; }
    void push_change(Workspace &ws, int64_t a, const double *d, double *u) override { ws.push_velocity(a, d, u); }
    bool state_drifts() const override { return single_; }

   private:
    // Block rows a chunk of the threaded product: a dense W's 64 rows are megabytes.
    static constexpr int64_t kProductRows = 64;
    const frix_problem &p_;
    double norm_q_;
    const bool single_;
    ThreadTeam *team_;
};

frix_error check_blocks(const frix_problem &p, const char *name) {
    if (!p.W || !p.W->block) return fail(FRIX_ERR_INTERNAL, "%s: W is not stored as 3x3 blocks", name);
    return FRIX_OK;
}

frix_error solve(SolveContext &ctx) {
    if (frix_error e = check_blocks(ctx.problem, "nsgs")) return e;
    Workspace ws(ctx.problem, settings_from(ctx.options));
    RowForm rows(ctx.problem);
    return run_sweeps(ctx, ws, rows, "nsgs");
}

// The single-precision columns of a large dense W (where the memory limit leaves room for
// them), kept by a persistent solver while W's values stay; null where W does not suit.
std::unique_ptr<Kept<SingleColumns>> single_columns(SolveContext &ctx, double min_bytes, int64_t panels) {
    const frix_matrix &W = *ctx.problem.W;
    if (!SingleColumns::suits(W, min_bytes) || !Monitor(ctx).fits_memory(SingleColumns::bytes_for(W))) return nullptr;
    auto columns = std::make_unique<Kept<SingleColumns>>(ctx.cache, FRIX_SOLVER_NSGS_VELOCITY);
    const uint64_t values = ctx.cache ? ctx.cache->w_values : 0, pattern = ctx.cache ? ctx.cache->w_pattern : 0;
    const bool reused = (**columns).holds(W, values, pattern, panels);
    const Stopwatch build;
    if (!reused) (**columns).build(W, values, pattern, panels);
    if (ctx.options.i(FRIX_OPT_VERBOSITY) >= 1) {
        char how[64];
        snprintf(how, sizeof how, reused ? "kept" : "built in %.3g s", build.seconds());
        log_line(&ctx.options, "nsgs-v: pushes through W's columns in single precision (%.0f MB, %s), on %lld thread%s",
                 SingleColumns::bytes_for(W) / 1e6, how, (long long)(**columns).panels(),
                 (**columns).panels() > 1 ? "s" : "");
    }
    return columns;
}

frix_error solve_velocity(SolveContext &ctx) { return solve_velocity_at(ctx, kSingleColumnsMinBytes); }

}  // namespace

frix_error run_velocity_sweeps(SolveContext &ctx, const SingleColumns *columns, const char *name) {
    Workspace ws(ctx.problem, settings_from(ctx.options));
    // The pipelined sweeps' threads: one a panel of the single-precision columns.
    std::unique_ptr<ThreadTeam> team;
    if (columns && columns->panels() > 1) team = std::make_unique<ThreadTeam>((int)columns->panels());
    if (columns) ws.push_through(columns, team.get());
    VelocityForm form(ctx.problem, columns != nullptr, team.get());
    return run_sweeps(ctx, ws, form, name);
}

frix_error solve_velocity_at(SolveContext &ctx, double single_min_bytes) {
    if (frix_error e = check_blocks(ctx.problem, "nsgs-v")) return e;
    int64_t part_sweeps = 0;
    frix_status part_status = FRIX_STATUS_NOT_RUN;
    Measures start;  // the warm start's, where the part measured it
    const Measures *given = ctx.measured_start;
    const bool part_ran = sweep_active_part(ctx, single_min_bytes, start, &part_sweeps, &part_status);
    if (part_ran && part_status != FRIX_STATUS_CONVERGED) {
        // Stopped, out of sweeps or time, or diverged: the driver measures r on the whole problem.
        ctx.info.status = part_status;
        ctx.info.iterations = part_sweeps;
        ctx.has_measured = false;
        ctx.measured_start = nullptr;
        return FRIX_OK;
    }
    // The whole problem's run goes on with the sweeps the part left, its reports numbered on.
    ForwardedReports after{&ctx.options, &ctx.clock, part_sweeps, false};
    frix_options rest = part_sweeps > 0 ? after.applied_to(ctx.options) : ctx.options;
    rest.ivalue[FRIX_OPT_MAX_ITER] = std::max<int64_t>(1, ctx.options.i(FRIX_OPT_MAX_ITER) - part_sweeps);
    // (global(): the named constructor that carries v and M's factorisation over.)
    SolveContext run = SolveContext::global(ctx.problem, rest, ctx.r, ctx.u, ctx.v, ctx.info, ctx.clock, ctx.mass)
                           .with_cache(ctx.cache);
    run.measured_start = ctx.measured_start;
    run.runaway_bound = ctx.runaway_bound;
    run.mass_shifted = ctx.mass_shifted;
    run.return_best = ctx.return_best;
    run.factor_mass = ctx.factor_mass;
    const std::unique_ptr<Kept<SingleColumns>> single =
        single_columns(run, single_min_bytes, ctx.options.i(FRIX_OPT_THREADS));
    const frix_error e = run_velocity_sweeps(run, single ? &**single : nullptr, "nsgs-v");
    ctx.has_measured = run.has_measured;
    ctx.measured = run.measured;
    ctx.measured_start = part_ran ? nullptr : given;  // never `start`, which ends here
    ctx.info.iterations += part_sweeps;
    if (single && !e) single->keep();
    return e;
}

namespace {

// The sweep limit covers the slowest FCLIB problems that NSGS solves at 1e-8 (Capsules:
// ~8000 sweeps).
const OptionDefault kDefaults[] = {
    {FRIX_OPT_MAX_ITER, 20000},
    {FRIX_OPT_LOCAL_SOLVER, local::kClosedForm},
    {FRIX_OPT_LOCAL_TOLERANCE, 1e-12},
    {FRIX_OPT_LOCAL_MAX_ITER, 20},
    {FRIX_OPT_ACCELERATION, 0},
    {(frix_option_key)0, 0}};

}  // namespace

const frix_option_key kExtraKeys[] = {FRIX_OPT_LOCAL_SOLVER,   FRIX_OPT_LOCAL_TOLERANCE, FRIX_OPT_LOCAL_MAX_ITER,
                                      FRIX_OPT_RELAXATION,     FRIX_OPT_SHUFFLE,         FRIX_OPT_SEED,
                                      FRIX_OPT_FREEZING,       FRIX_OPT_ERROR_FREQUENCY, FRIX_OPT_DRIFT_WINDOW,
                                      FRIX_OPT_ACCELERATION,   FRIX_OPT_ANDERSON,        (frix_option_key)0};

// nsgs-v: those of nsgs, and threads for its pipelined sweeps on a dense W.
const frix_option_key kVelocityKeys[] = {FRIX_OPT_LOCAL_SOLVER,   FRIX_OPT_LOCAL_TOLERANCE, FRIX_OPT_LOCAL_MAX_ITER,
                                         FRIX_OPT_RELAXATION,     FRIX_OPT_SHUFFLE,         FRIX_OPT_SEED,
                                         FRIX_OPT_FREEZING,       FRIX_OPT_ERROR_FREQUENCY, FRIX_OPT_DRIFT_WINDOW,
                                         FRIX_OPT_ACCELERATION,   FRIX_OPT_ANDERSON,        FRIX_OPT_THREADS,
                                         (frix_option_key)0};

// nsgs-v: freezing on by default; skipped contacts cost it nothing at all.
const OptionDefault kVelocityDefaults[] = {
    {FRIX_OPT_MAX_ITER, 20000},
    {FRIX_OPT_LOCAL_SOLVER, local::kClosedForm},
    {FRIX_OPT_LOCAL_TOLERANCE, 1e-12},
    {FRIX_OPT_LOCAL_MAX_ITER, 20},
    {FRIX_OPT_FREEZING, 10},
    {FRIX_OPT_ACCELERATION, 0},
    {(frix_option_key)0, 0}};

}  // namespace nsgs

const SolverEntry kNsgsEntry = {
    FRIX_SOLVER_NSGS,
    "nsgs",
    "FRICTION_3D_NSGS",
    "Nonsmooth Gauss-Seidel: sweeps over the contacts, each solved with the others held "
    "fixed (local q = q_a + sum_{b!=a} W_ab r_b, one pass over W's blocks per sweep). The "
    "default one-contact solver (562) is exact for take-off, stick and, through the root "
    "of the sliding-angle equation, slide; projected steps with a self-adaptive step finish "
    "the rare contacts where that fails (553: those projected steps alone, after the exact "
    "take-off and stick cases; 552: one projected step only). Convergence is linear. Stops on the "
    "light error |dr|/|r| "
    "confirmed by the full error (Siconos LIGHT_WITH_FULL_FINAL); the first test and every "
    "16th are full checks. Options: local_solver, "
    "local_tolerance, local_max_iter, relaxation (PSOR omega, projected back on the cone when "
    "> 1; omega = 0.9 breaks the limit cycles plain Gauss-Seidel falls into on some rigid "
    "scenes), shuffle (none, once, each sweep) and seed, freezing (a contact that moved by "
    "less than a tenth of the light tolerance's share is skipped for that many sweeps; all "
    "are swept again whenever a full check fails, so the result is never less accurate), "
    "error_frequency (the light error is tested every k sweeps) and drift_window (every k "
    "sweeps, when r's displacement over the last k sweeps points the way of the previous k's, "
    "r jumps along it to the next loss of contact: for rank-deficient piles on which the "
    "sweeps creep along a steady transfer of load; 0 = never, the default) and acceleration "
    "(1: after each sweep r moves on along its last step, Nesterov's momentum restarted whenever "
    "a sweep moves r more than each of the two before; freezing is then off; for piles whose "
    "sweeps converge slowly but steadily; 0 = off, the default) and anderson (k > 0: after each "
    "sweep r moves to the mix of the last k + 1 sweeps' results whose residuals' changes best "
    "cancel the last residual, projected on the cones, the history restarted when a sweep's "
    "step grows; in place of acceleration, freezing then off; for a regular W, such as an "
    "elastic body's, where the sweeps contract at a steady rate; 0 = off, the default).",
    nsgs::solve,
    true,
    false,
    nsgs::kExtraKeys,
    nsgs::kDefaults,
};

const SolverEntry kNsgsVelocityEntry = {
    FRIX_SOLVER_NSGS_VELOCITY,
    "nsgs-v",
    "FRICTION_3D_NSGSV",
    "Velocity-based nonsmooth Gauss-Seidel: the sweeps of nsgs (the same one-contact "
    "solvers, the same iterates), but u = W r + q is kept up to date: a contact reads its "
    "local q as u_a - W_aa r_a and pushes a change of its reaction through W's block column, "
    "so that a contact whose reaction does not change (separated, or frozen) costs O(1) "
    "instead of a pass over its block row, and the periodic full checks cost no product "
    "(u is recomputed exactly to confirm the end, which also removes the rounding drift). "
    "On a dense W of at least 32 MiB the pushes go through a single-precision copy of W's "
    "columns (half W's memory more, where the memory limit leaves room): half the bytes a "
    "sweep reads; the full checks recompute u from the double W, so the verdict stays in "
    "double precision. On such a W, threads (k > 1) cut u's rows into k runs of contacts: "
    "each thread solves its own contacts and pushes every change into its own rows, in the "
    "sweep's order, so the iterates are the same for any number of threads. "
    "Freezing is on by default (10 sweeps). Options: those of nsgs (local_solver, "
    "local_tolerance, local_max_iter, "
    "relaxation, shuffle, seed, freezing, error_frequency, drift_window, acceleration, anderson) "
    "and threads. "
    "Unlike "
    "Siconos 4.4's "
    "NSGSV "
    "(dense W only, pseudo-inverse, prints), it takes any sparse W.",
    nsgs::solve_velocity,
    true,
    false,
    nsgs::kVelocityKeys,
    nsgs::kVelocityDefaults,
};

}  // namespace frix
