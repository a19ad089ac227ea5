// Route (b) of global problems, solver 607: semismooth Newton on (v, r), W never formed.
#include "solvers/kit/global_newton.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "solvers/kit/mass_plus_contacts.hpp"
#include "solvers/kit/newton.hpp"
#include "solvers/kit/nsn_functions.hpp"
#include "src/error_state.hpp"
#include "src/linalg/linalg.hpp"
#include "src/log.hpp"
#include "src/matrix.hpp"
#include "src/measures.hpp"
#include "src/monitor.hpp"
#include "src/reduction.hpp"
#include "src/vec.hpp"
#include "solvers/entries.hpp"

namespace frix {

// ---- Route (b): semismooth Newton (Alart-Curnier) on (v, r).
namespace gnsn_ac {

namespace {

// The Jacobian [[M, -H], [B H^T, A]] in CSC with a fixed pattern; the dynamic entries are
// listed with where their value comes from.
struct Jacobian {
    int64_t n = 0, m = 0, size = 0;
    Csc J;
    // B H^T entries: slot, contact a, row i of the block, and H(j, 3a..3a+2).
    struct BHEntry {
        int64_t slot, a;
        int i;
        double h[3];
    };
    std::vector<BHEntry> bh;
    std::vector<int64_t> a_slot;  // 9 per contact: slot of A(i, c), column-major

    void build(const Csc &M, const Csc &H, int64_t nc) {
        n = M.rows;
        m = 3 * nc;
        size = n + m;
        struct E {
            int64_t col, row;
            int kind;  // 0 M, 1 -H, 2 BH, 3 A
            int64_t src;
            int64_t a;
            int i, c;
        };
        std::vector<E> es;
        for (int64_t j = 0; j < n; ++j)
            for (int64_t e = M.colptr[j]; e < M.colptr[j + 1]; ++e) es.push_back({j, M.rowind[e], 0, e, 0, 0, 0});
        for (int64_t k = 0; k < m; ++k)
            for (int64_t e = H.colptr[k]; e < H.colptr[k + 1]; ++e)
                es.push_back({n + k, H.rowind[e], 1, e, 0, 0, 0});
        // Rows of H used by contact a (the union over its 3 columns).
        std::vector<int64_t> mark(n, -1), rows;
        for (int64_t a = 0; a < nc; ++a) {
            rows.clear();
            for (int c = 0; c < 3; ++c)
                for (int64_t e = H.colptr[3 * a + c]; e < H.colptr[3 * a + c + 1]; ++e)
                    if (mark[H.rowind[e]] != a) {
                        mark[H.rowind[e]] = a;
                        rows.push_back(H.rowind[e]);
                    }
            for (int64_t j : rows)
                for (int i = 0; i < 3; ++i) es.push_back({j, n + 3 * a + i, 2, j, a, i, 0});
            for (int c = 0; c < 3; ++c)
                for (int i = 0; i < 3; ++i) es.push_back({n + 3 * a + c, n + 3 * a + i, 3, 0, a, i, c});
        }
        std::sort(es.begin(), es.end(), [](const E &x, const E &y) {
            return x.col != y.col ? x.col < y.col : x.row < y.row;
        });
        J.rows = J.cols = size;
        J.colptr.assign(size + 1, 0);
        J.rowind.resize(es.size());
        J.val.assign(es.size(), 0.0);
        a_slot.assign(9 * nc, 0);
        bh.clear();
        // H(j, col) lookup for the BH entries.
        auto h_at = [&](int64_t j, int64_t col) {
            auto first = H.rowind.begin() + H.colptr[col], last = H.rowind.begin() + H.colptr[col + 1];
            auto it = std::lower_bound(first, last, j);
            return (it != last && *it == j) ? H.val[it - H.rowind.begin()] : 0.0;
        };
        for (size_t s = 0; s < es.size(); ++s) {
            const E &e = es[s];
            ++J.colptr[e.col + 1];
            J.rowind[s] = e.row;
            switch (e.kind) {
                case 0: J.val[s] = M.val[e.src]; break;
                case 1: J.val[s] = -H.val[e.src]; break;
                case 2: {
                    BHEntry b{(int64_t)s, e.a, e.i, {0, 0, 0}};
                    for (int c = 0; c < 3; ++c) b.h[c] = h_at(e.src, 3 * e.a + c);
                    bh.push_back(b);
                    break;
                }
                default: a_slot[9 * e.a + e.i + 3 * e.c] = (int64_t)s; break;
            }
        }
        for (int64_t c = 0; c < size; ++c) J.colptr[c + 1] += J.colptr[c];
    }

    // The dynamic entries for A + delta B and B.
    void assemble(const std::vector<double> &A, const std::vector<double> &B, double delta) {
        for (const BHEntry &e : bh) {
            const double *Ba = &B[9 * e.a];
            J.val[e.slot] = Ba[e.i] * e.h[0] + Ba[e.i + 3] * e.h[1] + Ba[e.i + 6] * e.h[2];
        }
        for (size_t k = 0; k < a_slot.size(); ++k) J.val[a_slot[k]] = A[k] + delta * B[k];
    }
};

using vec::dot;

// How much the lumped blocks H_a^T diag(M)^-1 H_a underrate W's diagonal blocks: the median,
// over up to kRhoSamples contacts spread over the problem, of trace(H_a^T M^-1 H_a) over
// trace(H_a^T diag(M)^-1 H_a), from the driver's factorisation of M.
// 1 for a diagonal M (rigid bodies with diagonal inertia); far above on a stiff deformable
// body, where diag(M)^-1 ignores that the body moves as a whole.
double lumped_underrate(const frix_problem &p, const Csc &H, MassSolver &mass,
                        const std::vector<double> &lumped_trace) {
    std::vector<double> ratios;
    for (const auto &sample : sampled_delassus_diagonals(p, H, mass, kRhoSamples, 3)) {
        const double lumped = lumped_trace[sample.first], exact = sample.second;
        if (lumped > 0.0 && std::isfinite(exact)) ratios.push_back(exact / lumped);
    }
    if (ratios.empty()) return 1.0;
    std::nth_element(ratios.begin(), ratios.begin() + ratios.size() / 2, ratios.end());
    return ratios[ratios.size() / 2];
}

// rho from the lumped Delassus blocks H_a^T diag(M)^-1 H_a (W itself is never formed), scaled
// where they underrate W's; and the blocks' scale (mean |W_aa|), delta's unit.
struct LumpedRho {
    std::vector<double> rho_n, rho_t;
    double scale = 1.0;
};
LumpedRho lumped_rho(const SolveContext &ctx, const Csc &M, const Csc &H, const newton::Settings &s) {
    const frix_problem &p = ctx.problem;
    const int64_t n = p.n, nc = p.nc;
    std::vector<double> dinv(n, 0.0);
    for (int64_t j = 0; j < n; ++j)
        for (int64_t e = M.colptr[j]; e < M.colptr[j + 1]; ++e)
            if (M.rowind[e] == j && M.val[e] > 0.0) dinv[j] = 1.0 / M.val[e];
    std::vector<double> lumped(9 * nc, 0.0), lumped_trace(nc, 0.0);
    for (int64_t a = 0; a < nc; ++a) {
        double *Wd = &lumped[9 * a];
        for (int c1 = 0; c1 < 3; ++c1)
            for (int c2 = 0; c2 < 3; ++c2) {
                // sum_j H(j, 3a+c1) H(j, 3a+c2) / M_jj over the shared rows (both sorted).
                int64_t e1 = H.colptr[3 * a + c1], e2 = H.colptr[3 * a + c2];
                const int64_t f1 = H.colptr[3 * a + c1 + 1], f2 = H.colptr[3 * a + c2 + 1];
                double sum = 0.0;
                while (e1 < f1 && e2 < f2) {
                    if (H.rowind[e1] < H.rowind[e2]) ++e1;
                    else if (H.rowind[e2] < H.rowind[e1]) ++e2;
                    else {
                        sum += H.val[e1] * H.val[e2] * dinv[H.rowind[e1]];
                        ++e1, ++e2;
                    }
                }
                Wd[c1 + 3 * c2] = sum;
            }
        lumped_trace[a] = Wd[0] + Wd[4] + Wd[8];
    }
    // On a stiff deformable body diag(M)^-1 underrates M^-1 by orders of magnitude and rho from
    // the lumped blocks is as much too large (no step accepted, even with rho cut); a few exact
    // blocks give the factor.
    const double underrate =
        ctx.mass && s.rho_strategy != FRIX_RHO_CONSTANT ? lumped_underrate(p, H, *ctx.mass, lumped_trace)
                                                              : 1.0;
    const double correction = underrate > kUnderrateToCorrect ? underrate : 1.0;
    if (s.verbosity >= 1 && underrate != 1.0)
        log_line(&ctx.options, "global newton: the lumped blocks underrate W's by %.3g%s", underrate,
                 correction != 1.0 ? ": rho corrected" : "");
    LumpedRho out;
    out.rho_n.resize(nc), out.rho_t.resize(nc);
    double wscale = 0.0;
    for (int64_t a = 0; a < nc; ++a) {
        double Wd[9];
        for (int k = 0; k < 9; ++k) Wd[k] = correction * lumped[9 * a + k];
        nsn::contact_rho(s.rho_strategy, s.rho, Wd, &out.rho_n[a], &out.rho_t[a]);
        double fro = 0.0;
        for (double x : Wd) fro += x * x;
        wscale += std::sqrt(fro);
    }
    out.scale = nc > 0 && wscale > 0.0 ? wscale / (double)nc : 1.0;
    return out;
}

// Route (b)'s Newton system for kit::NewtonLoop: unknowns (v, r) in ctx.v and ctx.r, equations
// M v - H r - f = 0 and Phi(r, H^T v + w) = 0, merit 1/2 (|M v - H r - f|^2 + |Phi|^2).
class VrSystem : public kit::SystemDefaults {
   public:
    struct Point {
        std::vector<double> r, v;
    };
    VrSystem(SolveContext &ctx, const Csc &M, const Csc &H, LumpedRho rho, int64_t measure)
        : ctx_(ctx), p_(ctx.problem), n_(p_.n), nc_(p_.nc), m_(3 * p_.nc), rho_(std::move(rho)), measure_(measure),
          A_(9 * nc_), B_(9 * nc_), phi_(m_), res_(n_), dx_(n_ + m_), rhs_(n_ + m_), Mdv_(n_), Hdr_(n_), Htdv_(m_),
          rt_(m_), ut_(m_), phit_(m_), rest_(n_), vt_(n_) {
        jac_.build(M, H, nc_);
        // M's pattern is a mesh's for a deformable body, where nested dissection leaves far less
        // fill than AMD (notes/2026-11-28-newton-kit.md).
        lu_.set_ordering(linalg::SparseLU::Ordering::kNestedDissection);
        lu_.set_strategy_by_pivoting(true);
        lu_.set_budget(Monitor(ctx).budget());
    }
    frix_error evaluate(double &psi, double &err) {
        psi = merit(ctx_.r, ctx_.v, ctx_.u, res_.data(), phi_.data(), true);
        const Measures meas = global_measures(p_, ctx_.r, ctx_.v, ctx_.u, &equilibrium_);
        err = selected_error(meas, measure_);
        return FRIX_OK;
    }
    frix_error factor(double delta, kit::Factorisation &f) {
        jac_.assemble(A_, B_, delta * rho_.scale);
        if (lu_.stats().symbolic == 0)
            if (frix_error e = lu_.analyze(jac_.J.view())) return e;
        const frix_error e = lu_.factor(jac_.J.view());
        if (e == FRIX_ERR_OUT_OF_MEMORY) return e;
        f.factored = e == FRIX_OK && lu_.rcond() > 1e-15;
        f.refused = lu_.refused();
        return FRIX_OK;
    }
    frix_error solve(bool &finite) {
        for (int64_t j = 0; j < n_; ++j) rhs_[j] = -res_[j];
        for (int64_t i = 0; i < m_; ++i) rhs_[n_ + i] = -phi_[i];
        if (frix_error e = lu_.solve(rhs_.data(), dx_.data())) return e;
        for (int64_t i = 0; i < n_ + m_ && finite; ++i) finite = std::isfinite(dx_[i]);
        return FRIX_OK;
    }
    // Slope of the merit: res . (M dv - H dr) + Phi . (A dr + B H^T dv).
    frix_error directional(double &slope) {
        const double *dv = dx_.data(), *dr = dx_.data() + n_;
        matrix_gemv(*p_.M, 1.0, dv, 0.0, Mdv_.data());
        if (nc_ > 0) {
            matrix_gemv(*p_.H, 1.0, dr, 0.0, Hdr_.data());
            matrix_gemv_transposed(*p_.H, 1.0, dv, 0.0, Htdv_.data());
        }
        slope = 0.0;
        for (int64_t j = 0; j < n_; ++j) slope += res_[j] * (Mdv_[j] - Hdr_[j]);
        slope = nsn::add_merit_slope(slope, phi_.data(), A_.data(), B_.data(), dr, Htdv_.data(), nc_);
        return FRIX_OK;
    }
    // The merit at (v, r) + t (dv, dr): the equilibrium rows are linear.
    double merit_at(double t) {
        const double *dr = dx_.data() + n_;
        for (int64_t j = 0; j < n_; ++j) rest_[j] = res_[j] + t * (Mdv_[j] - Hdr_[j]);
        for (int64_t i = 0; i < m_; ++i) {
            rt_[i] = ctx_.r[i] + t * dr[i];
            ut_[i] = ctx_.u[i] + t * Htdv_[i];
        }
        contacts(rt_.data(), ut_.data(), phit_.data(), false);
        return 0.5 * (dot(rest_.data(), rest_.data(), n_) + dot(phit_.data(), phit_.data(), m_));
    }
    static constexpr bool kWatchable = true;
    // The error at (v, r) + (dv, dr) (the trial point's arrays hold it).
    frix_error full_step_error(double &err) {
        const double *dr = dx_.data() + n_;
        for (int64_t j = 0; j < n_; ++j) vt_[j] = ctx_.v[j] + dx_[j];
        for (int64_t i = 0; i < m_; ++i) rt_[i] = ctx_.r[i] + dr[i];
        double equilibrium = 0.0;
        err = selected_error(global_measures(p_, rt_.data(), vt_.data(), ut_.data(), &equilibrium), measure_);
        return FRIX_OK;
    }
    void move(double t) {
        for (int64_t j = 0; j < n_; ++j) ctx_.v[j] += t * dx_[j];
        for (int64_t i = 0; i < m_; ++i) ctx_.r[i] += t * dx_[n_ + i];
    }
    void save(Point &x) const {
        x.r.assign(ctx_.r, ctx_.r + m_);
        x.v.assign(ctx_.v, ctx_.v + n_);
    }
    void load(const Point &x) {
        std::copy(x.r.begin(), x.r.end(), ctx_.r);
        std::copy(x.v.begin(), x.v.end(), ctx_.v);
    }
    frix_error rejected(int64_t taken, bool &changed, double &psi) {
        if (!(changed = cuts_.cut(taken))) return FRIX_OK;
        for (int64_t a = 0; a < nc_; ++a) rho_.rho_n[a] *= kRhoCut, rho_.rho_t[a] *= kRhoCut;
        psi = merit(ctx_.r, ctx_.v, ctx_.u, res_.data(), phi_.data(), true);
        return FRIX_OK;
    }
    void log_step(int64_t step, double t, double err, double, double delta) const {
        if (ctx_.options.i(FRIX_OPT_VERBOSITY) >= 2)
            log_line(&ctx_.options, "global newton: step %lld t %.3g error %.3e equilibrium %.3e delta %.1e",
                     (long long)step, t, err, equilibrium_, delta);
    }
    const linalg::SparseLU &lu() const { return lu_; }

   private:
    // res = M v - H r - f, u = H^T v + w, Phi (A and B with the Jacobian); the merit.
    double merit(const double *r, const double *v, double *u, double *res, double *phi, bool jacobian) {
        matrix_gemv(*p_.M, 1.0, v, 0.0, res);
        if (nc_ > 0) matrix_gemv(*p_.H, -1.0, r, 1.0, res);
        for (int64_t j = 0; j < n_; ++j) res[j] -= p_.f[j];
        if (nc_ > 0) matrix_gemv_transposed(*p_.H, 1.0, v, 0.0, u);
        for (int64_t i = 0; i < m_; ++i) u[i] += p_.w[i];
        contacts(r, u, phi, jacobian);
        return 0.5 * (dot(res, res, n_) + dot(phi, phi, m_));
    }
    void contacts(const double *r, const double *u, double *phi, bool jacobian) {
        for (int64_t a = 0; a < nc_; ++a)
            nsn::contact_function(nsn::kAlartCurnier, r + 3 * a, u + 3 * a, p_.mu[a], rho_.rho_n[a], rho_.rho_t[a],
                                  phi + 3 * a, jacobian ? &A_[9 * a] : nullptr, jacobian ? &B_[9 * a] : nullptr);
    }

    SolveContext &ctx_;
    const frix_problem &p_;
    const int64_t n_, nc_, m_;
    LumpedRho rho_;
    const int64_t measure_;
    Jacobian jac_;
    linalg::SparseLU lu_;
    RhoCuts cuts_;
    double equilibrium_ = 0.0;
    std::vector<double> A_, B_, phi_, res_, dx_, rhs_, Mdv_, Hdr_, Htdv_, rt_, ut_, phit_, rest_, vt_;
};

frix_error solve(SolveContext &ctx) {
    const frix_problem &p = ctx.problem;
    const newton::Settings s = newton::settings_from(ctx.options, FRIX_SOLVER_NSN_AC);
    Csc M, H;
    if (frix_error e = to_csc(*p.M, M)) return e;
    if (frix_error e = to_csc(*p.H, H)) return e;
    // v starts from 0, not from the v0 = M^-1 f the driver leaves in it: the first step's
    // linear block gets to M v = H r + f anyway, and from v0 a rigid problem can stall
    // (notes/2026-11-28-newton-kit.md). From a warm r on a deformable body the driver's
    // v = M^-1 (H r + f) is kept (one or two steps from a good start, where v = 0 took 5-23),
    // not on a rigid pile (it stalls there too) nor on a shifted singular M (its free motion
    // amplified: notes/2026-11-28-gnsn-ac-first-step.md).
    const bool w_may_be_regular = 3 * p.nc <= p.n;
    if (!w_may_be_regular || ctx.mass_shifted || vec::all_zero(ctx.r, 3 * p.nc))
        std::fill(ctx.v, ctx.v + p.n, 0.0);
    VrSystem system(ctx, M, H, lumped_rho(ctx, M, H, s), s.measure);
    kit::Steps steps{Monitor(ctx)};
    kit::Counters counters;
    kit::RunResult res;
    const kit::Rules rules = rules_of(s.line_search, s.ls_max_iter, w_may_be_regular);
    if (frix_error e = kit::newton(system, steps, rules, counters, res)) return e;
    kit::record(ctx.info, res, steps, counters);
    Monitor::record_factorizations(ctx.info, system.lu().stats());
    if (s.verbosity >= 1)
        log_line(&ctx.options, "global newton: %s after %lld steps", frix_status_string(res.status),
                 (long long)steps.done);
    return FRIX_OK;
}

const frix_option_key kExtraKeys[] = {FRIX_OPT_RHO_STRATEGY, FRIX_OPT_RHO, FRIX_OPT_LINE_SEARCH,
                                      FRIX_OPT_LINE_SEARCH_MAX_ITER, (frix_option_key)0};
const OptionDefault kDefaults[] = {{FRIX_OPT_MAX_ITER, 500},
                                   {FRIX_OPT_LINE_SEARCH, FRIX_LINE_SEARCH_NONMONOTONE},
                                   {(frix_option_key)0, 0}};

}  // namespace
}  // namespace gnsn_ac

const SolverEntry kGnsnAcEntry = {
    FRIX_SOLVER_GLOBAL_NSN_AC, "gnsn-ac", "GLOBAL_FRICTION_3D_NSN_AC",
    "Semismooth Newton (Alart-Curnier) on the global problem itself: unknowns (v, r), "
    "equations M v - H r - f = 0 and Phi(r, H^T v + w) = 0, Jacobian [[M, -H], [B H^T, A]] "
    "factorised by UMFPACK with a nested-dissection (METIS) ordering (one symbolic analysis "
    "per solve; a second, for UMFPACK's unsymmetric strategy, where sticking contacts make the "
    "symmetric one pivot off the diagonal at 1.5 times its flops). W = H^T M^-1 H is never "
    "formed; rho comes from the lumped blocks H_a^T diag(M)^-1 H_a, scaled where they underrate W's "
    "blocks (estimated on 8 contacts with M's factorisation), and is cut tenfold, up to four "
    "times, while no step is accepted. "
    "Converged means both the error and the equilibrium residual are below the tolerance. "
    "Global problems only (local solvers reach global problems through "
    "the reduction W = H^T M^-1 H). Options: rho_strategy, rho, line_search (by default "
    "non-monotone Armijo, against the largest of the last 8 merits; Goldstein-Price is taken as "
    "Armijo with m1 = 0.01; where 3 nc <= n, a deformable body, the first step is taken full "
    "where it lowers the error), line_search_max_iter. v starts from 0, or on a deformable body "
    "warm-started with r from M^-1 (H r + f).",
    gnsn_ac::solve, false, true, gnsn_ac::kExtraKeys, gnsn_ac::kDefaults};

}  // namespace frix
