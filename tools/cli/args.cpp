#include "args.hpp"

#include "cli.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>

namespace frix_cli {

void usage_error(const char *command, const std::string &what) {
    fail(std::string(command) + ": " + what + " (see 'frix " + command + " --help')");
}

ArgCursor::ArgCursor(const char *command, int argc, char **argv)
    : command_(command), argc_(argc), argv_(argv) {}

bool ArgCursor::at_option() const {
    if (done() || options_ended_) return false;
    const char *a = argv_[index_];
    return a[0] == '-' && a[1] != '\0';  // a lone "-" is a positional argument
}

bool ArgCursor::flag(const char *name) {
    if (!at_option()) return false;
    const char *a = argv_[index_];
    if (std::strcmp(a, "--") == 0) {
        options_ended_ = true;
        ++index_;
        return false;
    }
    if (std::strcmp(a, name) != 0) {
        // "--json=1" is a mistake worth naming rather than "unknown option".
        std::size_t n = std::strlen(name);
        if (std::strncmp(a, name, n) == 0 && a[n] == '=')
            usage_error(command_, std::string("option '") + name + "' takes no value");
        return false;
    }
    ++index_;
    return true;
}

bool ArgCursor::option(const char *name, std::string &value) {
    if (!at_option()) return false;
    const char *a = argv_[index_];
    std::size_t n = std::strlen(name);
    if (std::strncmp(a, name, n) != 0) return false;
    if (a[n] == '=') {
        value = a + n + 1;
        ++index_;
        return true;
    }
    if (a[n] != '\0') return false;
    if (index_ + 1 >= argc_)
        usage_error(command_, std::string("option '") + name + "' needs a value");
    value = argv_[index_ + 1];
    index_ += 2;
    return true;
}

std::string ArgCursor::positional() { return argv_[index_++]; }

void ArgCursor::unknown_option() const {
    usage_error(command_, std::string("unknown option '") + argv_[index_] + "'");
}

HelpJsonArgs parse_help_json_args(const char *command, int argc, char **argv) {
    ArgCursor args(command, argc, argv);
    HelpJsonArgs a;
    while (!args.done()) {
        if (args.flag("--help") || args.flag("-h")) {
            a.help = true;
            return a;
        } else if (args.flag("--json")) {
            a.json = true;
        } else if (args.at_option()) {
            args.unknown_option();
        } else if (!args.done()) {
            a.positional.push_back(args.positional());
        }
    }
    return a;
}

namespace {

// The option key a label of `frix solve` names ("--tol", "--max-iter", "--set relaxation"),
// for the messages and choice names below; false for a label that names none.
bool key_of_label(const std::string &option, frix_option_key &key) {
    static const struct {
        const char *label;
        frix_option_key key;
    } kFlags[] = {{"--tol", FRIX_OPT_TOLERANCE},
                  {"--max-iter", FRIX_OPT_MAX_ITER},
                  {"--time-limit", FRIX_OPT_TIME_LIMIT},
                  {"--threads", FRIX_OPT_THREADS}};
    for (const auto &f : kFlags)
        if (option == f.label) {
            key = f.key;
            return true;
        }
    const std::string set = "--set ";
    return option.compare(0, set.size(), set) == 0 &&
           frix_option_by_name(option.c_str() + set.size(), &key) == FRIX_OK;
}

// The bounds of an option key: a key's bounds are the same in every solver that uses it, so
// the first such solver is asked. False if no solver uses it.
bool key_bounds(frix_option_key key, double &lo, double &hi, int &is_int) {
    for (int64_t k = 0; k < frix_solver_count(); ++k) {
        frix_options *o = nullptr;
        if (frix_options_create(frix_solver_id_at(k), &o) != FRIX_OK) continue;
        const bool uses = frix_options_bounds(o, key, &lo, &hi, &is_int) == FRIX_OK;
        frix_options_free(o);
        if (uses) return true;
    }
    return false;
}

// " is outside [LO, HI]" with the bounds of the option a label names, integers in full for
// int keys; "" when the label names no option.
std::string outside_bounds(const std::string &option) {
    frix_option_key key{};
    double lo = 0, hi = 0;
    int is_int = 0;
    if (!key_of_label(option, key) || !key_bounds(key, lo, hi, is_int)) return "";
    char buf[96];
    if (is_int)
        std::snprintf(buf, sizeof buf, " is outside [%.0f, %.0f]", lo, hi);
    else
        std::snprintf(buf, sizeof buf, " is outside [%g, %g]", lo, hi);
    return buf;
}

}  // namespace

std::vector<OptionChoice> option_choices(frix_option_key key) {
    double lo = 0, hi = 0;
    int is_int = 0;
    std::vector<OptionChoice> out;
    // Choices are a few small integers (local_solver's ids span 550..565); wider int ranges
    // are counts, not choices.
    const double kWidestChoiceRange = 1024;
    if (!key_bounds(key, lo, hi, is_int) || !is_int || hi - lo > kWidestChoiceRange) return out;
    for (auto v = static_cast<std::int64_t>(lo); v <= static_cast<std::int64_t>(hi); ++v)
        if (const char *name = frix_option_choice_name(key, v)) out.push_back({name, v});
    return out;
}

std::string choice_names(frix_option_key key) {
    std::string out;
    for (const OptionChoice &c : option_choices(key)) out += (out.empty() ? "" : ", ") + c.name;
    return out;
}

double parse_double(const char *command, const std::string &option, const std::string &text) {
    const char *s = text.c_str();
    char *end = nullptr;
    errno = 0;
    double v = std::strtod(s, &end);
    // A number beyond the doubles (1e400) is out of the option's range, not "not finite"; one
    // below them (1e-310, 1e-400) reads as the nearest double, and the library judges it.
    const bool overflow = errno == ERANGE && std::isinf(v);
    if (text.empty() || end == s || *end != '\0' || (!std::isfinite(v) && !overflow))
        usage_error(command, option + " expects a finite number, got '" + text + "'");
    if (overflow) {
        const std::string bounds = outside_bounds(option);
        usage_error(command, option + " " + text +
                                 (bounds.empty() ? " is beyond the largest double" : bounds));
    }
    return v;
}

std::int64_t parse_int(const char *command, const std::string &option, const std::string &text) {
    const char *s = text.c_str();
    char *end = nullptr;
    errno = 0;
    long long v = std::strtoll(s, &end, 10);
    if (!text.empty() && end != s && *end == '\0' && errno != ERANGE) return static_cast<std::int64_t>(v);
    // An option whose values are choices takes their names too ("--set shuffle=once").
    frix_option_key key{};
    int64_t named = 0;
    const bool keyed = key_of_label(option, key);
    if (keyed && frix_option_choice_by_name(key, s, &named) == FRIX_OK) return named;
    if (!text.empty() && end != s && *end == '\0') {  // an integer beyond 64 bits
        const std::string bounds = outside_bounds(option);
        usage_error(command, option + " " + text +
                                 (bounds.empty() ? " is beyond the 64-bit integers" : bounds));
    }
    const std::string names = keyed ? choice_names(key) : "";
    if (!names.empty())
        usage_error(command, option + " expects an integer or one of " + names + ", got '" + text + "'");
    usage_error(command, option + " expects an integer, got '" + text + "'");
}

}  // namespace frix_cli
