// rolling-nsn (3010): proximal semismooth Newton on rolling-friction problems (five entries a
// contact, six with spinning friction), for tight tolerances where W has full rank. Each
// proximal step (PROX's rule on W + alpha I, which a rank-deficient W needs) is solved by a
// Newton on the Alart-Curnier function of each contact (kit/local_rolling.hpp) in the contact's
// units (moments in units of force, as the sweeps' one-contact solver has them); the Jacobian
// A + B (W + alpha) is assembled from W's n x n blocks (the local form's, or H^T M^-1 H formed
// body by body for rigid bodies) and factorised by UMFPACK; the loop, line search,
// regularisation and status are the Newton kit's (kit/newton_engine.hpp).
// Id 3010, not 3001-3003: those are Siconos's rolling one-contact solvers and ADMM.
#include <algorithm>
#include <cmath>
#include <vector>

#include "solvers/entries.hpp"
#include "solvers/kit/local_rolling.hpp"
#include "solvers/kit/newton_engine.hpp"
#include "solvers/kit/rolling_forms.hpp"
#include "src/error_state.hpp"
#include "src/linalg/linalg.hpp"
#include "src/log.hpp"
#include "src/matrix.hpp"
#include "src/monitor.hpp"
#include "src/vec.hpp"

namespace frix {
namespace rolling_newton {
namespace {

using local_rolling::with_size;
using vec::dot;

// J = A + B (W + reg), A and B block-diagonal (n^2 values a contact, n = W.size), reg diagonal
// (n a contact), on W's block pattern plus the diagonal blocks, stored as the CSC of J^T (J's
// rows: they are W's block rows), so that the transposed solve gives J x = b.
class Jacobian {
   public:
    explicit Jacobian(const rolling::BlockRows &W) : W_(W) {
        const int64_t nc = (int64_t)W.row_ptr.size() - 1, n = W.size;
        slot_ptr_.assign((size_t)nc + 1, 0);
        for (int64_t a = 0; a < nc; ++a) {
            const size_t first = slots_.size();
            for (int64_t k = W.row_ptr[(size_t)a]; k < W.row_ptr[(size_t)a + 1]; ++k)
                slots_.push_back({W.block_col[(size_t)k], k});
            if (W.diag[(size_t)a] < 0) {
                slots_.push_back({a, -1});
                std::sort(slots_.begin() + (std::ptrdiff_t)first, slots_.end(),
                          [](const Slot &x, const Slot &y) { return x.col < y.col; });
            }
            slot_ptr_[(size_t)a + 1] = (int64_t)slots_.size();
        }
        ptr_.assign((size_t)(n * nc) + 1, 0);
        for (int64_t a = 0; a < nc; ++a)
            for (int64_t i = 0; i < n; ++i)
                ptr_[(size_t)(n * a + i + 1)] =
                    ptr_[(size_t)(n * a + i)] + n * (slot_ptr_[(size_t)a + 1] - slot_ptr_[(size_t)a]);
        ind_.resize((size_t)ptr_.back());
        val_.assign(ind_.size(), 0.0);
        for (int64_t a = 0; a < nc; ++a)
            for (int64_t i = 0; i < n; ++i) {
                int64_t at = ptr_[(size_t)(n * a + i)];
                for (int64_t s = slot_ptr_[(size_t)a]; s < slot_ptr_[(size_t)a + 1]; ++s)
                    for (int64_t j = 0; j < n; ++j) ind_[(size_t)at++] = n * slots_[(size_t)s].col + j;
            }
    }
    void assemble(const double *A, const double *B, const double *reg) {
        with_size(W_.size, [&](auto n) { assemble_sized<decltype(n)::value>(A, B, reg); });
    }
    linalg::CscView view() const {
        const int64_t m = (int64_t)ptr_.size() - 1;
        return linalg::CscView{m, m, ptr_.data(), ind_.data(), val_.data()};
    }

   private:
    template <int N>
    void assemble_sized(const double *A, const double *B, const double *reg) {
        const int64_t nc = (int64_t)slot_ptr_.size() - 1;
        for (int64_t a = 0; a < nc; ++a) {
            const double *Aa = A + N * N * a, *Ba = B + N * N * a;
            const int64_t width = N * (slot_ptr_[(size_t)a + 1] - slot_ptr_[(size_t)a]);
            for (int64_t s = slot_ptr_[(size_t)a]; s < slot_ptr_[(size_t)a + 1]; ++s) {
                const Slot &sl = slots_[(size_t)s];
                double blk[N * N] = {};
                if (sl.w >= 0) {
                    const double *Wk = &W_.val[N * N * (size_t)sl.w];
                    for (int j = 0; j < N; ++j)
                        for (int k = 0; k < N; ++k)
                            for (int i = 0; i < N; ++i) blk[i + N * j] += Ba[i + N * k] * Wk[k + N * j];
                }
                if (sl.col == a)
                    for (int j = 0; j < N; ++j)
                        for (int i = 0; i < N; ++i) blk[i + N * j] += Aa[i + N * j] + Ba[i + N * j] * reg[N * a + j];
                const int64_t off = N * (s - slot_ptr_[(size_t)a]);
                for (int i = 0; i < N; ++i)
                    for (int j = 0; j < N; ++j)
                        val_[(size_t)(ptr_[(size_t)(N * a)] + i * width + off + j)] = blk[i + N * j];
            }
        }
    }
    struct Slot {
        int64_t col, w;  // block column; W's block (-1: a diagonal block W lacks)
    };
    const rolling::BlockRows &W_;
    std::vector<Slot> slots_;
    std::vector<int64_t> slot_ptr_, ptr_, ind_;
    std::vector<double> val_;
};

// A run's Newton system (kit/newton_engine.hpp) on r (the caller's, in place): F(r) the
// contacts' Alart-Curnier functions in their units, F_a = F_AC(r'_a, u'_a) with r'_a =
// T_a^-1 r_a, u'_a = T_a u_a, T_a = diag(1, 1, 1, L_a, L_a[, L_a]) (local_rolling::alart_curnier); its
// Jacobian in r is A + B W with A_a = A'_a T_a^-1 and B_a = B'_a T_a (A', B' its blocks in
// the contact's units).
class System : public kit::SystemDefaults, public kit::InPlaceIterate {
   public:
    static constexpr bool kWatchable = true;

    System(const frix_problem &p, rolling::SweepForm &form, const rolling::BlockRows &W, const std::vector<double> &q,
           const std::vector<local_rolling::Contact> &contacts, double *r, const frix_options &o,
           const Monitor &monitor)
        : InPlaceIterate(r, W.size * (int64_t)contacts.size()),
          log_(&o),
          n_(W.size),
          problem_(&p),
          norm_q_(norm2(q.data(), (int64_t)q.size())),
          form_(form),
          W_(W),
          q_(q),
          c_(contacts),
          measure_(o.i(FRIX_OPT_ERROR_MEASURE)),
          jac_(W),
          A_(n_ * m_),
          B_(n_ * m_),
          reg_(m_),
          shift_(m_),
          F_(m_),
          rhs_(m_),
          Ft_(m_),
          scratch_(m_) {
        lu_.set_budget(monitor.budget());
        double sum = 0.0;  // the mean |W'_aa|_inf: delta's unit
        for (const local_rolling::Contact &c : c_) sum += c.degenerate ? 0.0 : 1.0 / c.rho0;
        w_scale_ = !c_.empty() && sum > 0.0 ? sum / (double)c_.size() : 1.0;
    }
    // The proximal problem of PROX: u = W r + q + alpha T^-2 (r - anchor) (W' + alpha I in the
    // contacts' units, alpha in units of the mean |W'_aa|), whose W' + alpha I has full rank when
    // W does not; alpha = 0: the problem itself.
    void set_proximal(double alpha, const double *anchor) {
        for (size_t a = 0; a < c_.size(); ++a)
            for (int i = 0; i < n_; ++i)
                shift_[n_ * a + i] = alpha * w_scale_ / (i >= 3 ? c_[a].length * c_[a].length : 1.0);
        alpha_ = alpha;
        anchor_ = anchor;
    }
    frix_error evaluate(double &psi, double &err) {
        velocity(r_, u_.data());
        equations(r_, u_.data(), F_.data(), true);
        psi = 0.5 * dot(F_.data(), F_.data(), m_);
        err = error_at(r_, u_.data());
        return FRIX_OK;
    }
    // The error of the problem itself at the iterate.
    double error() { return selected_error(form_.exact(r_, scratch_.data()), measure_); }
    frix_error factor(double delta, kit::Factorisation &f) {
        for (size_t a = 0; a < c_.size(); ++a)  // W' + delta I in the contact's units
            for (int i = 0; i < n_; ++i)
                reg_[n_ * a + i] = shift_[n_ * a + i] + delta * w_scale_ / (i >= 3 ? c_[a].length * c_[a].length : 1.0);
        jac_.assemble(A_.data(), B_.data(), reg_.data());
        if (!analysed_) {
            if (frix_error e = lu_.analyze(jac_.view()))
                return e == FRIX_ERR_OUT_OF_MEMORY ? e : (clear_error(), FRIX_OK);
            analysed_ = true;
        }
        const frix_error e = lu_.factor(jac_.view());
        f.factored = e == FRIX_OK && lu_.rcond() > 1e-15;
        f.refused = lu_.refused();
        if (e && e != FRIX_ERR_OUT_OF_MEMORY) clear_error();
        return e == FRIX_ERR_OUT_OF_MEMORY ? e : FRIX_OK;
    }
    frix_error solve(bool &finite) {
        for (int64_t i = 0; i < m_; ++i) rhs_[i] = -F_[i];
        if (frix_error e = lu_.solve(rhs_.data(), d_.data(), true)) return e;
        finite = vec::all_finite(d_.data(), (int64_t)d_.size());
        return FRIX_OK;
    }
    // The merit's slope along d: F . (A d + B (W + shift) d).
    frix_error directional(double &slope) {
        W_.multiply(d_.data(), du_.data());
        for (int64_t i = 0; i < m_; ++i) du_[i] += shift_[i] * d_[i];
        slope = with_size(n_, [&](auto n) { return slope_sized<decltype(n)::value>(); });
        return FRIX_OK;
    }
    double merit_at(double t) {
        along(t);
        equations(rt_.data(), ut_.data(), Ft_.data(), false);
        return 0.5 * dot(Ft_.data(), Ft_.data(), m_);
    }
    frix_error full_step_error(double &err) {
        along(1.0);
        err = error_at(rt_.data(), ut_.data());
        return FRIX_OK;
    }
    const linalg::SparseLU &lu() const { return lu_; }
    void log_step(int64_t step, double t, double err, double psi, double delta) const {
        if (log_->i(FRIX_OPT_VERBOSITY) >= 2)
            log_line(log_, "rolling-nsn: step %lld t %.3g error %.3e merit %.3e delta %.1e", (long long)step, t, err,
                     psi, delta);
    }

   private:
    // F . (A d + B du), contact by contact (N entries each).
    template <int N>
    double slope_sized() const {
        double slope = 0.0;
        for (int64_t a = 0; a < m_ / N; ++a) {
            const double *Aa = &A_[N * N * a], *Ba = &B_[N * N * a], *d = &d_[N * a], *du = &du_[N * a];
            for (int i = 0; i < N; ++i) {
                double s = 0.0;
                for (int j = 0; j < N; ++j) s += Aa[i + N * j] * d[j] + Ba[i + N * j] * du[j];
                slope += F_[N * a + i] * s;
            }
        }
        return slope;
    }
    void velocity(const double *r, double *u) const {
        W_.multiply(r, u);
        for (int64_t i = 0; i < m_; ++i) u[i] += q_[(size_t)i];
        if (alpha_ > 0.0)
            for (int64_t i = 0; i < m_; ++i) u[i] += shift_[i] * (r[i] - anchor_[i]);
    }
    // F at (r, u), with A and B when jacobian.
    void equations(const double *r, const double *u, double *F, bool jacobian) {
        const int n = n_;
        for (size_t a = 0; a < c_.size(); ++a) {
            const local_rolling::Contact &c = c_[a];
            const double L = c.length, *ra = r + n * a, *ua = u + n * a;
            double rs[local_rolling::kMaxSize], us[local_rolling::kMaxSize];
            for (int i = 0; i < n; ++i) rs[i] = i >= 3 ? ra[i] / L : ra[i], us[i] = i >= 3 ? ua[i] * L : ua[i];
            double *Aa = jacobian ? &A_[(size_t)(n * n) * a] : nullptr;
            double *Ba = jacobian ? &B_[(size_t)(n * n) * a] : nullptr;
            local_rolling::alart_curnier(rs, us, c.cones(), c.rho0, F + n * a, Aa, Ba);
            if (!jacobian) continue;
            for (int i = 0; i < n; ++i)
                for (int j = 3; j < n; ++j) Aa[i + n * j] /= L, Ba[i + n * j] *= L;
        }
    }
    // The error of the problem solved (the proximal one when alpha > 0), u its velocity at r.
    double error_at(const double *r, const double *u) {
        if (alpha_ == 0.0) return selected_error(form_.exact(r, scratch_.data()), measure_);
        const frix_problem &p = *problem_;
        return selected_error(rolling_measures_from_ru(p, r, u, norm_q_), measure_);
    }

    const frix_options *log_;
    const int n_;  // entries a contact
    const frix_problem *problem_;
    double norm_q_;
    double alpha_ = 0.0;
    const double *anchor_ = nullptr;
    rolling::SweepForm &form_;
    const rolling::BlockRows &W_;
    const std::vector<double> &q_;
    const std::vector<local_rolling::Contact> &c_;
    const int64_t measure_;
    Jacobian jac_;
    linalg::SparseLU lu_;
    bool analysed_ = false;
    double w_scale_ = 1.0;
    std::vector<double> A_, B_, reg_, shift_, F_, rhs_, Ft_, scratch_;
};

// Proximal steps: PROX's outer rule (prox.cpp), alpha = sigma error^nu (in units of the mean
// |W'_aa|), at least tenfold lower after a solved inner problem and tenfold higher after a
// failed one, a step that does not lower the error undone, and a stop where alpha comes back
// to a value already tried from the same iterate.
constexpr int64_t kInnerMaxIter = 50;
constexpr double kAlphaMin = 1e-12, kAlphaMax = 1e6;

frix_error run(SolveContext &ctx, rolling::SweepForm &form, const rolling::BlockRows &W, const std::vector<double> &q) {
    const frix_options &o = ctx.options;
    const Monitor monitor(ctx);
    const double tol = monitor.tolerance(), sigma = o.d(FRIX_OPT_PROX_SIGMA), nu = o.d(FRIX_OPT_PROX_NU);
    // The Newton steps, on each proximal step's limits; their errors are the inner problems'.
    kit::Steps inner{Monitor(ctx), kit::Steps::Errors::kOfAnInnerProblem};
    const std::vector<local_rolling::Contact> contacts = rolling::contacts_of(form, ctx.problem);
    double *r = ctx.r;
    System sys(ctx.problem, form, W, q, contacts, r, o, inner.monitor);
    kit::Counters counters;
    kit::Rules rules;
    rules.search = kit::search_of((int)o.i(FRIX_OPT_LINE_SEARCH), (int)o.i(FRIX_OPT_LINE_SEARCH_MAX_ITER));
    rules.delta_start = 0.0;            // alpha regularises J already
    rules.full_step_on_failure = true;  // PROX's rule: short steps stall on the regularised problems
    const auto adapted = [&](double err) { return std::clamp(sigma * std::pow(err, nu), kAlphaMin, kAlphaMax); };
    const int64_t m = contact_size(ctx.problem) * ctx.problem.nc;
    std::vector<double> rk(r, r + m), tried;
    double err = sys.error(), alpha = adapted(err);
    int64_t outer = 0;
    frix_status status = FRIX_STATUS_NOT_RUN;
    while (status == FRIX_STATUS_NOT_RUN) {
        status = kit::status_before_step(monitor, err, inner.done, inner);
        if (status == FRIX_STATUS_NOT_RUN && std::find(tried.begin(), tried.end(), alpha) != tried.end())
            status = FRIX_STATUS_STAGNATED;
        if (status != FRIX_STATUS_NOT_RUN) break;
        tried.push_back(alpha);
        ++outer;
        sys.set_proximal(alpha, rk.data());
        inner.monitor.with_limits(0.1 * std::max(err, tol),
                                  std::min(inner.done + kInnerMaxIter, monitor.max_iterations()));
        kit::RunResult res;
        if (frix_error e = kit::newton(sys, inner, rules, counters, res)) return e;
        status = kit::status_after_step(monitor, res.status);
        if (status != FRIX_STATUS_NOT_RUN) {
            std::copy(rk.begin(), rk.end(), r);
            break;
        }
        const double e_new = sys.error();
        if (o.i(FRIX_OPT_VERBOSITY) >= 1)
            log_line(&o, "rolling-nsn: step %lld alpha %.3e inner %s (%.2e) error %.3e", (long long)outer, alpha,
                     frix_status_string(res.status), res.error, e_new);
        if (e_new < err) {  // progress on the problem itself: the step is kept
            err = e_new;
            std::copy(r, r + m, rk.begin());
            tried.clear();
        } else {
            std::copy(rk.begin(), rk.end(), r);
        }
        const bool inner_ok = res.status == FRIX_STATUS_CONVERGED;
        alpha = inner_ok ? std::max(std::min(adapted(err), 0.1 * alpha), kAlphaMin) : std::min(alpha * 10.0, kAlphaMax);
        inner.report_measured(err);
    }
    std::copy(rk.begin(), rk.end(), r);  // the last accepted proximal iterate
    frix_info &info = ctx.info;
    info.status = status;
    info.error = err;
    info.iterations = inner.done;  // Newton steps: what a step costs (a factorisation)
    info.newton_iterations = counters.newton;
    info.line_search_steps = counters.line_search;
    Monitor::record_factorizations(info, sys.lu().stats());
    if (o.i(FRIX_OPT_VERBOSITY) >= 1)
        log_line(&o, "rolling-nsn: %s after %lld proximal steps (%lld Newton)", frix_status_string(status),
                 (long long)outer, (long long)counters.newton);
    return FRIX_OK;
}

// What a run takes at least on W's pattern of n x n blocks, known before W's values: its memory,
// the Jacobian (its values and row indices, and a slot a block) and its LU, which holds at least
// as many entries, and at least the values of L and U counted under a fill-reducing ordering of
// the symmetrised block pattern (on sphere piles many times the Jacobian: UMFPACK's own
// analysis would say so only after W and the Jacobian are formed); and the flops of that LU's
// first factorisation (none counted where the analysis fails: the time left then decides alone).
// W's own values come on top where the run forms W.
linalg::FactorPrice newton_price(const rolling::BlockRows &pattern) {
    const auto blocks = (double)pattern.block_col.size(), n = (double)pattern.size;
    const auto nc = (int64_t)pattern.row_ptr.size() - 1;
    linalg::FactorPrice price;
    double lu_bytes = 16.0 * n * n * blocks;
    linalg::FactorCost cost;
    std::vector<int64_t> colptr, rowind;
    if (nc > 0) block_graph(nc, pattern.row_ptr.data(), pattern.block_col.data(), colptr, rowind);
    if (nc > 0 && linalg::cholesky_cost({nc, nc, colptr.data(), rowind.data(), nullptr}, &cost) == FRIX_OK) {
        // L and U share the diagonal; each block operation is n^3 flops.
        lu_bytes = std::max(lu_bytes, 8.0 * n * n * (2.0 * cost.factor_entries - (double)nc));
        price.flops = 2.0 * cost.flops * n * n * n;
    } else {
        clear_error();  // the Jacobian's size alone
    }
    price.bytes = blocks * (16.0 * n * n + 16.0) + lu_bytes;
    return price;
}

// The run refused before it formed anything, for the limit `status` names: r as it was,
// measured once, into ctx.u (neither solve_on_form's last exact() nor, on the local form, the
// driver measure it again).
frix_error refuse_before_w(SolveContext &ctx, rolling::SweepForm &form, const linalg::FactorPrice &price,
                           frix_status status, bool &measured_at_r) {
    ctx.info.status = status;
    ctx.measured = form.exact(ctx.r, ctx.u);
    ctx.has_measured = ctx.problem.kind == FRIX_PROBLEM_ROLLING_LOCAL;  // the driver's own measure
    ctx.info.error = selected_error(ctx.measured, ctx.options.i(FRIX_OPT_ERROR_MEASURE));
    measured_at_r = true;
    ctx.info.iterations = 0;
    if (ctx.options.i(FRIX_OPT_VERBOSITY) >= 1)
        log_line(&ctx.options,
                 "rolling-nsn: W and its Newton system need at least %.3g MB and %.3g flops, more than the %s left",
                 price.bytes / 1e6, price.flops, status == FRIX_STATUS_MEMORY_LIMIT ? "memory" : "time");
    return FRIX_OK;
}

// run on either form: the local form's W and q as they are, the bodies' W = H^T M^-1 H and q
// formed body by body; neither where the time or memory left cannot hold the Newton system.
struct RunOnForm {
    SolveContext &ctx;
    bool &measured_at_r;
    frix_error operator()(rolling::RowForm &rows) const {
        const frix_problem &p = ctx.problem;
        const linalg::FactorPrice price = newton_price(rows.rows());
        if (const frix_status refused = Monitor(ctx).affords(price))
            return refuse_before_w(ctx, rows, price, refused, measured_at_r);
        const std::vector<double> q(p.q, p.q + contact_size(p) * p.nc);
        return run(ctx, rows, rows.rows(), q);
    }
    frix_error operator()(rolling::BodyForm &bodies) const {
        rolling::BlockRows W;
        std::vector<double> q((size_t)(contact_size(ctx.problem) * ctx.problem.nc));
        const Monitor monitor(ctx);
        const int n = bodies.size();
        linalg::FactorPrice price;
        frix_status refused = FRIX_STATUS_NOT_RUN;
        const auto fits = [&](const rolling::BlockRows &pattern) {
            price = newton_price(pattern);
            price.bytes += 8.0 * n * n * (double)pattern.block_col.size();
            refused = monitor.affords(price);
            return refused == FRIX_STATUS_NOT_RUN;
        };
        if (!bodies.reduce(W, q.data(), fits)) return refuse_before_w(ctx, bodies, price, refused, measured_at_r);
        return run(ctx, bodies, W, q);
    }
};

frix_error solve(SolveContext &ctx) {
    bool measured_at_r = false;
    return rolling::solve_on_form(ctx, "rolling-nsn", RunOnForm{ctx, measured_at_r}, 0, &measured_at_r);
}

const frix_option_key kExtraKeys[] = {FRIX_OPT_PROX_SIGMA, FRIX_OPT_PROX_NU, FRIX_OPT_LINE_SEARCH,
                                      FRIX_OPT_LINE_SEARCH_MAX_ITER, (frix_option_key)0};

const OptionDefault kDefaults[] = {{FRIX_OPT_MAX_ITER, 2000}, {(frix_option_key)0, 0}};

}  // namespace
}  // namespace rolling_newton

const SolverEntry kRollingNsnEntry = {
    FRIX_SOLVER_ROLLING_NSN,
    "rolling-nsn",
    nullptr,  // Siconos 4.4 has no Newton for rolling friction
    "Proximal semismooth Newton for rolling-friction problems (five entries a contact, six "
    "with spinning friction), for "
    "tight tolerances: proximal point steps on W + alpha I (alpha = prox_sigma error^prox_nu in "
    "units of the mean |W_aa|, lowered at least tenfold after a solved step, raised tenfold "
    "after a failed one; a step that does not lower the error is undone), each solved by a "
    "semismooth Newton on the Alart-Curnier function of the rolling law (Signorini, and "
    "Coulomb's law in the sliding disk of radius mu r_N, in the rolling disk of radius "
    "mu_r r_N and on the spinning interval of half-width mu_s r_N), per contact in units where "
    "moments are forces (m / L, L = sqrt(tr W_TT / tr "
    "W_RR)) with rho = 1 / |W_aa|_inf in those units. The Jacobian A + B (W + alpha) is "
    "assembled from W's 5x5 (6x6) blocks (local problems) or from H^T M^-1 H formed body by body "
    "(global problems of rigid bodies, M block-diagonal with blocks of at most 64 dofs; a "
    "deformable M is refused) and factorised by UMFPACK each step; the step is damped by a "
    "line search on 1/2 |F|^2. Converges in a few steps where W has full rank; on rigid "
    "sphere piles (rank-deficient W) it stalls, where rolling-nsgs is the solver. Options: "
    "prox_sigma, prox_nu, line_search, line_search_max_iter; iterations (and max_iter) count "
    "Newton steps, each one factorisation.",
    rolling_newton::solve,
    false,  // rolling problems only, in both forms
    false,
    rolling_newton::kExtraKeys,
    rolling_newton::kDefaults,
    true,
};

}  // namespace frix
