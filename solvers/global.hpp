// Global problems (M, H, f, w, mu): M v = H r + f, u = H^T v + w. Two routes:
//  - reduction (any local solver): W = H^T M^-1 H and q = H^T M^-1 f + w formed sparse with
//    CHOLMOD (UMFPACK when M is not symmetric positive definite), the local problem solved,
//    and v = M^-1 (H r + f) recovered;
//  - id 607: semismooth Newton on (v, r) itself with UMFPACK, which never forms W.
#pragma once

#include "auto_analysis.hpp"
#include "solver_api.hpp"

namespace frix {

extern const SolverEntry kGlobalNsnAcEntry;

// The driver's global path (src/solve.cpp): runs `entry` natively if it solves global
// problems, through the reduction otherwise. r, u (3nc) and v (n) as in frix_solve.
frix_error solve_global_problem(const frix_problem &p, const frix_options &opts,
                                const SolverEntry &entry, double *r, double *u, double *v,
                                frix_info &info, const Stopwatch &clock,
                                frix_error (*solve_local)(const frix_problem &, const frix_options &,
                                                          const SolverEntry &, double *, double *,
                                                          frix_info &, const Stopwatch &));

// Whether W = H^T M^-1 H would fit in memory: its 3x3 blocks (the structural bound of
// reduction_size) at 80 bytes each, against the memory this process may use (the machine's,
// or its control group's limit where lower). A deformable body makes W dense: on a large mesh
// it would not fit, and the system would kill the process part-way through forming it. A
// floor: forming W also holds Z = L^-1 P H and its transpose for a while (the 80x80x3 elastic
// grid: 3.3 GB by this count, 3.8 GB measured).
struct ReductionMemory {
    double needed = 0.0;     // bytes, at least
    double available = 0.0;  // bytes; 0 when unknown (then it fits)
    bool fits = true;
};
ReductionMemory reduction_memory(const autosolve::ReductionSize &size);

// Whether a global solve's measures meet `tol`: the error and the equilibrium residual both
// (the latter at least to 1e-12, which is rounding for M v = H r + f).
bool meets_global_tolerance(const frix_info &info, double tol);

}  // namespace frix
