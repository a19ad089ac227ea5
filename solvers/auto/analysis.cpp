// Problem analysis and island extraction for the auto solver.
#include "solvers/auto/analysis.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <utility>

#include "src/disjoint_sets.hpp"
#include "src/matrix.hpp"

namespace frix {
namespace autosolve {

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
            // Contacts already joined need not be read (a dense W: after its first row, none).
            if (j == i || sets.find(i) == sets.find(j)) continue;
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
    for (int64_t i = 0; i < nc; ++i)
        if (sets.find(i) == i) {
            ++a.islands;
            a.largest_island = std::max(a.largest_island, sets.size_of_root(i));
        }
    if (a.islands <= 1) return a;  // one unit: no lists needed
    // Islands numbered by their first contact (a deterministic order). A root's entry holds
    // its island's number from the island's first contact on; a root is a contact of its own
    // island, so its entry ends with that same number.
    a.island_of.assign((size_t)nc, -1);
    a.island_size.reserve((size_t)a.islands);
    for (int64_t i = 0; i < nc; ++i) {
        int64_t &number = a.island_of[(size_t)sets.find(i)];
        if (number < 0) {
            number = (int64_t)a.island_size.size();
            a.island_size.push_back(0);
        }
        a.island_of[(size_t)i] = number;
        ++a.island_size[(size_t)number];
    }
    return a;
}

std::vector<std::vector<int64_t>> solve_units(const Analysis &a, int64_t min_size) {
    const int64_t nc = a.contacts;
    std::vector<int64_t> large;  // islands of at least min_size contacts, largest first
    int64_t small_contacts = 0;
    for (int64_t k = 0; k < (int64_t)a.island_size.size(); ++k) {
        if (a.island_size[(size_t)k] >= min_size)
            large.push_back(k);
        else
            small_contacts += a.island_size[(size_t)k];
    }
    std::vector<std::vector<int64_t>> units;
    if (large.size() + (small_contacts > 0 ? 1 : 0) <= 1) {
        units.emplace_back((size_t)nc);
        std::iota(units[0].begin(), units[0].end(), int64_t{0});
        return units;
    }
    std::stable_sort(large.begin(), large.end(),
                     [&](int64_t x, int64_t y) { return a.island_size[(size_t)x] > a.island_size[(size_t)y]; });
    // Each island's unit: its rank among the large ones, or the last unit for the small.
    std::vector<int64_t> unit_of(a.island_size.size(), (int64_t)large.size());
    units.resize(large.size() + (small_contacts > 0 ? 1 : 0));
    for (size_t u = 0; u < large.size(); ++u) {
        unit_of[(size_t)large[u]] = (int64_t)u;
        units[u].reserve((size_t)a.island_size[(size_t)large[u]]);
    }
    if (small_contacts > 0) units.back().reserve((size_t)small_contacts);
    for (int64_t i = 0; i < nc; ++i) units[(size_t)unit_of[(size_t)a.island_of[(size_t)i]]].push_back(i);
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
    sub->symmetric = W.symmetric;  // a principal submatrix of W
    frix_problem *raw = nullptr;
    if (frix_error e = make_owned_local_problem(std::move(sub), std::move(q), std::move(mu), &raw)) return e;
    out.reset(raw);
    // The whole problem's weights (those of a global problem when W is its reduction).
    for (int64_t k = 0; k < n; ++k) raw->weight[(size_t)k] = p.weight[(size_t)island[(size_t)k]];
    return FRIX_OK;
}

}  // namespace autosolve
}  // namespace frix
