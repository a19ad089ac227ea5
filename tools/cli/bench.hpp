// `frix bench`: declarations shared by its parts (campaign, child runs, report).
#pragma once

#include <cmath>
#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace frix_cli {

// One row of runs.csv: one (problem, solver) run.
struct RunRecord {
    std::string problem, family;
    std::int64_t contacts = 0, dofs = 0;  // -1: not known (no run could read the problem)
    std::string solver;
    int solver_id = 0;
    // converged | max_iter | time_limit | stagnated | diverged | numerical_failure (frix) |
    // inaccurate | failed (Siconos) | timeout | crash(SIGNAME) | error | unsupported |
    // unreadable (the run's reader refused the file; the note says why)
    std::string status;
    std::int64_t iterations = 0;
    double error = 0, time = 0;        // frix's relative measure; seconds of solve
    double tolerance = 0, time_limit = 0;
    std::int64_t max_iter = 0;
    double reported_error = 0;        // the solver's own final error (Siconos's differs)
    std::string note;
    double peak_memory_mb = NAN;  // the run's peak resident memory, problem read included (NaN: not known)
    // The problem's own storage in 3x3 blocks: W's stored entries / 9 (local), M's and H's
    // (global); NaN: not known (older campaigns).
    double stored_blocks = NAN;
    double error_scaled = NAN;  // frix's default measure of the r returned (NaN: older campaigns)
    bool converged() const { return status == "converged"; }
    // Whether the answer meets the tolerance by frix's measure of Siconos's kind, and by the
    // default one: the same yardstick for both libraries' runs, whatever each stopped on.
    bool meets_siconos_measure() const { return error <= tolerance * (1.0 + 1e-9); }
    bool meets_default_measure() const { return error_scaled <= tolerance * (1.0 + 1e-9); }
};

struct TracePoint {
    std::int64_t iteration;
    double elapsed, error;
};

// The traces, by (problem, solver).
using TraceMap = std::map<std::pair<std::string, std::string>, std::vector<TracePoint>>;

// The columns of the two CSV files, in order.
std::vector<std::string> runs_header();
std::vector<std::string> run_fields(const RunRecord &r);
std::vector<std::string> traces_header();

// The family of a problem from its file name (a small table, first match wins).
std::string problem_family(const std::string &file_name);

// Reads DIR/runs.csv and DIR/traces.csv (if present) and writes DIR/profile.csv,
// DIR/work_precision.csv and DIR/summary.md; then the plots unless `plots` is false.
// Returns a line saying what was written (or why the plots were skipped).
std::string bench_report(const std::string &dir, bool plots, const std::string &self_dir);

// Performance profiles (Dolan and More): for each problem p the best time t_p over the
// solvers that converged; rho_s(tau) = share of the problems on which s converged with
// t_ps <= tau t_p. The step function is given by its breakpoints (tau ascending, rho after
// the step); tau = 1 is always the first one.
struct ProfileStep {
    double tau, rho;
};
std::map<std::string, std::vector<ProfileStep>> performance_profile(
    const std::vector<const RunRecord *> &runs, const std::vector<std::string> &solvers,
    std::size_t problem_count, double time_floor);

// Directory of the running executable (where frix-siconos and the plot script live).
std::string self_directory();
// Formats seconds as "m:ss" or "h:mm:ss".
std::string clock_text(double seconds);
std::string number_text(double v);  // exact round-trip text; "" for NaN

}  // namespace frix_cli
