// Error and status strings, and the thread-local message of the last failing call.
#include <cstdarg>
#include <cstdio>

#include "error_state.hpp"

namespace {
// One buffer per thread: concurrent solves never see each other's messages.
thread_local char last_message[1024] = "";
}  // namespace

namespace frix {

frix_error fail(frix_error code, const char *fmt, ...) {
    va_list args;
    va_start(args, fmt);
    std::vsnprintf(last_message, sizeof last_message, fmt, args);
    va_end(args);
    return code;
}

void clear_error() { last_message[0] = '\0'; }

}  // namespace frix

extern "C" {

FRIX_API const char *frix_error_string(frix_error code) {
    switch (code) {
        case FRIX_OK: return "no error";
        case FRIX_ERR_INVALID_ARGUMENT: return "invalid argument";
        case FRIX_ERR_DIMENSION: return "dimension mismatch";
        case FRIX_ERR_NOT_FINITE: return "NaN or Inf in input data";
        case FRIX_ERR_OUT_OF_MEMORY: return "out of memory";
        case FRIX_ERR_IO: return "input/output error";
        case FRIX_ERR_FORMAT: return "malformed file content";
        case FRIX_ERR_UNKNOWN_SOLVER: return "unknown solver";
        case FRIX_ERR_UNKNOWN_OPTION: return "unknown option for this solver";
        case FRIX_ERR_OPTION_RANGE: return "option value out of range";
        case FRIX_ERR_UNSUPPORTED: return "not supported";
        case FRIX_ERR_NUMERICAL: return "numerical failure";
        case FRIX_ERR_INTERNAL: return "internal error";
    }
    return "unknown error code";
}

FRIX_API const char *frix_status_string(frix_status status) {
    switch (status) {
        case FRIX_STATUS_NOT_RUN: return "not run";
        case FRIX_STATUS_CONVERGED: return "converged";
        case FRIX_STATUS_MAX_ITER: return "maximum iterations reached";
        case FRIX_STATUS_TIME_LIMIT: return "time limit reached";
        case FRIX_STATUS_STAGNATED: return "stagnated";
        case FRIX_STATUS_DIVERGED: return "diverged";
        case FRIX_STATUS_NUMERICAL_FAILURE: return "numerical failure";
        case FRIX_STATUS_STOPPED_BY_CALLBACK: return "stopped by callback";
        case FRIX_STATUS_MEMORY_LIMIT: return "memory limit reached";
    }
    return "unknown status";
}

FRIX_API const char *frix_last_error_message(void) { return last_message; }

}  // extern "C"
