// auto's two routes, which its entry (auto.cpp) dispatches to: local problems by parts
// (parts.cpp), global ones through the reduction or without W (global_routes.cpp).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "solvers/auto/pricing.hpp"
#include "src/linalg/linalg.hpp"
#include "src/solve_cache.hpp"
#include "src/solver_api.hpp"

namespace frix::autosolve {

// What a persistent solver keeps for auto (solve_cache.hpp): its parts' states (each part's
// stages reuse their analyses and factorisations) while W's pattern, and so the parts, stay;
// and for a global problem, the driver's states of the reduction auto runs (M's
// factorisation, W).
struct KeptAuto : CachedState {
    uint64_t w_pattern = 0;
    std::vector<std::vector<int64_t>> parts;
    std::vector<std::unique_ptr<SolveCache>> part_caches;
    SolveCache reduction;
    // A global problem's route prices, kept while M's and H's values stay: pricing analyses M
    // + H S H^T (and L's paths for W), which a persistent solver's next step need not redo.
    struct Prices {
        uint64_t m_values = 0, h_values = 0;  // the versions they were priced for (0: none)
        bool forming_w_priced = false, w_free_priced = false;
        linalg::FactorPrice forming_w;
        RoutePrices routes;
    } prices;
    // reduction_size's figures (a pass over M's and H's entries), kept while their values stay.
    struct Size {
        bool known = false;
        uint64_t m_values = 0, h_values = 0;
        ReductionSize figures;
    } size;
};

// A local problem: analysis, the first sweeps, the parts (on threads), their tightening and
// the status. Also the local step of the reduction route (kAutoReductionEntry).
frix_error solve_local(SolveContext &ctx);

// A global problem: the route its analysis and prices choose.
frix_error solve_global(SolveContext &ctx);

// auto as the local solver of its own reduction route: solve_local, not registered.
extern const SolverEntry kAutoReductionEntry;

}  // namespace frix::autosolve
