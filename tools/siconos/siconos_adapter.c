/* Siconos/Numerics 4.4 comparator: see siconos_adapter.h. Plain C because Siconos reports
 * fatal errors by longjmp, which must not cross C++ frames. */
#define _POSIX_C_SOURCE 200809L

#include "siconos_adapter.h"

#include <ctype.h>
#include <limits.h>
#include <math.h>
#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <cs.h> /* struct cs_dl_sparse, the layout of Siconos's CSparseMatrix (CS_INT long) */

#include "FrictionContactProblem.h"
#include "NonSmoothDrivers.h"
#include "NumericsMatrix.h"
#include "NumericsVerbose.h"
#include "SolverOptions.h"
#include "SparseBlockMatrix.h"
#include "sn_error_handling.h"

/* The local FC3D solvers of Siconos 4.4 (Friction_cst.h) that need nothing beyond
 * Debian's build (no GAMS). */
static const struct {
    int id;
    const char *name;
} kSolvers[] = {
    {500, "NSGS"},   {501, "NSGSV"},  {502, "PROX"},  {503, "TFP"},    {504, "NSN_AC"},
    {505, "DSFP"},   {506, "VI_FPP"}, {507, "VI_EG"}, {508, "HP"},     {511, "FPP"},
    {512, "EG"},     {513, "NSN_FB"}, {516, "ACLMFP"}, {517, "SOCLCP"}, {520, "NSN_NM"},
    {521, "NSN_AC_TEST"}, {522, "PFP"}, {523, "ADMM"},
};
enum { kSolverCount = (int)(sizeof kSolvers / sizeof kSolvers[0]) };

int frix_siconos_solver_count(void) { return kSolverCount; }

int frix_siconos_solver_id_at(int index) {
    return index >= 0 && index < kSolverCount ? kSolvers[index].id : -1;
}

const char *frix_siconos_solver_name(int id) {
    for (int k = 0; k < kSolverCount; ++k)
        if (kSolvers[k].id == id) return kSolvers[k].name;
    return NULL;
}

static int same_name(const char *a, const char *b) {
    for (; *a && *b; ++a, ++b)
        if (toupper((unsigned char)*a) != toupper((unsigned char)*b)) return 0;
    return *a == *b;
}

static const char *strip_prefix(const char *name, const char *prefix) {
    size_t n = strlen(prefix);
    for (size_t k = 0; k < n; ++k)
        if (toupper((unsigned char)name[k]) != prefix[k]) return name;
    return name + n;
}

int frix_siconos_solver_by_name(const char *name) {
    if (!name || !*name) return -1;
    char *end = NULL;
    long id = strtol(name, &end, 10);
    if (end && *end == '\0') return frix_siconos_solver_name((int)id) ? (int)id : -1;
    const char *s = strip_prefix(name, "SICONOS_");
    s = strip_prefix(s, "FRICTION_3D_");
    s = strip_prefix(s, "FC3D_");
    for (int k = 0; k < kSolverCount; ++k)
        if (same_name(s, kSolvers[k].name)) return kSolvers[k].id;
    return -1;
}

/* ---- The iteration callback ---------------------------------------------------------- */

typedef struct {
    struct timespec start;
    frix_siconos_trace_fn fn;
    void *data;
    int64_t calls;
} trace_env;

static double seconds_since(const struct timespec *start) {
    struct timespec now;
    clock_gettime(CLOCK_MONOTONIC, &now);
    return (double)(now.tv_sec - start->tv_sec) + 1e-9 * (double)(now.tv_nsec - start->tv_nsec);
}

static void collect(void *env, int size, double *reaction, double *velocity, double error,
                    void *extra) {
    (void)size;
    (void)reaction;
    (void)velocity;
    (void)extra;
    trace_env *t = (trace_env *)env;
    ++t->calls;
    if (t->fn) t->fn(t->data, t->calls, seconds_since(&t->start), error);
}

/* ---- Building Siconos's problem from frix's --------------------------------------------- */

/* W as Siconos's sparse-block matrix (3x3 blocks), through CSC as its FCLIB reader does. */
static NumericsMatrix *block_matrix(const frix_matrix *W, char *msg, size_t msg_len) {
    int64_t n = frix_matrix_rows(W), nnz = 0;
    if (frix_matrix_to_csc(W, &nnz, NULL, NULL, NULL) != FRIX_OK) {
        snprintf(msg, msg_len, "frix_matrix_to_csc: %s", frix_last_error_message());
        return NULL;
    }
    int64_t *colptr = malloc(sizeof(int64_t) * (size_t)(n + 1));
    int64_t *rowind = malloc(sizeof(int64_t) * (size_t)(nnz > 0 ? nnz : 1));
    double *values = malloc(sizeof(double) * (size_t)(nnz > 0 ? nnz : 1));
    cs_long_t *p = malloc(sizeof(cs_long_t) * (size_t)(n + 1));
    cs_long_t *i = malloc(sizeof(cs_long_t) * (size_t)(nnz > 0 ? nnz : 1));
    NumericsMatrix *M = NULL;
    if (!colptr || !rowind || !values || !p || !i) {
        snprintf(msg, msg_len, "out of memory");
    } else if (frix_matrix_to_csc(W, &nnz, colptr, rowind, values) != FRIX_OK) {
        snprintf(msg, msg_len, "frix_matrix_to_csc: %s", frix_last_error_message());
    } else {
        for (int64_t k = 0; k <= n; ++k) p[k] = (cs_long_t)colptr[k];
        for (int64_t k = 0; k < nnz; ++k) i[k] = (cs_long_t)rowind[k];
        cs_dl csc = {(cs_long_t)(nnz > 0 ? nnz : 1), (cs_long_t)n, (cs_long_t)n, p, i, values,
                     -1};
        M = NM_create(NM_SPARSE_BLOCK, (int)n, (int)n);
        if (SBM_from_csparse(3, (const CSparseMatrix *)&csc, M->matrix1) != 0) {
            snprintf(msg, msg_len, "SBM_from_csparse refused W");
            M = NM_free(M); /* clears and releases M, returns NULL */
        }
    }
    free(colptr);
    free(rowind);
    free(values);
    free(p);
    free(i);
    return M;
}

static double *copy_of(const double *x, int64_t n) {
    double *c = malloc(sizeof(double) * (size_t)(n > 0 ? n : 1));
    if (c && n > 0) memcpy(c, x, sizeof(double) * (size_t)n);
    return c;
}

/* fc3d_driver behind Siconos's jmp buffer: a numerics_error returns here instead of
 * aborting. Kept apart so that no local of the caller is live across the longjmp. */
static int guarded_driver(FrictionContactProblem *fc, double *r, double *u, SolverOptions *o,
                          int *ran) {
    *ran = 0;
    if (setjmp(*sn_get_jmp_buf()) != 0) return -1;
    int info = fc3d_driver(fc, r, u, o);
    sn_release_jmp_buf();
    *ran = 1;
    return info;
}

int frix_siconos_solve(const frix_problem *problem, int solver_id, double tolerance,
                       int64_t max_iter, double *r, double *u, frix_siconos_trace_fn trace,
                       void *trace_data, frix_siconos_result *res) {
    memset(res, 0, sizeof *res);
    res->siconos_error = NAN;
    res->error = NAN;
    res->time = NAN;
    if (!frix_siconos_solver_name(solver_id)) {
        snprintf(res->message, sizeof res->message, "unknown Siconos solver id %d", solver_id);
        return -1;
    }
    if (frix_problem_get_kind(problem) != FRIX_PROBLEM_LOCAL) {
        snprintf(res->message, sizeof res->message,
                 "the Siconos comparator takes local problems only (fc3d_driver)");
        return -1;
    }
    const int64_t nc = frix_problem_contacts(problem), m = 3 * nc;
    if (m > INT_MAX) {
        snprintf(res->message, sizeof res->message, "too large for Siconos's int sizes");
        return -1;
    }

    if (nc == 0) { /* nothing to solve; Siconos's structures do not expect it */
        res->ran = 1;
        res->error = res->siconos_error = res->time = 0;
        return 0;
    }

    numerics_set_verbose(0);
    NumericsMatrix *M = block_matrix(frix_problem_W(problem), res->message, sizeof res->message);
    if (!M) return -1;
    /* Copies: the problem frees them, and PROX modifies W and q in place. */
    FrictionContactProblem *fc = frictionContactProblem_new_with_data(
        3, (int)nc, M, copy_of(frix_problem_q(problem), m), copy_of(frix_problem_mu(problem), nc));
    SolverOptions *opts = solver_options_create(solver_id);
    opts->dparam[SICONOS_DPARAM_TOL] = tolerance;
    if (max_iter > 0) opts->iparam[SICONOS_IPARAM_MAX_ITER] = max_iter > INT_MAX ? INT_MAX : (int)max_iter;

    /* The callback only when a trace is asked for: Siconos does extra work per iteration for
     * it, which a timing-only solve must not pay. */
    trace_env env = {{0, 0}, trace, trace_data, 0};
    Callback *cb = NULL;
    if (trace) {
        cb = malloc(sizeof *cb);
        cb->env = &env;
        cb->collectStatsIteration = collect;
        opts->callback = cb;
    }

    struct timespec start;
    clock_gettime(CLOCK_MONOTONIC, &start);
    env.start = start;
    int ran = 0;
    int info = guarded_driver(fc, r, u, opts, &ran);
    res->time = seconds_since(&start);

    res->ran = ran;
    res->info = info;
    res->iterations = opts->iparam[SICONOS_IPARAM_ITER_DONE];
    res->siconos_error = opts->dparam[SICONOS_DPARAM_RESIDU];
    res->callbacks = env.calls;
    if (!ran) {
        const char *why = sn_fatal_error_msg();
        snprintf(res->message, sizeof res->message, "Siconos error: %s", why && *why ? why : "?");
    }

    opts->callback = NULL; /* ours, not Siconos's to free */
    free(cb);
    solver_options_delete(opts);
    frictionContactProblem_free(fc);

    /* One measure for both: frix's, of the r Siconos returned (u recomputed as W r + q). */
    if (ran) {
        if (frix_problem_error(problem, r, NULL, &res->error) != FRIX_OK) res->error = NAN;
        if (frix_matrix_gemv(frix_problem_W(problem), 1.0, r, 0.0, u) == FRIX_OK)
            for (int64_t k = 0; k < m; ++k) u[k] += frix_problem_q(problem)[k];
    }
    return ran ? 0 : -1;
}
