#include "bench_runner.hpp"

#include "bench_protocol.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>

namespace frix_cli {

double now_seconds() {
    using clock = std::chrono::steady_clock;
    return std::chrono::duration<double>(clock::now().time_since_epoch()).count();
}

std::string signal_name(int sig) {
    switch (sig) {
        case SIGSEGV: return "SIGSEGV";
        case SIGABRT: return "SIGABRT";
        case SIGBUS: return "SIGBUS";
        case SIGFPE: return "SIGFPE";
        case SIGILL: return "SIGILL";
        case SIGKILL: return "SIGKILL";
        case SIGTERM: return "SIGTERM";
        case SIGINT: return "SIGINT";
        case SIGPIPE: return "SIGPIPE";
        case SIGXCPU: return "SIGXCPU";
    }
    return "signal " + std::to_string(sig);
}

namespace {

// The last non-empty line of a log (what a crashing or refusing child said last).
std::string log_tail(const std::string &path) {
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    if (!in) return "";
    std::streamoff size = in.tellg(), from = std::max<std::streamoff>(0, size - 4096);
    in.seekg(from);
    std::string text(static_cast<std::size_t>(size - from), '\0');
    in.read(&text[0], static_cast<std::streamsize>(text.size()));
    while (!text.empty() && (text.back() == '\n' || text.back() == '\r' || text.back() == ' '))
        text.pop_back();
    std::size_t nl = text.find_last_of('\n');
    std::string line = nl == std::string::npos ? text : text.substr(nl + 1);
    if (line.size() > 200) line = line.substr(0, 200) + "...";
    return frix_bench::one_line(line);
}

std::vector<char *> c_argv(std::vector<std::string> &args) {
    std::vector<char *> out;
    for (std::string &a : args) out.push_back(&a[0]);
    out.push_back(nullptr);
    return out;
}

// In the child, between fork and exec: fd 3 = the pipe, 1 and 2 = the log, 0 = /dev/null.
[[noreturn]] void exec_child(std::vector<std::string> args, int pipe_w, int log_fd) {
    ::setpgid(0, 0);
    int w = ::fcntl(pipe_w, F_DUPFD, 10), l = ::fcntl(log_fd, F_DUPFD, 10);
    int in = ::open("/dev/null", O_RDONLY);
    if (w < 0 || l < 0 || in < 0 || ::dup2(in, 0) < 0 || ::dup2(l, 1) < 0 || ::dup2(l, 2) < 0 ||
        ::dup2(w, 3) < 0)
        ::_exit(126);
    // One thread per run: timings then do not depend on how many runs share the cores.
    ::setenv("OPENBLAS_NUM_THREADS", "1", 0);
    ::setenv("OMP_NUM_THREADS", "1", 0);
    std::vector<char *> argv = c_argv(args);
    ::execv(argv[0], argv.data());
    std::fprintf(stderr, "cannot run %s: %s\n", argv[0], std::strerror(errno));
    ::_exit(127);
}

}  // namespace

std::vector<std::size_t> Runner::running_indices() const {
    std::vector<std::size_t> out;
    for (const Child &c : children_) out.push_back(c.spec.index);
    return out;
}

void Runner::start(const RunSpec &spec) {
    RunOutcome fail_out;
    fail_out.index = spec.index;
    fail_out.status = "error";
    fail_out.error = fail_out.time = fail_out.reported_error = NAN;
    int p[2];
    if (::pipe2(p, O_CLOEXEC) != 0) {
        fail_out.note = std::string("pipe: ") + std::strerror(errno);
        failed_starts_.push_back(fail_out);
        return;
    }
    int log = ::open(spec.log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (log < 0) {
        fail_out.note = "cannot write " + spec.log_path + ": " + std::strerror(errno);
        ::close(p[0]);
        ::close(p[1]);
        failed_starts_.push_back(fail_out);
        return;
    }
    std::vector<std::string> args = spec.argv;
    args.push_back("--fd");
    args.push_back("3");
    std::fflush(stdout);
    std::fflush(stderr);
    pid_t pid = ::fork();
    if (pid == 0) exec_child(args, p[1], log);
    ::close(p[1]);
    ::close(log);
    if (pid < 0) {
        fail_out.note = std::string("fork: ") + std::strerror(errno);
        ::close(p[0]);
        failed_starts_.push_back(fail_out);
        return;
    }
    ::setpgid(pid, pid);  // also here, so that a kill right after the fork reaches the group
    ::fcntl(p[0], F_SETFL, ::fcntl(p[0], F_GETFL) | O_NONBLOCK);
    Child c;
    c.spec = spec;
    c.pid = pid;
    c.fd = p[0];
    c.start = now_seconds();
    c.out.index = spec.index;
    c.out.error = c.out.time = c.out.reported_error = NAN;
    children_.push_back(std::move(c));
}

void Runner::consume(Child &c, bool eof) {
    std::size_t pos = 0;
    for (;;) {
        std::size_t nl = c.buffer.find('\n', pos);
        if (nl == std::string::npos) {
            if (!eof || pos >= c.buffer.size()) break;
            nl = c.buffer.size();  // a last line without its newline
        }
        frix_bench::ProtocolLine line = frix_bench::parse_line(c.buffer.substr(pos, nl - pos));
        pos = std::min(nl + 1, c.buffer.size());
        const auto &f = line.fields;
        if (line.kind == 'P' && f.size() >= 3) {
            c.out.contacts = std::atoll(f[0].c_str());
            c.out.dofs = std::atoll(f[1].c_str());
            c.out.stored_blocks = frix_bench::to_double(f[2]);
        } else if (line.kind == 'T' && f.size() >= 3) {
            c.out.trace.push_back({std::atoll(f[0].c_str()), frix_bench::to_double(f[1]),
                                   frix_bench::to_double(f[2])});
        } else if (line.kind == 'R' && f.size() >= 5) {
            c.have_result = true;
            c.out.status = f[0];
            c.out.iterations = std::atoll(f[1].c_str());
            c.out.error = frix_bench::to_double(f[2]);
            c.out.time = frix_bench::to_double(f[3]);
            c.out.reported_error = frix_bench::to_double(f[4]);
            c.out.error_scaled = f.size() >= 6 ? frix_bench::to_double(f[5]) : NAN;
        } else if (line.kind == 'N' && !f.empty()) {
            c.out.note = f[0];
        } else if (line.kind == 'M' && !f.empty()) {
            c.out.peak_memory = frix_bench::to_double(f[0]);
        }
        if (nl >= c.buffer.size()) break;
    }
    c.buffer.erase(0, pos);
}

RunOutcome Runner::finish(Child &c) {
    RunOutcome out = std::move(c.out);
    out.wall = now_seconds() - c.start;
    const bool signaled = WIFSIGNALED(c.wait_status);
    if (!c.have_result || c.killed) {
        // No result: what the run reached is its last trace point (the solver's estimate).
        if (!out.trace.empty()) {
            out.iterations = out.trace.back().iteration;
            out.error = out.trace.back().error;
        }
        out.time = out.wall;
        if (c.killed) {
            out.status = "timeout";
            char buf[96];
            std::snprintf(buf, sizeof buf, "killed after %.1f s (time limit + grace)", out.wall);
            out.note = buf;
        } else if (signaled) {
            out.status = "crash(" + signal_name(WTERMSIG(c.wait_status)) + ")";
        } else {
            out.status = "error";
        }
    }
    if (!c.killed && out.status != "converged") {
        std::string tail = log_tail(c.spec.log_path);
        if (out.note.empty()) out.note = tail;
        if (out.note.empty() && WIFEXITED(c.wait_status) && !c.have_result)
            out.note = "exited with code " + std::to_string(WEXITSTATUS(c.wait_status)) +
                       " without a result";
    }
    return out;
}

std::vector<RunOutcome> Runner::poll(double timeout) {
    std::vector<RunOutcome> done;
    done.swap(failed_starts_);
    if (!done.empty()) return done;

    double now = now_seconds(), wait = timeout;
    std::vector<pollfd> fds;
    for (const Child &c : children_) {
        if (c.fd >= 0) fds.push_back({c.fd, POLLIN, 0});
        if (!c.killed) wait = std::min(wait, c.start + c.spec.wall_limit - now);
        if (c.fd < 0) wait = std::min(wait, 0.01);  // at EOF: only the exit is awaited
    }
    int ms = static_cast<int>(std::ceil(std::max(wait, 0.0) * 1000));
    if (::poll(fds.empty() ? nullptr : fds.data(), fds.size(), ms) < 0 && errno != EINTR)
        ms = 0;

    for (Child &c : children_) {
        while (c.fd >= 0) {
            char buf[8192];
            ssize_t n = ::read(c.fd, buf, sizeof buf);
            if (n > 0) {
                c.buffer.append(buf, static_cast<std::size_t>(n));
                consume(c, false);
            } else if (n == 0 || (errno != EAGAIN && errno != EINTR)) {
                consume(c, true);
                ::close(c.fd);
                c.fd = -1;
            } else {
                break;
            }
        }
        if (!c.exited) {
            // Seen ended but not yet reaped (WNOWAIT), the pid cannot be reused: kill what
            // the child may have left in its group holding the pipe, then reap it.
            siginfo_t si;
            si.si_pid = 0;
            if (::waitid(P_PID, static_cast<id_t>(c.pid), &si, WEXITED | WNOHANG | WNOWAIT) == 0 &&
                si.si_pid == c.pid) {
                ::kill(-c.pid, SIGKILL);
                // A run that did not say its peak (killed, crashed): the system's, which
                // counts the bench's own image at the fork too (Linux keeps it over exec).
                struct rusage usage {};
                if (::wait4(c.pid, &c.wait_status, 0, &usage) == c.pid && usage.ru_maxrss > 0 &&
                    !std::isfinite(c.out.peak_memory))
                    c.out.peak_memory = 1024.0 * static_cast<double>(usage.ru_maxrss);  // kB on Linux
                c.exited = true;
            }
        }
        if (!c.exited && !c.killed && now_seconds() - c.start > c.spec.wall_limit) {
            ::kill(-c.pid, SIGKILL);
            c.killed = true;
        }
    }
    for (std::size_t k = 0; k < children_.size();) {
        Child &c = children_[k];
        if (c.exited && c.fd < 0) {
            done.push_back(finish(c));
            children_.erase(children_.begin() + static_cast<std::ptrdiff_t>(k));
        } else {
            ++k;
        }
    }
    return done;
}

void Runner::kill_all() {
    for (Child &c : children_) {
        if (!c.exited) {
            ::kill(-c.pid, SIGKILL);
            ::waitpid(c.pid, &c.wait_status, 0);
        }
        if (c.fd >= 0) ::close(c.fd);
    }
    children_.clear();
}

std::string capture_output(const std::vector<std::string> &argv, int *exit_code) {
    *exit_code = -1;
    int p[2];
    if (::pipe2(p, O_CLOEXEC) != 0) return "";
    std::fflush(stdout);
    std::fflush(stderr);
    pid_t pid = ::fork();
    if (pid == 0) {
        if (::dup2(p[1], 1) < 0) ::_exit(126);
        std::vector<std::string> args = argv;
        std::vector<char *> cargv = c_argv(args);
        ::execv(cargv[0], cargv.data());
        ::_exit(127);
    }
    ::close(p[1]);
    std::string out;
    if (pid > 0) {
        char buf[4096];
        ssize_t n;
        while ((n = ::read(p[0], buf, sizeof buf)) > 0 || (n < 0 && errno == EINTR))
            if (n > 0) out.append(buf, static_cast<std::size_t>(n));
        int status = 0;
        if (::waitpid(pid, &status, 0) == pid && WIFEXITED(status)) *exit_code = WEXITSTATUS(status);
    }
    ::close(p[0]);
    return out;
}

}  // namespace frix_cli
