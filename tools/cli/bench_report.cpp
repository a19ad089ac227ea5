// `frix bench` report: from DIR/runs.csv and DIR/traces.csv to the performance profiles
// (profile.csv), the work-precision table (work_precision.csv), the summary tables
// (summary.md) and the plots (the Python script beside the frix executable draws what is
// computed here, so the numbers are tested without matplotlib).
#include "bench.hpp"
#include "cli.hpp"
#include "csv.hpp"

#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <set>

namespace frix_cli {
namespace {

// Times below this are raised to it: a ratio of two microsecond timings is noise.
constexpr double kTimeFloor = 1e-6;
// The accuracies of the work-precision curves, 1e-2 ... 1e-10.
constexpr int kFirstLevel = 2, kLastLevel = 10;

double to_number(const std::string &s) {
    if (s.empty()) return NAN;
    char *end = nullptr;
    double v = std::strtod(s.c_str(), &end);
    return *end == '\0' ? v : NAN;
}

std::vector<RunRecord> read_runs(const std::string &path) {
    CsvTable t = CsvTable::read(path, {"problem", "family", "solver", "status", "time", "error"});
    std::vector<RunRecord> out;
    for (std::size_t k = 0; k < t.rows(); ++k) {
        RunRecord r;
        r.problem = t.get(k, "problem");
        r.family = t.get(k, "family");
        r.contacts = std::atoll(t.get(k, "contacts").c_str());
        r.dofs = std::atoll(t.get(k, "dofs").c_str());
        r.solver = t.get(k, "solver");
        r.solver_id = std::atoi(t.get(k, "solver_id").c_str());
        r.status = t.get(k, "status");
        r.iterations = std::atoll(t.get(k, "iterations").c_str());
        r.error = to_number(t.get(k, "error"));
        r.time = to_number(t.get(k, "time"));
        r.tolerance = to_number(t.get(k, "tolerance"));
        r.time_limit = to_number(t.get(k, "time_limit"));
        r.max_iter = std::atoll(t.get(k, "max_iter").c_str());
        r.reported_error = to_number(t.get(k, "reported_error"));
        r.note = t.get(k, "note");
        r.peak_memory_mb = to_number(t.get(k, "peak_memory_mb"));  // absent from older campaigns
        r.stored_blocks = to_number(t.get(k, "stored_blocks"));    // as is this
        r.error_scaled = to_number(t.get(k, "error_scaled"));      // and this
        if (r.problem.empty() || r.solver.empty()) fail(path + ": row " + std::to_string(k + 2) + " lacks a problem or solver");
        out.push_back(r);
    }
    return out;
}

TraceMap read_traces(const std::string &path) {
    TraceMap out;
    struct stat st;
    if (::stat(path.c_str(), &st) != 0) return out;
    CsvTable t = CsvTable::read(path, {"problem", "solver", "elapsed", "error"});
    for (std::size_t k = 0; k < t.rows(); ++k)
        out[{t.get(k, "problem"), t.get(k, "solver")}].push_back(
            {std::atoll(t.get(k, "iteration").c_str()), to_number(t.get(k, "elapsed")),
             to_number(t.get(k, "error"))});
    return out;
}

template <class T>
void push_unique(std::vector<T> &v, const T &x) {
    if (std::find(v.begin(), v.end(), x) == v.end()) v.push_back(x);
}

double floored(double t) { return std::max(t, kTimeFloor); }

double geomean(const std::vector<double> &v) {
    if (v.empty()) return NAN;
    double s = 0;
    for (double x : v) s += std::log(floored(x));
    return std::exp(s / static_cast<double>(v.size()));
}

std::string fmt(const char *format, double v) {
    if (std::isnan(v)) return "–";
    char buf[64];
    std::snprintf(buf, sizeof buf, format, v);
    return buf;
}

// The time at which a run first reached `accuracy`, or NaN. A run counts only if its final
// error (frix's measure; for a killed run the last estimate) is within the accuracy; the
// time is then the first trace point at that accuracy. A trace carries errors of iterates
// (bench-run sets callback_estimates 0; the Siconos adapter measures a local solver's
// iterates, a global solver's trace is its own error); a later point above the accuracy is
// an iterate that auto, or a solver that does not keep its best, moved away from
// (settled_table.py marks such times).
double reach_time(const RunRecord &r, const std::vector<TracePoint> *trace, double accuracy) {
    double final_error = r.error, t = r.time;
    if (std::isnan(final_error) && trace && !trace->empty()) final_error = trace->back().error;
    if (!(final_error <= accuracy)) return NAN;
    if (std::isnan(t) && trace && !trace->empty()) t = trace->back().elapsed;
    if (trace)
        for (const TracePoint &p : *trace)
            if (p.error <= accuracy) {
                t = std::min(t, p.elapsed);
                break;
            }
    if (std::isfinite(r.time_limit) && t > r.time_limit) return NAN;
    return floored(t);
}

struct Campaign {
    std::vector<RunRecord> runs;
    std::vector<std::string> problems, solvers, families;
    std::map<std::string, std::string> family_of;
    std::map<std::pair<std::string, std::string>, const RunRecord *> at;
    std::map<std::string, int> id_of;  // solver -> its id (frix's, or Siconos's)
    double tolerance = NAN, time_limit = NAN;
    std::int64_t max_iter = 0;
    std::vector<std::string> unsupported;  // solvers that could run none of the problems
    std::vector<std::string> unreadable;   // "problem (the reader's message)", left out
};

Campaign index(std::vector<RunRecord> runs) {
    Campaign c;
    // A problem no run could read is left out of every table and profile: it is a bad file,
    // not a problem the solvers failed on (a hostile file must not move the profiles).
    std::map<std::string, bool> all_unreadable;
    for (const RunRecord &r : runs) {
        auto it = all_unreadable.emplace(r.problem, true).first;
        it->second = it->second && r.status == "unreadable";
    }
    std::set<std::string> listed;
    for (const RunRecord &r : runs) {
        if (!all_unreadable.at(r.problem))
            c.runs.push_back(r);
        else if (listed.insert(r.problem).second)
            c.unreadable.push_back(r.problem + " (" + r.note + ")");
    }
    for (const RunRecord &r : c.runs) {
        push_unique(c.problems, r.problem);
        push_unique(c.solvers, r.solver);
        push_unique(c.families, r.family);
        c.family_of[r.problem] = r.family;
        c.at[{r.problem, r.solver}] = &r;
        c.id_of[r.solver] = r.solver_id;
        if (std::isfinite(r.tolerance)) c.tolerance = r.tolerance;
        if (std::isfinite(r.time_limit)) c.time_limit = r.time_limit;
        c.max_iter = std::max(c.max_iter, r.max_iter);
    }
    // A solver for the other kind of problem (a global-only solver among local problems,
    // which `--solvers all` brings in) is left out of the tables rather than shown at 0.
    for (const std::string &s : c.solvers) {
        bool none = true;
        for (const RunRecord &r : c.runs) none = none && (r.solver != s || r.status == "unsupported");
        if (none) c.unsupported.push_back(s);
    }
    for (const std::string &s : c.unsupported)
        c.solvers.erase(std::find(c.solvers.begin(), c.solvers.end(), s));
    return c;
}

std::string profile_csv(const Campaign &c) {
    std::string out = csv_row({"scope", "problems", "solver", "tau", "rho"});
    std::vector<std::string> scopes = {"all"};
    scopes.insert(scopes.end(), c.families.begin(), c.families.end());
    for (const std::string &scope : scopes) {
        std::vector<const RunRecord *> runs;
        std::set<std::string> problems;
        for (const RunRecord &r : c.runs)
            if (scope == "all" || r.family == scope) {
                runs.push_back(&r);
                problems.insert(r.problem);
            }
        auto profile = performance_profile(runs, c.solvers, problems.size(), kTimeFloor);
        for (const std::string &s : c.solvers)
            for (const ProfileStep &step : profile[s])
                out += csv_row({scope, std::to_string(problems.size()), s, number_text(step.tau),
                                number_text(step.rho)});
    }
    return out;
}

std::string work_precision_csv(const Campaign &c, const TraceMap &traces) {
    std::string out = csv_row({"scope", "solver", "accuracy", "reached", "problems",
                               "geomean_time_reached", "geomean_time_penalized"});
    for (const std::string &s : c.solvers)
        for (int level = kFirstLevel; level <= kLastLevel; ++level) {
            const double accuracy = std::pow(10.0, -level);
            std::vector<double> reached, penalized;
            for (const std::string &p : c.problems) {
                auto run = c.at.find({p, s});
                if (run == c.at.end()) continue;
                auto tr = traces.find({p, s});
                double t = reach_time(*run->second, tr == traces.end() ? nullptr : &tr->second, accuracy);
                if (!std::isnan(t)) reached.push_back(t);
                penalized.push_back(std::isnan(t) ? c.time_limit : t);
            }
            char acc[16];
            std::snprintf(acc, sizeof acc, "1e-%02d", level);
            out += csv_row({"all", s, acc, std::to_string(reached.size()),
                            std::to_string(penalized.size()), number_text(geomean(reached)),
                            number_text(geomean(penalized))});
        }
    return out;
}

bool is_limit(const std::string &status) { return status == "time_limit" || status == "timeout"; }
bool is_crash(const std::string &status) { return status.compare(0, 5, "crash") == 0; }

// The default solver (auto) against the best of frix's other solvers and the best of
// Siconos's on each problem (the fastest that converged), and the geometric means of the three
// with an unsolved problem counted at the time limit. Empty unless auto ran beside another solver.
// Peak memory against the problem's size, per solver: the median over its runs of the peak
// per contact and per stored 3x3 block of the problem (W's, or M's and H's).
std::string memory_md(const Campaign &c) {
    std::string md = "\n| solver | peak memory per contact (kB), median / max | per stored block of the problem (B), "
                     "median / max |\n|---|---:|---:|\n";
    bool any = false;
    for (const std::string &s : c.solvers) {
        std::vector<double> per_contact, per_block;
        for (const std::string &p : c.problems) {
            auto it = c.at.find({p, s});
            if (it == c.at.end()) continue;
            const RunRecord &r = *it->second;
            if (!std::isfinite(r.peak_memory_mb)) continue;
            if (r.contacts > 0) per_contact.push_back(r.peak_memory_mb * 1e3 / (double)r.contacts);
            if (r.stored_blocks > 0) per_block.push_back(r.peak_memory_mb * 1e6 / r.stored_blocks);
        }
        const auto cell = [](std::vector<double> &v) {
            if (v.empty()) return std::string("-");
            std::sort(v.begin(), v.end());
            return fmt("%.3g", v[v.size() / 2]) + " / " + fmt("%.3g", v.back());
        };
        any = any || !per_contact.empty();
        md += "| " + s + " | " + cell(per_contact) + " | " + cell(per_block) + " |\n";
    }
    return any ? md : std::string();
}

std::string best_per_problem_md(const Campaign &c) {
    const bool have_auto = std::find(c.solvers.begin(), c.solvers.end(), "auto") != c.solvers.end();
    if (!have_auto || c.solvers.size() < 2) return "";
    bool have_frix = false, have_siconos = false;
    for (const std::string &s : c.solvers) {
        const bool siconos = s.compare(0, 8, "siconos:") == 0;
        have_siconos = have_siconos || siconos;
        have_frix = have_frix || (!siconos && s != "auto");
    }
    struct Best {
        std::string solver = "none";
        double time = INFINITY;
    };
    std::string rows;
    std::vector<double> g_auto, g_frix, g_siconos;
    char buf[512];
    for (const std::string &p : c.problems) {
        Best frix, siconos;
        double t_auto = INFINITY;
        std::int64_t contacts = 0;
        for (const std::string &s : c.solvers) {
            auto it = c.at.find({p, s});
            if (it == c.at.end()) continue;
            contacts = it->second->contacts;
            if (!it->second->converged()) continue;
            const double t = floored(it->second->time);
            Best &b = s.compare(0, 8, "siconos:") == 0 ? siconos : frix;
            if (s == "auto") t_auto = t;
            else if (t < b.time) b = {s, t};
        }
        auto cell = [](const Best &b) { return b.solver == "none" ? std::string("none") : b.solver + " " + fmt("%.3g", b.time); };
        auto ratio = [&](const Best &b) {
            return std::isfinite(t_auto) && std::isfinite(b.time) ? fmt("%.2f", t_auto / b.time) : std::string("-");
        };
        const auto penal = [&](double t) { return std::isfinite(t) ? t : c.time_limit; };
        g_auto.push_back(penal(t_auto));
        g_frix.push_back(penal(frix.time));
        g_siconos.push_back(penal(siconos.time));
        std::snprintf(buf, sizeof buf, "| %s | %lld | %s |", p.c_str(), static_cast<long long>(contacts),
                      std::isfinite(t_auto) ? fmt("%.3g", t_auto).c_str() : "unsolved");
        rows += buf;
        if (have_frix) rows += " " + cell(frix) + " | " + ratio(frix) + " |";
        if (have_siconos) rows += " " + cell(siconos) + " | " + ratio(siconos) + " |";
        rows += "\n";
    }
    std::string md = "\nThe default (auto) against the fastest other solver that converged, per problem; ratio = "
                     "auto / that time:\n\n| problem | contacts | auto |";
    std::string rule = "|---|---:|---:|";
    if (have_frix) md += " best other frix solver | ratio |", rule += "---|---:|";
    if (have_siconos) md += " best Siconos solver | ratio |", rule += "---|---:|";
    md += "\n" + rule + "\n" + rows;
    const double ga = geomean(g_auto);
    std::snprintf(buf, sizeof buf, "\nGeometric means, an unsolved problem counted at the time limit: auto %s s",
                  fmt("%.3g", ga).c_str());
    md += buf;
    if (have_frix) md += "; best other frix solver " + fmt("%.3g", geomean(g_frix)) + " s (auto / it " + fmt("%.2f", ga / geomean(g_frix)) + ")";
    if (have_siconos) md += "; best Siconos solver " + fmt("%.3g", geomean(g_siconos)) + " s (auto / it " + fmt("%.2f", ga / geomean(g_siconos)) + ")";
    md += ".\n";
    return md;
}

std::string summary_md(const Campaign &c) {
    std::string md;
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "%zu problems, %zu solvers; tolerance %g, time limit %g s per run, at most "
                  "%lld iterations; solved = the run's own verdict (frix's solvers stop on frix's "
                  "default measure, Siconos's on theirs); error = frix's measure of Siconos's kind "
                  "(residual / max(|q|, |r|, |u|)) for every solver, error_scaled = frix's default "
                  "one, both of the r returned (Siconos's measured by frix); times in seconds "
                  "(geometric means, times under 1 µs counted as 1 µs).\n\n",
                  c.problems.size(), c.solvers.size(), c.tolerance, c.time_limit,
                  static_cast<long long>(c.max_iter));
    md += buf;

    // Problems every solver solved: the common ground for the first table's mean.
    std::vector<std::string> common;
    for (const std::string &p : c.problems) {
        bool all = true;
        for (const std::string &s : c.solvers) {
            auto it = c.at.find({p, s});
            all = all && it != c.at.end() && it->second->converged();
        }
        if (all) common.push_back(p);
    }
    // Campaigns since the default measure changed hold both errors of every run: the answers
    // that meet the tolerance by each, whatever the run stopped on.
    bool both = false;
    for (const RunRecord &r : c.runs) both = both || std::isfinite(r.error_scaled);
    std::snprintf(buf, sizeof buf,
                  "| solver | solved%s | time limit | crash | other failure | geomean time, the %zu "
                  "problems all solved | geomean time, unsolved = time limit | peak memory (MB), "
                  "median / max |\n",
                  both ? " | meets the default measure | meets Siconos's measure" : "", common.size());
    md += buf;
    md += both ? "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n" : "|---|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const std::string &s : c.solvers) {
        int solved = 0, limit = 0, crash = 0, other = 0, meets_default = 0, meets_siconos = 0;
        std::vector<double> on_common, penalized, peaks;
        for (const std::string &p : c.problems) {
            auto it = c.at.find({p, s});
            if (it == c.at.end()) continue;
            const RunRecord &r = *it->second;
            if (std::isfinite(r.peak_memory_mb)) peaks.push_back(r.peak_memory_mb);
            meets_default += r.meets_default_measure();
            meets_siconos += r.meets_siconos_measure();
            if (r.converged()) ++solved;
            else if (is_limit(r.status)) ++limit;
            else if (is_crash(r.status)) ++crash;
            else ++other;
            if (std::find(common.begin(), common.end(), p) != common.end()) on_common.push_back(r.time);
            penalized.push_back(r.converged() ? r.time : c.time_limit);
        }
        std::sort(peaks.begin(), peaks.end());
        const std::string peak = peaks.empty() ? "-"
                                               : fmt("%.3g", peaks[peaks.size() / 2]) + " / " + fmt("%.3g", peaks.back());
        const std::string by_measure =
            both ? " | " + std::to_string(meets_default) + "/" + std::to_string(c.problems.size()) + " | " +
                       std::to_string(meets_siconos) + "/" + std::to_string(c.problems.size())
                 : std::string();
        std::snprintf(buf, sizeof buf, "| %s | %d/%zu%s | %d | %d | %d | %s | %s | %s |\n", s.c_str(), solved,
                      c.problems.size(), by_measure.c_str(), limit, crash, other,
                      fmt("%.3g", geomean(on_common)).c_str(), fmt("%.3g", geomean(penalized)).c_str(), peak.c_str());
        md += buf;
    }
    md += memory_md(c);
    md += best_per_problem_md(c);

    // frix and Siconos side by side: the solvers that share an id are the same algorithm.
    std::string pairs;
    for (const std::string &f : c.solvers) {
        if (f.compare(0, 8, "siconos:") == 0) continue;
        for (const std::string &s : c.solvers) {
            if (s.compare(0, 8, "siconos:") != 0) continue;
            if (c.id_of.at(f) != c.id_of.at(s) || c.id_of.at(f) == 0) continue;
            int nf = 0, ns = 0;
            std::vector<double> tf, ts;
            for (const std::string &p : c.problems) {
                auto a = c.at.find({p, f}), b = c.at.find({p, s});
                bool ok_f = a != c.at.end() && a->second->converged();
                bool ok_s = b != c.at.end() && b->second->converged();
                nf += ok_f;
                ns += ok_s;
                if (ok_f && ok_s) {
                    tf.push_back(a->second->time);
                    ts.push_back(b->second->time);
                }
            }
            double gf = geomean(tf), gs = geomean(ts);
            std::snprintf(buf, sizeof buf, "| %d | %s | %d | %s | %d | %zu | %s | %s | %s |\n",
                          c.id_of.at(f), f.c_str(), nf, s.c_str(), ns, tf.size(),
                          fmt("%.3g", gf).c_str(), fmt("%.3g", gs).c_str(),
                          fmt("%.3gx", gs / gf).c_str());
            pairs += buf;
        }
    }
    if (!pairs.empty()) {
        md += "\nSame algorithm (same id), frix and Siconos; times on the problems both solved:\n\n";
        md += "| id | frix | solved | Siconos | solved | both | frix time | Siconos time | Siconos / frix |\n";
        md += "|---:|---|---:|---|---:|---:|---:|---:|---:|\n";
        md += pairs;
    }

    md += "\nSolved per family (problems in the family):\n\n| solver |";
    std::string rule = "|---|";
    for (const std::string &fam : c.families) {
        int n = 0;
        for (const std::string &p : c.problems) n += c.family_of.at(p) == fam;
        md += " " + fam + " (" + std::to_string(n) + ") |";
        rule += "---:|";
    }
    md += "\n" + rule + "\n";
    for (const std::string &s : c.solvers) {
        md += "| " + s + " |";
        for (const std::string &fam : c.families) {
            int n = 0;
            for (const RunRecord &r : c.runs) n += r.solver == s && r.family == fam && r.converged();
            md += " " + std::to_string(n) + " |";
        }
        md += "\n";
    }

    std::vector<std::string> unsolved, untraced;
    for (const std::string &p : c.problems) {
        bool any = false;
        for (const std::string &s : c.solvers) {
            auto it = c.at.find({p, s});
            any = any || (it != c.at.end() && it->second->converged());
        }
        if (!any) unsolved.push_back(p);
    }
    for (const RunRecord &r : c.runs)
        if (r.note.find("no per-iteration trace") != std::string::npos) push_unique(untraced, r.solver);
    auto join = [](const std::vector<std::string> &v) {
        std::string s;
        for (const std::string &x : v) s += (s.empty() ? "" : ", ") + x;
        return s;
    };
    if (!unsolved.empty()) md += "\nSolved by no solver: " + join(unsolved) + ".\n";
    if (!c.unreadable.empty())
        md += "\nLeft out, as no run could read them: " + join(c.unreadable) + ".\n";
    if (!c.unsupported.empty())
        md += "\nLeft out, as they take none of these problems (e.g. global-only solvers): " +
              join(c.unsupported) + ".\n";
    if (!untraced.empty())
        md += "\nNo per-iteration trace (their work-precision points are the final ones only): " +
              join(untraced) + ".\n";
    return md;
}

void write_text(const std::string &path, const std::string &text) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << text;
    if (!out) fail("bench: cannot write " + path);
}

// Runs the plot script with the first Python that has matplotlib; the script exits with 3
// when matplotlib is missing. Debian's python3-matplotlib lives with /usr/bin/python3,
// which a python3 earlier on PATH (a virtualenv, pyenv) may not see.
std::string draw_plots(const std::string &dir, const std::string &self_dir) {
    const std::string script = self_dir + "/frix-bench-plots";
    if (::access(script.c_str(), R_OK) != 0) return "plots skipped: " + script + " not found";
    for (const char *python : {"python3", "/usr/bin/python3"}) {
        std::fflush(stdout);
        std::fflush(stderr);
        pid_t pid = ::fork();
        if (pid == 0) {
            ::setenv("FRIX_BENCH_PLOTS_QUIET", "1", 1);
            ::execlp(python, python, script.c_str(), dir.c_str(), static_cast<char *>(nullptr));
            ::_exit(127);
        }
        int status = 0;
        if (pid < 0 || ::waitpid(pid, &status, 0) != pid) continue;
        if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return "plots: " + dir + "/plots/";
        if (!(WIFEXITED(status) && (WEXITSTATUS(status) == 3 || WEXITSTATUS(status) == 127)))
            return "plots failed (" + std::string(python) + " " + script + ")";
    }
    return "plots skipped: no python3 with matplotlib (Debian: apt-get install python3-matplotlib)";
}

}  // namespace

std::map<std::string, std::vector<ProfileStep>> performance_profile(
    const std::vector<const RunRecord *> &runs, const std::vector<std::string> &solvers,
    std::size_t problem_count, double time_floor) {
    std::map<std::string, double> best;
    for (const RunRecord *r : runs)
        if (r->converged() && std::isfinite(r->time)) {
            double t = std::max(r->time, time_floor);
            auto it = best.find(r->problem);
            if (it == best.end() || t < it->second) best[r->problem] = t;
        }
    std::map<std::string, std::vector<double>> ratios;
    for (const RunRecord *r : runs)
        if (r->converged() && std::isfinite(r->time))
            ratios[r->solver].push_back(std::max(r->time, time_floor) / best.at(r->problem));
    std::map<std::string, std::vector<ProfileStep>> out;
    const double n = static_cast<double>(std::max<std::size_t>(problem_count, 1));
    for (const std::string &s : solvers) {
        std::vector<double> &v = ratios[s];
        std::sort(v.begin(), v.end());
        std::vector<ProfileStep> steps;
        std::size_t at_one = static_cast<std::size_t>(std::upper_bound(v.begin(), v.end(), 1.0) - v.begin());
        steps.push_back({1.0, static_cast<double>(at_one) / n});
        for (std::size_t k = at_one; k < v.size(); ++k)
            if (k + 1 == v.size() || v[k + 1] != v[k]) steps.push_back({v[k], static_cast<double>(k + 1) / n});
        out[s] = steps;
    }
    return out;
}

std::string bench_report(const std::string &dir, bool plots, const std::string &self_dir) {
    Campaign c = index(read_runs(dir + "/runs.csv"));
    if (c.runs.empty() && !c.unreadable.empty())
        fail("bench: no run could read any problem of " + dir + "/runs.csv, e.g. " + c.unreadable.front());
    if (c.runs.empty()) fail("bench: " + dir + "/runs.csv has no runs");
    if (c.solvers.empty()) fail("bench: no solver in " + dir + "/runs.csv could run any problem");
    TraceMap traces = read_traces(dir + "/traces.csv");
    write_text(dir + "/profile.csv", profile_csv(c));
    write_text(dir + "/work_precision.csv", work_precision_csv(c, traces));
    write_text(dir + "/summary.md", summary_md(c));
    std::string msg = "wrote " + dir + "/{runs,traces,profile,work_precision}.csv and " + dir + "/summary.md";
    if (plots) msg += "\n" + draw_plots(dir, self_dir);
    return msg;
}

}  // namespace frix_cli
