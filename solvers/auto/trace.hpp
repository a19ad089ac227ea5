// auto's trace: what its records are (the kinds of its lines), the figures its analysis
// records carry, and how they read.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "solvers/auto/analysis.hpp"
#include "src/info.hpp"

namespace frix::autosolve {

enum TraceKind {
    kAnalysis, kStage, kGiveUp, kTighten, kGlobalFallback, kGlobalDirect, kGlobalReduceAfter,
    kGlobalReduceRefused, kExistence
};

// What auto's analysis found (sizes, ranges, islands; for a global problem its own sizes and
// the bound on W = H^T M^-1 H): the figures of its kAnalysis and kGlobalDirect records.
struct AnalysisSummary : TraceDetail {
    int64_t contacts = 0, blocks = 0, islands = 0, largest_island = 0, dofs = 0;
    double diag_min = 0.0, diag_max = 0.0, mu_min = 0.0, mu_max = 0.0, rank_ratio = 0.0;
    // Global problems: the bound on the entries of W = H^T M^-1 H, and those of M and H.
    double reduced_entries = 0.0, input_entries = 0.0;
    // 3 nc <= n (rank_ratio <= 1): W may be regular, a deformable body with few contacts for
    // its dofs; the routes' choices between sweeps' accelerations and Newton finishers.
    bool w_may_be_regular() const { return rank_ratio <= 1.0; }
};

// A record of `kind` (a run for kStage) that reads as format_event says.
TraceEvent trace_event(TraceKind kind);
// The record of a local problem's analysis.
TraceEvent analysis_event(const Analysis &a);
// A record of `kind` carrying `figures` (kGlobalDirect: a global problem's).
TraceEvent summary_event(TraceKind kind, const AnalysisSummary &figures);
// The global problem's figures (dofs, rank ratio, W's bound) added to the analysis records of
// `trace`, those of the solve of its reduction.
void add_global_figures(std::vector<TraceEvent> &trace, const AnalysisSummary &global);

// The line of one of auto's records (with its newline).
std::string format_event(const frix_info &info, const TraceEvent &e);

}  // namespace frix::autosolve
