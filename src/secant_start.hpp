// A persistent solver's secant start (option secant_start): a host stepping along a load path
// (or any smooth sequence of data) solves problems whose answers move nearly linearly while the
// contacts keep their states, so the next answer is predicted far better by the secant of the
// last two answers than by the last one alone. Where a solve continues from the last answer
// (the caller passes it back unchanged), the matrices and the friction coefficients are those
// of the last two solves, and the data (q, or f and w) moved along a line over them, the solve
// starts from P_K(r_k + alpha (r_k - r_(k-1))) instead, alpha the data's step along the line.
// The start is only a start: the solve measures and iterates from it as from any other.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "solve_cache.hpp"

struct frix_problem;

namespace frix {

class SecantStart {
   public:
    // Before a solve from r (the caller's warm start): r replaced by the secant prediction
    // where it applies; whether it was.
    bool predict(const frix_problem &p, const SolveCache &versions, double *r) const;
    // r back to the last answer, which predict() found there and replaced.
    void restore_last_answer(double *r) const { std::copy(r_.begin(), r_.end(), r); }
    // After a solve: its data and answer r kept where it converged (a contact law of three
    // entries), the history forgotten otherwise (also where an allocation fails: it throws).
    void record(const frix_problem &p, const SolveCache &versions, const double *r, bool converged);

   private:
    // What must hold between the solves of the history for their answers to lie on a line.
    struct Setting {
        int kind = -1;
        int64_t nc = -1, n = -1;
        uint64_t w_values = 0, w_pattern = 0, m_values = 0, h_values = 0;
        std::vector<double> mu;
    };
    bool same_setting(const frix_problem &p, const SolveCache &versions) const;
    Setting setting_;
    // The last solve's data (q; or f then w) and answer, and their steps from the solve's
    // before.
    std::vector<double> data_, last_step_, r_, last_r_step_;
    int count_ = 0;  // solves held (0 to 2)
};

}  // namespace frix
