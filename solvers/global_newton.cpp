// Route (b) of global problems, solver 607: semismooth Newton on (v, r), W never formed.
#include "solvers/global_newton.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "solvers/mass_plus_contacts.hpp"
#include "solvers/newton.hpp"
#include "solvers/nsn_functions.hpp"
#include "src/error_state.hpp"
#include "src/linalg/linalg.hpp"
#include "src/log.hpp"
#include "src/matrix.hpp"
#include "src/measures.hpp"
#include "src/monitor.hpp"
#include "src/reduction.hpp"

namespace frix {

// ---- Route (b): semismooth Newton (Alart-Curnier) on (v, r).
namespace gnewton {

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

double dot(const double *x, const double *y, int64_t n) {
    double s = 0.0;
    for (int64_t i = 0; i < n; ++i) s += x[i] * y[i];
    return s;
}

// How much the lumped blocks H_a^T diag(M)^-1 H_a underrate W's diagonal blocks: the median,
// over up to kRhoSamples contacts spread over the problem, of trace(H_a^T M^-1 H_a) over
// trace(H_a^T diag(M)^-1 H_a), with M^-1 from the driver's factorisation (3 solves a contact).
// 1 for a diagonal M (rigid bodies with diagonal inertia); far above on a stiff deformable
// body, where diag(M)^-1 ignores that the body moves as a whole (an elastic grid with
// k = 1e12: about 4e5).
double lumped_underrate(const frix_problem &p, const Csc &H,
                        const std::function<frix_error(const double *, double *)> &solve_mass,
                        const std::vector<double> &lumped_trace) {
    std::vector<double> ratios;
    for (const auto &sample : sampled_delassus_diagonals(p, H, solve_mass, kRhoSamples, 3)) {
        const double lumped = lumped_trace[sample.first], exact = sample.second;
        if (lumped > 0.0 && std::isfinite(exact)) ratios.push_back(exact / lumped);
    }
    if (ratios.empty()) return 1.0;
    std::nth_element(ratios.begin(), ratios.begin() + ratios.size() / 2, ratios.end());
    return ratios[ratios.size() / 2];
}

frix_error solve(SolveContext &ctx) {
    const frix_problem &p = ctx.problem;
    const frix_options &o = ctx.options;
    frix_info &info = ctx.info;
    const newton::Settings s = newton::settings_from(o, FRIX_SOLVER_NSN_AC);
    const Monitor monitor(ctx);
    const double tol = monitor.tolerance();
    const int64_t max_iter = monitor.max_iterations();
    const int64_t n = p.n, nc = p.nc, m = 3 * nc, N = n + m;
    double *r = ctx.r, *u = ctx.u, *v = ctx.v;

    Csc M, H;
    if (frix_error e = to_csc(*p.M, M)) return e;
    if (frix_error e = to_csc(*p.H, H)) return e;
    // rho from the lumped Delassus blocks H_a^T diag(M)^-1 H_a: W itself is never formed.
    std::vector<double> dinv(n, 0.0), rho_n(nc), rho_t(nc);
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
    // the lumped blocks is as much too large (k = 1e12: no step accepted, even with rho cut
    // 1e4-fold); a few exact blocks give the factor.
    const double underrate =
        ctx.solve_mass && s.rho_strategy != FRIX_RHO_CONSTANT ? lumped_underrate(p, H, *ctx.solve_mass, lumped_trace)
                                                              : 1.0;
    const double correction = underrate > kUnderrateToCorrect ? underrate : 1.0;
    if (s.verbosity >= 1 && underrate != 1.0)
        log_line(&o, "global newton: the lumped blocks underrate W's by %.3g%s", underrate,
                 correction != 1.0 ? ": rho corrected" : "");
    double wscale = 0.0;
    for (int64_t a = 0; a < nc; ++a) {
        double Wd[9];
        for (int k = 0; k < 9; ++k) Wd[k] = correction * lumped[9 * a + k];
        nsn::contact_rho(s.rho_strategy, s.rho, Wd, &rho_n[a], &rho_t[a]);
        double fro = 0.0;
        for (double x : Wd) fro += x * x;
        wscale += std::sqrt(fro);
    }
    wscale = nc > 0 && wscale > 0.0 ? wscale / (double)nc : 1.0;

    Jacobian jac;
    jac.build(M, H, nc);
    linalg::SparseLU lu;
    // M's pattern is a mesh's for a deformable body, where nested dissection leaves far less
    // fill than AMD (an FEM-like grid of 1600 contacts: 4.3 s against 18.1 s, the same
    // steps); on the rigid global files of ../shared it is as fast or faster.
    lu.set_ordering(linalg::SparseLU::Ordering::kNestedDissection);
    lu.set_budget(monitor.budget());
    std::vector<double> A(9 * nc), B(9 * nc), phi(m), res(n), F(N), dx(N), rhs(N);
    std::vector<double> Mdv(n), Hdr(n), Htdv(m), rt(m), ut(m), phit(m), rest(n);
    std::vector<double> best_r(r, r + m), best_v(n);
    // v starts from 0, not from the v0 = M^-1 f the driver leaves in it: the first step's
    // linear block gets to M v = H r + f anyway, and from v0 the rigid spheres-in-a-box
    // problem stalls at 0.35 instead of 4e-7.
    for (int64_t j = 0; j < n; ++j) v[j] = 0.0;
    std::copy(v, v + n, best_v.begin());

    auto evaluate = [&](const double *rr, const double *vv, double *uu, double *rr_res, double *ph,
                        bool jacobian) {
        matrix_gemv(*p.M, 1.0, vv, 0.0, rr_res);
        if (nc > 0) matrix_gemv(*p.H, -1.0, rr, 1.0, rr_res);
        for (int64_t j = 0; j < n; ++j) rr_res[j] -= p.f[j];
        if (nc > 0) matrix_gemv_transposed(*p.H, 1.0, vv, 0.0, uu);
        for (int64_t i = 0; i < m; ++i) uu[i] += p.w[i];
        for (int64_t a = 0; a < nc; ++a)
            nsn::contact_function(nsn::kAlartCurnier, rr + 3 * a, uu + 3 * a, p.mu[a], rho_n[a],
                                  rho_t[a], ph + 3 * a, jacobian ? &A[9 * a] : nullptr,
                                  jacobian ? &B[9 * a] : nullptr);
        return 0.5 * (dot(rr_res, rr_res, n) + dot(ph, ph, m));
    };
    double equilibrium = 0.0;
    auto error_of = [&]() {
        const Measures meas = global_measures(p, r, v, u, &equilibrium);
        return std::max(selected_error(meas, s.measure), equilibrium);
    };

    double psi = evaluate(r, v, u, res.data(), phi.data(), true);
    newton::MeritHistory history(psi);
    double err = error_of();
    Progress progress(err);
    int64_t it = 0, ls_steps = 0;
    info.status = FRIX_STATUS_MAX_ITER;
    while (true) {
        const frix_status stop = status_before_step(err, tol, it, max_iter, [&] { return monitor.out_of_time(); });
        if (stop != FRIX_STATUS_NOT_RUN) {
            info.status = stop;
            break;
        }
        bool factored = false;
        for (int attempt = 0; attempt < 12 && !factored && !lu.refused(); ++attempt) {
            jac.assemble(A, B, progress.delta() * wscale);
            if (lu.stats().symbolic == 0)
                if (frix_error e = lu.analyze(jac.J.view())) return e;
            const frix_error e = lu.factor(jac.J.view());
            if (e == FRIX_ERR_OUT_OF_MEMORY) return e;
            factored = e == FRIX_OK && lu.rcond() > 1e-15;
            if (!factored) progress.factorisation_failed();
        }
        if (!factored) {
            info.status = lu.refused() ? lu.refused() : FRIX_STATUS_NUMERICAL_FAILURE;
            break;
        }
        for (int64_t j = 0; j < n; ++j) rhs[j] = -res[j];
        for (int64_t i = 0; i < m; ++i) rhs[n + i] = -phi[i];
        if (frix_error e = lu.solve(rhs.data(), dx.data())) return e;
        ++it;
        const double *dv = dx.data(), *dr = dx.data() + n;
        matrix_gemv(*p.M, 1.0, dv, 0.0, Mdv.data());
        if (nc > 0) {
            matrix_gemv(*p.H, 1.0, dr, 0.0, Hdr.data());
            matrix_gemv_transposed(*p.H, 1.0, dv, 0.0, Htdv.data());
        }
        // Slope of the merit: res . (M dv - H dr) + Phi . (A dr + B H^T dv).
        double slope = 0.0;
        for (int64_t j = 0; j < n; ++j) slope += res[j] * (Mdv[j] - Hdr[j]);
        slope = add_contacts_slope(slope, phi.data(), A.data(), B.data(), dr, Htdv.data(), nc);
        double t = 1.0;
        bool accepted = s.line_search == FRIX_LINE_SEARCH_NONE;
        if (!accepted && slope < 0.0) {
            const double c = s.line_search == FRIX_LINE_SEARCH_GOLDSTEIN_PRICE ? kM1 : kArmijo;
            // Non-monotone: against the largest of the last merits, so that a full step may
            // climb for a while over the kinks of the merit.
            const double ref = s.line_search == FRIX_LINE_SEARCH_NONMONOTONE ? history.reference(psi) : psi;
            const auto merit = [&](double step) {
                for (int64_t j = 0; j < n; ++j) rest[j] = res[j] + step * (Mdv[j] - Hdr[j]);
                for (int64_t i = 0; i < m; ++i) {
                    rt[i] = r[i] + step * dr[i];
                    ut[i] = u[i] + step * Htdv[i];
                }
                for (int64_t a = 0; a < nc; ++a)
                    nsn::contact_function(nsn::kAlartCurnier, &rt[3 * a], &ut[3 * a], p.mu[a], rho_n[a], rho_t[a],
                                          &phit[3 * a], nullptr, nullptr);
                return 0.5 * (dot(rest.data(), rest.data(), n) + dot(phit.data(), phit.data(), m));
            };
            t = backtrack(merit, psi, ref, c, slope, s.ls_max_iter, ls_steps);
            accepted = t > 0.0;
        }
        if (accepted) {
            for (int64_t j = 0; j < n; ++j) v[j] += t * dv[j];
            for (int64_t i = 0; i < m; ++i) r[i] += t * dr[i];
            psi = evaluate(r, v, u, res.data(), phi.data(), true);
            history.push(psi);
            err = error_of();
            progress.step_taken(t);
        } else if (progress.step_rejected()) {
            // rho can still be far too large (a calibration missed by the 8 samples, or a
            // constant rho: 1e5 on the elastic grid with k = 1e8, where 1e3 converges), and
            // no step lowers the merit then. Until a step is accepted, try smaller (later, a
            // failed step is a kink, not a scale: on the rigid spheres-in-a-box cuts end at
            // 1.5e-3 instead of 4e-7).
            for (int64_t a = 0; a < nc; ++a) rho_n[a] *= kRhoCut, rho_t[a] *= kRhoCut;
            psi = evaluate(r, v, u, res.data(), phi.data(), true);
            history = newton::MeritHistory(psi);  // (merits of another rho)
        }
        if (s.verbosity >= 2)
            log_line(&o, "global newton: step %lld t %.3g error %.3e equilibrium %.3e delta %.1e",
                     (long long)it, t, err, equilibrium, progress.delta());
        if (monitor.report(it, err)) {
            info.status = FRIX_STATUS_STOPPED_BY_CALLBACK;
            break;
        }
        if (progress.improved(err)) {
            std::copy(r, r + m, best_r.begin());
            std::copy(v, v + n, best_v.begin());
        }
        if (progress.stalled()) {
            info.status = FRIX_STATUS_STAGNATED;
            break;
        }
    }
    if (!(err <= progress.best())) {  // also when the last iterate is not finite
        std::copy(best_r.begin(), best_r.end(), r);
        std::copy(best_v.begin(), best_v.end(), v);
    }
    info.iterations = it;
    info.newton_iterations = it;
    info.line_search_steps = ls_steps;
    Monitor::record_factorizations(info, lu.stats());
    if (s.verbosity >= 1)
        log_line(&o, "global newton: %s after %lld steps", frix_status_string(info.status),
                 (long long)it);
    return FRIX_OK;
}

const frix_option_key kExtraKeys[] = {FRIX_OPT_RHO_STRATEGY, FRIX_OPT_RHO, FRIX_OPT_LINE_SEARCH,
                                      FRIX_OPT_LINE_SEARCH_MAX_ITER, (frix_option_key)0};
const OptionDefault kDefaults[] = {{FRIX_OPT_MAX_ITER, 500},
                                   {FRIX_OPT_LINE_SEARCH, FRIX_LINE_SEARCH_NONMONOTONE},
                                   {(frix_option_key)0, 0}};

}  // namespace
}  // namespace gnewton

const SolverEntry kGlobalNsnAcEntry = {
    FRIX_SOLVER_GLOBAL_NSN_AC, "gnsn-ac", "GLOBAL_FRICTION_3D_NSN_AC",
    "Semismooth Newton (Alart-Curnier) on the global problem itself: unknowns (v, r), "
    "equations M v - H r - f = 0 and Phi(r, H^T v + w) = 0, Jacobian [[M, -H], [B H^T, A]] "
    "factorised by UMFPACK with a nested-dissection (METIS) ordering (one symbolic analysis "
    "per solve). W = H^T M^-1 H is never formed; rho comes from the lumped blocks H_a^T "
    "diag(M)^-1 H_a, scaled where they underrate W's "
    "blocks (estimated on 8 contacts with M's factorisation), and is cut tenfold, up to four "
    "times, while no step is accepted. "
    "Converged means both the error and the equilibrium residual are below the tolerance. "
    "Global problems only (local solvers reach global problems through "
    "the reduction W = H^T M^-1 H). Options: rho_strategy, rho, line_search (by default "
    "non-monotone Armijo, against the largest of the last 8 merits; Goldstein-Price is taken as "
    "Armijo with m1 = 0.01), line_search_max_iter.",
    gnewton::solve, false, true, gnewton::kExtraKeys, gnewton::kDefaults};

}  // namespace frix
