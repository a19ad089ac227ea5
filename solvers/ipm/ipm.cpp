// IPM (id 524): a primal-dual interior-point method on Coulomb's law, then Newton (AC) from
// its best point.
//
// Per contact the law is written as two complementarity pairs and one extra unknown s:
//   0 <= r_N  ⟂  u_N >= 0,        L ∋ (mu r_N, r_T)  ⟂  (s, u_T) ∈ L,        u = W r + q,
// L the Lorentz cone {(t, x): |x| <= t}. It is Coulomb's law: sticking (u = 0, r inside K),
// sliding (u_N = 0, r on K's boundary and r_T = -mu r_N u_T / |u_T|, which the second pair
// forces with s = |u_T|) and take-off (r = 0, u_N >= 0, u_T free). Contacts with mu = 0 keep
// the first pair only and r_T = 0.
//
// Each iteration is a Mehrotra predictor-corrector step with Nesterov-Todd scaling on L. u and
// s are eliminated contact by contact, which leaves one sparse system (W + D) dr = rhs with D
// block diagonal (3x3): one UMFPACK factorisation per iteration, pattern analysed once.
// Coulomb's law is not monotone, so nothing guarantees convergence; in practice the iterates
// reach 1e-3..1e-8 in 10-60 iterations where first-order methods need thousands of sweeps
// (large granular scenes), but interior points stop short of the boundary: the method ends
// with semismooth Newton (Alart-Curnier) from its best iterate, which then converges in a few
// steps when the IPM got close. The warm start r cannot seed an interior point: it is
// returned at once if it meets the tolerance, and kept if nothing better is found.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <vector>

#include "solvers/kit/lorentz.hpp"
#include "src/error_state.hpp"
#include "src/linalg/linalg.hpp"
#include "src/log.hpp"
#include "src/matrix.hpp"
#include "solvers/entries.hpp"

namespace frix {
namespace ipm {

namespace {

using lorentz::jnorm2;
using lorentz::jordan;
using lorentz::jordan_solve;
using lorentz::max_step_lorentz;
using lorentz::mul3;
using lorentz::SystemPattern;

// Fraction of the largest step to the boundary taken (the usual 0.99).
constexpr double kToBoundary = 0.99;
// The IPM hands over to Newton after this many iterations without halving its best error,
// or when its step falls below kMinStep.
constexpr int kStallIterations = 30;
constexpr double kMinStep = 1e-10;

// Nesterov-Todd scaling of x, y in int L: the symmetric G with G x = G^-1 y, and G^-1 (both
// row-major 3x3). G = beta (2 v v^T - J), J = diag(1, -1, -1).
void nt_scaling(const double *x, const double *y, double *G, double *Gi) {
    const double nx = std::sqrt(std::max(jnorm2(x), 1e-300));
    const double ny = std::sqrt(std::max(jnorm2(y), 1e-300));
    const double xb[3] = {x[0] / nx, x[1] / nx, x[2] / nx}, yb[3] = {y[0] / ny, y[1] / ny, y[2] / ny};
    const double gamma = std::sqrt(std::max(0.5 * (1.0 + xb[0] * yb[0] + xb[1] * yb[1] + xb[2] * yb[2]), 1e-300));
    const double w[3] = {(xb[0] + yb[0]) / (2 * gamma), (yb[1] - xb[1]) / (2 * gamma),
                         (yb[2] - xb[2]) / (2 * gamma)};
    const double beta = std::sqrt(ny / nx), c = std::sqrt(2.0 * (w[0] + 1.0));
    const double v[3] = {(w[0] + 1.0) / c, w[1] / c, w[2] / c};
    const double J[3] = {1.0, -1.0, -1.0};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            const double d = i == j ? J[i] : 0.0;
            G[3 * i + j] = beta * (2.0 * v[i] * v[j] - d);
            Gi[3 * i + j] = (2.0 * J[i] * v[i] * v[j] * J[j] - d) / beta;
        }
}

using KeptState = lorentz::KeptSystem;

class Solver {
   public:
    Solver(SolveContext &ctx, KeptState &kept)
        : ctx_(ctx), p_(ctx.problem), nc_(p_.nc), m_(3 * p_.nc), pat_(kept.pat), lu_(kept.lu),
          analysed_(kept.analysed), kept_(kept) {}
    frix_error run();

   private:
    // Primal and dual cone vectors of contact a's Lorentz pair.
    void cone_x(const std::vector<double> &r, int64_t a, double *x) const {
        x[0] = p_.mu[a] * r[3 * a];
        x[1] = r[3 * a + 1];
        x[2] = r[3 * a + 2];
    }
    void cone_y(const std::vector<double> &u, const std::vector<double> &s, int64_t a,
                double *y) const {
        y[0] = s[a];
        y[1] = u[3 * a + 1];
        y[2] = u[3 * a + 2];
    }
    bool friction(int64_t a) const { return p_.mu[a] > 0.0; }
    void scalings();
    frix_error assemble_and_factor();
    // The Newton direction for the centring target sigma_tau; with `corrector`, Mehrotra's
    // second-order term of the affine direction (dr_a_, du_a_, ds_a_).
    frix_error direction(double target, bool corrector, std::vector<double> &dr,
                         std::vector<double> &du, std::vector<double> &ds);
    double step_to_boundary(const std::vector<double> &dr, const std::vector<double> &du,
                            const std::vector<double> &ds) const;
    double gap_after(double alpha) const;

    SolveContext &ctx_;
    const frix_problem &p_;
    const int64_t nc_, m_;
    std::vector<double> r_, u_, s_, pres_;
    // Per contact: G, G^-1, G^2 (row-major 3x3), G x, and D (row-major 3x3).
    std::vector<double> G_, Gi_, G2_, lambda_, D_;
    std::vector<double> dr_a_, du_a_, ds_a_, g_, rhs_;
    SystemPattern &pat_;
    std::vector<double> values_;
    linalg::SparseLU &lu_;
    bool &analysed_;
    KeptState &kept_;
};

void Solver::scalings() {
    for (int64_t a = 0; a < nc_; ++a) {
        double *D = &D_[9 * a];
        std::fill(D, D + 9, 0.0);
        // Normal row: du_N = (c - u_N dr_N) / r_N.
        D[0] = u_[3 * a] / r_[3 * a];
        if (!friction(a)) {  // r_T = 0 stays: identity rows below, D unused there
            continue;
        }
        double x[3], y[3];
        cone_x(r_, a, x);
        cone_y(u_, s_, a, y);
        double *G = &G_[9 * a];
        nt_scaling(x, y, G, &Gi_[9 * a]);
        mul3(G, x, &lambda_[3 * a]);
        // Tangential rows: dy = G t - G^2 dx with dx = (mu dr_N, dr_T), dy = (ds, du_T).
        double *G2 = &G2_[9 * a];
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                G2[3 * i + j] = G[3 * i] * G[j] + G[3 * i + 1] * G[3 + j] + G[3 * i + 2] * G[6 + j];
        for (int i = 1; i < 3; ++i) {
            D[3 * i] = G2[3 * i] * p_.mu[a];
            D[3 * i + 1] = G2[3 * i + 1];
            D[3 * i + 2] = G2[3 * i + 2];
        }
    }
}

frix_error Solver::assemble_and_factor() {
    pat_.assemble(*p_.W, D_.data(), values_);
    linalg::CscView A{m_, m_, pat_.colptr.data(), pat_.rowind.data(), values_.data()};
    if (!analysed_) {
        if (frix_error e = lu_.analyze(A)) return e;
        analysed_ = true;
    }
    return lu_.factor(A);
}

frix_error Solver::direction(double target, bool corrector, std::vector<double> &dr,
                             std::vector<double> &du, std::vector<double> &ds) {
    for (int64_t a = 0; a < nc_; ++a) {
        const double rN = r_[3 * a], uN = u_[3 * a];
        double c1 = target - rN * uN;
        if (corrector) c1 -= dr_a_[3 * a] * du_a_[3 * a];
        g_[3 * a] = c1 / rN;
        g_[3 * a + 1] = g_[3 * a + 2] = 0.0;
        ds[a] = 0.0;
        if (!friction(a)) continue;
        const double *l = &lambda_[3 * a], *G = &G_[9 * a];
        double ll[3];
        jordan(l, l, ll);
        double c[3] = {target - ll[0], -ll[1], -ll[2]};
        if (corrector) {
            const double dx[3] = {p_.mu[a] * dr_a_[3 * a], dr_a_[3 * a + 1], dr_a_[3 * a + 2]};
            const double dy[3] = {ds_a_[a], du_a_[3 * a + 1], du_a_[3 * a + 2]};
            double gx[3], gy[3], pr[3];
            mul3(G, dx, gx);
            mul3(&Gi_[9 * a], dy, gy);
            jordan(gx, gy, pr);
            for (int i = 0; i < 3; ++i) c[i] -= pr[i];
        }
        double t[3], Gt[3];
        jordan_solve(l, c, t);
        mul3(G, t, Gt);
        g_[3 * a + 1] = Gt[1];
        g_[3 * a + 2] = Gt[2];
        ds[a] = Gt[0];
    }
    // du = g - D dr and du - W dr = -pres give (W + D) dr = g + pres.
    for (int64_t i = 0; i < m_; ++i) rhs_[i] = g_[i] + pres_[i];
    for (int64_t a = 0; a < nc_; ++a)
        if (!friction(a)) rhs_[3 * a + 1] = rhs_[3 * a + 2] = 0.0;
    if (frix_error e = lu_.solve(rhs_.data(), dr.data())) return e;
    // du from the eliminated rows; on frictionless contacts du_T = W_T dr - pres_T.
    std::vector<double> &wdr = rhs_;  // reused as W dr
    matrix_gemv(*p_.W, 1.0, dr.data(), 0.0, wdr.data());
    for (int64_t a = 0; a < nc_; ++a) {
        double d3[3];
        mul3(&D_[9 * a], &dr[3 * a], d3);
        du[3 * a] = g_[3 * a] - d3[0];
        if (!friction(a)) {
            du[3 * a + 1] = wdr[3 * a + 1] - pres_[3 * a + 1];
            du[3 * a + 2] = wdr[3 * a + 2] - pres_[3 * a + 2];
            continue;
        }
        du[3 * a + 1] = g_[3 * a + 1] - d3[1];
        du[3 * a + 2] = g_[3 * a + 2] - d3[2];
        const double *G2 = &G2_[9 * a];  // row 0: ds = (G t)_0 - (G^2 dx)_0
        const double dx[3] = {p_.mu[a] * dr[3 * a], dr[3 * a + 1], dr[3 * a + 2]};
        ds[a] -= G2[0] * dx[0] + G2[1] * dx[1] + G2[2] * dx[2];
    }
    return FRIX_OK;
}

double Solver::step_to_boundary(const std::vector<double> &dr, const std::vector<double> &du,
                                const std::vector<double> &ds) const {
    double alpha = INFINITY;
    for (int64_t a = 0; a < nc_; ++a) {
        if (dr[3 * a] < 0.0) alpha = std::min(alpha, -r_[3 * a] / dr[3 * a]);
        if (du[3 * a] < 0.0) alpha = std::min(alpha, -u_[3 * a] / du[3 * a]);
        if (!friction(a)) continue;
        double x[3], y[3];
        cone_x(r_, a, x);
        cone_y(u_, s_, a, y);
        const double dx[3] = {p_.mu[a] * dr[3 * a], dr[3 * a + 1], dr[3 * a + 2]};
        const double dy[3] = {ds[a], du[3 * a + 1], du[3 * a + 2]};
        alpha = std::min(alpha, std::min(max_step_lorentz(x, dx), max_step_lorentz(y, dy)));
    }
    return alpha;
}

double Solver::gap_after(double alpha) const {
    double gap = 0.0;
    for (int64_t a = 0; a < nc_; ++a) {
        const double rN = r_[3 * a] + alpha * dr_a_[3 * a];
        gap += rN * (u_[3 * a] + alpha * du_a_[3 * a]);
        if (!friction(a)) continue;
        gap += p_.mu[a] * rN * (s_[a] + alpha * ds_a_[a]);
        for (int i = 1; i < 3; ++i)
            gap += (r_[3 * a + i] + alpha * dr_a_[3 * a + i]) * (u_[3 * a + i] + alpha * du_a_[3 * a + i]);
    }
    return gap;
}

frix_error Solver::run() {
    const frix_options &o = ctx_.options;
    const frix_matrix &W = *p_.W;
    frix_info &info = ctx_.info;
    const int verbosity = (int)o.i(FRIX_OPT_VERBOSITY);
    const int64_t m = m_;
    r_.assign(m, 0.0);
    u_.assign(m, 0.0);
    s_.assign(nc_, 0.0);
    pres_.assign(m, 0.0);
    G_.assign(9 * nc_, 0.0);
    Gi_.assign(9 * nc_, 0.0);
    G2_.assign(9 * nc_, 0.0);
    lambda_.assign(3 * nc_, 0.0);
    D_.assign(9 * nc_, 0.0);
    dr_a_.assign(m, 0.0);
    du_a_.assign(m, 0.0);
    ds_a_.assign(nc_, 0.0);
    g_.assign(m, 0.0);
    rhs_.assign(m, 0.0);
    std::vector<double> dr(m), du(m), ds(nc_), wr(m);
    lorentz::Run run(ctx_, kept_, kStallIterations);
    values_.assign(pat_.rowind.size(), 0.0);

    // Interior start on the cones' axes, scaled like the problem.
    const lorentz::StartScales scale = lorentz::start_scales(p_);
    for (int64_t a = 0; a < nc_; ++a) {
        r_[3 * a] = scale.force;
        u_[3 * a] = scale.velocity;
        s_[a] = scale.velocity;
    }
    double nu = 0.0;  // cone pairs (each a barrier weight of 1)
    for (int64_t a = 0; a < nc_; ++a) nu += friction(a) ? 2.0 : 1.0;

    bool handed_over = false;
    for (;;) {
        const lorentz::Run::Next next = run.check(r_.data());
        if (next != lorentz::Run::kIterate) {
            handed_over = next == lorentz::Run::kHandOver;
            break;
        }
        matrix_gemv(W, 1.0, r_.data(), 0.0, wr.data());
        double gap = 0.0;
        for (int64_t i = 0; i < m; ++i) pres_[i] = u_[i] - wr[i] - p_.q[i];
        for (int64_t a = 0; a < nc_; ++a) {
            if (!friction(a)) pres_[3 * a + 1] = pres_[3 * a + 2] = 0.0;  // u_T free
            gap += r_[3 * a] * u_[3 * a];
            if (friction(a))
                gap += p_.mu[a] * r_[3 * a] * s_[a] + r_[3 * a + 1] * u_[3 * a + 1] +
                       r_[3 * a + 2] * u_[3 * a + 2];
        }
        const double tau = gap / nu;
        scalings();
        if (frix_error e = assemble_and_factor()) {
            if (e != FRIX_ERR_NUMERICAL) return e;
            clear_error();
            if (lu_.refused()) {  // it would overrun the time or memory limit
                info.status = lu_.refused();
                break;
            }
            handed_over = true;  // a singular system: Newton takes over from the best point
            break;
        }
        if (frix_error e = direction(0.0, false, dr_a_, du_a_, ds_a_)) return e;
        const double alpha_aff = std::min(1.0, step_to_boundary(dr_a_, du_a_, ds_a_));
        const double sigma = std::pow(std::max(gap_after(alpha_aff), 0.0) / gap, 3.0);
        if (frix_error e = direction(sigma * tau, true, dr, du, ds)) return e;
        const double alpha = std::min(1.0, kToBoundary * step_to_boundary(dr, du, ds));
        bool finite = std::isfinite(alpha);
        for (int64_t i = 0; i < m && finite; ++i) finite = std::isfinite(dr[i]) && std::isfinite(du[i]);
        for (int64_t a = 0; a < nc_ && finite; ++a) finite = std::isfinite(ds[a]);
        run.count_iteration();
        if (verbosity >= 2)
            log_line(&o, "ipm: iteration %lld gap/nu %.3e |u - Wr - q| %.3e error %.3e step %.3g",
                     (long long)run.iterations(), tau, std::sqrt(std::inner_product(pres_.begin(), pres_.end(), pres_.begin(), 0.0)),
                     run.last_error(), alpha);
        if (!finite || alpha < kMinStep) {
            handed_over = true;
            break;
        }
        for (int64_t i = 0; i < m; ++i) {
            r_[i] += alpha * dr[i];
            u_[i] += alpha * du[i];
        }
        for (int64_t a = 0; a < nc_; ++a) s_[a] += alpha * ds[a];
    }
    const int64_t ipm_iterations = run.iterations();
    if (handed_over && verbosity >= 1)
        log_line(&o, "ipm: %lld iterations, best error %.3e; Newton from there", (long long)ipm_iterations,
                 run.best_error());
    if (frix_error e = run.end(handed_over)) return e;
    if (verbosity >= 1)
        log_line(&o, "ipm: %s after %lld iterations (%lld interior-point, %lld Newton)",
                 frix_status_string(info.status), (long long)info.iterations, (long long)ipm_iterations,
                 (long long)run.newton_steps());
    return FRIX_OK;
}

frix_error solve(SolveContext &ctx) {
    if (!ctx.problem.W || !ctx.problem.W->block)
        return fail(FRIX_ERR_INTERNAL, "ipm: W is not stored as 3x3 blocks");
    Kept<KeptState> kept(ctx.cache, FRIX_SOLVER_IPM);
    Solver solver(ctx, *kept);
    if (frix_error e = solver.run()) return e;
    kept.keep();
    return FRIX_OK;
}

const frix_option_key kExtraKeys[] = {(frix_option_key)0};
const OptionDefault kDefaults[] = {{FRIX_OPT_MAX_ITER, 500}, {(frix_option_key)0, 0}};

}  // namespace
}  // namespace ipm

const SolverEntry kIpmEntry = {
    FRIX_SOLVER_IPM, "ipm", "FRICTION_3D_IPM",
    "Primal-dual interior-point method on Coulomb's law written per contact as "
    "0 <= r_N ⟂ u_N >= 0 and L ∋ (mu r_N, r_T) ⟂ (s, u_T) ∈ L (L the Lorentz cone, s an extra "
    "unknown equal to |u_T| where the contact slides): Mehrotra predictor-corrector steps with "
    "Nesterov-Todd scaling, u and s eliminated per contact, one UMFPACK factorisation of "
    "W + D (D block diagonal) per iteration. When the interior iterates stop improving "
    "(interior points stay off the boundary) semismooth Newton (Alart-Curnier) continues from "
    "the best one. Coulomb's law is not monotone: there is no convergence guarantee. The warm "
    "start only ends the solve at once when it meets the "
    "tolerance (and is kept if nothing better is found). Iterations count interior-point "
    "iterations plus Newton steps.",
    ipm::solve, true, false, ipm::kExtraKeys, ipm::kDefaults};

}  // namespace frix
