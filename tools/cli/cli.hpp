// The `frix` command line: declarations shared by the subcommands.
// The CLI is a client of the public C API only (no header from src/).
#pragma once

#include <frix/frix.h>

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace frix_cli {

// Exit codes, documented in `frix --help`.
enum ExitCode {
    kExitConverged = 0,     // the command succeeded (for solve: status CONVERGED)
    kExitNotConverged = 1,  // the solve ran but stopped without converging
    kExitUsage = 2          // usage error, unreadable/invalid input, or the library refused
};

// Ends the current command: main() prints "frix: <message>" as one line on stderr and
// returns `code`. Thrown rather than exit()ed so that every handle is released.
struct Failure {
    int code;
    std::string message;
};
[[noreturn]] void fail(const std::string &message, int code = kExitUsage);

// The library's message for a failed call (falls back to the code's description); for
// FRIX_ERR_OUT_OF_MEMORY followed by out_of_memory_advice().
std::string library_message(frix_error err);
// What ran out and what to do: the process's limit ('ulimit -v', or the machine's memory)
// and what it holds, then the remedies (a larger limit, a smaller problem, memory_limit).
std::string out_of_memory_advice();
// Why a solve ended with FRIX_STATUS_MEMORY_LIMIT: the limit in force (option memory_limit,
// or what the process may use), what the reported iterate is, and what to do.
std::string memory_limit_note(const frix_options *options, int64_t iterations);
// "12.3 MB": bytes in decimal units, for messages.
std::string bytes_text(double bytes);

struct ProblemDeleter {
    // What a problem built from arrays borrows (frix_problem_local/global), freed after it.
    std::shared_ptr<void> borrowed;
    void operator()(frix_problem *p) const { frix_problem_free(p); }
};
struct OptionsDeleter {
    void operator()(frix_options *o) const { frix_options_free(o); }
};
struct InfoDeleter {
    void operator()(frix_info *i) const { frix_info_free(i); }
};
using ProblemPtr = std::unique_ptr<frix_problem, ProblemDeleter>;
using OptionsPtr = std::unique_ptr<frix_options, OptionsDeleter>;
using InfoPtr = std::unique_ptr<frix_info, InfoDeleter>;

// frix_read_problem (FCLIB or Siconos .dat), or fail with "cannot read PATH: <reason>".
ProblemPtr read_problem(const std::string &path);
// The same within `seconds_left` of a command's `time_limit`: read in a child process that
// sends the problem back and is killed when time runs out (a slow or huge file cannot hold
// the command past its limit); then fail with "reading PATH took longer than the time limit
// of T s" and kExitNotConverged, as a solve stopped by its time limit ends.
ProblemPtr read_problem(const std::string &path, double time_limit, double seconds_left);

// --guess K: K as a guess number (1, 2, ...), or a usage error of `command`.
int64_t parse_guess_number(const char *command, const std::string &text);
// r, u (and v: NULL for a local problem) from guess k (1-based, as FCLIB numbers them) of the
// FCLIB file `file`, which holds `problem`; fails saying how many guesses it holds.
void start_from_guess(const std::string &file, const frix_problem *problem, int64_t k, double *r, double *u,
                      double *v);

// Fails ("cannot write OUTPUT: ...") unless frix_fclib_write can replace `output` without
// losing data: its directory exists and is writable, and an existing file there (behind a
// symbolic link: the file linked to) is a regular, writable file and not `input` (the file
// the command reads; same device and inode, so hard and symbolic links count too) unless
// `force`. Called before any long work, so a solve never ends in a predictable write error.
void check_output(const std::string &output, const std::string &input, bool force);

// The non-empty pieces of text between the separators.
std::vector<std::string> split(const std::string &text, char sep);

const char *kind_name(frix_problem_kind kind);
// A stable lower-case token for JSON and scripts ("converged", "max_iter", ...).
const char *status_token(frix_status status);

// Subcommands: argv[0] is the subcommand name, as main() received it.
int cmd_solve(int argc, char **argv);
int cmd_info(int argc, char **argv);
int cmd_solvers(int argc, char **argv);
int cmd_convert(int argc, char **argv);
int cmd_bench(int argc, char **argv);
int cmd_bench_run(int argc, char **argv);  // hidden: one child run of `frix bench`

void print_main_help(std::FILE *out);
void print_solve_help(std::FILE *out);
void print_info_help(std::FILE *out);
void print_solvers_help(std::FILE *out);
void print_convert_help(std::FILE *out);
void print_bench_help(std::FILE *out);

}  // namespace frix_cli
