#include "solvers/nsgs.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

#include "src/coulomb.hpp"
#include "src/error_state.hpp"
#include "src/log.hpp"
#include "src/matrix.hpp"
#include "src/measures.hpp"
#include "src/monitor.hpp"
#include "src/random.hpp"

namespace frix {
namespace nsgs {

namespace {

void shuffle(std::vector<int64_t> &order, uint64_t &state) {
    for (size_t i = order.size(); i > 1; --i) {
        const size_t j = (size_t)(next_random(state) % i);
        std::swap(order[i - 1], order[j]);
    }
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

SweepStats Workspace::sweep_velocity(double *r, double *u) {
    const local::Params lp = s_.local;
    const auto local_q = [r, u](int64_t a, const local::Contact &c, double *ql) {
        // q_a + sum_{b != a} W_ab r_b = u_a - W_aa r_a.
        const double *Wd = c.W, *ra = r + 3 * a;
        ql[0] = u[3 * a] - (Wd[0] * ra[0] + Wd[3] * ra[1] + Wd[6] * ra[2]);
        ql[1] = u[3 * a + 1] - (Wd[1] * ra[0] + Wd[4] * ra[1] + Wd[7] * ra[2]);
        ql[2] = u[3 * a + 2] - (Wd[2] * ra[0] + Wd[5] * ra[1] + Wd[8] * ra[2]);
    };
    const auto step = [&lp](int64_t, local::Contact &c, const double *ql, double *rn) {
        return local::solve_contact(c, ql, rn, lp);
    };
    return sweep_loop(r, local_q, step, [this, u](int64_t a, const double *dr) { push_velocity(a, dr, u); });
}

void Workspace::push_velocity(int64_t a, const double *dr, double *u) {
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

// A full check also runs at the first evaluation and every kFullCheckPeriod evaluations: on
// rank-deficient W, r may keep drifting along the null space (large light error) while u,
// and the error, have converged, often from the first sweep on. Every full check but the
// first recalibrates the light tolerance, down or up.
constexpr int64_t kFullCheckPeriod = 16;
// Freezing starts after this many sweeps (Siconos' rule): the first sweeps move every contact.
constexpr int64_t kFreezeAfter = 10;
// Drift extrapolation (option drift_window): two successive windows' displacements count as
// one steady drift when the cosine of their angle exceeds this; a jump goes at most this many
// windows ahead.
constexpr double kDriftCosine = 0.99;
constexpr double kMaxDriftJump = 1000.0;
// The flags of SweepForm::agree after a sweep.
constexpr unsigned kStopAsked = 1u, kOutOfTime = 2u;

// On rank-deficient W, NSGS can sit for millions of sweeps on a plateau of the error while r
// drifts at a steady rate along a nearly self-equilibrated transfer of load between contacts,
// until one of them loses contact and the error falls. The drift is carried ahead at once:
// every `window` sweeps, the displacement d of r over the window is compared with the
// previous window's; when both point the same way, r jumps along d to the first loss of contact
// ahead (t = min r_aN / -d_aN over the contacts with d_aN < 0; when |d| shrank, at most to
// the limit of the geometric series of displacements) and is projected on the cones. The
// sweeps that follow restore what the straight line missed. A jump raises the error for a
// while, so none is taken within two windows of the sweep limit.
class DriftExtrapolation {
   public:
    // r: the start of the first window.
    DriftExtrapolation(int64_t window, int64_t m, const double *r) : window_(window), m_((size_t)m) {
        if (window_ <= 0) return;
        both_.assign(2 * m_, 0.0);  // one allocation: solves of a few sweeps run often
        std::copy(r, r + m, both_.begin());
    }
    // After sweep `it` of at most `max_sweeps`: true when r jumped (then u and the frozen
    // contacts need a refresh).
    bool after_sweep(int64_t it, int64_t max_sweeps, double *r, const double *mu) {
        if (window_ <= 0 || it % window_ != 0) return false;
        const size_t m = m_;
        double *start_ = both_.data(), *last_ = both_.data() + m_;
        double dd = 0.0, dl = 0.0, ll = 0.0;
        for (size_t i = 0; i < m; ++i) {
            const double d = r[i] - start_[i];
            dd += d * d;
            dl += d * last_[i];
            ll += last_[i] * last_[i];
            last_[i] = d;
            start_[i] = r[i];
        }
        const bool steady = have_last_ && dd > 0.0 && dl > kDriftCosine * std::sqrt(dd * ll);
        have_last_ = dd > 0.0;
        if (!steady) return false;
        double t = INFINITY;
        for (size_t a = 0; 3 * a < m; ++a)
            if (last_[3 * a] < 0.0 && r[3 * a] > 0.0) t = std::min(t, -r[3 * a] / last_[3 * a]);
        const double ratio = std::sqrt(dd / ll);
        if (ratio < 1.0) t = std::min(t, ratio / (1.0 - ratio));
        if (!(t > 1.0) || !std::isfinite(t) || max_sweeps - it < 2 * window_) return false;
        t = std::min(t, kMaxDriftJump);
        for (size_t i = 0; i < m; ++i) r[i] += t * last_[i];
        coulomb::project_on_cones(r, mu, (int64_t)(m / 3));
        std::copy(r, r + m, start_);
        have_last_ = false;  // a new window history from the new point
        ++jumps_;
        return true;
    }
    int64_t jumps() const { return jumps_; }

   private:
    int64_t window_;
    size_t m_;
    std::vector<double> both_;  // r at the window's start, then the last window's displacement
    bool have_last_ = false;
    int64_t jumps_ = 0;
};

// Nesterov momentum on the sweep (option acceleration; O'Donoghue and Candes's adaptive
// restart): after the k-th sweep since the last restart, r = x_k, the sweep's result, moves to
// P_K(x_k + beta_k (x_k - x_{k-1})), beta_k = (k - 1) / (k + 2). The momentum restarts (beta
// = 0) whenever a sweep moved r more than each of the two before (a sweep's displacement often
// alternates from one sweep to the next), and after a drift jump. Where load crosses a pile
// a layer a sweep, the sweeps' steps keep their direction for long, which momentum follows;
// the sweep itself, and its fixed points, stay as they are. Freezing is off under it: the
// extrapolation moves the contacts freezing would skip, and the two together can hold the
// error on a plateau.
class Momentum {
   public:
    Momentum(bool on, int64_t m, const double *r) : on_(on) {
        if (!on_) return;
        last_.assign(r, r + m);
        line_.resize((size_t)m);
    }
    bool on() const { return on_; }
    // After a sweep that moved r by |dr|^2 = dr2 (jumped: r then jumped ahead of the sweep).
    void after_sweep(double dr2, bool jumped, double *r, const double *mu, Workspace &ws, SweepForm &form, double *u) {
        if (!on_) return;
        if (jumped || !(dr2 <= std::max(last_dr2_[0], last_dr2_[1]))) k_ = 0;
        last_dr2_[1] = last_dr2_[0];
        last_dr2_[0] = dr2;
        ++k_;
        const double beta = (double)(k_ - 1) / (double)(k_ + 2);
        const size_t m = last_.size();
        for (size_t i = 0; i < m; ++i) {
            const double x = r[i];
            line_[i] = x + beta * (x - last_[i]);
            last_[i] = x;
            r[i] = line_[i];
        }
        if (beta != 0.0) coulomb::project_on_cones(r, mu, (int64_t)(m / 3));
        form.extrapolate(ws, beta, line_.data(), r, u);
    }

   private:
    bool on_;
    std::vector<double> last_, line_;  // x_{k-1}; the line point before its projection
    double last_dr2_[2] = {INFINITY, INFINITY};  // the last two sweeps' |dr|^2
    int64_t k_ = 0;
};

// W's block rows (nsgs): the local q from each row; nothing kept between sweeps.
class RowForm : public SweepForm {
   public:
    explicit RowForm(const frix_problem &p) : p_(p) {}
    SweepStats sweep(Workspace &ws, double *r, double *) override { return ws.sweep(r); }
    Measures exact(const double *r, double *u) override { return local_measures(p_, r, u); }

   private:
    const frix_problem &p_;
};

// W's block columns (nsgs-v): u = W r + q kept up to date by each change of r.
class VelocityForm : public SweepForm {
   public:
    explicit VelocityForm(const frix_problem &p) : p_(p), norm_q_(norm2(p.q, 3 * p.nc)) {}
    SweepStats sweep(Workspace &ws, double *r, double *u) override { return ws.sweep_velocity(r, u); }
    Measures exact(const double *r, double *u) override { return local_measures(p_, r, u); }
    bool kept(const double *r, double *u, Measures &m) override {
        m = measures_from_ru(r, u, p_.mu, p_.weight.data(), p_.nc, norm_q_);
        return true;
    }
    void restart(const double *r, double *u) override {
        matrix_gemv(*p_.W, 1.0, r, 0.0, u);
        for (int64_t i = 0; i < 3 * p_.nc; ++i) u[i] += p_.q[i];
    }
    void extrapolate(Workspace &ws, double beta, const double *line, const double *y, double *u) override {
        extrapolate_affine(beta, line, y, p_.nc, u, 3 * (size_t)p_.nc, u_last_,
                           [&ws, u](int64_t a, const double *d) { ws.push_velocity(a, d, u); });
    }

   private:
    const frix_problem &p_;
    double norm_q_;
    std::vector<double> u_last_;  // u at the previous extrapolation's x
};

frix_error run(SolveContext &ctx, bool velocity) {
    const frix_problem &p = ctx.problem;
    const char *name = velocity ? "nsgs-v" : "nsgs";
    if (!p.W || !p.W->block)
        return fail(FRIX_ERR_INTERNAL, "%s: W is not stored as 3x3 blocks", name);
    Workspace ws(p, settings_from(ctx.options));
    RowForm rows(p);
    VelocityForm columns(p);
    return run_sweeps(ctx, ws, velocity ? (SweepForm &)columns : (SweepForm &)rows, name);
}

}  // namespace

frix_error run_sweeps(SolveContext &ctx, Workspace &ws, SweepForm &form, const char *name) {
    const frix_problem &p = ctx.problem;
    const frix_options &o = ctx.options;
    const Settings s = settings_from(o);
    const Monitor monitor(ctx);
    const double tol = monitor.tolerance();
    const int64_t max_iter = monitor.max_iterations();
    const int64_t verbosity = o.i(FRIX_OPT_VERBOSITY);
    const int64_t measure = o.i(FRIX_OPT_ERROR_MEASURE);
    const int64_t frequency = o.i(FRIX_OPT_ERROR_FREQUENCY);
    const int64_t m = 3 * p.nc;

    double *r = ctx.r;
    double *u = ctx.u;
    frix_info &info = ctx.info;
    // The last exact measures, handed to the driver when r has not moved since (at_r).
    Measures last;
    bool at_r = false;
    auto exact_error = [&]() {
        last = form.exact(r, u);
        at_r = true;
        return selected_error(last, measure);
    };
    auto hand_over = [&]() {
        ctx.has_measured = at_r && form.measures_are_local();
        ctx.measured = last;
    };
    // A periodic check: from what the form keeps up to date where it keeps something; a
    // passing check is confirmed by the exact error.
    auto full_error = [&]() {
        Measures kept;
        if (!form.kept(r, u, kept)) return exact_error();
        const double e = selected_error(kept, measure);
        return e <= tol ? exact_error() : e;
    };

    // A warm start that already solves the problem costs one product, not a sweep.
    bool warm = false;
    for (int64_t i = 0; i < m && !warm; ++i) warm = r[i] != 0.0;
    warm = form.agree(warm ? 1u : 0u) != 0;
    if (warm) {
        const double e = exact_error();
        if (e <= tol) {
            info.status = FRIX_STATUS_CONVERGED;
            info.iterations = 0;
            hand_over();
            return FRIX_OK;
        }
    } else {
        form.restart(r, u);
    }

    const int64_t all_contacts = form.all_contacts(p.nc);
    DriftExtrapolation drift(o.i(FRIX_OPT_DRIFT_WINDOW), m, r);
    Momentum momentum(o.i(FRIX_OPT_ACCELERATION) != 0, m, r);

    // The best r of the full checks, returned when the run ends worse (ctx.return_best).
    std::vector<double> best_r;
    double best_error = INFINITY;
    const bool keep_best = ctx.return_best && form.restores();
    double tol_light = tol;
    int64_t it = 0, evaluations = 0;
    info.status = FRIX_STATUS_MAX_ITER;
    bool checked_last = false;  // whether the last sweep ended with a full check
    double last_full = NAN, estimate = NAN, last_r2 = 0.0;
    while (it < max_iter) {
        if (s.freezing > 0)
            ws.set_freeze_threshold(it >= kFreezeAfter && !momentum.on()
                                        ? tol_light * tol_light * last_r2 / (10.0 * (double)all_contacts)
                                        : -1.0);
        const SweepStats st = form.sweep(ws, r, u);
        at_r = false;
        ++it;
        last_r2 = st.r2;
        if (!std::isfinite(st.r2)) {
            info.status = FRIX_STATUS_DIVERGED;
            break;
        }
        const bool jumped = drift.after_sweep(it, max_iter, r, p.mu);
        if (jumped) {
            form.restart(r, u);
            ws.thaw();
            if (verbosity >= 1)
                log_line(&o, "%s: sweep %lld: drift carried ahead (jump %lld)", name, (long long)it,
                         (long long)drift.jumps());
        }
        momentum.after_sweep(st.dr2, jumped, r, p.mu, ws, form, u);
        checked_last = false;
        double light = NAN;
        if (it % frequency == 0 && !jumped) {  // (the sweep's light error predates a jump)
            ++evaluations;
            light = st.r2 > 0.0 ? std::sqrt(st.dr2 / st.r2) : std::sqrt(st.dr2);
            estimate = light;
            // The first test's full check only ends a solve that is already done; the light
            // tolerance is calibrated by the periodic ones (calibrated after one sweep, it
            // misjudges the sweeps to come).
            const bool first_only = evaluations == 1 && light > tol_light;
            if (light <= tol_light || first_only || evaluations % kFullCheckPeriod == 0) {
                const double e = full_error();
                checked_last = true;
                last_full = e;
                if (keep_best && e < best_error) {
                    best_error = e;
                    best_r.assign(r, r + m);
                }
                if (!first_only) estimate = e;
                if (e <= tol) {
                    info.status = FRIX_STATUS_CONVERGED;
                    estimate = e;
                } else if (!std::isfinite(e)) {
                    info.status = FRIX_STATUS_DIVERGED;
                } else if (st.dr2 == 0.0 && st.frozen == 0) {
                    info.status = FRIX_STATUS_STAGNATED;  // r is a fixed point of the sweep
                } else if (!first_only) {
                    // LIGHT_WITH_FULL_FINAL: the light error that should mean full error = tol.
                    if (light > 0.0) tol_light = light / e * tol;
                    // Frozen contacts may be what keeps the error up: sweep them all again.
                    ws.thaw();
                }
            }
        }
        if (verbosity >= 2 || (verbosity >= 1 && checked_last))
            log_line(&o,
                     "%s: sweep %lld light %.3e%s%.3e rejected %lld unsolved %lld frozen %lld",
                     name, (long long)it, light, checked_last ? " full " : " tol_light ",
                     checked_last ? last_full : tol_light, (long long)st.rejected,
                     (long long)st.unsolved, (long long)st.frozen);
        // The callback sees every sweep, the last one too; it can only stop a running solve.
        const bool stop = monitor.report(it, estimate);
        if (info.status != FRIX_STATUS_MAX_ITER) break;
        const unsigned flags = form.agree((stop ? kStopAsked : 0u) | (monitor.out_of_time() ? kOutOfTime : 0u));
        if (flags & kStopAsked) {
            info.status = FRIX_STATUS_STOPPED_BY_CALLBACK;
            break;
        }
        if (flags & kOutOfTime) {
            info.status = FRIX_STATUS_TIME_LIMIT;
            break;
        }
    }
    // The iteration limit may fall between two full checks.
    if (info.status == FRIX_STATUS_MAX_ITER && !checked_last && exact_error() <= tol)
        info.status = FRIX_STATUS_CONVERGED;
    if (info.status != FRIX_STATUS_CONVERGED && !best_r.empty()) {
        bool finite_r = true;
        for (int64_t i = 0; i < m && finite_r; ++i) finite_r = std::isfinite(r[i]);
        const double final_error = !finite_r ? INFINITY : at_r ? selected_error(last, measure) : exact_error();
        if (best_error < final_error) {
            std::copy(best_r.begin(), best_r.end(), r);
            form.restart(r, u);
            exact_error();
        }
    }
    info.iterations = it;
    hand_over();
    if (verbosity >= 1)
        log_line(&o, "%s: %s after %lld sweeps", name, frix_status_string(info.status),
                 (long long)it);
    return FRIX_OK;
}

namespace {

frix_error solve(SolveContext &ctx) { return run(ctx, false); }
frix_error solve_velocity(SolveContext &ctx) { return run(ctx, true); }


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
                                      FRIX_OPT_ACCELERATION,   (frix_option_key)0};

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
    "sweeps converge slowly but steadily; 0 = off, the default).",
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
    "Freezing is on by default (10 sweeps). Options: those of nsgs (local_solver, "
    "local_tolerance, local_max_iter, "
    "relaxation, shuffle, seed, freezing, error_frequency, drift_window, acceleration). Unlike "
    "Siconos 4.4's "
    "NSGSV "
    "(dense W only, pseudo-inverse, prints), it takes any sparse W.",
    nsgs::solve_velocity,
    true,
    false,
    nsgs::kExtraKeys,
    nsgs::kVelocityDefaults,
};

}  // namespace frix
