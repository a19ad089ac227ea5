#include "fclib_error.hpp"

#include <cstdarg>
#include <cstdio>

#include "error_state.hpp"

namespace frix::fclib {

void raise(frix_error code, const char *fmt, ...) {
    char buffer[1024];
    va_list args;
    va_start(args, fmt);
    std::vsnprintf(buffer, sizeof buffer, fmt, args);
    va_end(args);
    throw Failure{fail(code, "%s", buffer)};
}

void reraise(frix_error code, const std::string &context) {
    // Copied first: the core's message lives in the buffer that raise() overwrites.
    const std::string detail = frix_last_error_message();
    raise(code, "%s: %s", context.c_str(), detail.c_str());
}

std::string printable(const std::string &text, bool keep_line_breaks) {
    std::string out;
    out.reserve(text.size());
    for (const char c : text) {
        const auto byte = static_cast<unsigned char>(c);
        const bool line_break = c == '\n' || c == '\t';
        if ((byte < 0x20 || byte == 0x7f) && !(keep_line_breaks && line_break)) {
            char escape[5];
            std::snprintf(escape, sizeof escape, "\\x%02x", byte);
            out += escape;
        } else {
            out += c;
        }
    }
    return out;
}

void raise_from_core(frix_error code, const std::string &context) {
    reraise(code == FRIX_ERR_OUT_OF_MEMORY ? code : FRIX_ERR_FORMAT, context);
}

}  // namespace frix::fclib
