// The line searches of the Newton solvers, over a merit callable merit(t): the merit at
// x + t d, for the Newton direction d from x (models: PETSc's SNESLineSearch, Siconos's
// fc3d_nonsmooth_Newton_solvers). Goldstein-Price, Armijo's backtracking (also against the
// largest of the last merits: non-monotone), and the constants they share. Each search keeps
// the arithmetic of the solvers that use it: their results are the same bits as before the
// searches were shared.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>

namespace frix::kit {

// Goldstein-Price's constants of Siconos (m1, m2); Armijo's sigma.
constexpr double kGoldsteinM1 = 0.01, kGoldsteinM2 = 0.99, kArmijoSigma = 1e-4;

// The last merits of a Newton run, for the non-monotone search (Armijo against the largest).
class MeritHistory {
   public:
    explicit MeritHistory(double psi) { push(psi); }
    void push(double psi) { last_[seen_++ % kMemory] = psi; }
    // The reference of the Armijo test: psi, or the largest of the last merits if larger.
    double reference(double psi) const {
        for (int64_t k = 0; k < seen_ && k < kMemory; ++k) psi = psi < last_[k] ? last_[k] : psi;
        return psi;
    }

   private:
    static constexpr int kMemory = 8;
    double last_[kMemory];
    int64_t seen_ = 0;
};

// Where a search ended: accepted at t; or not, with t where the trials left it, best_t the
// trial of the lowest merit below the start's (0: none) and last_merit the last trial's.
// searched: whether trials were taken (not for kNone, nor along a d that does not descend).
struct SearchResult {
    bool accepted = false, searched = false;
    double t = 0.0, best_t = 0.0, last_merit = 0.0;
};

// Goldstein-Price from t = 1 on merits psi + m2 t slope <= merit(t) <= psi + m1 t slope,
// bisecting between the longest step found too short and the shortest found too long; never
// beyond 1 (Newton's step). A non-finite merit is too long, unless nan_too_long is false (the
// one-contact Newton, local_newton.cpp, takes a NaN merit as accepted). trials counts merits.
template <class Merit>
SearchResult goldstein_price(const Merit &merit, double psi, double slope, int max_trials, int64_t &trials,
                             bool nan_too_long = true) {
    SearchResult s;
    double lo = 0.0, hi = INFINITY, best_merit = psi;
    s.t = 1.0, s.searched = true;
    for (int k = 0; k < max_trials; ++k) {
        const double pt = s.last_merit = merit(s.t);
        ++trials;
        if (pt < best_merit) best_merit = pt, s.best_t = s.t;
        if (pt > psi + kGoldsteinM1 * s.t * slope || (nan_too_long && !std::isfinite(pt))) {
            hi = s.t;
        } else if (pt < psi + kGoldsteinM2 * s.t * slope && s.t < 1.0) {
            lo = s.t;  // too short: Newton steps are never extended beyond 1
        } else {
            s.accepted = true;
            return s;
        }
        s.t = std::isfinite(hi) ? 0.5 * (lo + hi) : std::min(2.0 * s.t, 1.0);
    }
    return s;
}

// Armijo's sufficient decrease merit(t) <= bound(t), from the merit psi the step starts at.
struct Decrease {
    double ref;    // psi, or the largest of the last merits (non-monotone)
    double c;      // the constant: kArmijoSigma, or kGoldsteinM1 (gnsn-ac's Goldstein-Price)
    double slope;  // the merit's slope along d at t = 0
    // Written (1 - 2 c t) ref: for the merit 1/2 |F|^2, whose slope along an exact Newton step
    // is -2 ref (the distributed nsn-ac's test, kept in its arithmetic).
    bool newton_merit = false;
    double bound(double t) const { return newton_merit ? (1.0 - 2.0 * c * t) * ref : ref + c * t * slope; }
};

// Backtracking from t = 1, halved after each of at most max_trials trials: the first t with
// merit(t) <= d.bound(t) is accepted. trials counts the merits taken.
template <class Merit>
SearchResult backtrack(const Merit &merit, double psi, const Decrease &d, int max_trials, int64_t &trials) {
    SearchResult s;
    double best_merit = psi;
    s.t = 1.0, s.searched = true;
    for (int k = 0; k < max_trials; ++k, s.t *= 0.5) {
        const double pt = s.last_merit = merit(s.t);
        ++trials;
        if (pt < best_merit) best_merit = pt, s.best_t = s.t;
        if (pt <= d.bound(s.t)) {
            s.accepted = true;
            return s;
        }
    }
    return s;
}

// The search a Newton run takes (option line_search and line_search_max_iter, as its solver
// reads them).
struct Search {
    enum Kind { kNone, kGoldsteinPrice, kArmijo, kNonmonotone, kNewtonMerit };
    Kind kind = kGoldsteinPrice;
    double c = kArmijoSigma;  // Armijo's constant (kArmijo, kNonmonotone, kNewtonMerit)
    int max_trials = 20;
    // Whether the search needs the merit's slope along d: a direction that does not descend
    // (slope >= 0) is then not searched.
    bool uses_slope() const { return kind != kNone && kind != kNewtonMerit; }
};

// The local Newton's reading of option line_search (frix_line_search): each as it says.
Search search_of(int64_t line_search, int64_t max_trials);
// gnsn-ac's: Goldstein-Price is taken as Armijo with m1.
Search armijo_search_of(int64_t line_search, int64_t max_trials);
// The distributed nsn-ac's: none, or any other as Armijo in its Newton-merit form.
Search newton_merit_search_of(int64_t line_search, int64_t max_trials);

// The search s along d from the merit psi (slope: the merit's slope, when s.uses_slope();
// history: the last merits, for kNonmonotone). kNone accepts t = 1; a search that needs a
// slope accepts nothing where d does not descend.
SearchResult line_search(const Search &s, const std::function<double(double)> &merit, double psi, double slope,
                         const MeritHistory &history, int64_t &trials);

}  // namespace frix::kit
