/* libFuzzer target: problem validation and solving on arbitrary small inputs. The bytes choose
 * a matrix constructor (CSC, CSR, triplets, dense, 3x3 blocks), sizes, indices (in range or
 * not, negative too) and values (raw doubles: NaN, Inf, subnormals, huge), then q/f/w/mu and
 * a local or global problem; a problem that is accepted is measured and solved by a solver of
 * the registry with a few iterations.
 * Invariants (abort() = a finding): refusals come with a message and leave *out NULL; an
 * accepted problem solves to finite r, u (v), a finite error, a valid status; CONVERGED only
 * with the independent measure within the tolerance; never FRIX_ERR_INTERNAL. */
#include <frix/frix.h>

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    const uint8_t *data;
    size_t size, at;
} stream;

static uint8_t byte(stream *s) { return s->at < s->size ? s->data[s->at++] : 0; }

/* Full range (FRIX_FUZZ_FULL_RANGE=1 in the environment): raw doubles up to 1e308, whose
 * products overflow. Without it, magnitudes stay within [1e-300, 1e12] (and NaN/Inf), which
 * is what the short runs of the test suite explore. */
static int full_range = -1;

/* FRIX_FUZZ_KNOWN_OPEN=1 waives one class of findings, for triage only (no run sets it since
 * the drivers fall back to a finite state): a solve that returns a finite but huge r whose
 * u = W r + q, or whose error measure, overflows to Inf/NaN. Crashes, sanitizer reports, leaks,
 * a non-finite r, FRIX_ERR_INTERNAL and a false CONVERGED are never waived. */
static int known_open(void) {
    static int value = -1;
    if (value < 0) value = getenv("FRIX_FUZZ_KNOWN_OPEN") && *getenv("FRIX_FUZZ_KNOWN_OPEN") == '1';
    return value;
}

static double real(stream *s) {
    uint8_t mode = byte(s);
    if (mode < 200) return ((double)byte(s) - 128.0) / 16.0; /* mostly tame values */
    if (full_range < 0) full_range = getenv("FRIX_FUZZ_FULL_RANGE") && *getenv("FRIX_FUZZ_FULL_RANGE") == '1';
    if (!full_range) {
        static const double tame[] = {0.0, -0.0, 1e-300, 1e12, -1e12, 1e-12, NAN, INFINITY};
        return tame[byte(s) % 8] * (mode < 240 ? 1.0 : ((double)byte(s) + 1.0) / 64.0);
    }
    if (mode < 240) {
        static const double special[] = {0.0, -0.0, 1e-300, 1e300, -1e300, 1e-12, 1e12, 4.9e-324};
        return special[byte(s) % 8];
    }
    double x = 0; /* raw bits: NaN, Inf, anything */
    uint8_t b[8];
    for (int k = 0; k < 8; ++k) b[k] = byte(s);
    memcpy(&x, b, sizeof x);
    return x;
}

/* An index: mostly in [0, bound), sometimes just outside or negative. */
static int64_t index_of(stream *s, int64_t bound) {
    uint8_t b = byte(s);
    if (b < 240) return bound > 0 ? (int64_t)(b % (uint64_t)bound) : 0;
    static const int64_t odd[] = {-1, INT64_MIN, INT64_MAX};
    if (b < 243) return odd[b - 240];
    return bound + (int64_t)(b - 243);
}

static void check_refusal(frix_error err, const void *out) {
    if (err == FRIX_ERR_INTERNAL || out != NULL || frix_last_error_message()[0] == '\0') abort();
}

/* A matrix of nrows x ncols from the stream, through one of the five constructors. */
static frix_error make_matrix(stream *s, int64_t nrows, int64_t ncols, frix_matrix **out) {
    const int how = byte(s) % 5;
    const int64_t nnz = byte(s) % 24;
    int64_t ptr[40], idx[24], idx2[24];
    double val[9 * 24];
    frix_error err;
    *out = NULL;
    if (how == 0 || how == 1) { /* CSC / CSR: a pointer array that may decrease or overflow */
        const int64_t nptr = (how == 0 ? ncols : nrows) + 1;
        if (nptr > 40) return FRIX_ERR_DIMENSION;
        ptr[0] = byte(s) < 250 ? 0 : 1;
        for (int64_t k = 1; k < nptr; ++k) {
            uint8_t b = byte(s);
            ptr[k] = b < 230 ? ptr[k - 1] + (b % 4 < 3 ? b % 3 : 0) : ptr[k - 1] - 1;
            if (ptr[k] > nnz) ptr[k] = nnz;
        }
        for (int64_t k = 0; k < nnz; ++k) {
            idx[k] = index_of(s, how == 0 ? nrows : ncols);
            val[k] = real(s);
        }
        /* the constructors read ptr[n] entries: keep them within the arrays */
        for (int64_t k = 0; k < nptr; ++k)
            if (ptr[k] > nnz || ptr[k] < 0) ptr[k] = nnz;
        err = how == 0 ? frix_matrix_from_csc(nrows, ncols, ptr, idx, val, out)
                       : frix_matrix_from_csr(nrows, ncols, ptr, idx, val, out);
    } else if (how == 2) {
        for (int64_t k = 0; k < nnz; ++k) {
            idx[k] = index_of(s, nrows);
            idx2[k] = index_of(s, ncols);
            val[k] = real(s);
        }
        err = frix_matrix_from_triplets(nrows, ncols, nnz, idx, idx2, val, out);
    } else if (how == 3) {
        if (nrows * ncols > 9 * 24) return FRIX_ERR_DIMENSION;
        for (int64_t k = 0; k < nrows * ncols; ++k) val[k] = byte(s) < 128 ? 0.0 : real(s);
        err = frix_matrix_from_dense(nrows, ncols, val, nrows > 0 ? nrows : 1, out);
    } else {
        const int64_t nb = nnz % 8;
        for (int64_t k = 0; k < nb; ++k) {
            idx[k] = index_of(s, nrows / 3);
            idx2[k] = index_of(s, ncols / 3);
            for (int e = 0; e < 9; ++e) val[9 * k + e] = real(s);
        }
        err = frix_matrix_from_blocks(nrows / 3, ncols / 3, nb, idx, idx2, val, out);
    }
    if (err != FRIX_OK) check_refusal(err, *out);
    return err;
}

/* A finding: what it was, and the problem that caused it (to reproduce it by hand). */
static void finding(const char *what, const frix_problem *p, int solver, const frix_info *info) {
    fprintf(stderr, "FINDING: %s; solver %d, status %d, iterations %lld, error %.17g\n", what, solver,
            info ? (int)frix_info_status(info) : -1, info ? (long long)frix_info_iterations(info) : -1LL,
            info ? frix_info_error(info) : 0.0);
    const int global = frix_problem_get_kind(p) == FRIX_PROBLEM_GLOBAL;
    const int64_t nc = frix_problem_contacts(p), n = frix_problem_dofs(p);
    const frix_matrix *mats[2] = {global ? frix_problem_M(p) : frix_problem_W(p), frix_problem_H(p)};
    for (int k = 0; k < (global ? 2 : 1); ++k) {
        int64_t nnz = 0, ptr[64], idx[512];
        double val[512];
        if (frix_matrix_to_csc(mats[k], &nnz, NULL, NULL, NULL) || nnz > 512 || frix_matrix_cols(mats[k]) > 63 ||
            frix_matrix_to_csc(mats[k], &nnz, ptr, idx, val))
            continue;
        fprintf(stderr, "%s %lld x %lld, CSC:", global ? (k ? "H" : "M") : "W", (long long)frix_matrix_rows(mats[k]),
                (long long)frix_matrix_cols(mats[k]));
        for (int64_t j = 0; j < frix_matrix_cols(mats[k]); ++j)
            for (int64_t e = ptr[j]; e < ptr[j + 1]; ++e)
                fprintf(stderr, " (%lld,%lld)=%.17g", (long long)idx[e], (long long)j, val[e]);
        fprintf(stderr, "\n");
    }
    const double *vecs[3] = {global ? frix_problem_f(p) : frix_problem_q(p), global ? frix_problem_w(p) : NULL,
                             frix_problem_mu(p)};
    const int64_t lens[3] = {global ? n : 3 * nc, global ? 3 * nc : 0, nc};
    for (int k = 0; k < 3; ++k) {
        fprintf(stderr, "%s:", k == 0 ? (global ? "f" : "q") : k == 1 ? "w" : "mu");
        for (int64_t i = 0; i < lens[k]; ++i) fprintf(stderr, " %.17g", vecs[k][i]);
        fprintf(stderr, "\n");
    }
    abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    stream s = {data, size, 0};
    const int global = byte(&s) & 1;
    const int64_t nc = byte(&s) % 4; /* contacts */
    /* Sizes: mostly consistent, sometimes off by a little. */
    const int64_t skew = byte(&s) < 230 ? 0 : (int64_t)(byte(&s) % 5) - 2;
    const int64_t n = global ? 1 + byte(&s) % 9 : 0;
    frix_matrix *A = NULL, *B = NULL;
    double vec1[40], vec2[40], mu[8];
    for (int k = 0; k < 40; ++k) {
        vec1[k] = real(&s);
        vec2[k] = real(&s);
    }
    for (int k = 0; k < 8; ++k) mu[k] = byte(&s) < 240 ? (double)byte(&s) / 64.0 : real(&s);
    frix_problem *p = NULL;
    frix_error err;
    if (!global) {
        err = make_matrix(&s, 3 * nc + skew, 3 * nc + (byte(&s) < 250 ? skew : 1), &A);
        if (err == FRIX_OK) {
            err = frix_problem_local(A, vec1, mu, nc, &p);
            if (err != FRIX_OK) check_refusal(err, p);
        }
    } else {
        err = make_matrix(&s, n, n, &A);
        if (err == FRIX_OK) err = make_matrix(&s, n + skew, 3 * nc, &B);
        if (err == FRIX_OK) {
            err = frix_problem_global(A, B, vec1, vec2, mu, nc, &p);
            if (err != FRIX_OK) check_refusal(err, p);
        }
    }
    /* Known and open (issue 7 note): a global problem with no degrees of freedom (n = 0) but
     * contacts is accepted, and then every solver but 607 fails in the reduction. */
    if (err == FRIX_OK && global && frix_problem_dofs(p) == 0 && nc > 0 && known_open()) {
        frix_problem_free(p);
        p = NULL;
        err = FRIX_ERR_DIMENSION;
    }
    if (err == FRIX_OK) {
        const int64_t m = 3 * nc;
        double r[12], u[12], v[16], error = NAN;
        for (int k = 0; k < 12; ++k) r[k] = byte(&s) < 200 ? 0.0 : real(&s); /* warm start, maybe NaN */
        for (int k = 0; k < 16; ++k) v[k] = 0.0;
        frix_options *o = NULL;
        frix_info *info = NULL, *check = NULL;
        const int solver = frix_solver_id_at(byte(&s) % frix_solver_count());
        if (frix_options_create(solver, &o) || frix_options_set_int(o, FRIX_OPT_MAX_ITER, 1 + byte(&s) % 30) ||
            frix_options_set_double(o, FRIX_OPT_TIME_LIMIT, 0.5) || frix_info_create(&info) ||
            frix_info_create(&check))
            abort();
        err = frix_solve(p, o, r, u, global ? v : NULL, info);
        if (err == FRIX_ERR_INTERNAL) finding(frix_last_error_message(), p, solver, info);
        if (err == FRIX_OK) {
            const frix_status st0 = frix_info_status(info);
            const int waived = known_open() && st0 != FRIX_STATUS_CONVERGED;
            for (int64_t k = 0; k < m; ++k)
                if (!isfinite(r[k]) || (!isfinite(u[k]) && !waived)) finding("non-finite r or u", p, solver, info);
            for (int64_t k = 0; global && k < n; ++k)
                if (!isfinite(v[k])) finding("non-finite v", p, solver, info);
            const frix_status st = frix_info_status(info);
            if (st < FRIX_STATUS_CONVERGED || st > FRIX_STATUS_NUMERICAL_FAILURE) finding("bad status", p, solver, info);
            if (!(frix_info_error(info) >= 0) && !waived) finding("error not a finite number >= 0", p, solver, info);
            if (frix_problem_measure(p, r, global ? v : NULL, NULL, check) != FRIX_OK)
                finding("the returned r cannot be measured", p, solver, info);
            if (st == FRIX_STATUS_CONVERGED &&
                (frix_info_get_double(check, FRIX_INFO_ERROR_SCALED, &error) != FRIX_OK || !(error <= 1e-8)))
                finding("converged, but the measured error is above the tolerance", p, solver, info);
        } else if (err != FRIX_ERR_UNSUPPORTED && err != FRIX_ERR_NUMERICAL && err != FRIX_ERR_NOT_FINITE) {
            /* an accepted problem is solvable or says why not */
            finding(frix_last_error_message(), p, solver, info);
        }
        frix_info_free(check);
        frix_info_free(info);
        frix_options_free(o);
        frix_problem_free(p);
    }
    frix_matrix_free(A);
    frix_matrix_free(B);
    return 0;
}
