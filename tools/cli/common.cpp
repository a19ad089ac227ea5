// Helpers shared by the subcommands.
#include "args.hpp"
#include "cli.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <climits>
#include <cmath>
#include <cstring>
#include <new>
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

// ---- read_problem with a time limit: the file is read in a child process, which sends the
// problem back through a pipe in the layout both ends share (they are the same executable):
// 'E', the reader's message; or 'P', kind, contacts, dofs, title, each matrix as CSC (rows,
// cols, nnz, colptr, rowind, values: W, or M and H), then q, mu (local) or f, w, mu (global).

double steady_seconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

constexpr int kChildOutOfMemory = 3;  // the reading child's exit code when it ran out of memory

struct ChildWriter {
    int fd;
    bool ok = true;
    void bytes(const void *data, std::size_t size) {
        const char *p = static_cast<const char *>(data);
        while (ok && size > 0) {
            const ssize_t n = ::write(fd, p, size);
            if (n < 0 && errno == EINTR) continue;
            if (n <= 0) ok = false;
            else p += n, size -= static_cast<std::size_t>(n);
        }
    }
    void integer(int64_t v) { bytes(&v, sizeof v); }
    void text(const std::string &t) {
        integer(static_cast<int64_t>(t.size()));
        bytes(t.data(), t.size());
    }
    void doubles(const double *v, int64_t count) { bytes(v, static_cast<std::size_t>(count) * sizeof(double)); }
    void matrix(const frix_matrix *m) {
        const int64_t cols = frix_matrix_cols(m);
        int64_t nnz = 0;
        if (frix_matrix_to_csc(m, &nnz, nullptr, nullptr, nullptr) != FRIX_OK) {
            ok = false;
            return;
        }
        std::vector<int64_t> colptr(static_cast<std::size_t>(cols) + 1), rowind(static_cast<std::size_t>(std::max<int64_t>(nnz, 1)));
        std::vector<double> values(rowind.size());
        if (frix_matrix_to_csc(m, &nnz, colptr.data(), rowind.data(), values.data()) != FRIX_OK) {
            ok = false;
            return;
        }
        integer(frix_matrix_rows(m));
        integer(cols);
        integer(nnz);
        bytes(colptr.data(), colptr.size() * sizeof(int64_t));
        bytes(rowind.data(), static_cast<std::size_t>(nnz) * sizeof(int64_t));
        doubles(values.data(), nnz);
    }
};

[[noreturn]] void read_in_child(const std::string &path, int fd) {
    int code = 0;
    try {
        frix_problem *raw = nullptr;
        const frix_error err = frix_read_problem(path.c_str(), &raw);
        ProblemPtr p(raw);
        ChildWriter w{fd};
        if (err != FRIX_OK) {
            w.bytes("E", 1);
            w.text(library_message(err));
        } else {
            const frix_problem_kind kind = frix_problem_get_kind(p.get());
            const bool global = kind == FRIX_PROBLEM_GLOBAL || kind == FRIX_PROBLEM_ROLLING_GLOBAL;
            const bool rolling = kind == FRIX_PROBLEM_ROLLING_LOCAL || kind == FRIX_PROBLEM_ROLLING_GLOBAL;
            const bool spinning = frix_problem_mu_s(p.get()) != nullptr;
            const int64_t nc = frix_problem_contacts(p.get()), n = frix_problem_dofs(p.get());
            const int64_t m = frix_problem_contact_dofs(p.get());
            w.bytes("P", 1);
            w.integer((global ? 1 : 0) + (rolling ? 2 : 0) + (spinning ? 4 : 0));
            w.integer(nc);
            w.integer(n);
            w.text(frix_problem_title(p.get()));
            w.text(frix_problem_description(p.get()));
            w.text(frix_problem_math_info(p.get()));
            if (global) {
                w.matrix(frix_problem_M(p.get()));
                w.matrix(frix_problem_H(p.get()));
                w.doubles(frix_problem_f(p.get()), n);
                w.doubles(frix_problem_w(p.get()), m);
            } else {
                w.matrix(frix_problem_W(p.get()));
                w.doubles(frix_problem_q(p.get()), m);
            }
            w.doubles(frix_problem_mu(p.get()), nc);
            if (rolling) w.doubles(frix_problem_mu_r(p.get()), nc);
            if (spinning) w.doubles(frix_problem_mu_s(p.get()), nc);
        }
        code = w.ok ? 0 : 1;
    } catch (const std::bad_alloc &) {
        code = kChildOutOfMemory;
    } catch (...) {
        code = 1;
    }
    ::_exit(code);  // no atexit handlers, no stdio flush: the parent's are not the child's
}

// The parent's end: every read waits at most until the deadline.
struct ChildReader {
    int fd;
    double deadline;
    bool timed_out = false;
    bool take(void *data, std::size_t size) {
        char *p = static_cast<char *>(data);
        while (size > 0) {
            const double left = deadline - steady_seconds();
            pollfd pfd{fd, POLLIN, 0};
            const int ms = left > 0 ? static_cast<int>(std::min(std::ceil(left * 1000.0), 1e9)) : 0;
            const int ready = ::poll(&pfd, 1, ms);
            if (ready < 0 && errno == EINTR) continue;
            if (ready == 0) {
                timed_out = true;
                return false;
            }
            const ssize_t n = ::read(fd, p, size);
            if (n < 0 && (errno == EINTR || errno == EAGAIN)) continue;
            if (n <= 0) return false;
            p += n;
            size -= static_cast<std::size_t>(n);
        }
        return true;
    }
    bool integer(int64_t &v, int64_t max) { return take(&v, sizeof v) && v >= 0 && v <= max; }
    template <class T>
    bool array(std::vector<T> &v, int64_t count) {
        v.assign(static_cast<std::size_t>(std::max<int64_t>(count, 1)), T());
        return take(v.data(), static_cast<std::size_t>(count) * sizeof(T));
    }
};

struct MatrixFree {
    void operator()(frix_matrix *m) const { frix_matrix_free(m); }
};

// What a problem sent by the child borrows: it lives as long as the problem (ProblemDeleter).
struct SentProblem {
    std::unique_ptr<frix_matrix, MatrixFree> W, M, H;
    std::vector<double> q, f, w, mu, mu_r, mu_s;
};

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
    std::string text = msg && *msg ? msg : frix_error_string(err);
    // "out of memory" alone does not say which limit was hit nor what to do about it.
    if (err == FRIX_ERR_OUT_OF_MEMORY) text += " (" + out_of_memory_advice() + ")";
    return text;
}

std::string bytes_text(double bytes) {
    char buf[32];
    if (!(bytes >= 0.0) || !std::isfinite(bytes)) return "unknown";
    if (bytes < 1e3) std::snprintf(buf, sizeof buf, "%.0f B", bytes);
    else if (bytes < 1e6) std::snprintf(buf, sizeof buf, "%.3g kB", bytes / 1e3);
    else if (bytes < 1e9) std::snprintf(buf, sizeof buf, "%.3g MB", bytes / 1e6);
    else std::snprintf(buf, sizeof buf, "%.3g GB", bytes / 1e9);
    return buf;
}

namespace {

// The process's address space and resident memory (Linux: /proc/self/statm), 0 if unknown.
void process_memory(double &address_space, double &resident) {
    address_space = resident = 0.0;
    const long page = ::sysconf(_SC_PAGESIZE);
    if (std::FILE *f = std::fopen("/proc/self/statm", "r")) {
        long size = 0, rss = 0;
        if (std::fscanf(f, "%ld %ld", &size, &rss) == 2 && page > 0) {
            address_space = static_cast<double>(size) * static_cast<double>(page);
            resident = static_cast<double>(rss) * static_cast<double>(page);
        }
        std::fclose(f);
    }
}

// What the machine (or the control group, in a container) lets the process use, 0 if unknown:
// the ground of the library's default memory_limit.
double machine_memory() {
    double bytes = 0.0;
    const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
    if (pages > 0 && page > 0) bytes = static_cast<double>(pages) * static_cast<double>(page);
    for (const char *path : {"/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory/memory.limit_in_bytes"})
        if (std::FILE *f = std::fopen(path, "r")) {
            double limit = 0.0;  // "max" (no limit) does not parse
            if (std::fscanf(f, "%lf", &limit) == 1 && limit > 0.0 && (bytes == 0.0 || limit < bytes)) bytes = limit;
            std::fclose(f);
        }
    return bytes;
}

}  // namespace

std::string out_of_memory_advice() {
    double space = 0.0, resident = 0.0;
    process_memory(space, resident);
    struct rlimit as {};
    std::string text;
    if (::getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY) {
        text = "the process's address space is limited to " + bytes_text(static_cast<double>(as.rlim_cur)) +
               " ('ulimit -v') and spans " + bytes_text(space) + " now; raise 'ulimit -v'";
    } else {
        text = "the process holds " + bytes_text(resident) + " of the " + bytes_text(machine_memory()) +
               " the machine lets it use; free memory";
    }
    return text + ", solve a smaller problem, or give --set memory_limit=BYTES so that a solver "
                  "that factorises stops with status 'memory limit reached' rather than fail";
}

std::string memory_limit_note(const frix_options *options, int64_t iterations) {
    double limit = 0.0;
    if (!options || frix_options_get_double(options, FRIX_OPT_MEMORY_LIMIT, &limit) != FRIX_OK) limit = 0.0;
    double space = 0.0, resident = 0.0;
    process_memory(space, resident);
    std::string text = "a factorisation the solver needed would have taken more than ";
    if (limit > 0.0)
        text += "the memory limit of " + bytes_text(limit) + " (--set memory_limit)";
    else
        text += "the memory left (memory_limit 0: the " + bytes_text(machine_memory()) +
                " the machine lets the process use, less the " + bytes_text(resident) + " it holds)";
    text += ", so it was not started";
    if (iterations == 0)
        text += "; the iterate reported is the start (r = 0, or the guess it was given), not an answer the solver "
                "found";
    return text + ". Give a larger --set memory_limit=BYTES (0: all the memory there is), a solver that "
                  "factorises nothing (nsgs), or a smaller problem";
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

ProblemPtr read_problem(const std::string &path, double time_limit, double seconds_left) {
    int p[2];
    if (::pipe2(p, O_CLOEXEC) != 0) return read_problem(path);  // no child: read here, unbounded
    std::fflush(stdout);
    std::fflush(stderr);
    const pid_t pid = ::fork();
    if (pid == 0) {
        ::close(p[0]);
        read_in_child(path, p[1]);
    }
    ::close(p[1]);
    if (pid < 0) {
        ::close(p[0]);
        return read_problem(path);
    }
    // The child is killed and reaped on every way out, a failure included.
    struct Child {
        pid_t pid;
        int fd;
        int status = 0;
        bool reaped = false;
        void reap() {
            if (reaped) return;
            while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {}
            reaped = true;
        }
        ~Child() {
            if (!reaped) {
                ::kill(pid, SIGKILL);
                reap();
            }
            ::close(fd);
        }
    } child{pid, p[0]};
    ChildReader in{p[0], steady_seconds() + std::max(seconds_left, 0.0)};
    auto broken = [&]() {
        char limit[32];
        std::snprintf(limit, sizeof limit, "%g", time_limit);
        if (in.timed_out)
            fail("reading " + path + " took longer than the time limit of " + limit +
                     " s (give a larger --time-limit, or 0 for none)",
                 kExitNotConverged);
        ::kill(pid, SIGKILL);  // a child that sent garbage is not waited for
        child.reap();
        if (WIFSIGNALED(child.status))
            fail("cannot read " + path + ": the reader stopped with signal " + std::to_string(WTERMSIG(child.status)) +
                 " (" + strsignal(WTERMSIG(child.status)) + ")");
        if (WIFEXITED(child.status) && WEXITSTATUS(child.status) == kChildOutOfMemory)
            fail("cannot read " + path + ": out of memory while reading it (the process's memory limit, "
                 "'ulimit -v', may be too small for this problem)");
        fail("cannot read " + path + ": the reading process ended before it sent the whole problem");
    };
    constexpr int64_t kMaxCount = int64_t(1) << 48;  // a bound on every size, against garbage
    char tag = 0;
    if (!in.take(&tag, 1)) broken();
    if (tag == 'E') {
        int64_t size = 0;
        std::string message;
        if (!in.integer(size, 1 << 20)) broken();
        message.resize(static_cast<std::size_t>(size));
        if (size > 0 && !in.take(&message[0], message.size())) broken();
        fail("cannot read " + path + ": " + message);
    }
    if (tag != 'P') broken();
    int64_t form = 0, nc = 0, n = 0;  // form: 1 global, + 2 rolling, + 4 spinning (with rolling)
    if (!in.integer(form, 7) || (form >= 4 && (form & 2) == 0) || !in.integer(nc, kMaxCount) ||
        !in.integer(n, kMaxCount))
        broken();
    // The problem's texts: title, description, math info (the library keeps them short).
    std::string texts[3];
    for (std::string &text : texts) {
        int64_t size = 0;
        if (!in.integer(size, 1 << 20)) broken();
        text.resize(static_cast<std::size_t>(size));
        if (size > 0 && !in.take(&text[0], text.size())) broken();
    }
    auto data = std::make_shared<SentProblem>();
    auto matrix = [&](std::unique_ptr<frix_matrix, MatrixFree> &out) {
        int64_t rows = 0, cols = 0, nnz = 0;
        std::vector<int64_t> colptr, rowind;
        std::vector<double> values;
        if (!in.integer(rows, kMaxCount) || !in.integer(cols, kMaxCount) || !in.integer(nnz, kMaxCount) ||
            !in.array(colptr, cols + 1) || !in.array(rowind, nnz) || !in.array(values, nnz))
            broken();
        frix_matrix *m = nullptr;
        const frix_error err = frix_matrix_from_csc(rows, cols, colptr.data(), rowind.data(), values.data(), &m);
        out.reset(m);
        if (err != FRIX_OK) fail("cannot read " + path + ": " + library_message(err));
    };
    frix_problem *raw = nullptr;
    frix_error err;
    const bool global = (form & 1) != 0, rolling = (form & 2) != 0, spinning = (form & 4) != 0;
    const int64_t m = (spinning ? 6 : rolling ? 5 : 3) * nc;
    const auto coefficients = [&]() {
        return in.array(data->mu, nc) && (!rolling || in.array(data->mu_r, nc)) &&
               (!spinning || in.array(data->mu_s, nc));
    };
    SentProblem &d = *data;
    if (global) {
        matrix(d.M);
        matrix(d.H);
        if (!in.array(d.f, n) || !in.array(d.w, m) || !coefficients()) broken();
        child.reap();
        if (spinning)
            err = frix_problem_spinning_global(d.M.get(), d.H.get(), d.f.data(), d.w.data(), d.mu.data(),
                                               d.mu_r.data(), d.mu_s.data(), nc, &raw);
        else if (rolling)
            err = frix_problem_rolling_global(d.M.get(), d.H.get(), d.f.data(), d.w.data(), d.mu.data(),
                                              d.mu_r.data(), nc, &raw);
        else
            err = frix_problem_global(d.M.get(), d.H.get(), d.f.data(), d.w.data(), d.mu.data(), nc, &raw);
    } else {
        matrix(d.W);
        if (!in.array(d.q, m) || !coefficients()) broken();
        child.reap();
        if (spinning)
            err = frix_problem_spinning_local(d.W.get(), d.q.data(), d.mu.data(), d.mu_r.data(), d.mu_s.data(), nc,
                                              &raw);
        else if (rolling)
            err = frix_problem_rolling_local(d.W.get(), d.q.data(), d.mu.data(), d.mu_r.data(), nc, &raw);
        else
            err = frix_problem_local(d.W.get(), d.q.data(), d.mu.data(), nc, &raw);
    }
    ProblemPtr problem(raw, ProblemDeleter{data});
    if (err == FRIX_OK) err = frix_problem_set_title(problem.get(), texts[0].c_str());
    if (err == FRIX_OK) err = frix_problem_set_description(problem.get(), texts[1].c_str());
    if (err == FRIX_OK) err = frix_problem_set_math_info(problem.get(), texts[2].c_str());
    if (err != FRIX_OK) fail("cannot read " + path + ": " + library_message(err));
    return problem;
}

const char *kind_name(frix_problem_kind kind) {
    switch (kind) {
        case FRIX_PROBLEM_LOCAL: return "local";
        case FRIX_PROBLEM_GLOBAL: return "global";
        case FRIX_PROBLEM_ROLLING_LOCAL: return "rolling-local";
        case FRIX_PROBLEM_ROLLING_GLOBAL: return "rolling-global";
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

int64_t parse_guess_number(const char *command, const std::string &text) {
    const int64_t k = parse_int(command, "--guess", text);
    if (k < 1) usage_error(command, "--guess expects a guess number (1, 2, ...), got '" + text + "'");
    return k;
}

// r, u (and v) from guess k (1-based) of the FCLIB file `file`, which holds `problem`.
void start_from_guess(const std::string &file, const frix_problem *problem, int64_t k, double *r, double *u,
                      double *v) {
    int64_t count = 0;
    if (frix_error err = frix_fclib_guess_count(file.c_str(), &count))
        fail("--guess: cannot read the guesses of " + file + ": " + library_message(err));
    if (k > count)
        fail("--guess " + std::to_string(k) + ": " + file + " holds " + std::to_string(count) + " guess" +
             (count == 1 ? "" : "es"));
    if (frix_error err = frix_fclib_read_guess(file.c_str(), problem, k - 1, r, u, v))
        fail("--guess " + std::to_string(k) + ": " + library_message(err));
}

}  // namespace frix_cli
