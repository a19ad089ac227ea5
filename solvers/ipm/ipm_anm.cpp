// IPM-ANM (id 903): the interior-point path of Coulomb's law followed by Taylor series (an
// asymptotic numerical method), then semismooth Newton from its best point.
//
// Per contact with friction the law is written with one extra unknown s as
//   x = (mu r_N, r_T) in L,  y = (u_N / mu + s, u_T) in L,  x∘y = 0,  s^2 = |u_T|^2,
// L the Lorentz cone and ∘ its Jordan product: with s = |u_T|, y is the modified velocity û
// scaled by 1/mu in its normal part, and x∘y = 0 is r ⟂ û. Every equation is bilinear in
// (r, s) once u = W r + q is put in. A frictionless contact keeps x = r_N, y = u_N + s with
// s = 0 and r_T = 0.
//
// From an interior start X0 = (r0, s0) the path is R(X) = lambda R(X0), R the residual of the
// equations above (x∘y and s^2 - |u_T|^2), lambda from 1 down to 0, where it is the law. The
// path is followed by pseudo-arclength in (X, lambda), so that it can pass where lambda turns
// back: each step factorises the Jacobian once, computes the path's Taylor series to order
// kOrder with that one factorisation (one solve per order), and steps as far as the series is
// accurate to kSeriesAccuracy (Cochelin's radius), less where an iterate would leave the cones;
// a chord Newton correction with the same factorisation brings the end back onto the path.
// u and s are eliminated contact by contact, which leaves (W + D) dr = g as in ipm.cpp.
//
// Interior iterates converge slowly where the answer is not strictly complementary: the error
// falls like sqrt(lambda). The method therefore hands over to Newton (Alart-Curnier) from its
// best point once lambda is spent, the series stalls, or the error stops falling. Coulomb's
// law is not monotone: nothing guarantees that the path reaches lambda = 0.
#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include "solvers/kit/lorentz.hpp"
#include "src/error_state.hpp"
#include "src/linalg/linalg.hpp"
#include "src/log.hpp"
#include "src/matrix.hpp"
#include "solvers/entries.hpp"

namespace frix {
namespace ipm_anm {

namespace {

using lorentz::jordan;
using lorentz::jordan_solve;
using lorentz::jnorm2;
using lorentz::mul3;
using lorentz::SystemPattern;

// Order of the Taylor series and the accuracy that sets a step's length: the series' last
// term may change the point by this much (relative to the unit tangent).
constexpr int kOrder = 10;
constexpr double kSeriesAccuracy = 1e-6;
// A step is cut by this factor until its end lies inside the cones (at most kMaxCuts times).
constexpr double kCut = 0.7;
constexpr int kMaxCuts = 60;
// Chord corrections at a step's end, with the step's factorisation.
constexpr int kCorrections = 2;
// Newton takes over when lambda falls below kLambdaEnd (the error then is about
// sqrt(lambda)), after kStallSteps steps without halving the best error, or when the series
// gives a step shorter than kMinStep.
constexpr double kLambdaEnd = 1e-16;
constexpr int kStallSteps = 30;
constexpr double kMinStep = 1e-12;

// A point (or a series term) of the path: r, s and lambda; wr holds W r (without q).
struct Point {
    std::vector<double> r, s, wr;
    double lambda = 0.0;
    void resize(int64_t nc) {
        r.assign(3 * nc, 0.0);
        s.assign(nc, 0.0);
        wr.assign(3 * nc, 0.0);
    }
};

using KeptState = lorentz::KeptSystem;

class Solver {
   public:
    Solver(SolveContext &ctx, KeptState &kept)
        : ctx_(ctx), p_(ctx.problem), nc_(p_.nc), m_(3 * p_.nc), kept_(kept) {}
    frix_error run();

   private:
    bool friction(int64_t a) const { return p_.mu[a] > 0.0; }
    // Contact a's cone vectors at the point (r, s) with u = wr + q.
    void cone_x(const Point &X, int64_t a, double *x) const {
        x[0] = friction(a) ? p_.mu[a] * X.r[3 * a] : X.r[3 * a];
        x[1] = X.r[3 * a + 1];
        x[2] = X.r[3 * a + 2];
    }
    // The linear part of y (without q) when `with_q` is false: the series' terms.
    void cone_y(const Point &X, int64_t a, bool with_q, double *y) const {
        const double *q = &p_.q[3 * a];
        const double uN = X.wr[3 * a] + (with_q ? q[0] : 0.0);
        y[0] = friction(a) ? uN / p_.mu[a] + X.s[a] : uN + X.s[a];
        y[1] = X.wr[3 * a + 1] + (with_q ? q[1] : 0.0);
        y[2] = X.wr[3 * a + 2] + (with_q ? q[2] : 0.0);
    }
    // R(X): 4 entries per contact (x∘y, then s^2 - |u_T|^2; frictionless: r_N y_0, r_T, s).
    void residual(const Point &X, std::vector<double> &R) const;
    // The quadratic terms of R between two series terms, added to out.
    void add_quadratic(const Point &A, const Point &B, std::vector<double> &out) const;
    bool interior(const Point &X) const;
    frix_error factor(const Point &X);
    // Solves J (dr, ds) = b at the factorised point (b: 4 per contact).
    frix_error solve(const std::vector<double> &b, Point &d);
    void product(Point &X) const { matrix_gemv(*p_.W, 1.0, X.r.data(), 0.0, X.wr.data()); }
    double dot(const Point &A, const Point &B) const;
    // The steps of run(), in order.
    Point interior_start();
    frix_error step(lorentz::Run &run, Point &X, int verbosity, const char *&why, bool &go_on);
    frix_error series(bool turning, bool &finite);
    bool step_end(const Point &X, double &length, Point &Y) const;
    double distance_off_path(const Point &Y);
    frix_error correct(Point &Y);

    SolveContext &ctx_;
    const frix_problem &p_;
    const int64_t nc_, m_;
    KeptState &kept_;
    double r_scale_ = 1.0, s_scale_ = 1.0;
    Point at_;                            // the factorised point
    std::vector<double> T_, D_, values_;  // per contact: T = L(x)^-1 L(y) diag(mu, 1, 1), D
    std::vector<double> t_, rhs_;         // per contact, in solve(): L(x)^-1 b's Jordan part
    // The path: R0 = R(X0), the series' terms U[k] (U[0] unused), y (J y = R0), the
    // correction d; R and b scratch (4 per contact).
    std::vector<double> R0_, R_, b_;
    std::vector<Point> U_;
    Point y_, d_;
};

void Solver::residual(const Point &X, std::vector<double> &R) const {
    R.assign(4 * nc_, 0.0);
    for (int64_t a = 0; a < nc_; ++a) {
        double x[3], y[3];
        cone_x(X, a, x);
        cone_y(X, a, true, y);
        double *Ra = &R[4 * a];
        if (!friction(a)) {
            Ra[0] = x[0] * y[0];
            Ra[1] = x[1];
            Ra[2] = x[2];
            Ra[3] = X.s[a];
            continue;
        }
        jordan(x, y, Ra);
        Ra[3] = X.s[a] * X.s[a] - y[1] * y[1] - y[2] * y[2];
    }
}

void Solver::add_quadratic(const Point &A, const Point &B, std::vector<double> &out) const {
    for (int64_t a = 0; a < nc_; ++a) {
        double x[3], y[3];
        cone_x(A, a, x);
        cone_y(B, a, false, y);
        double *o = &out[4 * a];
        if (!friction(a)) {
            o[0] += x[0] * y[0];
            continue;
        }
        double z[3];
        jordan(x, y, z);
        o[0] += z[0];
        o[1] += z[1];
        o[2] += z[2];
        o[3] += A.s[a] * B.s[a] - A.wr[3 * a + 1] * B.wr[3 * a + 1] - A.wr[3 * a + 2] * B.wr[3 * a + 2];
    }
}

bool Solver::interior(const Point &X) const {
    for (int64_t a = 0; a < nc_; ++a) {
        double x[3], y[3];
        cone_x(X, a, x);
        cone_y(X, a, true, y);
        if (!friction(a)) {
            if (!(x[0] > 0.0 && y[0] > 0.0)) return false;
            continue;
        }
        if (!(x[0] > 0.0 && y[0] > 0.0 && jnorm2(x) > 0.0 && jnorm2(y) > 0.0 && X.s[a] > 0.0))
            return false;
    }
    return std::isfinite(X.lambda);
}

frix_error Solver::factor(const Point &X) {
    at_ = X;
    for (int64_t a = 0; a < nc_; ++a) {
        double x[3], y[3];
        cone_x(X, a, x);
        cone_y(X, a, true, y);
        double *D = &D_[9 * a], *T = &T_[9 * a];
        std::fill(D, D + 9, 0.0);
        if (!friction(a)) {  // y0 dr_N + r_N (du_N + ds) = b0, ds = b1; r_T's rows: identity
            D[0] = y[0] / x[0];
            continue;
        }
        // Columns of L(y) diag(mu, 1, 1), each solved with x: T = L(x)^-1 L(y) diag(mu, 1, 1).
        const double cols[3][3] = {{p_.mu[a] * y[0], p_.mu[a] * y[1], p_.mu[a] * y[2]},
                                   {y[1], y[0], 0.0},
                                   {y[2], 0.0, y[0]}};
        for (int j = 0; j < 3; ++j) {
            double t[3];
            jordan_solve(x, cols[j], t);
            for (int i = 0; i < 3; ++i) T[3 * i + j] = t[i];
        }
        // du_T = t_T - T_T dr; ds = b1 / 2s + u_T.du_T / s; du_N = mu (dy_0 - ds).
        const double s = X.s[a];
        for (int j = 0; j < 3; ++j) {
            D[3 + j] = T[3 + j];
            D[6 + j] = T[6 + j];
            D[j] = p_.mu[a] * (T[j] - (y[1] * T[3 + j] + y[2] * T[6 + j]) / s);
        }
    }
    kept_.pat.assemble(*p_.W, D_.data(), values_);
    linalg::CscView A{m_, m_, kept_.pat.colptr.data(), kept_.pat.rowind.data(), values_.data()};
    if (!kept_.analysed) {
        if (frix_error e = kept_.lu.analyze(A)) return e;
        kept_.analysed = true;
    }
    return kept_.lu.factor(A);
}

frix_error Solver::solve(const std::vector<double> &b, Point &d) {
    for (int64_t a = 0; a < nc_; ++a) {
        double x[3], y[3];
        cone_x(at_, a, x);
        cone_y(at_, a, true, y);
        const double *ba = &b[4 * a];
        if (!friction(a)) {
            rhs_[3 * a] = ba[0] / x[0] - ba[3];
            rhs_[3 * a + 1] = ba[1];
            rhs_[3 * a + 2] = ba[2];
            continue;
        }
        double *t = &t_[3 * a];
        jordan_solve(x, ba, t);
        const double s = at_.s[a];
        rhs_[3 * a] = p_.mu[a] * (t[0] - 0.5 * ba[3] / s - (y[1] * t[1] + y[2] * t[2]) / s);
        rhs_[3 * a + 1] = t[1];
        rhs_[3 * a + 2] = t[2];
    }
    if (frix_error e = kept_.lu.solve(rhs_.data(), d.r.data())) return e;
    for (int64_t a = 0; a < nc_; ++a) {
        const double *ba = &b[4 * a];
        if (!friction(a)) {
            d.s[a] = ba[3];
            continue;
        }
        double y[3], Tdr[3];
        cone_y(at_, a, true, y);
        const double *t = &t_[3 * a];
        mul3(&T_[9 * a], &d.r[3 * a], Tdr);
        const double s = at_.s[a];
        d.s[a] = 0.5 * ba[3] / s + (y[1] * (t[1] - Tdr[1]) + y[2] * (t[2] - Tdr[2])) / s;
    }
    product(d);
    return FRIX_OK;
}

// The scaled inner product of the arclength: r in units of the start's force, s of its
// velocity, both as means over the contacts, and lambda as it is.
double Solver::dot(const Point &A, const Point &B) const {
    double sr = 0.0, ss = 0.0;
    for (int64_t i = 0; i < m_; ++i) sr += A.r[i] * B.r[i];
    for (int64_t a = 0; a < nc_; ++a) ss += A.s[a] * B.s[a];
    return (sr / (r_scale_ * r_scale_) + ss / (s_scale_ * s_scale_)) / (double)nc_ + A.lambda * B.lambda;
}

frix_error Solver::run() {
    const frix_options &o = ctx_.options;
    frix_info &info = ctx_.info;
    const int verbosity = (int)o.i(FRIX_OPT_VERBOSITY);
    lorentz::Run run(ctx_, kept_, kStallSteps);
    T_.assign(9 * nc_, 0.0);
    D_.assign(9 * nc_, 0.0);
    t_.assign(m_, 0.0);
    rhs_.assign(m_, 0.0);
    Point X = interior_start();
    residual(X, R0_);
    U_.assign(kOrder + 1, Point());
    for (Point &t : U_) t.resize(nc_);
    y_.resize(nc_);
    d_.resize(nc_);
    b_.assign(4 * nc_, 0.0);
    const char *why = nullptr;  // why the path hands over to Newton (null: it does not)
    for (bool go_on = true; go_on;)
        if (frix_error e = step(run, X, verbosity, why, go_on)) return e;
    const bool handed_over = why != nullptr;
    const int64_t path_steps = run.iterations();
    if (handed_over && verbosity >= 1)
        log_line(&o, "ipm-anm: %lld steps (%s), lambda %.3e, best error %.3e; Newton from there",
                 (long long)path_steps, why, X.lambda, run.best_error());
    if (frix_error e = run.end(handed_over)) return e;
    if (verbosity >= 1)
        log_line(&o, "ipm-anm: %s after %lld iterations (%lld path steps, %lld Newton)",
                 frix_status_string(info.status), (long long)info.iterations, (long long)path_steps,
                 (long long)run.newton_steps());
    return FRIX_OK;
}

// Interior start, scaled like the problem (as ipm's): r on the cones' axes, s so that y lies
// inside L by at least the velocity scale.
Point Solver::interior_start() {
    const lorentz::StartScales scale = lorentz::start_scales(p_);
    s_scale_ = scale.velocity;
    r_scale_ = scale.force;
    Point X;
    X.resize(nc_);
    for (int64_t a = 0; a < nc_; ++a) X.r[3 * a] = r_scale_;
    product(X);
    for (int64_t a = 0; a < nc_; ++a) {
        const double uN = X.wr[3 * a] + p_.q[3 * a];
        const double uT = std::hypot(X.wr[3 * a + 1] + p_.q[3 * a + 1], X.wr[3 * a + 2] + p_.q[3 * a + 2]);
        X.s[a] = friction(a) ? uT + std::max(0.0, -uN) / p_.mu[a] + s_scale_ : std::max(0.0, -uN) + s_scale_;
    }
    X.lambda = 1.0;
    return X;
}

// One step of the path from X: the Jacobian factorised at X, the series, its end cut into the
// cones and corrected; X moves there. go_on is false when the path ends here: why is then
// set if Newton takes over.
frix_error Solver::step(lorentz::Run &run, Point &X, int verbosity, const char *&why, bool &go_on) {
    go_on = false;
    const lorentz::Run::Next next = run.check(X.r.data());
    if (next == lorentz::Run::kStop) return FRIX_OK;
    if (next == lorentz::Run::kHandOver) {
        why = "the error stopped falling";
        return FRIX_OK;
    }
    if (X.lambda < kLambdaEnd) {
        why = "lambda spent";
        return FRIX_OK;
    }
    if (frix_error e = factor(X)) {
        if (e != FRIX_ERR_NUMERICAL) return e;
        clear_error();
        if (kept_.lu.refused()) ctx_.info.status = kept_.lu.refused();  // it would overrun the time or memory limit
        else why = "a singular Jacobian";
        return FRIX_OK;
    }
    run.count_iteration();
    bool finite = false;
    if (frix_error e = series(run.iterations() > 1, finite)) return e;
    const double last = std::sqrt(dot(U_[kOrder], U_[kOrder]));
    double length = finite ? std::pow(kSeriesAccuracy / last, 1.0 / (kOrder - 1)) : 0.0;
    if (!std::isfinite(length)) length = 0.0;
    Point Y;
    if (!step_end(X, length, Y)) {
        why = "the series gave no step";
        return FRIX_OK;
    }
    const double off_path = verbosity >= 2 ? distance_off_path(Y) : 0.0;
    if (frix_error e = correct(Y)) return e;
    if (verbosity >= 2)
        log_line(&ctx_.options, "ipm-anm: step %lld lambda %.3e length %.3g off the path %.3e error %.3e",
                 (long long)run.iterations(), Y.lambda, length, off_path, run.last_error());
    X = std::move(Y);
    go_on = true;
    return FRIX_OK;
}

// The series' terms U[1 .. kOrder] at the factorised point. Order 1: the unit tangent
// (X_1, lambda_1) = lambda_1 (y, 1), J y = R0, oriented as the last one (lambda falling at
// the start; `turning`: there is a last one). Orders k >= 2: J X_k - lambda_k R0 =
// -sum_{i+j=k} Q(X_i, X_j) with <X_k, X_1> + lambda_k lambda_1 = 0. finite: every lambda_k is.
frix_error Solver::series(bool turning, bool &finite) {
    if (frix_error e = solve(R0_, y_)) return e;
    y_.lambda = 1.0;
    double l1 = 1.0 / std::sqrt(dot(y_, y_));
    if (turning) {
        const double turn = l1 * (dot(y_, U_[1]));
        if (turn < 0.0) l1 = -l1;
    } else {
        l1 = -l1;
    }
    Point &U1 = U_[1];
    for (int64_t i = 0; i < m_; ++i) {
        U1.r[i] = l1 * y_.r[i];
        U1.wr[i] = l1 * y_.wr[i];
    }
    for (int64_t a = 0; a < nc_; ++a) U1.s[a] = l1 * y_.s[a];
    U1.lambda = l1;
    const double y_dot_1 = dot(y_, U1);  // y.lambda = 1: <y, X_1> + lambda_1
    finite = std::isfinite(l1);
    for (int k = 2; k <= kOrder && finite; ++k) {
        std::fill(b_.begin(), b_.end(), 0.0);
        for (int i = 1; i < k; ++i) add_quadratic(U_[i], U_[k - i], b_);
        for (double &v : b_) v = -v;
        Point &Uk = U_[k];
        if (frix_error e = solve(b_, Uk)) return e;
        Uk.lambda = 0.0;
        const double lk = -dot(Uk, U1) / y_dot_1;
        for (int64_t i = 0; i < m_; ++i) {
            Uk.r[i] += lk * y_.r[i];
            Uk.wr[i] += lk * y_.wr[i];
        }
        for (int64_t a = 0; a < nc_; ++a) Uk.s[a] += lk * y_.s[a];
        Uk.lambda = lk;
        finite = std::isfinite(lk);
    }
    return FRIX_OK;
}

// Y = the series' sum at `length` from X, the length cut until Y lies inside the cones with
// lambda > 0; false if none down to kMinStep does.
bool Solver::step_end(const Point &X, double &length, Point &Y) const {
    Y = X;
    for (int cut = 0; cut < kMaxCuts && length >= kMinStep; ++cut, length *= kCut) {
        for (int64_t i = 0; i < m_; ++i) {
            double r = 0.0, w = 0.0;
            for (int k = kOrder; k >= 1; --k) {
                r = (r + U_[k].r[i]) * length;
                w = (w + U_[k].wr[i]) * length;
            }
            Y.r[i] = X.r[i] + r;
            Y.wr[i] = X.wr[i] + w;
        }
        for (int64_t a = 0; a < nc_; ++a) {
            double s = 0.0;
            for (int k = kOrder; k >= 1; --k) s = (s + U_[k].s[a]) * length;
            Y.s[a] = X.s[a] + s;
        }
        double l = 0.0;
        for (int k = kOrder; k >= 1; --k) l = (l + U_[k].lambda) * length;
        Y.lambda = X.lambda + l;
        if (Y.lambda > 0.0 && interior(Y)) return true;
    }
    return false;
}

// How far Y lies off the path, relative to |R0| (logged): the series' accuracy, before the
// corrections hide it.
double Solver::distance_off_path(const Point &Y) {
    residual(Y, R_);
    double g = 0.0, g0 = 0.0;
    for (int64_t i = 0; i < 4 * nc_; ++i) {
        g += (R_[i] - Y.lambda * R0_[i]) * (R_[i] - Y.lambda * R0_[i]);
        g0 += R0_[i] * R0_[i];
    }
    return std::sqrt(g / g0);
}

// Chord corrections at fixed lambda: J dX = -(R(Y) - lambda R0), within the cones.
frix_error Solver::correct(Point &Y) {
    for (int c = 0; c < kCorrections; ++c) {
        residual(Y, R_);
        for (int64_t i = 0; i < 4 * nc_; ++i) b_[i] = -(R_[i] - Y.lambda * R0_[i]);
        if (frix_error e = solve(b_, d_)) return e;
        double t = 1.0;
        Point Z = Y;
        bool inside_z = false;
        for (int cut = 0; cut < 20 && !inside_z; ++cut, t *= 0.5) {
            for (int64_t i = 0; i < m_; ++i) {
                Z.r[i] = Y.r[i] + t * d_.r[i];
                Z.wr[i] = Y.wr[i] + t * d_.wr[i];
            }
            for (int64_t a = 0; a < nc_; ++a) Z.s[a] = Y.s[a] + t * d_.s[a];
            inside_z = interior(Z);
        }
        if (!inside_z) break;
        Y = std::move(Z);
    }
    return FRIX_OK;
}

frix_error solve(SolveContext &ctx) {
    if (!ctx.problem.W || !ctx.problem.W->block)
        return fail(FRIX_ERR_INTERNAL, "ipm-anm: W is not stored as 3x3 blocks");
    Kept<KeptState> kept(ctx.cache, FRIX_SOLVER_IPM_ANM);
    Solver solver(ctx, *kept);
    if (frix_error e = solver.run()) return e;
    kept.keep();
    return FRIX_OK;
}

const frix_option_key kExtraKeys[] = {(frix_option_key)0};
const OptionDefault kDefaults[] = {{FRIX_OPT_MAX_ITER, 1000}, {(frix_option_key)0, 0}};

}  // namespace
}  // namespace ipm_anm

const SolverEntry kIpmAnmEntry = {
    FRIX_SOLVER_IPM_ANM, "ipm-anm", nullptr,
    "Interior-point path of Coulomb's law (x = (mu r_N, r_T) and y = (u_N / mu + s, u_T) in the "
    "Lorentz cone, x∘y = 0, s^2 = |u_T|^2) followed by pseudo-arclength with Taylor series of "
    "order 10 (asymptotic numerical method): one UMFPACK factorisation of W + D per step. "
    "Semismooth Newton (Alart-Curnier) continues from the best point once the path is spent "
    "or stalls. No convergence guarantee (Coulomb's law is not monotone). The warm start only "
    "ends the solve at once when it meets the tolerance. Iterations count path steps plus "
    "Newton steps.",
    ipm_anm::solve, true, false, ipm_anm::kExtraKeys, ipm_anm::kDefaults};

}  // namespace frix
