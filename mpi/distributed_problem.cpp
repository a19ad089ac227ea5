// Distributed local problems: each rank's block rows, the ghosts they couple to, the
// exchange with the neighbours and the colouring of the ranks that orders the sweep.
#include <algorithm>
#include <climits>
#include <cmath>
#include <memory>

#include "mpi/distributed.hpp"
#include "src/error_state.hpp"
#include "src/problem.hpp"
#include "src/monitor.hpp"
#include "src/reduction.hpp"

namespace frix {
namespace mpi {

int owner_of(const std::vector<int64_t> &starts, int64_t g) {
    return (int)(std::upper_bound(starts.begin(), starts.end(), g) - starts.begin()) - 1;
}

int checked_count(int64_t n) {
    if (n > INT_MAX) {
        fail(FRIX_ERR_DIMENSION, "a rank's part holds %lld values, more than one MPI message carries (%d)",
             (long long)n, INT_MAX);
        throw Failure{FRIX_ERR_DIMENSION};
    }
    return (int)n;
}

namespace {

// Checks one rank's input as frix_problem_local checks a whole problem; FRIX_OK or a message.
frix_error check_part(int64_t first, int64_t owned, const int64_t *row_ptr, const int64_t *block_col,
                      const double *block_val, const double *q, const double *mu, const char *where) {
    if (first < 0 || owned < 0)
        return fail(FRIX_ERR_DIMENSION, "%s: first (%lld) and owned (%lld) must be >= 0", where, (long long)first,
                    (long long)owned);
    if (owned == 0) return FRIX_OK;
    if (!row_ptr || !q || !mu) return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: row_ptr, q and mu are required", where);
    if (row_ptr[0] != 0) return fail(FRIX_ERR_DIMENSION, "%s: row_ptr[0] is %lld, not 0", where, (long long)row_ptr[0]);
    for (int64_t i = 0; i < owned; ++i) {
        if (row_ptr[i + 1] < row_ptr[i])
            return fail(FRIX_ERR_DIMENSION, "%s: row_ptr decreases at row %lld", where, (long long)i);
        for (int64_t k = row_ptr[i] + 1; k < row_ptr[i + 1]; ++k)
            if (block_col[k] <= block_col[k - 1])
                return fail(FRIX_ERR_DIMENSION, "%s: the block columns of row %lld do not increase", where,
                            (long long)i);
    }
    const int64_t blocks = row_ptr[owned];
    if (blocks > 0 && (!block_col || !block_val))
        return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: block_col and block_val are required", where);
    for (int64_t k = 0; k < 9 * blocks; ++k)
        if (!std::isfinite(block_val[k]))
            return fail(FRIX_ERR_NOT_FINITE, "%s: block_val[%lld] is not finite", where, (long long)k);
    if (frix_error e = check_vector(where, "q", q, 3 * owned)) return e;
    return check_mu(where, mu, owned);
}


// Greedy colouring of the ranks in rank order: each takes the smallest colour none of its
// lower neighbours has. Every rank computes it from the same gathered lists.
void colour_ranks(frix_mpi_problem &p) {
    const frix_mpi_context &c = *p.ctx;
    int count = (int)p.neighbours.size();
    std::vector<int> counts((size_t)c.size), displs((size_t)c.size + 1, 0);
    check(MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, c.comm), "MPI_Allgather");
    for (int k = 0; k < c.size; ++k) displs[(size_t)k + 1] = displs[(size_t)k] + counts[(size_t)k];
    std::vector<int> lists((size_t)displs[(size_t)c.size]);
    check(MPI_Allgatherv(p.neighbours.data(), count, MPI_INT, lists.data(), counts.data(), displs.data(), MPI_INT,
                         c.comm),
          "MPI_Allgatherv");
    std::vector<int> colour((size_t)c.size, 0);
    std::vector<char> taken;
    int colours = 1;
    for (int k = 0; k < c.size; ++k) {
        taken.assign((size_t)counts[(size_t)k] + 1, 0);
        for (int e = displs[(size_t)k]; e < displs[(size_t)k + 1]; ++e) {
            const int j = lists[(size_t)e];
            if (j < k && colour[(size_t)j] < (int)taken.size()) taken[(size_t)colour[(size_t)j]] = 1;
        }
        int mine = 0;
        while (taken[(size_t)mine]) ++mine;
        colour[(size_t)k] = mine;
        colours = std::max(colours, mine + 1);
    }
    p.colour = colour[(size_t)c.rank];
    p.colours = colours;
    p.neighbour_colour.clear();
    for (const int j : p.neighbours) p.neighbour_colour.push_back(colour[(size_t)j]);
}

// Builds p (ctx, first, owned set) from checked input: local columns, ghosts, exchange plan,
// boundary, colours. Collective.
void build(frix_mpi_problem &p, const int64_t *row_ptr, const int64_t *block_col, const double *block_val,
           const double *q, const double *mu, const double *scale) {
    const int64_t owned = p.owned, first = p.first, blocks = owned > 0 ? row_ptr[owned] : 0;
    // Ghosts: the columns outside [first, first + owned), increasing.
    for (int64_t k = 0; k < blocks; ++k)
        if (block_col[k] < first || block_col[k] >= first + owned) p.ghosts.push_back(block_col[k]);
    std::sort(p.ghosts.begin(), p.ghosts.end());
    p.ghosts.erase(std::unique(p.ghosts.begin(), p.ghosts.end()), p.ghosts.end());
    const int64_t held = owned + (int64_t)p.ghosts.size();

    frix_matrix &W = p.W;
    W.block = true;
    W.rows = 3 * owned;
    W.cols = 3 * held;
    W.block_rows = owned;
    W.block_cols = held;
    W.row_ptr.assign(row_ptr, row_ptr + owned + 1);
    if (owned == 0) W.row_ptr.assign(1, 0);
    W.block_col.resize((size_t)blocks);
    W.block_val.assign(block_val, block_val + 9 * blocks);
    W.diag_index.assign((size_t)owned, -1);
    std::vector<char> has_ghost((size_t)owned, 0);
    for (int64_t i = 0; i < owned; ++i)
        for (int64_t k = row_ptr[i]; k < row_ptr[i + 1]; ++k) {
            const int64_t g = block_col[k];
            if (g >= first && g < first + owned) {
                W.block_col[(size_t)k] = g - first;
                if (g - first == i) W.diag_index[(size_t)i] = k;
            } else {
                W.block_col[(size_t)k] =
                    owned + (std::lower_bound(p.ghosts.begin(), p.ghosts.end(), g) - p.ghosts.begin());
                has_ghost[(size_t)i] = 1;
            }
        }
    p.q.assign(q, q + 3 * owned);
    p.mu.assign(mu, mu + owned);
    p.view.kind = FRIX_PROBLEM_LOCAL;
    p.view.nc = owned;
    p.view.W = &p.W;
    p.view.q = p.q.data();
    p.view.mu = p.mu.data();
    // The serial weights of the whole problem (set_contact_weights): the fill's mean over all ranks.
    p.view.weight = unfilled_contact_weights(p.view, {});
    fill_over_ranks(p.ctx->comm, p.view.weight);
    if (scale != q) p.w.assign(scale, scale + 3 * owned);
    plan_exchange(p, has_ghost);
}

}  // namespace

std::vector<int64_t> exchange_lists(MPI_Comm comm, const std::vector<std::vector<int64_t>> &out,
                                    std::vector<int> *in_displs) {
    const size_t P = out.size();
    std::vector<int> counts(P), displs(P + 1, 0), in_counts(P), at(P + 1, 0);
    std::vector<int64_t> flat;
    for (size_t k = 0; k < P; ++k) {
        counts[k] = checked_count((int64_t)out[k].size());
        displs[k + 1] = displs[k] + counts[k];
        flat.insert(flat.end(), out[k].begin(), out[k].end());
    }
    check(MPI_Alltoall(counts.data(), 1, MPI_INT, in_counts.data(), 1, MPI_INT, comm), "MPI_Alltoall");
    for (size_t k = 0; k < P; ++k) at[k + 1] = at[k] + in_counts[k];
    std::vector<int64_t> in((size_t)at[P]);
    check(MPI_Alltoallv(flat.data(), counts.data(), displs.data(), MPI_INT64_T, in.data(), in_counts.data(), at.data(),
                        MPI_INT64_T, comm),
          "MPI_Alltoallv");
    if (in_displs) *in_displs = std::move(at);
    return in;
}

void plan_exchange(frix_mpi_problem &p, const std::vector<char> &has_ghost) {
    const frix_mpi_context &c = *p.ctx;
    const int64_t owned = p.owned, first = p.first;
    // Ask each owner for its ghosts; what the others ask of this rank is what it sends.
    const size_t P = (size_t)c.size;
    std::vector<std::vector<int64_t>> asks(P);
    for (const int64_t g : p.ghosts) asks[(size_t)owner_of(p.starts, g)].push_back(g);
    std::vector<int> asked_displs;
    const std::vector<int64_t> wanted = exchange_lists(c.comm, asks, &asked_displs);
    std::vector<char> sent((size_t)owned, 0);
    p.send_ptr.assign(1, 0);
    p.recv_ptr.assign(1, 0);
    // This rank's ghosts owned by neighbour k are one run (increasing global indices):
    // ghost slots recv_ptr[k] .. recv_ptr[k+1].
    int64_t first_ghost = 0;
    for (size_t k = 0; k < P; ++k) {
        const int64_t runs_to = first_ghost + (int64_t)asks[k].size();
        if (asks[k].empty() && asked_displs[k] == asked_displs[k + 1]) continue;
        p.neighbours.push_back((int)k);
        for (int e = asked_displs[k]; e < asked_displs[k + 1]; ++e) {
            const int64_t local = wanted[(size_t)e] - first;
            p.send.push_back(local);
            sent[(size_t)local] = 1;
        }
        p.send_ptr.push_back((int64_t)p.send.size());
        p.recv_ptr.push_back(runs_to);
        first_ghost = runs_to;
    }
    for (int64_t i = 0; i < owned; ++i) (has_ghost[(size_t)i] || sent[(size_t)i] ? p.boundary : p.interior).push_back(i);
    colour_ranks(p);
}

frix_error cut_by_part(const int *part, int64_t n, int ranks, std::vector<int64_t> &cut, std::vector<int64_t> &order,
                       const char *where) {
    const size_t P = (size_t)ranks;
    cut.assign(P + 1, 0);
    order.clear();
    if (!part) {
        const int64_t base = n / ranks, extra = n % ranks;
        for (size_t k = 0; k < P; ++k) cut[k + 1] = cut[k] + base + ((int64_t)k < extra ? 1 : 0);
        return FRIX_OK;
    }
    for (int64_t a = 0; a < n; ++a)
        if (part[a] < 0 || part[a] >= ranks)
            return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: part[%lld] = %d is not a rank (0 .. %d)", where, (long long)a,
                        part[a], ranks - 1);
    // A stable counting sort by part.
    for (int64_t a = 0; a < n; ++a) ++cut[(size_t)part[a] + 1];
    for (size_t k = 0; k < P; ++k) cut[k + 1] += cut[k];
    std::vector<int64_t> next(cut.begin(), cut.end() - 1);
    order.resize((size_t)n);
    for (int64_t a = 0; a < n; ++a) order[(size_t)next[(size_t)part[a]]++] = a;
    return FRIX_OK;
}

bool gather_blocks(MPI_Comm comm, int64_t first, int64_t count, std::vector<int64_t> &starts) {
    int size = 1;
    check(MPI_Comm_size(comm, &size), "MPI_Comm_size");
    const int64_t mine[2] = {first, count};
    std::vector<int64_t> all((size_t)size * 2);
    check(MPI_Allgather(mine, 2, MPI_INT64_T, all.data(), 2, MPI_INT64_T, comm), "MPI_Allgather");
    starts.assign((size_t)size + 1, 0);
    bool contiguous = true;
    for (int k = 0; k < size; ++k) {
        contiguous = contiguous && all[2 * (size_t)k] == starts[(size_t)k] && all[2 * (size_t)k + 1] >= 0;
        starts[(size_t)k + 1] = starts[(size_t)k] + std::max<int64_t>(all[2 * (size_t)k + 1], 0);
    }
    return contiguous;
}

std::unique_ptr<frix_mpi_problem> start_part(frix_mpi_context *ctx, int64_t first, int64_t owned, frix_error &e,
                                             const char *where) {
    auto p = std::make_unique<frix_mpi_problem>();
    p->ctx = ctx;
    p->first = first;
    p->owned = owned;
    const bool contiguous = gather_blocks(ctx->comm, first, owned, p->starts);
    p->total = p->starts[(size_t)ctx->size];
    p->ids.resize((size_t)std::max<int64_t>(owned, 0));
    for (int64_t i = 0; i < owned; ++i) p->ids[(size_t)i] = first + i;
    if (!e && !contiguous)
        e = fail(FRIX_ERR_DIMENSION,
                 "%s: the ranks' contacts must be contiguous blocks in rank order from 0 (this rank: first %lld, owned "
                 "%lld; rank 0 must start at 0 and each rank where the one before ends)",
                 where, (long long)first, (long long)owned);
    return p;
}

frix_error make(frix_mpi_context *ctx, int64_t first, int64_t owned, const int64_t *row_ptr, const int64_t *block_col,
                const double *block_val, const double *q, const double *mu, const double *scale, frix_mpi_problem **out,
                const char *where) {
    frix_error e = check_part(first, owned, row_ptr, block_col, block_val, q, mu, where);
    std::unique_ptr<frix_mpi_problem> p = start_part(ctx, first, owned, e, where);
    if (!e)
        for (int64_t k = 0; k < (owned > 0 ? row_ptr[owned] : 0); ++k)
            if (block_col[k] < 0 || block_col[k] >= p->total) {
                e = fail(FRIX_ERR_DIMENSION, "%s: block_col[%lld] = %lld is not a contact (there are %lld)", where,
                         (long long)k, (long long)block_col[k], (long long)p->total);
                break;
            }
    if (frix_error agreed = agree(ctx->comm, e, where)) return agreed;
    build(*p, row_ptr, block_col, block_val, q, mu, scale ? scale : q);
    *out = p.release();
    return FRIX_OK;
}

namespace {

// A global problem as the local one its ranks solve: W = H^T M^-1 H and q = H^T M^-1 f + w,
// formed on the root by the serial library's reduction (M factorised once).
frix_error reduce(const frix_problem &g, std::unique_ptr<frix_matrix> &W, std::vector<double> &q, const char *where) {
    const int64_t m = 3 * g.nc;
    frix_options opts;
    frix_options *defaults = nullptr;
    if (frix_error e = frix_options_create(FRIX_SOLVER_NSGS, &defaults)) return e;
    opts = *defaults;
    frix_options_free(defaults);
    const Stopwatch clock;
    const ReductionSize size = reduction_bound(g);
    const ReductionMemory memory = reduction_memory(size, Monitor(opts, clock));
    if (!memory.fits)
        return fail(FRIX_ERR_OUT_OF_MEMORY,
                    "%s: W = H^T M^-1 H would take at least %.3g GB, more than the %.3g GB the root may take", where,
                    memory.needed / 1e9, memory.available / 1e9);
    MassSolver ms;
    if (frix_error e = ms.factor(*g.M)) return e;
    std::vector<double> x((size_t)g.n);
    if (frix_error e = ms.solve(g.f, x.data())) return e;
    q.assign((size_t)m, 0.0);
    if (m > 0) matrix_gemv_transposed(*g.H, 1.0, x.data(), 0.0, q.data());
    for (int64_t i = 0; i < m; ++i) q[(size_t)i] += g.w[i];
    bool stopped = false;
    if (frix_error e = ms.congruence(*g.H, size.w_blocks, W, [] { return false; }, stopped)) return e;
    if (!W || !W->block) return fail(FRIX_ERR_INTERNAL, "%s: the reduction did not give 3x3 blocks", where);
    return FRIX_OK;
}

// What the root sends: the local problem the ranks get (the one given, or its global one
// reduced), its contacts in the order of the parts (order[k]: the contact the k-th sent is),
// and where each rank's run starts (cut: on every rank).
struct RootProblem {
    std::vector<int64_t> cut, order;
    const frix_matrix *W = nullptr;
    const double *q = nullptr, *mu = nullptr, *scale = nullptr;  // scale: a global problem's w
    std::vector<double> weight;  // a global problem's contact weights (1 where it has none), its free velocity
    double free = -1.0;
    std::unique_ptr<frix_matrix> reduced_W;
    std::vector<double> reduced_q;
    int64_t nc = 0;
};

// On the root: checks the problem, reduces a global one, and orders the contacts by part.
frix_error prepare_root(const frix_problem *problem, const int *part, int ranks, RootProblem &root,
                        const char *where) {
    if (!problem) return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: problem is NULL on the root", where);
    if (frix_error other = check_release(*problem, where, "problem")) return other;
    if (frix_error rolling = refuse_rolling(*problem, where)) return rolling;
    if (frix_error bad = check_problem_vectors(*problem)) return bad;
    const bool global = problem->kind == FRIX_PROBLEM_GLOBAL;
    if (global) {
        if (frix_error e = reduce(*problem, root.reduced_W, root.reduced_q, where)) return e;
    } else if (problem->nc > 0 && !problem->W->block) {
        return fail(FRIX_ERR_UNSUPPORTED, "%s: W must be stored in 3x3 blocks", where);
    }
    root.nc = problem->nc;
    root.W = global ? root.reduced_W.get() : problem->W;
    root.q = global ? root.reduced_q.data() : problem->q;
    root.mu = problem->mu;
    if (global) {  // the reduced answer is measured as the global problem's (frix_solve's rule)
        root.scale = problem->w;
        root.weight.assign((size_t)problem->nc, 1.0);
        if (problem->weight.size() == (size_t)problem->nc) root.weight = problem->weight;
        root.free = free_velocity(*problem);
    }
    return cut_by_part(part, root.nc, ranks, root.cut, root.order, where);
}

// The root's rows in the order sent: row lengths, their blocks (columns renumbered and
// increasing in each row), and the per-contact vectors. Without parts they are the problem's
// own arrays. Empty on the other ranks.
struct SentRows {
    std::vector<int64_t> lengths, block_at;  // block_at: where each row's blocks start
    std::vector<int64_t> col_store;
    std::vector<double> val_store, q_store, mu_store, scale_store, weight_store;
    const int64_t *cols = nullptr;
    const double *vals = nullptr, *q = nullptr, *mu = nullptr, *scale = nullptr, *weight = nullptr;
};

// The rows in the order of the parts, each row's blocks by increasing new column.
void permute_rows(const RootProblem &root, bool global, SentRows &out) {
    const frix_matrix *W = root.W;
    const int64_t nc = root.nc;
    std::vector<int64_t> position((size_t)nc);
    for (int64_t k = 0; k < nc; ++k) position[(size_t)root.order[(size_t)k]] = k;
    out.col_store.reserve(W->block_col.size());
    out.val_store.reserve(W->block_val.size());
    out.q_store.resize(3 * (size_t)nc);
    out.mu_store.resize((size_t)nc);
    if (global) out.scale_store.resize(3 * (size_t)nc);
    if (global) out.weight_store.resize((size_t)nc);
    std::vector<std::pair<int64_t, int64_t>> row;  // (new column, block)
    for (int64_t k = 0; k < nc; ++k) {
        const int64_t a = root.order[(size_t)k];
        row.clear();
        for (int64_t b = W->row_ptr[(size_t)a]; b < W->row_ptr[(size_t)a + 1]; ++b)
            row.emplace_back(position[(size_t)W->block_col[(size_t)b]], b);
        std::sort(row.begin(), row.end());
        for (const auto &cb : row) {
            out.col_store.push_back(cb.first);
            out.val_store.insert(out.val_store.end(), W->block_val.begin() + 9 * cb.second,
                                 W->block_val.begin() + 9 * cb.second + 9);
        }
        std::copy(root.q + 3 * a, root.q + 3 * a + 3, out.q_store.begin() + 3 * k);
        out.mu_store[(size_t)k] = root.mu[a];
        if (global) std::copy(root.scale + 3 * a, root.scale + 3 * a + 3, out.scale_store.begin() + 3 * k);
        if (global) out.weight_store[(size_t)k] = root.weight[(size_t)a];
    }
    out.cols = out.col_store.data();
    out.vals = out.val_store.data();
    out.q = out.q_store.data();
    out.mu = out.mu_store.data();
    out.scale = out.scale_store.data();
    out.weight = out.weight_store.data();
}

void rows_to_send(const RootProblem &root, bool permuted, bool global, SentRows &out) {
    const frix_matrix *W = root.W;
    const int64_t nc = root.nc;
    out.q = root.q;
    out.mu = root.mu;
    out.scale = root.scale;
    out.weight = root.weight.data();
    out.lengths.resize((size_t)nc);
    for (int64_t k = 0; k < nc; ++k) {
        const int64_t a = permuted ? root.order[(size_t)k] : k;
        out.lengths[(size_t)k] = W->row_ptr[(size_t)a + 1] - W->row_ptr[(size_t)a];
    }
    if (permuted) {
        permute_rows(root, global, out);
    } else if (nc > 0) {
        out.cols = W->block_col.data();
        out.vals = W->block_val.data();
    }
    out.block_at.assign((size_t)nc + 1, 0);
    for (int64_t k = 0; k < nc; ++k) out.block_at[(size_t)k + 1] = out.block_at[(size_t)k] + out.lengths[(size_t)k];
}

// Each rank's share of what is scattered, and where it starts: rows (and per-contact
// scalars), blocks, block values (9 a block), per-contact vectors (3 a contact).
struct Shares {
    std::vector<int> rows, rows_at, blocks, blocks_at, nine, nine_at, three, three_at;
    explicit Shares(size_t P)
        : rows(P), rows_at(P), blocks(P), blocks_at(P), nine(P), nine_at(P), three(P), three_at(P) {}
    // On the root, from the ranks' runs of contacts (cut) and of blocks (block_at).
    void count(const std::vector<int64_t> &cut, const std::vector<int64_t> &block_at) {
        for (size_t k = 0; k < rows.size(); ++k) {
            const int64_t b0 = block_at[(size_t)cut[k]], b1 = block_at[(size_t)cut[k + 1]];
            rows[k] = checked_count(cut[k + 1] - cut[k]);
            rows_at[k] = checked_count(cut[k]);
            blocks[k] = checked_count(b1 - b0);
            blocks_at[k] = checked_count(b0);
            nine[k] = checked_count(9 * (b1 - b0));
            nine_at[k] = checked_count(9 * b0);
            three[k] = checked_count(3 * (cut[k + 1] - cut[k]));
            three_at[k] = checked_count(3 * cut[k]);
        }
    }
};

// This rank's part as received, and the problem made of it (collective).
frix_error receive_part(frix_mpi_context *ctx, int root, const SentRows &sent, const Shares &shares,
                        const std::vector<int64_t> &order, int64_t first, int64_t owned, bool global, bool permuted,
                        double free, frix_mpi_problem **out, const char *where) {
    int my_blocks = 0;
    check(MPI_Scatter(shares.blocks.data(), 1, MPI_INT, &my_blocks, 1, MPI_INT, root, ctx->comm), "MPI_Scatter");
    std::vector<int64_t> my_lengths((size_t)owned), row_ptr((size_t)owned + 1, 0), block_col((size_t)my_blocks),
        ids((size_t)owned);
    std::vector<double> block_val(9 * (size_t)my_blocks), q(3 * (size_t)owned), mu((size_t)owned),
        w(global ? 3 * (size_t)owned : 0), weight(global ? (size_t)owned : 0);
    const auto scatter = [&](const void *from, const std::vector<int> &counts, const std::vector<int> &at,
                             MPI_Datatype type, void *to, int64_t count) {
        check(MPI_Scatterv(from, counts.data(), at.data(), type, to, checked_count(count), type, root, ctx->comm),
              "MPI_Scatterv");
    };
    scatter(sent.lengths.data(), shares.rows, shares.rows_at, MPI_INT64_T, my_lengths.data(), owned);
    for (int64_t i = 0; i < owned; ++i) row_ptr[(size_t)i + 1] = row_ptr[(size_t)i] + my_lengths[(size_t)i];
    scatter(sent.cols, shares.blocks, shares.blocks_at, MPI_INT64_T, block_col.data(), my_blocks);
    scatter(sent.vals, shares.nine, shares.nine_at, MPI_DOUBLE, block_val.data(), 9 * (int64_t)my_blocks);
    scatter(sent.q, shares.three, shares.three_at, MPI_DOUBLE, q.data(), 3 * owned);
    scatter(sent.mu, shares.rows, shares.rows_at, MPI_DOUBLE, mu.data(), owned);
    if (global) scatter(sent.scale, shares.three, shares.three_at, MPI_DOUBLE, w.data(), 3 * owned);
    if (global) scatter(sent.weight, shares.rows, shares.rows_at, MPI_DOUBLE, weight.data(), owned);
    if (permuted)
        scatter(order.data(), shares.rows, shares.rows_at, MPI_INT64_T, ids.data(), owned);
    else
        for (int64_t i = 0; i < owned; ++i) ids[(size_t)i] = first + i;
    if (frix_error made = make(ctx, first, owned, row_ptr.data(), block_col.data(), block_val.data(), q.data(),
                               mu.data(), global ? w.data() : nullptr, out, where))
        return made;
    (*out)->ids = std::move(ids);
    if (global) (*out)->view.weight = std::move(weight), (*out)->free = free;
    return FRIX_OK;
}

}  // namespace
}  // namespace mpi
}  // namespace frix

extern "C" {

FRIX_API frix_error frix_mpi_problem_local(frix_mpi_context *ctx, int64_t first, int64_t owned, const int64_t *row_ptr,
                                           const int64_t *block_col, const double *block_val, const double *q,
                                           const double *mu, frix_mpi_problem **out) {
    return frix::guard("frix_mpi_problem_local", [&]() -> frix_error {
        using frix::fail;
        if (!ctx) return fail(FRIX_ERR_INVALID_ARGUMENT, "frix_mpi_problem_local: ctx is NULL");
        if (out) *out = nullptr;
        const frix_error e =
            out ? FRIX_OK : fail(FRIX_ERR_INVALID_ARGUMENT, "frix_mpi_problem_local: out is NULL");
        if (frix_error agreed = frix::mpi::agree(ctx->comm, e, "frix_mpi_problem_local")) return agreed;
        return frix::mpi::make(ctx, first, owned, row_ptr, block_col, block_val, q, mu, nullptr, out,
                               "frix_mpi_problem_local");
    });
}

FRIX_API frix_error frix_mpi_problem_scatter(frix_mpi_context *ctx, int root, const frix_problem *problem,
                                             const int *part, frix_mpi_problem **out) {
    return frix::guard("frix_mpi_problem_scatter", [&]() -> frix_error {
        using frix::fail;
        using frix::mpi::check;
        const char *where = "frix_mpi_problem_scatter";
        if (!ctx) return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: ctx is NULL", where);
        if (out) *out = nullptr;
        if (root < 0 || root >= ctx->size)
            return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: root %d is not a rank (0 .. %d)", where, root, ctx->size - 1);
        const bool is_root = ctx->rank == root;
        const size_t P = (size_t)ctx->size;
        frix_error e = FRIX_OK;
        if (!out) e = fail(FRIX_ERR_INVALID_ARGUMENT, "%s: out is NULL", where);
        frix::mpi::RootProblem on_root;
        on_root.cut.assign(P + 1, 0);
        if (!e && is_root) e = frix::mpi::prepare_root(problem, part, ctx->size, on_root, where);
        if (frix_error agreed = frix::mpi::agree(ctx->comm, e, where)) return agreed;
        std::vector<int64_t> &cut = on_root.cut;
        check(MPI_Bcast(cut.data(), (int)P + 1, MPI_INT64_T, root, ctx->comm), "MPI_Bcast");
        int flags[2] = {is_root && on_root.scale ? 1 : 0, is_root && !on_root.order.empty() ? 1 : 0};
        check(MPI_Bcast(flags, 2, MPI_INT, root, ctx->comm), "MPI_Bcast");
        check(MPI_Bcast(&on_root.free, 1, MPI_DOUBLE, root, ctx->comm), "MPI_Bcast");
        const bool global = flags[0] != 0, permuted = flags[1] != 0;
        const int64_t first = cut[(size_t)ctx->rank], owned = cut[(size_t)ctx->rank + 1] - first;
        frix::mpi::SentRows sent;
        frix::mpi::Shares shares(P);
        if (is_root) {
            frix::mpi::rows_to_send(on_root, permuted, global, sent);
            shares.count(cut, sent.block_at);
        }
        return frix::mpi::receive_part(ctx, root, sent, shares, on_root.order, first, owned, global, permuted,
                                       on_root.free, out, where);
    });
}

FRIX_API void frix_mpi_problem_free(frix_mpi_problem *p) { delete p; }

FRIX_API frix_error frix_mpi_problem_get_int(const frix_mpi_problem *p, frix_mpi_key key, int64_t *value) {
    return frix::guard("frix_mpi_problem_get_int", [&]() -> frix_error {
        using frix::fail;
        if (!p || !value) return fail(FRIX_ERR_INVALID_ARGUMENT, "frix_mpi_problem_get_int: p and value are required");
        int64_t messages = 0;
        for (size_t k = 0; k + 1 < p->send_ptr.size(); ++k) messages += p->send_ptr[k + 1] > p->send_ptr[k] ? 1 : 0;
        switch (key) {
            case FRIX_MPI_CONTACTS: *value = p->total; return FRIX_OK;
            case FRIX_MPI_FIRST: *value = p->first; return FRIX_OK;
            case FRIX_MPI_OWNED: *value = p->owned; return FRIX_OK;
            case FRIX_MPI_GHOSTS: *value = (int64_t)p->ghosts.size(); return FRIX_OK;
            case FRIX_MPI_BOUNDARY: *value = (int64_t)p->boundary.size(); return FRIX_OK;
            case FRIX_MPI_NEIGHBOURS: *value = (int64_t)p->neighbours.size(); return FRIX_OK;
            case FRIX_MPI_COLOUR: *value = p->colour; return FRIX_OK;
            case FRIX_MPI_COLOURS: *value = p->colours; return FRIX_OK;
            case FRIX_MPI_MESSAGES_SENT: *value = messages; return FRIX_OK;
            case FRIX_MPI_DOF_FIRST: *value = p->global ? p->global->dof_first : 0; return FRIX_OK;
            case FRIX_MPI_DOFS: *value = p->global ? p->global->dofs : 0; return FRIX_OK;
        }
        return fail(FRIX_ERR_INVALID_ARGUMENT, "frix_mpi_problem_get_int: unknown key %d", (int)key);
    });
}

FRIX_API frix_error frix_mpi_problem_ids(const frix_mpi_problem *p, int64_t *ids) {
    return frix::guard("frix_mpi_problem_ids", [&]() -> frix_error {
        if (!p || (p->owned > 0 && !ids))
            return frix::fail(FRIX_ERR_INVALID_ARGUMENT, "frix_mpi_problem_ids: p and ids are required");
        std::copy(p->ids.begin(), p->ids.end(), ids);
        return FRIX_OK;
    });
}

FRIX_API frix_error frix_mpi_gather(const frix_mpi_problem *p, int root, const double *x_owned, double *x_all) {
    return frix::guard("frix_mpi_gather", [&]() -> frix_error {
        using frix::fail;
        if (!p) return fail(FRIX_ERR_INVALID_ARGUMENT, "frix_mpi_gather: p is NULL");
        const frix_mpi_context &c = *p->ctx;
        frix_error e = FRIX_OK;
        if (root < 0 || root >= c.size)
            e = fail(FRIX_ERR_INVALID_ARGUMENT, "frix_mpi_gather: root %d is not a rank (0 .. %d)", root, c.size - 1);
        else if (p->owned > 0 && !x_owned)
            e = fail(FRIX_ERR_INVALID_ARGUMENT, "frix_mpi_gather: x_owned is NULL");
        else if (c.rank == root && p->total > 0 && !x_all)
            e = fail(FRIX_ERR_INVALID_ARGUMENT, "frix_mpi_gather: x_all is NULL on the root");
        if (frix_error agreed = frix::mpi::agree(c.comm, e, "frix_mpi_gather")) return agreed;
        std::vector<int> counts((size_t)c.size), at((size_t)c.size), id_counts((size_t)c.size), id_at((size_t)c.size);
        for (size_t k = 0; k < (size_t)c.size; ++k) {
            id_counts[k] = frix::mpi::checked_count(p->starts[k + 1] - p->starts[k]);
            id_at[k] = frix::mpi::checked_count(p->starts[k]);
            counts[k] = frix::mpi::checked_count(3 * (p->starts[k + 1] - p->starts[k]));
            at[k] = frix::mpi::checked_count(3 * p->starts[k]);
        }
        // The values in the order of the ranks, then each put back at its contact's index.
        const bool is_root = c.rank == root;
        std::vector<double> values(is_root ? 3 * (size_t)p->total : 0);
        std::vector<int64_t> ids(is_root ? (size_t)p->total : 0);
        frix::mpi::check(MPI_Gatherv(x_owned, (int)(3 * p->owned), MPI_DOUBLE, values.data(), counts.data(), at.data(),
                                     MPI_DOUBLE, root, c.comm),
                         "MPI_Gatherv");
        frix::mpi::check(MPI_Gatherv(p->ids.data(), (int)p->owned, MPI_INT64_T, ids.data(), id_counts.data(),
                                     id_at.data(), MPI_INT64_T, root, c.comm),
                         "MPI_Gatherv");
        for (size_t k = 0; k < ids.size(); ++k)
            for (int i = 0; i < 3; ++i) x_all[3 * ids[k] + i] = values[3 * k + i];
        return FRIX_OK;
    });
}

}  // extern "C"
