// The prices of auto's stages and routes, in one unit (the work of one 3x3 block of W times a
// vector, policy.hpp): known before anything runs, so that the choices they drive do not
// depend on the machine's speed or load.
#pragma once

#include <cmath>

#include "solvers/kit/mass_plus_contacts.hpp"
#include "src/linalg/linalg.hpp"
#include "src/problem.hpp"

namespace frix::autosolve {

// A part's stages.
struct StageCosts {
    double sweep = 0.0;           // one NSGS sweep
    double admm_iteration = 0.0;  // one ADMM iteration: two triangular solves, products, projections
    double admm_setup = 0.0;      // ADMM's factorisation of W + rho I
    double ipm = 0.0;             // an interior-point stage to its end
    double admm_bytes = 0.0;      // peak memory of ADMM's factorisation (Cholesky of W's pattern)
    double ipm_bytes = 0.0;       // of the IPM's (LU, priced at twice Cholesky's)
};

// The prices of p's stages. The IPM and Newton factorise an unsymmetric matrix of W's
// pattern by LU (about twice Cholesky's flops).
frix_error price_stages(const frix_problem &p, StageCosts *c);

// Where W would be dense: what the two routes of a global problem are priced at, in flops of
// a factorisation.
struct RoutePrices {
    double with_w = NAN, without_w = NAN, without_w_bytes = NAN;
};

// Forming W: its exact flops (`forming_w`), then kSweepsOnW sweeps over its `w_blocks` blocks
// (18 flops each), memory-bound. Without W: one factorisation of M + rho H H^T (CHOLMOD's
// analysis of its pattern), then kWFreeIterations of ADMM, each two triangular solves with
// that factor (4 flops per entry of L), memory-bound too. False where that factor cannot be
// priced (the route is then not taken). W's writes (forming_w.writes, which a time limit
// prices) are left out: these constants were set on the flops alone, and with the writes
// added a thick elastic grid near the boundary took the slower route
// (notes/2026-11-28-w-price.md). `system`: M + H S H^T built and analysed for the route's
// solver, which takes it (offer_mass_plus_contacts) rather than doing both again; analysed in
// M's ordering where that fits it (MassPlusContacts::build; `mass`: M factorised).
bool price_w_free_route(const frix_problem &p, const MassSolver &mass, const linalg::FactorPrice &forming_w,
                        double w_blocks, RoutePrices *prices, MassPlusContacts &system);

}  // namespace frix::autosolve
