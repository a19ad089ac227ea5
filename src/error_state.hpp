// Internal: setting frix_error results with a message, and the exception barrier that every
// extern "C" entry point goes through.
#pragma once

#include <frix/frix_errors.h>

#include <exception>
#include <new>

namespace frix {

// Records a printf-style message for frix_last_error_message() in this thread and returns
// `code`, so call sites read `return fail(FRIX_ERR_DIMENSION, "q has %lld entries", n);`.
frix_error fail(frix_error code, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

// Clears this thread's message (entry points call it on success paths only when useful).
void clear_error();

// Thrown inside the library where unwinding is simpler than returning; caught by guard().
struct Failure {
    frix_error code;
};

// Runs body() (which returns frix_error) and turns every escaping C++ exception into a
// frix_error with a message: no exception ever crosses the C ABI.
template <class Body>
frix_error guard(const char *where, Body &&body) noexcept {
    try {
        return body();
    } catch (const Failure &f) {
        return f.code;  // message already recorded by the thrower
    } catch (const std::bad_alloc &) {
        return fail(FRIX_ERR_OUT_OF_MEMORY, "%s: out of memory", where);
    } catch (const std::exception &e) {
        return fail(FRIX_ERR_INTERNAL, "%s: internal error: %s", where, e.what());
    } catch (...) {
        return fail(FRIX_ERR_INTERNAL, "%s: internal error (unknown exception)", where);
    }
}

}  // namespace frix
