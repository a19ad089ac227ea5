/* frix — the entry point for hosts that load libfrix at run time (dlopen) rather than link it.
 *
 * A host looks up one symbol, frix_plugin_api, and calls it with the table ABI version it was
 * compiled against (FRIX_PLUGIN_ABI_VERSION). It gets a constant table of function pointers
 * to the C API, or NULL if the loaded library cannot serve that version (an older library
 * asked for a newer version):
 *
 *   void *lib = dlopen("libfrix.so.0", RTLD_NOW | RTLD_LOCAL);
 *   frix_plugin_api_fn entry = (frix_plugin_api_fn)dlsym(lib, "frix_plugin_api");
 *   const frix_plugin_table *frix = entry ? entry(FRIX_PLUGIN_ABI_VERSION) : NULL;
 *   if (frix && FRIX_PLUGIN_HAS(frix, solve)) frix->solve(...);
 *
 * The contract (docs/abi.md): within one table ABI version, members are only ever appended,
 * never removed, reordered or retyped, so a host built against an older header reads the
 * members it knows from a newer library. A host built against a newer header checks with
 * FRIX_PLUGIN_HAS before using a member the loaded library may not have. The table is
 * static and constant: valid while the library stays loaded, safe to share between threads.
 * Everything a member returns or takes follows the plain C API of the same name (frix_solve
 * for solve, and so on); handles of the table and of the linked API are the same objects.
 * This header needs no libfrix at link time: a host includes it for the types only.
 */
#ifndef FRIX_PLUGIN_H
#define FRIX_PLUGIN_H

#include <stddef.h>
#include <stdint.h>
#include "frix_export.h"
#include <frix/frix_version.h> /* generated at configure time */
#include "frix_errors.h"
#include "frix_matrix.h"
#include "frix_problem.h"
#include "frix_options.h"
#include "frix_solve.h"
#include "frix_persistent.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The table layout this header describes. A new version is a longer table: the members of
 * the versions before it, in the same places, and a new group after them. The library serves
 * every version it has had (version 1: up to info_stage_note; version 2: the persistent
 * solver too; version 3: its set_contacts; version 4: options' choices by name; version 5:
 * rolling friction, the problems' texts and compressed files; version 6: spinning friction),
 * each with its
 * own size and abi_version, so a host asks for the version its header has and gets nothing it
 * does not know. */
#define FRIX_PLUGIN_ABI_VERSION 6

/* Non-zero if the loaded table has `member` (a table from an older library may end
 * before it). */
#define FRIX_PLUGIN_HAS(table, member)                                                   \
    ((table) != NULL && (table)->size >= offsetof(frix_plugin_table, member) + sizeof((table)->member))

typedef struct frix_plugin_table {
    /* ---- Header, identical in every table version. */
    size_t size;          /* sizeof the table in the loaded library */
    int abi_version;      /* the version of this table: the one requested */
    int version_number;   /* the loaded library's FRIX_VERSION_NUMBER (MMmmpp) */
    const char *(*version_string)(void);

    /* ---- Errors (frix_errors.h). */
    const char *(*error_string)(frix_error code);
    const char *(*status_string)(frix_status status);
    const char *(*last_error_message)(void);

    /* ---- Matrices (frix_matrix.h). */
    frix_error (*matrix_from_csc)(int64_t nrows, int64_t ncols, const int64_t *colptr,
                                  const int64_t *rowind, const double *values, frix_matrix **out);
    frix_error (*matrix_from_csr)(int64_t nrows, int64_t ncols, const int64_t *rowptr,
                                  const int64_t *colind, const double *values, frix_matrix **out);
    frix_error (*matrix_from_triplets)(int64_t nrows, int64_t ncols, int64_t nnz,
                                       const int64_t *rows, const int64_t *cols,
                                       const double *values, frix_matrix **out);
    frix_error (*matrix_from_dense)(int64_t nrows, int64_t ncols, const double *values,
                                    int64_t ld, frix_matrix **out);
    frix_error (*matrix_from_blocks)(int64_t nblock_rows, int64_t nblock_cols, int64_t nblocks,
                                     const int64_t *block_rows, const int64_t *block_cols,
                                     const double *values, frix_matrix **out);
    void (*matrix_free)(frix_matrix *m);
    int64_t (*matrix_rows)(const frix_matrix *m);
    int64_t (*matrix_cols)(const frix_matrix *m);
    int64_t (*matrix_nnz)(const frix_matrix *m);
    frix_error (*matrix_gemv)(const frix_matrix *m, double alpha, const double *x, double beta,
                              double *y);
    frix_error (*matrix_gemv_transposed)(const frix_matrix *m, double alpha, const double *x,
                                         double beta, double *y);
    frix_error (*matrix_to_csc)(const frix_matrix *m, int64_t *nnz, int64_t *colptr,
                                int64_t *rowind, double *values);
    int64_t (*matrix_block_count)(const frix_matrix *m);
    int (*matrix_is_block)(const frix_matrix *m);
    frix_error (*matrix_diagonal_block)(const frix_matrix *m, int64_t k, double *out);

    /* ---- Problems (frix_problem.h). */
    frix_error (*problem_local)(const frix_matrix *W, const double *q, const double *mu,
                                int64_t nc, frix_problem **out);
    frix_error (*problem_global)(const frix_matrix *M, const frix_matrix *H, const double *f,
                                 const double *w, const double *mu, int64_t nc,
                                 frix_problem **out);
    void (*problem_free)(frix_problem *p);
    frix_problem_kind (*problem_get_kind)(const frix_problem *p);
    int64_t (*problem_contacts)(const frix_problem *p);
    int64_t (*problem_contact_dofs)(const frix_problem *p);
    int64_t (*problem_dofs)(const frix_problem *p);
    frix_error (*problem_set_title)(frix_problem *p, const char *title);
    const char *(*problem_title)(const frix_problem *p);
    const frix_matrix *(*problem_W)(const frix_problem *p);
    const frix_matrix *(*problem_M)(const frix_problem *p);
    const frix_matrix *(*problem_H)(const frix_problem *p);
    const double *(*problem_q)(const frix_problem *p);
    const double *(*problem_f)(const frix_problem *p);
    const double *(*problem_w)(const frix_problem *p);
    const double *(*problem_mu)(const frix_problem *p);

    /* ---- Options (frix_options.h). */
    frix_error (*options_create)(int solver_id, frix_options **out);
    frix_error (*options_copy)(const frix_options *src, frix_options **out);
    void (*options_free)(frix_options *opts);
    int (*options_solver)(const frix_options *opts);
    frix_error (*options_set_int)(frix_options *opts, frix_option_key key, int64_t value);
    frix_error (*options_set_double)(frix_options *opts, frix_option_key key, double value);
    frix_error (*options_get_int)(const frix_options *opts, frix_option_key key, int64_t *value);
    frix_error (*options_get_double)(const frix_options *opts, frix_option_key key,
                                     double *value);
    frix_error (*options_bounds)(const frix_options *opts, frix_option_key key, double *lower,
                                 double *upper, int *is_int);
    const char *(*option_name)(frix_option_key key);
    frix_error (*option_by_name)(const char *name, frix_option_key *key);
    frix_error (*options_set_callback)(frix_options *opts, frix_progress_fn fn, void *user_data);

    /* ---- Solver registry (frix_solve.h). */
    int64_t (*solver_count)(void);
    int (*solver_id_at)(int64_t index);
    const char *(*solver_name)(int solver_id);
    const char *(*solver_describe)(int solver_id);
    frix_error (*solver_by_name)(const char *name, int *solver_id);

    /* ---- Results and solving (frix_solve.h). */
    frix_error (*info_create)(frix_info **out);
    void (*info_free)(frix_info *info);
    frix_error (*info_get_int)(const frix_info *info, frix_info_key key, int64_t *value);
    frix_error (*info_get_double)(const frix_info *info, frix_info_key key, double *value);
    frix_status (*info_status)(const frix_info *info);
    int64_t (*info_iterations)(const frix_info *info);
    double (*info_error)(const frix_info *info);
    double (*info_solve_time)(const frix_info *info);
    frix_error (*solve)(const frix_problem *problem, const frix_options *options, double *r,
                        double *u, double *v, frix_info *info);
    frix_error (*problem_measure)(const frix_problem *problem, const double *r, const double *v,
                                  double *u, frix_info *info);
    frix_error (*problem_error)(const frix_problem *problem, const double *r, const double *v,
                                double *error);

    /* ---- Files (frix_read.h, frix_fclib.h). */
    frix_error (*read_problem)(const char *path, frix_problem **out);
    frix_error (*fclib_read)(const char *path, frix_problem **out);
    frix_error (*fclib_read_solution)(const char *path, const frix_problem *problem, double *r,
                                      double *u, double *v);
    frix_error (*fclib_write)(const char *path, const frix_problem *problem, const double *sol_r,
                              const double *sol_u, const double *sol_v, int64_t n_guesses,
                              const double *guess_r, const double *guess_u,
                              const double *guess_v);
    frix_error (*dat_read)(const char *path, frix_problem **out);
    frix_error (*fclib_guess_count)(const char *path, int64_t *count);
    frix_error (*fclib_read_guess)(const char *path, const frix_problem *problem, int64_t index,
                                   double *r, double *u, double *v);

    /* ---- Appended in frix 0.1 after the first table: the default solver's trace and the
     * existence check (frix_solve.h). Check with FRIX_PLUGIN_HAS before use. */
    const char *(*info_trace)(const frix_info *info);
    frix_error (*problem_check_existence)(const frix_problem *problem, double time_limit,
                                          frix_info *info);
    const char *(*existence_describe)(frix_existence verdict);

    /* ---- Appended in frix 0.1: the log sink (frix_options.h). Check with FRIX_PLUGIN_HAS. */
    frix_error (*options_set_log)(frix_options *opts, frix_log_fn fn, void *user_data);
    /* ---- Appended in frix 0.1: the stage records (frix_info.h). */
    int64_t (*info_stage_count)(const frix_info *info);
    frix_error (*info_stage_get_int)(const frix_info *info, int64_t index, frix_stage_key key,
                                     int64_t *value);
    frix_error (*info_stage_get_double)(const frix_info *info, int64_t index, frix_stage_key key,
                                        double *value);
    const char *(*info_stage_note)(const frix_info *info, int64_t index);

    /* ---- Table version 2: the persistent solver (frix_persistent.h). */
    frix_error (*persistent_create)(const frix_problem *problem, const frix_options *options,
                                    frix_persistent **out);
    void (*persistent_free)(frix_persistent *ps);
    frix_error (*persistent_solve)(frix_persistent *ps, double *r, double *u, double *v,
                                   frix_info *info);
    frix_error (*persistent_update_local)(frix_persistent *ps, const frix_matrix *W,
                                          const double *q, const double *mu);
    frix_error (*persistent_update_global)(frix_persistent *ps, const frix_matrix *M,
                                           const frix_matrix *H, const double *f,
                                           const double *w, const double *mu);

    /* ---- Table version 3: contacts that come and go (frix_persistent.h). */
    frix_error (*persistent_set_contacts_local)(frix_persistent *ps, const frix_matrix *W,
                                                const double *q, const double *mu, int64_t nc);
    frix_error (*persistent_set_contacts_global)(frix_persistent *ps, const frix_matrix *H,
                                                 const double *w, const double *mu, int64_t nc);

    /* ---- Table version 4: options' choices by name (frix_options.h). */
    const char *(*option_choice_name)(frix_option_key key, int64_t value);
    frix_error (*option_choice_by_name)(frix_option_key key, const char *name, int64_t *value);
    frix_error (*options_set_by_name)(frix_options *opts, const char *key, const char *text);

    /* ---- Table version 5: rolling friction and the problems' texts (frix_problem.h),
     * compressed FCLIB files (frix_fclib.h), rolling problems in the persistent solver
     * (frix_persistent.h). */
    frix_error (*problem_rolling_local)(const frix_matrix *W, const double *q, const double *mu,
                                        const double *mu_r, int64_t nc, frix_problem **out);
    frix_error (*problem_rolling_global)(const frix_matrix *M, const frix_matrix *H, const double *f,
                                         const double *w, const double *mu, const double *mu_r,
                                         int64_t nc, frix_problem **out);
    const double *(*problem_mu_r)(const frix_problem *p);
    frix_error (*problem_set_description)(frix_problem *p, const char *description);
    const char *(*problem_description)(const frix_problem *p);
    frix_error (*problem_set_math_info)(frix_problem *p, const char *math_info);
    const char *(*problem_math_info)(const frix_problem *p);
    frix_error (*fclib_write_compressed)(const char *path, const frix_problem *problem,
                                         const double *sol_r, const double *sol_u,
                                         const double *sol_v, int64_t n_guesses,
                                         const double *guess_r, const double *guess_u,
                                         const double *guess_v, int level);
    frix_error (*persistent_set_contacts_rolling_local)(frix_persistent *ps, const frix_matrix *W,
                                                        const double *q, const double *mu,
                                                        const double *mu_r, int64_t nc);
    frix_error (*persistent_set_contacts_rolling_global)(frix_persistent *ps, const frix_matrix *H,
                                                         const double *w, const double *mu,
                                                         const double *mu_r, int64_t nc);
    frix_error (*persistent_update_mu_r)(frix_persistent *ps, const double *mu_r);

    /* ---- Table version 6: spinning friction (frix_problem.h, frix_persistent.h). */
    frix_error (*problem_spinning_local)(const frix_matrix *W, const double *q, const double *mu,
                                         const double *mu_r, const double *mu_s, int64_t nc,
                                         frix_problem **out);
    frix_error (*problem_spinning_global)(const frix_matrix *M, const frix_matrix *H, const double *f,
                                          const double *w, const double *mu, const double *mu_r,
                                          const double *mu_s, int64_t nc, frix_problem **out);
    const double *(*problem_mu_s)(const frix_problem *p);
    frix_error (*persistent_set_contacts_spinning_local)(frix_persistent *ps, const frix_matrix *W,
                                                         const double *q, const double *mu,
                                                         const double *mu_r, const double *mu_s,
                                                         int64_t nc);
    frix_error (*persistent_set_contacts_spinning_global)(frix_persistent *ps, const frix_matrix *H,
                                                          const double *w, const double *mu,
                                                          const double *mu_r, const double *mu_s,
                                                          int64_t nc);
    frix_error (*persistent_update_mu_s)(frix_persistent *ps, const double *mu_s);

    /* New members go here, at the end, and nowhere else. */
} frix_plugin_table;

/* The one entry point for dlopen hosts: the table of version `requested_abi_version`, or
 * NULL (with frix_last_error_message set) if this library does not serve that version. */
FRIX_API const frix_plugin_table *frix_plugin_api(int requested_abi_version);

/* The type to cast dlsym(lib, "frix_plugin_api") to. */
typedef const frix_plugin_table *(*frix_plugin_api_fn)(int requested_abi_version);

#ifdef __cplusplus
}
#endif

#endif /* FRIX_PLUGIN_H */
