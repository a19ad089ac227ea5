// Options by key: the key table (type, bounds, default), per-solver key sets and defaults.
#include "options.hpp"

#include <cctype>
#include <cerrno>
#include <cfloat>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "error_state.hpp"
#include "solver_api.hpp"

namespace {

using frix::fail;

// One named value of an option whose values are choices.
struct Choice {
    int64_t value;
    const char *name;
};

struct KeySpec {
    frix_option_key key;
    const char *name;
    bool is_int;
    double lower, upper;  // inclusive
    double default_value;
    const int64_t *allowed = nullptr;  // for keys naming a choice: the values, 0-terminated
    // The names of its values, ended by a null name; the first of a value is its name, any
    // later one an alias accepted when read.
    const Choice *choices = nullptr;
    bool choices_are_solvers = false;  // the allowed values are solver ids, named by the registry
};

// The names of the enums of frix_options.h, as the API spells the enumerators.
const Choice kShuffleNames[] = {{FRIX_SHUFFLE_NONE, "none"},
                                {FRIX_SHUFFLE_ONCE, "once"},
                                {FRIX_SHUFFLE_EACH_SWEEP, "each_sweep"},
                                {0, nullptr}};
const Choice kRhoStrategyNames[] = {{FRIX_RHO_CONSTANT, "constant"},
                                    {FRIX_RHO_SPECTRAL, "spectral"},
                                    {FRIX_RHO_SPLIT, "split"},
                                    {0, nullptr}};
const Choice kLineSearchNames[] = {{FRIX_LINE_SEARCH_NONE, "none"},
                                   {FRIX_LINE_SEARCH_GOLDSTEIN_PRICE, "goldstein_price"},
                                   {FRIX_LINE_SEARCH_ARMIJO, "armijo"},
                                   {FRIX_LINE_SEARCH_NONMONOTONE, "nonmonotone"},
                                   {0, nullptr}};
const Choice kHybridNames[] = {{FRIX_HYBRID_NONE, "none"}, {FRIX_HYBRID_NSGS, "nsgs"}, {0, nullptr}};
// "relative" is the enumerator's own name (FRIX_MEASURE_RELATIVE) of Siconos's measure.
const Choice kErrorMeasureNames[] = {{FRIX_MEASURE_RELATIVE, "siconos"},
                                     {FRIX_MEASURE_Q_RELATIVE, "q_relative"},
                                     {FRIX_MEASURE_SCALED, "scaled"},
                                     {FRIX_MEASURE_RELATIVE, "relative"},
                                     {0, nullptr}};
const Choice kLocalSolverNames[] = {{FRIX_LOCAL_NEWTON_AC, "newton_ac"},
                                    {FRIX_LOCAL_NEWTON_AC_GP, "newton_ac_gp"},
                                    {FRIX_LOCAL_PROJECTION, "projection"},
                                    {FRIX_LOCAL_PROJECTION_ITERATED, "projection_iterated"},
                                    {FRIX_LOCAL_NEWTON_FB, "newton_fb"},
                                    {FRIX_LOCAL_CLOSED_FORM, "closed_form"},
                                    {FRIX_LOCAL_HYBRID, "hybrid"},
                                    {0, nullptr}};

// The one-contact solvers (frix_local_solver).
const int64_t kLocalSolvers[] = {FRIX_LOCAL_PROJECTION, FRIX_LOCAL_PROJECTION_ITERATED,
                                 FRIX_LOCAL_CLOSED_FORM, FRIX_LOCAL_NEWTON_AC,
                                 FRIX_LOCAL_NEWTON_AC_GP, FRIX_LOCAL_NEWTON_FB,
                                 FRIX_LOCAL_HYBRID, 0};

// The Newton solvers PROX may run inside.
const int64_t kInnerSolvers[] = {FRIX_SOLVER_NSN_AC, FRIX_SOLVER_NSN_FB, FRIX_SOLVER_NSN_NM, 0};

// Common defaults: the tolerance our users ask for (FCLIB comparisons use 1e-8), and
// limits that a solver's entry may override.
const KeySpec kKeys[] = {
    {FRIX_OPT_TOLERANCE, "tolerance", false, 0.0, 1.0, 1e-8},
    {FRIX_OPT_MAX_ITER, "max_iter", true, 1.0, 1e9, 1000.0},
    {FRIX_OPT_TIME_LIMIT, "time_limit", false, 0.0, 1e9, 0.0},
    {FRIX_OPT_VERBOSITY, "verbosity", true, 0.0, 3.0, 0.0},
    {FRIX_OPT_ERROR_MEASURE, "error_measure", true, 0.0, 2.0, 2.0, nullptr, kErrorMeasureNames},
    {FRIX_OPT_LOCAL_SOLVER, "local_solver", true, 550.0, 565.0, 562.0, kLocalSolvers, kLocalSolverNames},
    {FRIX_OPT_LOCAL_TOLERANCE, "local_tolerance", false, 0.0, 1.0, 1e-12},
    {FRIX_OPT_LOCAL_MAX_ITER, "local_max_iter", true, 1.0, 1e6, 20.0},
    {FRIX_OPT_RELAXATION, "relaxation", false, 1e-3, 1.999, 1.0},
    {FRIX_OPT_SHUFFLE, "shuffle", true, 0.0, 2.0, 0.0, nullptr, kShuffleNames},
    {FRIX_OPT_SEED, "seed", true, 0.0, 9007199254740992.0 /* 2^53 */, 0.0},
    {FRIX_OPT_RHO_STRATEGY, "rho_strategy", true, 0.0, 2.0, 1.0, nullptr, kRhoStrategyNames},
    {FRIX_OPT_RHO, "rho", false, 1e-300, 1e300, 1.0},
    {FRIX_OPT_LINE_SEARCH, "line_search", true, 0.0, 3.0, 1.0, nullptr, kLineSearchNames},
    {FRIX_OPT_LINE_SEARCH_MAX_ITER, "line_search_max_iter", true, 1.0, 1000.0, 20.0},
    {FRIX_OPT_HYBRID, "hybrid", true, 0.0, 1.0, 1.0, nullptr, kHybridNames},
    {FRIX_OPT_HYBRID_SWEEPS, "hybrid_sweeps", true, 1.0, 1e6, 50.0},
    {FRIX_OPT_PROX_ALPHA, "prox_alpha", false, 0.0, 1e300, 0.0},
    {FRIX_OPT_PROX_SIGMA, "prox_sigma", false, 1e-300, 1e300, 5.0},
    {FRIX_OPT_PROX_NU, "prox_nu", false, 1e-3, 10.0, 1.0},
    {FRIX_OPT_INNER_SOLVER, "inner_solver", true, FRIX_SOLVER_NSN_AC, FRIX_SOLVER_NSN_NM, FRIX_SOLVER_NSN_AC, kInnerSolvers, nullptr, true},
    {FRIX_OPT_FREEZING, "freezing", true, 0.0, 1e6, 0.0},
    {FRIX_OPT_ERROR_FREQUENCY, "error_frequency", true, 1.0, 1e6, 1.0},
    {FRIX_OPT_RHO_ADAPTIVE, "rho_adaptive", true, 0.0, 1.0, 1.0},
    {FRIX_OPT_INNER_MAX_ITER, "inner_max_iter", true, 1.0, 1e9, 1000.0},
    {FRIX_OPT_INNER_TOLERANCE_RATIO, "inner_tolerance_ratio", false, 1e-6, 1.0, 0.1},
    {FRIX_OPT_ACCELERATION, "acceleration", true, 0.0, 1.0, 1.0},
    {FRIX_OPT_THREADS, "threads", true, 1.0, 256.0, 1.0},
    {FRIX_OPT_EXISTENCE_CHECK, "existence_check", true, 0.0, 1.0, 1.0},
    {FRIX_OPT_DRIFT_WINDOW, "drift_window", true, 0.0, 1e9, 0.0},
    {FRIX_OPT_WATCHDOG, "watchdog", true, 0.0, 1000.0, 0.0},
    {FRIX_OPT_MEMORY_LIMIT, "memory_limit", false, 0.0, 1e18, 0.0},
    {FRIX_OPT_ANDERSON, "anderson", true, 0.0, 50.0, 0.0},
    {FRIX_OPT_CALLBACK_ESTIMATES, "callback_estimates", true, 0.0, 1.0, 1.0},
    {FRIX_OPT_SECANT_START, "secant_start", true, 0.0, 1.0, 1.0},
};

const frix_option_key kCommonKeys[] = {FRIX_OPT_TOLERANCE,     FRIX_OPT_MAX_ITER,     FRIX_OPT_TIME_LIMIT,
                                       FRIX_OPT_VERBOSITY,     FRIX_OPT_ERROR_MEASURE, FRIX_OPT_MEMORY_LIMIT,
                                       FRIX_OPT_EXISTENCE_CHECK, FRIX_OPT_CALLBACK_ESTIMATES, FRIX_OPT_SECANT_START};

const KeySpec *spec_of(int key) {
    for (const KeySpec &s : kKeys)
        if (s.key == key) return &s;
    return nullptr;
}

bool solver_uses(const frix::SolverEntry &e, int key) {
    for (frix_option_key k : kCommonKeys)
        if (k == key) return true;
    for (const frix_option_key *k = e.extra_keys; k && *k; ++k)
        if (*k == key) return true;
    return false;
}

// The spec of `key` if the options' solver uses it; otherwise a recorded error.
frix_error lookup(const char *where, const frix_options *opts, int key, const KeySpec **spec) {
    if (!opts) return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: options is NULL", where);
    const KeySpec *s = spec_of(key);
    if (!s) return fail(FRIX_ERR_UNKNOWN_OPTION, "%s: unknown option key %d", where, key);
    const frix::SolverEntry *e = frix::find_solver(opts->solver_id);
    if (!e || !solver_uses(*e, key))
        return fail(FRIX_ERR_UNKNOWN_OPTION, "%s: solver %s does not use option '%s'", where,
                    e ? e->name : "?", s->name);
    *spec = s;
    return FRIX_OK;
}

// Sets key s.key to value in o, in the slot of its type (no checks).
void assign(frix_options &o, const KeySpec &s, double value) {
    if (s.is_int)
        o.ivalue[s.key] = (int64_t)value;
    else
        o.dvalue[s.key] = value;
}

// The shortest text that reads back as v ("1e-310", not "9.9999999999999694e-311").
std::string number_text(double v) {
    char buf[40];
    for (int digits = 1; digits <= 17; ++digits) {
        std::snprintf(buf, sizeof buf, "%.*g", digits, v);
        if (std::strtod(buf, nullptr) == v) break;
    }
    return buf;
}

// A value or bound of key s as the user reads it: integers in full for int keys.
std::string value_text(const KeySpec &s, double v) {
    char buf[40];
    if (s.is_int && v == std::floor(v) && std::fabs(v) < 9.2e18) {
        std::snprintf(buf, sizeof buf, "%lld", (long long)v);
        return buf;
    }
    return number_text(v);
}

// The name of value v of key s, or nullptr.
const char *choice_name(const KeySpec &s, int64_t v) {
    for (const Choice *c = s.choices; c && c->name; ++c)
        if (c->value == v) return c->name;
    if (s.choices_are_solvers)
        for (const int64_t *a = s.allowed; *a; ++a)
            if (*a == v) {
                const frix::SolverEntry *e = frix::find_solver((int)v);
                return e ? e->name : nullptr;
            }
    return nullptr;
}

// " (none = 0, once = 1, each_sweep = 2)" for a key with named values, else "": refusals
// list what would be accepted.
std::string choices_text(const KeySpec &s) {
    std::string out;
    auto add = [&](int64_t v) {
        const char *n = choice_name(s, v);
        if (!n) return;
        out += out.empty() ? " (" : ", ";
        out += std::string(n) + " = " + std::to_string((long long)v);
    };
    if (s.allowed)
        for (const int64_t *a = s.allowed; *a; ++a) add(*a);
    else if (s.choices)
        for (int64_t v = (int64_t)s.lower; v <= (int64_t)s.upper; ++v) add(v);
    return out.empty() ? out : out + ")";
}

// Names compare without case, '-' as '_': "each-sweep" and "EACH_SWEEP" are each_sweep.
bool same_name(const char *a, const char *b) {
    for (;; ++a, ++b) {
        char x = (char)std::tolower((unsigned char)*a), y = (char)std::tolower((unsigned char)*b);
        if (x == '-') x = '_';
        if (y == '-') y = '_';
        if (x != y) return false;
        if (!x) return true;
    }
}

// The value of key s named `name`: true and *value, or false.
bool choice_value(const KeySpec &s, const char *name, int64_t *value) {
    for (const Choice *c = s.choices; c && c->name; ++c)
        if (same_name(c->name, name)) {
            *value = c->value;
            return true;
        }
    if (s.choices_are_solvers)
        for (const int64_t *a = s.allowed; *a; ++a) {
            const frix::SolverEntry *e = frix::find_solver((int)*a);
            if (e && (same_name(e->name, name) || (e->siconos_name && same_name(e->siconos_name, name)))) {
                *value = *a;
                return true;
            }
        }
    return false;
}

frix_error out_of_range(const char *where, const KeySpec &s, const std::string &given) {
    return fail(FRIX_ERR_OPTION_RANGE, "%s: %s = %s is outside [%s, %s]%s", where, s.name,
                given.c_str(), value_text(s, s.lower).c_str(), value_text(s, s.upper).c_str(),
                choices_text(s).c_str());
}

// An int key's value: checked as an integer, so that no value beyond 2^53 rounds into range.
frix_error store_int(const char *where, frix_options *opts, const KeySpec &s, int64_t value) {
    if (!s.is_int) {
        const double d = (double)value;
        if (!(d >= s.lower && d <= s.upper)) return out_of_range(where, s, std::to_string((long long)value));
        assign(*opts, s, d);
        return FRIX_OK;
    }
    if (value < (int64_t)s.lower || value > (int64_t)s.upper)
        return out_of_range(where, s, std::to_string((long long)value));
    if (s.allowed) {
        const int64_t *a = s.allowed;
        while (*a && *a != value) ++a;
        if (!*a)
            return fail(FRIX_ERR_OPTION_RANGE, "%s: %s = %lld is not one of the defined values%s",
                        where, s.name, (long long)value, choices_text(s).c_str());
    }
    opts->ivalue[s.key] = value;
    return FRIX_OK;
}

// given: the value as the caller wrote it, for messages (nullptr: v's own text).
frix_error store(const char *where, frix_options *opts, const KeySpec &s, double value,
                 const char *given = nullptr) {
    const std::string text = given ? std::string(given) : number_text(value);
    if (std::isnan(value))
        return fail(FRIX_ERR_OPTION_RANGE, "%s: %s = %s is not a number", where, s.name, text.c_str());
    if (value < s.lower || value > s.upper) return out_of_range(where, s, text);
    if (s.is_int) {
        if (value != std::floor(value))
            return fail(FRIX_ERR_OPTION_RANGE, "%s: %s must be an integer (got %s)", where, s.name,
                        text.c_str());
        return store_int(where, opts, s, (int64_t)value);
    }
    assign(*opts, s, value);
    return FRIX_OK;
}

// Key s set from text: a choice name, an integer (exact, for int keys) or a number.
frix_error store_text(const char *where, frix_options *opts, const KeySpec &s, const char *text) {
    int64_t named = 0;
    if (choice_value(s, text, &named)) return store_int(where, opts, s, named);
    const bool numeral = text[0] != '\0' && !std::isspace((unsigned char)text[0]);
    char *end = nullptr;
    if (numeral && s.is_int) {
        errno = 0;
        const long long v = std::strtoll(text, &end, 10);
        if (end != text && *end == '\0' && errno != ERANGE) return store_int(where, opts, s, v);
    }
    errno = 0;
    const double v = std::strtod(text, &end);
    // Out of the doubles' range (1e400, 1e-400) is a range error, stated with the key's bounds.
    if (numeral && end != text && *end == '\0') {
        if (errno == ERANGE && (std::isinf(v) || v == 0.0)) return out_of_range(where, s, text);
        return store(where, opts, s, v, text);
    }
    const std::string names = choices_text(s);
    return fail(FRIX_ERR_OPTION_RANGE, "%s: %s = '%s' is not %s%s%s", where, s.name, text,
                s.is_int ? "an integer" : "a number", names.empty() ? "" : " nor a name of a choice",
                names.c_str());
}

}  // namespace

namespace frix {

namespace {

void fill_defaults(const SolverEntry &e, frix_options &o) {
    o = frix_options();
    o.solver_id = e.id;
    for (const KeySpec &s : kKeys) assign(o, s, s.default_value);
    for (const OptionDefault *d = e.defaults; d && d->key; ++d) assign(o, *spec_of(d->key), d->value);
}

}  // namespace

void default_options(const SolverEntry &e, frix_options &o) {
    // Made once for every registered solver (the registry is fixed) and copied: auto sets up
    // the options of every stage it runs, on small problems many times a millisecond.
    static const std::vector<frix_options> made = [] {
        std::vector<frix_options> t((size_t)solver_count());
        for (int64_t k = 0; k < solver_count(); ++k) fill_defaults(solver_at(k), t[(size_t)k]);
        return t;
    }();
    for (const frix_options &d : made)
        if (d.solver_id == e.id) {
            o = d;
            return;
        }
    fill_defaults(e, o);
}

}  // namespace frix

extern "C" {

FRIX_API frix_error frix_options_create(int solver_id, frix_options **out) {
    return frix::guard("frix_options_create", [&]() -> frix_error {
        if (!out) return fail(FRIX_ERR_INVALID_ARGUMENT, "frix_options_create: out is NULL");
        *out = nullptr;
        const frix::SolverEntry *e = frix::find_solver(solver_id);
        if (!e) return fail(FRIX_ERR_UNKNOWN_SOLVER, "frix_options_create: no solver has id %d", solver_id);
        auto o = std::make_unique<frix_options>();
        o->solver_id = solver_id;
        for (const KeySpec &s : kKeys) store("frix_options_create", o.get(), s, s.default_value);
        for (const frix::OptionDefault *d = e->defaults; d && d->key; ++d)
            if (store("frix_options_create", o.get(), *spec_of(d->key), d->value) != FRIX_OK) {
                const std::string why = frix_last_error_message();  // fail() rewrites that buffer
                return fail(FRIX_ERR_INTERNAL, "solver %s has an invalid default: %s", e->name,
                            why.c_str());
            }
        *out = o.release();
        return FRIX_OK;
    });
}

FRIX_API frix_error frix_options_copy(const frix_options *src, frix_options **out) {
    return frix::guard("frix_options_copy", [&]() -> frix_error {
        if (!src || !out) return fail(FRIX_ERR_INVALID_ARGUMENT, "frix_options_copy: NULL argument");
        *out = new frix_options(*src);
        return FRIX_OK;
    });
}

FRIX_API void frix_options_free(frix_options *opts) { delete opts; }

FRIX_API int frix_options_solver(const frix_options *opts) { return opts ? opts->solver_id : 0; }

FRIX_API frix_error frix_options_set_int(frix_options *opts, frix_option_key key, int64_t value) {
    return frix::guard("frix_options_set_int", [&]() -> frix_error {
        const KeySpec *s;
        if (frix_error e = lookup("frix_options_set_int", opts, key, &s)) return e;
        return store_int("frix_options_set_int", opts, *s, value);
    });
}

FRIX_API frix_error frix_options_set_double(frix_options *opts, frix_option_key key, double value) {
    return frix::guard("frix_options_set_double", [&]() -> frix_error {
        const KeySpec *s;
        if (frix_error e = lookup("frix_options_set_double", opts, key, &s)) return e;
        return store("frix_options_set_double", opts, *s, value);
    });
}

FRIX_API frix_error frix_options_set_by_name(frix_options *opts, const char *key, const char *value) {
    return frix::guard("frix_options_set_by_name", [&]() -> frix_error {
        if (!key || !value) return fail(FRIX_ERR_INVALID_ARGUMENT, "frix_options_set_by_name: NULL argument");
        frix_option_key k{};
        if (frix_error e = frix_option_by_name(key, &k)) return e;
        const KeySpec *s;
        if (frix_error e = lookup("frix_options_set_by_name", opts, k, &s)) return e;
        return store_text("frix_options_set_by_name", opts, *s, value);
    });
}

FRIX_API frix_error frix_options_get_int(const frix_options *opts, frix_option_key key,
                                         int64_t *value) {
    const KeySpec *s;
    if (frix_error e = lookup("frix_options_get_int", opts, key, &s)) return e;
    if (!value) return fail(FRIX_ERR_INVALID_ARGUMENT, "frix_options_get_int: value is NULL");
    if (!s->is_int)
        return fail(FRIX_ERR_INVALID_ARGUMENT, "frix_options_get_int: %s is a double option", s->name);
    *value = opts->ivalue[key];
    return FRIX_OK;
}

FRIX_API frix_error frix_options_get_double(const frix_options *opts, frix_option_key key,
                                            double *value) {
    const KeySpec *s;
    if (frix_error e = lookup("frix_options_get_double", opts, key, &s)) return e;
    if (!value) return fail(FRIX_ERR_INVALID_ARGUMENT, "frix_options_get_double: value is NULL");
    *value = s->is_int ? (double)opts->ivalue[key] : opts->dvalue[key];
    return FRIX_OK;
}

FRIX_API frix_error frix_options_bounds(const frix_options *opts, frix_option_key key,
                                        double *lower, double *upper, int *is_int) {
    const KeySpec *s;
    if (frix_error e = lookup("frix_options_bounds", opts, key, &s)) return e;
    if (lower) *lower = s->lower;
    if (upper) *upper = s->upper;
    if (is_int) *is_int = s->is_int ? 1 : 0;
    return FRIX_OK;
}

FRIX_API const char *frix_option_name(frix_option_key key) {
    const KeySpec *s = spec_of(key);
    return s ? s->name : nullptr;
}

FRIX_API frix_error frix_option_by_name(const char *name, frix_option_key *key) {
    if (!name || !key) return fail(FRIX_ERR_INVALID_ARGUMENT, "frix_option_by_name: NULL argument");
    for (const KeySpec &s : kKeys)
        if (std::strcmp(s.name, name) == 0) {
            *key = s.key;
            return FRIX_OK;
        }
    return fail(FRIX_ERR_UNKNOWN_OPTION, "frix_option_by_name: no option is called '%s'", name);
}

FRIX_API const char *frix_option_choice_name(frix_option_key key, int64_t value) {
    const KeySpec *s = spec_of(key);
    return s ? choice_name(*s, value) : nullptr;
}

FRIX_API frix_error frix_option_choice_by_name(frix_option_key key, const char *name, int64_t *value) {
    return frix::guard("frix_option_choice_by_name", [&]() -> frix_error {
        if (!name || !value) return fail(FRIX_ERR_INVALID_ARGUMENT, "frix_option_choice_by_name: NULL argument");
        const KeySpec *s = spec_of(key);
        if (!s) return fail(FRIX_ERR_UNKNOWN_OPTION, "frix_option_choice_by_name: unknown option key %d", (int)key);
        if (choice_value(*s, name, value)) return FRIX_OK;
        const std::string names = choices_text(*s);
        if (names.empty())
            return fail(FRIX_ERR_OPTION_RANGE, "frix_option_choice_by_name: %s takes a number, not a named choice",
                        s->name);
        return fail(FRIX_ERR_OPTION_RANGE, "frix_option_choice_by_name: %s has no choice '%s'%s", s->name, name,
                    names.c_str());
    });
}

FRIX_API frix_error frix_options_set_callback(frix_options *opts, frix_progress_fn fn,
                                              void *user_data) {
    if (!opts) return fail(FRIX_ERR_INVALID_ARGUMENT, "frix_options_set_callback: options is NULL");
    opts->callback = fn;
    opts->callback_data = fn ? user_data : nullptr;
    return FRIX_OK;
}

FRIX_API frix_error frix_options_set_log(frix_options *opts, frix_log_fn fn, void *user_data) {
    if (!opts) return fail(FRIX_ERR_INVALID_ARGUMENT, "frix_options_set_log: options is NULL");
    opts->log = fn;
    opts->log_data = fn ? user_data : nullptr;
    return FRIX_OK;
}

}  // extern "C"
