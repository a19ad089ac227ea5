// Internal layout of frix_options: one slot per key, typed by the key table in options.cpp.
#pragma once

#include <frix/frix_options.h>

#include <cstdint>

#include "handle_header.hpp"

namespace frix {
constexpr int kMaxOptionKey = 35;  // highest frix_option_key value
struct SolverEntry;
}

struct frix_options {
    frix::HandleHeader header = frix::header_of<frix_options>();  // first, in every release
    int solver_id = 0;
    // Slot k holds key k (slot 0 unused); ints are stored in ivalue, doubles in dvalue.
    int64_t ivalue[frix::kMaxOptionKey + 1] = {};
#ifdef FRIX_TEST_NEXT_RELEASE
    int64_t next_release_slots[8] = {};  // test only: the longer record of a later release
#endif
    double dvalue[frix::kMaxOptionKey + 1] = {};
    frix_progress_fn callback = nullptr;
    void *callback_data = nullptr;
    // Internal (auto's watchdog, which judges estimates too): called in place of callback, on
    // callback_data, after every iteration with whether `error` was measured on the iterate.
    int (*callback_with_kind)(void *data, int64_t iteration, double error, bool measured) = nullptr;
    frix_log_fn log = nullptr;  // null: stderr
    void *log_data = nullptr;

    // Whether a callback of either kind is set.
    bool has_callback() const { return callback || callback_with_kind; }

    // Typed reads for solvers (the key must be one the solver declared; no checks here).
    int64_t i(frix_option_key k) const { return ivalue[k]; }
    double d(frix_option_key k) const { return dvalue[k]; }
};

namespace frix {
// The options frix_options_create(e.id) makes, without its checks and without allocating:
// for solvers that run other solvers (auto), whose tables frix_options_create checks.
void default_options(const SolverEntry &e, frix_options &o);
}  // namespace frix
