// The solver registry: a constant table (no mutable global state), keyed by stable ids.
#include <cctype>
#include <cstdlib>
#include <cstring>
#include <string>

#include "solvers/entries.hpp"
#include "src/error_state.hpp"
#include "src/solver_api.hpp"

namespace {

// In the order solvers were added (ids are the stable keys, not positions). A solver appears
// here only once it really solves.
const frix::SolverEntry *const kSolvers[] = {
    &frix::kNsgsEntry,
    &frix::kProxEntry,
    &frix::kNsnAcEntry,
    &frix::kNsnFbEntry,
    &frix::kNsnNmEntry,
    &frix::kGnsnAcEntry,
    &frix::kNsgsVelocityEntry,
    &frix::kViFppEntry,
    &frix::kViEgEntry,
    &frix::kHpEntry,
    &frix::kTfpEntry,
    &frix::kAclmEntry,
    &frix::kAdmmEntry,
    &frix::kAutoEntry,
    &frix::kIpmEntry,
    &frix::kIpmAnmEntry,
    &frix::kGadmmEntry,
    &frix::kGnsnAlEntry,
    &frix::kGnsgsEntry,
    &frix::kRollingNsgsEntry,
    &frix::kRollingNsnEntry,
};
constexpr int64_t kSolverCount = sizeof kSolvers / sizeof kSolvers[0];

std::string upper(const char *s) {
    std::string out(s);
    for (char &c : out) c = (char)std::toupper((unsigned char)c);
    return out;
}

// Siconos spells one solver several ways: FRICTION_3D_NSGS, SICONOS_FRICTION_3D_NSGS, FC3D_NSGS.
bool matches_siconos(const frix::SolverEntry &e, const std::string &name) {
    if (!e.siconos_name) return false;
    std::string s = e.siconos_name;
    if (name == s || name == "SICONOS_" + s) return true;
    const std::string prefix = "FRICTION_3D_", global = "GLOBAL_FRICTION_3D_", rolling = "ROLLING_FRICTION_3D_";
    if (s.compare(0, global.size(), global) == 0) return name == "GFC3D_" + s.substr(global.size());
    if (s.compare(0, rolling.size(), rolling) == 0) return name == "RFC3D_" + s.substr(rolling.size());
    return s.compare(0, prefix.size(), prefix) == 0 && name == "FC3D_" + s.substr(prefix.size());
}

}  // namespace

namespace frix {

const SolverEntry *find_solver(int id) {
    for (const SolverEntry *e : kSolvers)
        if (e->id == id) return e;
    return nullptr;
}

int64_t solver_count() { return kSolverCount; }

const SolverEntry &solver_at(int64_t index) { return *kSolvers[index]; }

}  // namespace frix

extern "C" {

FRIX_API int64_t frix_solver_count(void) { return kSolverCount; }

FRIX_API int frix_solver_id_at(int64_t index) {
    return index >= 0 && index < kSolverCount ? kSolvers[index]->id : -1;
}

FRIX_API const char *frix_solver_name(int solver_id) {
    const frix::SolverEntry *e = frix::find_solver(solver_id);
    return e ? e->name : nullptr;
}

FRIX_API const char *frix_solver_describe(int solver_id) {
    const frix::SolverEntry *e = frix::find_solver(solver_id);
    return e ? e->description : nullptr;
}

FRIX_API frix_error frix_solver_by_name(const char *name, int *solver_id) {
    return frix::guard("frix_solver_by_name", [&]() -> frix_error {
        if (!name || !solver_id)
            return frix::fail(FRIX_ERR_INVALID_ARGUMENT, "frix_solver_by_name: NULL argument");
        char *end = nullptr;
        long id = std::strtol(name, &end, 10);
        if (*name && end && *end == '\0') {
            if (frix::find_solver((int)id) && id == (int)id) {
                *solver_id = (int)id;
                return FRIX_OK;
            }
            return frix::fail(FRIX_ERR_UNKNOWN_SOLVER, "no solver has id %s (see frix_solver_count)", name);
        }
        std::string want = upper(name);
        for (const frix::SolverEntry *e : kSolvers)
            if (upper(e->name) == want || matches_siconos(*e, want)) {
                *solver_id = e->id;
                return FRIX_OK;
            }
        return frix::fail(FRIX_ERR_UNKNOWN_SOLVER, "no solver is called '%s'", name);
    });
}

}  // extern "C"
