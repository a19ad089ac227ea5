// Distributed global problems of rigid bodies (frix_mpi_problem_rigid): each rank's contacts
// with their blocks of H^T, the bodies they act on with their mass blocks, and the ghosts (the
// other ranks' contacts acting on those bodies), found through a directory of the bodies.
#include <algorithm>
#include <cmath>
#include <memory>
#include <utility>
#include <vector>

#include "mpi/distributed_forms.hpp"
#include "src/disjoint_sets.hpp"
#include "src/error_state.hpp"
#include "src/problem.hpp"
#include "src/linalg/linalg.hpp"

namespace frix {
namespace mpi {
namespace {

bool all_finite(const double *x, int64_t n) {
    for (int64_t i = 0; i < n; ++i)
        if (!std::isfinite(x[i])) return false;
    return true;
}

// One rank's input, checked on its own.
frix_error check_rigid(int64_t first, int64_t owned, const int64_t *bodies, const double *G, const double *w,
                       const double *mu, int64_t held, const int64_t *body_ids, const double *M, const double *f,
                       const char *where) {
    if (first < 0 || owned < 0 || held < 0)
        return fail(FRIX_ERR_DIMENSION, "%s: first, owned and held must be >= 0", where);
    if (owned > 0 && (!bodies || !G || !w || !mu))
        return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: bodies, G, w and mu are required", where);
    if (held > 0 && (!body_ids || !M || !f))
        return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: body_ids, M and f are required", where);
    if (!all_finite(G, 36 * owned) || !all_finite(w, 3 * owned) || !all_finite(M, 36 * held) ||
        !all_finite(f, 6 * held))
        return fail(FRIX_ERR_NOT_FINITE, "%s: G, w, M and f must be finite", where);
    if (frix_error e = check_mu(where, mu, owned)) return e;
    std::vector<int64_t> ids(body_ids, body_ids + held);
    std::sort(ids.begin(), ids.end());
    for (size_t b = 0; b < ids.size(); ++b)
        if (ids[b] < 0 || (b > 0 && ids[b] == ids[b - 1]))
            return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: body id %lld is negative or given twice", where,
                        (long long)ids[b]);
    for (int64_t i = 0; i < 2 * owned; ++i)
        if (bodies[i] < -1 || (bodies[i] >= 0 && !std::binary_search(ids.begin(), ids.end(), bodies[i])))
            return fail(FRIX_ERR_INVALID_ARGUMENT,
                        "%s: contact %lld acts on body %lld, which this rank did not give (body_ids)", where,
                        (long long)(first + i / 2), (long long)bodies[i]);
    return FRIX_OK;
}

// The ghosts: the other ranks' contacts on the bodies this rank holds (those its contacts act
// on, whose velocities its sweeps read, and any other it gave, whose velocities it reports).
// Each body's home rank (body % size) hears of every contact on it, and of every rank holding
// it (a pair (body, -1 - rank)), and tells each of those ranks the body's contacts. Returns
// the pairs (body, contact) whose contact is another rank's.
std::vector<std::pair<int64_t, int64_t>> other_contacts_on_my_bodies(const frix_mpi_problem &p, const int64_t *bodies) {
    const frix_mpi_context &c = *p.ctx;
    const size_t P = (size_t)c.size;
    std::vector<std::vector<int64_t>> to_home(P);
    for (int64_t i = 0; i < p.owned; ++i)
        for (int s = 0; s < 2; ++s) {
            const int64_t b = bodies[2 * i + s];
            if (b < 0 || (s == 1 && b == bodies[2 * i])) continue;
            std::vector<int64_t> &l = to_home[(size_t)(b % (int64_t)P)];
            l.push_back(b);
            l.push_back(p.first + i);
        }
    for (const int64_t b : p.body_ids) {
        std::vector<int64_t> &l = to_home[(size_t)(b % (int64_t)P)];
        l.push_back(b);
        l.push_back(-1 - (int64_t)c.rank);
    }
    const std::vector<int64_t> at_home = exchange_lists(c.comm, to_home);
    std::vector<std::pair<int64_t, int64_t>> pairs;
    for (size_t k = 0; k + 1 < at_home.size(); k += 2) pairs.emplace_back(at_home[k], at_home[k + 1]);
    std::sort(pairs.begin(), pairs.end());
    std::vector<std::vector<int64_t>> to_ranks(P);
    std::vector<int> ranks;
    for (size_t g = 0; g < pairs.size();) {
        size_t end = g;
        ranks.clear();
        for (; end < pairs.size() && pairs[end].first == pairs[g].first; ++end) {
            const int64_t who = pairs[end].second;
            ranks.push_back(who < 0 ? (int)(-1 - who) : owner_of(p.starts, who));
        }
        std::sort(ranks.begin(), ranks.end());
        ranks.erase(std::unique(ranks.begin(), ranks.end()), ranks.end());
        if (ranks.size() > 1)
            for (const int r : ranks)
                for (size_t e = g; e < end; ++e)
                    if (pairs[e].second >= 0) {
                        to_ranks[(size_t)r].push_back(pairs[e].first);
                        to_ranks[(size_t)r].push_back(pairs[e].second);
                    }
        g = end;
    }
    const std::vector<int64_t> back = exchange_lists(c.comm, to_ranks);
    std::vector<std::pair<int64_t, int64_t>> others;
    for (size_t k = 0; k + 1 < back.size(); k += 2)
        if (back[k + 1] < p.first || back[k + 1] >= p.first + p.owned) others.emplace_back(back[k], back[k + 1]);
    return others;
}

// The ghosts' bodies and blocks G from their owners, into the ghost slots (after the owned
// contacts' own), over the exchange plan.
void fetch_ghost_data(frix_mpi_problem &p, std::vector<int64_t> &bodies, std::vector<double> &G) {
    const frix_mpi_context &c = *p.ctx;
    const size_t n = p.neighbours.size();
    std::vector<int64_t> send_bodies;
    std::vector<double> send_G;
    for (const int64_t a : p.send) {
        send_bodies.insert(send_bodies.end(), bodies.begin() + 2 * a, bodies.begin() + 2 * a + 2);
        send_G.insert(send_G.end(), G.begin() + 36 * a, G.begin() + 36 * a + 36);
    }
    std::vector<MPI_Request> requests;
    requests.reserve(4 * n);
    for (size_t k = 0; k < n; ++k) {
        const int64_t from = p.recv_ptr[k], to = p.recv_ptr[k + 1];
        if (to > from) {
            requests.emplace_back();
            check(MPI_Irecv(bodies.data() + 2 * (p.owned + from), checked_count(2 * (to - from)), MPI_INT64_T,
                            p.neighbours[k], 1, c.comm, &requests.back()),
                  "MPI_Irecv");
            requests.emplace_back();
            check(MPI_Irecv(G.data() + 36 * (p.owned + from), checked_count(36 * (to - from)), MPI_DOUBLE,
                            p.neighbours[k], 2, c.comm, &requests.back()),
                  "MPI_Irecv");
        }
        const int64_t s0 = p.send_ptr[k], s1 = p.send_ptr[k + 1];
        if (s1 > s0) {
            requests.emplace_back();
            check(MPI_Isend(send_bodies.data() + 2 * s0, checked_count(2 * (s1 - s0)), MPI_INT64_T, p.neighbours[k], 1,
                            c.comm, &requests.back()),
                  "MPI_Isend");
            requests.emplace_back();
            check(MPI_Isend(send_G.data() + 36 * s0, checked_count(36 * (s1 - s0)), MPI_DOUBLE, p.neighbours[k], 2,
                            c.comm, &requests.back()),
                  "MPI_Isend");
        }
    }
    check(MPI_Waitall((int)requests.size(), requests.data(), MPI_STATUSES_IGNORE), "MPI_Waitall");
}

// Slots, M^-1, v0, M^-1 G^T and W_aa; FRIX_ERR_NUMERICAL for a singular mass block.
frix_error form_bodies(frix_mpi_problem &p, const std::vector<int64_t> &bodies, int64_t held, const double *M,
                       const double *f, const char *where) {
    const int64_t contacts = p.owned + (int64_t)p.ghosts.size();
    std::vector<std::pair<int64_t, int64_t>> slot_of((size_t)held);
    for (int64_t b = 0; b < held; ++b) slot_of[(size_t)b] = {p.body_ids[(size_t)b], b};
    std::sort(slot_of.begin(), slot_of.end());
    p.side_slot.assign(2 * (size_t)contacts, -1);
    for (int64_t i = 0; i < 2 * contacts; ++i) {
        const auto it = std::lower_bound(slot_of.begin(), slot_of.end(), std::make_pair(bodies[(size_t)i], (int64_t)-1));
        if (bodies[(size_t)i] >= 0 && it != slot_of.end() && it->first == bodies[(size_t)i])
            p.side_slot[(size_t)i] = it->second;
    }
    p.minv.assign(36 * (size_t)held, 0.0);
    p.v0.assign(6 * (size_t)held, 0.0);
    double a[36];
    for (int64_t b = 0; b < held; ++b) {
        double scale = 0.0, *inv = &p.minv[36 * (size_t)b];
        for (int e = 0; e < 36; ++e) {
            a[e] = M[36 * b + e];
            scale = std::max(scale, std::fabs(a[e]));
        }
        for (int j = 0; j < 6; ++j) inv[j + 6 * j] = 1.0;
        if (!linalg::invert_small(6, a, inv, scale))
            return fail(FRIX_ERR_NUMERICAL, "%s: the mass block of body %lld is singular", where,
                        (long long)p.body_ids[(size_t)b]);
        for (int i = 0; i < 6; ++i)
            for (int j = 0; j < 6; ++j) p.v0[6 * (size_t)b + i] += inv[i + 6 * j] * f[6 * b + j];
    }
    // M^-1 G^T for each side with a body held here (6 x 3, column-major).
    p.mg.assign(36 * (size_t)contacts, 0.0);
    for (int64_t c = 0; c < contacts; ++c)
        for (int s = 0; s < 2; ++s) {
            const int64_t slot = p.side_slot[2 * (size_t)c + s];
            if (slot < 0) continue;
            const double *g = &p.G[36 * (size_t)c + 18 * s], *inv = &p.minv[36 * (size_t)slot];
            double *out = &p.mg[36 * (size_t)c + 18 * s];
            for (int k = 0; k < 3; ++k)
                for (int i = 0; i < 6; ++i) {
                    double t = 0.0;
                    for (int j = 0; j < 6; ++j) t += inv[i + 6 * j] * g[6 * k + j];
                    out[i + 6 * k] = t;
                }
        }
    // W_aa = sum over the sides of G M^-1 G^T.
    p.diag.assign(9 * (size_t)p.owned, 0.0);
    for (int64_t c = 0; c < p.owned; ++c)
        for (int s = 0; s < 2; ++s) {
            if (p.side_slot[2 * (size_t)c + s] < 0) continue;
            const double *g = &p.G[36 * (size_t)c + 18 * s], *mg = &p.mg[36 * (size_t)c + 18 * s];
            for (int k = 0; k < 3; ++k)
                for (int l = 0; l < 3; ++l) {
                    double t = 0.0;
                    for (int j = 0; j < 6; ++j) t += g[6 * k + j] * mg[j + 6 * l];
                    p.diag[9 * (size_t)c + k + 3 * l] += t;
                }
        }
    p.mass.assign(M, M + 36 * held);
    p.body_f.assign(f, f + 6 * held);
    return FRIX_OK;
}

// Whether this rank is the lowest to hold each of its bodies, in their order (the bodies'
// home ranks, body % size, hear of every rank holding them).
std::vector<char> kept_bodies(const frix_mpi_problem &p) {
    const MPI_Comm comm = p.ctx->comm;
    const size_t P = (size_t)p.ctx->size;
    std::vector<std::vector<int64_t>> to_home(P), back(P);
    for (const int64_t b : p.body_ids) to_home[(size_t)(b % (int64_t)P)].push_back(b);
    std::vector<int> at;
    const std::vector<int64_t> heard = exchange_lists(comm, to_home, &at);
    std::vector<std::pair<int64_t, int>> holders;
    for (size_t k = 0; k < P; ++k)
        for (int e = at[k]; e < at[k + 1]; ++e) holders.emplace_back(heard[(size_t)e], (int)k);
    std::sort(holders.begin(), holders.end());
    for (size_t e = 0; e < holders.size(); ++e)
        if (e == 0 || holders[e].first != holders[e - 1].first)
            back[(size_t)holders[e].second].push_back(holders[e].first);
    std::vector<int64_t> mine = exchange_lists(comm, back);
    std::sort(mine.begin(), mine.end());
    std::vector<char> kept(p.body_ids.size(), 0);
    for (size_t b = 0; b < kept.size(); ++b) kept[b] = std::binary_search(mine.begin(), mine.end(), p.body_ids[b]);
    return kept;
}

// Held contact c's blocks of H^T on the bodies held here (slots[k], 18 values row-major in
// blocks[k]); the two sides' blocks added where both are one body, as the whole H holds them.
int contact_blocks(const frix_mpi_problem &p, int64_t c, int64_t slots[2], double blocks[2][18]) {
    int count = 0;
    for (int s = 0; s < 2; ++s) {
        const int64_t slot = p.side_slot[2 * (size_t)c + s];
        if (slot < 0) continue;
        const double *g = &p.G[36 * (size_t)c + 18 * s];
        if (count == 1 && slots[0] == slot) {
            for (int e = 0; e < 18; ++e) blocks[0][e] += g[e];
            continue;
        }
        slots[count] = slot;
        std::copy(g, g + 18, blocks[count++]);
    }
    return count;
}

// The default measure's weights and floor of the whole problem (set_contact_weights and
// free_velocity on M = diag(M_b), H^T = the blocks G): w_a from diag(M) at the contacts' bodies,
// diag(M)^-1/2 and the load dofs of the kept bodies (every contact on a body held here is a
// held contact). Collective.
void rigid_weights(frix_mpi_problem &p) {
    const int64_t held = (int64_t)p.body_ids.size(), contacts = p.owned + (int64_t)p.ghosts.size();
    const auto m_jj = [&](int64_t slot, int j) { return p.mass[36 * (size_t)slot + 7 * (size_t)j]; };
    std::vector<double> contact((size_t)p.owned, 0.0), jacobi(p.w);
    std::vector<char> reached(6 * (size_t)held, 0);
    int64_t slots[2];
    double blocks[2][18];
    for (int64_t c = 0; c < contacts; ++c)
        for (int k = 0, n = contact_blocks(p, c, slots, blocks); k < n; ++k)
            for (int j = 0; j < 6; ++j) {
                const double d = m_jj(slots[k], j), *col = &blocks[k][j];
                if (col[0] != 0.0 || col[6] != 0.0 || col[12] != 0.0) reached[6 * (size_t)slots[k] + j] = 1;
                if (c >= p.owned) continue;
                contact[(size_t)c] += col[0] * col[0] * inverse_mass(d, 0.0);
                const double f_j = p.body_f[6 * (size_t)slots[k] + j];
                if (d > 0.0)
                    for (int e = 0; e < 3; ++e) jacobi[3 * (size_t)c + e] += col[6 * e] * (f_j / d);
            }
    p.kept = kept_bodies(p);
    std::vector<double> dof, f;
    std::vector<char> load;
    for (int64_t b = 0; b < held; ++b) {
        if (!p.kept[(size_t)b]) continue;
        DisjointSets parts(6);  // the body's dofs joined by M's entries, as M's graph joins them
        for (int i = 0; i < 6; ++i)
            for (int j = 0; j < 6; ++j)
                if (p.mass[36 * (size_t)b + 6 * (size_t)j + i] != 0.0) parts.unite(i, j);
        char touched[6] = {0};
        for (int j = 0; j < 6; ++j) touched[parts.find(j)] |= reached[6 * (size_t)b + j];
        for (int j = 0; j < 6; ++j) {
            dof.push_back(std::sqrt(inverse_mass(m_jj(b, j), 0.0)));
            f.push_back(p.body_f[6 * (size_t)b + j]);
            load.push_back(!reached[6 * (size_t)b + j] && touched[parts.find(j)]);
        }
    }
    RanksWeights weights =
        finish_weights(p.ctx->comm, p.total, std::move(contact), std::move(dof), f, load, p.w, jacobi);
    p.view.weight = std::move(weights.contact);
    p.dof_weight = std::move(weights.dof);
    p.free = weights.free;
}

}  // namespace
}  // namespace mpi
}  // namespace frix

extern "C" {

FRIX_API frix_error frix_mpi_problem_rigid(frix_mpi_context *ctx, int64_t first, int64_t owned, const int64_t *bodies,
                                           const double *G, const double *w, const double *mu, int64_t held,
                                           const int64_t *body_ids, const double *M, const double *f,
                                           frix_mpi_problem **out) {
    return frix::guard("frix_mpi_problem_rigid", [&]() -> frix_error {
        using frix::fail;
        const char *where = "frix_mpi_problem_rigid";
        if (!ctx) return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: ctx is NULL", where);
        if (out) *out = nullptr;
        frix_error e = out ? frix::mpi::check_rigid(first, owned, bodies, G, w, mu, held, body_ids, M, f, where)
                           : fail(FRIX_ERR_INVALID_ARGUMENT, "%s: out is NULL", where);
        std::unique_ptr<frix_mpi_problem> p = frix::mpi::start_part(ctx, first, owned, e, where);
        if (frix_error agreed = frix::mpi::agree(ctx->comm, e, where)) return agreed;
        frix_mpi_problem &part = *p;
        part.rigid = true;
        part.mu.assign(mu, mu + owned);
        part.w.assign(w, w + 3 * owned);
        part.q = part.w;  // unused by the rigid form; |w| is the scale
        part.body_ids.assign(body_ids, body_ids + held);
        // Ghosts, and which owned contacts share a body with one.
        const auto others = frix::mpi::other_contacts_on_my_bodies(part, bodies);
        std::vector<int64_t> shared_bodies;
        for (const auto &bc : others) {
            part.ghosts.push_back(bc.second);
            shared_bodies.push_back(bc.first);
        }
        std::sort(part.ghosts.begin(), part.ghosts.end());
        part.ghosts.erase(std::unique(part.ghosts.begin(), part.ghosts.end()), part.ghosts.end());
        std::sort(shared_bodies.begin(), shared_bodies.end());
        std::vector<char> has_ghost((size_t)owned, 0);
        for (int64_t i = 0; i < 2 * owned; ++i)
            if (bodies[i] >= 0 && std::binary_search(shared_bodies.begin(), shared_bodies.end(), bodies[i]))
                has_ghost[(size_t)(i / 2)] = 1;
        frix::mpi::plan_exchange(part, has_ghost);
        const int64_t contacts = owned + (int64_t)part.ghosts.size();
        std::vector<int64_t> all_bodies(2 * (size_t)contacts, -1);
        std::copy(bodies, bodies + 2 * owned, all_bodies.begin());
        part.G.assign(36 * (size_t)contacts, 0.0);
        std::copy(G, G + 36 * owned, part.G.begin());
        frix::mpi::fetch_ghost_data(part, all_bodies, part.G);
        e = frix::mpi::form_bodies(part, all_bodies, held, M, f, where);
        if (frix_error agreed = frix::mpi::agree(ctx->comm, e, where)) return agreed;
        frix::mpi::rigid_weights(part);
        part.view.kind = FRIX_PROBLEM_GLOBAL;
        part.view.nc = owned;
        part.view.mu = part.mu.data();
        part.view.w = part.w.data();
        *out = p.release();
        return FRIX_OK;
    });
}

FRIX_API frix_error frix_mpi_problem_velocities(const frix_mpi_problem *p, double *v) {
    return frix::guard("frix_mpi_problem_velocities", [&]() -> frix_error {
        if (!p || !(p->rigid || p->global) || !p->solved || (!p->v.empty() && !v))
            return frix::fail(FRIX_ERR_INVALID_ARGUMENT,
                              "frix_mpi_problem_velocities: a global problem (rigid bodies or the host's M), solved, and "
                              "v are required");
        std::copy(p->v.begin(), p->v.end(), v);
        return FRIX_OK;
    });
}

}  // extern "C"
