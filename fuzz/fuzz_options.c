/* libFuzzer target: options validation. The bytes are a program of operations on a handful
 * of option handles: create for a solver id (registered or not), set int/double of any key
 * to any value (raw doubles: NaN, Inf), get, bounds, copy, and name look-ups (solver names,
 * option names) of arbitrary strings.
 * Invariants (abort() = a finding): a refused set leaves the value as it was; an accepted one
 * reads back exactly and lies within the key's bounds; an int key holds an integer; unknown
 * keys and solvers are refused with a message; nothing crashes or leaks. */
#include <frix/frix.h>

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    const uint8_t *data;
    size_t size, at;
} stream;

static uint8_t byte(stream *s) { return s->at < s->size ? s->data[s->at++] : 0; }

static int64_t i64(stream *s) {
    uint64_t x = 0;
    for (int k = 0; k < 8; ++k) x = (x << 8) | byte(s);
    uint8_t mode = byte(s);
    if (mode < 160) return (int64_t)(x % 2048) - 1024; /* small values around the bounds */
    return (int64_t)x;
}

static double f64(stream *s) {
    uint8_t mode = byte(s);
    if (mode < 120) return ((double)byte(s) - 64.0) / 8.0;
    if (mode < 200) return (double)i64(s);
    uint64_t x = 0;
    for (int k = 0; k < 8; ++k) x = (x << 8) | byte(s);
    double d;
    memcpy(&d, &x, sizeof d);
    return d;
}

static int same_value(double a, double b) { return a == b || (isnan(a) && isnan(b)); }

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    stream s = {data, size, 0};
    frix_options *h[4] = {NULL, NULL, NULL, NULL};
    char text[33];
    for (int op = 0; op < 64 && s.at < s.size; ++op) {
        const uint8_t code = byte(&s);
        frix_options **slot = &h[code >> 6];
        frix_option_key key = (frix_option_key)((int)byte(&s) % 28 - 2);
        switch (code % 8) {
        case 0: { /* create */
            int id = byte(&s) < 200 ? frix_solver_id_at(byte(&s) % frix_solver_count()) : (int)i64(&s);
            frix_options *o = (frix_options *)0x1;
            frix_error e = frix_options_create(id, &o);
            if (e == FRIX_OK) {
                if (!o || frix_options_solver(o) != id || !frix_solver_name(id)) abort();
                frix_options_free(*slot);
                *slot = o;
            } else if (e != FRIX_ERR_UNKNOWN_SOLVER || o != NULL || frix_solver_name(id) != NULL) {
                abort();
            }
            break;
        }
        case 1:
        case 2: { /* set (double or int), then check the effect */
            if (!*slot) break;
            double before = NAN, after = NAN, lo, hi;
            int is_int = 0;
            const int known = frix_options_bounds(*slot, key, &lo, &hi, &is_int) == FRIX_OK;
            if (known && frix_options_get_double(*slot, key, &before) != FRIX_OK) abort();
            frix_error e;
            double want;
            if (code % 8 == 1) {
                want = f64(&s);
                e = frix_options_set_double(*slot, key, want);
            } else {
                int64_t x = i64(&s);
                want = (double)x;
                e = frix_options_set_int(*slot, key, x);
            }
            if (!known) {
                if (e != FRIX_ERR_UNKNOWN_OPTION) abort();
                break;
            }
            if (frix_options_get_double(*slot, key, &after) != FRIX_OK) abort();
            if (e == FRIX_OK) {
                if (!(want >= lo && want <= hi) || after != want) abort();
                if (is_int && want != floor(want)) abort();
            } else {
                if (e != FRIX_ERR_OPTION_RANGE || !same_value(after, before)) abort();
                if (frix_last_error_message()[0] == '\0') abort();
            }
            break;
        }
        case 3: { /* get int */
            int64_t x;
            if (!*slot) break;
            frix_error e = frix_options_get_int(*slot, key, &x);
            if (e != FRIX_OK && e != FRIX_ERR_UNKNOWN_OPTION && e != FRIX_ERR_INVALID_ARGUMENT) abort();
            break;
        }
        case 4: { /* copy: an identical handle */
            if (!*slot) break;
            frix_options *c = NULL;
            if (frix_options_copy(*slot, &c) != FRIX_OK) abort();
            for (int k = 0; k < 26; ++k) {
                double a, b;
                frix_error ea = frix_options_get_double(*slot, (frix_option_key)k, &a);
                frix_error eb = frix_options_get_double(c, (frix_option_key)k, &b);
                if (ea != eb || (ea == FRIX_OK && !same_value(a, b))) abort();
            }
            frix_options_free(h[(code >> 4) & 3]);
            h[(code >> 4) & 3] = c;
            break;
        }
        case 5:
        case 6: { /* names of arbitrary strings */
            size_t len = byte(&s) % 32;
            for (size_t k = 0; k < len; ++k) text[k] = (char)byte(&s);
            text[len] = '\0';
            int id = -12345;
            if (code % 8 == 5) {
                frix_error e = frix_solver_by_name(text, &id);
                if (e == FRIX_OK ? frix_solver_name(id) == NULL : (e != FRIX_ERR_UNKNOWN_SOLVER || id != -12345))
                    abort();
            } else {
                frix_option_key k2 = (frix_option_key)-77;
                frix_error e = frix_option_by_name(text, &k2);
                if (e == FRIX_OK ? strcmp(frix_option_name(k2), text) != 0 : e != FRIX_ERR_UNKNOWN_OPTION) abort();
            }
            break;
        }
        default: /* free */
            frix_options_free(*slot);
            *slot = NULL;
            break;
        }
    }
    for (int k = 0; k < 4; ++k) frix_options_free(h[k]);
    return 0;
}
