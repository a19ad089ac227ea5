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

double parse_double(const char *command, const std::string &option, const std::string &text) {
    const char *s = text.c_str();
    char *end = nullptr;
    errno = 0;
    double v = std::strtod(s, &end);
    if (text.empty() || end == s || *end != '\0' || errno == ERANGE || !std::isfinite(v))
        usage_error(command, option + " expects a finite number, got '" + text + "'");
    return v;
}

std::int64_t parse_int(const char *command, const std::string &option, const std::string &text) {
    const char *s = text.c_str();
    char *end = nullptr;
    errno = 0;
    long long v = std::strtoll(s, &end, 10);
    if (text.empty() || end == s || *end != '\0' || errno == ERANGE)
        usage_error(command, option + " expects an integer, got '" + text + "'");
    return static_cast<std::int64_t>(v);
}

}  // namespace frix_cli
