#include "solvers/kit/local_newton.hpp"

#include <algorithm>
#include <cmath>

#include "solvers/kit/line_search.hpp"
#include "solvers/kit/nsn_functions.hpp"
#include "src/coulomb.hpp"

namespace frix::local {

namespace {

constexpr int kLineSearchTrials = 20;

// Solves the 3x3 system J x = b by Gaussian elimination with partial pivoting; false if J is
// (numerically) singular.
bool solve3(const double *Jcm, const double *b, double *x) {
    double a[3][4];
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) a[i][j] = Jcm[i + 3 * j];
        a[i][3] = b[i];
    }
    double scale = 0.0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) scale = std::max(scale, std::fabs(a[i][j]));
    if (!(scale > 0.0)) return false;
    for (int k = 0; k < 3; ++k) {
        int piv = k;
        for (int i = k + 1; i < 3; ++i)
            if (std::fabs(a[i][k]) > std::fabs(a[piv][k])) piv = i;
        if (!(std::fabs(a[piv][k]) > 1e-14 * scale)) return false;
        if (piv != k)
            for (int j = 0; j < 4; ++j) std::swap(a[k][j], a[piv][j]);
        for (int i = k + 1; i < 3; ++i) {
            const double f = a[i][k] / a[k][k];
            for (int j = k; j < 4; ++j) a[i][j] -= f * a[k][j];
        }
    }
    for (int i = 2; i >= 0; --i) {
        double s = a[i][3];
        for (int j = i + 1; j < 3; ++j) s -= a[i][j] * x[j];
        x[i] = s / a[i][i];
    }
    return std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2]);
}

struct Eval {
    double u[3], phi[3], A[9], B[9], merit;
};

void evaluate(const Contact &c, const double *q, const double *r, int formulation, double rn,
              double rt, Eval &e, bool jacobian) {
    for (int i = 0; i < 3; ++i) e.u[i] = q[i] + c.W[i] * r[0] + c.W[i + 3] * r[1] + c.W[i + 6] * r[2];
    nsn::contact_function(formulation, r, e.u, c.mu, rn, rt, e.phi, jacobian ? e.A : nullptr,
                          jacobian ? e.B : nullptr);
    e.merit = 0.5 * (e.phi[0] * e.phi[0] + e.phi[1] * e.phi[1] + e.phi[2] * e.phi[2]);
}

}  // namespace

bool newton_contact(const Contact &c, const double *q, double *r, const Params &p, int formulation,
                    bool line_search) {
    // rho split between the normal and tangential parts (Siconos' default for 551/565).
    double rn, rt;
    nsn::contact_rho(2, 1.0, c.W, &rn, &rt);
    double x[3] = {r[0], r[1], r[2]}, best[3] = {r[0], r[1], r[2]};
    double rel = 0.0;
    coulomb::contact_residual(c.W, q, c.mu, x, &rel);
    double best_rel = rel;
    if (rel <= p.tol) return true;
    Eval e;
    evaluate(c, q, x, formulation, rn, rt, e, true);
    for (int it = 0; it < p.max_iter; ++it) {
        // J = A + B (W + delta I); delta > 0 only where J is singular (degenerate W_aa).
        double J[9], d[3];
        const double rhs[3] = {-e.phi[0], -e.phi[1], -e.phi[2]};
        bool ok = false;
        for (double delta = 0.0; !ok && delta < 1e3 * c.rho0 + 1.0; delta = delta == 0.0 ? 1e-10 : delta * 100.0) {
            const double shift = c.rho0 > 0.0 ? delta / c.rho0 : delta;
            for (int j = 0; j < 3; ++j)
                for (int i = 0; i < 3; ++i)
                    J[i + 3 * j] = e.A[i + 3 * j] + shift * e.B[i + 3 * j] + e.B[i] * c.W[3 * j] +
                                   e.B[i + 3] * c.W[3 * j + 1] + e.B[i + 6] * c.W[3 * j + 2];
            ok = solve3(J, rhs, d);
        }
        if (!ok) break;
        double t = 1.0;
        if (line_search) {
            // Goldstein-Price on 1/2 |Phi|^2, whose slope along the Newton step is -2 merit. A
            // search that ends without a sufficient decrease takes the step where it left off
            // if its last trial decreased the merit, else Newton stops.
            Eval trial;
            const auto merit = [&](double step) {
                double xt[3];
                for (int i = 0; i < 3; ++i) xt[i] = x[i] + step * d[i];
                evaluate(c, q, xt, formulation, rn, rt, trial, false);
                return trial.merit;
            };
            int64_t trials = 0;
            const kit::SearchResult s =
                kit::goldstein_price(merit, e.merit, -2.0 * e.merit, kLineSearchTrials, trials, false);
            if (!s.accepted && !(s.last_merit < e.merit)) break;
            t = s.t;
        }
        for (int i = 0; i < 3; ++i) x[i] += t * d[i];
        evaluate(c, q, x, formulation, rn, rt, e, true);
        coulomb::contact_residual(c.W, q, c.mu, x, &rel);
        if (!std::isfinite(rel)) break;
        if (rel < best_rel) {
            best_rel = rel;
            std::copy(x, x + 3, best);
        }
        if (rel <= p.tol) break;
    }
    std::copy(best, best + 3, r);
    return best_rel <= p.tol;
}

}  // namespace frix::local
