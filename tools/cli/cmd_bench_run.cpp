// `frix bench-run FILE --solver NAME --tol T --max-iter N --time-limit S [--guess K] --fd FD` (hidden):
// one run of a `frix bench` campaign, in a child process of its own. It reads FILE, says its
// sizes, then streams the trace and the result to FD in the bench protocol
// (bench_protocol.hpp). An unreadable FILE is the result "unreadable" with the reader's
// message as the note.
//
// For the bench's own tests, FRIX_BENCH_FAULT=hang|crash[:TEXT][,...] makes the runs whose
// "FILE SOLVER" contains TEXT (all runs without it) hang or abort instead of solving: that
// is how the isolation (time limit, crash) is proven without a solver that misbehaves.
#include "args.hpp"
#include "bench_protocol.hpp"
#include "cli.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

namespace frix_cli {
namespace {

void injected_fault(const std::string &file, const std::string &solver) {
    const char *env = std::getenv("FRIX_BENCH_FAULT");
    if (!env || !*env) return;
    std::string all = env;
    for (std::size_t start = 0; start <= all.size();) {
        std::size_t comma = all.find(',', start);
        if (comma == std::string::npos) comma = all.size();
        std::string spec = all.substr(start, comma - start), kind = spec, text;
        start = comma + 1;
        std::size_t colon = spec.find(':');
        if (colon != std::string::npos) {
            kind = spec.substr(0, colon);
            text = spec.substr(colon + 1);
        }
        if (!text.empty() && (file + " " + solver).find(text) == std::string::npos) continue;
        if (kind == "hang")
            for (;;) ::pause();
        if (kind == "crash") std::abort();
    }
}

struct Stream {
    frix_bench::TraceThinner thinner;
    int fd;
};

int on_progress(void *data, int64_t iteration, double error, double elapsed) {
    auto *s = static_cast<Stream *>(data);
    if (s->thinner.keep(elapsed, error))
        frix_bench::write_line(s->fd, frix_bench::trace_line(iteration, elapsed, error));
    return 0;
}

// Sets an option the solver has; an int option is clamped into its bounds (a campaign's
// --max-iter applies to solvers with different ranges).
void set_option(frix_options *o, frix_option_key key, double value, const char *label) {
    double lo = 0, hi = 0;
    int is_int = 0;
    frix_error err = frix_options_bounds(o, key, &lo, &hi, &is_int);
    if (err != FRIX_OK) fail(std::string("bench-run: ") + label + ": " + library_message(err));
    if (is_int)
        err = frix_options_set_int(o, key, static_cast<int64_t>(std::clamp(value, lo, hi)));
    else
        err = frix_options_set_double(o, key, value);
    if (err != FRIX_OK) fail(std::string("bench-run: ") + label + ": " + library_message(err));
}

}  // namespace

int cmd_bench_run(int argc, char **argv) {
    ArgCursor args("bench-run", argc, argv);
    std::string file, solver, v;
    std::vector<std::pair<frix_option_key, double>> settings;  // --set NAME=VALUE
    double tol = 1e-8, time_limit = 0;
    int64_t max_iter = 0, guess = 0;
    int fd = -1;
    while (!args.done()) {
        if (args.option("--solver", v)) {
            solver = v;
        } else if (args.option("--tol", v)) {
            tol = parse_double("bench-run", "--tol", v);
        } else if (args.option("--max-iter", v)) {
            max_iter = parse_int("bench-run", "--max-iter", v);
        } else if (args.option("--time-limit", v)) {
            time_limit = parse_double("bench-run", "--time-limit", v);
        } else if (args.option("--guess", v)) {
            guess = parse_guess_number("bench-run", v);
        } else if (args.option("--fd", v)) {
            fd = static_cast<int>(parse_int("bench-run", "--fd", v));
        } else if (args.option("--set", v)) {
            const std::size_t eq = v.find('=');
            frix_option_key key{};
            if (eq == std::string::npos || frix_option_by_name(v.substr(0, eq).c_str(), &key) != FRIX_OK)
                usage_error("bench-run", "--set expects a known NAME=VALUE, got '" + v + "'");
            settings.push_back({key, parse_double("bench-run", "--set", v.substr(eq + 1))});
        } else if (args.at_option()) {
            args.unknown_option();
        } else {
            if (!file.empty()) usage_error("bench-run", "expected one FILE");
            file = args.positional();
        }
    }
    if (file.empty() || solver.empty() || fd < 0)
        usage_error("bench-run", "expected FILE --solver NAME --fd FD");
    std::signal(SIGPIPE, SIG_IGN);
    injected_fault(file, solver);

    int id = 0;
    if (frix_solver_by_name(solver.c_str(), &id) != FRIX_OK)
        fail("bench-run: unknown solver '" + solver + "'");
    frix_options *raw = nullptr;
    frix_error err = frix_options_create(id, &raw);
    OptionsPtr opts(raw);
    if (err != FRIX_OK) fail("bench-run: " + library_message(err));
    set_option(opts.get(), FRIX_OPT_TOLERANCE, tol, "--tol");
    if (max_iter > 0) set_option(opts.get(), FRIX_OPT_MAX_ITER, static_cast<double>(max_iter), "--max-iter");
    set_option(opts.get(), FRIX_OPT_TIME_LIMIT, time_limit, "--time-limit");
    // The trace holds errors of iterates only (not NSGS's light error between its full checks):
    // the times to an accuracy are read from it.
    set_option(opts.get(), FRIX_OPT_CALLBACK_ESTIMATES, 0.0, "callback_estimates");
    for (const auto &kv : settings) set_option(opts.get(), kv.first, kv.second, frix_option_name(kv.first));
    Stream stream{{}, fd};
    frix_options_set_callback(opts.get(), on_progress, &stream);

    // The problem is read here, in the run's own process, and never by the bench: a file
    // that hangs, crashes or refuses the reader costs this run alone. The time limit covers
    // the read (the bench's wall-clock limit counts from this process's start): the solver
    // gets what is left of it.
    const auto read_start = std::chrono::steady_clock::now();
    ProblemPtr problem;
    try {
        problem = read_problem(file);
    } catch (const Failure &e) {
        frix_bench::write_line(fd, frix_bench::note_line(e.message));
        frix_bench::write_line(fd, frix_bench::result_line("unreadable", 0, NAN, NAN, NAN, NAN));
        frix_bench::write_line(fd, frix_bench::peak_memory_line());
        return kExitUsage;
    }
    const double read_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - read_start).count();
    const frix_problem_kind kind = frix_problem_get_kind(problem.get());
    const bool global = kind == FRIX_PROBLEM_GLOBAL || kind == FRIX_PROBLEM_ROLLING_GLOBAL;
    const auto entries = [](const frix_matrix *a) {
        return a ? static_cast<double>(std::max<int64_t>(0, frix_matrix_nnz(a))) : 0.0;
    };
    const double stored = global ? entries(frix_problem_M(problem.get())) + entries(frix_problem_H(problem.get()))
                                 : entries(frix_problem_W(problem.get()));
    frix_bench::write_line(fd, frix_bench::problem_line(frix_problem_contacts(problem.get()),
                                                        global ? frix_problem_dofs(problem.get())
                                                               : frix_problem_contact_dofs(problem.get()),
                                                        stored / 9.0));
    if (time_limit > 0) {
        const double left = time_limit - read_time;
        if (!(left > 0)) {
            char note[160];
            std::snprintf(note, sizeof note, "reading the problem took %.3g s, the whole time limit of %g s",
                          read_time, time_limit);
            frix_bench::write_line(fd, frix_bench::note_line(note));
            frix_bench::write_line(fd, frix_bench::result_line("time_limit", 0, NAN, read_time, NAN, NAN));
            frix_bench::write_line(fd, frix_bench::peak_memory_line());
            return kExitNotConverged;
        }
        set_option(opts.get(), FRIX_OPT_TIME_LIMIT, left, "--time-limit");
    }
    const int64_t m = frix_problem_contact_dofs(problem.get()), n = frix_problem_dofs(problem.get());
    std::vector<double> r(static_cast<std::size_t>(std::max<int64_t>(m, 1)), 0.0);
    std::vector<double> u(r.size(), 0.0), vel(static_cast<std::size_t>(std::max<int64_t>(n, 1)), 0.0);
    double *vp = global ? vel.data() : nullptr;
    if (guess > 0) {
        // A guess the file lacks (or cannot give) is this run's error, as an unreadable file is.
        try {
            start_from_guess(file, problem.get(), guess, r.data(), u.data(), vp);
        } catch (const Failure &e) {
            frix_bench::write_line(fd, frix_bench::note_line(e.message));
            frix_bench::write_line(fd, frix_bench::result_line("error", 0, NAN, NAN, NAN, NAN));
            frix_bench::write_line(fd, frix_bench::peak_memory_line());
            return kExitUsage;
        }
    }
    const std::vector<double> r_start = r, v_start = vel;  // each repeat starts where the first did

    frix_info *raw_info = nullptr;
    err = frix_info_create(&raw_info);
    if (err != FRIX_OK) fail("bench-run: " + library_message(err));
    InfoPtr info(raw_info);
    err = frix_solve(problem.get(), opts.get(), r.data(), u.data(), vp, info.get());
    if (err != FRIX_OK) {
        const bool unsupported = err == FRIX_ERR_UNSUPPORTED;
        frix_bench::write_line(fd, frix_bench::note_line(library_message(err)));
        frix_bench::write_line(fd, frix_bench::result_line(unsupported ? "unsupported" : "error",
                                                           0, NAN, NAN, NAN, NAN));
        frix_bench::write_line(fd, frix_bench::peak_memory_line());
        return kExitUsage;
    }
    // The error column is always frix's measure of Siconos's kind, for a global problem
    // frix_bench::global_error, error_scaled the default one, which holds the equilibrium
    // already (both for Siconos's runs too). The
    // solver's own stopping measure, which an option may change, is the reported one.
    const frix_status status = frix_info_status(info.get());
    const int64_t iterations = frix_info_iterations(info.get());
    const double reported = frix_info_error(info.get());
    double error = NAN, error_scaled = NAN;
    if (frix_info_get_double(info.get(), FRIX_INFO_ERROR_RELATIVE, &error) != FRIX_OK) error = NAN;
    if (frix_info_get_double(info.get(), FRIX_INFO_ERROR_SCALED, &error_scaled) != FRIX_OK) error_scaled = NAN;
    if (global) {
        double equilibrium = NAN;
        if (frix_info_get_double(info.get(), FRIX_INFO_EQUILIBRIUM, &equilibrium) != FRIX_OK) equilibrium = NAN;
        error = frix_bench::global_error(error, equilibrium);
    }
    // Short solves again, without the trace, for the median time (RepeatTimer).
    frix_bench::RepeatTimer timer;
    timer.add(frix_info_solve_time(info.get()));
    frix_options_set_callback(opts.get(), nullptr, nullptr);
    while (timer.again()) {
        r = r_start;
        vel = v_start;
        if (frix_solve(problem.get(), opts.get(), r.data(), u.data(), vp, info.get()) != FRIX_OK) break;
        timer.add(frix_info_solve_time(info.get()));
    }
    if (status == FRIX_STATUS_MEMORY_LIMIT)
        frix_bench::write_line(fd, frix_bench::note_line(memory_limit_note(opts.get(), iterations)));
    frix_bench::write_line(fd, frix_bench::result_line(status_token(status), iterations, error,
                                                       timer.median(), reported, error_scaled));
    frix_bench::write_line(fd, frix_bench::peak_memory_line());
    return status == FRIX_STATUS_CONVERGED ? kExitConverged : kExitNotConverged;
}

}  // namespace frix_cli
