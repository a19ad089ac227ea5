// `frix bench [FILES or DIRS...] --solvers LIST --tol T --time-limit S --out DIR`: every
// solver on every problem, each run in a child process (bench_runner.hpp), then the report
// (bench_report.cpp): DIR/runs.csv, DIR/traces.csv, profiles, work-precision, summary, plots.
#include "args.hpp"
#include "bench.hpp"
#include "bench_protocol.hpp"
#include "bench_runner.hpp"
#include "cli.hpp"
#include "csv.hpp"

#include <dirent.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <set>
#include <sstream>

namespace frix_cli {
namespace {

// The Siconos solvers of the shared baseline (siconos-4.4-baseline.csv): "siconos:all".
const char *const kSiconosAll[] = {"NSGS", "NSN_AC", "NSN_FB", "NSN_NM", "PROX",
                                   "VI_FPP", "VI_EG", "TFP", "ADMM"};

struct BenchArgs {
    std::vector<std::string> paths;
    std::string solvers = "all", out, report_dir;
    double tol = 1e-8, time_limit = 10, grace = -1;
    std::int64_t max_iter = 100000, jobs = 1;
    std::int64_t rounds = 1;  // --rounds K: each pair run K times, the time their median
    std::int64_t guess = 0;  // --guess K: every run starts from each file's guess K; 0: from r = 0
    bool plots = true, quiet = false, help = false;
};

struct Solver {
    std::string name;  // "nsgs", "siconos:NSGS", "gnsgs@threads=2"
    int id = 0;
    bool siconos = false;
    std::vector<std::string> settings;  // frix's: "NAME=VALUE", passed to bench-run as --set
};

struct Problem {
    std::string path, name, family;
    // From the first run that read the problem (the bench reads none itself); -1 and NaN
    // until then, and for a problem no run could read.
    std::int64_t contacts = -1, dofs = -1;
    double stored_blocks = NAN;  // see RunRecord
};

volatile std::sig_atomic_t g_interrupted = 0;
void on_interrupt(int) { g_interrupted = 1; }

BenchArgs parse(int argc, char **argv) {
    ArgCursor args("bench", argc, argv);
    BenchArgs a;
    std::string v;
    while (!args.done()) {
        if (args.flag("--help") || args.flag("-h")) {
            a.help = true;
            return a;
        } else if (args.option("--solvers", v)) {
            a.solvers = v;
        } else if (args.option("--tol", v)) {
            a.tol = parse_double("bench", "--tol", v);
        } else if (args.option("--time-limit", v)) {
            a.time_limit = parse_double("bench", "--time-limit", v);
        } else if (args.option("--grace", v)) {
            a.grace = parse_double("bench", "--grace", v);
        } else if (args.option("--max-iter", v)) {
            a.max_iter = parse_int("bench", "--max-iter", v);
        } else if (args.option("--guess", v)) {
            a.guess = parse_guess_number("bench", v);
        } else if (args.option("--rounds", v)) {
            a.rounds = parse_int("bench", "--rounds", v);
        } else if (args.option("--jobs", v) || args.option("-j", v)) {
            a.jobs = parse_int("bench", "--jobs", v);
        } else if (args.option("--out", v) || args.option("-o", v)) {
            a.out = v;
        } else if (args.option("--report", v)) {
            a.report_dir = v;
        } else if (args.flag("--no-plots")) {
            a.plots = false;
        } else if (args.flag("--quiet") || args.flag("-q")) {
            a.quiet = true;
        } else if (args.at_option()) {
            args.unknown_option();
        } else {
            a.paths.push_back(args.positional());
        }
    }
    if (!a.report_dir.empty()) {
        if (!a.paths.empty() || !a.out.empty())
            usage_error("bench", "--report DIR takes no problems and no --out");
        return a;
    }
    if (a.paths.empty()) usage_error("bench", "expected FILES or DIRS of problems");
    if (a.out.empty()) usage_error("bench", "--out DIR is required");
    if (!(a.tol > 0 && a.tol <= 1)) usage_error("bench", "--tol must be in (0, 1]");
    if (!(a.time_limit > 0)) usage_error("bench", "--time-limit must be > 0 seconds");
    if (a.max_iter < 1) usage_error("bench", "--max-iter must be >= 1");
    if (a.jobs < 1 || a.jobs > 64) usage_error("bench", "--jobs must be in [1, 64]");
    if (a.rounds < 1 || a.rounds > 99) usage_error("bench", "--rounds must be in [1, 99]");
    if (a.grace < 0) a.grace = 1.0 + 0.2 * a.time_limit;
    return a;
}

std::string upper(std::string s) {
    for (char &c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    return s;
}

// The Siconos solvers the comparator offers, by asking it ("frix-siconos --list").
std::vector<Solver> siconos_catalogue(const std::string &adapter) {
    int code = 0;
    std::string text = capture_output({adapter, "--list"}, &code);
    if (code != 0) fail("bench: " + adapter + " --list failed (exit code " + std::to_string(code) + ")");
    std::vector<Solver> out;
    std::istringstream in(text);
    Solver s;
    std::string name;
    while (in >> s.id >> name) {
        s.name = "siconos:" + name;
        s.siconos = true;
        out.push_back(s);
    }
    return out;
}

std::vector<Solver> resolve_solvers(const std::string &list, const std::string &adapter) {
    std::vector<Solver> out;
    std::vector<Solver> catalogue;
    bool catalogue_read = false, warned = false;
    auto add = [&](const Solver &s) {
        for (const Solver &o : out)
            if (o.name == s.name) return;
        out.push_back(s);
    };
    for (const std::string &item : split(list, ',')) {
        if (item.compare(0, 8, "siconos:") == 0) {
            if (::access(adapter.c_str(), X_OK) != 0) {
                if (!warned)
                    std::fprintf(stderr,
                                 "frix: bench: Siconos solvers skipped: %s was not built (install "
                                 "libsiconos-numerics-dev and configure again)\n",
                                 adapter.c_str());
                warned = true;
                continue;
            }
            if (!catalogue_read) catalogue = siconos_catalogue(adapter);
            catalogue_read = true;
            // The catalogue's names: local solvers short (NSGS), global ones as GFC3D_NSN_AC.
            std::string want = upper(item.substr(8));
            for (const char *prefix : {"SICONOS_", "FRICTION_3D_", "FC3D_"})
                if (want.compare(0, std::string(prefix).size(), prefix) == 0)
                    want.erase(0, std::string(prefix).size());
            const std::string global = "GLOBAL_FRICTION_3D_";
            if (want.compare(0, global.size(), global) == 0) want.replace(0, global.size(), "GFC3D_");
            std::vector<std::string> wanted = {want};
            if (want == "ALL") wanted.assign(std::begin(kSiconosAll), std::end(kSiconosAll));
            bool found = false;
            for (const std::string &w : wanted)
                for (const Solver &s : catalogue)
                    if (s.name == "siconos:" + w || std::to_string(s.id) == w) {
                        add(s);
                        found = true;
                    }
            if (!found) usage_error("bench", "unknown Siconos solver '" + item + "' (see 'frix-siconos --list')");
        } else if (item == "all") {
            for (int64_t k = 0; k < frix_solver_count(); ++k) {
                int id = frix_solver_id_at(k);
                add({frix_solver_name(id), id, false, {}});
            }
        } else {
            // NAME@OPTION=VALUE@...: a frix solver with options of its own.
            std::vector<std::string> parts = split(item, '@');
            int id = 0;
            if (frix_solver_by_name(parts[0].c_str(), &id) != FRIX_OK)
                usage_error("bench", "unknown solver '" + parts[0] + "' (see 'frix solvers')");
            Solver s{frix_solver_name(id), id, false, {}};
            for (std::size_t k = 1; k < parts.size(); ++k) {
                const std::size_t eq = parts[k].find('=');
                frix_option_key key{};
                if (eq == std::string::npos || eq + 1 == parts[k].size() ||
                    frix_option_by_name(parts[k].substr(0, eq).c_str(), &key) != FRIX_OK)
                    usage_error("bench", "'" + item + "': expected SOLVER@OPTION=VALUE with an option of 'frix solvers'");
                s.settings.push_back(parts[k]);
                s.name += "@" + parts[k];
            }
            add(s);
        }
    }
    if (out.empty()) usage_error("bench", "no solver to run");
    return out;
}

bool is_directory(const std::string &path) {
    struct stat st;
    return ::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

std::string base_name(const std::string &path) {
    std::size_t slash = path.find_last_of('/');
    return slash == std::string::npos ? path : path.substr(slash + 1);
}

// A directory gives its *.hdf5 files (sorted); a file is taken as given. No problem is read
// here: each run reads its own in its child process, within the run's time limit, so that a
// file that hangs, crashes or refuses the reader costs its own rows only. A path that does
// not exist is reported and left out (stat opens nothing, so a FIFO cannot block it).
std::vector<Problem> collect_problems(const std::vector<std::string> &paths) {
    std::vector<std::string> files;
    for (const std::string &p : paths) {
        if (!is_directory(p)) {
            files.push_back(p);
            continue;
        }
        std::vector<std::string> names;
        if (DIR *d = ::opendir(p.c_str())) {
            while (const dirent *e = ::readdir(d)) {
                std::string n = e->d_name;
                if (n.size() > 5 && n.compare(n.size() - 5, 5, ".hdf5") == 0) names.push_back(n);
            }
            ::closedir(d);
        }
        std::sort(names.begin(), names.end());
        for (const std::string &n : names) files.push_back(p + (p.back() == '/' ? "" : "/") + n);
    }
    std::vector<Problem> out;
    std::multiset<std::string> seen;
    for (const std::string &f : files) seen.insert(base_name(f));
    for (const std::string &f : files) {
        Problem pr;
        pr.path = f;
        pr.name = base_name(f);
        if (seen.count(pr.name) > 1) {  // same name in two directories: keep them apart
            std::string dir = f.substr(0, f.size() - pr.name.size());
            while (!dir.empty() && dir.back() == '/') dir.pop_back();
            pr.name = base_name(dir) + "/" + pr.name;
        }
        pr.family = problem_family(pr.name);
        struct stat st;
        if (::stat(f.c_str(), &st) != 0) {
            std::fprintf(stderr, "frix: bench: left out: cannot read %s: %s\n", f.c_str(), std::strerror(errno));
            continue;
        }
        out.push_back(pr);
    }
    if (out.empty()) usage_error("bench", "no problem among the paths given");
    return out;
}

std::string safe_file_name(std::string s) {
    for (char &c : s)
        if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '-' && c != '_') c = '_';
    return s;
}

// The terminal line: problem k of N, solver, elapsed, ETA.
class Progress {
public:
    Progress(std::size_t total, bool quiet)
        : total_(total), quiet_(quiet), tty_(::isatty(2) != 0), start_(now_seconds()) {}
    void running(std::size_t done, const std::string &what) {
        if (quiet_ || !tty_) return;
        // Redrawn at most 5 times a second: the loop wakes up for every trace line.
        if (done == last_done_ && now_seconds() - last_draw_ < 0.2) return;
        draw(done, what);
    }
    void finished(std::size_t done, const RunRecord &r) {
        if (quiet_) return;
        if (tty_) {
            draw(done, r.problem + "  " + r.solver + ": " + r.status);
            return;
        }
        std::fprintf(stderr, "[%zu/%zu] %s %s: %s, %.3g s (%s elapsed, ETA %s)\n", done, total_,
                     r.problem.c_str(), r.solver.c_str(), r.status.c_str(), r.time,
                     clock_text(elapsed()).c_str(), clock_text(eta(done)).c_str());
    }
    void end() {
        if (!quiet_ && tty_) std::fprintf(stderr, "\r\033[K");
    }
    double elapsed() const { return now_seconds() - start_; }

private:
    double eta(std::size_t done) const {
        return done ? elapsed() / static_cast<double>(done) * static_cast<double>(total_ - done) : 0;
    }
    void draw(std::size_t done, const std::string &what) {
        const int bar = 20;
        int filled = static_cast<int>(bar * done / std::max<std::size_t>(total_, 1));
        std::string line = "[" + std::to_string(done) + "/" + std::to_string(total_) + "] [" +
                           std::string(static_cast<std::size_t>(filled), '#') +
                           std::string(static_cast<std::size_t>(bar - filled), '.') + "] " +
                           clock_text(elapsed()) + " elapsed, ETA " +
                           (done ? clock_text(eta(done)) : std::string("?")) + "  " + what;
        winsize ws{};
        std::size_t width = ::ioctl(2, TIOCGWINSZ, &ws) == 0 && ws.ws_col > 20 ? ws.ws_col : 100;
        if (line.size() >= width) line = line.substr(0, width - 1);
        std::fprintf(stderr, "\r\033[K%s", line.c_str());
        std::fflush(stderr);
        last_done_ = done;
        last_draw_ = now_seconds();
    }
    std::size_t total_;
    bool quiet_, tty_;
    double start_, last_draw_ = 0;
    std::size_t last_done_ = static_cast<std::size_t>(-1);
};

void write_file(const std::string &path, const std::string &text) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << text;
    if (!out) fail("bench: cannot write " + path);
}

// Rescales a run's trace (its points in time order) to end at `time`, shorter or longer: the
// time reported is a median of solves, and the trace stays on that one clock.
void end_trace_at(std::vector<TracePoint> &trace, double time) {
    if (trace.empty() || !(trace.back().elapsed > 0.0) || !std::isfinite(time)) return;
    // Clamped: x * (time / x) may exceed time by an ulp, and the rows that follow must not go
    // back in time.
    const double scale = time / trace.back().elapsed;
    for (TracePoint &t : trace) t.elapsed = std::min(t.elapsed * scale, time);
}

int run_campaign(const BenchArgs &a) {
    const std::string self = self_directory();
    const std::string adapter = self + "/frix-siconos";
    std::vector<Solver> solvers = resolve_solvers(a.solvers, adapter);
    std::vector<Problem> problems = collect_problems(a.paths);

    for (std::size_t slash = a.out.find('/', 1); slash != std::string::npos; slash = a.out.find('/', slash + 1))
        ::mkdir(a.out.substr(0, slash).c_str(), 0755);  // like mkdir -p
    ::mkdir(a.out.c_str(), 0755);
    const std::string logs = a.out + "/logs";
    ::mkdir(logs.c_str(), 0755);
    if (!is_directory(logs)) fail("bench: cannot create " + logs);

    // A pair is (problem, solver); a run is a pair's round. A problem's runs go round by round
    // (every solver once, then again), so that a pair's rounds and its rivals' interleave in
    // time; a pair whose first round did not converge is not run again.
    const std::size_t total = problems.size() * solvers.size(), rounds = static_cast<std::size_t>(a.rounds);
    const std::size_t slots = total * rounds;
    auto pair_of = [&](std::size_t run) {
        return run / (rounds * solvers.size()) * solvers.size() + run % solvers.size();
    };
    auto round_of = [&](std::size_t run) { return run / solvers.size() % rounds; };
    std::vector<RunRecord> records(total);
    std::vector<std::vector<TracePoint>> traces(total);
    std::vector<std::vector<double>> round_times(total);
    std::vector<char> first_done(total, 0);
    // Written as the runs end, so that an interrupted campaign keeps what it did; rewritten
    // in (problem, solver) order at the end.
    std::ofstream runs_csv(a.out + "/runs.csv", std::ios::trunc);
    std::ofstream traces_csv(a.out + "/traces.csv", std::ios::trunc);
    if (!runs_csv || !traces_csv) fail("bench: cannot write into " + a.out);
    runs_csv << csv_row(runs_header()) << std::flush;
    traces_csv << csv_row(traces_header()) << std::flush;

    const std::string in_rounds =
        rounds > 1 ? " (at most " + std::to_string(slots) + " in " + std::to_string(rounds) + " rounds)" : "";
    std::fprintf(stderr, "frix bench: %zu problems x %zu solvers = %zu runs%s, tolerance %g, "
                         "time limit %g s (+%g s grace), %lld job(s)\n",
                 problems.size(), solvers.size(), total, in_rounds.c_str(), a.tol, a.time_limit, a.grace,
                 static_cast<long long>(a.jobs));
    auto old_int = std::signal(SIGINT, on_interrupt);
    auto old_term = std::signal(SIGTERM, on_interrupt);

    // "problem 3/28 Capsules-i125-1213.hdf5  siconos:NSN_AC"
    auto running_text = [&](std::size_t run) {
        const std::size_t k = pair_of(run) / solvers.size();
        return "problem " + std::to_string(k + 1) + "/" + std::to_string(problems.size()) + " " +
               problems[k].name + "  " + solvers[run % solvers.size()].name +
               (rounds > 1 ? " (round " + std::to_string(round_of(run) + 1) + ")" : std::string());
    };
    Runner runner(static_cast<std::size_t>(a.jobs));
    Progress progress(slots, a.quiet);
    std::size_t next = 0, done = 0, started = 0;  // done: runs ended or skipped
    char num[64];
    while ((next < slots || runner.running() > 0) && !g_interrupted) {
        while (runner.can_start() && next < slots) {
            const std::size_t pair = pair_of(next);
            if (round_of(next) > 0) {
                if (!first_done[pair]) break;  // a later round waits for the first one's verdict
                if (!records[pair].converged()) {
                    ++next, ++done;
                    continue;
                }
            }
            const Problem &p = problems[pair / solvers.size()];
            const Solver &s = solvers[pair % solvers.size()];
            RunSpec spec;
            spec.index = next;
            spec.log_path = logs + "/run-" + std::to_string(next) + ".log";
            // The limit counts from the child's start, reading the problem included. frix's
            // solvers stop themselves at it and get the grace to report; Siconos's have no
            // time limit: past it they only burn the campaign's time, so they are killed sooner.
            spec.wall_limit = a.time_limit + (s.siconos ? std::min(a.grace, 1.0) : a.grace);
            std::snprintf(num, sizeof num, "%.17g", a.tol);
            std::string tol = num;
            if (s.siconos) {
                spec.argv = {adapter, p.path, "--solver", s.name.substr(8), "--tol", tol,
                             "--max-iter", std::to_string(a.max_iter)};
            } else {
                std::snprintf(num, sizeof num, "%.17g", a.time_limit);
                spec.argv = {self + "/frix", "bench-run", p.path, "--solver", frix_solver_name(s.id), "--tol", tol,
                             "--max-iter", std::to_string(a.max_iter), "--time-limit", num};
                for (const std::string &kv : s.settings) {
                    spec.argv.push_back("--set");
                    spec.argv.push_back(kv);
                }
            }
            if (a.guess > 0) {
                spec.argv.push_back("--guess");
                spec.argv.push_back(std::to_string(a.guess));
            }
            runner.start(spec);
            ++started;
            progress.running(done, running_text(next));
            ++next;
        }
        for (RunOutcome &o : runner.poll(0.25)) {
            const std::size_t run = o.index, pair = pair_of(run);
            Problem &p = problems[pair / solvers.size()];
            const Solver &s = solvers[pair % solvers.size()];
            if (o.problem_read() && p.contacts < 0) {
                p.contacts = o.contacts;
                p.dofs = o.dofs;
                p.stored_blocks = o.stored_blocks;
            }
            // frix's runs say when they have read the problem; one killed before is stopped
            // by the time limit while reading (a huge or slow file), not while solving.
            if (o.status == "timeout" && !s.siconos && !o.problem_read()) o.note += " while reading the problem";
            // frix-siconos reads with frix's reader and says so in the same words.
            if (s.siconos && o.status == "error" && o.note.find("cannot read " + p.path + ": ") != std::string::npos)
                o.status = "unreadable";
            const std::string log = logs + "/run-" + std::to_string(run) + ".log";
            if (round_of(run) > 0) {
                const bool in_time = o.status == "converged" && o.time <= a.time_limit;
                round_times[pair].push_back(in_time ? o.time : a.time_limit);
                if (!in_time)
                    records[pair].note += std::string(records[pair].note.empty() ? "" : "; ") + "round " +
                                          std::to_string(round_of(run) + 1) + ": " + o.status +
                                          " (its time counted at the limit)";
                ::unlink(log.c_str());
                ++done;
                RunRecord shown = records[pair];
                shown.status = o.status, shown.time = o.time;
                progress.finished(done, shown);
                continue;
            }
            RunRecord &r = records[pair];
            r = {p.name, p.family, p.contacts, p.dofs, s.name, s.id, o.status, o.iterations,
                 o.error, o.time, a.tol, a.time_limit, a.max_iter, o.reported_error, o.note,
                 o.peak_memory / 1e6, p.stored_blocks, o.error_scaled};
            // One rule for all: a result after the time limit does not count as converged
            // (frix's solvers stop themselves at it; Siconos's are only killed later).
            if (r.converged() && r.time > a.time_limit) {
                r.status = "time_limit";
                r.note = "converged after the time limit";
            }
            first_done[pair] = 1;
            round_times[pair].push_back(r.time);
            traces[pair] = std::move(o.trace);
            if (std::isfinite(r.error) && std::isfinite(r.time) && r.status != "timeout" &&
                r.status.compare(0, 5, "crash") != 0) {
                // The trace is the first solve's; the time reported is the median of the
                // repeats of a short solve (RepeatTimer), usually shorter: the trace is
                // rescaled to end at it.
                if (!traces[pair].empty() && traces[pair].back().elapsed > r.time) end_trace_at(traces[pair], r.time);
                traces[pair].push_back({r.iterations, r.time, r.error});
            }
            ++done;
            runs_csv << csv_row(run_fields(r)) << std::flush;
            for (const TracePoint &t : traces[pair])
                traces_csv << csv_row({r.problem, r.solver, std::to_string(t.iteration),
                                       number_text(t.elapsed), number_text(t.error)});
            traces_csv.flush();
            // Logs are kept for the runs that did not converge and said something.
            struct stat st;
            if (r.converged() || ::stat(log.c_str(), &st) != 0 || st.st_size == 0)
                ::unlink(log.c_str());
            else
                ::rename(log.c_str(), (logs + "/" + safe_file_name(p.name + "--" + s.name) + ".log").c_str());
            progress.finished(done, r);
        }
        if (runner.running() > 0) progress.running(done, running_text(runner.running_indices().front()));
    }
    progress.end();
    std::signal(SIGINT, old_int);
    std::signal(SIGTERM, old_term);
    if (g_interrupted) {
        runner.kill_all();
        std::fprintf(stderr, "frix bench: interrupted after %zu of %zu runs; %s/runs.csv has the first rounds\n",
                     done, slots, a.out.c_str());
        return 130;
    }
    ::rmdir(logs.c_str());  // only if empty

    std::string runs_text = csv_row(runs_header()), traces_text = csv_row(traces_header());
    for (std::size_t k = 0; k < total; ++k) {
        if (round_times[k].size() > 1) {
            records[k].time = frix_bench::median(round_times[k]);  // a missed round counts at the limit
            end_trace_at(traces[k], records[k].time);
        }
        // A run that ended before any other had read its problem (Siconos's, one killed
        // while reading) gets the sizes another run read.
        const Problem &p = problems[k / solvers.size()];
        if (records[k].contacts < 0 && p.contacts >= 0) {
            records[k].contacts = p.contacts;
            records[k].dofs = p.dofs;
            records[k].stored_blocks = p.stored_blocks;
        }
        runs_text += csv_row(run_fields(records[k]));
        for (const TracePoint &t : traces[k])
            traces_text += csv_row({records[k].problem, records[k].solver, std::to_string(t.iteration),
                                    number_text(t.elapsed), number_text(t.error)});
    }
    runs_csv.close();
    traces_csv.close();
    write_file(a.out + "/runs.csv", runs_text);
    write_file(a.out + "/traces.csv", traces_text);
    std::fprintf(stderr, "frix bench: %zu runs in %s\n", started, clock_text(progress.elapsed()).c_str());
    std::printf("%s\n", bench_report(a.out, a.plots, self).c_str());
    return kExitConverged;
}

}  // namespace

int cmd_bench(int argc, char **argv) {
    BenchArgs a = parse(argc, argv);
    if (a.help) {
        print_bench_help(stdout);
        return kExitConverged;
    }
    if (!a.report_dir.empty()) {
        std::printf("%s\n", bench_report(a.report_dir, a.plots, self_directory()).c_str());
        return kExitConverged;
    }
    return run_campaign(a);
}

}  // namespace frix_cli
