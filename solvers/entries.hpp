// Every solver's entry, for the registry (registry.cpp) and for the files that define them (a
// namespace-scope const has internal linkage unless declared extern first). One place, so that
// no family header declares another family's entries.
#pragma once

#include "src/solver_api.hpp"

namespace frix {

extern const SolverEntry kAclmEntry;
extern const SolverEntry kAdmmEntry;
extern const SolverEntry kAutoEntry;
extern const SolverEntry kGadmmEntry;
extern const SolverEntry kGnsnAlEntry;
extern const SolverEntry kGnsgsEntry;
extern const SolverEntry kGnsnAcEntry;
extern const SolverEntry kHpEntry;
extern const SolverEntry kIpmAnmEntry;
extern const SolverEntry kIpmEntry;
extern const SolverEntry kNsgsEntry;
extern const SolverEntry kNsgsVelocityEntry;
extern const SolverEntry kNsnAcEntry;
extern const SolverEntry kNsnFbEntry;
extern const SolverEntry kNsnNmEntry;
extern const SolverEntry kProxEntry;
extern const SolverEntry kRollingNsgsEntry;
extern const SolverEntry kRollingNsnEntry;
extern const SolverEntry kTfpEntry;
extern const SolverEntry kViEgEntry;
extern const SolverEntry kViFppEntry;

}  // namespace frix
