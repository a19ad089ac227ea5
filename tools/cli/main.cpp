// `frix`: solve, inspect and list solvers for FCLIB frictional contact problems.
#include "cli.hpp"

#include <cstring>
#include <exception>
#include <new>
#include <string>

namespace frix_cli {
namespace {

int print_version() {
    // The header's version is the one the CLI was built with; the library's is the one
    // actually loaded (they differ only when libfrix.so was swapped underneath).
    std::printf("frix %s (library %s)\n", FRIX_VERSION_STRING, frix_version_string());
    return kExitConverged;
}

int help_for(const char *topic) {
    if (!topic) {
        print_main_help(stdout);
    } else if (std::strcmp(topic, "solve") == 0) {
        print_solve_help(stdout);
    } else if (std::strcmp(topic, "info") == 0) {
        print_info_help(stdout);
    } else if (std::strcmp(topic, "solvers") == 0) {
        print_solvers_help(stdout);
    } else if (std::strcmp(topic, "convert") == 0) {
        print_convert_help(stdout);
    } else if (std::strcmp(topic, "bench") == 0) {
        print_bench_help(stdout);
    } else {
        fail(std::string("no help for '") + topic + "' (commands: solve, info, solvers, convert, bench)");
    }
    return kExitConverged;
}

int run(int argc, char **argv) {
    if (argc < 2) fail("missing command (see 'frix --help')");
    const char *cmd = argv[1];
    if (std::strcmp(cmd, "--help") == 0 || std::strcmp(cmd, "-h") == 0) return help_for(nullptr);
    if (std::strcmp(cmd, "--version") == 0 || std::strcmp(cmd, "-V") == 0) {
        if (argc > 2) fail("--version takes no arguments");
        return print_version();
    }
    if (std::strcmp(cmd, "help") == 0) {
        if (argc > 3) fail("help takes at most one command name");
        return help_for(argc == 3 ? argv[2] : nullptr);
    }
    if (std::strcmp(cmd, "solve") == 0) return cmd_solve(argc - 1, argv + 1);
    if (std::strcmp(cmd, "info") == 0) return cmd_info(argc - 1, argv + 1);
    if (std::strcmp(cmd, "solvers") == 0) return cmd_solvers(argc - 1, argv + 1);
    if (std::strcmp(cmd, "convert") == 0) return cmd_convert(argc - 1, argv + 1);
    if (std::strcmp(cmd, "bench") == 0) return cmd_bench(argc - 1, argv + 1);
    // Hidden: one run of a bench campaign, in the child process the bench starts.
    if (std::strcmp(cmd, "bench-run") == 0) return cmd_bench_run(argc - 1, argv + 1);
    if (cmd[0] == '-') fail(std::string("unknown option '") + cmd + "' (see 'frix --help')");
    fail(std::string("unknown command '") + cmd + "' (see 'frix --help')");
}

}  // namespace
}  // namespace frix_cli

int main(int argc, char **argv) {
    using namespace frix_cli;
    try {
        return run(argc, argv);
    } catch (const Failure &f) {
        std::fflush(stdout);
        std::fprintf(stderr, "frix: %s\n", f.message.c_str());
        return f.code;
    } catch (const std::bad_alloc &) {
        std::fflush(stdout);
        // Unwound, the failed allocation's memory is free again: the advice can be built
        // (and is left out if it cannot).
        std::string advice;
        try {
            advice = " (" + out_of_memory_advice() + ")";
        } catch (...) {
            advice.clear();
        }
        std::fprintf(stderr, "frix: %s%sout of memory%s\n", argc > 1 ? argv[1] : "", argc > 1 ? ": " : "",
                     advice.c_str());
        return kExitUsage;
    } catch (const std::exception &e) {
        std::fflush(stdout);
        std::fprintf(stderr, "frix: internal error: %s\n", e.what());
        return kExitUsage;
    }
}
