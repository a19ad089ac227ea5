// Command-line parsing for one subcommand: options as "--name VALUE" or "--name=VALUE",
// flags, "--" to end the options, and strict number parsing.
#pragma once

#include <frix/frix_options.h>

#include <cstdint>
#include <string>
#include <vector>

namespace frix_cli {

class ArgCursor {
public:
    // argv[0] is the subcommand's name; parsing starts at argv[1].
    ArgCursor(const char *command, int argc, char **argv);

    bool done() const { return index_ >= argc_; }
    // True when the current argument looks like an option (and "--" has not been seen).
    bool at_option() const;
    // Consumes the current argument if it is the flag `name`.
    bool flag(const char *name);
    // Consumes "--name VALUE" or "--name=VALUE" into `value`. A value may start with '-'
    // (so "--tol -1" reaches the range check). A missing value is a usage error.
    bool option(const char *name, std::string &value);
    // Consumes the current argument as a positional one.
    std::string positional();
    [[noreturn]] void unknown_option() const;

    const char *command() const { return command_; }

private:
    const char *command_;
    int argc_;
    char **argv_;
    int index_ = 1;
    bool options_ended_ = false;
};

// The arguments of a command that takes --help (-h), --json and positional arguments only
// (info, solvers). On --help the rest is not read; an unknown option is a usage error.
struct HelpJsonArgs {
    bool help = false;
    bool json = false;
    std::vector<std::string> positional;
};
HelpJsonArgs parse_help_json_args(const char *command, int argc, char **argv);

// Whole-string conversions; anything else (empty, trailing text, NaN/Inf) is a usage error
// naming the command and option. For a label that names an option of `frix solve` ("--tol",
// "--set NAME"), a number beyond the doubles or 64-bit integers is refused with the option's
// bounds, a double below the doubles' range reads as the nearest one (the library then judges
// its range), and an option whose values are choices takes their names too
// (frix_option_choice_by_name: "--set shuffle=once").
double parse_double(const char *command, const std::string &option, const std::string &text);
std::int64_t parse_int(const char *command, const std::string &option, const std::string &text);

// The named values of an option key (shuffle: none 0, once 1, each_sweep 2), in the order of
// their values; empty for a key whose values have no names.
struct OptionChoice {
    std::string name;
    std::int64_t value;
};
std::vector<OptionChoice> option_choices(frix_option_key key);
// "none, once, each_sweep", "" for a key without choices.
std::string choice_names(frix_option_key key);

// "frix SUB: <what> (see 'frix SUB --help')" as a usage Failure.
[[noreturn]] void usage_error(const char *command, const std::string &what);

}  // namespace frix_cli
