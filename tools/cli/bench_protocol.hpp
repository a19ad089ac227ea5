// The lines a `frix bench` child run writes to its parent through a pipe (the parent reads
// them as they come, so the trace of a run that is later killed is not lost):
//
//   P <contacts> <dofs> <stored blocks>   the problem, once read (frix's runs only: the bench
//                                         reads no problem itself, a hostile file then costs
//                                         only its own runs)
//   T <iteration> <elapsed s> <error>     one point of the trace (thinned, see TraceThinner)
//   R <status> <iterations> <error> <time s> <reported error> <scaled error>   the result, once
//     (error: frix's measure of Siconos's kind; scaled error: frix's default measure; for a
//     global problem each the larger of it and the equilibrium residual)
//   N <text>                              a note (one line), e.g. a library message
//   M <bytes>                             the run's peak resident memory, after R (VmHWM:
//                                         the program's own, from its exec)
//
// Fields are tab-separated; numbers are written so that they read back exactly. Header-only
// because two executables speak it: `frix bench-run` (frix's solvers) and `frix-siconos`
// (the Siconos comparator, built only when Siconos is installed).
#pragma once

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace frix_bench {

// Keeps a bounded, plot-worthy subset of the per-iteration points: the first point, every
// point that reaches a new tenth of a decade below the best error so far (so the time to
// reach any 10^-k is exact), every point in a higher tenth of a decade than the last one kept
// (a full check that belies an estimate below it, such as NSGS's light error: a report can
// then tell a time that a later point belies, as settled_table.py marks), and points spaced
// geometrically in time (so stalls still show). NSGS can do 10^5 sweeps in a run; this keeps
// a few hundred points: a rise is kept once, until a new best.
class TraceThinner {
public:
    bool keep(double elapsed, double error) {
        const bool finite = std::isfinite(error);
        bool take = false;
        if (count_ == 0) {
            take = true;
        } else if (finite && (bin(error) < best_bin_ || bin(error) > last_bin_)) {
            take = true;
        } else if (elapsed >= 1.5 * last_time_ && elapsed - last_time_ >= 1e-4) {
            take = true;
        }
        ++count_;
        if (!take) return false;
        if (finite && bin(error) < best_bin_) best_bin_ = bin(error);
        if (finite) last_bin_ = bin(error);
        last_time_ = elapsed;
        return true;
    }

private:
    static long bin(double error) {
        if (error <= 0) return -100000;  // exactly solved: below every level
        return static_cast<long>(std::floor(10.0 * std::log10(error)));
    }
    long best_bin_ = 100000;
    long last_bin_ = 100000;  // the last point kept
    double last_time_ = 0;
    std::int64_t count_ = 0;
};

// "%.17g" reads back to the same double; NaN and Inf are written as "nan" / "inf".
inline std::string exact(double v) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return buf;
}

inline std::string one_line(std::string s) {
    for (char &c : s)
        if (c == '\n' || c == '\r' || c == '\t') c = ' ';
    return s;
}

inline std::string trace_line(std::int64_t iteration, double elapsed, double error) {
    return "T\t" + std::to_string(iteration) + "\t" + exact(elapsed) + "\t" + exact(error) + "\n";
}

// The process's peak resident memory in bytes (Linux: VmHWM of /proc/self/status), NaN
// where the system does not say.
inline double peak_resident_bytes() {
    double bytes = NAN;
    if (std::FILE *f = std::fopen("/proc/self/status", "r")) {
        char line[256];
        while (std::fgets(line, sizeof line, f))
            if (std::sscanf(line, "VmHWM: %lf kB", &bytes) == 1) {
                bytes *= 1024.0;
                break;
            }
        std::fclose(f);
    }
    return bytes;
}

inline std::string peak_memory_line() { return "M\t" + exact(peak_resident_bytes()) + "\n"; }

inline std::string result_line(const std::string &status, std::int64_t iterations, double error,
                               double time, double reported_error, double error_scaled) {
    return "R\t" + status + "\t" + std::to_string(iterations) + "\t" + exact(error) + "\t" +
           exact(time) + "\t" + exact(reported_error) + "\t" + exact(error_scaled) + "\n";
}

inline std::string problem_line(std::int64_t contacts, std::int64_t dofs, double stored_blocks) {
    return "P\t" + std::to_string(contacts) + "\t" + std::to_string(dofs) + "\t" + exact(stored_blocks) + "\n";
}

inline std::string note_line(const std::string &text) { return "N\t" + one_line(text) + "\n"; }

// The error field of a global problem's run, frix's and Siconos's alike: the larger of the
// relative error and the equilibrium residual (an answer that breaks M v = H r + f is not
// accurate, whatever its contact error; r = v = 0 has none).
inline double global_error(double error, double equilibrium) {
    return std::isnan(equilibrium) ? NAN : std::max(error, equilibrium);
}

// Writes the whole line or gives up silently: a parent that went away must not turn into
// a crash of the child (SIGPIPE is ignored by the children for the same reason).
inline void write_line(int fd, const std::string &line) {
    const char *p = line.data();
    std::size_t left = line.size();
    while (left > 0) {
        ssize_t n = ::write(fd, p, left);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return;
        p += n;
        left -= static_cast<std::size_t>(n);
    }
}

// The median of `values` (the mean of the middle two where their count is even); NaN if none.
inline double median(std::vector<double> values) {
    if (values.empty()) return NAN;
    std::sort(values.begin(), values.end());
    const std::size_t k = values.size() / 2;
    return values.size() % 2 ? values[k] : 0.5 * (values[k - 1] + values[k]);
}

// Timing: a short solve is repeated from the same start (r = 0) in the same process and the
// median time reported, for frix and Siconos alike. One cold call of a microsecond solve
// measures page faults and cache misses more than the solver, and the machines are shared
// and noisy. The first solve gives the trace, the status and the error; the repeats only
// the time.
class RepeatTimer {
   public:
    static constexpr int kMaxSolves = 9;
    static constexpr double kBudget = 0.25;  // seconds of solving in all, repeats included

    void add(double seconds) { times_.push_back(seconds); }
    // Whether to solve once more: the time so far is short and the count is below the cap.
    bool again() const {
        double total = 0.0;
        for (double t : times_) total += t;
        return !times_.empty() && (int)times_.size() < kMaxSolves && std::isfinite(total) &&
               total + total / (double)times_.size() <= kBudget;
    }
    double median() const { return frix_bench::median(times_); }
    int solves() const { return (int)times_.size(); }

   private:
    std::vector<double> times_;
};

// The parent's side: one parsed line.
struct ProtocolLine {
    char kind = 0;  // 'P', 'T', 'R', 'N', 'M', or 0 for a line that is none of them
    std::vector<std::string> fields;
};

inline ProtocolLine parse_line(const std::string &line) {
    ProtocolLine out;
    if (line.size() < 2 || line[1] != '\t') return out;
    out.kind = line[0];
    std::size_t start = 2;
    for (;;) {
        std::size_t tab = line.find('\t', start);
        out.fields.push_back(line.substr(start, tab == std::string::npos ? tab : tab - start));
        if (tab == std::string::npos) break;
        start = tab + 1;
    }
    return out;
}

inline double to_double(const std::string &s) {
    if (s.empty()) return NAN;
    char *end = nullptr;
    double v = std::strtod(s.c_str(), &end);
    return end && *end == '\0' ? v : NAN;
}

}  // namespace frix_bench
