// Route (a) on the contacts the free motion presses: W formed for those contacts alone, grown
// by the ones that end up penetrating (pressed_reduction.cpp).
#pragma once

#include <cmath>
#include <functional>
#include <vector>

#include "info.hpp"
#include "options.hpp"
#include "problem.hpp"
#include "solver_api.hpp"

namespace frix {

// The reduction route on a problem of p's M and f and some of its contacts (part, p's
// `contacts`): W formed from part's H (or kept, where formed for those contacts), at most
// w_blocks blocks, the local solve from (r, u) with q its free velocity, v recovered
// (M v = H r + f), the run's work and verdict into info.
using ReducedRoute =
    std::function<frix_error(const frix_problem &part, const std::vector<int64_t> &contacts, const frix_options &opts,
                             double w_blocks, const double *q, double *r, double *u, double *v, frix_info &info)>;

// What the caller keeps between solves: the contacts of the part whose W it holds (null: none),
// which the part starts from; W's structural bound in blocks (NaN: not known; set when found).
struct PressedPart {
    const std::vector<int64_t> *kept = nullptr;
    double structural_blocks = NAN;
};

enum class PressedFirst {
    kNotApplied,  // r and info as they were
    kAnswered,    // (r, u, v) and info are the route's answer
    kWholeNext,   // the contacts grew past the route's share: info holds the rounds' work, and
                  // the whole reduction goes on from r
};

// A one-shot reduction whose W would be large (w_blocks blocks) and whose contacts pressed at
// the start (q_N < 0, q = H^T M^-1 f + w, or r != 0 there) are few enough: `reduce` on those
// contacts alone, r = 0 on the others; where some of the others end up penetrating (u_N < 0),
// again with them added, from the last r. A kept part's contacts stay in the part.
frix_error solve_pressed_first(const frix_problem &p, const frix_options &opts, const double *q, double w_blocks,
                               double *r, double *u, double *v, frix_info &info, const Stopwatch &clock,
                               const ReducedRoute &reduce, PressedPart &part, PressedFirst *outcome);

}  // namespace frix
