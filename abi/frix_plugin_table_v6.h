/* The frozen layout of frix_plugin_table, table ABI version 6 (version 5 and spinning
 * friction: its problems and the persistent solver's calls for them), as first released.
 * NEVER EDIT: tests/abi_table.c checks that every member listed here keeps its offset and its
 * type in include/frix/frix_plugin.h, as it does for versions 1 to 5
 * (abi/frix_plugin_table_v1.h to _v5.h). A new table ABI version gets a new frozen file. */
#ifndef FRIX_PLUGIN_TABLE_V6_H
#define FRIX_PLUGIN_TABLE_V6_H

#include <frix/frix.h>

typedef struct frix_plugin_table_v6 {
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
} frix_plugin_table_v6;

#define FRIX_PLUGIN_TABLE_V6_MEMBERS(X) \
    X(size) \
    X(abi_version) \
    X(version_number) \
    X(version_string) \
    X(error_string) \
    X(status_string) \
    X(last_error_message) \
    X(matrix_from_csc) \
    X(matrix_from_csr) \
    X(matrix_from_triplets) \
    X(matrix_from_dense) \
    X(matrix_from_blocks) \
    X(matrix_free) \
    X(matrix_rows) \
    X(matrix_cols) \
    X(matrix_nnz) \
    X(matrix_gemv) \
    X(matrix_gemv_transposed) \
    X(matrix_to_csc) \
    X(matrix_block_count) \
    X(matrix_is_block) \
    X(matrix_diagonal_block) \
    X(problem_local) \
    X(problem_global) \
    X(problem_free) \
    X(problem_get_kind) \
    X(problem_contacts) \
    X(problem_contact_dofs) \
    X(problem_dofs) \
    X(problem_set_title) \
    X(problem_title) \
    X(problem_W) \
    X(problem_M) \
    X(problem_H) \
    X(problem_q) \
    X(problem_f) \
    X(problem_w) \
    X(problem_mu) \
    X(options_create) \
    X(options_copy) \
    X(options_free) \
    X(options_solver) \
    X(options_set_int) \
    X(options_set_double) \
    X(options_get_int) \
    X(options_get_double) \
    X(options_bounds) \
    X(option_name) \
    X(option_by_name) \
    X(options_set_callback) \
    X(solver_count) \
    X(solver_id_at) \
    X(solver_name) \
    X(solver_describe) \
    X(solver_by_name) \
    X(info_create) \
    X(info_free) \
    X(info_get_int) \
    X(info_get_double) \
    X(info_status) \
    X(info_iterations) \
    X(info_error) \
    X(info_solve_time) \
    X(solve) \
    X(problem_measure) \
    X(problem_error) \
    X(read_problem) \
    X(fclib_read) \
    X(fclib_read_solution) \
    X(fclib_write) \
    X(dat_read) \
    X(fclib_guess_count) \
    X(fclib_read_guess) \
    X(info_trace) \
    X(problem_check_existence) \
    X(existence_describe) \
    X(options_set_log) \
    X(info_stage_count) \
    X(info_stage_get_int) \
    X(info_stage_get_double) \
    X(info_stage_note) \
    X(persistent_create) \
    X(persistent_free) \
    X(persistent_solve) \
    X(persistent_update_local) \
    X(persistent_update_global) \
    X(persistent_set_contacts_local) \
    X(persistent_set_contacts_global) \
    X(option_choice_name) \
    X(option_choice_by_name) \
    X(options_set_by_name) \
    X(problem_rolling_local) \
    X(problem_rolling_global) \
    X(problem_mu_r) \
    X(problem_set_description) \
    X(problem_description) \
    X(problem_set_math_info) \
    X(problem_math_info) \
    X(fclib_write_compressed) \
    X(persistent_set_contacts_rolling_local) \
    X(persistent_set_contacts_rolling_global) \
    X(persistent_update_mu_r) \
    X(problem_spinning_local) \
    X(problem_spinning_global) \
    X(problem_mu_s) \
    X(persistent_set_contacts_spinning_local) \
    X(persistent_set_contacts_spinning_global) \
    X(persistent_update_mu_s)

#endif /* FRIX_PLUGIN_TABLE_V6_H */
