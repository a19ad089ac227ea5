// `frix solve FILE.hdf5 [options]`: read, solve from r = 0, report, optionally write.
#include "args.hpp"
#include "cli.hpp"
#include "json.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <chrono>
#include <string>
#include <vector>

namespace frix_cli {
namespace {

// One option value as typed; converted once the solver (hence the option's type) is known.
struct Setting {
    frix_option_key key;
    std::string label;  // the option, for messages: "--tol", "--set relaxation"
    std::string text;
    std::string shown;  // how the user wrote it: "--tol -1", "--set relaxation=3"
};

struct SolveArgs {
    std::string file, output;
    std::string solver = "auto";
    int64_t guess = 0;  // --guess K: start from the file's guess K (1-based, as FCLIB numbers them); 0: r = 0
    std::vector<Setting> settings;
    bool json = false;
    bool force = false;  // --force: --output may name FILE itself
    int verbosity = 0;
    // The progress line: by default on a terminal only; --progress forces it (one line per
    // update), --quiet turns it off.
    bool progress_forced = false, quiet = false;
};

// A solve that lasts shows where it is on stderr: after the first second, the elapsed time,
// the iterations, the last error the solver reported (for auto, its current stage's, not
// the whole problem's) and the tolerance it must reach. Auto's current stage is not shown:
// the public API gives the stages only after the solve (frix_info_stage_*). On a terminal
// one line, redrawn at most 5 times a second and erased at the end; otherwise (--progress)
// one line per second.
class SolveProgress {
public:
    SolveProgress(bool tty, double tolerance) : tty_(tty), tolerance_(tolerance) {}
    static int callback(void *data, int64_t iteration, double error, double elapsed) {
        static_cast<SolveProgress *>(data)->update(iteration, error, elapsed);
        return 0;
    }
    void end() {
        if (drawn_ && tty_) std::fprintf(stderr, "\r\033[K");
        std::fflush(stderr);
    }

private:
    void update(int64_t iteration, double error, double elapsed) {
        if (elapsed < kFirstDraw || elapsed - last_draw_ < (tty_ ? 0.2 : 1.0)) return;
        std::fprintf(stderr, "%sfrix solve: %.1f s, %lld iterations, error %.3e (target %.3g)%s",
                     tty_ ? "\r\033[K" : "", elapsed, static_cast<long long>(iteration), error,
                     tolerance_, tty_ ? "" : "\n");
        std::fflush(stderr);
        last_draw_ = elapsed;
        drawn_ = true;
    }
    static constexpr double kFirstDraw = 1.0;  // shorter solves print nothing
    bool tty_;
    double tolerance_;
    bool drawn_ = false;
    double last_draw_ = -1.0;
};

struct Report {
    std::string file, output;
    frix_problem_kind kind = FRIX_PROBLEM_LOCAL;
    int64_t contacts = 0, contact_dofs = 0, dofs = 0;
    int solver_id = 0;
    std::string solver_name;
    frix_status status = FRIX_STATUS_NOT_RUN;
    int64_t iterations = 0;
    int64_t measure = FRIX_MEASURE_RELATIVE;
    double error = NAN, tolerance = NAN, time = NAN;
    double error_relative = NAN, error_q_relative = NAN, residual = NAN;
    double cone_violation = NAN, penetration = NAN, complementarity = NAN, equilibrium = NAN;
    double equilibrium_scaled = NAN;  // global: the default measure's equilibrium part
    // Newton-type solvers and global problems (0 where not applicable).
    int64_t newton_iterations = 0, line_search_steps = 0, factorizations = 0, symbolic_analyses = 0,
            hybrid_sweeps = 0;
    double factorization_time = 0.0, setup_time = 0.0, reduction_time = 0.0;
    // Whether a solution exists at all: the solver's own check, or the CLI's after a failure.
    frix_existence existence = FRIX_EXISTENCE_NOT_CHECKED;
    double existence_margin = NAN;
    // What the solver did, line by line (frix_info_trace: auto's analysis, stages and switches).
    std::vector<std::string> trace;
};

SolveArgs parse(int argc, char **argv, bool &help) {
    ArgCursor args("solve", argc, argv);
    SolveArgs a;
    std::vector<std::string> files;
    std::string v;
    help = false;
    while (!args.done()) {
        if (args.flag("--help") || args.flag("-h")) {
            help = true;
            return a;
        } else if (args.option("--solver", v)) {
            a.solver = v;
        } else if (args.option("--tol", v)) {
            a.settings.push_back({FRIX_OPT_TOLERANCE, "--tol", v, "--tol " + v});
        } else if (args.option("--max-iter", v)) {
            a.settings.push_back({FRIX_OPT_MAX_ITER, "--max-iter", v, "--max-iter " + v});
        } else if (args.option("--time-limit", v)) {
            a.settings.push_back({FRIX_OPT_TIME_LIMIT, "--time-limit", v, "--time-limit " + v});
        } else if (args.option("--threads", v)) {
            a.settings.push_back({FRIX_OPT_THREADS, "--threads", v, "--threads " + v});
        } else if (args.option("--set", v)) {
            std::size_t eq = v.find('=');
            if (eq == std::string::npos || eq == 0)
                usage_error("solve", "--set expects NAME=VALUE, got '" + v + "'");
            std::string name = v.substr(0, eq);
            frix_option_key key{};
            if (frix_option_by_name(name.c_str(), &key) != FRIX_OK)
                usage_error("solve", "unknown option name '" + name + "' in --set");
            a.settings.push_back({key, "--set " + name, v.substr(eq + 1), "--set " + v});
        } else if (args.option("--output", v) || args.option("-o", v)) {
            if (v.empty()) usage_error("solve", "--output needs a file name");
            a.output = v;
        } else if (args.option("--guess", v)) {
            a.guess = parse_guess_number("solve", v);
        } else if (args.flag("--json")) {
            a.json = true;
        } else if (args.flag("--force")) {
            a.force = true;
        } else if (args.flag("--progress")) {
            a.progress_forced = true;
        } else if (args.flag("--quiet") || args.flag("-q")) {
            a.quiet = true;
        } else if (args.flag("--verbose") || args.flag("-v")) {
            ++a.verbosity;
        } else if (args.flag("-vv")) {
            a.verbosity += 2;
        } else if (args.flag("-vvv")) {
            a.verbosity += 3;
        } else if (args.at_option()) {
            args.unknown_option();
        } else if (!args.done()) {
            files.push_back(args.positional());
        }
    }
    if (files.size() != 1) usage_error("solve", "expected one FILE.hdf5");
    if (a.quiet && a.progress_forced)
        usage_error("solve", "--quiet and --progress exclude each other");
    a.file = files[0];
    if (a.verbosity > 0)
        a.settings.push_back({FRIX_OPT_VERBOSITY, "--verbose", std::to_string(a.verbosity),
                              "verbosity " + std::to_string(a.verbosity)});
    return a;
}

// The library decides what is in range; the CLI only reports what it says.
void apply(frix_options *opts, const Setting &s) {
    double lower = 0, upper = 0;
    int is_int = 0;
    frix_error err = frix_options_bounds(opts, s.key, &lower, &upper, &is_int);
    if (err != FRIX_OK) fail("solve: " + s.label + ": " + library_message(err));
    if (is_int)
        err = frix_options_set_int(opts, s.key, parse_int("solve", s.label, s.text));
    else
        err = frix_options_set_double(opts, s.key, parse_double("solve", s.label, s.text));
    if (err != FRIX_OK) fail("solve: " + s.shown + ": " + library_message(err));
}

OptionsPtr make_options(const SolveArgs &a) {
    int id = 0;
    if (frix_solver_by_name(a.solver.c_str(), &id) != FRIX_OK)
        fail("solve: unknown solver '" + a.solver + "' (see 'frix solvers')");
    frix_options *raw = nullptr;
    frix_error err = frix_options_create(id, &raw);
    OptionsPtr opts(raw);
    if (err != FRIX_OK) fail("solve: solver '" + a.solver + "': " + library_message(err));
    for (const Setting &s : a.settings) apply(opts.get(), s);
    return opts;
}

double info_double(const frix_info *info, frix_info_key key) {
    double v = NAN;
    if (frix_info_get_double(info, key, &v) != FRIX_OK) return NAN;
    return v;
}

void read_existence(Report &r, const frix_info *info) {
    int64_t existence = FRIX_EXISTENCE_NOT_CHECKED;
    frix_info_get_int(info, FRIX_INFO_EXISTENCE, &existence);
    r.existence = static_cast<frix_existence>(existence);
    r.existence_margin = info_double(info, FRIX_INFO_EXISTENCE_MARGIN);
}

void fill_from_info(Report &r, const frix_info *info) {
    int64_t id = 0;
    if (frix_info_get_int(info, FRIX_INFO_SOLVER_ID, &id) == FRIX_OK)
        r.solver_id = static_cast<int>(id);
    const char *name = frix_solver_name(r.solver_id);
    r.solver_name = name ? name : "?";
    r.status = frix_info_status(info);
    r.iterations = frix_info_iterations(info);
    r.error = frix_info_error(info);
    r.time = frix_info_solve_time(info);
    r.tolerance = info_double(info, FRIX_INFO_TOLERANCE);
    r.error_relative = info_double(info, FRIX_INFO_ERROR_RELATIVE);
    r.error_q_relative = info_double(info, FRIX_INFO_ERROR_Q_RELATIVE);
    r.residual = info_double(info, FRIX_INFO_RESIDUAL_ABSOLUTE);
    r.cone_violation = info_double(info, FRIX_INFO_CONE_VIOLATION);
    r.penetration = info_double(info, FRIX_INFO_PENETRATION);
    r.complementarity = info_double(info, FRIX_INFO_COMPLEMENTARITY);
    r.equilibrium = info_double(info, FRIX_INFO_EQUILIBRIUM);
    r.equilibrium_scaled = info_double(info, FRIX_INFO_EQUILIBRIUM_SCALED);
    frix_info_get_int(info, FRIX_INFO_NEWTON_ITERATIONS, &r.newton_iterations);
    frix_info_get_int(info, FRIX_INFO_LINE_SEARCH_STEPS, &r.line_search_steps);
    frix_info_get_int(info, FRIX_INFO_FACTORIZATIONS, &r.factorizations);
    frix_info_get_int(info, FRIX_INFO_SYMBOLIC_ANALYSES, &r.symbolic_analyses);
    frix_info_get_int(info, FRIX_INFO_HYBRID_SWEEPS, &r.hybrid_sweeps);
    r.factorization_time = info_double(info, FRIX_INFO_FACTORIZATION_TIME);
    r.setup_time = info_double(info, FRIX_INFO_SETUP_TIME);
    r.reduction_time = info_double(info, FRIX_INFO_REDUCTION_TIME);
    read_existence(r, info);
    r.trace = split(frix_info_trace(info), '\n');
}

// A failed solve says whether the problem has a solution at all: the solver's verdict when
// it checked (auto does), otherwise the library's check with its default budget. A check
// that cannot run leaves "not checked": the solve's own report matters more.
// left: seconds left of the command's time limit (infinite without one); none left: no check.
void check_existence_after_failure(Report &r, const frix_problem *problem, frix_info *info, double left) {
    if (r.status == FRIX_STATUS_CONVERGED || r.existence != FRIX_EXISTENCE_NOT_CHECKED) return;
    if (!(left > 0.0)) return;
    if (frix_problem_check_existence(problem, std::isfinite(left) ? left : 0.0, info) == FRIX_OK)
        read_existence(r, info);
}

// The existence line of a failed solve: the verdict and what it means for the failure.
std::string existence_text(const Report &r) {
    char margin[64];
    std::snprintf(margin, sizeof margin, "margin %.2e", r.existence_margin);
    const std::string verdict = frix_existence_describe(r.existence);
    switch (r.existence) {
        case FRIX_EXISTENCE_GUARANTEED:
            return verdict + " (" + margin + "): the solver failed to find it";
        case FRIX_EXISTENCE_DOUBTFUL:
            return verdict + " (certificate: a reaction in the cones that does no work, " + margin + ")";
        case FRIX_EXISTENCE_UNDETERMINED:
            return verdict + " (the check ran out of budget)";
        default:
            return verdict;
    }
}

// The measure's name as options take it (scaled, siconos, q_relative).
const char *measure_name(int64_t measure) {
    const char *name = frix_option_choice_name(FRIX_OPT_ERROR_MEASURE, measure);
    return name ? name : "unknown";
}

// What the error is relative to, in one line of the report.
const char *measure_meaning(int64_t measure) {
    switch (measure) {
        case FRIX_MEASURE_Q_RELATIVE: return "natural-map residual / |q|";
        case FRIX_MEASURE_RELATIVE: return "Siconos: natural-map residual / max(|q|, |r|, |u|)";
        default: return "residual of (W_aa r, u^), in velocity units, / max(|q|, |u|)";
    }
}

void print_json(const Report &r) {
    JsonWriter w;
    w.begin_object();
    w.string("file", r.file);
    w.string("kind", kind_name(r.kind));
    w.integer("contacts", r.contacts);
    w.integer("contact_dofs", r.contact_dofs);
    w.integer("dofs", r.dofs);
    w.string("solver", r.solver_name);
    w.integer("solver_id", r.solver_id);
    w.string("status", status_token(r.status));
    w.string("status_text", frix_status_string(r.status));
    w.boolean("converged", r.status == FRIX_STATUS_CONVERGED);
    w.integer("iterations", r.iterations);
    w.number("error", r.error);
    w.string("error_measure", measure_name(r.measure));
    w.number("tolerance", r.tolerance);
    w.number("time", r.time);
    w.string("existence", frix_existence_describe(r.existence));
    w.number("existence_margin", r.existence_margin);
    w.begin_object("measures");
    w.number("error_relative", r.error_relative);
    w.number("error_q_relative", r.error_q_relative);
    w.number("residual_absolute", r.residual);
    w.number("cone_violation", r.cone_violation);
    w.number("penetration", r.penetration);
    w.number("complementarity", r.complementarity);
    w.number("equilibrium", r.equilibrium);
    w.number("equilibrium_scaled", r.equilibrium_scaled);
    w.end_object();
    w.begin_object("linear_algebra");
    w.integer("newton_iterations", r.newton_iterations);
    w.integer("line_search_steps", r.line_search_steps);
    w.integer("hybrid_sweeps", r.hybrid_sweeps);
    w.integer("factorizations", r.factorizations);
    w.integer("symbolic_analyses", r.symbolic_analyses);
    w.number("factorization_time", r.factorization_time);
    w.number("setup_time", r.setup_time);
    w.number("reduction_time", r.reduction_time);
    w.end_object();
    w.begin_array("trace");
    for (const std::string &line : r.trace) w.string(nullptr, line);
    w.end_array();
    if (r.output.empty())
        w.null("output");
    else
        w.string("output", r.output);
    w.end_object();
    std::printf("%s\n", w.text().c_str());
}

void print_text(const Report &r) {
    std::printf("%-16s %s\n", "file", r.file.c_str());
    if (r.kind == FRIX_PROBLEM_LOCAL || r.kind == FRIX_PROBLEM_ROLLING_LOCAL)
        std::printf("%-16s %s, %lld contacts\n", "problem", kind_name(r.kind), static_cast<long long>(r.contacts));
    else
        std::printf("%-16s %s, %lld contacts, %lld dofs\n", "problem", kind_name(r.kind),
                    static_cast<long long>(r.contacts), static_cast<long long>(r.dofs));
    std::printf("%-16s %s (id %d)\n", "solver", r.solver_name.c_str(), r.solver_id);
    std::printf("%-16s %s\n", "status", frix_status_string(r.status));
    if (r.status != FRIX_STATUS_CONVERGED)
        std::printf("%-16s %s\n", "existence", existence_text(r).c_str());
    std::printf("%-16s %lld\n", "iterations", static_cast<long long>(r.iterations));
    std::printf("%-16s %.3e (%s, tolerance %.1e)\n", "error", r.error, measure_name(r.measure),
                r.tolerance);
    std::printf("%-16s %s%s\n", "  relative to", measure_meaning(r.measure),
                r.kind == FRIX_PROBLEM_GLOBAL ? ", and the equilibrium residual" : "");
    if (r.setup_time > 0.0)
        std::printf("%-16s %.3g s (setup %.3g s, then the solver %.3g s)\n", "time", r.time, r.setup_time,
                    r.time - r.setup_time);
    else
        std::printf("%-16s %.3g s\n", "time", r.time);
    std::printf("%-16s %.3e\n", "error / |q|", r.error_q_relative);
    std::printf("%-16s %.3e\n", "siconos error", r.error_relative);
    std::printf("%-16s %.3e\n", "residual", r.residual);
    std::printf("%-16s %.3e\n", "cone violation", r.cone_violation);
    std::printf("%-16s %.3e\n", "penetration", r.penetration);
    std::printf("%-16s %.3e\n", "complementarity", r.complementarity);
    if (r.kind == FRIX_PROBLEM_GLOBAL)
        std::printf("%-16s %.3e (diag(M)-weighted: %.3e)\n", "equilibrium", r.equilibrium, r.equilibrium_scaled);
    else if (r.kind == FRIX_PROBLEM_ROLLING_GLOBAL)
        std::printf("%-16s %.3e\n", "equilibrium", r.equilibrium);
    if (r.newton_iterations > 0)
        std::printf("%-16s %lld (%lld line-search steps, %lld fallback sweeps)\n", "newton steps",
                    static_cast<long long>(r.newton_iterations),
                    static_cast<long long>(r.line_search_steps), static_cast<long long>(r.hybrid_sweeps));
    if (r.factorizations > 0)
        std::printf("%-16s %lld (%lld symbolic), %.3g s\n", "factorizations",
                    static_cast<long long>(r.factorizations),
                    static_cast<long long>(r.symbolic_analyses), r.factorization_time);
    if (r.reduction_time > 0.0)
        std::printf("%-16s %.3g s: M (factorised, or analysed only) and q %.3g s, W = H^T M^-1 H %.3g s\n",
                    "setup", r.setup_time, r.setup_time - r.reduction_time, r.reduction_time);
    else if (r.setup_time > 0.0)
        std::printf("%-16s %.3g s: M (factorised, or analysed only) and q\n", "setup", r.setup_time);
    for (std::size_t k = 0; k < r.trace.size(); ++k)
        std::printf("%-16s %s\n", k == 0 ? "trace" : "", r.trace[k].c_str());
    if (!r.output.empty()) std::printf("%-16s %s\n", "written to", r.output.c_str());
}

}  // namespace

int cmd_solve(int argc, char **argv) {
    bool help = false;
    SolveArgs a = parse(argc, argv, help);
    if (help) {
        print_solve_help(stdout);
        return kExitConverged;
    }
    // The time limit holds for the whole command: reading the file, the solve, and the
    // existence check after a failure each get what is left of it.
    const auto start = std::chrono::steady_clock::now();
    auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
    // Options first: a usage mistake is reported before any file is touched. Then the
    // output: a solve that may take hours must not end in a write error known from the start.
    OptionsPtr opts = make_options(a);
    if (!a.output.empty()) check_output(a.output, a.file, a.force);
    double limit = 0.0;
    if (frix_options_get_double(opts.get(), FRIX_OPT_TIME_LIMIT, &limit) != FRIX_OK) limit = 0.0;
    // Under a limit the file is read in a child process, stopped when the limit runs out.
    ProblemPtr problem = limit > 0.0 ? read_problem(a.file, limit, limit - elapsed()) : read_problem(a.file);
    if (limit > 0.0)  // at least a moment for the solve, which then returns at once
        frix_options_set_double(opts.get(), FRIX_OPT_TIME_LIMIT, std::max(limit - elapsed(), 1e-6));

    Report rep;
    rep.file = a.file;
    rep.kind = frix_problem_get_kind(problem.get());
    rep.contacts = frix_problem_contacts(problem.get());
    rep.contact_dofs = frix_problem_contact_dofs(problem.get());
    rep.dofs = frix_problem_dofs(problem.get());
    if (frix_options_get_int(opts.get(), FRIX_OPT_ERROR_MEASURE, &rep.measure) != FRIX_OK)
        rep.measure = FRIX_MEASURE_RELATIVE;

    // Sized at least 1 so that an empty problem still passes valid pointers.
    std::vector<double> r(static_cast<std::size_t>(std::max<int64_t>(rep.contact_dofs, 1)), 0.0);
    std::vector<double> u(r.size(), 0.0);
    std::vector<double> v(static_cast<std::size_t>(std::max<int64_t>(rep.dofs, 1)), 0.0);
    const bool global = rep.kind == FRIX_PROBLEM_GLOBAL || rep.kind == FRIX_PROBLEM_ROLLING_GLOBAL;
    double *vp = global ? v.data() : nullptr;
    if (a.guess > 0) start_from_guess(a.file, problem.get(), a.guess, r.data(), u.data(), vp);

    frix_info *raw_info = nullptr;
    frix_error err = frix_info_create(&raw_info);
    InfoPtr info(raw_info);
    if (err != FRIX_OK) fail("solve: " + library_message(err));
    // The solver's own messages (--verbose) replace the progress line.
    const bool tty = ::isatty(2) != 0;
    double tolerance = NAN;
    frix_options_get_double(opts.get(), FRIX_OPT_TOLERANCE, &tolerance);
    SolveProgress progress(tty && !a.progress_forced, tolerance);
    if (a.progress_forced || (tty && !a.quiet && a.verbosity == 0))
        frix_options_set_callback(opts.get(), SolveProgress::callback, &progress);
    err = frix_solve(problem.get(), opts.get(), r.data(), u.data(), vp, info.get());
    progress.end();
    if (err != FRIX_OK) fail("cannot solve " + a.file + ": " + library_message(err));
    fill_from_info(rep, info.get());
    check_existence_after_failure(rep, problem.get(), info.get(), limit > 0.0 ? limit - elapsed() : INFINITY);

    // Written whatever the status: a non-converged iterate is still worth inspecting.
    std::string write_error;
    if (!a.output.empty()) {
        err = frix_fclib_write(a.output.c_str(), problem.get(), r.data(), u.data(), vp, 0,
                               nullptr, nullptr, nullptr);
        if (err == FRIX_OK)
            rep.output = a.output;
        else
            write_error = "cannot write " + a.output + ": " + library_message(err);
    }

    if (a.json)
        print_json(rep);
    else
        print_text(rep);
    // "memory limit reached" alone does not say which limit, nor that the error is the start's.
    if (rep.status == FRIX_STATUS_MEMORY_LIMIT)
        std::fprintf(stderr, "frix: solve: memory limit reached: %s.\n", memory_limit_note(opts.get(), rep.iterations).c_str());
    if (!write_error.empty()) fail(write_error);
    return rep.status == FRIX_STATUS_CONVERGED ? kExitConverged : kExitNotConverged;
}

}  // namespace frix_cli
