// `frix bench --help` (kept beside the bench rather than in help.cpp: it is long and only
// the bench's).
#include "cli.hpp"

namespace frix_cli {

void print_bench_help(std::FILE *out) {
    std::fputs(
        "Usage: frix bench FILES|DIRS... --out DIR [options]\n"
        "       frix bench --report DIR [--no-plots]\n"
        "\n"
        "Runs every solver on every problem (a directory gives its *.hdf5 files), each run\n"
        "in a child process of its own with a wall-clock limit, so that a crash or a hang\n"
        "costs one run and not the campaign. Every run starts from r = 0. Writes:\n"
        "  DIR/runs.csv          one row per run: problem, family, contacts, dofs, solver,\n"
        "                        status, iterations, error, time, solver_id, tolerance,\n"
        "                        time_limit, max_iter, reported_error, note,\n"
        "                        peak_memory_mb (the run's process, problem read included)\n"
        "  DIR/traces.csv        error against elapsed time per run (thinned: every tenth\n"
        "                        of a decade gained, and geometric steps in time)\n"
        "  DIR/profile.csv       performance profiles rho_s(tau), overall and per family\n"
        "  DIR/work_precision.csv  time to reach 1e-2 ... 1e-10, per solver\n"
        "  DIR/summary.md        tables: solved counts, geometric-mean times, peak memory,\n"
        "                        auto against the best other frix and Siconos solver per\n"
        "                        problem, frix and Siconos side by side, solved per family\n"
        "  DIR/plots/            PNG and SVG of the profiles and work-precision curves\n"
        "                        (needs python3 with matplotlib; skipped with a note if not)\n"
        "  DIR/logs/             what the runs that did not converge printed\n"
        "\n"
        "Options:\n"
        "  --solvers LIST      comma-separated: frix solver names or ids, 'all' (every\n"
        "                      solver registered), 'siconos:NAME' (a Siconos 4.4 solver:\n"
        "                      NSGS, NSN_AC, NSN_FB, NSN_NM, PROX, VI_FPP, VI_EG, TFP, ADMM,\n"
        "                      ...; for global problems GFC3D_NSN_AC, GFC3D_NSGS_WR,\n"
        "                      GFC3D_ADMM, GFC3D_IPM, ...), 'siconos:all' (the nine local\n"
        "                      ones); default all. On a global problem the error is the\n"
        "                      larger of the relative error and the equilibrium residual\n"
        "  --tol T             tolerance of every run (default 1e-8)\n"
        "  --time-limit S      seconds per run (default 10); frix's solvers stop at it,\n"
        "                      any run still going at S + grace is killed ('timeout')\n"
        "  --grace S           default 1 + 0.2 x the time limit\n"
        "  --max-iter N        iteration limit of every run (default 100000)\n"
        "  --jobs N            runs at a time (default 1: timings undisturbed)\n"
        "  --out DIR           where the files go (created if needed)\n"
        "  --report DIR        only redo the tables and plots from DIR/runs.csv and\n"
        "                      DIR/traces.csv\n"
        "  --no-plots          do not run the plot script\n"
        "  -q, --quiet         no progress line\n"
        "  -h, --help          show this help\n"
        "\n"
        "Status of a run: converged, max_iter, time_limit, memory_limit, stagnated,\n"
        "diverged, numerical_failure (frix); inaccurate (Siconos says converged, frix's\n"
        "measure does not), failed (Siconos); timeout (killed), crash(SIGNAL), error,\n"
        "unsupported.\n"
        "The error is frix's relative measure for every solver: Siconos's r is measured by\n"
        "frix. Siconos's solvers run through frix-siconos, built beside frix when Debian's\n"
        "libsiconos-numerics-dev is installed; without it they are skipped with a note.\n"
        "\n"
        "Exit status: 0 the campaign ran (whatever the runs' results), 2 usage error,\n"
        "130 interrupted.\n",
        out);
}

}  // namespace frix_cli
