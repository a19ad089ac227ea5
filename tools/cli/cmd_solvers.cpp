// `frix solvers [NAME|ID] [--json]`: the registry, or one solver in detail.
#include "args.hpp"
#include "cli.hpp"
#include "json.hpp"

#include <cmath>
#include <vector>

namespace frix_cli {
namespace {

// Option keys are small pinned integers that are only ever added; scanning this range
// finds every key a solver accepts without a list to keep in sync here.
constexpr int kLastOptionKeyScanned = 127;

struct OptionRow {
    frix_option_key key;
    const char *name;
    bool is_int;
    double value, lower, upper;
};

// "once" for shuffle's value 1: the name of an option's value, "" where it has none.
std::string value_name(const OptionRow &r, double v) {
    const char *n = r.is_int && std::isfinite(v) ? frix_option_choice_name(r.key, static_cast<int64_t>(v)) : nullptr;
    return n ? n : "";
}

// The first line of a description, cut after its first sentence when that line is long.
std::string summary(const char *text) {
    if (!text) return "";
    std::string s(text);
    s = s.substr(0, s.find('\n'));
    const std::size_t kLong = 90;
    if (s.size() > kLong) {
        std::size_t dot = s.find(". ");
        if (dot != std::string::npos) s = s.substr(0, dot + 1);
    }
    return s;
}

// Cut at a word boundary to at most `width` characters, marking the cut with "...".
std::string fit(const std::string &s, std::size_t width) {
    if (s.size() <= width) return s;
    std::size_t cut = s.rfind(' ', width - 3);
    if (cut == std::string::npos || cut == 0) cut = width - 3;
    std::string out = s.substr(0, cut);
    while (!out.empty() && (out.back() == ',' || out.back() == ' ' || out.back() == ':'))
        out.pop_back();
    return out + "...";
}

std::vector<OptionRow> accepted_options(int id) {
    std::vector<OptionRow> rows;
    frix_options *o = nullptr;
    if (frix_options_create(id, &o) != FRIX_OK) return rows;
    for (int k = 1; k <= kLastOptionKeyScanned; ++k) {
        auto key = static_cast<frix_option_key>(k);
        OptionRow row{key, frix_option_name(key), false, 0, 0, 0};
        int is_int = 0;
        if (!row.name || frix_options_bounds(o, key, &row.lower, &row.upper, &is_int) != FRIX_OK)
            continue;
        row.is_int = is_int != 0;
        if (frix_options_get_double(o, key, &row.value) != FRIX_OK) row.value = NAN;
        rows.push_back(row);
    }
    frix_options_free(o);
    return rows;
}

int list_all(bool json) {
    int64_t n = frix_solver_count();
    if (json) {
        JsonWriter w;
        w.begin_object();
        w.begin_array("solvers");
        for (int64_t i = 0; i < n; ++i) {
            int id = frix_solver_id_at(i);
            const char *name = frix_solver_name(id);
            const char *desc = frix_solver_describe(id);
            w.begin_object();
            w.integer("id", id);
            w.string("name", name ? name : "");
            w.string("summary", summary(desc));
            w.end_object();
        }
        w.end_array();
        w.end_object();
        std::printf("%s\n", w.text().c_str());
        return kExitConverged;
    }
    std::printf("%5s  %-12s %s\n", "id", "name", "description");
    for (int64_t i = 0; i < n; ++i) {
        int id = frix_solver_id_at(i);
        const char *name = frix_solver_name(id);
        std::printf("%5d  %-12s %s\n", id, name ? name : "?",
                    fit(summary(frix_solver_describe(id)), 60).c_str());
    }
    return kExitConverged;
}

std::string format_value(double v, bool is_int) {
    char buf[48];
    if (!std::isfinite(v)) return v > 0 ? "inf" : v < 0 ? "-inf" : "-";
    if (is_int)
        std::snprintf(buf, sizeof buf, "%.0f", v);
    else
        std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}

int describe_one(const std::string &which, bool json) {
    int id = 0;
    frix_error err = frix_solver_by_name(which.c_str(), &id);
    if (err != FRIX_OK) fail("unknown solver '" + which + "' (see 'frix solvers')");
    const char *name = frix_solver_name(id);
    const char *desc = frix_solver_describe(id);
    std::vector<OptionRow> rows = accepted_options(id);
    if (json) {
        JsonWriter w;
        w.begin_object();
        w.integer("id", id);
        w.string("name", name ? name : "");
        w.string("description", desc ? desc : "");
        w.begin_array("options");
        for (const OptionRow &r : rows) {
            w.begin_object();
            w.string("name", r.name);
            w.string("type", r.is_int ? "int" : "double");
            w.number("default", r.value);
            w.number("min", r.lower);
            w.number("max", r.upper);
            const std::vector<OptionChoice> choices = option_choices(r.key);
            if (!choices.empty()) {
                w.string("default_name", value_name(r, r.value));
                w.begin_array("choices");
                for (const OptionChoice &c : choices) {
                    w.begin_object();
                    w.string("name", c.name);
                    w.integer("value", c.value);
                    w.end_object();
                }
                w.end_array();
            }
            w.end_object();
        }
        w.end_array();
        w.end_object();
        std::printf("%s\n", w.text().c_str());
        return kExitConverged;
    }
    std::printf("%s (id %d)\n\n%s\n", name ? name : "?", id, desc ? desc : "");
    if (!rows.empty()) {
        std::printf("\nOptions (frix solve --set NAME=VALUE):\n");
        std::printf("  %-16s %-7s %-12s %s\n", "name", "type", "default", "range");
        for (const OptionRow &r : rows) {
            // An option whose values are choices shows its default by name and, for its
            // range, its names (which --set takes as well as the numbers) with their values.
            std::string names;
            for (const OptionChoice &c : option_choices(r.key))
                names += (names.empty() ? "" : ", ") + c.name + " (" + std::to_string(c.value) + ")";
            const std::string dflt = value_name(r, r.value);
            if (!names.empty())
                std::printf("  %-16s %-7s %-12s %s\n", r.name, "int",
                            (dflt.empty() ? format_value(r.value, r.is_int) : dflt).c_str(),
                            names.c_str());
            else
                std::printf("  %-16s %-7s %-12s [%s, %s]\n", r.name, r.is_int ? "int" : "double",
                            format_value(r.value, r.is_int).c_str(),
                            format_value(r.lower, r.is_int).c_str(),
                            format_value(r.upper, r.is_int).c_str());
        }
    }
    return kExitConverged;
}

}  // namespace

int cmd_solvers(int argc, char **argv) {
    const HelpJsonArgs args = parse_help_json_args("solvers", argc, argv);
    if (args.help) {
        print_solvers_help(stdout);
        return kExitConverged;
    }
    if (args.positional.size() > 1) usage_error("solvers", "expected at most one solver name");
    return args.positional.empty() ? list_all(args.json) : describe_one(args.positional[0], args.json);
}

}  // namespace frix_cli
