// frix_mpi_partition: the contacts cut into one part per rank by Scotch on the contact graph
// (two contacts are neighbours when W couples them, or, for a global problem, when they act
// on a common dof).
#include <algorithm>
#include <climits>
#include <cstdint>
#include <cstdio>
#include <vector>

#include <scotch/scotch.h>

#include "mpi/distributed.hpp"
#include "src/error_state.hpp"
#include "src/reduction.hpp"

namespace frix {
namespace mpi {
namespace {

// The contact graph of a local problem (W's off-diagonal blocks, made symmetric) or of a
// global one (contacts sharing a dof of H), as adjacency lists without self loops.
void contact_graph(const frix_problem &p, std::vector<int64_t> &ptr, std::vector<int64_t> &adj) {
    const int64_t nc = p.nc;
    std::vector<std::vector<int64_t>> lists((size_t)nc);
    if (p.kind == FRIX_PROBLEM_LOCAL) {
        const frix_matrix &W = *p.W;
        for (int64_t a = 0; a < nc; ++a)
            for (int64_t k = W.row_ptr[(size_t)a]; k < W.row_ptr[(size_t)a + 1]; ++k) {
                const int64_t b = W.block_col[(size_t)k];
                if (b == a) continue;
                lists[(size_t)a].push_back(b);
                lists[(size_t)b].push_back(a);
            }
    } else {
        Csc H;
        if (frix_error e = to_csc(*p.H, H)) throw Failure{e};
        std::vector<std::vector<int64_t>> on_dof((size_t)p.n);
        for (int64_t c = 0; c < 3 * nc; ++c)
            for (int64_t e = H.colptr[(size_t)c]; e < H.colptr[(size_t)c + 1]; ++e) {
                std::vector<int64_t> &l = on_dof[(size_t)H.rowind[(size_t)e]];
                if (l.empty() || l.back() != c / 3) l.push_back(c / 3);
            }
        for (const std::vector<int64_t> &l : on_dof)
            for (size_t i = 0; i < l.size(); ++i)
                for (size_t j = 0; j < l.size(); ++j)
                    if (l[i] != l[j]) lists[(size_t)l[i]].push_back(l[j]);
    }
    ptr.assign(1, 0);
    adj.clear();
    for (std::vector<int64_t> &l : lists) {
        std::sort(l.begin(), l.end());
        l.erase(std::unique(l.begin(), l.end()), l.end());
        adj.insert(adj.end(), l.begin(), l.end());
        ptr.push_back((int64_t)adj.size());
        std::vector<int64_t>().swap(l);
    }
}

// Scotch's partition of the graph into `parts` parts of about equal weight (a contact's
// weight: 1 + its neighbours, its share of a sweep's work), in a context of its own set to be
// deterministic with a fixed seed: the same parts for the same graph on every run (its
// default, threaded and randomly seeded, gives other parts on each call).
frix_error run_partitioner(int parts, const std::vector<int64_t> &ptr, const std::vector<int64_t> &adj, int *part) {
    const SCOTCH_Num n = (SCOTCH_Num)(ptr.size() - 1);
    if (adj.size() >= (size_t)INT_MAX)
        return fail(FRIX_ERR_DIMENSION, "frix_mpi_partition: the contact graph has %zu edges, more than Scotch's "
                    "indices hold", adj.size());
    std::vector<SCOTCH_Num> vert(ptr.begin(), ptr.end()), edge(adj.begin(), adj.end()), weight((size_t)n), out((size_t)n);
    for (SCOTCH_Num a = 0; a < n; ++a) weight[(size_t)a] = vert[(size_t)a + 1] - vert[(size_t)a] + 1;
    SCOTCH_Context context;
    SCOTCH_Graph graph, bound;
    SCOTCH_Strat strategy;
    if (SCOTCH_contextInit(&context) != 0) return fail(FRIX_ERR_INTERNAL, "frix_mpi_partition: SCOTCH_contextInit failed");
    SCOTCH_contextOptionSetNum(&context, SCOTCH_OPTIONNUMDETERMINISTIC, 1);
    SCOTCH_contextRandomSeed(&context, 1);
    SCOTCH_graphInit(&graph);
    SCOTCH_graphInit(&bound);
    SCOTCH_stratInit(&strategy);
    int rc = SCOTCH_graphBuild(&graph, 0, n, vert.data(), nullptr, weight.data(), nullptr, (SCOTCH_Num)edge.size(),
                               edge.data(), nullptr);
    if (rc == 0) rc = SCOTCH_contextBindGraph(&context, &graph, &bound);
    if (rc == 0) rc = SCOTCH_graphPart(&bound, (SCOTCH_Num)parts, &strategy, out.data());
    SCOTCH_stratExit(&strategy);
    SCOTCH_graphExit(&bound);
    SCOTCH_graphExit(&graph);
    SCOTCH_contextExit(&context);
    if (rc != 0) return fail(FRIX_ERR_INTERNAL, "frix_mpi_partition: Scotch could not partition the contact graph");
    for (SCOTCH_Num a = 0; a < n; ++a) part[a] = (int)out[(size_t)a];
    return FRIX_OK;
}

}  // namespace

}  // namespace mpi
}  // namespace frix

extern "C" {

FRIX_API frix_error frix_mpi_partition(frix_mpi_context *ctx, int root, const frix_problem *problem, int *part) {
    return frix::guard("frix_mpi_partition", [&]() -> frix_error {
        using frix::fail;
        const char *where = "frix_mpi_partition";
        if (!ctx) return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: ctx is NULL", where);
        frix_error e = FRIX_OK;
        if (root < 0 || root >= ctx->size)
            return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: root %d is not a rank (0 .. %d)", where, root, ctx->size - 1);
        const bool is_root = ctx->rank == root;
        if (is_root) {
            if (!problem || !part)
                e = fail(FRIX_ERR_INVALID_ARGUMENT, "%s: problem and part are required on the root", where);
            else if (frix_error other = frix::mpi::check_release(*problem, where, "problem"))
                e = other;
            else if (frix_error rolling = frix::refuse_rolling(*problem, where))
                e = rolling;
            else if (problem->nc >= INT_MAX)
                e = fail(FRIX_ERR_DIMENSION, "%s: %lld contacts, more than PETSc's indices hold", where,
                         (long long)problem->nc);
            else if (problem->kind == FRIX_PROBLEM_LOCAL && problem->nc > 0 && !problem->W->block)
                e = fail(FRIX_ERR_UNSUPPORTED, "%s: W must be stored in 3x3 blocks", where);
        }
        if (frix_error agreed = frix::mpi::agree(ctx->comm, e, where)) return agreed;
        // One part: nothing to cut (and no PETSc to start).
        if (ctx->size == 1) {
            std::fill(part, part + problem->nc, 0);
            return FRIX_OK;
        }
        // The graph is whole on the root: Scotch runs there.
        if (is_root) {
            std::vector<int64_t> ptr, adj;
            frix::mpi::contact_graph(*problem, ptr, adj);
            e = frix::mpi::run_partitioner(ctx->size, ptr, adj, part);
        }
        return frix::mpi::agree(ctx->comm, e, where);
    });
}

}  // extern "C"
