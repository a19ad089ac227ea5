// Route (a) on the contacts the free motion presses (pressed_reduction.hpp). On a deformable
// body W = H^T M^-1 H is dense, and forming it costs more than anything else of a one-shot
// solve; the contacts the free motion leaves open mostly stay open. Their rows of W are only
// needed to prove that: u = H^T v + w from the answer's v does it for all of them at once.
#include "pressed_reduction.hpp"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "log.hpp"
#include "measures.hpp"
#include "monitor.hpp"
#include "reduction.hpp"
#include "vec.hpp"

namespace frix {

namespace {

// W's bytes from which its contacts are pressed first: below, forming all of W costs too little
// to be worth a second round (figures: notes/2026-11-30-pressed-contacts-first.md).
constexpr double kMinWBytes = 32.0 * 1024.0 * 1024.0;
// The share of the contacts up to which the route applies: W's part costs the square of it.
constexpr double kMaxShare = 0.8;
// Rounds at most: each forms the part's W again.
constexpr int kMaxRounds = 3;

// The columns of H (a CSC copy) of the contacts `in`, three each, as a general CSC matrix.
frix_matrix columns_of(const Csc &h, const std::vector<int64_t> &in) {
    frix_matrix out;
    out.rows = h.rows;
    out.cols = 3 * (int64_t)in.size();
    out.col_ptr.assign(1, 0);
    for (int64_t a : in)
        for (int64_t j = 3 * a; j < 3 * a + 3; ++j) {
            out.row_ind.insert(out.row_ind.end(), h.rowind.begin() + h.colptr[j], h.rowind.begin() + h.colptr[j + 1]);
            out.val.insert(out.val.end(), h.val.begin() + h.colptr[j], h.val.begin() + h.colptr[j + 1]);
            out.col_ptr.push_back((int64_t)out.row_ind.size());
        }
    return out;
}

// x's entries of the contacts `in`, three each.
std::vector<double> entries_of(const double *x, const std::vector<int64_t> &in) {
    std::vector<double> out;
    out.reserve(3 * in.size());
    for (int64_t a : in) out.insert(out.end(), x + 3 * a, x + 3 * a + 3);
    return out;
}

}  // namespace

frix_error solve_pressed_first(const frix_problem &p, const frix_options &opts, const double *q,
                               const ReductionSize &bound,
                               double *r, double *u, double *v, frix_info &info, const Stopwatch &clock,
                               const ReducedRoute &reduce, PressedFirst *outcome) {
    *outcome = PressedFirst::kNotApplied;
    const int64_t nc = p.nc;
    if (p.kind != FRIX_PROBLEM_GLOBAL || nc == 0 || kBytesPerReducedBlock * bound.w_blocks < kMinWBytes)
        return FRIX_OK;
    std::vector<char> in_part((size_t)nc, 0);
    int64_t count = 0;
    for (int64_t a = 0; a < nc; ++a)
        if (q[3 * a] < 0.0 || !vec::all_zero(r + 3 * a, 3)) in_part[(size_t)a] = 1, ++count;
    if (count == 0 || (double)count > kMaxShare * (double)nc) return FRIX_OK;
    // The bound on W may be nc^2 blocks unexamined: its structure decides (rigid bodies' W is
    // sparse, and cheap to form whole), and bounds each part's W.
    const double structural_blocks = bound.structural ? bound.w_blocks : reduction_size(p).w_blocks;
    if (kBytesPerReducedBlock * structural_blocks < kMinWBytes) return FRIX_OK;
    Csc h;
    if (frix_error e = to_csc(*p.H, h)) return e;
    const Monitor monitor(opts, clock);
    const double tol = monitor.tolerance();
    const int64_t max_iter = opts.i(FRIX_OPT_MAX_ITER), measure = opts.i(FRIX_OPT_ERROR_MEASURE);
    // The whole problem's error at the start of a round, for the callback's report before its W
    // is formed (NaN: not known; a warm r's velocity is not v = M^-1 f, the driver's).
    double start_error = NAN;
    if (opts.has_callback() && vec::all_zero(r, 3 * nc))
        start_error = selected_error(global_measures(p, r, v, u, nullptr), measure);
    frix_info so_far;  // the rounds so far
    for (int round = 0; round < kMaxRounds; ++round) {
        if (!std::isnan(start_error) && monitor.report(so_far.iterations, start_error)) {
            so_far.status = FRIX_STATUS_STOPPED_BY_CALLBACK;
            break;
        }
        std::vector<int64_t> part_contacts;
        for (int64_t a = 0; a < nc; ++a)
            if (in_part[(size_t)a]) part_contacts.push_back(a);
        if (opts.i(FRIX_OPT_VERBOSITY) >= 1)
            log_line(&opts, "reduction: W for the %lld of %lld contacts pressed at the start%s",
                     (long long)part_contacts.size(), (long long)nc,
                     round > 0 ? " or penetrating at the last answer" : "");
        // The part: p's M and f, its contacts' H, w and mu, measured with p's weights.
        const frix_matrix part_h = columns_of(h, part_contacts);
        std::vector<double> part_w = entries_of(p.w, part_contacts), part_q = entries_of(q, part_contacts);
        std::vector<double> part_r = entries_of(r, part_contacts), part_mu, part_u(3 * part_contacts.size(), 0.0);
        frix_problem part;
        part.kind = p.kind;
        part.nc = (int64_t)part_contacts.size();
        part.n = p.n;
        part.M = p.M;
        part.H = &part_h;
        part.f = p.f;
        part.w = part_w.data();
        for (int64_t a : part_contacts)
            part_mu.push_back(p.mu[a]), part.weight.push_back(p.weight.empty() ? 1.0 : p.weight[(size_t)a]);
        part.mu = part_mu.data();
        part.dof_weight = p.dof_weight;
        part.load_weight = p.load_weight;
        // The part's iterations and callback reports follow on from the rounds before it; its
        // errors are the part's, estimates of the whole problem's.
        frix_options part_options = opts;
        part_options.ivalue[FRIX_OPT_MAX_ITER] = max_iter - so_far.iterations;
        ForwardedReports forward{&opts, &clock, so_far.iterations, true};
        part_options = forward.applied_to(part_options);
        frix_info round_run = info.next_run();
        // W's blocks: the part's square, within the bound on the whole W.
        const double part_blocks = std::min(structural_blocks, (double)part.nc * (double)part.nc);
        if (frix_error e = reduce(part, part_options, part_blocks, part_q.data(), part_r.data(), part_u.data(), v,
                                  round_run))
            return e;
        // r stays 0 on the others: a contact with r != 0 is in the part from the start.
        for (size_t k = 0; k < part_contacts.size(); ++k)
            std::copy(&part_r[3 * k], &part_r[3 * k] + 3, r + 3 * part_contacts[k]);
        if (round > 0) round_run.absorb(so_far);
        so_far = std::move(round_run);
        // The whole problem's measure of the answer (u for every contact, the others' from v)
        // decides: contacts outside the part with r = 0 and u_N >= 0 add nothing to it. An
        // answer within it converged, whatever the part's stricter scale said.
        const double error = selected_error(global_measures(p, r, v, u, nullptr), measure);
        const frix_status status = so_far.status;
        if (error <= tol && (status == FRIX_STATUS_MAX_ITER || status == FRIX_STATUS_STAGNATED))
            so_far.status = FRIX_STATUS_CONVERGED;
        if (so_far.status != FRIX_STATUS_CONVERGED || error <= tol) break;  // stopped or short: the driver measures
        if (so_far.iterations >= max_iter) {
            so_far.status = FRIX_STATUS_MAX_ITER;
            break;
        }
        if (monitor.out_of_time()) {
            so_far.status = FRIX_STATUS_TIME_LIMIT;
            break;
        }
        int64_t penetrating = 0;
        for (int64_t a = 0; a < nc; ++a)
            if (!in_part[(size_t)a] && u[3 * a] < 0.0) in_part[(size_t)a] = 1, ++penetrating;
        if (penetrating == 0) break;
        count += penetrating;
        if ((double)count > kMaxShare * (double)nc || round + 1 == kMaxRounds) {
            info = std::move(so_far);
            *outcome = PressedFirst::kWholeNext;
            return FRIX_OK;
        }
        start_error = error;
    }
    info = std::move(so_far);
    *outcome = PressedFirst::kAnswered;
    return FRIX_OK;
}

}  // namespace frix
