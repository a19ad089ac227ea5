/* Internal hooks that let the C tests reach kernels behind the public API. They are
 * defined in testing_hooks.cpp beside this file, which is built into the tests alone and
 * linked with the library's objects: libfrix.a and libfrix.so do not carry them. Not an API:
 * they change with the internals. */
#ifndef FRIX_TESTING_H
#define FRIX_TESTING_H

#include <stdint.h>

#include <frix/frix.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ---- One-contact kernels (solvers/kit/local3x3.hpp). Vectors normal first, W column-major. */

/* Outcomes of frix_testing_solve_contact (the values of frix::local::Outcome). */
enum {
    FRIX_TESTING_TAKE_OFF = 1,
    FRIX_TESTING_STICK = 2,
    FRIX_TESTING_SLIDE = 3,
    FRIX_TESTING_ITERATED = 4,
    FRIX_TESTING_NOT_CONVERGED = 5,
    FRIX_TESTING_NO_SOLUTION = 6,
    FRIX_TESTING_STEP = 7,
    FRIX_TESTING_NEWTON = 8
};

void frix_testing_project_on_cone(double r[3], double mu);
void frix_testing_project_on_disk(double r[3], double radius);
/* r <- its projection on the rolling cone of `size` entries (5, or 6 with spinning friction:
 * src/rolling.hpp); returns the case (0: r = 0; else 1 + the parts cut back: 1 friction,
 * 2 rolling, 4 spinning). */
int frix_testing_project_on_rolling_cone(double *r, double mu, double mu_r, double mu_s, int size);

/* One contact: r is the warm start in, the result out; local_solver is one of the
 * FRIX_LOCAL_* values of the option local_solver (frix_options.h). Returns an outcome. */
int frix_testing_solve_contact(const double W[9], const double q[3], double mu, double r[3],
                               int local_solver, double tol, int max_iter);

/* The sliding root alone: 1 and r set if a valid sliding solution was found. */
int frix_testing_solve_slide(const double W[9], const double q[3], double mu,
                             const double hint[3], double r[3]);

/* |r - P_K(r - u^)| with u = W r + q; *relative (may be NULL) gets it / max(|q|,|r|,|u|). */
double frix_testing_contact_residual(const double W[9], const double q[3], double mu,
                                     const double r[3], double *relative);

/* ---- A stage of auto (solvers/auto/stage.hpp) from a warm start whose measures its part holds. */
/* nsgs or nsgs-v (solver_id) on the local problem p from the warm start r (result out), as auto
 * runs a part's stage to tolerance 1e-8 where the part's u holds W r + q: handed the start's
 * measures (SolveContext::measured_start), their errors multiplied by `claim` (1: as they are),
 * instead of measuring the start itself. *sweeps and *error: the stage's. A frix_error value. */
int frix_testing_stage_from_measured_start(const frix_problem *p, int solver_id, double claim, double *r,
                                           int64_t *sweeps, double *error);
/* auto's watch over a Newton polish (Watch::Newton, `patience` slow steps) fed `count` reports
 * (errors[k], measured[k] != 0) at iterations 1, 2, ...: the index of the report it stopped
 * the stage at, -1 where it let it run, -2 where its options could not be made. */
int frix_testing_newton_watch(const double *errors, const int *measured, int count, int64_t patience);

/* ---- Semismooth reformulations of one contact (solvers/kit/nsn_functions.hpp): Phi(r, u) and
 * the blocks A = dPhi/dr, B = dPhi/du (column-major; may be NULL). formulation: 0
 * Alart-Curnier, 1 Fischer-Burmeister, 2 natural map. */
void frix_testing_contact_function(int formulation, const double r[3], const double u[3],
                                   double mu, double rho_n, double rho_t, double phi[3],
                                   double A[9], double B[9]);

/* ---- The rolling one-contact kernels (solvers/kit/local_rolling.hpp): size entries a contact
 * (5, or 6 with spinning friction), W size x size column-major. */

/* Outcomes of frix_testing_rolling_solve_contact (the values of frix::local_rolling::Outcome). */
enum {
    FRIX_TESTING_ROLLING_TAKE_OFF = 1,
    FRIX_TESTING_ROLLING_STICK = 2,
    FRIX_TESTING_ROLLING_NEWTON = 3,
    FRIX_TESTING_ROLLING_ITERATED = 4,
    FRIX_TESTING_ROLLING_NOT_CONVERGED = 5,
    FRIX_TESTING_ROLLING_NO_SOLUTION = 6
};

/* One contact: r is the warm start in, the result out. Returns an outcome. */
int frix_testing_rolling_solve_contact(int size, const double *W, const double *q, double mu, double mu_r,
                                       double mu_s, double *r, double tol, int max_iter);

/* x <- P_K(x) and D (size x size, may be NULL) its generalized Jacobian at the x given; returns
 * the projection's case (src/rolling.hpp). */
int frix_testing_rolling_projection(int size, double *x, double mu, double mu_r, double mu_s, double *D);

/* The Alart-Curnier function F(r, u) of one contact and its blocks A = dF/dr, B = dF/du (size x
 * size; may be NULL). */
void frix_testing_rolling_alart_curnier(int size, const double *r, const double *u, double mu, double mu_r,
                                        double mu_s, double rho, double *F, double *A, double *B);

/* ---- The local forms of rolling-nsgs's sweeps (solvers/kit/rolling_forms.hpp). `sweeps` plain
 * sweeps (no momentum) on the local rolling problem p from r (the result out): on W where it lies
 * (stored = 1: its 3x3 block rows, or its columns read as its rows), or on a copy of its block
 * rows (stored = 0). A frix_error value: FRIX_ERR_UNSUPPORTED where stored = 1 and W cannot be
 * read so (stored by columns, not symmetric to round-off). */
int frix_testing_rolling_local_sweeps(const frix_problem *p, int stored, int sweeps, double *r);

/* ---- The loads a factorised M was solved for (src/load_span.hpp). The k loads F (n x k,
 * column-major) come in order, as a host's steps: each is asked for from the span of those
 * before it (LoadSpan::answer; from_span[i] = 1 where answered), else its answer is X's column
 * i and it joins the span (LoadSpan::add). answers (n x k): what each got. M is n x n, CSC. */
void frix_testing_load_span(int64_t n, const int64_t *colptr, const int64_t *rowind, const double *values, int k,
                            const double *F, const double *X, double *answers, int *from_span);

/* M's load solves (MassSolver::solve_load, keeping loads): M factorised, x0 = M^-1 f, then M
 * replaced by M2 (same size) and factorised, x1 = M2^-1 (s f). A frix_error value. */
int frix_testing_mass_loads(const frix_matrix *M, const frix_matrix *M2, const double *f, double s, double *x0,
                            double *x1);

/* ---- Linear algebra back-end (src/linalg). Return a frix_error value. */
/* Analyses once, factorises A then 2A, solves (2A) x = b; counters out. */
int frix_testing_sparse_lu(int64_t n, const int64_t *colptr, const int64_t *rowind,
                           const double *values, const double *b, double *x, int64_t *symbolic,
                           int64_t *numeric);
/* SparseLU with set_strategy_by_pivoting(1, excess) (nested dissection): analysed and
 * factorised with `first`, then factorised twice with `later` (same pattern), then
 * x = A^-1 b. *symbolic: the analyses; flops[3]: each factorisation's flops. */
int frix_testing_lu_strategy(int64_t n, const int64_t *colptr, const int64_t *rowind, const double *first,
                             const double *later, double excess, const double *b, double *x, int64_t *symbolic,
                             double *flops);
/* Cholesky of A (upper triangle read): x = A^-1 b and, if k > 0, C = B^T A^-1 B (k x k dense,
 * column-major) for the n x k CSC matrix B. */
int frix_testing_sparse_cholesky(int64_t n, const int64_t *colptr, const int64_t *rowind,
                                 const double *values, const double *b, double *x, int64_t k,
                                 const int64_t *bp, const int64_t *bi, const double *bx,
                                 double *C);
/* The same solve with the layout for repeated solves (for_solves = 1) or the supernodal one
 * (0); *supernodal: whether the factor was supernodal. */
int frix_testing_sparse_cholesky_layout(int for_solves, int64_t n, const int64_t *colptr, const int64_t *rowind,
                                        const double *values, const double *b, double *x, int *supernodal);
/* A supernodal Cholesky of A (upper triangle read) and its single-precision copy: x_single
 * through the copy and x_double = A^-1 b; refuse: the copy's budget refuses it. *kept: whether
 * the copy was kept; *dropped: whether a second factorisation of A dropped it. */
int frix_testing_single_cholesky(int64_t n, const int64_t *colptr, const int64_t *rowind, const double *values,
                                 const double *b, int refuse, double *x_single, double *x_double, int *kept,
                                 int *dropped);
/* x = (s M + s rho H H^T)^-1 (s b) (s = scale) by solve_near from x's value on entry, `solves`
 * times, the single-precision copy kept where it can be (*kept: whether it was); *through_copy
 * and *finished_in_double: the solves through the copy and those finished in double; *in_use:
 * whether the copy is still used after them. */
int frix_testing_solve_near(const frix_matrix *M, const frix_matrix *H, double rho, double scale, const double *b,
                            double *x, int solves, int *kept, int64_t *through_copy, int64_t *finished_in_double,
                            int *in_use);
/* M + rho H H^T as the solvers without W build it, for any contact blocks (identity_blocks =
 * 0) or multiples of the identity (1), offered M's ordering: *flops of its factorisation,
 * x = (M + rho H H^T)^-1 b and *mass_ordering, whether it was analysed in M's ordering. */
int frix_testing_mass_plus_contacts(int identity_blocks, const frix_matrix *M, const frix_matrix *H, double rho,
                                    const double *b, double *x, double *flops, int *mass_ordering);
/* diag[j] = b_j^T M^-1 b_j for the columns of B as the solvers without W sample W's diagonal
 * (MassSolver::inverse_diagonal), and the same from one full solve a column (by_solves). */
int frix_testing_inverse_diagonal(const frix_matrix *M, const frix_matrix *B, double *diag, double *by_solves);
/* The flops and entries of L of a Cholesky factorisation of A's pattern (upper triangle read,
 * values not needed), from the symbolic analysis alone. */
int frix_testing_cholesky_cost(int64_t n, const int64_t *colptr, const int64_t *rowind, double *flops,
                               double *entries);
/* The same count under CHOLMOD's AMD ordering alone (no nested dissection tried). */
int frix_testing_amd_cholesky_cost(int64_t n, const int64_t *colptr, const int64_t *rowind, double *flops,
                                   double *entries);
/* The prices of factorisations of A (n x n CSC, both triangles, SPD), in flops, against what
 * they do: *cholesky_price the price a SparseCholesky asks its budget with before factorising,
 * *cholesky_cost cholesky_cost's count of A's pattern; *lu_price the price of a SparseLU with
 * a nested-dissection ordering, *lu_upper whether that is UMFPACK's upper bound, *lu_done the
 * flops UMFPACK's factorisation then did. */
int frix_testing_factor_prices(int64_t n, const int64_t *colptr, const int64_t *rowind, const double *values,
                               double *cholesky_price, double *cholesky_cost, double *lu_price, int *lu_upper,
                               double *lu_done);
/* C = B^T A^-1 B as frix_testing_sparse_cholesky, asked whether to stop about questions_asked
 * times over the work, at most every min_flops flops (0: as often as asked, at most after
 * every supernode with work); the work is told
 * to stop at the stop_at-th question (never if stop_at <= 0). *questions: how many were asked;
 * *stopped: whether the work stopped; *nnz: the entries of C returned. */
int frix_testing_congruence_questions(int64_t n, const int64_t *colptr, const int64_t *rowind,
                                      const double *values, int64_t k, const int64_t *bp,
                                      const int64_t *bi, const double *bx, double questions_asked, double min_flops,
                                      int stop_at, double *C, int *questions, int *stopped,
                                      int64_t *nnz);
/* The flops and entries of L of a Cholesky of a matrix with the 3x3 block pattern of W (n x n
 * CSC, n a multiple of 3, stored as blocks), as auto prices it. */
int frix_testing_block_cholesky_cost(int64_t n, const int64_t *colptr, const int64_t *rowind,
                                     const double *values, double *flops, double *entries);
/* W = H^T M^-1 H (M n x n symmetric positive definite, H n x k, k a multiple of 3, both CSC)
 * as the reduction of a global problem forms it, as a dense column-major D (k x k); *blocks:
 * the 3x3 blocks W stores. */
int frix_testing_reduction(int64_t n, const int64_t *mp, const int64_t *mi, const double *mx, int64_t k,
                           const int64_t *hp, const int64_t *hi, const double *hx, double *D,
                           int64_t *blocks);
/* The price of forming W = H^T M^-1 H (MassSolver::congruence_price, M n x n and H n x k as
 * CSC): its flops and writes; *blocks: the blocks of the W then formed. */
/* Monitor::affords (the frix_status it answers) on a first factorisation priced at flops
 * and writes, under a time limit of time_limit seconds. */
int frix_testing_affords(double flops, double writes, double time_limit);
int frix_testing_w_price(int64_t n, const int64_t *mp, const int64_t *mi, const double *mx, int64_t k,
                         const int64_t *hp, const int64_t *hi, const double *hx, double *flops, double *writes,
                         int64_t *blocks);
/* The n x n CSC matrix (n a multiple of 3) assembled column by column as the reduction
 * assembles W (room reserved for expected_blocks blocks), as a dense column-major D; *blocks:
 * its 3x3 blocks; *in_place: 1 when it was found symmetric to the bit (its columns' storage
 * then becomes its rows'). */
int frix_testing_matrix_from_columns(int64_t n, const int64_t *colptr, const int64_t *rowind,
                                     const double *values, double expected_blocks, double *D,
                                     int64_t *blocks, int *in_place);
/* Dense LU (cholesky = 0) or Cholesky (1): x = A^-1 b. */
int frix_testing_dense_solve(int cholesky, int64_t n, const double *A, const double *b, double *x);

/* ---- Sweeps (solvers/kit/sweeps.hpp). */
/* nsgs-v as frix_solve runs it with options o (of nsgs-v; a global p is reduced first), its
 * pushes through W's columns in single precision (single = 1) or in double (0) whatever W's
 * size: frix_solve's own choice goes by W's size (kSingleColumnsMinBytes). */
int frix_testing_nsgs_velocity(int single, const frix_problem *p, const frix_options *o, double *r, double *u,
                               double *v, frix_info *info);
/* u += W's block column a times dr through the single-precision columns (solvers/kit/
 * single_columns.hpp) of W, which must store every block; read from W's rows where symmetric
 * = 1 (W then symmetric to the bit). FRIX_ERR_INVALID_ARGUMENT where W does not suit. */
int frix_testing_single_push(const frix_matrix *W, int symmetric, int64_t a, const double dr[3], double *u);
/* The large arrays' helpers (src/memory.hpp) on a vector of doubles: assign_advised to each of
 * the `count` sizes in turn, each filled with its index in `sizes` plus 1, then copy_advised
 * of `count` values; returns 0 where every content was right and a shrinking assign kept the
 * storage, else the 1-based step that failed. */
int frix_testing_advised_arrays(const int64_t *sizes, int count, const double *values);
/* The existence check's test of W's symmetric part (src/existence.hpp) on a local problem:
 * 0 positive semidefinite within `tolerance`, 1 not, 2 undecided (too costly to factorise). */
int frix_testing_symmetric_part_psd(const frix_problem *p, double tolerance);
/* frix::matrix_from_csc_taking on vectors holding copies of the arrays (nnz entries); *taken
 * is set to 1 where the matrix took the vectors (left empty), 0 where they were left as given,
 * -1 otherwise. */
int frix_testing_matrix_from_csc_taking(int64_t nrows, int64_t ncols, const int64_t *colptr, const int64_t *rowind,
                                        const double *values, int64_t nnz, frix_matrix **out, int *taken);

#ifdef __cplusplus
}
#endif

#endif /* FRIX_TESTING_H */
