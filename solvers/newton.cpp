#include "solvers/newton.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "solvers/nsgs.hpp"
#include "solvers/nsn_functions.hpp"
#include "src/error_state.hpp"
#include "src/log.hpp"
#include "src/matrix.hpp"
#include "src/measures.hpp"
#include "src/monitor.hpp"

namespace frix {
namespace newton {

namespace {

double dot(const double *x, const double *y, int64_t n) {
    double s = 0.0;
    for (int64_t i = 0; i < n; ++i) s += x[i] * y[i];
    return s;
}

// Goldstein-Price constants of Siconos (m1, m2), Armijo's sigma.
constexpr double kM1 = 0.01, kM2 = 0.99, kArmijo = 1e-4;
// Newton is declared stalled after this many steps without halving the best error, or this
// many failed line searches in a row.
constexpr int kStallSteps = 25;
constexpr int kMaxLineSearchFailures = 3;
// The hybrid gives up after this many Newton + NSGS rounds in a row without halving the error.
constexpr int kMaxIdleRounds = 10;
// The Jacobian regularisation delta (relative to the mean |W_aa|): where it starts and
// restarts, and below which it is dropped (tuned on the rank-deficient FCLIB problems).
constexpr double kDeltaStart = 1e-6, kDeltaFloor = 1e-8;
// Active systems up to this size are factorised dense (LAPACK): a 60 x 60 LU costs less than
// UMFPACK's fixed overhead.
constexpr int64_t kDenseMax = 60;
// The watchdog (option watchdog = k; Chamberlain, Powell, Lemarechal and Pedersen's technique,
// judged by the error measure instead of the merit). The merit 1/2 |Phi|^2 can disagree with
// the error: with bodies 1e6 times heavier than others, the Alart-Curnier merit is dominated
// by the heavy bodies' contacts and rises by a factor 1e8 on the full step that takes the
// error from 9.2e-2 to 2.3e-6 (hard case chain_mass1e6), so the line search keeps cutting the
// step to nothing (stagnated at 2.9e-4, where full steps converge in 4). Where the line search
// stalls (its step below kWatchdogShortStep, or none) while the full step at least halves the
// best error (kWatchdogTrigger), the full step is taken, then k - 1 more steps, full too where
// the line search would cut them short (with the line search there instead, nsn-fb still
// stagnated on chain_mass1e6 and stack_mass1e6 took 29 steps instead of 8); unless the error
// then stands tenfold below the best error at the start (kWatchdogGain), the run goes back to
// the start with everything it knew there and does not try again in that run. A failed try
// costs k steps and leaves the path as it was, up to rounding (the sparse LU's analysis may be
// redone on the way back; Kapla-3x3x20 s60 parts from it 29 steps later, at the fourth digit
// of the error, and ends after 126 steps instead of 121): on chaotic paths (local_problem_test) a
// kept excursion judged on its first point alone, or by its best error, took 110 to 163
// steps instead of 63; judged after k = 5 steps, 68.
constexpr double kWatchdogShortStep = 1e-2, kWatchdogTrigger = 0.5, kWatchdogGain = 0.1;

}  // namespace

linalg::FactorStats Engine::total_stats() const {
    linalg::FactorStats s = lu_.stats();
    s.numeric += dense_lu_.stats().numeric;
    s.seconds += dense_lu_.stats().seconds;
    return s;
}

linalg::FactorStats Engine::factor_stats() const { return total_stats() - stats_before_; }

Engine &engine_for(KeptEngine &kept, const SolveCache *cache, const frix_matrix &W, const double *mu,
                   int64_t nc, const Settings &s) {
    if (kept.engine && cache && kept.w_pattern == cache->w_pattern && kept.nc == nc) {
        kept.engine->rebind(W, mu, s);
    } else {
        kept.engine = std::make_unique<Engine>(W, mu, nc, s);
        kept.nc = nc;
    }
    kept.w_pattern = cache ? cache->w_pattern : 0;
    return *kept.engine;
}

bool Limits::out_of_time() const { return Monitor(options, clock).out_of_time(); }

bool Limits::report(double error) {
    // Once the callback asked to stop it is not called again, though the caller (PROX's outer
    // step after an inner solve) may still report before it gets to stop.
    if (!stop_requested && (ctx ? Monitor(*ctx) : Monitor(options, clock)).report(*iterations, error))
        stop_requested = true;
    return stop_requested;
}

Settings settings_from(const frix_options &o, int solver_id) {
    Settings s;
    s.formulation = solver_id == FRIX_SOLVER_NSN_FB   ? nsn::kFischerBurmeister
                    : solver_id == FRIX_SOLVER_NSN_NM ? nsn::kNaturalMap
                                                      : nsn::kAlartCurnier;
    s.rho_strategy = (int)o.i(FRIX_OPT_RHO_STRATEGY);
    s.rho = o.d(FRIX_OPT_RHO);
    s.line_search = (int)o.i(FRIX_OPT_LINE_SEARCH);
    s.ls_max_iter = (int)o.i(FRIX_OPT_LINE_SEARCH_MAX_ITER);
    s.hybrid = (int)o.i(FRIX_OPT_HYBRID);
    s.hybrid_sweeps = o.i(FRIX_OPT_HYBRID_SWEEPS);
    s.watchdog = (int)o.i(FRIX_OPT_WATCHDOG);
    s.measure = o.i(FRIX_OPT_ERROR_MEASURE);
    s.verbosity = (int)o.i(FRIX_OPT_VERBOSITY);
    s.log = &o;
    return s;
}

Engine::Engine(const frix_matrix &W, const double *mu, int64_t nc, const Settings &s)
    : W_(&W), nc_(nc), m_(3 * nc), rho_n_(nc), rho_t_(nc), A_(9 * nc), B_(9 * nc) {
    index_.assign(nc, 0);
    rebind(W, mu, s);
}

void Engine::rebind(const frix_matrix &W, const double *mu, const Settings &s) {
    static const double kZero[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
    W_ = &W;
    mu_ = mu;
    s_ = s;
    double scale = 0.0;
    for (int64_t a = 0; a < nc_; ++a) {
        const int64_t d = W.diag_index[a];
        const double *Waa = d >= 0 ? &W.block_val[9 * d] : kZero;
        nsn::contact_rho(s.rho_strategy, s.rho, Waa, &rho_n_[a], &rho_t_[a]);
        double fro = 0.0;
        for (int i = 0; i < 9; ++i) fro += Waa[i] * Waa[i];
        scale += std::sqrt(fro);
    }
    w_scale_ = nc_ > 0 && scale > 0.0 ? scale / (double)nc_ : 1.0;
    counters = Counters();
    full_step_on_failure = false;
    analysed_ = false;  // the active set is found afresh, as by a new engine
    stats_before_ = total_stats();
}

// Contacts whose Phi does not depend on u (B_a = 0, A_a = I: separating ones) have the
// Newton step d_a = -Phi_a outright and drop out of the linear system; the others are
// "active". The system's pattern is W's block pattern on the active contacts plus their
// diagonal blocks: it changes only when contacts join the active set, and is analysed again
// only then. On granular scenes, where many contacts separate, the system is much smaller
// than W.
bool Engine::update_active() {
    bool changed = !analysed_;
    for (int64_t a = 0; a < nc_; ++a) {
        const double *A = &A_[9 * a], *B = &B_[9 * a];
        bool free = A[0] == 1.0 && A[4] == 1.0 && A[8] == 1.0;
        for (int i = 0; i < 9 && free; ++i) free = B[i] == 0.0 && (i % 4 == 0 || A[i] == 0.0);
        // Only joining contacts change the pattern: one that separates stays in the system
        // (its rows are then the identity), so that the active set, and with it the
        // analysis, settles after a few steps instead of following every change.
        if (!analysed_) {
            index_[a] = free ? -1 : 0;
        } else if (!free && index_[a] < 0) {
            changed = true;
            index_[a] = 0;
        }
    }
    if (!changed) return false;
    int64_t k = 0;
    for (int64_t a = 0; a < nc_; ++a)
        if (index_[a] >= 0) index_[a] = k++;
    n_active_ = k;
    build_pattern();
    return true;
}

void Engine::build_pattern() {
    const int64_t nb = W_->nblocks();
    const int64_t na = n_active_;
    std::vector<int64_t> count(na, 0);  // blocks per active block column
    for (int64_t a = 0; a < nc_; ++a) {
        if (index_[a] < 0) continue;
        if (W_->diag_index[a] < 0) ++count[index_[a]];
        for (int64_t b = W_->row_ptr[a]; b < W_->row_ptr[a + 1]; ++b)
            if (index_[W_->block_col[b]] >= 0) ++count[index_[W_->block_col[b]]];
    }
    std::vector<int64_t> start(na + 1, 0);
    for (int64_t c = 0; c < na; ++c) start[c + 1] = start[c] + 9 * count[c];
    colptr_.assign(3 * na + 1, 0);
    for (int64_t c = 0; c < na; ++c)
        for (int j = 0; j < 3; ++j) colptr_[3 * c + j + 1] = start[c] + (j + 1) * 3 * count[c];
    rowind_.assign(start[na], 0);
    values_.assign(start[na], 0.0);
    block_pos_.assign(nb, -1);
    block_stride_.assign(nb, 0);
    diag_pos_.assign(nc_, -1);
    diag_stride_.assign(nc_, 0);
    // Active block rows in increasing order: each column's list of block rows comes out sorted.
    std::vector<int64_t> fill(na, 0);
    auto place = [&](int64_t ia, int64_t ic) {
        const int64_t pos = start[ic] + 3 * fill[ic]++, stride = 3 * count[ic];
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 3; ++i) rowind_[pos + j * stride + i] = 3 * ia + i;
        return pos;
    };
    for (int64_t a = 0; a < nc_; ++a) {
        const int64_t ia = index_[a];
        if (ia < 0) continue;
        bool placed_diag = W_->diag_index[a] >= 0;
        for (int64_t b = W_->row_ptr[a]; b < W_->row_ptr[a + 1]; ++b) {
            const int64_t c = W_->block_col[b], ic = index_[c];
            if (ic < 0) continue;
            if (!placed_diag && c > a) {
                diag_pos_[a] = place(ia, ia);
                diag_stride_[a] = 3 * count[ia];
                placed_diag = true;
            }
            block_pos_[b] = place(ia, ic);
            block_stride_[b] = 3 * count[ic];
        }
        if (!placed_diag) {
            diag_pos_[a] = place(ia, ia);
            diag_stride_[a] = 3 * count[ia];
        }
    }
}

void Engine::evaluate(const double *r, const double *u, bool jacobian, double *phi) {
    for (int64_t a = 0; a < nc_; ++a)
        nsn::contact_function(s_.formulation, r + 3 * a, u + 3 * a, mu_[a], rho_n_[a], rho_t_[a],
                              phi + 3 * a, jacobian ? &A_[9 * a] : nullptr,
                              jacobian ? &B_[9 * a] : nullptr);
}

void Engine::assemble(double shift) {
    double *val = values_.data();
    for (int64_t a = 0; a < nc_; ++a) {
        if (index_[a] < 0) continue;
        const double *A = &A_[9 * a], *B = &B_[9 * a];
        // J_aa = A + shift B + B W_aa (the last term added with W's diagonal block below).
        double D[9];
        for (int i = 0; i < 9; ++i) D[i] = A[i] + shift * B[i];
        if (W_->diag_index[a] < 0) {
            const int64_t pos = diag_pos_[a], st = diag_stride_[a];
            for (int j = 0; j < 3; ++j)
                for (int i = 0; i < 3; ++i) val[pos + j * st + i] = D[i + 3 * j];
        }
        for (int64_t b = W_->row_ptr[a]; b < W_->row_ptr[a + 1]; ++b) {
            const int64_t pos = block_pos_[b], st = block_stride_[b];
            if (pos < 0) continue;  // column of a separating contact
            const double *Wb = &W_->block_val[9 * b];
            const bool diag = W_->block_col[b] == a;
            for (int j = 0; j < 3; ++j)
                for (int i = 0; i < 3; ++i) {
                    double v = B[i] * Wb[3 * j] + B[i + 3] * Wb[3 * j + 1] + B[i + 6] * Wb[3 * j + 2];
                    if (diag) v += D[i + 3 * j];
                    val[pos + j * st + i] = v;
                }
        }
    }
}

// The Newton step d from the factorised active system: d_a = -Phi_a on separating contacts,
// then the active ones with those moved to the right-hand side.
frix_error Engine::step(const double *phi, double *d, double *rhs, double *x) {
    for (int64_t a = 0; a < nc_; ++a)
        if (index_[a] < 0)
            for (int i = 0; i < 3; ++i) d[3 * a + i] = -phi[3 * a + i];
    if (n_active_ == 0) return FRIX_OK;
    for (int64_t a = 0; a < nc_; ++a) {
        const int64_t ia = index_[a];
        if (ia < 0) continue;
        double t[3] = {0.0, 0.0, 0.0};
        for (int64_t b = W_->row_ptr[a]; b < W_->row_ptr[a + 1]; ++b)
            if (index_[W_->block_col[b]] < 0)
                block_gemv_add(&W_->block_val[9 * b], &d[3 * W_->block_col[b]], t);
        const double *B = &B_[9 * a];
        for (int i = 0; i < 3; ++i)
            rhs[3 * ia + i] = -phi[3 * a + i] - (B[i] * t[0] + B[i + 3] * t[1] + B[i + 6] * t[2]);
    }
    if (frix_error e = use_dense_ ? dense_lu_.solve(rhs, x) : lu_.solve(rhs, x)) return e;
    for (int64_t a = 0; a < nc_; ++a)
        if (index_[a] >= 0)
            for (int i = 0; i < 3; ++i) d[3 * a + i] = x[3 * index_[a] + i];
    return FRIX_OK;
}

// 1/2 |Phi(r + t d, u + t du)|^2; rt, ut, phi are work vectors.
double Engine::merit_along(const double *r, const double *u, const double *d, const double *du,
                           double t, double *rt, double *ut, double *phi) {
    for (int64_t i = 0; i < m_; ++i) {
        rt[i] = r[i] + t * d[i];
        ut[i] = u[i] + t * du[i];
    }
    evaluate(rt, ut, false, phi);
    ++counters.line_search;
    return 0.5 * dot(phi, phi, m_);
}

double Engine::full_step_error(const double *r, const double *u, const double *d, const double *du,
                               double norm_q, double *rt, double *ut) const {
    for (int64_t i = 0; i < m_; ++i) {
        rt[i] = r[i] + d[i];
        ut[i] = u[i] + du[i];
    }
    return selected_error(measures_from_ru(rt, ut, mu_, s_.weight, nc_, norm_q), s_.measure);
}

frix_error Engine::run(double *r, const double *q, double shift, double tol, Limits &lim,
                       RunResult &res, double scale_q) {
    const int64_t m = m_;
    lu_.set_budget(Monitor(lim.options, lim.clock).budget());  // this run's time and memory limits
    std::vector<double> u(m), phi(m), d(m), du(m), rhs(m), x(m), rt(m), ut(m), phit(m), best(r, r + m);
    const double norm_q = scale_q >= 0.0 ? scale_q : std::sqrt(dot(q, q, m));
    auto product = [&](const double *z, double *y) {  // y = (W + shift I) z
        matrix_gemv(*W_, 1.0, z, 0.0, y);
        if (shift != 0.0)
            for (int64_t i = 0; i < m; ++i) y[i] += shift * z[i];
    };
    auto velocity = [&]() {
        product(r, u.data());
        for (int64_t i = 0; i < m; ++i) u[i] += q[i];
    };
    auto error_of = [&]() {
        return selected_error(measures_from_ru(r, u.data(), mu_, s_.weight, nc_, norm_q), s_.measure);
    };

    velocity();
    evaluate(r, u.data(), true, phi.data());
    double psi = 0.5 * dot(phi.data(), phi.data(), m);
    double err = error_of();
    double best_err = err, ref_err = err;
    int since_progress = 0, ls_failures = 0;
    // Jacobian regularisation, in units of w_scale_. Rank-deficient W (rigid scenes) make
    // J singular on the sticking contacts, and the raw Newton step then runs along W's null
    // space; a small delta costs nothing in u (the null space does not move u) and keeps the
    // steps acceptable. It falls after full steps, down to 0 on well-posed problems.
    // A proximal shift already regularises J: delta then starts at 0.
    double delta = shift > 0.0 ? 0.0 : kDeltaStart;
    MeritHistory history(psi);
    // A watchdog excursion (kWatchdogTrigger) and the state it returns to when it fails.
    struct Excursion {
        bool active = false, spent = false;  // one failed excursion per run
        int steps = 0;
        std::vector<double> r, best;
        double best_err = 0.0, ref_err = 0.0, err = 0.0, delta = 0.0;
        int since_progress = 0, ls_failures = 0;
        MeritHistory history{0.0};
    } excursion;
    res.status = FRIX_STATUS_MAX_ITER;

    while (true) {
        if (err <= tol) {
            res.status = FRIX_STATUS_CONVERGED;
            break;
        }
        if (!std::isfinite(err)) {  // the best (finite) iterate is given back below
            res.status = FRIX_STATUS_DIVERGED;
            break;
        }
        if (*lim.iterations >= lim.max_iter) {
            res.status = FRIX_STATUS_MAX_ITER;
            break;
        }
        if (lim.stop_requested) {
            res.status = FRIX_STATUS_STOPPED_BY_CALLBACK;
            break;
        }
        if (lim.out_of_time()) {
            res.status = FRIX_STATUS_TIME_LIMIT;
            break;
        }
        // Factorise the active part of J (+ delta B); a singular J is regularised until it
        // factorises. The pattern (and so the symbolic analysis) changes only with the
        // active set.
        const bool new_pattern = update_active();
        const int64_t ma = 3 * n_active_;
        use_dense_ = ma <= kDenseMax;
        if (ma > 0) {
            linalg::CscView J{ma, ma, colptr_.data(), rowind_.data(), values_.data()};
            // A persistent solver's engine keeps the analysis of the active set it last
            // analysed: when a later solve finds the same set, the analysis still holds.
            if (new_pattern && !use_dense_ && index_ != analysed_index_) {
                assemble(shift + delta * w_scale_);
                analysed_index_.clear();
                if (frix_error e = lu_.analyze(J)) return e;
                analysed_index_ = index_;
            }
            bool factored = false;
            frix_status refused = FRIX_STATUS_NOT_RUN;
            for (int attempt = 0; attempt < 12 && !factored && !refused; ++attempt) {
                assemble(shift + delta * w_scale_);
                frix_error e;
                if (use_dense_) {
                    dense_.assign((size_t)(ma * ma), 0.0);
                    for (int64_t j = 0; j < ma; ++j)
                        for (int64_t k = colptr_[j]; k < colptr_[j + 1]; ++k)
                            dense_[(size_t)(rowind_[k] + ma * j)] = values_[k];
                    e = dense_lu_.factor(ma, dense_.data(), ma);
                    factored = e == FRIX_OK && dense_lu_.rcond() > 1e-15;
                } else {
                    e = lu_.factor(J);
                    factored = e == FRIX_OK && lu_.rcond() > 1e-15;
                    refused = lu_.refused();
                }
                if (e == FRIX_ERR_OUT_OF_MEMORY) return e;
                if (!factored) delta = delta == 0.0 ? kDeltaStart : delta * 100.0;
                if (delta > 1e6) break;
            }
            if (!factored) {
                res.status = refused ? refused : FRIX_STATUS_NUMERICAL_FAILURE;
                break;
            }
        }
        analysed_ = true;
        if (frix_error e = step(phi.data(), d.data(), rhs.data(), x.data())) return e;
        bool finite = true;
        for (int64_t i = 0; i < m && finite; ++i) finite = std::isfinite(d[i]);
        ++counters.newton;
        ++*lim.iterations;

        double t = 0.0;
        bool accepted = false;
        if (finite) {
            product(d.data(), du.data());
            // Slope of the merit along d: Phi . (A d + B du), the exact directional derivative.
            double slope = 0.0;
            for (int64_t a = 0; a < nc_; ++a) {
                const double *A = &A_[9 * a], *B = &B_[9 * a], *da = &d[3 * a], *dua = &du[3 * a];
                for (int i = 0; i < 3; ++i)
                    slope += phi[3 * a + i] *
                             (A[i] * da[0] + A[i + 3] * da[1] + A[i + 6] * da[2] + B[i] * dua[0] +
                              B[i + 3] * dua[1] + B[i + 6] * dua[2]);
            }
            const double ref = s_.line_search == FRIX_LINE_SEARCH_NONMONOTONE ? history.reference(psi) : psi;
            if (s_.line_search == FRIX_LINE_SEARCH_NONE) {
                t = 1.0;
                accepted = true;
            } else if (slope < 0.0) {
                double lo = 0.0, hi = INFINITY;
                t = 1.0;
                double best_t = 0.0, best_psi = psi;
                for (int k = 0; k < s_.ls_max_iter; ++k) {
                    const double pt = merit_along(r, u.data(), d.data(), du.data(), t, rt.data(),
                                                  ut.data(), phit.data());
                    if (pt < best_psi) best_psi = pt, best_t = t;
                    if (s_.line_search == FRIX_LINE_SEARCH_GOLDSTEIN_PRICE) {
                        if (pt > psi + kM1 * t * slope || !std::isfinite(pt)) {
                            hi = t;
                        } else if (pt < psi + kM2 * t * slope && t < 1.0) {
                            lo = t;  // too short: Newton steps are never extended beyond 1
                        } else {
                            accepted = true;
                            break;
                        }
                        t = std::isfinite(hi) ? 0.5 * (lo + hi) : std::min(2.0 * t, 1.0);
                    } else {
                        if (pt <= ref + kArmijo * t * slope) {
                            accepted = true;
                            break;
                        }
                        t *= 0.5;
                    }
                }
                // The full step's error is measured only where the line search stalled.
                const bool may_watch =
                    s_.watchdog > 0 && !full_step_on_failure && !excursion.active && !excursion.spent;
                if (may_watch && (!accepted || t < kWatchdogShortStep) &&
                    full_step_error(r, u.data(), d.data(), du.data(), norm_q, rt.data(), ut.data()) <=
                        kWatchdogTrigger * best_err) {
                    excursion.active = true;
                    excursion.steps = 0;
                    excursion.r.assign(r, r + m);
                    excursion.best = best;
                    excursion.best_err = best_err, excursion.ref_err = ref_err;
                    excursion.err = err, excursion.delta = delta;
                    excursion.since_progress = since_progress, excursion.ls_failures = ls_failures;
                    excursion.history = history;
                    t = 1.0;
                    accepted = true;
                }
                if (!accepted && full_step_on_failure) {
                    t = 1.0;  // Siconos' rule: a failed line search takes the full step
                    accepted = true;
                }
                if (!accepted && best_t > 0.0) {  // no sufficient decrease, but a decrease
                    t = best_t;
                    accepted = true;
                }
            }
        }
        // Within an excursion, the steps the line search would cut short are full steps too.
        if (finite && excursion.active && (!accepted || t < kWatchdogShortStep)) {
            t = 1.0;
            accepted = true;
        }
        if (accepted) {
            for (int64_t i = 0; i < m; ++i) r[i] += t * d[i];
            velocity();  // a fresh product: no drift of u = W r + q over many steps
            evaluate(r, u.data(), true, phi.data());
            psi = 0.5 * dot(phi.data(), phi.data(), m);
            history.push(psi);
            err = error_of();
            ls_failures = 0;
            if (t == 1.0) delta = delta < kDeltaFloor ? 0.0 : delta * 0.1;
        } else {
            // No descent along d: a more regularised Jacobian gives a shorter, safer step.
            ++ls_failures;
            delta = std::max(delta * 10.0, kDeltaStart);
        }
        // The excursion's k steps (the full step first) are judged: kept when the error fell
        // tenfold below the best error at its start, otherwise undone.
        if (excursion.active && ++excursion.steps >= s_.watchdog) {
            excursion.active = false;
            if (!(err <= kWatchdogGain * excursion.best_err)) {
                excursion.spent = true;
                std::copy(excursion.r.begin(), excursion.r.end(), r);
                best = excursion.best;
                best_err = excursion.best_err, ref_err = excursion.ref_err;
                delta = excursion.delta;
                since_progress = excursion.since_progress, ls_failures = excursion.ls_failures;
                history = excursion.history;
                velocity();
                evaluate(r, u.data(), true, phi.data());
                psi = 0.5 * dot(phi.data(), phi.data(), m);
                err = error_of();
                if (s_.verbosity >= 2)
                    log_line(s_.log, "newton: watchdog: back to step %lld",
                             (long long)(counters.newton - s_.watchdog));
            }
        }
        if (s_.verbosity >= 2)
            log_line(s_.log, "newton: step %lld t %.3g error %.3e merit %.3e delta %.1e",
                     (long long)counters.newton, t, err, psi, delta);
        // During an excursion the callback sees the error of the point it may return to.
        lim.report(excursion.active ? excursion.err : err);
        if (err < best_err) {
            best_err = err;
            std::copy(r, r + m, best.begin());
        }
        if (best_err < 0.5 * ref_err) {
            ref_err = best_err;
            since_progress = 0;
        } else if ((!excursion.active && ++since_progress >= kStallSteps) ||
                   ls_failures >= kMaxLineSearchFailures) {
            res.status = FRIX_STATUS_STAGNATED;
            break;
        }
    }
    if (!(err <= best_err)) {
        std::copy(best.begin(), best.end(), r);
        err = best_err;
    }
    res.error = err;
    return FRIX_OK;
}

namespace {

frix_error solve(SolveContext &ctx, int solver_id) {
    const frix_problem &p = ctx.problem;
    const frix_options &o = ctx.options;
    if (!p.W || !p.W->block) return fail(FRIX_ERR_INTERNAL, "newton: W is not stored as 3x3 blocks");
    Settings s = settings_from(o, solver_id);
    const Monitor monitor(ctx);
    const double tol = monitor.tolerance();
    frix_info &info = ctx.info;
    int64_t iterations = 0;
    Limits lim{o, ctx.clock, &iterations, monitor.max_iterations()};
    lim.ctx = &ctx;
    Kept<KeptEngine> kept(ctx.cache, solver_id);
    s.weight = p.weight.data();
    Engine &engine = engine_for(*kept, ctx.cache, *p.W, p.mu, p.nc, s);
    RunResult res;
    std::unique_ptr<nsgs::Workspace> gs;  // made on the first fallback only
    std::vector<double> keep;
    int idle_rounds = 0;  // Newton + NSGS rounds in a row that did not halve the error
    double round_start = INFINITY;  // the error at the last halving
    while (true) {
        if (frix_error e = engine.run(ctx.r, p.q, 0.0, tol, lim, res)) return e;
        if (res.status != FRIX_STATUS_STAGNATED && res.status != FRIX_STATUS_NUMERICAL_FAILURE) break;
        if (s.hybrid != FRIX_HYBRID_NSGS) break;
        // Newton stalls (typically on rank-deficient W): NSGS sweeps move r to where the
        // active set is right, then Newton resumes from there. The better r is kept.
        if (!gs) {
            nsgs::Settings gss;
            gss.local.solver = local::kClosedForm;
            gs = std::make_unique<nsgs::Workspace>(p, gss);
        }
        keep.assign(ctx.r, ctx.r + 3 * p.nc);
        const double before = res.error;
        for (int64_t k = 0; k < s.hybrid_sweeps && iterations < lim.max_iter; ++k) {
            gs->sweep(ctx.r);
            ++engine.counters.sweeps;
            ++iterations;
        }
        const double after = selected_error(local_measures(p, ctx.r, ctx.u), s.measure);
        if (s.verbosity >= 1)
            log_line(s.log, "newton: stalled at %.3e, %lld NSGS sweeps -> %.3e", before,
                     (long long)s.hybrid_sweeps, after);
        lim.report(after);
        if (!(after <= before)) std::copy(keep.begin(), keep.end(), ctx.r);
        if (after <= tol) {
            res.status = FRIX_STATUS_CONVERGED;
            break;
        }
        if (after < 0.5 * round_start) {
            round_start = after;
            idle_rounds = 0;
        } else {
            ++idle_rounds;
        }
        if (idle_rounds >= kMaxIdleRounds) {
            res.status = FRIX_STATUS_STAGNATED;  // neither Newton nor NSGS makes progress
            break;
        }
        if (iterations >= lim.max_iter || lim.out_of_time() || lim.stop_requested) {
            res.status = lim.stop_requested  ? FRIX_STATUS_STOPPED_BY_CALLBACK
                         : lim.out_of_time() ? FRIX_STATUS_TIME_LIMIT
                                             : FRIX_STATUS_MAX_ITER;
            break;
        }
    }
    info.status = res.status;
    info.iterations = iterations;
    info.newton_iterations = engine.counters.newton;
    info.line_search_steps = engine.counters.line_search;
    info.hybrid_sweeps = engine.counters.sweeps;
    Monitor::record_factorizations(info, engine.factor_stats());
    if (s.verbosity >= 1)
        log_line(s.log, "newton: %s after %lld iterations (%lld Newton, %lld sweeps)",
                 frix_status_string(info.status), (long long)iterations,
                 (long long)engine.counters.newton, (long long)engine.counters.sweeps);
    kept.keep();
    return FRIX_OK;
}

frix_error solve_ac(SolveContext &ctx) { return solve(ctx, FRIX_SOLVER_NSN_AC); }
frix_error solve_fb(SolveContext &ctx) { return solve(ctx, FRIX_SOLVER_NSN_FB); }
frix_error solve_nm(SolveContext &ctx) { return solve(ctx, FRIX_SOLVER_NSN_NM); }

const frix_option_key kExtraKeys[] = {FRIX_OPT_RHO_STRATEGY, FRIX_OPT_RHO, FRIX_OPT_LINE_SEARCH,
                                      FRIX_OPT_LINE_SEARCH_MAX_ITER, FRIX_OPT_HYBRID,
                                      FRIX_OPT_HYBRID_SWEEPS, FRIX_OPT_WATCHDOG, (frix_option_key)0};

// The watchdog (kWatchdogTrigger) with 5 steps for Alart-Curnier and Fischer-Burmeister; not
// for the natural map, whose full steps it cuts short on problems the natural map solves.
const OptionDefault kAcDefaults[] = {{FRIX_OPT_MAX_ITER, 2000},
                                     {FRIX_OPT_RHO_STRATEGY, FRIX_RHO_SPECTRAL},
                                     {FRIX_OPT_WATCHDOG, 5},
                                     {(frix_option_key)0, 0}};
// FB and the natural map take rho = 1/W_NN (the split strategy's rho_N): with the spectral
// rho they stall on three of the rigid FCLIB problems (Capsules, spheres-in-a-box) that
// they solve with this one; Alart-Curnier is the other way round.
const OptionDefault kFbDefaults[] = {{FRIX_OPT_MAX_ITER, 2000},
                                     {FRIX_OPT_RHO_STRATEGY, FRIX_RHO_SPLIT},
                                     {FRIX_OPT_WATCHDOG, 5},
                                     {(frix_option_key)0, 0}};
const OptionDefault kNmDefaults[] = {{FRIX_OPT_MAX_ITER, 2000},
                                     {FRIX_OPT_RHO_STRATEGY, FRIX_RHO_SPLIT},
                                     {(frix_option_key)0, 0}};

#define FRIX_NEWTON_COMMON_DOC                                                                   \
    " The generalized Jacobian A + B W is assembled directly in sparse form from W's 3x3 "      \
    "blocks (pattern fixed for the solve: one UMFPACK symbolic analysis, one numeric "          \
    "factorisation per step); the step is damped by a line search on 1/2 |Phi|^2 "             \
    "(Goldstein-Price by default, Armijo, non-monotone Armijo or none). A singular Jacobian "  \
    "(rank-deficient W) is regularised as A + B (W + delta I) with delta adapted. With "        \
    "hybrid = nsgs (the default), a stalled Newton hands over to NSGS sweeps and resumes. "    \
    "Options: rho_strategy (constant, spectral, split), rho, line_search, "                    \
    "line_search_max_iter, hybrid, hybrid_sweeps, watchdog (where the line search stalls but the " \
    "full step halves the best error: the full step and k - 1 more, full too where the line "  \
    "search would cut them short, undone unless the error fell tenfold). Iterations count "     \
    "Newton steps plus fallback sweeps."

}  // namespace
}  // namespace newton

const SolverEntry kNsnAcEntry = {
    FRIX_SOLVER_NSN_AC, "nsn-ac", "FRICTION_3D_NSN_AC",
    "Semismooth Newton on the Alart-Curnier formulation Phi(r) = 0 (per contact: "
    "r_N - max(0, r_N - rho_N u_N) and r_T minus the projection of r_T - rho_T u_T on the disk "
    "of radius mu max(0, r_N - rho_N u_N))." FRIX_NEWTON_COMMON_DOC,
    newton::solve_ac, true, false, newton::kExtraKeys, newton::kAcDefaults};

const SolverEntry kNsnFbEntry = {
    FRIX_SOLVER_NSN_FB, "nsn-fb", "FRICTION_3D_NSN_FB",
    "Semismooth Newton on the Fischer-Burmeister function of the second-order cone "
    "complementarity K ∋ r ⟂ u^ ∈ K* (u^ the De Saxce velocity), after the sqrt(mu) scaling "
    "that maps K and K* onto the Lorentz cone." FRIX_NEWTON_COMMON_DOC,
    newton::solve_fb, true, false, newton::kExtraKeys, newton::kFbDefaults};

const SolverEntry kNsnNmEntry = {
    FRIX_SOLVER_NSN_NM, "nsn-nm", "FRICTION_3D_NSN_NM",
    "Semismooth Newton on the natural map Phi(r) = r - P_K(r - rho u^), the residual of the "
    "error measure (u^ the De Saxce velocity)." FRIX_NEWTON_COMMON_DOC,
    newton::solve_nm, true, false, newton::kExtraKeys, newton::kNmDefaults};

}  // namespace frix
