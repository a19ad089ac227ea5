// Failing from deep inside the FCLIB code: record the message and unwind to the entry
// point's guard(), which returns the code. Reading a file has dozens of failure points;
// unwinding keeps each of them one line long.
#pragma once

#include <frix/frix_errors.h>

#include <string>

namespace frix::fclib {

[[noreturn]] void raise(frix_error code, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

// Turns a failure returned by a core constructor (matrix, problem) into a file error:
// content that the core refuses is malformed content of the file, so the code becomes
// FRIX_ERR_FORMAT (out of memory stays what it is) and the message gains `context`.
[[noreturn]] void raise_from_core(frix_error code, const std::string &context);

// The same, keeping the core's code: for failures that are not about file content.
[[noreturn]] void reraise(frix_error code, const std::string &context);

// Text from a file (a title, a link target, a token) with its control characters (bytes
// below 0x20, and 0x7f) written as \xHH: it ends up in messages and titles that callers
// print, where raw escape sequences would drive the terminal. With keep_line_breaks, line
// feeds and tabs stay as they are (multi-line text such as a description).
std::string printable(const std::string &text, bool keep_line_breaks = false);

}  // namespace frix::fclib
