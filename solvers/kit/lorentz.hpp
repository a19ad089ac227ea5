// The building blocks of the interior-point solvers (ipm.cpp, ipm_anm.cpp): per
// contact a pair of Lorentz-cone vectors, L = {(t, x): |x| <= t}, the sparse system
// (W + D) dr = g left once u and the cone unknowns are eliminated contact by contact, and the
// rules of a run (lorentz.cpp): its start's scales, its stops, and Newton's finish.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "solvers/kit/newton.hpp"
#include "src/linalg/linalg.hpp"
#include "src/matrix.hpp"
#include "src/solve_cache.hpp"
#include "src/solver_api.hpp"

namespace frix {
namespace lorentz {

inline double jnorm2(const double *x) { return x[0] * x[0] - x[1] * x[1] - x[2] * x[2]; }

// Largest a > 0 with x + a dx in L (x in int L); +inf if the ray stays inside.
inline double max_step_lorentz(const double *x, const double *dx) {
    double amax = dx[0] < 0.0 ? -x[0] / dx[0] : INFINITY;
    const double a2 = jnorm2(dx), a1 = 2.0 * (x[0] * dx[0] - x[1] * dx[1] - x[2] * dx[2]);
    const double a0 = jnorm2(x);
    if (a2 == 0.0) {
        if (a1 < 0.0) amax = std::min(amax, -a0 / a1);
        return amax;
    }
    const double disc = a1 * a1 - 4.0 * a2 * a0;
    if (disc < 0.0) return amax;
    const double sq = std::sqrt(disc);
    double t1 = (-a1 - sq) / (2.0 * a2), t2 = (-a1 + sq) / (2.0 * a2);
    if (t1 > t2) std::swap(t1, t2);
    // a2 < 0: the quadratic is negative outside [t1, t2] (0 inside); a2 > 0: inside (t1, t2).
    if (a2 < 0.0) {
        if (t2 > 0.0) amax = std::min(amax, t2);
    } else if (t1 > 0.0) {
        amax = std::min(amax, t1);
    }
    return amax;
}

inline void mul3(const double *A, const double *x, double *y) {  // row-major A
    for (int i = 0; i < 3; ++i) y[i] = A[3 * i] * x[0] + A[3 * i + 1] * x[1] + A[3 * i + 2] * x[2];
}

// Jordan product of L: x∘y = (x.y, x0 y1 + y0 x1).
inline void jordan(const double *x, const double *y, double *z) {
    z[0] = x[0] * y[0] + x[1] * y[1] + x[2] * y[2];
    z[1] = x[0] * y[1] + y[0] * x[1];
    z[2] = x[0] * y[2] + y[0] * x[2];
}

// t with l∘t = c (l in int L).
inline void jordan_solve(const double *l, const double *c, double *t) {
    const double det = l[0] * l[0] - l[1] * l[1] - l[2] * l[2];
    t[0] = (l[0] * c[0] - l[1] * c[1] - l[2] * c[2]) / det;
    t[1] = (c[1] - t[0] * l[1]) / l[0];
    t[2] = (c[2] - t[0] * l[2]) / l[0];
}

// CSC pattern of W + block diagonal, with, for every entry, where its W value comes from
// (an index into W's block values; kZero for a diagonal entry W does not store) and, for the
// diagonal blocks, the position of each of the 9 entries. The tangential rows of frictionless
// contacts are the identity rows of dr_T = 0: their entries are kZero or kOne, whatever W has.
struct SystemPattern {
    static constexpr int64_t kZero = -1, kOne = -2;
    std::vector<int64_t> colptr, rowind, w_source, diag_pos;  // diag_pos: 9 per contact
    void build(const frix_matrix &W, const double *mu, int64_t nc) {
        const int64_t m = 3 * nc;
        std::vector<std::vector<std::pair<int64_t, int64_t>>> cols(m);  // (row, source)
        for (int64_t a = 0; a < nc; ++a) {
            if (W.diag_index[a] < 0)
                for (int j = 0; j < 3; ++j)
                    for (int i = 0; i < 3; ++i) cols[3 * a + j].push_back({3 * a + i, kZero});
            for (int64_t b = W.row_ptr[a]; b < W.row_ptr[a + 1]; ++b) {
                const int64_t c = W.block_col[b];
                for (int j = 0; j < 3; ++j)
                    for (int i = 0; i < 3; ++i)  // block values are column-major
                        cols[3 * c + j].push_back({3 * a + i, 9 * b + i + 3 * j});
            }
        }
        colptr.assign(m + 1, 0);
        rowind.clear();
        w_source.clear();
        diag_pos.assign(9 * nc, -1);
        for (int64_t j = 0; j < m; ++j) {
            std::sort(cols[j].begin(), cols[j].end());
            for (const auto &e : cols[j]) {
                const int64_t a = j / 3;
                if (e.first / 3 == a) diag_pos[9 * a + 3 * (e.first % 3) + j % 3] = (int64_t)rowind.size();
                rowind.push_back(e.first);
                const bool fixed_row = e.first % 3 != 0 && !(mu[e.first / 3] > 0.0);
                w_source.push_back(fixed_row ? (e.first == j ? kOne : kZero) : e.second);
            }
            colptr[j + 1] = (int64_t)rowind.size();
        }
    }
    // The values of W + D in this pattern (D: 9 row-major entries per contact). D's
    // tangential rows are zero on frictionless contacts: their identity rows stay.
    void assemble(const frix_matrix &W, const double *D, std::vector<double> &values) const {
        const int64_t nnz = (int64_t)rowind.size(), nc = (int64_t)diag_pos.size() / 9;
        values.resize(nnz);
        for (int64_t k = 0; k < nnz; ++k) {
            const int64_t src = w_source[k];
            values[k] = src >= 0 ? W.block_val[src] : src == kOne ? 1.0 : 0.0;
        }
        for (int64_t a = 0; a < nc; ++a)
            for (int i = 0; i < 9; ++i) values[diag_pos[9 * a + i]] += D[9 * a + i];
    }
};

// What a persistent interior-point solver keeps (solve_cache.hpp): the system's pattern and
// its symbolic analysis, valid while W's pattern and the set of frictionless contacts stay;
// and the Newton engine that finishes a run.
struct KeptSystem : CachedState {
    SystemPattern pat;
    linalg::SparseLU lu;
    bool analysed = false;
    uint64_t w_pattern = 0;
    std::vector<char> frictionless;  // per contact, of the pattern
    newton::KeptEngine polish;
    // Builds the pattern afresh (and forgets the analysis) unless the kept one fits.
    void refresh(const SolveCache *cache, const frix_matrix &W, const double *mu, int64_t nc) {
        std::vector<char> now(nc);
        for (int64_t a = 0; a < nc; ++a) now[a] = !(mu[a] > 0.0);
        const uint64_t pattern = cache ? cache->w_pattern : 0;
        if (cache && analysed && w_pattern == pattern && frictionless == now) return;
        pat.build(W, mu, nc);
        analysed = false;
        w_pattern = pattern;
        frictionless = std::move(now);
    }
};

// The scales of an interior start: |q|_inf for velocities (1 if q = 0), that over the mean
// |W_NN| for forces.
struct StartScales {
    double force = 1.0, velocity = 1.0;
};
StartScales start_scales(const frix_problem &p);

// The rules an interior-point run checks before each of its iterations, and its end. An
// interior point cannot start from the warm start: that is the best iterate until a better
// one is seen, and the answer at once if it meets the tolerance. The run hands over to Newton
// (Alart-Curnier, spectral rho) from its best iterate when its error has not halved for
// `stall_after` iterations, or when the solver says so; iterations count its own, then
// Newton's steps.
class Run {
   public:
    enum Next { kIterate, kStop, kHandOver };
    // Also refreshes the kept system for this problem and gives its LU the solve's limits.
    Run(SolveContext &ctx, KeptSystem &kept, int stall_after);
    // Measures r (3 per contact) and keeps it if it is the best so far; then whether to
    // iterate, to stop (converged, the callback or a runaway of r, max_iter, the time limit:
    // the status is in ctx.info) or to hand over to Newton.
    Next check(const double *r);
    void count_iteration() { ++steps_.done; }
    int64_t iterations() const { return steps_.done; }
    double best_error() const { return best_err_; }
    double last_error() const { return last_err_; }  // of the r check() measured last
    // The best iterate into ctx.r, Newton from it when `hand_over`, and the run's counters
    // (iterations, Newton's steps, the factorisations of the kept LU and Newton's) in ctx.info.
    frix_error end(bool hand_over);
    int64_t newton_steps() const { return newton_steps_; }

   private:
    SolveContext &ctx_;
    KeptSystem &kept_;
    const int stall_after_;
    const double tol_;
    const int64_t measure_;
    int64_t newton_steps_ = 0;
    kit::Steps steps_;  // the run's iterations, then Newton's
    linalg::FactorStats stats_before_;
    std::vector<double> best_;
    double best_err_, last_err_ = INFINITY, ref_err_ = INFINITY;
    int since_progress_ = 0;
};

}  // namespace lorentz
}  // namespace frix
