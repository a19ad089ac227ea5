#include "nsgs.hpp"

#include <cmath>
#include <cstdio>
#include <utility>

#include "error_state.hpp"
#include "matrix.hpp"
#include "measures.hpp"

namespace frix {
namespace nsgs {

namespace {

// splitmix64: a small, fully specified generator, so a seed gives the same order everywhere.
uint64_t next_random(uint64_t &state) {
    uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

void shuffle(std::vector<int64_t> &order, uint64_t &state) {
    for (size_t i = order.size(); i > 1; --i) {
        const size_t j = (size_t)(next_random(state) % i);
        std::swap(order[i - 1], order[j]);
    }
}

inline bool finite3(const double *x) {
    return std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2]);
}

}  // namespace

Workspace::Workspace(const frix_problem &p, const Settings &s)
    : W_(*p.W), q_(p.q), s_(s), contacts_((size_t)p.nc), rng_(s.seed) {
    for (int64_t a = 0; a < p.nc; ++a) {
        const int64_t d = W_.diag_index[a];
        static const double kZero[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
        local::contact_setup(d >= 0 ? &W_.block_val[9 * d] : kZero, p.mu[a], contacts_[a]);
    }
    if (s_.shuffle != FRIX_SHUFFLE_NONE) {
        order_.resize((size_t)p.nc);
        for (int64_t a = 0; a < p.nc; ++a) order_[a] = a;
        if (s_.shuffle == FRIX_SHUFFLE_ONCE) shuffle(order_, rng_);
    }
}

Settings settings_from(const frix_options &o) {
    Settings s;
    s.local.solver = (int)o.i(FRIX_OPT_LOCAL_SOLVER);
    s.local.tol = o.d(FRIX_OPT_LOCAL_TOLERANCE);
    s.local.max_iter = (int)o.i(FRIX_OPT_LOCAL_MAX_ITER);
    s.relaxation = o.d(FRIX_OPT_RELAXATION);
    s.shuffle = (int)o.i(FRIX_OPT_SHUFFLE);
    s.seed = (uint64_t)o.i(FRIX_OPT_SEED);
    return s;
}

SweepStats Workspace::sweep(double *r) {
    SweepStats st;
    if (s_.shuffle == FRIX_SHUFFLE_EACH_SWEEP) shuffle(order_, rng_);
    const int64_t nc = (int64_t)contacts_.size();
    const int64_t *row_ptr = W_.row_ptr.data();
    const int64_t *col = W_.block_col.data();
    const int64_t *diag = W_.diag_index.data();
    const double *val = W_.block_val.data();
    const int64_t *order = order_.empty() ? nullptr : order_.data();
    const double omega = s_.relaxation;
    for (int64_t k = 0; k < nc; ++k) {
        const int64_t a = order ? order[k] : k;
        // Local q: q_a + sum_{b != a} W_ab r_b, in one pass over the block row that steps
        // over the diagonal block instead of subtracting it (no cancellation).
        double ql[3] = {q_[3 * a], q_[3 * a + 1], q_[3 * a + 2]};
        const int64_t beg = row_ptr[a], end = row_ptr[a + 1], d = diag[a];
        const int64_t mid = d >= 0 ? d : end;
        for (int64_t b = beg; b < mid; ++b) block_gemv_add(val + 9 * b, r + 3 * col[b], ql);
        for (int64_t b = d >= 0 ? d + 1 : end; b < end; ++b)
            block_gemv_add(val + 9 * b, r + 3 * col[b], ql);

        double *ra = r + 3 * a;
        double rn[3] = {ra[0], ra[1], ra[2]};
        const local::Outcome out = local::solve_contact(contacts_[a], ql, rn, s_.local);
        if (out == local::Outcome::NotConverged || out == local::Outcome::NoSolution) ++st.unsolved;
        if (omega != 1.0) {
            for (int i = 0; i < 3; ++i) rn[i] = omega * rn[i] + (1.0 - omega) * ra[i];
            if (omega > 1.0) local::project_on_cone(rn, contacts_[a].mu);
        }
        if (!finite3(rn)) {
            ++st.rejected;
        } else {
            const double d0 = rn[0] - ra[0], d1 = rn[1] - ra[1], d2 = rn[2] - ra[2];
            st.dr2 += d0 * d0 + d1 * d1 + d2 * d2;
            ra[0] = rn[0];
            ra[1] = rn[1];
            ra[2] = rn[2];
        }
        st.r2 += ra[0] * ra[0] + ra[1] * ra[1] + ra[2] * ra[2];
    }
    return st;
}

namespace {

// A full check also runs every kFullCheckPeriod sweeps: on rank-deficient W, r may keep
// drifting along the null space (large light error) while u, and the error, have converged.
// Every full check recalibrates the light tolerance, down or up.
constexpr int64_t kFullCheckPeriod = 16;

frix_error solve(SolveContext &ctx) {
    const frix_problem &p = ctx.problem;
    const frix_options &o = ctx.options;
    if (!p.W || !p.W->block)
        return fail(FRIX_ERR_INTERNAL, "nsgs: W is not stored as 3x3 blocks");

    const Settings s = settings_from(o);
    const double tol = o.d(FRIX_OPT_TOLERANCE);
    const int64_t max_iter = o.i(FRIX_OPT_MAX_ITER);
    const double time_limit = o.d(FRIX_OPT_TIME_LIMIT);
    const int64_t verbosity = o.i(FRIX_OPT_VERBOSITY);
    const int64_t measure = o.i(FRIX_OPT_ERROR_MEASURE);

    Workspace ws(p, s);
    double *r = ctx.r;
    frix_info &info = ctx.info;
    auto full_error = [&]() { return selected_error(local_measures(p, r, ctx.u), measure); };

    // A warm start that already solves the problem costs one product, not a sweep.
    bool warm = false;
    for (int64_t i = 0; i < 3 * p.nc && !warm; ++i) warm = r[i] != 0.0;
    if (warm) {
        const double e = full_error();
        if (e <= tol) {
            info.status = FRIX_STATUS_CONVERGED;
            info.iterations = 0;
            return FRIX_OK;
        }
    }

    double tol_light = tol;
    int64_t it = 0;
    info.status = FRIX_STATUS_MAX_ITER;
    bool checked_last = false;  // whether the last sweep ended with a full check
    double last_full = NAN;
    while (it < max_iter) {
        const SweepStats st = ws.sweep(r);
        ++it;
        if (!std::isfinite(st.r2)) {
            info.status = FRIX_STATUS_DIVERGED;
            break;
        }
        const double light = st.r2 > 0.0 ? std::sqrt(st.dr2 / st.r2) : std::sqrt(st.dr2);
        double estimate = light;
        checked_last = false;
        if (light <= tol_light || it % kFullCheckPeriod == 0) {
            const double e = full_error();
            checked_last = true;
            last_full = estimate = e;
            if (e <= tol) {
                info.status = FRIX_STATUS_CONVERGED;
            } else if (!std::isfinite(e)) {
                info.status = FRIX_STATUS_DIVERGED;
            } else if (st.dr2 == 0.0) {
                info.status = FRIX_STATUS_STAGNATED;  // r is a fixed point of the sweep
            } else {
                // LIGHT_WITH_FULL_FINAL: the light error that should mean full error = tol.
                tol_light = light / e * tol;
            }
        }
        if (verbosity >= 2 || (verbosity >= 1 && checked_last))
            std::fprintf(stderr, "nsgs: sweep %lld light %.3e%s%.3e rejected %lld unsolved %lld\n",
                         (long long)it, light, checked_last ? " full " : " tol_light ",
                         checked_last ? last_full : tol_light, (long long)st.rejected,
                         (long long)st.unsolved);
        // The callback sees every sweep, the last one too; it can only stop a running solve.
        const bool stop = o.callback && o.callback(o.callback_data, it, estimate, ctx.clock.seconds()) != 0;
        if (info.status != FRIX_STATUS_MAX_ITER) break;
        if (stop) {
            info.status = FRIX_STATUS_STOPPED_BY_CALLBACK;
            break;
        }
        if (time_limit > 0.0 && ctx.clock.seconds() >= time_limit) {
            info.status = FRIX_STATUS_TIME_LIMIT;
            break;
        }
    }
    // The iteration limit may fall between two full checks.
    if (info.status == FRIX_STATUS_MAX_ITER && !checked_last && full_error() <= tol)
        info.status = FRIX_STATUS_CONVERGED;
    info.iterations = it;
    if (verbosity >= 1)
        std::fprintf(stderr, "nsgs: %s after %lld sweeps\n",
                     frix_status_string(info.status), (long long)it);
    return FRIX_OK;
}

const frix_option_key kExtraKeys[] = {FRIX_OPT_LOCAL_SOLVER, FRIX_OPT_LOCAL_TOLERANCE,
                                      FRIX_OPT_LOCAL_MAX_ITER, FRIX_OPT_RELAXATION,
                                      FRIX_OPT_SHUFFLE, FRIX_OPT_SEED, (frix_option_key)0};

// The sweep limit covers the slowest FCLIB problems that NSGS solves at 1e-8 (Capsules:
// ~8000 sweeps).
const OptionDefault kDefaults[] = {
    {FRIX_OPT_MAX_ITER, 20000},
    {FRIX_OPT_LOCAL_SOLVER, local::kClosedForm},
    {FRIX_OPT_LOCAL_TOLERANCE, 1e-12},
    {FRIX_OPT_LOCAL_MAX_ITER, 20},
    {(frix_option_key)0, 0}};

}  // namespace
}  // namespace nsgs

const SolverEntry kNsgsEntry = {
    FRIX_SOLVER_NSGS,
    "nsgs",
    "FRICTION_3D_NSGS",
    "Nonsmooth Gauss-Seidel: sweeps over the contacts, each solved with the others held "
    "fixed (local q = q_a + sum_{b!=a} W_ab r_b, one pass over W's blocks per sweep). The "
    "default one-contact solver (562) is exact for take-off, stick and, through the root "
    "of the sliding-angle equation, slide; projected steps with a self-adaptive step finish "
    "the rare contacts where that fails (553: those projected steps alone, after the exact "
    "take-off and stick cases; 552: one projected step only). Cheap per sweep and "
    "robust, it is the method of choice for rigid multibody scenes; convergence is linear and "
    "slows on rank-deficient W at tight tolerances. Stops on the light error |dr|/|r| "
    "confirmed by the full error (Siconos LIGHT_WITH_FULL_FINAL). Options: local_solver, "
    "local_tolerance, local_max_iter, relaxation (omega, projected back on the cone when > "
    "1; omega = 0.9 breaks the limit cycles plain Gauss-Seidel falls into on some rigid "
    "scenes), "
    "shuffle (none, once, each sweep) and seed.",
    nsgs::solve,
    true,
    false,
    nsgs::kExtraKeys,
    nsgs::kDefaults,
};

}  // namespace frix
