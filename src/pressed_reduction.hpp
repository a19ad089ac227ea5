// Route (a) on the contacts the free motion presses: W formed for those contacts alone, grown
// by the ones that end up penetrating (pressed_reduction.cpp).
#pragma once

#include <functional>

#include "info.hpp"
#include "options.hpp"
#include "problem.hpp"
#include "reduction.hpp"
#include "solver_api.hpp"

namespace frix {

// The reduction route on a problem of p's M and f and some of its contacts (sub): W formed from
// sub's H, at most w_blocks blocks, the local solve from (r, u) with q its free velocity, v
// recovered (M v = H r + f), the run's work and verdict into info.
using ReducedRoute = std::function<frix_error(const frix_problem &sub, const frix_options &opts, double w_blocks,
                                              const double *q, double *r, double *u, double *v, frix_info &info)>;

enum class PressedFirst {
    kNotApplied,  // r and info as they were
    kAnswered,    // (r, u, v) and info are the route's answer
    kWholeNext,   // the contacts grew past the route's share, or a third round missed the
                  // tolerance: info holds the rounds' work, and the whole reduction goes on from r
};

// A one-shot reduction whose W would be large (bound: the driver's, reduction_bound) and whose contacts pressed at
// the start (q_N < 0, q = H^T M^-1 f + w, or r != 0 there) are few enough: `reduce` on those
// contacts alone, r = 0 on the others; where the whole problem's measure of that answer misses
// the tolerance and some of the others penetrate (u_N < 0), again with them added, from the last
// r. The rounds share max_iter and the callback's numbering.
frix_error solve_pressed_first(const frix_problem &p, const frix_options &opts, const double *q,
                               const ReductionSize &bound,
                               double *r, double *u, double *v, frix_info &info, const Stopwatch &clock,
                               const ReducedRoute &reduce, PressedFirst *outcome);

}  // namespace frix
