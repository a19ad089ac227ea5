#include "log.hpp"

#include <cstdarg>
#include <cstdio>
#include <string>

namespace frix {

void log_line(const frix_options *o, const char *format, ...) {
    char small[256];
    std::va_list args;
    va_start(args, format);
    const int n = std::vsnprintf(small, sizeof small, format, args);
    va_end(args);
    if (n < 0) return;
    std::string big;
    const char *line = small;
    if ((size_t)n >= sizeof small) {
        big.resize((size_t)n + 1);
        va_start(args, format);
        std::vsnprintf(&big[0], big.size(), format, args);
        va_end(args);
        big.resize((size_t)n);
        line = big.c_str();
    }
    if (o && o->log)
        o->log(o->log_data, line);
    else
        std::fprintf(stderr, "%s\n", line);
}

}  // namespace frix
