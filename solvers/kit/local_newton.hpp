// One-contact semismooth Newton solvers (ids 550, 551, 561 and the Newton part of 565 of
// frix_options.h): Newton on Phi(r, W_aa r + q) = 0 for the three unknowns of one contact,
// with the functions and Jacobians of nsn_functions.hpp. NSGS reaches them through
// local::solve_contact (local3x3.cpp), which also runs 565's fallback to projections.
#pragma once

#include "solvers/kit/local3x3.hpp"

namespace frix::local {

constexpr int kNewtonAc = 550;      // FRIX_LOCAL_NEWTON_AC: full steps
constexpr int kNewtonAcGp = 551;    // FRIX_LOCAL_NEWTON_AC_GP
constexpr int kNewtonFb = 561;      // FRIX_LOCAL_NEWTON_FB
constexpr int kHybrid = 565;        // FRIX_LOCAL_HYBRID

// Newton from r (updated in place when it improves the one-contact residual). formulation
// is an nsn::Formulation; line_search false means full steps. True if the relative
// one-contact residual reached p.tol within p.max_iter steps.
bool newton_contact(const Contact &c, const double *q, double *r, const Params &p, int formulation,
                    bool line_search);

}  // namespace frix::local
