// auto (id 900), the default solver: problem analysis, islands and a watched sequence of the
// other solvers (the files of solvers/auto/, auto.cpp first).
#pragma once

#include "src/solver_api.hpp"

namespace frix {

extern const SolverEntry kAutoEntry;

}  // namespace frix
