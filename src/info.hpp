// Internal layout of frix_info.
#pragma once

#include <frix/frix_solve.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "handle_header.hpp"

namespace frix {

struct TraceEvent;
// A note's own figures beyond TraceEvent's numbers (auto's analysis): only the recording
// solver's `format` reads them.
struct TraceDetail {
    virtual ~TraceDetail() = default;
};
// How a record becomes its line of the trace: the recording solver's own function.
using TraceFormatter = std::string (*)(const frix_info &info, const TraceEvent &event);

// One record of a solve's trace (frix_info_trace, the stage records): a solver's run, or a
// note of the solver that recorded it. Kept as data and formatted only when asked for
// (formatting numbers costs more than solving a small problem); only the recording solver,
// through `format`, knows what `kind` and the numbers of a note mean.
struct TraceEvent {
    int kind = 0;                 // the recording solver's vocabulary
    bool run = false;             // a solver's run: solver_id .. seconds are its figures
    TraceFormatter format = nullptr;
    int64_t island = 0;           // 1-based; 0 when the problem is solved as one island
    int64_t island_contacts = 0;
    int solver_id = 0;
    frix_status status = FRIX_STATUS_NOT_RUN;
    const char *why = nullptr;    // a static string: why the run was stopped by its caller
    int64_t random_starts = 0;    // > 0: the run went from that many random starts
    int64_t iterations = 0;
    double seconds = 0.0, error = 0.0, value = 0.0;  // a note's numbers mean what `format` says
    std::shared_ptr<const TraceDetail> detail;       // null for most records
};

// The trace's text (src/trace.cpp): all of it, or one record's line.
std::string format_trace(const frix_info &info);
std::string format_event(const frix_info &info, const TraceEvent &event);

}  // namespace frix

struct frix_info {
    frix::HandleHeader header = frix::header_of<frix_info>();  // first, in every release
    frix_status status = FRIX_STATUS_NOT_RUN;
    int64_t iterations = 0;
    int solver_id = 0;
    int64_t contacts = 0;

    double error = NAN;
    double error_relative = NAN;
    double error_q_relative = NAN;
    double error_scaled = NAN;
    double residual_absolute = NAN;
    double cone_violation = NAN;
    double penetration = NAN;
    double complementarity = NAN;
    double equilibrium = NAN;
    double error_contact = NAN;
    double equilibrium_scaled = NAN;
    double solve_time = 0.0;
    double tolerance = NAN;

    int64_t newton_iterations = 0;
    int64_t line_search_steps = 0;
    int64_t factorizations = 0;
    int64_t symbolic_analyses = 0;
    int64_t hybrid_sweeps = 0;
    int64_t inner_iterations = 0;
    double factorization_time = 0.0;
    double setup_time = 0.0;
    double reduction_time = 0.0;  // the part of setup_time forming W = H^T M^-1 H

    int64_t islands = 0;
    int64_t switches = 0;
    frix_existence existence = FRIX_EXISTENCE_NOT_CHECKED;
    // r ran away (the Monitor stopped the run, or the driver found its answer past the bound):
    // the driver reports it as diverged.
    bool ran_away = false;
    double existence_margin = NAN;
    std::vector<frix::TraceEvent> trace;
    mutable std::string trace_text;  // formatted by frix_info_trace
    mutable std::string stage_note;  // formatted by frix_info_stage_note

    // One run made of several: `earlier`'s work comes before this one's. The counters (work,
    // iterations, switches) add up, the trace reads earlier's records first, and the islands
    // are earlier's where this run found none. The status and measures stay this run's.
    void absorb(const frix_info &earlier);
    // The empty record of a further run of the same solve: its solver, contacts and tolerance.
    frix_info next_run() const {
        frix_info run;
        run.solver_id = solver_id;
        run.contacts = contacts;
        run.tolerance = tolerance;
        return run;
    }
};
