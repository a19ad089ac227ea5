// Help texts. Defaults are read from the library so the help never goes stale.
#include "cli.hpp"

namespace frix_cli {
namespace {

const char kExitText[] =
    "Exit status: 0 success (for solve: converged), 1 the solve ran but did not\n"
    "converge, 2 usage error, unreadable or invalid input, or refused by the library.\n";

// "tolerance 1e-08, max_iter 1000" for the default solver, as far as the library tells.
std::string default_settings() {
    frix_options *o = nullptr;
    if (frix_options_create(FRIX_SOLVER_AUTO, &o) != FRIX_OK) return "";
    std::string s;
    double tol = 0;
    int64_t iters = 0;
    char buf[96];
    if (frix_options_get_double(o, FRIX_OPT_TOLERANCE, &tol) == FRIX_OK &&
        frix_options_get_int(o, FRIX_OPT_MAX_ITER, &iters) == FRIX_OK) {
        std::snprintf(buf, sizeof buf, "tolerance %g, max_iter %lld", tol,
                      static_cast<long long>(iters));
        s = buf;
    }
    frix_options_free(o);
    return s;
}

}  // namespace

void print_main_help(std::FILE *out) {
    std::fputs(
        "frix - discrete 3D frictional contact problems with Coulomb friction\n"
        "\n"
        "Usage:\n"
        "  frix solve FILE.hdf5 [--solver NAME|ID] [--tol T] [--max-iter N]\n"
        "             [--time-limit S] [--threads N] [--output SOL.hdf5] [--json] [--verbose]\n"
        "             [--progress | --quiet]\n"
        "  frix info FILE.hdf5 [--json]\n"
        "  frix solvers [NAME|ID] [--json]\n"
        "  frix convert IN OUT.hdf5 [--title TEXT] [--force]\n"
        "  frix bench FILES|DIRS... [--solvers LIST] [--tol T] [--time-limit S] --out DIR\n"
        "  frix help [COMMAND]     frix COMMAND --help     frix --version\n"
        "\n"
        "Commands:\n"
        "  solve     solve an FCLIB problem from r = 0; report status, iterations, error\n"
        "  info      describe an FCLIB problem: kind, sizes, nnz, friction, title\n"
        "  solvers   list the registered solvers, or describe one\n"
        "  convert   write a problem (FCLIB or Siconos .dat) as a new FCLIB file\n"
        "  bench     run solvers (frix's and Siconos's) on problems: CSV, profiles, plots\n"
        "\n"
        "FILE may be an FCLIB .hdf5 file or a Siconos text problem (.dat).\n"
        "\n",
        out);
    std::fputs(kExitText, out);
}

void print_solve_help(std::FILE *out) {
    std::string defaults = default_settings();
    std::fputs(
        "Usage: frix solve FILE.hdf5 [options]\n"
        "\n"
        "Solves the FCLIB problem (local or global) in FILE starting from r = 0 (or a\n"
        "guess stored in FILE, --guess), and\n"
        "prints the solver, status, iterations, error (the measure compared with the\n"
        "tolerance), time (for a global problem split into the setup, M factorised\n"
        "and q and W = H^T M^-1 H formed, and the solver's), the other error measures\n"
        "and, for auto, its trace (the analysis and every stage it ran). When the\n"
        "solve fails, it also says whether a solution exists at all\n"
        "(frix_problem_check_existence): a failure of the solver, a problem that\n"
        "may have none, or undetermined.\n"
        "\n"
        "Options:\n"
        "  --solver NAME|ID    a name or id from 'frix solvers', or the Siconos spelling\n"
        "                      (FRICTION_3D_NSGS); default auto\n"
        "  --tol T             stop when the error <= T\n"
        "  --max-iter N        iteration limit\n"
        "  --time-limit S      limit in seconds on the whole command: reading the file,\n"
        "                      the solve and the existence check (0 = none)\n"
        "  --threads N         threads for auto, gnsgs, rolling-nsgs and nsgs-v on a large\n"
        "                      dense W (default 1; the answer does not depend on it)\n"
        "  --set NAME=VALUE    any other solver option by name (see 'frix solvers NAME'),\n"
        "                      e.g. memory_limit=2e9 (bytes the solve may add; a\n"
        "                      factorisation that would exceed it is not started);\n"
        "                      an option whose values are choices takes their names\n"
        "                      or numbers: shuffle=once, error_measure=siconos\n"
        "  --guess K           start from the file's guess K (1, 2, ...: FCLIB's /guesses,\n"
        "                      e.g. the warm start a time-stepping code dumped) instead\n"
        "                      of r = 0\n"
        "  --output SOL.hdf5   write the problem and the solution (r, u, and v for a\n"
        "                      global problem) to a new FCLIB file; checked before the\n"
        "                      solve: an existing SOL.hdf5 is replaced atomically, not\n"
        "                      if it is read-only or not a regular file (a symbolic link\n"
        "                      keeps pointing to the new file)\n"
        "  --force             let --output replace FILE itself (refused otherwise)\n"
        "  --json              print one JSON object instead of text\n"
        "  -v, --verbose       the solver prints its progress on stderr (repeat: more)\n"
        "  --progress          a progress line on stderr every second (time, iterations,\n"
        "                      error) once the solve has run 1 s; by default only when\n"
        "                      stderr is a terminal, as one line redrawn in place\n"
        "  -q, --quiet         no progress line\n"
        "  -h, --help          show this help\n",
        out);
    if (!defaults.empty()) std::fprintf(out, "\nDefaults of auto: %s.\n", defaults.c_str());
    std::fputs("\n", out);
    std::fputs(kExitText, out);
}

void print_info_help(std::FILE *out) {
    std::fputs(
        "Usage: frix info FILE.hdf5 [--json]\n"
        "\n"
        "Describes the FCLIB problem in FILE: kind (local or global), the contact law\n"
        "(Coulomb; with rolling friction; with rolling and spinning friction), contacts,\n"
        "sizes, stored entries (W, or M and H), friction coefficients (mu, mu_r, mu_s),\n"
        "title, and whether the file holds a solution and guesses.\n"
        "\n"
        "Options:\n"
        "  --json              print one JSON object instead of text\n"
        "  -h, --help          show this help\n"
        "\n",
        out);
    std::fputs(kExitText, out);
}

void print_solvers_help(std::FILE *out) {
    std::fputs(
        "Usage: frix solvers [NAME|ID] [--json]\n"
        "\n"
        "Without an argument, lists the registered solvers (id, name, summary).\n"
        "With one, prints that solver's description and the options it accepts: type,\n"
        "default and range, or for an option whose values are choices their names\n"
        "(which 'frix solve --set NAME=VALUE' takes) with their numbers.\n"
        "\n"
        "Options:\n"
        "  --json              print JSON instead of text\n"
        "  -h, --help          show this help\n"
        "\n",
        out);
    std::fputs(kExitText, out);
}

void print_convert_help(std::FILE *out) {
    std::fputs(
        "Usage: frix convert IN OUT.hdf5 [--title TEXT]\n"
        "\n"
        "Reads the problem in IN (an FCLIB file, or a Siconos text problem .dat, local or\n"
        "global) and writes it to OUT as an FCLIB file, which Siconos and libfclib read\n"
        "too. A global problem stays global; nothing is solved or reduced. OUT is replaced\n"
        "atomically if it exists, unless it is read-only or not a regular file, or is IN\n"
        "itself (a symbolic link keeps pointing to the new file).\n"
        "\n"
        "Options:\n"
        "  --title TEXT        the title stored in OUT (default: IN's, if any)\n"
        "  --force             let OUT replace IN itself (refused otherwise, even through\n"
        "                      a hard or symbolic link)\n"
        "  -h, --help          show this help\n"
        "\n",
        out);
    std::fputs(kExitText, out);
}

}  // namespace frix_cli
