// Progress lines of the solvers (option verbosity > 0) go to the host's log sink
// (frix_options_set_log), or to stderr where none is set: a host can route them.
#pragma once

#include "options.hpp"

namespace frix {

// One line; `format` has no trailing newline. o may be null (then stderr).
void log_line(const frix_options *o, const char *format, ...) __attribute__((format(printf, 2, 3)));

}  // namespace frix
