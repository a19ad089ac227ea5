// The existence check (frix_problem_check_existence).
//
// A frictional contact problem has a solution when the velocities it can produce meet the
// interior of the dual cone: some z with u(z) = A z + b strictly inside K* at every contact
// (local: A = W, b = q; global: A = H^T, b = w, z = v; Klarbring-Pang, Cadoux). When no
// such z exists a separating y does: y in K, y != 0, A^T y = 0 and b.y <= 0, a
// self-equilibrated reaction in the friction cones that does no work.
//
// Both come out of one convex problem. With e = (1, 0, 0) at every contact and a shift t > 0,
//     minimise f_t(z) = 1/2 dist^2(u(z) - t e, K*),
// whose gradient is -A^T y with y = P_K(t e - u(z)) (Moreau: x - P_K*(x) = -P_K(-x)).
//   - An iterate with u(z) - (t/2) e in K* is a witness: a solution exists.
//   - Near a minimiser with f_t > 0, y is in K with A^T y ~ 0 and (b - t e).y = -|y|^2 < 0.
//     b.y / sum_a y_N,a bounds from above the best shift t* = sup{t : some z has
//     u(z) - t e in K*}: negative, y is the certificate; positive, t was too large and the
//     search goes on with half that bound.
// The minimisation is FISTA with function restarts and a backtracked step 1/L, L first
// estimated by power iterations, in preconditioned variables (class Operator). A witness is
// checked in the original variables, u(z) recomputed from z; a certificate is accepted when
// the reaction y does no work: y.W y <= kNoWork lambda_max(W) |y|^2 after Jacobi scaling.
#include "existence.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "error_state.hpp"
#include "coulomb.hpp"
#include "matrix.hpp"
#include "measures.hpp"
#include "solver_api.hpp"
#include "vec.hpp"

namespace {

using Vec = std::vector<double>;
using frix::max_abs;
using frix::vec::dot;

// ---- Budget and tolerances.
// time_limit = 0: steps worth about kDefaultWork multiply-adds (a step costs one or two
// products with W or H and a few vector updates), but no fewer than kDefaultMinIterations
// and no more than kDefaultMaxIterations, and never more than kDefaultSeconds. A small
// problem thus gets many cheap steps (ill-conditioned ones need ~10^4: a chain of bodies
// whose masses span 1e6), and the verdict does not depend on the clock below ~10^6 nonzeros
// (about 0.5 s on one core).
constexpr double kDefaultWork = 1e9;
constexpr int64_t kDefaultMinIterations = 1000;
constexpr int64_t kDefaultMaxIterations = 1000000;
constexpr double kDefaultSeconds = 2.0;
// An explicit time limit: that many seconds, and at most kMaxIterations steps.
constexpr int64_t kMaxIterations = 100000000;
constexpr double kMaxTimeLimit = 1e9;  // the upper bound of FRIX_OPT_TIME_LIMIT
constexpr int kPowerIterations = 30;
// A y in K with |y.W y| <= kNoWork lambda_max(W) |y|^2 and |W y|^2 <= kNoWork lambda_max^2
// |y|^2 (W Jacobi-scaled; for a global problem the W of diag(M)) counts as W y = 0: y is then
// the exact certificate of a problem whose factor (H, or W^1/2) is moved by a relative
// sqrt(kNoWork). Strict on purpose: a false "no solution may exist" would blame the problem
// for a solver's failure.
constexpr double kNoWork = 1e-12;
// ... and |W^T y|^2 <= kAdjointNoWork kNoWork lambda_max^2 |y|^2, which follows from the two
// above (with 9 for 10) when W's symmetric part is PSD, even if W is not quite symmetric (W's
// assembled by simulators often are not: the shared Siconos problems' to 1e-5..2e-2 of
// their largest entry).
constexpr double kAdjointNoWork = 10.0;
// A witness must clear the cone by more than the rounding of u(z) = A z + b.
constexpr double kWitnessFloor = 1e-10;
// A best shift below this share of |D b|_rms means the problem sits on the boundary between
// having a strictly feasible point and not: no strictly feasible point within rounding.
constexpr double kBoundaryShift = 1e-9;
// A Rayleigh quotient y.K y below -kIndefinite L |y|^2 tells that W's symmetric part is not
// PSD (beyond the noise of assembled W's: down to -5e-6 L in the shared problems), so that
// the metric of W may not descend.
constexpr double kIndefinite = 1e-6;
// The step 1/L may shrink this far below 1/|K| (backtracking makes up for a low estimate of
// |K|): further means the direction does not descend, which a PSD K rules out.
constexpr double kMaxStepShrink = 1e6;
// A witness is confirmed by a Cholesky factorisation of W's symmetric part, shifted by
// kIndefinite (frix::symmetric_part_psd), where that is cheap enough.
// u is recomputed from z this often: the updates u += K y / L drift by rounding.
constexpr int64_t kResyncEvery = 100;

// The root mean square over contacts of |x_a|: the scale of margins. Summed over x / max|x|,
// so that no square overflows or underflows.
double contact_rms(const double *x, int64_t nc) {
    const double largest = max_abs(x, 3 * nc);
    if (!(largest > 0.0) || !std::isfinite(largest)) return largest;
    double s = 0.0;
    for (int64_t i = 0; i < 3 * nc; ++i) s += (x[i] / largest) * (x[i] / largest);
    return largest * std::sqrt(s / (double)nc);
}

// min_a (u_N,a - mu_a |u_T,a|): the largest s with u - s e in K* at every contact.
double dual_cone_margin(const double *u, const double *mu, int64_t nc) {
    double s = std::numeric_limits<double>::infinity();
    for (int64_t a = 0; a < nc; ++a)
        s = std::min(s, u[3 * a] - mu[a] * std::hypot(u[3 * a + 1], u[3 * a + 2]));
    return s;
}

// y_a = P_K(t e - u_a) at every contact (y may be null); returns 1/2 |y|^2, which is
// 1/2 dist^2(u - t e, K*) by Moreau's decomposition.
double cone_residual(const double *u, double t, const double *mu, int64_t nc, double *y) {
    double f = 0.0;
    for (int64_t a = 0; a < nc; ++a) {
        double x[3] = {t - u[3 * a], -u[3 * a + 1], -u[3 * a + 2]};
        frix::coulomb::project_on_cone(x, mu[a]);
        f += 0.5 * (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
        if (y) std::copy(x, x + 3, y + 3 * a);
    }
    return f;
}

// Multiply-adds of one step in the diagonal metric: two products, and the vector updates.
double step_cost(const frix_problem &p) {
    const frix_matrix &A = p.kind == FRIX_PROBLEM_LOCAL ? *p.W : *p.H;
    const double nnz = A.block ? 9.0 * (double)A.nblocks() : (double)A.val.size();
    return 2.0 * nnz + 16.0 * (double)(3 * p.nc + p.n);
}

class Budget {
   public:
    Budget(double time_limit, double step_cost)
        : seconds_(time_limit > 0.0 ? time_limit : kDefaultSeconds),
          iterations_(time_limit > 0.0 ? kMaxIterations : default_iterations(step_cost)) {}
    // Counts one step; false once the steps or the seconds are used up.
    bool next() { return ++used_ <= iterations_ && clock_.seconds() < seconds_; }

   private:
    static int64_t default_iterations(double step_cost) {
        const double steps = kDefaultWork / std::max(step_cost, 1.0);
        return (int64_t)std::clamp(steps, (double)kDefaultMinIterations, (double)kDefaultMaxIterations);
    }

    frix::Stopwatch clock_;
    double seconds_;
    int64_t iterations_;
    int64_t used_ = 0;
};

// How the search measures z (below, Operator).
enum class Metric {
    OfW,       // local problems: z moves by D y, D u by D W D y (one product per step)
    Diagonal,  // z moves by P A^T D y, P diagonal (two products per step)
};

// u(z) = A z + b and the preconditioned directions of the search.
//
// The search runs in scaled variables: each contact's rows multiplied by one d_a > 0 (cone
// membership does not change), and z measured in a metric P, so that a step
// z += P A^T D y / L moves the scaled velocities D u by K y / L, K = D A P A^T D, L = |K|.
//   - d_a = 1 / sqrt(mean diagonal of the contact's block of W), W = H^T diag(M)^-1 H for a
//     global problem: Jacobi scaling, which evens out contacts on bodies of very different
//     masses.
//   - Metric::OfW, local problems: P = W^-1 on range(W), so K = D W D has the condition
//     number of W instead of its square, and a step costs one product. It is a descent
//     direction when W's symmetric part is PSD (the search falls back on the next metric
//     when it finds otherwise).
//   - Metric::Diagonal: P = D^2 (local) or diag(M)^-1 (global), K = (D A P^1/2)(D A P^1/2)^T:
//     exact for any A, two products per step.
class Operator {
   public:
    Operator(const frix_problem &p, Metric metric)
        : p_(p), nc_(p.nc), m_(3 * p.nc), n_(p.kind == FRIX_PROBLEM_LOCAL ? 3 * p.nc : p.n),
          metric_(metric), work_m_(m_) {
        // diag(M)^-1 where that diagonal is positive (1 elsewhere): the metric of v.
        if (p.kind == FRIX_PROBLEM_GLOBAL) dof_metric_ = frix::inverse_mass_diagonal(p, 1.0);
        set_contact_scales();
        if (p.kind == FRIX_PROBLEM_LOCAL && metric == Metric::Diagonal) {
            dof_metric_.resize(n_);
            for (int64_t j = 0; j < n_; ++j) dof_metric_[j] = d_[j / 3] * d_[j / 3];
        }
    }

    int64_t contacts() const { return nc_; }
    int64_t contact_dofs() const { return m_; }
    int64_t dofs() const { return n_; }
    Metric metric() const { return metric_; }
    const double *b() const { return p_.kind == FRIX_PROBLEM_LOCAL ? p_.q : p_.w; }
    const double *mu() const { return p_.mu; }
    double scale(int64_t a) const { return d_[a]; }

    // The largest y.K y / (L |y|^2) of a certificate y: the work criterion where K is a
    // W (metric of W, global problems), its square where K = D W D^2 W^T D (a local problem
    // in the diagonal metric: |D W^T D y| <= kNoWork |D W D| |y|).
    double certificate_threshold() const {
        return p_.kind == FRIX_PROBLEM_LOCAL && metric_ == Metric::Diagonal ? kNoWork * kNoWork : kNoWork;
    }
    // Whether a y meeting certificate_threshold() also has |D A^T D y|^2 <= eps L^2 |y|^2
    // (kAdjointNoWork kNoWork), as a certificate must: true by construction in the diagonal
    // metric; in the metric of W, where only D W D y is at hand, one more product checks it
    // (a W whose symmetric part is not PSD can have W y = 0 with W^T y != 0).
    bool certifies(const Vec &y, double L) const {
        if (metric_ == Metric::Diagonal) return true;
        Vec Dy(m_), WtDy(m_);
        for (int64_t i = 0; i < m_; ++i) Dy[i] = d_[i / 3] * y[i];
        adjoint(Dy.data(), WtDy.data());
        double sq = 0.0, yy = 0.0;
        for (int64_t i = 0; i < m_; ++i) {
            sq += d_[i / 3] * d_[i / 3] * WtDy[i] * WtDy[i];
            yy += y[i] * y[i];
        }
        return sq <= kAdjointNoWork * kNoWork * L * L * yy;
    }

    // u = A (factor z) + b, in the original variables.
    void values(const double *z, double factor, double *u) const {
        product(z, u);
        const double *b = this->b();
        for (int64_t i = 0; i < m_; ++i) u[i] = factor * u[i] + b[i];
    }
    // u = D A z + b_scaled.
    void scaled_values(const double *z, const Vec &b_scaled, double *u) const {
        product(z, u);
        scale_contacts(u);
        for (int64_t i = 0; i < m_; ++i) u[i] += b_scaled[i];
    }
    // dz = P A^T D y and Ky = D A dz.
    void directions(const double *y, double *dz, double *Ky) const {
        for (int64_t i = 0; i < m_; ++i) work_m_[i] = d_[i / 3] * y[i];
        if (metric_ == Metric::OfW) {
            std::copy(work_m_.begin(), work_m_.end(), dz);
        } else {
            adjoint(work_m_.data(), dz);
            for (int64_t j = 0; j < n_; ++j) dz[j] *= dof_metric_[j];
        }
        product(dz, Ky);
        scale_contacts(Ky);
    }

   private:
    void scale_contacts(double *u) const {
        for (int64_t i = 0; i < m_; ++i) u[i] *= d_[i / 3];
    }
    void product(const double *z, double *u) const {  // u = A z
        if (p_.kind == FRIX_PROBLEM_LOCAL)
            frix::matrix_gemv(*p_.W, 1.0, z, 0.0, u);
        else
            frix::matrix_gemv_transposed(*p_.H, 1.0, z, 0.0, u);
    }
    void adjoint(const double *y, double *z) const {  // z = A^T y
        if (p_.kind == FRIX_PROBLEM_LOCAL)
            frix::matrix_gemv_transposed(*p_.W, 1.0, y, 0.0, z);
        else
            frix::matrix_gemv(*p_.H, 1.0, y, 0.0, z);
    }

    // d_a from the contact's mean diagonal; contacts without a usable one (no coupling, or
    // an overflow) take the mean of the others, so that they weigh like a typical contact.
    void set_contact_scales() {
        const Vec diag = frix::delassus_diagonal(p_, dof_metric_);
        Vec mean(nc_);
        double sum = 0.0;
        int64_t counted = 0;
        for (int64_t a = 0; a < nc_; ++a) {
            mean[a] = (diag[3 * a] + diag[3 * a + 1] + diag[3 * a + 2]) / 3.0;
            if (usable(mean[a])) {
                sum += mean[a];
                ++counted;
            }
        }
        const double typical = counted > 0 && usable(sum / (double)counted) ? sum / (double)counted : 1.0;
        d_.resize(nc_);
        for (int64_t a = 0; a < nc_; ++a) d_[a] = 1.0 / std::sqrt(usable(mean[a]) ? mean[a] : typical);
    }
    static bool usable(double diagonal) {
        return diagonal > 0.0 && std::isfinite(diagonal) && std::isfinite(1.0 / std::sqrt(diagonal));
    }

    const frix_problem &p_;
    int64_t nc_, m_, n_;
    Metric metric_;
    Vec d_, dof_metric_;
    mutable Vec work_m_;  // D y
};

struct Norm {
    double value;     // |K| (a slight underestimate: the search backtracks)
    bool indefinite;  // the dominant eigenvalue is negative: K is not PSD
};

// |K| by power iterations from a fixed start (deterministic, and orthogonal to no
// eigenvector in practice).
Norm estimate_norm(const Operator &op) {
    const int64_t m = op.contact_dofs();
    Vec x(m), Kx(m), dz(op.dofs());
    for (int64_t i = 0; i < m; ++i) x[i] = 1.0 + (double)(i % 7) / 7.0;
    double norm = 0.0, rayleigh = 0.0;
    for (int k = 0; k < kPowerIterations; ++k) {
        const double length = std::sqrt(dot(x, x));
        if (!(length > 0.0) || !std::isfinite(length)) break;
        for (double &xi : x) xi /= length;
        op.directions(x.data(), dz.data(), Kx.data());
        rayleigh = dot(x, Kx);
        norm = std::sqrt(dot(Kx, Kx));
        if (!(norm > 0.0) || !std::isfinite(norm)) break;
        x.swap(Kx);
    }
    return {norm, rayleigh < -kIndefinite * norm};
}

enum class Outcome {
    Verdict,
    NeedsDiagonalMetric,  // the metric of W cannot settle this problem (W's symmetric part
                          // is not PSD): start again in the other
};

struct Result {
    Outcome outcome;
    frix_existence verdict;
    double margin;
    bool indefinite = false;  // W's symmetric part showed a negative curvature
};

// One run of the search (see the top of the file) on one Operator.
class Search {
   public:
    Search(const Operator &op, Budget &budget)
        : op_(op), budget_(budget), nc_(op.contacts()), m_(op.contact_dofs()), n_(op.dofs()),
          mu_(op.mu()), b_(op.b()), beta_(contact_rms(b_, nc_)), b_scaled_(m_), y_(m_), Ky_(m_),
          u_(m_), u_prev_(m_), u_ext_(m_), u_new_(m_), z_(n_, 0.0), z_prev_(n_, 0.0), z_ext_(n_),
          z_new_(n_), dz_(n_) {
        // The search sees D b / unit, of unit RMS: its numbers are of order 1 whatever the
        // scales of W and q; z is in units of unit (the witness is unit z).
        for (int64_t i = 0; i < m_; ++i) b_scaled_[i] = op.scale(i / 3) * b_[i];
        const double rms = contact_rms(b_scaled_.data(), nc_);
        unit_ = rms > 0.0 && std::isfinite(rms) ? rms : 1.0;
        for (double &bi : b_scaled_) bi /= unit_;
    }

    Result run() {
        const Norm norm = estimate_norm(op_);
        if (norm.indefinite && op_.metric() == Metric::OfW) return indefinite();
        // K = 0 (no coupling at all): any step is a non-move and every y a certificate.
        norm_ = norm.value > 0.0 && std::isfinite(norm.value) ? norm.value : 1.0;
        L_ = norm_;
        t_ = 1.0;  // the RMS of the scaled b
        u_ = b_scaled_;
        u_prev_ = u_;
        f_ = cone_residual(u_.data(), t_, mu_, nc_, nullptr);
        int64_t since_resync = 0;
        while (budget_.next()) {
            extrapolate();
            const double f_ext = cone_residual(u_ext_.data(), t_, mu_, nc_, y_.data());
            if (!std::isfinite(f_ext)) return undetermined();
            op_.directions(y_.data(), dz_.data(), Ky_.data());
            const double yKy = dot(y_, Ky_), yy = dot(y_, y_);
            if (op_.metric() == Metric::OfW && yKy < -kIndefinite * norm_ * yy) return indefinite();
            if (does_no_work(yKy, yy)) {
                const double t_before = t_;
                if (judge_certificate()) {
                    if (!op_.certifies(y_, norm_)) return needs_diagonal_metric();
                    return {Outcome::Verdict, FRIX_EXISTENCE_DOUBTFUL, margin_};
                }
                if (t_ != t_before) continue;  // a new phase: y belonged to the old shift
            }
            // With K PSD, L >= |K| satisfies the descent lemma: a runaway L means it is not.
            if (!gradient_step(f_ext, yKy))
                return op_.metric() == Metric::OfW ? needs_diagonal_metric() : undetermined();
            if (dual_cone_margin(u_new_.data(), mu_, nc_) >= 0.5 * t_ && is_witness(z_new_))
                return {Outcome::Verdict, FRIX_EXISTENCE_GUARANTEED, margin_};
            advance();
            if (++since_resync >= kResyncEvery) {
                resync();
                since_resync = 0;
            }
        }
        // Out of budget: the last iterate may still clear the cone by less than t/2.
        if (is_witness(z_)) return {Outcome::Verdict, FRIX_EXISTENCE_GUARANTEED, margin_};
        return undetermined();
    }

   private:
    static Result undetermined() { return {Outcome::Verdict, FRIX_EXISTENCE_UNDETERMINED, NAN}; }
    static Result needs_diagonal_metric() {
        return {Outcome::NeedsDiagonalMetric, FRIX_EXISTENCE_NOT_CHECKED, NAN};
    }
    static Result indefinite() { return {Outcome::NeedsDiagonalMetric, FRIX_EXISTENCE_NOT_CHECKED, NAN, true}; }

    // y_ is a candidate certificate: |y.K y| <= eps |K| |y|^2, and |K y|^2 <= eps |K|^2 |y|^2,
    // which follows from the first when K is PSD and excludes the cancellations of an
    // indefinite one. |K| is the power iterations' estimate, which can only be low (stricter),
    // not the backtracked L.
    bool does_no_work(double yKy, double yy) const {
        const double eps = op_.certificate_threshold();
        return yy > 0.0 && std::fabs(yKy) <= eps * norm_ * yy && dot(Ky_, Ky_) <= eps * norm_ * norm_ * yy;
    }

    // z_ext = z + momentum (z - z_prev), the same for u (FISTA).
    void extrapolate() {
        const double theta_next = 0.5 * (1.0 + std::sqrt(1.0 + 4.0 * theta_ * theta_));
        const double momentum = (theta_ - 1.0) / theta_next;
        theta_ = theta_next;
        for (int64_t j = 0; j < n_; ++j) z_ext_[j] = z_[j] + momentum * (z_[j] - z_prev_[j]);
        for (int64_t i = 0; i < m_; ++i) u_ext_[i] = u_[i] + momentum * (u_[i] - u_prev_[i]);
    }

    // z_new = z_ext + dz / L with L doubled until the step decreases f as the descent lemma
    // promises (L from the power iterations may be low). False if L runs away.
    bool gradient_step(double f_ext, double yKy) {
        // f is computed to about eps |y| (|u| + t sqrt(nc)): no backtracking on rounding.
        const double noise = 16.0 * DBL_EPSILON * std::sqrt(2.0 * f_ext) *
                             (std::sqrt(dot(u_ext_, u_ext_)) + t_ * std::sqrt((double)nc_));
        while (L_ <= kMaxStepShrink * norm_) {
            const double h = 1.0 / L_;
            for (int64_t j = 0; j < n_; ++j) z_new_[j] = z_ext_[j] + h * dz_[j];
            for (int64_t i = 0; i < m_; ++i) u_new_[i] = u_ext_[i] + h * Ky_[i];
            f_new_ = cone_residual(u_new_.data(), t_, mu_, nc_, nullptr);
            if (f_new_ <= f_ext - 0.5 * h * yKy + noise) return std::isfinite(f_new_);
            L_ *= 2.0;
        }
        return false;
    }

    // Accepts the step; restarts the momentum when f went up (O'Donoghue-Candes).
    void advance() {
        const bool restart = f_new_ > f_;
        z_prev_.swap(z_);
        z_.swap(z_new_);
        u_prev_.swap(u_);
        u_.swap(u_new_);
        if (restart) restart_momentum();
        f_ = f_new_;
    }

    void restart_momentum() {
        theta_ = 1.0;
        z_prev_ = z_;
        u_prev_ = u_;
    }

    void resync() {
        op_.scaled_values(z_.data(), b_scaled_, u_.data());
        op_.scaled_values(z_prev_.data(), b_scaled_, u_prev_.data());
        f_ = cone_residual(u_.data(), t_, mu_, nc_, nullptr);
    }

    // y_ (scaled, in K, K y ~ 0) as a certificate. True with margin_ set when it settles the
    // question; otherwise it may lower the shift t_ to half the bound it gives.
    bool judge_certificate() {
        double work = 0.0, sum_yN_scaled = 0.0, sum_yN = 0.0;
        for (int64_t i = 0; i < m_; ++i) work += b_scaled_[i] * y_[i];  // = b . (D y) / unit
        for (int64_t a = 0; a < nc_; ++a) {
            sum_yN_scaled += y_[3 * a];
            sum_yN += op_.scale(a) * y_[3 * a];
        }
        if (!(sum_yN_scaled > 0.0) || !(sum_yN > 0.0)) return false;
        const double bound = work / sum_yN_scaled;  // of the best shift, scaled variables
        if (work < 0.0 || bound < kBoundaryShift) {
            margin_ = beta_ > 0.0 ? std::min(work / sum_yN * (unit_ / beta_), 0.0) : 0.0;
            return true;
        }
        if (bound < t_) {
            t_ = 0.5 * bound;
            restart_momentum();
            f_ = cone_residual(u_.data(), t_, mu_, nc_, nullptr);
        }
        return false;
    }

    // True, with margin_ set, if u(z) = A z + b recomputed clears K* by more than rounding.
    bool is_witness(const Vec &z) {
        Vec u(m_);
        op_.values(z.data(), unit_, u.data());
        const double s = dual_cone_margin(u.data(), mu_, nc_);
        const double floor = kWitnessFloor * std::max(max_abs(b_, m_), max_abs(u.data(), m_));
        if (!(s > floor)) return false;
        margin_ = beta_ > 0.0 ? s / beta_ : std::numeric_limits<double>::infinity();
        return true;
    }

    const Operator &op_;
    Budget &budget_;
    const int64_t nc_, m_, n_;
    const double *mu_, *b_;
    const double beta_;  // contact_rms(b): margins are relative to it
    double unit_ = 1.0;  // of b_scaled_ and z (see the constructor)
    double norm_ = 1.0;  // |K| estimated by power iterations
    double L_ = 1.0;     // its backtracked value, for the step 1/L
    double t_ = 1.0, theta_ = 1.0, f_ = 0.0, f_new_ = 0.0, margin_ = NAN;
    Vec b_scaled_, y_, Ky_, u_, u_prev_, u_ext_, u_new_;  // contact space, scaled
    Vec z_, z_prev_, z_ext_, z_new_, dz_;                 // z space
};


}  // namespace

namespace frix {

frix_existence check_existence(const frix_problem &p, double time_limit, double *margin) {
    double unused = NAN;
    double &out = margin ? *margin : unused;
    if (p.nc == 0) {
        out = std::numeric_limits<double>::infinity();
        return FRIX_EXISTENCE_GUARANTEED;
    }
    const double *b = p.kind == FRIX_PROBLEM_LOCAL ? p.q : p.w;
    const double beta = contact_rms(b, p.nc);
    const double s = dual_cone_margin(b, p.mu, p.nc);
    if (s > kWitnessFloor * max_abs(b, 3 * p.nc)) {  // z = 0 is a witness
        out = s / beta;
        return FRIX_EXISTENCE_GUARANTEED;
    }
    Budget budget(time_limit, step_cost(p));
    Result r{Outcome::NeedsDiagonalMetric, FRIX_EXISTENCE_NOT_CHECKED, NAN};
    if (p.kind == FRIX_PROBLEM_LOCAL) {
        const Operator op(p, Metric::OfW);
        r = Search(op, budget).run();
    }
    bool indefinite = false;
    if (r.outcome == Outcome::NeedsDiagonalMetric) {
        indefinite = r.indefinite;
        const Operator op(p, Metric::Diagonal);
        r = Search(op, budget).run();
    }
    // A strictly feasible z proves a solution only when W's symmetric part is PSD (W = -I
    // has one and no solution): with a negative curvature seen, or a factorisation that
    // finds one, the check cannot tell.
    if (r.verdict == FRIX_EXISTENCE_GUARANTEED && p.kind == FRIX_PROBLEM_LOCAL && !separates_at_zero(p) &&
        (indefinite || symmetric_part_psd(p, kIndefinite) == Psd::No)) {
        out = NAN;
        return FRIX_EXISTENCE_UNDETERMINED;
    }
    if (r.verdict != FRIX_EXISTENCE_GUARANTEED && separates_at_zero(p)) {
        out = 0.0;  // no strictly feasible point found, but r = 0 is a solution
        return FRIX_EXISTENCE_GUARANTEED;
    }
    out = r.margin;
    return r.verdict;
}

}  // namespace frix

extern "C" {

FRIX_API frix_error frix_problem_check_existence(const frix_problem *problem, double time_limit,
                                                 frix_info *info) {
    return frix::guard("frix_problem_check_existence", [&]() -> frix_error {
        const char *where = "frix_problem_check_existence";
        if (!problem) return frix::fail(FRIX_ERR_INVALID_ARGUMENT, "%s: problem is NULL", where);
        if (!info) return frix::fail(FRIX_ERR_INVALID_ARGUMENT, "%s: info is NULL", where);
        if (!(time_limit >= 0.0 && time_limit <= kMaxTimeLimit))
            return frix::fail(FRIX_ERR_INVALID_ARGUMENT, "%s: time_limit = %g is outside [0, %g]",
                              where, time_limit, kMaxTimeLimit);
        // The check's cones are the three-component ones. Of a rolling-friction problem it
        // decides only the case r = 0 solves (a local problem whose contacts all separate),
        // and otherwise says that it cannot decide.
        if (frix::is_rolling(*problem)) {
            const bool separating = frix::separates_at_zero(*problem);
            info->existence = separating ? FRIX_EXISTENCE_GUARANTEED : FRIX_EXISTENCE_UNDETERMINED;
            info->existence_margin = separating ? 0.0 : NAN;
            return FRIX_OK;
        }
        if (frix_error e = frix::check_problem_vectors(*problem)) return e;
        double margin = NAN;
        info->existence = frix::check_existence(*problem, time_limit, &margin);
        info->existence_margin = margin;
        return FRIX_OK;
    });
}

}  // extern "C"
