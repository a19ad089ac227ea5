// The prices of auto's stages and routes (pricing.hpp).
#include "solvers/auto/pricing.hpp"

#include "solvers/auto/policy.hpp"
#include "solvers/kit/mass_plus_contacts.hpp"
#include "src/error_state.hpp"
#include "src/matrix.hpp"
#include "src/reduction.hpp"

namespace frix::autosolve {

frix_error price_stages(const frix_problem &p, StageCosts *c) {
    const frix_matrix &W = *p.W;
    const double blocks = (double)W.nblocks(), contacts = (double)p.nc;
    linalg::FactorCost fc;
    if (frix_error e = block_cholesky_cost(W, &fc)) return e;
    const double cholesky = fc.flops * kFactorFlopWork;
    const double solve = 2.0 * 2.0 * fc.factor_entries * kFactorFlopWork;
    c->sweep = blocks + kContactWork * contacts;
    c->admm_iteration = solve + 4.0 * blocks + kContactWork * contacts;
    c->admm_setup = cholesky;
    c->ipm = kIpmFactorizations * (2.0 * cholesky + solve + blocks);
    c->admm_bytes = fc.bytes;
    c->ipm_bytes = 2.0 * fc.bytes;
    return FRIX_OK;
}

bool price_w_free_route(const frix_problem &p, const MassSolver &mass, const linalg::FactorPrice &forming_w,
                        double w_blocks, RoutePrices *prices, MassPlusContacts &system) {
    Csc M, H;
    linalg::FactorCost cost;
    if (to_csc(*p.M, M) || to_csc(*p.H, H) ||
        system.build(M, H, p.nc, "auto", ContactBlocks::kMultiplesOfIdentity, mass.ordering()) ||
        system.analyse(&cost)) {
        clear_error();
        return false;
    }
    prices->with_w = forming_w.flops + kMemoryBoundWork * kSweepsOnW * 18.0 * w_blocks;
    prices->without_w = cost.flops + kMemoryBoundWork * kWFreeIterations * 4.0 * cost.factor_entries;
    prices->without_w_bytes = cost.bytes;
    return true;
}

}  // namespace frix::autosolve
