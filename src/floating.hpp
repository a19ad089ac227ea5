// Global problems whose M is singular: a static problem with a body held only by its contacts
// (a stiffness matrix with rigid modes). Found by one step of inverse iteration with M's
// factorisation; solved on M + eps diag(M), the shift's effect removed by proximal passes
// (solve_global.cpp), or refused where the contacts do not hold the free motion.
#pragma once

#include <memory>
#include <vector>

#include "matrix.hpp"
#include "problem.hpp"
#include "reduction.hpp"

namespace frix {

// The shift of a singular M, relative to each diagonal entry: small against every mode the
// elastic body resists (the Jacobi-scaled M's smallest eigenvalue of a mesh that is held is
// far above it), large enough that M + eps diag(M) factorises with a few correct digits.
constexpr double kFloatingShift = 1e-6;
// M counts as singular where the Rayleigh quotient below is under this: at most rounding of a
// free motion, 100 times below the shift.
constexpr double kSingularQuotient = 1e-12;

// x.M x / x.D x with x = M^-1 D^1/2 z (ms holds M's factorisation, D = diag(M) as
// p.dof_weight gives it, z a fixed +-1 vector): one step of inverse iteration from z, close to
// the smallest eigenvalue of D^-1/2 M D^-1/2 where that is far below the others (a free
// motion; rounding then leaves it near 1e-16 or below, or negative). NaN where the solve fails.
double free_motion_quotient(const frix_problem &p, const MassSolver &ms);

// eps D_ii for every dof, D = diag(M) as p.dof_weight gives it (1 / dof_weight^2).
std::vector<double> mass_shift(const frix_problem &p, double eps);

// M + eps D, D = diag(M) as p.dof_weight gives it (1 / dof_weight^2), with a diagonal entry
// added where M's pattern has none.
std::unique_ptr<frix_matrix> shifted_mass(const frix_problem &p, double eps);

}  // namespace frix
