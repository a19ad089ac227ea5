// The result record: creation, reads by key, and one run's ledger made of several (absorb).
#include "info.hpp"

#include "error_state.hpp"
#include "monitor.hpp"

using frix::fail;

void frix_info::absorb(const frix_info &earlier) {
    frix::Monitor::add_work(*this, earlier);
    iterations += earlier.iterations;
    switches += earlier.switches;
    if (islands == 0) islands = earlier.islands;
    trace.insert(trace.begin(), earlier.trace.begin(), earlier.trace.end());
}

extern "C" {

FRIX_API frix_error frix_info_create(frix_info **out) {
    return frix::guard("frix_info_create", [&]() -> frix_error {
        if (!out) return fail(FRIX_ERR_INVALID_ARGUMENT, "frix_info_create: out is NULL");
        *out = new frix_info();
        return FRIX_OK;
    });
}

FRIX_API void frix_info_free(frix_info *info) { delete info; }

FRIX_API frix_error frix_info_get_int(const frix_info *info, frix_info_key key, int64_t *value) {
    if (!info || !value) return fail(FRIX_ERR_INVALID_ARGUMENT, "frix_info_get_int: NULL argument");
    switch (key) {
        case FRIX_INFO_STATUS: *value = info->status; return FRIX_OK;
        case FRIX_INFO_ITERATIONS: *value = info->iterations; return FRIX_OK;
        case FRIX_INFO_SOLVER_ID: *value = info->solver_id; return FRIX_OK;
        case FRIX_INFO_CONTACTS: *value = info->contacts; return FRIX_OK;
        case FRIX_INFO_NEWTON_ITERATIONS: *value = info->newton_iterations; return FRIX_OK;
        case FRIX_INFO_LINE_SEARCH_STEPS: *value = info->line_search_steps; return FRIX_OK;
        case FRIX_INFO_FACTORIZATIONS: *value = info->factorizations; return FRIX_OK;
        case FRIX_INFO_SYMBOLIC_ANALYSES: *value = info->symbolic_analyses; return FRIX_OK;
        case FRIX_INFO_HYBRID_SWEEPS: *value = info->hybrid_sweeps; return FRIX_OK;
        case FRIX_INFO_INNER_ITERATIONS: *value = info->inner_iterations; return FRIX_OK;
        case FRIX_INFO_ISLANDS: *value = info->islands; return FRIX_OK;
        case FRIX_INFO_SWITCHES: *value = info->switches; return FRIX_OK;
        case FRIX_INFO_EXISTENCE: *value = info->existence; return FRIX_OK;
        default: break;
    }
    return fail(FRIX_ERR_INVALID_ARGUMENT, "frix_info_get_int: key %d is not an int key", (int)key);
}

FRIX_API frix_error frix_info_get_double(const frix_info *info, frix_info_key key, double *value) {
    if (!info || !value) return fail(FRIX_ERR_INVALID_ARGUMENT, "frix_info_get_double: NULL argument");
    switch (key) {
        case FRIX_INFO_ERROR: *value = info->error; return FRIX_OK;
        case FRIX_INFO_ERROR_RELATIVE: *value = info->error_relative; return FRIX_OK;
        case FRIX_INFO_ERROR_Q_RELATIVE: *value = info->error_q_relative; return FRIX_OK;
        case FRIX_INFO_ERROR_SCALED: *value = info->error_scaled; return FRIX_OK;
        case FRIX_INFO_RESIDUAL_ABSOLUTE: *value = info->residual_absolute; return FRIX_OK;
        case FRIX_INFO_CONE_VIOLATION: *value = info->cone_violation; return FRIX_OK;
        case FRIX_INFO_PENETRATION: *value = info->penetration; return FRIX_OK;
        case FRIX_INFO_COMPLEMENTARITY: *value = info->complementarity; return FRIX_OK;
        case FRIX_INFO_EQUILIBRIUM: *value = info->equilibrium; return FRIX_OK;
        case FRIX_INFO_ERROR_CONTACT: *value = info->error_contact; return FRIX_OK;
        case FRIX_INFO_EQUILIBRIUM_SCALED: *value = info->equilibrium_scaled; return FRIX_OK;
        case FRIX_INFO_SOLVE_TIME: *value = info->solve_time; return FRIX_OK;
        case FRIX_INFO_TOLERANCE: *value = info->tolerance; return FRIX_OK;
        case FRIX_INFO_FACTORIZATION_TIME: *value = info->factorization_time; return FRIX_OK;
        case FRIX_INFO_SETUP_TIME: *value = info->setup_time; return FRIX_OK;
        case FRIX_INFO_REDUCTION_TIME: *value = info->reduction_time; return FRIX_OK;
        case FRIX_INFO_EXISTENCE_MARGIN: *value = info->existence_margin; return FRIX_OK;
        default: break;
    }
    return fail(FRIX_ERR_INVALID_ARGUMENT, "frix_info_get_double: key %d is not a double key", (int)key);
}

FRIX_API frix_status frix_info_status(const frix_info *info) {
    return info ? info->status : FRIX_STATUS_NOT_RUN;
}
FRIX_API int64_t frix_info_iterations(const frix_info *info) { return info ? info->iterations : 0; }
FRIX_API double frix_info_error(const frix_info *info) { return info ? info->error : NAN; }
FRIX_API double frix_info_solve_time(const frix_info *info) { return info ? info->solve_time : 0.0; }
FRIX_API const char *frix_info_trace(const frix_info *info) {
    if (!info) return "";
    try {  // no exception crosses the C API: without memory, the trace is empty
        info->trace_text = frix::format_trace(*info);
    } catch (...) {
        info->trace_text.clear();
    }
    return info->trace_text.c_str();
}

FRIX_API int64_t frix_info_stage_count(const frix_info *info) {
    return info ? (int64_t)info->trace.size() : 0;
}

namespace {

// The record `index` of info's trace into *out, or the error.
frix_error stage_record(const frix_info *info, int64_t index, const void *value, const char *where,
                        const frix::TraceEvent **out) {
    if (!info || !value) return frix::fail(FRIX_ERR_INVALID_ARGUMENT, "%s: NULL argument", where);
    if (index < 0 || index >= (int64_t)info->trace.size())
        return frix::fail(FRIX_ERR_DIMENSION, "%s: record %lld of %lld", where, (long long)index,
                          (long long)info->trace.size());
    *out = &info->trace[(size_t)index];
    return FRIX_OK;
}

}  // namespace

FRIX_API frix_error frix_info_stage_get_int(const frix_info *info, int64_t index, frix_stage_key key,
                                            int64_t *value) {
    const frix::TraceEvent *e = nullptr;
    if (frix_error err = stage_record(info, index, value, "frix_info_stage_get_int", &e)) return err;
    const bool run = e->run;
    switch (key) {
        case FRIX_STAGE_SOLVER_ID: *value = run ? e->solver_id : 0; return FRIX_OK;
        case FRIX_STAGE_STATUS: *value = run ? e->status : FRIX_STATUS_NOT_RUN; return FRIX_OK;
        case FRIX_STAGE_ITERATIONS: *value = run ? e->iterations : 0; return FRIX_OK;
        case FRIX_STAGE_PART: *value = e->island; return FRIX_OK;
        case FRIX_STAGE_PART_CONTACTS: *value = e->island_contacts; return FRIX_OK;
        case FRIX_STAGE_RANDOM_STARTS: *value = run ? e->random_starts : 0; return FRIX_OK;
        case FRIX_STAGE_STOPPED_BY_AUTO: *value = run && e->why != nullptr; return FRIX_OK;
        default:
            return frix::fail(FRIX_ERR_INVALID_ARGUMENT, "frix_info_stage_get_int: key %d is not an int key",
                              (int)key);
    }
}

FRIX_API frix_error frix_info_stage_get_double(const frix_info *info, int64_t index,
                                               frix_stage_key key, double *value) {
    const frix::TraceEvent *e = nullptr;
    if (frix_error err = stage_record(info, index, value, "frix_info_stage_get_double", &e)) return err;
    const bool run = e->run;
    switch (key) {
        case FRIX_STAGE_ERROR: *value = run ? e->error : NAN; return FRIX_OK;
        case FRIX_STAGE_SECONDS: *value = run ? e->seconds : 0.0; return FRIX_OK;
        default:
            return frix::fail(FRIX_ERR_INVALID_ARGUMENT,
                              "frix_info_stage_get_double: key %d is not a double key", (int)key);
    }
}

FRIX_API const char *frix_info_stage_note(const frix_info *info, int64_t index) {
    if (!info || index < 0 || index >= (int64_t)info->trace.size()) return "";
    try {  // no exception crosses the C API: without memory, the note is empty
        info->stage_note = frix::format_event(*info, info->trace[(size_t)index]);
    } catch (...) {
        info->stage_note.clear();
    }
    while (!info->stage_note.empty() && info->stage_note.back() == '\n') info->stage_note.pop_back();
    return info->stage_note.c_str();
}

FRIX_API const char *frix_existence_describe(frix_existence verdict) {
    switch (verdict) {
        case FRIX_EXISTENCE_NOT_CHECKED: return "not checked";
        case FRIX_EXISTENCE_GUARANTEED: return "a solution exists";
        case FRIX_EXISTENCE_DOUBTFUL: return "no solution may exist";
        case FRIX_EXISTENCE_UNDETERMINED: return "undetermined";
    }
    return "unknown verdict";
}

}  // extern "C"
