// nsgs-v's active part (sweep_active_part, sweeps.hpp): in a persistent solve on a large dense
// W, the sweeps first run on the contacts in touch, with their own W_SS kept between solves,
// so that a push reads only their rows; the whole problem's run then measures the answer.
#include <algorithm>
#include <memory>
#include <utility>
#include <vector>

#include "solvers/kit/sweeps.hpp"
#include "src/info.hpp"
#include "src/log.hpp"
#include "src/measures.hpp"
#include "src/monitor.hpp"
#include "src/vec.hpp"

namespace frix {
namespace nsgs {

namespace {

// The part: the contacts closed at the warm start (r_a != 0, or u_aN <= 0) and the open ones
// nearest to closing, with W_SS (and its single-precision columns) kept between solves. While
// the others keep r = 0, u_S = W_SS r_S + q_S exactly.
struct ActivePart : CachedState {
    std::vector<int64_t> contacts;  // S, increasing
    frix_matrix W;                  // W_SS, every block stored
    uint64_t w_values = 0, w_pattern = 0;
    int64_t threads = 0;  // the panels its columns were cut for
    SingleColumns columns;
    std::vector<double> q, mu, r, u;
};
// Not a solver id: the part is nsgs-v's second state in a cache (SolveCache's keys).
constexpr int kActivePartKey = -FRIX_SOLVER_NSGS_VELOCITY;
// The part is taken where at least this share of the contacts is open: fewer leave too
// little of each push out to pay for the part's own checks.
constexpr double kMinOpenShare = 0.25;
// The open contacts nearest to closing taken into a new part (a share of the open ones), and
// how much larger than a new part a kept one may be: a load path's next steps close some of
// them, and the part is then kept rather than built again.
constexpr double kMarginShare = 0.1, kMaxKeptExcess = 0.25;
// A part's bytes a block: W_SS's values and block index, and the single-precision copy.
constexpr double kPartBytesPerBlock = 72.0 + 8.0 + 36.0;

}  // namespace

bool sweep_active_part(SolveContext &ctx, double single_min_bytes, Measures &start, int64_t *sweeps,
                       frix_status *status) {
    const frix_problem &p = ctx.problem;
    const frix_matrix &W = *p.W;
    const int64_t nc = p.nc;
    if (!ctx.cache || !SingleColumns::suits(W, single_min_bytes) || vec::all_zero(ctx.r, 3 * nc)) return false;
    Kept<ActivePart> part(ctx.cache, kActivePartKey);
    // A part of an earlier W is dropped (not given back); a current one is kept for later.
    const bool current = part.reused() && part->w_values == ctx.cache->w_values &&
                         part->w_pattern == ctx.cache->w_pattern;
    if (current) part.keep();
    // The warm start's u = W r + q and its measures, which the whole run then takes: a start
    // that already meets the tolerance is left to it.
    if (!ctx.measured_start) {
        start = local_measures(p, ctx.r, ctx.u);
        ctx.measured_start = &start;
    }
    const Monitor monitor(ctx);
    if (selected_error(*ctx.measured_start, ctx.options.i(FRIX_OPT_ERROR_MEASURE)) <= monitor.tolerance()) return false;
    std::vector<uint8_t> in_part((size_t)nc, 0);
    std::vector<std::pair<double, int64_t>> open;
    int64_t closed = 0;
    for (int64_t a = 0; a < nc; ++a) {
        if (!vec::all_zero(ctx.r + 3 * a, 3) || !(ctx.u[3 * a] > 0.0)) in_part[(size_t)a] = 1, ++closed;
        else open.emplace_back(ctx.u[3 * a], a);
    }
    if (closed == 0 || (double)open.size() < kMinOpenShare * (double)nc) return false;
    std::vector<int64_t> &S = part->contacts;
    const int64_t threads = std::max<int64_t>(1, ctx.options.i(FRIX_OPT_THREADS));
    const size_t margin = (size_t)(kMarginShare * (double)open.size());
    bool reuse = current && part->threads == threads &&
                 (double)S.size() <= (1.0 + kMaxKeptExcess) * (double)((size_t)closed + margin);
    if (reuse) {
        std::vector<uint8_t> held((size_t)nc, 0);
        for (int64_t a : S) held[(size_t)a] = 1;
        for (int64_t a = 0; a < nc && reuse; ++a) reuse = !in_part[(size_t)a] || held[(size_t)a];
    }
    if (!reuse) {
        std::sort(open.begin(), open.end());
        for (size_t k = 0; k < margin; ++k) in_part[(size_t)open[k].second] = 1;
        std::vector<int64_t> chosen;
        for (int64_t a = 0; a < nc; ++a)
            if (in_part[(size_t)a]) chosen.push_back(a);
        // The memory the part adds to what it holds already (its storage is reused).
        const double ns = (double)chosen.size(), held = 8.0 * (double)(part->W.block_val.capacity() +
                                                                      part->W.block_col.capacity());
        if (!monitor.fits_memory(std::max(0.0, kPartBytesPerBlock * ns * ns - held))) return false;
        part->w_values = 0;  // a part half rebuilt is not current
        S = std::move(chosen);
        dense_restriction(W, S, part->W);
        part->columns.build(part->W, 0, 0, threads);
        part->w_values = ctx.cache->w_values;
        part->w_pattern = ctx.cache->w_pattern;
        part->threads = threads;
        part.keep();
    }
    const int64_t ns = (int64_t)S.size();
    part->q.resize((size_t)(3 * ns));
    part->mu.resize((size_t)ns);
    part->r.resize((size_t)(3 * ns));
    part->u.resize((size_t)(3 * ns));
    for (int64_t i = 0; i < ns; ++i) {
        const int64_t a = S[(size_t)i];
        part->mu[(size_t)i] = p.mu[a];
        std::copy_n(p.q + 3 * a, 3, &part->q[(size_t)(3 * i)]);
        std::copy_n(ctx.r + 3 * a, 3, &part->r[(size_t)(3 * i)]);
    }
    frix_problem *sub = nullptr;
    if (make_local_problem(&part->W, part->q.data(), part->mu.data(), ns, &sub)) return false;
    const std::unique_ptr<frix_problem> sub_owner(sub);
    // Measured as the whole problem is: its contacts' weights, not W_SS's own.
    if (!p.weight.empty())
        for (int64_t i = 0; i < ns; ++i) sub->weight[(size_t)i] = p.weight[(size_t)S[(size_t)i]];
    // The part's errors are its own problem's: the caller's callback takes them as estimates.
    ForwardedReports reports{&ctx.options, &ctx.clock, 0, true};
    const frix_options part_options = reports.applied_to(ctx.options);
    frix_info info;
    SolveContext part_ctx =
        SolveContext::local(*sub, part_options, part->r.data(), part->u.data(), info, ctx.clock);
    part_ctx.runaway_bound = ctx.runaway_bound;
    part_ctx.return_best = ctx.return_best;
    if (run_velocity_sweeps(part_ctx, &part->columns, "nsgs-v (active part)") != FRIX_OK) return false;
    for (int64_t i = 0; i < ns; ++i) std::copy_n(&part->r[(size_t)(3 * i)], 3, ctx.r + 3 * S[(size_t)i]);
    ctx.measured_start = nullptr;  // r moved
    ctx.info.ran_away = ctx.info.ran_away || info.ran_away;
    *sweeps = info.iterations;
    *status = info.status;
    if (ctx.options.i(FRIX_OPT_VERBOSITY) >= 1)
        log_line(&ctx.options, "nsgs-v: active part, %lld of %lld contacts (%s): %s after %lld sweeps", (long long)ns,
                 (long long)nc, reuse ? "kept" : "built", frix_status_string(info.status), (long long)info.iterations);
    return true;
}

}  // namespace nsgs
}  // namespace frix
