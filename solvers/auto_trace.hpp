// auto's trace: what its records are (the kinds of its lines) and how they read.
#pragma once

#include <string>

#include "src/info.hpp"

namespace frix::autosolve {

enum TraceKind {
    kAnalysis, kStage, kGiveUp, kTighten, kGlobalFallback, kGlobalDirect, kGlobalReduceAfter, kExistence
};

// A record of `kind` (a run for kStage) that reads as format_event says.
TraceEvent trace_event(TraceKind kind);

// The line of one of auto's records (with its newline).
std::string format_event(const frix_info &info, const TraceEvent &e);

}  // namespace frix::autosolve
