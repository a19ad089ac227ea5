// `frix bench`: runs in child processes, so that a crash, an exit() or a hang costs one run
// and not the campaign. Each child gets its own process group, a wall-clock limit enforced
// here (SIGKILL to the group), stdout/stderr into a log file, and a pipe on fd 3 for the
// bench protocol, read as it comes.
#pragma once

#include "bench.hpp"

#include <sys/types.h>

#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

namespace frix_cli {

struct RunSpec {
    std::size_t index = 0;          // the caller's key for the run
    std::vector<std::string> argv;  // argv[0] is the program's path; "--fd 3" is added
    std::string log_path;           // the child's stdout and stderr
    double wall_limit = 0;          // seconds from the start; the child is killed after it
};

struct RunOutcome {
    std::size_t index = 0;
    std::string status;  // from the child's result line, or timeout / crash(SIG) / error
    std::int64_t iterations = 0;
    double error = 0, time = 0, reported_error = 0, error_scaled = NAN;
    double wall = 0;     // seconds from start to end, as seen from here
    double peak_memory = NAN;  // bytes: the child's peak resident memory (problem read included)
                               // as it said it, or the system's for a run that did not
    std::string note;
    std::vector<TracePoint> trace;
    // The problem's sizes as the run read them (its P line); -1 and NaN: the run did not say
    // (it did not get that far, or it is Siconos's, which does not say).
    std::int64_t contacts = -1, dofs = -1;
    double stored_blocks = NAN;
    bool problem_read() const { return contacts >= 0; }
};

class Runner {
public:
    explicit Runner(std::size_t jobs) : jobs_(jobs ? jobs : 1) {}
    ~Runner() { kill_all(); }
    Runner(const Runner &) = delete;
    Runner &operator=(const Runner &) = delete;

    bool can_start() const { return children_.size() < jobs_; }
    std::size_t running() const { return children_.size(); }
    std::vector<std::size_t> running_indices() const;
    // Forks and executes spec.argv; a failure to start is reported as an outcome by poll().
    void start(const RunSpec &spec);
    // Waits at most `timeout` seconds for output or an end; returns the runs that ended.
    std::vector<RunOutcome> poll(double timeout);
    // Kills every running child and reaps it (used on interruption and destruction).
    void kill_all();

private:
    struct Child {
        RunSpec spec;
        pid_t pid = -1;
        int fd = -1;  // read end of the protocol pipe, -1 once at EOF
        double start = 0;
        bool killed = false, exited = false, have_result = false;
        int wait_status = 0;
        std::string buffer;
        RunOutcome out;
    };
    void consume(Child &c, bool eof);
    RunOutcome finish(Child &c);

    std::size_t jobs_;
    std::vector<Child> children_;
    std::vector<RunOutcome> failed_starts_;
};

// Runs argv to its end and returns its stdout ("" if it cannot be started).
std::string capture_output(const std::vector<std::string> &argv, int *exit_code);

// "SIGSEGV" for 11, ...
std::string signal_name(int sig);

// Monotonic seconds.
double now_seconds();

}  // namespace frix_cli
