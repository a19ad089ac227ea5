// The internal interface between the solve driver (src/solve.cpp, src/solve_global.cpp), the
// registry (solvers/registry.cpp, which defines find_solver and its kin) and the solver
// families (solvers/*.cpp). The core includes no solver: it finds them through the registry.
#pragma once

#include <frix/frix_solve.h>

#include <chrono>
#include <cstdint>
#include <functional>
#include <mutex>
#include <vector>

#include "info.hpp"
#include "measures.hpp"
#include "options.hpp"
#include "problem.hpp"
#include "solve_cache.hpp"

namespace frix {

class MassSolver;

// A solve's clock, shared by its stages (and their threads).
class Stopwatch {
   public:
    Stopwatch() : start_(std::chrono::steady_clock::now()) {}
    double seconds() const {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    }
    // Flops per second of a dense LU factorisation on this machine, the fastest of a few
    // measured on first use (milliseconds; never without a time limit): what a
    // factorisation's flop count costs in seconds.
    double factor_rate() const;
    // Entries per second this machine writes outside the BLAS into memory it has not touched
    // yet (the first write of a page and scattered additions), measured as factor_rate is:
    // what a count of such writes (linalg::FactorPrice::writes) costs in seconds.
    double write_rate() const;
    // Bytes the solve may still take: `limit` (the option memory_limit; when 0, the memory the
    // process may use less what it held when first asked) less what the process has grown by
    // since that first question. INFINITY when the system does not say.
    double memory_left(double limit) const;

   private:
    std::chrono::steady_clock::time_point start_;
    mutable std::once_flag rate_once_;
    mutable double rate_ = 0.0;
    mutable std::once_flag write_once_;
    mutable double write_rate_ = 0.0;
    mutable std::once_flag memory_once_;
    mutable double resident_at_start_ = 0.0, available_ = 0.0;
};

// What a solver receives. The driver has already validated the problem and options, handled
// the empty and all-separating cases, and made r finite (a non-finite warm start is replaced
// by 0). The solver must:
//   - leave r finite (reject a non-finite local update rather than store it),
//   - set info->status and info->iterations (the driver computes the final measures from r
//     with the measures module and sets info->error; a solver must not claim CONVERGED
//     unless its own full-error check passed; a solver whose last local_measures call was
//     at the r it returns may hand those measures over in `measured`, and u then holds
//     W r + q: the driver does not pay for the same measures twice),
//   - honour tolerance, max_iter, time_limit (against `clock`) and the callback.
struct SolveContext {
    const frix_problem &problem;
    const frix_options &options;
    double *r;   // contact_size(problem) nc, warm start in, result out
    double *u;   // as r, output (the driver recomputes it at the end)
    double *v;   // n, global problems only
    frix_info &info;
    const Stopwatch &clock;
    // Global problems: the driver's factorisation of M (x = M^-1 b), for a solver that can use
    // it (607 calibrates its rho with it; auto's reduction route does not factorise M again);
    // null where there is none.
    MassSolver *mass = nullptr;
    // What a persistent solver keeps between solves (see solve_cache.hpp); null for a
    // one-shot frix_solve.
    SolveCache *cache;
    // Local problems: local_measures(problem, r, u) at the returned r, when the solver's last
    // call was there (see above); the driver measures r itself when it is not set.
    bool has_measured = false;
    Measures measured{};
    // Local problems: local_measures(problem, r, u) at the warm start, when the caller has them
    // (u then holds W r + q on entry): a solver that would measure its start takes these instead
    // of paying for the same product with W again. Null: not known.
    const Measures *measured_start = nullptr;
    // Set by the driver where it left M's numeric factorisation to the solver
    // (SolverEntry::mass_factor_on_demand): mass then holds M's analysis alone, and this
    // completes it as the driver would have (the limits asked, a singular M found). Where it
    // answers *ready false the solver returns at once: M is singular (the driver takes over) or
    // its factorisation would overrun the limit mass->refused() names (the solver's status).
    const std::function<frix_error(bool *ready)> *factor_mass = nullptr;
    // Set by the driver: the bound past which r runs away (runaway_bound); 0: no check.
    double runaway_bound = 0.0;
    // Set by the driver in its passes on a singular M's shifted M + eps diag(M) (floating.hpp):
    // there the velocity M^-1 (H r + f) of a warm r carries 1/eps times the load r leaves
    // unbalanced along the free motion.
    bool mass_shifted = false;
    // Set by frix_solve for the caller's own solve: a solver that did not converge returns
    // the best iterate it measured rather than its last. Not for the stages of a solver that
    // runs others (auto), which go on from where a stage ended.
    bool return_best = false;

    // A solve of a local problem (v, M's factorisation and the cache unset); named so that no
    // caller lines up the members by position.
    static SolveContext local(const frix_problem &p, const frix_options &o, double *r, double *u, frix_info &info,
                              const Stopwatch &clock) {
        return SolveContext{p, o, r, u, nullptr, info, clock, nullptr, nullptr};
    }
    // A solve of a global problem: v, and the driver's factorisation of M, where there is one.
    static SolveContext global(const frix_problem &p, const frix_options &o, double *r, double *u, double *v,
                               frix_info &info, const Stopwatch &clock, MassSolver *mass) {
        return SolveContext{p, o, r, u, v, info, clock, mass, nullptr};
    }
    // The same solve with a persistent solver's cache.
    SolveContext &with_cache(SolveCache *c) {
        cache = c;
        return *this;
    }
};

// A run whose reactions, in velocity units (w_a |r_a|, frix_problem::weight), exceed this many
// times the problem's free velocity has run away: no solution is that far from the data's
// scale (a solution scales with q), and a problem without one lets r grow without end.
constexpr double kRunawayFactor = 1e8;

// kRunawayFactor times the norm of a problem's free velocity (|q|, or free_velocity(p) for a
// global problem; Measures::norm_free); 0 when that is 0 (then r = 0 solves the problem, and
// nothing is checked) or not finite.
double runaway_bound(double free_velocity_norm);

// Whether r (contact_size(p) nc entries) has run away past `bound` (> 0): some w_a |r_a,i|
// above it (frix_problem::weight).
bool runs_away(const frix_problem &p, const double *r, double bound);

// A solve's warm start r (m entries) made finite (a non-finite entry would poison every
// iterate: 0 instead), and a copy of it to fall back on if the run diverges (a finite but huge
// r can make u overflow, and the caller must never get a non-finite u or error back); empty
// when r = 0 (the usual cold start: no allocation for it).
std::vector<double> finite_warm_start(double *r, int64_t m);

// Whether measures of an answer are finite: the relative error, |u| (an overflowed u can leave
// the relative error finite, dividing by |u| = Inf) and, for a global problem, the equilibrium.
bool finite_measures(const Measures &x);

// Whether a flag raised on this process is raised anywhere (Monitor::Agree): none (the default)
// on one process; the distributed solves pass an OR over ranks, so that every rank decides alike.
using Agree = std::function<bool(bool)>;

// How the driver measures an answer r of p (for a global problem with its velocity v = M^-1
// (H r + f)): u (and v) set for it, and its measures into `out`.
using MeasureAnswer = std::function<frix_error(const double *r, double *u, double *v, Measures &out)>;

// The driver's rule for a run that diverged, on every path: a run the Monitor stopped as a
// runaway (frix_info::ran_away) is DIVERGED; so is one that is `broken` (its r, v or measures
// `meas` not finite) or that did not converge with an r that runs_away past `bound` (then
// marked ran_away too). Such a run answers with the start (warm_start; r = 0 where it is empty,
// or where a broken run's start is not finite either), measured by `measure` into r, u, v (v:
// null for a local problem) and meas; a run that ran away keeps the r it returned only where
// its error (measure_kind) is below half of the start's. A distributed solve passes p, r, u, v
// and warm_start of this rank's contacts, meas and info.status as every rank has them, a
// collective `measure`, and `agree`: whether the run broke or ran away is then decided over
// the ranks (a runaway is one rank's contact past the bound), the same on every one.
frix_error fall_back_on_divergence(const frix_problem &p, int64_t measure_kind, const std::vector<double> &warm_start,
                                   bool broken, double bound, const MeasureAnswer &measure, double *r, double *u,
                                   double *v, Measures &meas, frix_info &info, const Agree &agree = nullptr);

using SolverFn = frix_error (*)(SolveContext &ctx);

struct OptionDefault {
    frix_option_key key;
    double value;  // int keys hold integral values
};

struct SolverEntry {
    int id;
    const char *name;           // "nsgs"
    const char *siconos_name;   // "FRICTION_3D_NSGS" (without prefix variants), or nullptr
    const char *description;
    SolverFn solve;
    bool solves_local;
    bool solves_global;
    // Keys this solver reads beyond the common ones (tolerance, max_iter, time_limit,
    // verbosity, error_measure), terminated by a 0 key.
    const frix_option_key *extra_keys;
    // Defaults that differ from the key table's, terminated by a 0 key.
    const OptionDefault *defaults;
    // Whether it solves rolling-friction problems (frix_problem.h), in both forms; no other
    // solver is handed one. A solver of rolling problems only has solves_local and
    // solves_global false (they are about the three-component problems).
    bool solves_rolling = false;
    // A solver of global problems that reads the start's r alone: the global solves it runs
    // recover the velocity a warm r gives where they need it (auto's routes), so the driver
    // does not before it.
    bool starts_from_r = false;
    // A solver of global problems that needs M's numeric factorisation on some of its paths
    // only and asks for it there (SolveContext::factor_mass): the driver of a one-shot solve
    // from r = 0 then analyses M alone (auto: its route without W never solves with M).
    bool mass_factor_on_demand = false;
};

// nullptr if unknown.
const SolverEntry *find_solver(int id);
int64_t solver_count();
const SolverEntry &solver_at(int64_t index);

// FRIX_ERR_UNSUPPORTED, the message led by `caller`, where `entry` does not solve p's kind of
// problem (rolling friction or three components; a local one for a solver of global problems
// only); FRIX_OK otherwise. frix_solve and frix_persistent_create ask it alike.
frix_error check_solver_takes(const char *caller, const SolverEntry &entry, const frix_problem &p);

// The driver's local path (src/solve.cpp), for either kind of contact (three entries, or five
// for rolling friction): the all-separating case, a finite warm start, `entry`'s solve watched
// for a runaway, the final measures of r, the fallback of a diverged run
// (fall_back_on_divergence) and the status check against the measures. Also the local step of
// the reduction route of global problems. `measures`, when given, receives the final
// measures (u then holds W r + q). accept_start: a warm start that already meets the tolerance
// is the answer, with no iteration (frix_solve's own call; a stage or a pass of a solve starts
// from an r that was just found short of it). measured_start: the caller's measures of the
// finite warm start r, u holding W r + q on entry (SolveContext::measured_start); the solver
// gets them, as it gets accept_start's.
frix_error solve_local_problem(const frix_problem &p, const frix_options &opts,
                               const SolverEntry &entry, double *r, double *u, frix_info &info,
                               const Stopwatch &clock, SolveCache *cache = nullptr,
                               Measures *measures = nullptr, bool return_best = false, bool accept_start = false,
                               const Measures *measured_start = nullptr);

// The driver's global path (src/solve_global.cpp): runs `entry` natively if it solves global
// problems, through the reduction W = H^T M^-1 H otherwise; a rolling-friction problem goes to
// its solver as it is (the rolling solvers handle M themselves). Either way watched for a
// runaway, with the fallback of a diverged run. r, u (contact_size(p) nc) and v (n) as in
// frix_solve. `enclosing`, when given, is M's factorisation made by an enclosing driver on the
// same problem (SolveContext::mass): used instead of one of its own.
frix_error solve_global_problem(const frix_problem &p, const frix_options &opts,
                                const SolverEntry &entry, double *r, double *u, double *v,
                                frix_info &info, const Stopwatch &clock, SolveCache *cache = nullptr,
                                MassSolver *enclosing = nullptr);

// frix_solve's whole contract (argument checks, the default solver, a fresh info), with the
// states of a persistent solver when `cache` is given.
frix_error solve_problem(const char *caller, const frix_problem *problem, const frix_options *options,
                         double *r, double *u, double *v, frix_info *info, SolveCache *cache);

// Whether a global solve's measures meet `tol`: its error, which holds the equilibrium
// residual (selected_error).
bool meets_global_tolerance(const frix_info &info, double tol);

// The default solver of frix_solve(problem, NULL, ...).
constexpr int kDefaultSolver = FRIX_SOLVER_AUTO;

}  // namespace frix
