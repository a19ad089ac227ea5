// Helpers shared by the subcommands.
#include "cli.hpp"

#include <sstream>

namespace frix_cli {

void fail(const std::string &message, int code) {
    // One line on stderr, whatever the library's message contains.
    std::string line = message;
    for (char &c : line)
        if (c == '\n' || c == '\r') c = ' ';
    throw Failure{code, line};
}

std::vector<std::string> split(const std::string &text, char sep) {
    std::vector<std::string> out;
    std::stringstream in(text);
    std::string item;
    while (std::getline(in, item, sep))
        if (!item.empty()) out.push_back(item);
    return out;
}

std::string library_message(frix_error err) {
    const char *msg = frix_last_error_message();
    if (msg && *msg) return msg;
    return frix_error_string(err);
}

ProblemPtr read_problem(const std::string &path) {
    frix_problem *p = nullptr;
    frix_error err = frix_read_problem(path.c_str(), &p);
    if (err != FRIX_OK) {
        frix_problem_free(p);
        fail("cannot read " + path + ": " + library_message(err));
    }
    return ProblemPtr(p);
}

const char *kind_name(frix_problem_kind kind) {
    switch (kind) {
        case FRIX_PROBLEM_LOCAL: return "local";
        case FRIX_PROBLEM_GLOBAL: return "global";
    }
    return "unknown";
}

const char *status_token(frix_status status) {
    switch (status) {
        case FRIX_STATUS_NOT_RUN: return "not_run";
        case FRIX_STATUS_CONVERGED: return "converged";
        case FRIX_STATUS_MAX_ITER: return "max_iter";
        case FRIX_STATUS_TIME_LIMIT: return "time_limit";
        case FRIX_STATUS_STAGNATED: return "stagnated";
        case FRIX_STATUS_DIVERGED: return "diverged";
        case FRIX_STATUS_NUMERICAL_FAILURE: return "numerical_failure";
        case FRIX_STATUS_STOPPED_BY_CALLBACK: return "stopped_by_callback";
        case FRIX_STATUS_MEMORY_LIMIT: return "memory_limit";
    }
    return "unknown";
}

}  // namespace frix_cli
