// The lines of auto's trace: its analysis, its stages and its decisions, formatted only when
// the trace is read.
#include "solvers/auto_trace.hpp"

#include <algorithm>
#include <cstdarg>
#include <cstdio>

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

}  // namespace

std::string format_event(const frix_info &info, const TraceEvent &e) {
    std::string out = island_label(e);
    {
        switch (static_cast<TraceKind>(e.kind)) {
            case kAnalysis: {
                const AnalysisSummary &a = info.analysis;
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
                break;
            }
            case kStage:
                append(out, "%s", name_of(e.solver_id));
                if (e.random_starts > 0)
                    append(out, " from %lld random start%s", (long long)e.random_starts, e.random_starts == 1 ? "" : "s");
                append(out, ": %s after %lld iterations in %.3g s, error %.3e",
                       e.why ? "stopped by the watchdog" : frix_status_string(e.status), (long long)e.iterations,
                       e.seconds, e.error);
                if (e.why) append(out, " (%s)", e.why);
                out += "\n";
                break;
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
            case kGlobalDirect: {
                // status: the limit forming W would overrun (FRIX_STATUS_NOT_RUN: none); value:
                // forming W's price over the route without it; solver_id: the route's first solver.
                const AnalysisSummary &a = info.analysis;
                append(out, "analysis: global, %lld dofs, %lld contacts; W = H^T M^-1 H would have up to %.3g "
                            "entries (%.3g per entry of M and H: a deformable body couples all its contacts), ",
                       (long long)a.dofs, (long long)a.contacts, a.reduced_entries,
                       a.reduced_entries / std::max(1.0, a.input_entries));
                if (e.status)
                    append(out, "and forming it would overrun the %s limit",
                           e.status == FRIX_STATUS_MEMORY_LIMIT ? "memory" : "time");
                else
                    append(out, "and forming it is priced %.3g times the route without it", e.value);
                if (e.solver_id == FRIX_SOLVER_GLOBAL_ADMM)
                    append(out, ": %s on (v, r) without it, then %s if needed\n", name_of(e.solver_id),
                           name_of(FRIX_SOLVER_GLOBAL_AL_NEWTON));
                else
                    append(out, ": %s on (v, r) without it\n", name_of(e.solver_id));
                break;
            }
            case kGlobalReduceAfter:
                append(out, "without W: %s (error %.3e, equilibrium %.3e): W = H^T M^-1 H formed after all, the "
                            "reduced solve from the start\n",
                       frix_status_string(e.status), e.error, e.value);
                break;
            case kExistence:
                append(out, "existence check: %s\n", frix_existence_describe(info.existence));
                break;
        }
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

}  // namespace frix::autosolve
