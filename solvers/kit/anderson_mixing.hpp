// Anderson's mix of the last sweeps (option anderson), an acceleration of run_sweeps
// (kit/sweeps.cpp).
#pragma once

#include <cstdint>
#include <vector>

#include "solvers/kit/sweeps.hpp"

namespace frix {
namespace nsgs {

// Anderson acceleration of the sweep (option anderson = depth): the sweep is a fixed-point map
// g; with f_i = g(x_i) - x_i over the last depth + 1 sweeps, r moves after each sweep to
// y = P_K(g_k - sum_j gamma_j (g_{j+1} - g_j)), gamma the least-squares fit of the changes
// f_{j+1} - f_j to f_k, and the form's affine state follows the same combination. Where the
// sweep contracts at a steady rate (a regular W: elastic bodies), the mix extrapolates the
// slow modes as a Krylov method would. The history starts again when a sweep's step grows
// (the map changed: contacts changed state) and whenever r jumps.
class AndersonMixing {
   public:
    AndersonMixing(int64_t depth, int64_t m, const double *r) : depth_(depth), m_((size_t)m) {
        if (depth_ <= 0) return;
        x_.assign(r, r + m);
        const size_t slots = (size_t)depth_ + 1;
        g_.resize(slots * m_);
        f_.resize(slots * m_);
        columns_.resize((size_t)depth_ * m_);
        line_.resize(m_);
    }
    bool on() const { return depth_ > 0; }
    // Off for the rest of the run (a form that cannot follow a combination).
    void off() { depth_ = 0; }
    // r changed other than by a sweep: the history starts again from r.
    void restart(const double *r) {
        if (!on()) return;
        count_ = 0;
        std::copy(r, r + m_, x_.begin());
    }
    void after_sweep(double *r, const double *mu, Workspace &ws, SweepForm &form, double *u);
    // Whether it keeps copies of the form's affine state.
    bool holds_states() const { return on() && count_ > 0; }
    // Those copies move by `correction` (the form's exact() corrected the state by it), so
    // that the mix's differences carry no jump.
    void shift_states(const std::vector<double> &correction);

   private:
    size_t slot(int64_t i) const { return (size_t)((newest_ - count_ + 1 + i + 2 * (depth_ + 1)) % (depth_ + 1)); }
    int64_t fit(int64_t columns);

    int64_t depth_;
    size_t m_;
    std::vector<double> x_;                   // the last sweep's start
    std::vector<double> g_, f_, k_;           // per slot: g, f = g - x, the affine state at g
    std::vector<double> columns_, line_;      // the fit's orthogonalised columns; the mixed point
    std::vector<double> r_fit_, gamma_, rhs_;  // the fit's triangle (columns x columns), weights, Q^T f_k
    std::vector<char> kept_column_;
    int64_t count_ = 0, newest_ = -1;
    double last_f2_ = INFINITY;
};

}  // namespace nsgs
}  // namespace frix
