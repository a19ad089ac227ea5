// Options by key: the key table (type, bounds, default), per-solver key sets and defaults.
#include "options.hpp"

#include <cfloat>
#include <cmath>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "error_state.hpp"
#include "solver_api.hpp"

namespace {

using frix::fail;

struct KeySpec {
    frix_option_key key;
    const char *name;
    bool is_int;
    double lower, upper;  // inclusive
    double default_value;
    const int64_t *allowed = nullptr;  // for keys naming a choice: the values, 0-terminated
};

// The one-contact solvers (frix_local_solver).
const int64_t kLocalSolvers[] = {FRIX_LOCAL_PROJECTION, FRIX_LOCAL_PROJECTION_ITERATED,
                                 FRIX_LOCAL_CLOSED_FORM, FRIX_LOCAL_NEWTON_AC,
                                 FRIX_LOCAL_NEWTON_AC_GP, FRIX_LOCAL_NEWTON_FB,
                                 FRIX_LOCAL_HYBRID, 0};

// The Newton solvers PROX may run inside.
const int64_t kInnerSolvers[] = {504, 513, 520, 0};

// Common defaults: the tolerance our users ask for (FCLIB comparisons use 1e-8), and
// limits that a solver's entry may override.
const KeySpec kKeys[] = {
    {FRIX_OPT_TOLERANCE, "tolerance", false, 0.0, 1.0, 1e-8},
    {FRIX_OPT_MAX_ITER, "max_iter", true, 1.0, 1e9, 1000.0},
    {FRIX_OPT_TIME_LIMIT, "time_limit", false, 0.0, 1e9, 0.0},
    {FRIX_OPT_VERBOSITY, "verbosity", true, 0.0, 3.0, 0.0},
    {FRIX_OPT_ERROR_MEASURE, "error_measure", true, 0.0, 2.0, 2.0},
    {FRIX_OPT_LOCAL_SOLVER, "local_solver", true, 550.0, 565.0, 562.0, kLocalSolvers},
    {FRIX_OPT_LOCAL_TOLERANCE, "local_tolerance", false, 0.0, 1.0, 1e-12},
    {FRIX_OPT_LOCAL_MAX_ITER, "local_max_iter", true, 1.0, 1e6, 20.0},
    {FRIX_OPT_RELAXATION, "relaxation", false, 1e-3, 1.999, 1.0},
    {FRIX_OPT_SHUFFLE, "shuffle", true, 0.0, 2.0, 0.0},
    {FRIX_OPT_SEED, "seed", true, 0.0, 9007199254740992.0 /* 2^53 */, 0.0},
    {FRIX_OPT_RHO_STRATEGY, "rho_strategy", true, 0.0, 2.0, 1.0},
    {FRIX_OPT_RHO, "rho", false, 1e-300, 1e300, 1.0},
    {FRIX_OPT_LINE_SEARCH, "line_search", true, 0.0, 3.0, 1.0},
    {FRIX_OPT_LINE_SEARCH_MAX_ITER, "line_search_max_iter", true, 1.0, 1000.0, 20.0},
    {FRIX_OPT_HYBRID, "hybrid", true, 0.0, 1.0, 1.0},
    {FRIX_OPT_HYBRID_SWEEPS, "hybrid_sweeps", true, 1.0, 1e6, 50.0},
    {FRIX_OPT_PROX_ALPHA, "prox_alpha", false, 0.0, 1e300, 0.0},
    {FRIX_OPT_PROX_SIGMA, "prox_sigma", false, 1e-300, 1e300, 5.0},
    {FRIX_OPT_PROX_NU, "prox_nu", false, 1e-3, 10.0, 1.0},
    {FRIX_OPT_INNER_SOLVER, "inner_solver", true, 504.0, 520.0, 504.0, kInnerSolvers},
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
};

const frix_option_key kCommonKeys[] = {FRIX_OPT_TOLERANCE, FRIX_OPT_MAX_ITER, FRIX_OPT_TIME_LIMIT,
                                       FRIX_OPT_VERBOSITY, FRIX_OPT_ERROR_MEASURE, FRIX_OPT_MEMORY_LIMIT};

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

frix_error store(const char *where, frix_options *opts, const KeySpec &s, double value) {
    if (std::isnan(value) || value < s.lower || value > s.upper)
        return fail(FRIX_ERR_OPTION_RANGE, "%s: %s = %g is outside [%g, %g]", where, s.name, value,
                    s.lower, s.upper);
    if (s.is_int) {
        if (value != std::floor(value))
            return fail(FRIX_ERR_OPTION_RANGE, "%s: %s must be an integer (got %g)", where, s.name, value);
        if (s.allowed) {
            const int64_t *a = s.allowed;
            while (*a && *a != (int64_t)value) ++a;
            if (!*a)
                return fail(FRIX_ERR_OPTION_RANGE, "%s: %s = %g is not one of the defined values",
                            where, s.name, value);
        }
    }
    assign(*opts, s, value);
    return FRIX_OK;
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
    const KeySpec *s;
    if (frix_error e = lookup("frix_options_set_int", opts, key, &s)) return e;
    return store("frix_options_set_int", opts, *s, (double)value);
}

FRIX_API frix_error frix_options_set_double(frix_options *opts, frix_option_key key, double value) {
    const KeySpec *s;
    if (frix_error e = lookup("frix_options_set_double", opts, key, &s)) return e;
    return store("frix_options_set_double", opts, *s, value);
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
