// Helpers shared by the subcommands.
#include "cli.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstring>
#include <sstream>

namespace frix_cli {
namespace {

std::string directory_of(const std::string &path) {
    const auto slash = path.find_last_of('/');
    if (slash == std::string::npos) return ".";
    if (slash == 0) return "/";
    return path.substr(0, slash);
}

// The file a write to `path` replaces: symbolic links in the last component followed, as
// frix_fclib_write follows them (it keeps a link a link), so the checks see that file.
// A link that cannot be followed is left to the writer to report.
std::string resolve_links(const std::string &path) {
    std::string p = path;
    for (int hops = 0; hops < 40; ++hops) {  // 40: the kernel's own limit (ELOOP)
        struct stat st;
        if (lstat(p.c_str(), &st) != 0 || !S_ISLNK(st.st_mode)) return p;
        char link[PATH_MAX + 1];
        const ssize_t n = readlink(p.c_str(), link, sizeof link);
        if (n <= 0 || static_cast<std::size_t>(n) >= sizeof link) return p;
        const std::string to(link, static_cast<std::size_t>(n));
        p = to[0] == '/' || p.find('/') == std::string::npos ? to : directory_of(p) + "/" + to;
    }
    return p;
}

const char *kind_of(mode_t mode) {
    if (S_ISDIR(mode)) return "a directory";
    if (S_ISFIFO(mode)) return "a FIFO";
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISSOCK(mode)) return "a socket";
    return "of another kind";
}

}  // namespace

void fail(const std::string &message, int code) {
    // One line on stderr, whatever the library's message contains.
    std::string line = message;
    for (char &c : line)
        if (c == '\n' || c == '\r') c = ' ';
    throw Failure{code, line};
}

void check_output(const std::string &output, const std::string &input, bool force) {
    const std::string target = resolve_links(output);
    const std::string it = target == output ? "it" : target + " (where it links)";
    auto refuse = [&](const std::string &why) { fail("cannot write " + output + ": " + why); };
    // lstat only: a FIFO or device is recognised without being opened (opening a FIFO
    // blocks until a reader comes).
    struct stat out;
    if (lstat(target.c_str(), &out) == 0) {
        if (!S_ISREG(out.st_mode))
            refuse(it + " is " + kind_of(out.st_mode) + ", not a regular file");
        struct stat in;
        if (!force && !input.empty() && stat(input.c_str(), &in) == 0 && in.st_dev == out.st_dev &&
            in.st_ino == out.st_ino)
            refuse(it + " is the input file " + input + " (give --force to replace it)");
        // Root passes access() on any file, so no write bit for anyone is read-only too.
        if (access(target.c_str(), W_OK) != 0 || (out.st_mode & 0222) == 0)
            refuse(it + " is read-only");
    } else if (errno != ENOENT) {
        refuse(std::strerror(errno));
    }
    // The new file is written next to the target and renamed over it.
    const std::string dir = directory_of(target);
    struct stat d;
    if (stat(dir.c_str(), &d) != 0) refuse("directory " + dir + ": " + std::strerror(errno));
    if (!S_ISDIR(d.st_mode)) refuse(dir + " is not a directory");
    if (access(dir.c_str(), W_OK | X_OK) != 0)
        refuse("directory " + dir + " is not writable: " + std::strerror(errno));
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
