// `frix-siconos`: solve an FCLIB problem read by frix with a Siconos 4.4 solver (FC3D for a
// local problem, GFC3D for a global one) and report it as `frix solve` does, the error being
// frix's measure of Siconos's r (and v).
//
//   frix-siconos FILE.hdf5 --solver NAME|ID [--tol T] [--max-iter N] [--guess K] [--json] [--trace]
//   frix-siconos --list [--json]
//
// `frix bench` runs it as a child (hidden option --fd N: the bench protocol on fd N,
// bench_protocol.hpp), so that Siconos's abort()/exit() or a hang costs one run only.
#include "siconos_adapter.h"

#include "args.hpp"
#include "bench_protocol.hpp"
#include "cli.hpp"
#include "json.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <vector>

namespace frix_cli {
namespace {

struct Args {
    std::string file, solver;
    double tol = 1e-8;
    std::int64_t max_iter = 0;  // 0: Siconos's default for the solver
    std::int64_t guess = 0;     // --guess K: start from the file's guess K; 0: from r = 0, v = 0
    bool json = false, trace = false, list = false, help = false;
    int fd = -1;
};

void print_help() {
    std::fputs(
        "Usage: frix-siconos FILE.hdf5 --solver NAME|ID [--tol T] [--max-iter N] [--guess K]\n"
        "                   [--json] [--trace]\n"
        "       frix-siconos --list [--json]\n"
        "\n"
        "Solves the FCLIB problem in FILE (read by frix) from r = 0 (and v = 0), or from\n"
        "its guess K (--guess), with a\n"
        "Siconos 4.4 solver: a local problem with an FC3D solver (fc3d_driver), a global one\n"
        "with a GFC3D solver (gfc3d_driver), a rolling one with an RFC3D or GRFC3D solver\n"
        "(rolling_fc3d_driver, g_rolling_fc3d_driver). Reports it like 'frix solve': the error is\n"
        "frix's relative measure of the r (and v) Siconos returned, and for a global problem\n"
        "the equilibrium |M v - H r - f| / max(|f|, |M v|, |H r|) beside it; Siconos's own\n"
        "error is shown too. The time is that of the driver alone.\n"
        "\n"
        "Options:\n"
        "  --solver NAME|ID   local: NSGS, NSN_AC, NSN_FB, NSN_NM, PROX, VI_FPP, VI_EG, TFP,\n"
        "                     ADMM, ... with FC3D_ or FRICTION_3D_ spellings; global:\n"
        "                     GFC3D_NSN_AC, GFC3D_NSGS_WR, GFC3D_ADMM, GFC3D_IPM, ... with\n"
        "                     GLOBAL_FRICTION_3D_ spellings; rolling friction: RFC3D_NSGS,\n"
        "                     RFC3D_ADMM (local), GRFC3D_NSGS_WR (global); or the id (see --list)\n"
        "  --tol T            Siconos's dparam[TOL] (default 1e-8)\n"
        "  --max-iter N       Siconos's iparam[MAX_ITER] (default: the solver's own)\n"
        "  --guess K          start from FILE's guess K (1, 2, ...), as 'frix solve --guess'\n"
        "  --json             one JSON object instead of text\n"
        "  --trace            with --json: the per-iteration errors, for the solvers that\n"
        "                     call Siconos's iteration callback\n"
        "  --list             the solvers offered (id and name; the GFC3D_ ones are global)\n"
        "\n"
        "Exit status: 0 converged (frix's error <= T, and for a global problem the\n"
        "equilibrium <= T, frix's rule), 1 not converged, 2 usage error,\n"
        "unreadable input, a solver for the other kind of problem (local / global), or\n"
        "Siconos refused the problem.\n",
        stdout);
}

Args parse(int argc, char **argv) {
    ArgCursor args("frix-siconos", argc, argv);
    Args a;
    std::vector<std::string> files;
    std::string v;
    while (!args.done()) {
        if (args.flag("--help") || args.flag("-h")) {
            a.help = true;
            return a;
        } else if (args.flag("--list")) {
            a.list = true;
        } else if (args.option("--solver", v)) {
            a.solver = v;
        } else if (args.option("--tol", v)) {
            a.tol = parse_double("frix-siconos", "--tol", v);
        } else if (args.option("--max-iter", v)) {
            a.max_iter = parse_int("frix-siconos", "--max-iter", v);
        } else if (args.option("--guess", v)) {
            a.guess = parse_guess_number("frix-siconos", v);
        } else if (args.option("--fd", v)) {
            a.fd = static_cast<int>(parse_int("frix-siconos", "--fd", v));
        } else if (args.flag("--json")) {
            a.json = true;
        } else if (args.flag("--trace")) {
            a.trace = true;
        } else if (args.at_option()) {
            args.unknown_option();
        } else if (!args.done()) {
            files.push_back(args.positional());
        }
    }
    if (a.list) return a;
    if (files.size() != 1) fail("expected one FILE.hdf5 (see 'frix-siconos --help')");
    if (a.solver.empty()) fail("--solver is required (see 'frix-siconos --list')");
    if (!(a.tol >= 0 && a.tol <= 1)) fail("--tol " + std::to_string(a.tol) + " is outside [0, 1]");
    a.file = files[0];
    return a;
}

int list(bool json) {
    JsonWriter w;
    w.begin_array();
    for (int k = 0; k < frix_siconos_solver_count(); ++k) {
        int id = frix_siconos_solver_id_at(k);
        // Text: "id name" and nothing else on a line, which `frix bench` reads; the GFC3D_
        // (GRFC3D_) prefix of the name marks a global (rolling) solver.
        if (json) {
            w.begin_object();
            w.integer("id", id);
            w.string("name", frix_siconos_solver_name(id));
            w.string("kind", frix_siconos_solver_is_rolling(id) == 1 ? "rolling"
                             : frix_siconos_solver_is_global(id)   ? "global"
                                                                   : "local");
            w.end_object();
        } else {
            std::printf("%5d  %s\n", id, frix_siconos_solver_name(id));
        }
    }
    w.end_array();
    if (json) std::printf("%s\n", w.text().c_str());
    return kExitConverged;
}

// The trace as it comes: streamed to the bench's pipe, or kept for --json --trace.
struct TraceSink {
    frix_bench::TraceThinner thinner;
    int fd = -1;
    std::vector<double> points;  // iteration, elapsed, error
};

void on_iteration(void *data, int64_t iteration, double elapsed, double error) {
    auto *sink = static_cast<TraceSink *>(data);
    if (!sink->thinner.keep(elapsed, error)) return;
    if (sink->fd >= 0) frix_bench::write_line(sink->fd, frix_bench::trace_line(iteration, elapsed, error));
    sink->points.insert(sink->points.end(), {static_cast<double>(iteration), elapsed, error});
}

// Siconos prints some solvers' progress on stdout whatever its verbosity (GFC3D_IPM's
// iteration table): while Siconos runs, stdout goes to stderr, so that stdout holds the
// report alone (one JSON object with --json).
class SiconosOutputToStderr {
public:
    SiconosOutputToStderr() {
        std::fflush(stdout);
        saved_ = ::dup(1);
        if (saved_ >= 0 && ::dup2(2, 1) < 0) {
            ::close(saved_);
            saved_ = -1;
        }
    }
    ~SiconosOutputToStderr() {
        std::fflush(stdout);
        if (saved_ >= 0) {
            ::dup2(saved_, 1);
            ::close(saved_);
        }
    }
    SiconosOutputToStderr(const SiconosOutputToStderr &) = delete;
    SiconosOutputToStderr &operator=(const SiconosOutputToStderr &) = delete;

private:
    int saved_ = -1;
};

// frix's measure decides convergence, as for frix's own solvers: for a global problem the
// error and the equilibrium both.
const char *status_of(const frix_siconos_result &res, double tol, std::int64_t max_iter,
                      bool global) {
    if (res.refused_kind) return "unsupported";  // a solver for the other kind of problem
    if (!res.ran) return "error";
    if (res.error <= tol && (!global || res.equilibrium <= tol))
        return "converged";
    if (res.info == 0) return "inaccurate";  // Siconos says converged, frix's measure does not
    if (max_iter > 0 && res.iterations >= max_iter) return "max_iter";
    return "failed";
}

int run(int argc, char **argv) {
    Args a = parse(argc, argv);
    if (a.help) {
        print_help();
        return kExitConverged;
    }
    if (a.list) return list(a.json);
    int id = frix_siconos_solver_by_name(a.solver.c_str());
    if (id < 0) fail("unknown Siconos solver '" + a.solver + "' (see 'frix-siconos --list')");
    if (a.fd >= 0) std::signal(SIGPIPE, SIG_IGN);

    ProblemPtr problem = read_problem(a.file);
    const frix_problem_kind kind = frix_problem_get_kind(problem.get());
    const bool global = kind == FRIX_PROBLEM_GLOBAL || kind == FRIX_PROBLEM_ROLLING_GLOBAL;
    const bool rolling = kind == FRIX_PROBLEM_ROLLING_LOCAL || kind == FRIX_PROBLEM_ROLLING_GLOBAL;
    const int64_t nc = frix_problem_contacts(problem.get());
    const int64_t n = global ? frix_problem_dofs(problem.get()) : 0;
    const std::string name = std::string("siconos:") + frix_siconos_solver_name(id);
    // A solver for the other kind of problem is a usage error, found before anything runs;
    // the bench, which runs every solver on every problem, records it as unsupported.
    // Siconos has no problem with spinning friction (its rolling problems have five entries a
    // contact): every one of its solvers refuses one.
    const bool rolling_solver = frix_siconos_solver_is_rolling(id) == 1;
    const bool spinning = frix_problem_mu_s(problem.get()) != nullptr;
    if (spinning || frix_siconos_solver_is_global(id) != (global ? 1 : 0) || rolling_solver != rolling) {
        const std::string why =
            spinning ? name + " cannot solve " + a.file +
                           ": it has spinning friction (six entries a contact), which Siconos has no problem for "
                           "(frix's rolling solvers take it)"
            : rolling != rolling_solver
                ? (rolling ? name + " does not solve rolling-friction problems (" + a.file +
                                 " is one): use RFC3D_NSGS or RFC3D_ADMM (local form) or GRFC3D_NSGS_WR (global)"
                           : name + " solves rolling-friction problems only, and " + a.file + " is not one")
            : rolling ? (global ? name + " solves the local form (W) of rolling problems, and " + a.file +
                                      " is global: use GRFC3D_NSGS_WR"
                                : name + " solves the global form of rolling problems, and " + a.file +
                                      " is local: use RFC3D_NSGS or RFC3D_ADMM")
            : global  ? name + " is a local solver (fc3d_driver) and " + a.file +
                           " is a global problem: use a GFC3D_ solver (see 'frix-siconos --list')"
                      : name + " is a global solver (gfc3d_driver) and " + a.file +
                           " is a local problem: use an FC3D solver (see 'frix-siconos --list')";
        if (a.fd >= 0) {
            frix_bench::write_line(a.fd, frix_bench::note_line(why));
            frix_bench::write_line(a.fd, frix_bench::result_line("unsupported", 0, NAN, NAN, NAN, NAN));
            frix_bench::write_line(a.fd, frix_bench::peak_memory_line());
            return kExitUsage;
        }
        fail(why);
    }
    std::vector<double> r(static_cast<std::size_t>(std::max<int64_t>(frix_problem_contact_dofs(problem.get()), 1)),
                          0.0);
    std::vector<double> u(r.size(), 0.0);
    std::vector<double> v(static_cast<std::size_t>(std::max<int64_t>(n, 1)), 0.0);
    double *vp = global ? v.data() : nullptr;
    if (a.guess > 0) start_from_guess(a.file, problem.get(), a.guess, r.data(), u.data(), vp);
    const std::vector<double> r0 = r, v0 = v;
    TraceSink sink;
    sink.fd = a.fd;
    frix_siconos_result res;
    frix_bench::RepeatTimer timer;
    {
        SiconosOutputToStderr quiet_stdout;
        frix_siconos_solve(problem.get(), id, a.tol, a.max_iter, r.data(), u.data(), vp,
                           on_iteration, &sink, &res);
        // Short solves again from the same start, without the trace, for the median time
        // (RepeatTimer, the same rule as frix's side).
        timer.add(res.time);
        while (res.ran && timer.again()) {
            std::vector<double> r2 = r0, u2(u.size(), 0.0), v2 = v0;
            frix_siconos_result again;
            frix_siconos_solve(problem.get(), id, a.tol, a.max_iter, r2.data(), u2.data(),
                               global ? v2.data() : nullptr, nullptr, nullptr, &again);
            if (!again.ran) break;
            timer.add(again.time);
        }
    }
    res.time = timer.median();
    const char *status = status_of(res, a.tol, a.max_iter, global);
    std::string note = res.message;
    if (res.ran && res.callbacks == 0)
        note = "no per-iteration trace (this solver does not call Siconos's iteration callback)";

    if (a.fd >= 0) {
        // The result line has one error field, from which the bench ranks every run whatever
        // its status: for a global problem frix_bench::global_error. Both measures are in the
        // note, which runs.csv keeps.
        double error = res.error, error_scaled = res.error_scaled;
        if (global && res.ran) {
            char eq[96];
            std::snprintf(eq, sizeof eq, "error %.3e, equilibrium %.3e (error column: the larger)",
                          res.error, res.equilibrium);
            note = note.empty() ? std::string(eq) : note + "; " + eq;
            error = frix_bench::global_error(res.error, res.equilibrium);  // error_scaled holds it already
        }
        if (!note.empty()) frix_bench::write_line(a.fd, frix_bench::note_line(note));
        frix_bench::write_line(a.fd, frix_bench::result_line(status, res.iterations, error,
                                                             res.time, res.siconos_error, error_scaled));
        frix_bench::write_line(a.fd, frix_bench::peak_memory_line());
    } else if (a.json) {
        JsonWriter w;
        w.begin_object();
        w.string("file", a.file);
        w.string("kind", global ? (rolling ? "rolling-global" : "global") : rolling ? "rolling-local" : "local");
        w.integer("contacts", nc);
        if (global) w.integer("dofs", n);
        w.string("solver", name);
        w.integer("solver_id", id);
        w.string("status", status);
        w.boolean("converged", std::string(status) == "converged");
        w.integer("iterations", res.iterations);
        w.number("error", res.error);
        w.string("error_measure", "relative");
        w.number("tolerance", a.tol);
        w.number("time", res.time);
        w.integer("siconos_info", res.info);
        w.number("siconos_error", res.siconos_error);
        // Where `frix solve --json` has them: frix's default measure too, so that both
        // libraries compare in it.
        w.begin_object("measures");
        w.number("error_scaled", res.error_scaled);
        w.number("error_relative", res.error);
        if (global) w.number("equilibrium", res.equilibrium);
        w.end_object();
        if (note.empty())
            w.null("note");
        else
            w.string("note", note);
        if (a.trace) {
            w.begin_array("trace");
            for (std::size_t k = 0; k + 2 < sink.points.size(); k += 3) {
                w.begin_array();
                w.integer(nullptr, static_cast<std::int64_t>(sink.points[k]));
                w.number(nullptr, sink.points[k + 1]);
                w.number(nullptr, sink.points[k + 2]);
                w.end_array();
            }
            w.end_array();
        }
        w.end_object();
        std::printf("%s\n", w.text().c_str());
    } else {
        std::printf("%-16s %s\n", "file", a.file.c_str());
        if (global)
            std::printf("%-16s %s, %lld contacts, %lld dofs\n", "problem", rolling ? "rolling-global" : "global",
                        static_cast<long long>(nc), static_cast<long long>(n));
        else
            std::printf("%-16s %s, %lld contacts\n", "problem", rolling ? "rolling-local" : "local",
                        static_cast<long long>(nc));
        std::printf("%-16s %s (id %d)\n", "solver", name.c_str(), id);
        std::printf("%-16s %s\n", "status", status);
        std::printf("%-16s %lld\n", "iterations", static_cast<long long>(res.iterations));
        std::printf("%-16s %.3e (frix's relative measure, tolerance %.1e)\n", "error", res.error,
                    a.tol);
        if (global) std::printf("%-16s %.3e\n", "equilibrium", res.equilibrium);
        std::printf("%-16s %.3e (info %d)\n", "siconos error", res.siconos_error, res.info);
        std::printf("%-16s %.3g s (%s)\n", "time", res.time,
                    global ? (rolling ? "g_rolling_fc3d_driver" : "gfc3d_driver")
                           : rolling ? "rolling_fc3d_driver" : "fc3d_driver");
        if (!note.empty()) std::printf("%-16s %s\n", "note", note.c_str());
    }
    if (!res.ran && a.fd < 0) fail(a.file + ": " + res.message);
    return std::string(status) == "converged" ? kExitConverged : kExitNotConverged;
}

}  // namespace
}  // namespace frix_cli

// Read by LeakSanitizer in sanitizer builds (FRIX_SANITIZE), unused otherwise: Siconos 4.4
// leaks a few structs of its own per solve (solver_options_delete does not release the
// options it deletes, NM_preserve's copy is not freed), and its global rolling driver the
// sparse matrices of its reformulation, allocated by CXSparse, whose frames LeakSanitizer's
// unwinder does not pass (the adapter itself allocates nothing through CXSparse). Not ours to
// fix; ours stay checked.
extern "C" const char *__lsan_default_suppressions();
extern "C" __attribute__((used)) const char *__lsan_default_suppressions() {
    return "leak:libsiconos_numerics.so\nleak:libcxsparse.so\n";
}

int main(int argc, char **argv) {
    try {
        return frix_cli::run(argc, argv);
    } catch (const frix_cli::Failure &f) {
        // The CLI's argument helpers word messages for `frix SUBCOMMAND`; this is a program
        // of its own, named once.
        std::string msg = f.message;
        const std::string self = "frix-siconos: ", sub = "'frix frix-siconos --help'";
        if (msg.compare(0, self.size(), self) == 0) msg.erase(0, self.size());
        std::size_t at = msg.find(sub);
        if (at != std::string::npos) msg.replace(at, sub.size(), "'frix-siconos --help'");
        std::fflush(stdout);
        std::fprintf(stderr, "frix-siconos: %s\n", msg.c_str());
        return f.code;
    }
}
