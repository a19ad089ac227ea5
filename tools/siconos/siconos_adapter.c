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
#include "Friction_cst.h"
#include "GlobalFrictionContactProblem.h"
#include "GlobalRollingFrictionContactProblem.h"
#include "RollingFrictionContactProblem.h"
#include "NonSmoothDrivers.h"
#include "NumericsMatrix.h"
#include "NumericsSparseMatrix.h"
#include "NumericsVerbose.h"
#include "SolverOptions.h"
#include "SparseBlockMatrix.h"
#include "sn_error_handling.h"

/* The FC3D local and GFC3D global solvers of Siconos 4.4 (Friction_cst.h) that need
 * nothing beyond Debian's build (no GAMS); not GFC3D_NSGSV_WR either, whose inner solver
 * exits on the sparse W its reformulation builds. A global one is named as Siconos names
 * it (SICONOS_GLOBAL_FRICTION_3D_*_STR), so that its name alone says which kind it solves. */
static const struct {
    int id;
    const char *name;
    int global;
} kSolvers[] = {
    {500, "NSGS", 0},   {501, "NSGSV", 0},  {502, "PROX", 0},   {503, "TFP", 0},
    {504, "NSN_AC", 0}, {505, "DSFP", 0},   {506, "VI_FPP", 0}, {507, "VI_EG", 0},
    {508, "HP", 0},     {511, "FPP", 0},    {512, "EG", 0},     {513, "NSN_FB", 0},
    {516, "ACLMFP", 0}, {517, "SOCLCP", 0}, {520, "NSN_NM", 0}, {521, "NSN_AC_TEST", 0},
    {522, "PFP", 0},    {523, "ADMM", 0},
    {600, "GFC3D_NSGS_WR", 1},   {602, "GFC3D_PROX_WR", 1}, {603, "GFC3D_DSFP_WR", 1},
    {604, "GFC3D_TFP_WR", 1},    {605, "GFC3D_NSGS", 1},    {606, "GFC3D_NSN_AC_WR", 1},
    {607, "GFC3D_NSN_AC", 1},    {610, "GFC3D_VI_FPP", 1},  {611, "GFC3D_VI_EG", 1},
    {612, "GFC3D_ACLMFP", 1},    {613, "GFC3D_ADMM", 1},    {614, "GFC3D_ADMM_WR", 1},
    {615, "GFC3D_IPM", 1},
    /* Rolling friction, local form (rolling_fc3d_driver) and global form
     * (g_rolling_fc3d_driver): rolling problems only. */
    {3000, "RFC3D_NSGS", 0},     {3003, "RFC3D_ADMM", 0},   {5000, "GRFC3D_NSGS_WR", 1},
};
enum { kSolverCount = (int)(sizeof kSolvers / sizeof kSolvers[0]) };
static const char kGlobalPrefix[] = "GFC3D_";

int frix_siconos_solver_count(void) { return kSolverCount; }

int frix_siconos_solver_id_at(int index) {
    return index >= 0 && index < kSolverCount ? kSolvers[index].id : -1;
}

const char *frix_siconos_solver_name(int id) {
    for (int k = 0; k < kSolverCount; ++k)
        if (kSolvers[k].id == id) return kSolvers[k].name;
    return NULL;
}

int frix_siconos_solver_is_rolling(int id) {
    if (!frix_siconos_solver_name(id)) return -1;
    return id == SICONOS_ROLLING_FRICTION_3D_NSGS || id == SICONOS_ROLLING_FRICTION_3D_ADMM ||
           id == SICONOS_GLOBAL_ROLLING_FRICTION_3D_NSGS_WR;
}

int frix_siconos_solver_is_global(int id) {
    for (int k = 0; k < kSolverCount; ++k)
        if (kSolvers[k].id == id) return kSolvers[k].global;
    return -1;
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
    const char *gr = strip_prefix(s, "GLOBAL_ROLLING_FRICTION_3D_");
    if (gr == s) gr = strip_prefix(s, "GRFC3D_");
    if (gr != s) { /* a global rolling solver's spelling: its short name after GRFC3D_ */
        for (int k = 0; k < kSolverCount; ++k)
            if (kSolvers[k].global && frix_siconos_solver_is_rolling(kSolvers[k].id) == 1 &&
                same_name(gr, kSolvers[k].name + strlen("GRFC3D_")))
                return kSolvers[k].id;
        return -1;
    }
    const char *g = strip_prefix(s, "GLOBAL_FRICTION_3D_");
    if (g == s) g = strip_prefix(s, kGlobalPrefix);
    if (g != s) { /* a global solver's spelling: its short name after GFC3D_ */
        for (int k = 0; k < kSolverCount; ++k)
            if (kSolvers[k].global && frix_siconos_solver_is_rolling(kSolvers[k].id) == 0 &&
                same_name(g, kSolvers[k].name + strlen(kGlobalPrefix)))
                return kSolvers[k].id;
        return -1;
    }
    const char *rolling = strip_prefix(s, "ROLLING_FRICTION_3D_");
    if (rolling != s) { /* Siconos's long spelling of RFC3D_ */
        for (int k = 0; k < kSolverCount; ++k)
            if (frix_siconos_solver_is_rolling(kSolvers[k].id) == 1 && same_name(rolling, kSolvers[k].name + 6))
                return kSolvers[k].id;
        return -1;
    }
    s = strip_prefix(s, "FRICTION_3D_");
    s = strip_prefix(s, "FC3D_");
    for (int k = 0; k < kSolverCount; ++k)
        if (!kSolvers[k].global && same_name(s, kSolvers[k].name)) return kSolvers[k].id;
    return -1;
}

/* ---- The iteration callback ---------------------------------------------------------- */

typedef struct {
    struct timespec start;
    frix_siconos_trace_fn fn;
    void *data;
    int64_t calls;
    /* A local problem: each iterate (reaction, of the problem's size) is measured by frix (its
     * default measure, as frix's own traces), and the seconds that takes are left out of the
     * times. NULL: Siconos's error. */
    const frix_problem *measured;
    double measuring;
} trace_env;

static double seconds_since(const struct timespec *start) {
    struct timespec now;
    clock_gettime(CLOCK_MONOTONIC, &now);
    return (double)(now.tv_sec - start->tv_sec) + 1e-9 * (double)(now.tv_nsec - start->tv_nsec);
}

static void collect(void *env, int size, double *reaction, double *velocity, double error,
                    void *extra) {
    (void)velocity;
    (void)extra;
    trace_env *t = (trace_env *)env;
    ++t->calls;
    if (!t->fn) return;
    if (t->measured && (int64_t)size == frix_problem_contact_dofs(t->measured) && reaction) {
        struct timespec before;
        clock_gettime(CLOCK_MONOTONIC, &before);
        double e = NAN;
        error = frix_problem_error(t->measured, reaction, NULL, &e) == FRIX_OK ? e : NAN;
        t->measuring += seconds_since(&before);
    }
    t->fn(t->data, t->calls, seconds_since(&t->start) - t->measuring, error);
}

/* ---- Building Siconos's problem from frix's --------------------------------------------- */

/* A frix matrix as compressed sparse columns in CSparse's index type (cs_dl, the layout of
 * Siconos's CSparseMatrix); p, i and x are the caller's to free, also on failure. */
typedef struct {
    int64_t rows, cols, nnz;
    cs_long_t *p, *i;
    double *x;
} csc_copy;

static int export_csc(const frix_matrix *A, csc_copy *c, char *msg, size_t msg_len) {
    memset(c, 0, sizeof *c);
    c->rows = frix_matrix_rows(A);
    c->cols = frix_matrix_cols(A);
    if (frix_matrix_to_csc(A, &c->nnz, NULL, NULL, NULL) != FRIX_OK) {
        snprintf(msg, msg_len, "frix_matrix_to_csc: %s", frix_last_error_message());
        return 0;
    }
    const size_t cols1 = (size_t)(c->cols + 1), nz = (size_t)(c->nnz > 0 ? c->nnz : 1);
    int64_t *colptr = malloc(sizeof(int64_t) * cols1);
    int64_t *rowind = malloc(sizeof(int64_t) * nz);
    c->x = malloc(sizeof(double) * nz);
    c->p = malloc(sizeof(cs_long_t) * cols1);
    c->i = malloc(sizeof(cs_long_t) * nz);
    int ok = 0;
    if (!colptr || !rowind || !c->x || !c->p || !c->i) {
        snprintf(msg, msg_len, "out of memory");
    } else if (frix_matrix_to_csc(A, &c->nnz, colptr, rowind, c->x) != FRIX_OK) {
        snprintf(msg, msg_len, "frix_matrix_to_csc: %s", frix_last_error_message());
    } else {
        for (int64_t k = 0; k <= c->cols; ++k) c->p[k] = (cs_long_t)colptr[k];
        for (int64_t k = 0; k < c->nnz; ++k) c->i[k] = (cs_long_t)rowind[k];
        ok = 1;
    }
    free(colptr);
    free(rowind);
    return ok;
}

static void free_csc(csc_copy *c) {
    free(c->p);
    free(c->i);
    free(c->x);
}

/* W as Siconos's sparse-block matrix (3x3 blocks), through CSC as its FCLIB reader does. */
static NumericsMatrix *block_matrix(const frix_matrix *W, char *msg, size_t msg_len) {
    csc_copy c;
    NumericsMatrix *M = NULL;
    if (export_csc(W, &c, msg, msg_len)) {
        cs_dl csc = {(cs_long_t)(c.nnz > 0 ? c.nnz : 1), (cs_long_t)c.rows, (cs_long_t)c.cols,
                     c.p, c.i, c.x, -1};
        M = NM_create(NM_SPARSE_BLOCK, (int)c.rows, (int)c.cols);
        if (SBM_from_csparse(3, (const CSparseMatrix *)&csc, M->matrix1) != 0) {
            snprintf(msg, msg_len, "SBM_from_csparse refused W");
            M = NM_free(M); /* clears and releases M, returns NULL */
        }
    }
    free_csc(&c);
    return M;
}

/* M or H as Siconos's sparse matrix with its CSC storage as the origin, what its FCLIB
 * reader builds for a global problem: the global solvers factorise and multiply that. */
static NumericsMatrix *sparse_matrix(const frix_matrix *A, char *msg, size_t msg_len) {
    csc_copy c;
    NumericsMatrix *S = NULL;
    if (export_csc(A, &c, msg, msg_len)) {
        S = NM_create(NM_SPARSE, (int)c.rows, (int)c.cols);
        NumericsSparseMatrix *sp = numericsSparseMatrix(S);
        NM_csc_alloc(S, (CS_INT)(c.nnz > 0 ? c.nnz : 1));
        memcpy(sp->csc->p, c.p, sizeof(cs_long_t) * (size_t)(c.cols + 1));
        if (c.nnz > 0) {
            memcpy(sp->csc->i, c.i, sizeof(cs_long_t) * (size_t)c.nnz);
            memcpy(sp->csc->x, c.x, sizeof(double) * (size_t)c.nnz);
        }
        sp->origin = NSM_CSC;
        NSM_inc_version(sp, NSM_CSC); /* the CSC storage is the current one */
    }
    free_csc(&c);
    return S;
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

/* rolling_fc3d_driver, the same way. */
static int guarded_rolling_driver(RollingFrictionContactProblem *rfc, double *r, double *u, SolverOptions *o,
                                  int *ran) {
    *ran = 0;
    if (setjmp(*sn_get_jmp_buf()) != 0) return -1;
    int info = rolling_fc3d_driver(rfc, r, u, o);
    sn_release_jmp_buf();
    *ran = 1;
    return info;
}

/* g_rolling_fc3d_driver, the same way. */
static int guarded_global_rolling_driver(GlobalRollingFrictionContactProblem *grfc, double *r, double *u,
                                         double *v, SolverOptions *o, int *ran) {
    *ran = 0;
    if (setjmp(*sn_get_jmp_buf()) != 0) return -1;
    int info = g_rolling_fc3d_driver(grfc, r, u, v, o);
    sn_release_jmp_buf();
    *ran = 1;
    return info;
}

/* gfc3d_driver, the same way. */
static int guarded_global_driver(GlobalFrictionContactProblem *gfc, double *r, double *u,
                                 double *v, SolverOptions *o, int *ran) {
    *ran = 0;
    if (setjmp(*sn_get_jmp_buf()) != 0) return -1;
    int info = gfc3d_driver(gfc, r, u, v, o);
    sn_release_jmp_buf();
    *ran = 1;
    return info;
}

static double norm2(const double *x, int64_t n) {
    double s = 0.0;
    for (int64_t k = 0; k < n; ++k) s += x[k] * x[k];
    return sqrt(s);
}

/* Siconos's global problem from frix's: copies of M, H, f (its q), w (its b) and mu, which
 * globalFrictionContact_free releases. NULL with msg set if a matrix is refused. */
static GlobalFrictionContactProblem *global_problem(const frix_problem *problem, char *msg,
                                                    size_t msg_len) {
    const int64_t nc = frix_problem_contacts(problem), m = 3 * nc, n = frix_problem_dofs(problem);
    NumericsMatrix *M = sparse_matrix(frix_problem_M(problem), msg, msg_len);
    NumericsMatrix *H = M ? sparse_matrix(frix_problem_H(problem), msg, msg_len) : NULL;
    if (!H) {
        if (M) NM_free(M);
        return NULL;
    }
    GlobalFrictionContactProblem *gfc = globalFrictionContactProblem_new();
    gfc->dimension = 3;
    gfc->numberOfContacts = (int)nc;
    gfc->M = M;
    gfc->H = H;
    gfc->q = copy_of(frix_problem_f(problem), n);
    gfc->b = copy_of(frix_problem_w(problem), m);
    gfc->mu = copy_of(frix_problem_mu(problem), nc);
    gfc->norm_q = norm2(gfc->q, n);
    gfc->norm_b = norm2(gfc->b, m);
    gfc->env = NULL;
    return gfc;
}

/* Siconos's global rolling problem from frix's, as global_problem builds the other: copies of
 * M, H, f, w, mu and mu_r, which globalRollingFrictionContactProblem_free releases. */
static GlobalRollingFrictionContactProblem *global_rolling_problem(const frix_problem *problem, char *msg,
                                                                   size_t msg_len) {
    const int64_t nc = frix_problem_contacts(problem), m = 5 * nc, n = frix_problem_dofs(problem);
    NumericsMatrix *M = sparse_matrix(frix_problem_M(problem), msg, msg_len);
    NumericsMatrix *H = M ? sparse_matrix(frix_problem_H(problem), msg, msg_len) : NULL;
    if (!H) {
        if (M) NM_free(M);
        return NULL;
    }
    GlobalRollingFrictionContactProblem *grfc = globalRollingFrictionContactProblem_new();
    grfc->dimension = 5;
    grfc->numberOfContacts = (int)nc;
    grfc->M = M;
    grfc->H = H;
    grfc->q = copy_of(frix_problem_f(problem), n);
    grfc->b = copy_of(frix_problem_w(problem), m);
    grfc->mu = copy_of(frix_problem_mu(problem), nc);
    grfc->mu_r = copy_of(frix_problem_mu_r(problem), nc);
    return grfc;
}

/* frix's measures of an answer: the relative and the default (scaled) errors of (r, u = W r +
 * q or H^T v + w), u written, and for a global problem the equilibrium residual of (r, v).
 * NaN where frix cannot measure it (r or v not finite). */
static void measure_answer(const frix_problem *problem, const double *r, const double *v,
                           double *u, frix_siconos_result *res) {
    frix_info *info = NULL;
    if (frix_info_create(&info) != FRIX_OK) return;
    if (frix_problem_measure(problem, r, v, u, info) == FRIX_OK) {
        if (frix_info_get_double(info, FRIX_INFO_ERROR_RELATIVE, &res->error) != FRIX_OK)
            res->error = NAN;
        if (frix_info_get_double(info, FRIX_INFO_ERROR_SCALED, &res->error_scaled) != FRIX_OK)
            res->error_scaled = NAN;
        if (v && frix_info_get_double(info, FRIX_INFO_EQUILIBRIUM, &res->equilibrium) != FRIX_OK)
            res->equilibrium = NAN;
    }
    frix_info_free(info);
}

int frix_siconos_solve(const frix_problem *problem, int solver_id, double tolerance,
                       int64_t max_iter, double *r, double *u, double *v,
                       frix_siconos_trace_fn trace, void *trace_data, frix_siconos_result *res) {
    memset(res, 0, sizeof *res);
    res->siconos_error = NAN;
    res->error = NAN;
    res->error_scaled = NAN;
    res->equilibrium = NAN;
    res->time = NAN;
    const int global_solver = frix_siconos_solver_is_global(solver_id);
    if (global_solver < 0) {
        snprintf(res->message, sizeof res->message, "unknown Siconos solver id %d", solver_id);
        return -1;
    }
    const frix_problem_kind kind = frix_problem_get_kind(problem);
    const int global = kind == FRIX_PROBLEM_GLOBAL || kind == FRIX_PROBLEM_ROLLING_GLOBAL;
    const int rolling = kind == FRIX_PROBLEM_ROLLING_LOCAL || kind == FRIX_PROBLEM_ROLLING_GLOBAL;
    const int rolling_solver = frix_siconos_solver_is_rolling(solver_id);
    /* Siconos's rolling problems have five entries a contact: it has no spinning friction. */
    if (frix_problem_mu_s(problem) != NULL) {
        res->refused_kind = 1;
        snprintf(res->message, sizeof res->message,
                 "the problem has spinning friction (six entries a contact), which Siconos has no problem "
                 "for: %s cannot solve it (frix's rolling solvers do)",
                 frix_siconos_solver_name(solver_id));
        return -1;
    }
    /* The rolling drivers take rolling problems, and nothing else does. */
    if (rolling != rolling_solver) {
        res->refused_kind = 1;
        snprintf(res->message, sizeof res->message,
                 rolling ? "%s is not a rolling-friction solver: use RFC3D_NSGS or RFC3D_ADMM (local form) or "
                           "GRFC3D_NSGS_WR (global form)"
                         : "%s solves rolling-friction problems only",
                 frix_siconos_solver_name(solver_id));
        return -1;
    }
    /* Each driver takes one form: fc3d_driver and rolling_fc3d_driver a W, gfc3d_driver and
     * g_rolling_fc3d_driver an M and an H. */
    if (global != global_solver) {
        res->refused_kind = 1;
        snprintf(res->message, sizeof res->message,
                 global ? "%s is a local solver (u = W r + q) and the problem is global: use a "
                          "global one (see --list)"
                        : "%s is a global solver (M v = H r + f) and the problem is local: use a "
                          "local one (see --list)",
                 frix_siconos_solver_name(solver_id));
        return -1;
    }
    const int64_t nc = frix_problem_contacts(problem), m = frix_problem_contact_dofs(problem);
    const int64_t n = global ? frix_problem_dofs(problem) : 0;
    if (global && !v) {
        snprintf(res->message, sizeof res->message, "a global problem needs v");
        return -1;
    }
    if (m > INT_MAX || n > INT_MAX) {
        snprintf(res->message, sizeof res->message, "too large for Siconos's int sizes");
        return -1;
    }

    if (nc == 0) { /* nothing to solve; Siconos's structures do not expect it */
        res->ran = 1;
        res->error = res->error_scaled = res->siconos_error = res->time = 0;
        if (global) { /* v = M^-1 f, a linear solve that frix does: no contact problem here */
            if (frix_solve(problem, NULL, r, u, v, NULL) != FRIX_OK) {
                res->ran = 0;
                snprintf(res->message, sizeof res->message, "v = M^-1 f: %s",
                         frix_last_error_message());
                return -1;
            }
            measure_answer(problem, r, v, u, res);
        }
        return 0;
    }

    numerics_set_verbose(0);
    FrictionContactProblem *fc = NULL;
    GlobalFrictionContactProblem *gfc = NULL;
    RollingFrictionContactProblem *rfc = NULL;
    GlobalRollingFrictionContactProblem *grfc = NULL;
    if (global && rolling) {
        grfc = global_rolling_problem(problem, res->message, sizeof res->message);
        if (!grfc) return -1;
    } else if (global) {
        gfc = global_problem(problem, res->message, sizeof res->message);
        if (!gfc) return -1;
    } else if (rolling) {
        /* W as Siconos's sparse (CSC) matrix: its rolling NSGS asserts on a sparse-block one
         * (NM_extract_diag_block5: "has to be checked carefully"); CSC ran as fast as dense on
         * the piles of notes/2026-11-28-rolling.md (the one-contact iterations dominate). */
        NumericsMatrix *W = sparse_matrix(frix_problem_W(problem), res->message, sizeof res->message);
        if (!W) return -1;
        rfc = rollingFrictionContactProblem_new_with_data(5, (int)nc, W, copy_of(frix_problem_q(problem), m),
                                                          copy_of(frix_problem_mu(problem), nc),
                                                          copy_of(frix_problem_mu_r(problem), nc));
    } else {
        NumericsMatrix *W = block_matrix(frix_problem_W(problem), res->message,
                                         sizeof res->message);
        if (!W) return -1;
        /* Copies: the problem frees them, and PROX modifies W and q in place. */
        fc = frictionContactProblem_new_with_data(3, (int)nc, W,
                                                  copy_of(frix_problem_q(problem), m),
                                                  copy_of(frix_problem_mu(problem), nc));
    }
    SolverOptions *opts = solver_options_create(solver_id);
    if (!opts) {
        snprintf(res->message, sizeof res->message, "Siconos has no options for solver id %d",
                 solver_id);
        if (gfc) globalFrictionContact_free(gfc);
        if (fc) frictionContactProblem_free(fc);
        if (rfc) rollingFrictionContactProblem_free(rfc);
        if (grfc) globalRollingFrictionContactProblem_free(grfc);
        return -1;
    }
    opts->dparam[SICONOS_DPARAM_TOL] = tolerance;
    /* GFC3D_IPM solves by default the convex relaxation (u_N without the De Saxce term
     * mu |u_T|), whose solution is not the Coulomb one that frix measures; told to update
     * that term, as GFC3D_ADMM does by default, it solves the problem the others solve. */
    if (solver_id == SICONOS_GLOBAL_FRICTION_3D_IPM)
        opts->iparam[SICONOS_FRICTION_3D_ADMM_IPARAM_UPDATE_S] =
            SICONOS_FRICTION_3D_ADMM_UPDATE_S_YES;
    if (max_iter > 0) opts->iparam[SICONOS_IPARAM_MAX_ITER] = max_iter > INT_MAX ? INT_MAX : (int)max_iter;

    /* The callback only when a trace is asked for: Siconos does extra work per iteration for
     * it, which a timing-only solve must not pay. */
    trace_env env = {{0, 0}, trace, trace_data, 0, global ? NULL : problem, 0.0};
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
    int info = grfc      ? guarded_global_rolling_driver(grfc, r, u, v, opts, &ran)
               : global  ? guarded_global_driver(gfc, r, u, v, opts, &ran)
               : rolling ? guarded_rolling_driver(rfc, r, u, opts, &ran)
                         : guarded_driver(fc, r, u, opts, &ran);
    res->time = seconds_since(&start) - env.measuring;

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
    if (gfc) {
        /* globalFrictionContact_free asserts that env is empty (Debian's Siconos keeps its
         * asserts); ours is, so whatever a solver left there leaks instead of aborting. */
        gfc->env = NULL;
        globalFrictionContact_free(gfc);
    } else if (rfc) {
        rollingFrictionContactProblem_free(rfc);
    } else if (grfc) {
        globalRollingFrictionContactProblem_free(grfc);
    } else {
        frictionContactProblem_free(fc);
    }

    /* One measure for both: frix's, of the r (and v) Siconos returned; u recomputed as
     * W r + q, or H^T v + w. */
    if (ran) measure_answer(problem, r, global ? v : NULL, u, res);
    return ran ? 0 : -1;
}
