// The lines of auto's trace: its analysis, its stages and its decisions, formatted only when
// the trace is read.
#include "solvers/auto/trace.hpp"

#include <algorithm>
#include <cstdarg>
#include <cstdio>
#include <memory>

#include "src/solver_api.hpp"

namespace frix::autosolve {

namespace {

void append(std::string &out, const char *fmt, ...) {
    char buf[512];
    va_list ap;
    va_start(ap, fmt);
    std::vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    out += buf;
}

const char *name_of(int solver_id) {
    const SolverEntry *e = find_solver(solver_id);
    return e ? e->name : "?";
}

std::string island_label(const TraceEvent &e) {
    if (e.island == 0) return std::string();
    char buf[96];
    std::snprintf(buf, sizeof buf, "part %lld (%lld contacts): ", (long long)e.island,
                  (long long)e.island_contacts);
    return buf;
}

// The figures a record carries (none: all zero).
const AnalysisSummary &figures_of(const TraceEvent &e) {
    static const AnalysisSummary none;
    return e.detail ? static_cast<const AnalysisSummary &>(*e.detail) : none;
}

void analysis_line(std::string &out, const frix_info &info, const AnalysisSummary &a) {
    append(out, "analysis: %lld contacts, %lld W blocks, %lld island%s (largest %lld), "
                "|W_aa| %.3g..%.3g, mu %.3g..%.3g", (long long)a.contacts, (long long)a.blocks,
           (long long)a.islands, a.islands == 1 ? "" : "s", (long long)a.largest_island,
           a.diag_min, a.diag_max, a.mu_min, a.mu_max);
    if (a.dofs > 0)
        append(out, "; global: %lld dofs, rank ratio 3nc/n %.3g, W = H^T M^-1 H at most %.3g entries "
                    "(%.3g per entry of M and H)",
               (long long)a.dofs, a.rank_ratio, a.reduced_entries,
               a.reduced_entries / std::max(1.0, a.input_entries));
    if (a.dofs > 0 && info.setup_time > 0.0)
        append(out, "; setup %.3g s (W = H^T M^-1 H %.3g s)", info.setup_time, info.reduction_time);
    out += "\n";
}

void stage_line(std::string &out, const TraceEvent &e) {
    append(out, "%s", name_of(e.solver_id));
    if (e.random_starts > 0)
        append(out, " from %lld random start%s", (long long)e.random_starts, e.random_starts == 1 ? "" : "s");
    append(out, ": %s after %lld iterations in %.3g s, error %.3e",
           e.why ? "stopped by the watchdog" : frix_status_string(e.status), (long long)e.iterations,
           e.seconds, e.error);
    if (e.why) append(out, " (%s)", e.why);
    out += "\n";
}

// status: the limit forming W would overrun, as asked up front (FRIX_STATUS_NOT_RUN: none, or
// the time left to ask before W is formed after the route); value: forming W's
// price over the route without it; solver_id: the route's first solver.
void direct_line(std::string &out, const TraceEvent &e) {
    const AnalysisSummary &a = figures_of(e);
    append(out, "analysis: global, %lld dofs, %lld contacts; W = H^T M^-1 H would have up to %.3g "
                "entries (%.3g per entry of M and H: a body couples all the contacts it carries), ",
           (long long)a.dofs, (long long)a.contacts, a.reduced_entries,
           a.reduced_entries / std::max(1.0, a.input_entries));
    if (e.status)
        append(out, "and forming it would overrun the %s limit",
               e.status == FRIX_STATUS_MEMORY_LIMIT ? "memory" : "time");
    else
        append(out, "and forming it is priced %.3g times the route without it", e.value);
    if (e.solver_id == FRIX_SOLVER_GLOBAL_ADMM && a.w_may_be_regular())  // (global_routes.cpp's w_free_route)
        append(out, ": %s on (v, r) without it, then %s and %s if needed\n", name_of(e.solver_id),
               name_of(FRIX_SOLVER_GLOBAL_NSN_AC), name_of(FRIX_SOLVER_GLOBAL_AL_NEWTON));
    else if (e.solver_id == FRIX_SOLVER_GLOBAL_ADMM)
        append(out, ": %s on (v, r) without it, then %s if needed\n", name_of(e.solver_id),
               name_of(FRIX_SOLVER_GLOBAL_AL_NEWTON));
    else
        append(out, ": %s on (v, r) without it\n", name_of(e.solver_id));
}

}  // namespace

std::string format_event(const frix_info &info, const TraceEvent &e) {
    std::string out = island_label(e);
    switch (static_cast<TraceKind>(e.kind)) {
        case kAnalysis: analysis_line(out, info, figures_of(e)); break;
        case kStage: stage_line(out, e); break;
        case kGiveUp:
            append(out, "a whole round without halving the error (best %.3e): giving up\n", e.error);
            break;
        case kTighten:
            append(out, "combined error %.3e above the tolerance: islands again to %.3e\n", e.error, e.value);
            break;
        case kGlobalFallback:
            append(out, "reduced solve %s (error %.3e, equilibrium %.3e): %s on (v, r) from its result\n",
                   frix_status_string(e.status), e.error, e.value, name_of(e.solver_id));
            break;
        case kGlobalDirect: direct_line(out, e); break;
        case kGlobalReduceAfter:
            append(out, "without W: %s (error %.3e, equilibrium %.3e): W = H^T M^-1 H formed after all, the "
                        "reduced solve from the start\n",
                   frix_status_string(e.status), e.error, e.value);
            break;
        case kGlobalReduceRefused:
            append(out, "without W: error %.3e, equilibrium %.3e; forming W = H^T M^-1 H would overrun the %s "
                        "limit: not formed\n",
                   e.error, e.value, e.status == FRIX_STATUS_MEMORY_LIMIT ? "memory" : "time");
            break;
        case kExistence: append(out, "existence check: %s\n", frix_existence_describe(info.existence)); break;
    }
    return out;
}

TraceEvent trace_event(TraceKind kind) {
    TraceEvent e;
    e.kind = kind;
    e.run = kind == kStage;
    e.format = &format_event;
    return e;
}

TraceEvent summary_event(TraceKind kind, const AnalysisSummary &figures) {
    TraceEvent e = trace_event(kind);
    e.detail = std::make_shared<const AnalysisSummary>(figures);
    return e;
}

TraceEvent analysis_event(const Analysis &a) {
    AnalysisSummary s;
    s.contacts = a.contacts;
    s.blocks = a.blocks;
    s.islands = a.islands;
    s.largest_island = a.largest_island;
    s.diag_min = a.diag_min, s.diag_max = a.diag_max;
    s.mu_min = a.mu_min, s.mu_max = a.mu_max;
    return summary_event(kAnalysis, s);
}

void add_global_figures(std::vector<TraceEvent> &trace, const AnalysisSummary &global) {
    for (TraceEvent &e : trace) {
        if (e.format != &format_event || e.kind != kAnalysis) continue;
        AnalysisSummary s = figures_of(e);
        s.dofs = global.dofs;
        s.rank_ratio = global.rank_ratio;
        s.reduced_entries = global.reduced_entries;
        s.input_entries = global.input_entries;
        e.detail = std::make_shared<const AnalysisSummary>(s);
    }
}

}  // namespace frix::autosolve
