// Problem analysis and island extraction for the auto solver.
#include "solvers/auto_analysis.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <utility>

#include "src/disjoint_sets.hpp"
#include "src/matrix.hpp"

namespace frix {
namespace autosolve {

namespace {


}  // namespace

Analysis analyse_local(const frix_problem &p) {
    Analysis a;
    const frix_matrix &W = *p.W;
    const int64_t nc = p.nc;
    a.contacts = nc;
    a.contact_dofs = 3 * nc;
    a.blocks = W.nblocks();
    a.diag_min = INFINITY;
    a.mu_min = INFINITY;
    DisjointSets sets(nc);
    for (int64_t i = 0; i < nc; ++i) {
        for (int64_t b = W.row_ptr[(size_t)i]; b < W.row_ptr[(size_t)i + 1]; ++b) {
            const int64_t j = W.block_col[(size_t)b];
            if (j == i) continue;
            // A stored block of zeros couples nothing.
            const double *B = &W.block_val[9 * (size_t)b];
            if (std::any_of(B, B + 9, [](double x) { return x != 0.0; })) sets.unite(i, j);
        }
        double d2 = 0.0;
        if (W.diag_index[(size_t)i] >= 0) {
            const double *D = &W.block_val[9 * (size_t)W.diag_index[(size_t)i]];
            for (int k = 0; k < 9; ++k) d2 += D[k] * D[k];
        }
        a.diag_min = std::min(a.diag_min, std::sqrt(d2));
        a.diag_max = std::max(a.diag_max, std::sqrt(d2));
        a.mu_min = std::min(a.mu_min, p.mu[i]);
        a.mu_max = std::max(a.mu_max, p.mu[i]);
    }
    if (nc == 0) a.diag_min = a.mu_min = 0.0;
    // Islands numbered by their first contact, then sorted largest first (stable: the order
    // is deterministic).
    std::vector<int64_t> index_of_root((size_t)nc, -1);
    for (int64_t i = 0; i < nc; ++i) {
        const int64_t root = sets.find(i);
        if (index_of_root[(size_t)root] < 0) {
            index_of_root[(size_t)root] = (int64_t)a.islands.size();
            a.islands.emplace_back();
        }
        a.islands[(size_t)index_of_root[(size_t)root]].push_back(i);
    }
    if (a.islands.size() > 1)  // (a sort allocates a buffer even for one element)
        std::stable_sort(a.islands.begin(), a.islands.end(),
                         [](const std::vector<int64_t> &x, const std::vector<int64_t> &y) { return x.size() > y.size(); });
    return a;
}

std::vector<std::vector<int64_t>> group_small_islands(std::vector<std::vector<int64_t>> islands, int64_t min_size) {
    // One island (the usual small problem): it is the one unit as it stands.
    if (islands.size() <= 1) return islands;
    std::vector<std::vector<int64_t>> units;
    std::vector<int64_t> small;
    for (std::vector<int64_t> &island : islands) {
        if ((int64_t)island.size() >= min_size)
            units.push_back(std::move(island));
        else
            small.insert(small.end(), island.begin(), island.end());
    }
    if (!small.empty()) {
        std::sort(small.begin(), small.end());
        units.push_back(std::move(small));
    }
    return units;
}

frix_error extract_island(const frix_problem &p, const std::vector<int64_t> &island,
                          std::unique_ptr<frix_problem, void (*)(frix_problem *)> &out) {
    const frix_matrix &W = *p.W;
    const int64_t n = (int64_t)island.size();
    // Position of each contact of the island in it; the islands are closed under W's
    // coupling, so every block of their rows lands inside.
    std::vector<int64_t> local_index((size_t)p.nc, -1);
    for (int64_t k = 0; k < n; ++k) local_index[(size_t)island[(size_t)k]] = k;

    auto sub = std::make_unique<frix_matrix>();
    sub->rows = sub->cols = 3 * n;
    sub->block = true;
    sub->block_rows = sub->block_cols = n;
    sub->row_ptr.assign((size_t)n + 1, 0);
    sub->diag_index.assign((size_t)n, -1);
    std::vector<double> q((size_t)(3 * n)), mu((size_t)n);
    for (int64_t k = 0; k < n; ++k) {
        const int64_t i = island[(size_t)k];
        for (int64_t b = W.row_ptr[(size_t)i]; b < W.row_ptr[(size_t)i + 1]; ++b) {
            const int64_t j = local_index[(size_t)W.block_col[(size_t)b]];
            if (j < 0) continue;  // a stored zero block towards another island
            if (j == k) sub->diag_index[(size_t)k] = (int64_t)sub->block_col.size();
            sub->block_col.push_back(j);
            sub->block_val.insert(sub->block_val.end(), &W.block_val[9 * (size_t)b],
                                  &W.block_val[9 * (size_t)b] + 9);
        }
        sub->row_ptr[(size_t)k + 1] = (int64_t)sub->block_col.size();
        for (int c = 0; c < 3; ++c) q[(size_t)(3 * k + c)] = p.q[3 * i + c];
        mu[(size_t)k] = p.mu[i];
    }
    frix_problem *raw = nullptr;
    if (frix_error e = make_owned_local_problem(std::move(sub), std::move(q), std::move(mu), &raw)) return e;
    out.reset(raw);
    return FRIX_OK;
}

}  // namespace autosolve
}  // namespace frix
