// The text of frix_info_trace: one line per record, each formatted by the solver that
// recorded it.
#include "info.hpp"

namespace frix {

std::string format_event(const frix_info &info, const TraceEvent &e) {
    return e.format ? e.format(info, e) : std::string();
}

std::string format_trace(const frix_info &info) {
    std::string out;
    for (const TraceEvent &e : info.trace) out += format_event(info, e);
    return out;
}

}  // namespace frix
