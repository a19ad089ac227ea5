// The default measure's weights of a global problem with the host's M over the ranks
// (RanksWeights): set_contact_weights' and free_velocity's rules (src/problem.hpp) on each
// rank's rows of M and H^T, with what a row needs of another rank's dofs fetched from it.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "mpi/distributed_forms.hpp"
#include "src/disjoint_sets.hpp"
#include "src/problem.hpp"

namespace frix {
namespace mpi {
namespace {

// Where id stands in `sorted` (increasing, holding it).
int64_t position(const std::vector<int64_t> &sorted, int64_t id) {
    return (int64_t)(std::lower_bound(sorted.begin(), sorted.end(), id) - sorted.begin());
}

// `width` values of each dof of `ids` (other ranks' dofs, increasing) from their owners, in
// the order of ids; each rank answers from `mine` (width values for each of its own dofs).
std::vector<double> fetch(MPI_Comm comm, const frix_mpi_global_rows &g, const std::vector<int64_t> &ids,
                          const std::vector<double> &mine, int width) {
    const size_t ranks = g.dof_starts.size() - 1;
    std::vector<std::vector<int64_t>> asks(ranks);
    for (const int64_t j : ids) asks[(size_t)owner_of(g.dof_starts, j)].push_back(j);
    std::vector<int> asked_at;
    const std::vector<int64_t> asked = exchange_lists(comm, asks, &asked_at);
    std::vector<double> answers(width * asked.size()), out(width * ids.size());
    for (size_t e = 0; e < asked.size(); ++e)
        for (int c = 0; c < width; ++c) answers[width * e + c] = mine[width * (size_t)(asked[e] - g.dof_first) + c];
    std::vector<int> send_counts(ranks), send_at(ranks), recv_counts(ranks), recv_at(ranks + 1, 0);
    for (size_t k = 0; k < ranks; ++k) {
        send_counts[k] = checked_count((int64_t)width * (asked_at[k + 1] - asked_at[k]));
        send_at[k] = checked_count((int64_t)width * asked_at[k]);
        recv_counts[k] = checked_count((int64_t)width * (int64_t)asks[k].size());
        recv_at[k + 1] = checked_count((int64_t)recv_at[k] + recv_counts[k]);
    }
    check(MPI_Alltoallv(answers.data(), send_counts.data(), send_at.data(), MPI_DOUBLE, out.data(), recv_counts.data(),
                        recv_at.data(), MPI_DOUBLE, comm),
          "MPI_Alltoallv");
    return out;
}

// Whether each owned dof carries load_velocity's load: no contact reaches it (H has no entry
// in its row) and its body, its component of M's graph, some contact touches (as
// set_contact_weights decides on the whole problem). Each rank finds the components of its
// rows; those that reach other ranks' dofs are joined over the edges all ranks gather.
std::vector<char> load_dofs(const frix_mpi_problem &p) {
    const frix_mpi_global_rows &g = *p.global;
    const MPI_Comm comm = p.ctx->comm;
    const int64_t n = g.dofs, first = g.dof_first;
    const auto own = [&](int64_t j) { return j >= first && j < first + n; };
    // The nodes: the owned dofs, then the other ranks' dofs of this rank's rows of M.
    std::vector<int64_t> foreign;
    for (size_t k = 0; k < g.m_col.size(); ++k)
        if (g.m_val[k] != 0.0 && !own(g.m_col[k])) foreign.push_back(g.m_col[k]);
    std::sort(foreign.begin(), foreign.end());
    foreign.erase(std::unique(foreign.begin(), foreign.end()), foreign.end());
    const int64_t nodes = n + (int64_t)foreign.size();
    const auto node = [&](int64_t j) {
        return own(j) ? j - first : n + position(foreign, j);
    };
    const auto dof_of = [&](int64_t x) { return x < n ? first + x : foreign[(size_t)(x - n)]; };
    DisjointSets local(nodes);
    for (int64_t i = 0; i < n; ++i)
        for (int64_t k = g.m_ptr[(size_t)i]; k < g.m_ptr[(size_t)i + 1]; ++k)
            if (g.m_val[(size_t)k] != 0.0) local.unite(i, node(g.m_col[(size_t)k]));
    // Each owner learns which of its dofs a contact reaches (1) and which another rank's rows
    // of M hold (0): those join its components to that rank's.
    std::vector<char> reached((size_t)n, 0), shared((size_t)nodes, 0);
    std::vector<std::vector<int64_t>> tell(g.dof_starts.size() - 1);
    const auto tell_owner = [&](int64_t j, int64_t what) {
        std::vector<int64_t> &to = tell[(size_t)owner_of(g.dof_starts, j)];
        to.push_back(j);
        to.push_back(what);
    };
    for (size_t k = 0; k < g.ht_col.size(); ++k) {
        if (g.ht_val[k] == 0.0) continue;
        const int64_t j = g.ht_col[k];
        if (own(j)) reached[(size_t)(j - first)] = 1;
        else tell_owner(j, 1);
    }
    for (const int64_t j : foreign) tell_owner(j, 0);
    const std::vector<int64_t> told = exchange_lists(comm, tell);
    for (size_t e = 0; e + 1 < told.size(); e += 2)
        (told[e + 1] ? reached : shared)[(size_t)(told[e] - first)] = 1;
    for (int64_t x = n; x < nodes; ++x) shared[(size_t)x] = 1;
    // Each local component: its label (its smallest dof), whether a contact touches it and
    // whether it reaches another rank.
    std::vector<int64_t> label((size_t)nodes, INT64_MAX);
    std::vector<char> touched((size_t)nodes, 0), spans((size_t)nodes, 0);
    for (int64_t x = 0; x < nodes; ++x) {
        const size_t root = (size_t)local.find(x);
        label[root] = std::min(label[root], dof_of(x));
        if (x < n && reached[(size_t)x]) touched[root] = 1;
        if (shared[(size_t)x]) spans[root] = 1;
    }
    // The components that span ranks, joined: each shared node's edge to its component's label,
    // and the labels of the touched ones (-1), gathered by every rank in rank order.
    std::vector<int64_t> mine;
    for (int64_t x = 0; x < nodes; ++x) {
        const size_t root = (size_t)local.find(x);
        if (shared[(size_t)x]) mine.insert(mine.end(), {label[root], dof_of(x)});
        if ((int64_t)root == x && spans[root] && touched[root]) mine.insert(mine.end(), {label[root], -1});
    }
    const std::vector<int64_t> edges = exchange_lists(comm, std::vector<std::vector<int64_t>>(tell.size(), mine));
    std::vector<int64_t> ids;
    for (const int64_t id : edges)
        if (id >= 0) ids.push_back(id);
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    const auto index = [&](int64_t id) { return position(ids, id); };
    DisjointSets joined((int64_t)ids.size());
    for (size_t e = 0; e + 1 < edges.size(); e += 2)
        if (edges[e + 1] >= 0) joined.unite(index(edges[e]), index(edges[e + 1]));
    std::vector<char> joined_touched(ids.size(), 0);
    for (size_t e = 0; e + 1 < edges.size(); e += 2)
        if (edges[e + 1] < 0) joined_touched[(size_t)joined.find(index(edges[e]))] = 1;
    std::vector<char> load((size_t)n, 0);
    for (int64_t i = 0; i < n; ++i) {
        const size_t root = (size_t)local.find(i);
        const bool body_touched =
            spans[root] ? joined_touched[(size_t)joined.find(index(label[root]))] != 0 : touched[root] != 0;
        load[(size_t)i] = !reached[(size_t)i] && body_touched;
    }
    return load;
}

}  // namespace

RanksWeights ranks_weights(const frix_mpi_problem &p) {
    const frix_mpi_global_rows &g = *p.global;
    const MPI_Comm comm = p.ctx->comm;
    const int64_t n = g.dofs, nc = p.owned;
    // M's diagonal and f on the owned dofs, and on the other ranks' dofs the contacts reach.
    std::vector<double> diag_f(2 * (size_t)n, 0.0);
    for (int64_t i = 0; i < n; ++i) {
        for (int64_t k = g.m_ptr[(size_t)i]; k < g.m_ptr[(size_t)i + 1]; ++k)
            if (g.m_col[(size_t)k] == g.dof_first + i) diag_f[2 * (size_t)i] = g.m_val[(size_t)k];
        diag_f[2 * (size_t)i + 1] = g.f[(size_t)i];
    }
    std::vector<int64_t> foreign;
    for (const int64_t j : g.ht_col)
        if (j < g.dof_first || j >= g.dof_first + n) foreign.push_back(j);
    std::sort(foreign.begin(), foreign.end());
    foreign.erase(std::unique(foreign.begin(), foreign.end()), foreign.end());
    const std::vector<double> fetched = fetch(comm, g, foreign, diag_f, 2);
    const auto at = [&](int64_t j) -> const double * {
        if (j >= g.dof_first && j < g.dof_first + n) return &diag_f[2 * (size_t)(j - g.dof_first)];
        return &fetched[2 * (size_t)position(foreign, j)];
    };
    // w_a: the normal entry of H_a^T diag(M)^-1 H_a; |H^T D^-1 f + w|'s terms on the way.
    std::vector<double> contact((size_t)nc, 0.0), jacobi(p.w);
    for (int64_t row = 0; row < 3 * nc; ++row)
        for (int64_t k = g.ht_ptr[(size_t)row]; k < g.ht_ptr[(size_t)row + 1]; ++k) {
            const double h = g.ht_val[(size_t)k], *df = at(g.ht_col[(size_t)k]);
            if (row % 3 == 0) contact[(size_t)(row / 3)] += h * h * inverse_mass(df[0], 0.0);
            if (df[0] > 0.0) jacobi[(size_t)row] += h * (df[1] / df[0]);
        }
    std::vector<double> dof((size_t)n);
    for (int64_t i = 0; i < n; ++i) dof[(size_t)i] = std::sqrt(inverse_mass(diag_f[2 * (size_t)i], 0.0));
    return finish_weights(comm, p.total, std::move(contact), std::move(dof), g.f, load_dofs(p), p.w, jacobi);
}

frix_problem watched_contacts(const frix_mpi_problem &p, const RanksWeights &weights) {
    frix_problem part;
    part.kind = FRIX_PROBLEM_GLOBAL;
    part.nc = p.owned;
    part.n = p.global->dofs;
    part.mu = p.mu.data();
    part.w = p.w.data();
    part.weight = weights.contact;
    return part;
}

void fill_over_ranks(MPI_Comm comm, std::vector<double> &x) {
    PositiveMean mean;
    mean.add(x);
    double sums[2] = {mean.sum, mean.count};
    reduce_all(comm, sums, 2, "ss");
    mean.sum = sums[0], mean.count = sums[1];
    fill_not_positive(x, mean.fill());
}

RanksWeights finish_weights(MPI_Comm comm, int64_t total, std::vector<double> contact, std::vector<double> dof,
                            const std::vector<double> &f, const std::vector<char> &load, const std::vector<double> &w,
                            const std::vector<double> &jacobi) {
    RanksWeights out;
    out.contact = std::move(contact);
    out.dof = std::move(dof);
    fill_over_ranks(comm, out.contact);
    fill_over_ranks(comm, out.dof);
    // load_velocity over the load dofs of all ranks.
    std::vector<double> scaled_load;
    for (size_t i = 0; i < load.size(); ++i)
        if (load[i]) scaled_load.push_back(f[i] * out.dof[i]);
    double counts[2] = {(double)scaled_load.size(), 0.0};
    for (const double x : out.contact) counts[1] += x / (double)total;
    reduce_all(comm, counts, 2, "ss");
    const double load_norm = norm2_all(comm, scaled_load.data(), (int64_t)scaled_load.size());
    const double load_velocity = total > 0 ? load_velocity_of(counts[1], total, load_norm, (int64_t)counts[0]) : 0.0;
    out.free = free_velocity_of(norm2_all(comm, w.data(), (int64_t)w.size()),
                                norm2_all(comm, jacobi.data(), (int64_t)jacobi.size()), load_velocity);
    return out;
}

}  // namespace mpi
}  // namespace frix
