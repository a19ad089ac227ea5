// The frix_testing_* hooks of frix_testing.h: thin wrappers over internal kernels, built
// into the tests only (the library they link), never into libfrix.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "solvers/kit/local3x3.hpp"
#include "solvers/kit/local_rolling.hpp"
#include "solvers/kit/rolling_forms.hpp"
#include "src/coulomb.hpp"
#include "src/load_span.hpp"
#include "src/reduction.hpp"
#include "src/rolling.hpp"

#define FRIX_TESTING_HOOK extern "C"

namespace {
using frix::local::Outcome;
static_assert((int)Outcome::TakeOff == 1 && (int)Outcome::Stick == 2 && (int)Outcome::Slide == 3 &&
                  (int)Outcome::Iterated == 4 && (int)Outcome::NotConverged == 5 &&
                  (int)Outcome::NoSolution == 6 && (int)Outcome::Step == 7 &&
                  (int)Outcome::Newton == 8,
              "frix_testing.h mirrors these values");
}  // namespace

namespace {
using Rolling = frix::local_rolling::Outcome;
static_assert((int)Rolling::TakeOff == 1 && (int)Rolling::Stick == 2 && (int)Rolling::Newton == 3 &&
                  (int)Rolling::Iterated == 4 && (int)Rolling::NotConverged == 5 && (int)Rolling::NoSolution == 6,
              "frix_testing.h mirrors these values");

frix::rolling::Cones rolling_cones(int size, double mu, double mu_r, double mu_s) {
    return frix::rolling::Cones{mu, mu_r, size == 6 ? mu_s : 0.0, size == 6 ? 6 : 5};
}
}  // namespace

FRIX_TESTING_HOOK int frix_testing_rolling_solve_contact(int size, const double *W, const double *q, double mu,
                                                         double mu_r, double mu_s, double *r, double tol,
                                                         int max_iter) {
    frix::local_rolling::Contact c;
    frix::local_rolling::contact_setup(W, rolling_cones(size, mu, mu_r, mu_s), c);
    frix::local_rolling::Params p;
    p.tol = tol;
    p.max_iter = max_iter;
    return (int)frix::local_rolling::solve_contact(c, q, r, p);
}

FRIX_TESTING_HOOK int frix_testing_rolling_local_sweeps(const frix_problem *p, int stored, int sweeps, double *r) {
    if (!p || !r || p->kind != FRIX_PROBLEM_ROLLING_LOCAL || !p->W) return FRIX_ERR_INVALID_ARGUMENT;
    const auto run = [&](frix::rolling::SweepForm &form) {
        std::vector<frix::local_rolling::Contact> contacts = frix::rolling::contacts_of(form, *p);
        for (int k = 0; k < sweeps; ++k) frix::rolling::sweep(form, contacts, frix::local_rolling::Params{}, r);
        return FRIX_OK;
    };
    if (!stored) {
        frix::rolling::RowForm rows(*p);
        return run(rows);
    }
    frix::rolling::StoredForm form(*p);
    if (!form.serves()) return FRIX_ERR_UNSUPPORTED;
    return run(form);
}

FRIX_TESTING_HOOK int frix_testing_rolling_projection(int size, double *x, double mu, double mu_r, double mu_s,
                                                      double *D) {
    const frix::rolling::Cones k = rolling_cones(size, mu, mu_r, mu_s);
    double given[frix::local_rolling::kMaxSize];
    std::copy(x, x + k.size, given);
    const int which = frix::rolling::project_on_cone(x, k);
    if (D) frix::local_rolling::projection_jacobian(given, which, k, D);
    return which;
}

FRIX_TESTING_HOOK void frix_testing_rolling_alart_curnier(int size, const double *r, const double *u, double mu,
                                                          double mu_r, double mu_s, double rho, double *F, double *A,
                                                          double *B) {
    frix::local_rolling::alart_curnier(r, u, rolling_cones(size, mu, mu_r, mu_s), rho, F, A, B);
}

FRIX_TESTING_HOOK void frix_testing_project_on_cone(double r[3], double mu) {
    frix::coulomb::project_on_cone(r, mu);
}

FRIX_TESTING_HOOK void frix_testing_project_on_disk(double r[3], double radius) {
    frix::coulomb::project_on_disk(r, radius);
}

FRIX_TESTING_HOOK int frix_testing_project_on_rolling_cone(double *r, double mu, double mu_r, double mu_s,
                                                           int size) {
    return frix::rolling::project_on_cone(r, frix::rolling::Cones{mu, mu_r, mu_s, size});
}

FRIX_TESTING_HOOK int frix_testing_solve_contact(const double W[9], const double q[3], double mu,
                                                 double r[3], int local_solver, double tol,
                                                 int max_iter) {
    frix::local::Contact c;
    frix::local::contact_setup(W, mu, c);
    frix::local::Params p;
    p.solver = local_solver;
    p.tol = tol;
    p.max_iter = max_iter;
    return (int)frix::local::solve_contact(c, q, r, p);
}

FRIX_TESTING_HOOK int frix_testing_solve_slide(const double W[9], const double q[3], double mu,
                                               const double hint[3], double r[3]) {
    frix::local::Contact c;
    frix::local::contact_setup(W, mu, c);
    return frix::local::solve_slide(c, q, hint, r) ? 1 : 0;
}

FRIX_TESTING_HOOK double frix_testing_contact_residual(const double W[9], const double q[3],
                                                       double mu, const double r[3],
                                                       double *relative) {
    return frix::coulomb::contact_residual(W, q, mu, r, relative);
}

// ---- A stage of auto from a warm start whose measures its part holds.
#include "solvers/auto/stage.hpp"

FRIX_TESTING_HOOK int frix_testing_stage_from_measured_start(const frix_problem *p, int solver_id, double claim,
                                                             double *r, int64_t *sweeps, double *error) {
    std::vector<double> u((size_t)(3 * p->nc));
    frix::Measures start = frix::local_measures(*p, r, u.data());
    start.relative *= claim, start.q_relative *= claim, start.scaled *= claim;
    frix_options *o = nullptr;
    if (frix_error e = frix_options_create(FRIX_SOLVER_AUTO, &o)) return e;
    const frix::Stopwatch clock;
    frix::autosolve::Shared shared(*o, clock);
    const frix::autosolve::StageGround ground{*p, shared, u.data(), nullptr, nullptr, &start};
    frix::autosolve::StageOutcome out;
    const frix_error e =
        frix::autosolve::run_stage(ground, frix::autosolve::stall_request(solver_id, 1000, 1000, 1e-8), r, out);
    frix_options_free(o);
    *sweeps = out.info.iterations;
    *error = out.info.error;
    return e;
}

// Watch::Newton fed count progress reports (errors, measured flags), one per iteration: the
// index of the report it stopped at, -1 where it let the stage run, -2 where its options could
// not be made.
FRIX_TESTING_HOOK int frix_testing_newton_watch(const double *errors, const int *measured, int count,
                                                int64_t patience) {
    frix_options *o = nullptr;
    if (frix_options_create(FRIX_SOLVER_AUTO, &o) != FRIX_OK) return -2;
    const frix::Stopwatch clock;
    frix::autosolve::Shared shared(*o, clock);
    frix::autosolve::Watchdog dog(shared, frix::autosolve::Watch::Newton, 1e-12, patience, 0);
    int stopped = -1;
    for (int k = 0; k < count && stopped < 0; ++k)
        if (dog.on_progress(k + 1, errors[k], measured[k] != 0)) stopped = k;
    frix_options_free(o);
    return stopped;
}

// ---- Semismooth functions (solvers/kit/nsn_functions.hpp) and the linear algebra back-end.
#include "solvers/kit/local_newton.hpp"
#include "solvers/kit/nsn_functions.hpp"
#include "src/linalg/linalg.hpp"

FRIX_TESTING_HOOK void frix_testing_contact_function(int formulation, const double r[3],
                                                     const double u[3], double mu, double rho_n,
                                                     double rho_t, double phi[3], double A[9],
                                                     double B[9]) {
    frix::nsn::contact_function(formulation, r, u, mu, rho_n, rho_t, phi, A, B);
}

// Factorises the n x n CSC matrix twice with one symbolic analysis (the second time with
// the values scaled by 2) and solves A x = b with the second factorisation (so x = A^-1 b / 2).
// Returns the frix_error; *symbolic and *numeric receive the counters.
FRIX_TESTING_HOOK int frix_testing_sparse_lu(int64_t n, const int64_t *colptr,
                                             const int64_t *rowind, const double *values,
                                             const double *b, double *x, int64_t *symbolic,
                                             int64_t *numeric) {
    frix::linalg::SparseLU lu;
    frix::linalg::CscView A{n, n, colptr, rowind, values};
    int e = lu.analyze(A);
    if (e == FRIX_OK) e = lu.factor(A);
    std::vector<double> twice(values, values + colptr[n]);
    for (double &v : twice) v *= 2.0;
    frix::linalg::CscView A2{n, n, colptr, rowind, twice.data()};
    if (e == FRIX_OK) e = lu.factor(A2);
    if (e == FRIX_OK) e = lu.solve(b, x);
    *symbolic = lu.stats().symbolic;
    *numeric = lu.stats().numeric;
    return e;
}

// SparseLU with set_strategy_by_pivoting(true, excess): analysed and factorised with `first`,
// then factorised twice with `later` (the same pattern), then x = A^-1 b with the last
// factorisation. *symbolic: the analyses done; flops[0..2]: each factorisation's flops.
FRIX_TESTING_HOOK int frix_testing_lu_strategy(int64_t n, const int64_t *colptr, const int64_t *rowind,
                                               const double *first, const double *later, double excess,
                                               const double *b, double *x, int64_t *symbolic, double *flops) {
    frix::linalg::SparseLU lu;
    lu.set_ordering(frix::linalg::SparseLU::Ordering::kNestedDissection);
    lu.set_strategy_by_pivoting(true, excess);
    const frix::linalg::CscView A1{n, n, colptr, rowind, first}, A2{n, n, colptr, rowind, later};
    int e = lu.analyze(A1);
    if (e == FRIX_OK) e = lu.factor(A1);
    if (e == FRIX_OK) flops[0] = lu.flops_done(), e = lu.factor(A2);
    if (e == FRIX_OK) flops[1] = lu.flops_done(), e = lu.factor(A2);
    if (e == FRIX_OK) flops[2] = lu.flops_done(), e = lu.solve(b, x);
    *symbolic = lu.stats().symbolic;
    return e;
}

namespace {
// The k x k CSC matrix (cp, ci, cx) as a dense column-major C.
void to_dense(int64_t k, const std::vector<int64_t> &cp, const std::vector<int64_t> &ci,
              const std::vector<double> &cx, double *C) {
    for (int64_t i = 0; i < k * k; ++i) C[i] = 0.0;
    for (int64_t j = 0; j < k; ++j)
        for (int64_t p = cp[j]; p < cp[j + 1]; ++p) C[ci[p] + k * j] = cx[p];
}
}  // namespace

// Sparse Cholesky of A (upper triangle read): x = A^-1 b, and C = B^T A^-1 B (k x k dense,
// column-major) for the n x k CSC matrix B.
FRIX_TESTING_HOOK int frix_testing_sparse_cholesky(int64_t n, const int64_t *colptr,
                                                   const int64_t *rowind, const double *values,
                                                   const double *b, double *x, int64_t k,
                                                   const int64_t *bp, const int64_t *bi,
                                                   const double *bx, double *C) {
    frix::linalg::SparseCholesky ch;
    int e = ch.factor({n, n, colptr, rowind, values});
    if (e == FRIX_OK) e = ch.solve(b, x);
    if (e != FRIX_OK || k == 0) return e;
    std::vector<int64_t> cp, ci;
    std::vector<double> cx;
    e = ch.inverse_congruence({n, k, bp, bi, bx}, cp, ci, cx);
    if (e != FRIX_OK) return e;
    to_dense(k, cp, ci, cx, C);
    return FRIX_OK;
}

// x = A^-1 b with the factor's layout chosen by for_solves; whether it was supernodal.
FRIX_TESTING_HOOK int frix_testing_sparse_cholesky_layout(int for_solves, int64_t n, const int64_t *colptr,
                                                          const int64_t *rowind, const double *values,
                                                          const double *b, double *x, int *supernodal) {
    using Layout = frix::linalg::SparseCholesky::Layout;
    frix::linalg::SparseCholesky ch(for_solves ? Layout::kForSolves : Layout::kSupernodal);
    int e = ch.factor({n, n, colptr, rowind, values});
    if (e == FRIX_OK) e = ch.solve(b, x);
    *supernodal = ch.supernodal();
    return e;
}

FRIX_TESTING_HOOK int frix_testing_single_cholesky(int64_t n, const int64_t *colptr, const int64_t *rowind,
                                                   const double *values, const double *b, int refuse,
                                                   double *x_single, double *x_double, int *kept, int *dropped) {
    frix::linalg::SparseCholesky ch(frix::linalg::SparseCholesky::Layout::kSupernodal);
    int e = ch.factor({n, n, colptr, rowind, values});
    if (e) return e;
    const auto budget = [refuse](const frix::linalg::FactorPrice &price) {
        return refuse && price.bytes > 0.0 ? FRIX_STATUS_MEMORY_LIMIT : FRIX_STATUS_NOT_RUN;
    };
    *kept = ch.keep_single_copy(budget) && ch.has_single_copy();
    e = ch.solve(b, x_double);
    if (e == FRIX_OK && *kept) e = ch.solve_with_single_copy(b, x_single);
    if (e == FRIX_OK && !*kept) {
        // without a copy such a solve must fail
        e = ch.solve_with_single_copy(b, x_single) == FRIX_OK ? FRIX_ERR_INTERNAL : FRIX_OK;
        frix::clear_error();
    }
    if (e == FRIX_OK) e = ch.factor({n, n, colptr, rowind, values});
    *dropped = !ch.has_single_copy();
    return e;
}

FRIX_TESTING_HOOK int frix_testing_solve_near(const frix_matrix *Mm, const frix_matrix *Hm, double rho, double scale,
                                              const double *b, double *x, int solves, int *kept,
                                              int64_t *through_copy, int64_t *finished_in_double, int *in_use) {
    frix::Csc M, H;
    int e = frix::to_csc(*Mm, M);
    if (e == FRIX_OK) e = frix::to_csc(*Hm, H);
    if (e) return e;
    for (double &m : M.val) m *= scale;
    const int64_t nc = H.cols / 3, n = M.rows;
    frix::MassPlusContacts system;
    e = system.build(M, H, nc, "test", frix::ContactBlocks::kMultiplesOfIdentity, {});
    std::vector<double> S(9 * nc, 0.0), sb(b, b + n);
    for (int64_t a = 0; a < nc; ++a) S[9 * a] = S[9 * a + 4] = S[9 * a + 8] = scale * rho;
    for (double &v : sb) v *= scale;
    if (e == FRIX_OK) e = system.factor(S.data(), nullptr);
    *kept = e == FRIX_OK && system.keep_single_copy(nullptr);
    for (int k = 0; k < solves && e == FRIX_OK; ++k) e = system.solve_near(sb.data(), x);
    *through_copy = system.single_solves();
    *finished_in_double = system.solves_finished_in_double();
    *in_use = system.uses_single_copy();
    return e;
}

namespace {
// cholesky_cost of A's pattern (upper triangle) with the orderings given.
int pattern_cholesky_cost(int64_t n, const int64_t *colptr, const int64_t *rowind, frix::linalg::Orderings orderings,
                          double *flops, double *entries) {
    frix::linalg::FactorCost c;
    const int e = frix::linalg::cholesky_cost({n, n, colptr, rowind, nullptr}, &c, orderings);
    *flops = c.flops;
    *entries = c.factor_entries;
    return e;
}
}  // namespace

// The price of a Cholesky factorisation of A's pattern (upper triangle), from the symbolic
// analysis alone.
FRIX_TESTING_HOOK int frix_testing_cholesky_cost(int64_t n, const int64_t *colptr, const int64_t *rowind,
                                                 double *flops, double *entries) {
    return pattern_cholesky_cost(n, colptr, rowind, frix::linalg::Orderings::kAmdOrNested, flops, entries);
}

// The same under CHOLMOD's AMD ordering alone, what analyze_symmetric starts from.
FRIX_TESTING_HOOK int frix_testing_amd_cholesky_cost(int64_t n, const int64_t *colptr, const int64_t *rowind,
                                                     double *flops, double *entries) {
    return pattern_cholesky_cost(n, colptr, rowind, frix::linalg::Orderings::kAmdOnly, flops, entries);
}

FRIX_TESTING_HOOK int frix_testing_factor_prices(int64_t n, const int64_t *colptr, const int64_t *rowind,
                                                 const double *values, double *cholesky_price, double *cholesky_cost,
                                                 double *lu_price, int *lu_upper, double *lu_done) {
    const frix::linalg::CscView A{n, n, colptr, rowind, values};
    frix::linalg::SparseCholesky ch;
    ch.set_budget([&](const frix::linalg::FactorPrice &price) {
        *cholesky_price = price.flops;
        return FRIX_STATUS_NOT_RUN;
    });
    int e = ch.factor(A);
    frix::linalg::FactorCost cost;
    if (e == FRIX_OK) e = frix::linalg::cholesky_cost(A, &cost);
    *cholesky_cost = cost.flops;
    frix::linalg::SparseLU lu;
    lu.set_ordering(frix::linalg::SparseLU::Ordering::kNestedDissection);
    lu.set_budget([&](const frix::linalg::FactorPrice &price) {
        *lu_price = price.flops;
        *lu_upper = price.flops_upper_bound ? 1 : 0;
        return FRIX_STATUS_NOT_RUN;
    });
    if (e == FRIX_OK) e = lu.analyze(A);
    if (e == FRIX_OK) e = lu.factor(A);
    *lu_done = lu.flops_done();
    return e;
}

FRIX_TESTING_HOOK int frix_testing_congruence_questions(int64_t n, const int64_t *colptr,
                                                        const int64_t *rowind, const double *values,
                                                        int64_t k, const int64_t *bp, const int64_t *bi,
                                                        const double *bx, double questions_asked, double min_flops, int stop_at,
                                                        double *C, int *questions, int *stopped,
                                                        int64_t *nnz) {
    frix::linalg::SparseCholesky ch;
    int e = ch.factor({n, n, colptr, rowind, values});
    if (e != FRIX_OK) return e;
    std::vector<int64_t> cp, ci;
    std::vector<double> cx;
    *questions = 0;
    auto stop = [&]() { return ++*questions == stop_at; };
    bool was_stopped = false;
    e = ch.inverse_congruence({n, k, bp, bi, bx}, cp, ci, cx, stop, &was_stopped, questions_asked, min_flops);
    *stopped = was_stopped ? 1 : 0;
    *nnz = (int64_t)cx.size();
    if (e != FRIX_OK || was_stopped) return e;
    to_dense(k, cp, ci, cx, C);
    return FRIX_OK;
}

// The n x n CSC matrix through BlockMatrixFromColumns (column by column), as a dense
// column-major D; *blocks: its blocks; *in_place: whether it was found symmetric.
#include "src/matrix.hpp"

FRIX_TESTING_HOOK int frix_testing_matrix_from_columns(int64_t n, const int64_t *colptr, const int64_t *rowind,
                                                       const double *values, double expected_blocks, double *D,
                                                       int64_t *blocks, int *in_place) {
    frix::BlockMatrixFromColumns columns(n, "test matrix", expected_blocks);
    for (int64_t j = 0; j < n; ++j)
        if (int e = columns.add_column(colptr[j + 1] - colptr[j], rowind + colptr[j], values + colptr[j])) return e;
    std::unique_ptr<frix_matrix> A;
    if (int e = columns.finish(A)) return e;
    for (int64_t i = 0; i < n * n; ++i) D[i] = 0.0;
    frix::for_each_entry(*A, [&](int64_t i, int64_t j, double v) { D[i + n * j] = v; });
    *blocks = A->nblocks();
    *in_place = columns.in_place() ? 1 : 0;
    return FRIX_OK;
}

// The price of a Cholesky of a matrix with the block pattern of W (n x n CSC, n a multiple
// of 3, stored as 3x3 blocks).
FRIX_TESTING_HOOK int frix_testing_block_cholesky_cost(int64_t n, const int64_t *colptr, const int64_t *rowind,
                                                       const double *values, double *flops, double *entries) {
    frix_matrix *W = nullptr;
    int e = frix_matrix_from_csc(n, n, colptr, rowind, values, &W);
    frix::linalg::FactorCost c;
    if (e == FRIX_OK) e = frix::block_cholesky_cost(*W, &c);
    frix_matrix_free(W);
    *flops = c.flops;
    *entries = c.factor_entries;
    return e;
}

// W = H^T M^-1 H as the reduction forms it (M factorised, W summed into block-CSR), as a
// dense column-major D (k x k); *blocks: W's 3x3 blocks.
#include "src/reduction.hpp"

namespace {
// M (n x n) factorised and W = H^T M^-1 H formed as the reduction does (H n x k, both CSC);
// *price, when given, W's price asked before.
int reduce(int64_t n, const int64_t *mp, const int64_t *mi, const double *mx, int64_t k, const int64_t *hp,
           const int64_t *hi, const double *hx, std::unique_ptr<frix_matrix> &W, frix::linalg::FactorPrice *price) {
    frix_matrix *M = nullptr, *H = nullptr;
    int e = frix_matrix_from_csc(n, n, mp, mi, mx, &M);
    if (e == FRIX_OK) e = frix_matrix_from_csc(n, k, hp, hi, hx, &H);
    if (e == FRIX_OK) {
        frix::MassSolver ms;
        bool stopped = false;
        e = ms.factor(*M);
        if (e == FRIX_OK && price && !ms.congruence_price(*H, price)) e = FRIX_ERR_INTERNAL;
        if (e == FRIX_OK) e = ms.congruence(*H, 0.0, W, nullptr, stopped);
    }
    frix_matrix_free(M);
    frix_matrix_free(H);
    return e;
}
}  // namespace

FRIX_TESTING_HOOK int frix_testing_reduction(int64_t n, const int64_t *mp, const int64_t *mi, const double *mx,
                                             int64_t k, const int64_t *hp, const int64_t *hi, const double *hx,
                                             double *D, int64_t *blocks) {
    std::unique_ptr<frix_matrix> W;
    if (int e = reduce(n, mp, mi, mx, k, hp, hi, hx, W, nullptr)) return e;
    for (int64_t i = 0; i < k * k; ++i) D[i] = 0.0;
    frix::for_each_entry(*W, [&](int64_t i, int64_t j, double v) { D[i + k * j] = v; });
    *blocks = W->nblocks();
    return FRIX_OK;
}

FRIX_TESTING_HOOK int frix_testing_w_price(int64_t n, const int64_t *mp, const int64_t *mi, const double *mx,
                                           int64_t k, const int64_t *hp, const int64_t *hi, const double *hx,
                                           double *flops, double *writes, int64_t *blocks) {
    std::unique_ptr<frix_matrix> W;
    frix::linalg::FactorPrice price;
    if (int e = reduce(n, mp, mi, mx, k, hp, hi, hx, W, &price)) return e;
    *flops = price.flops;
    *writes = price.writes;
    *blocks = W->nblocks();
    return FRIX_OK;
}

// Monitor::affords on a first factorisation priced at `flops` and `writes`, under a time limit
// of `time_limit` seconds (no memory asked): FRIX_STATUS_NOT_RUN when it fits.
#include "src/monitor.hpp"
FRIX_TESTING_HOOK int frix_testing_affords(double flops, double writes, double time_limit) {
    frix_options o;
    o.dvalue[FRIX_OPT_TIME_LIMIT] = time_limit;
    const frix::Stopwatch clock;
    frix::linalg::FactorPrice price;
    price.flops = flops;
    price.writes = writes;
    return frix::Monitor(o, clock).affords(price);
}

// Dense LU (cholesky = 0) or Cholesky (1) of the column-major n x n A: x = A^-1 b.
FRIX_TESTING_HOOK int frix_testing_dense_solve(int cholesky, int64_t n, const double *A,
                                               const double *b, double *x) {
    if (cholesky) {
        frix::linalg::DenseCholesky ch;
        int e = ch.factor(n, A, n);
        return e == FRIX_OK ? ch.solve(b, x) : e;
    }
    frix::linalg::DenseLU lu;
    int e = lu.factor(n, A, n);
    return e == FRIX_OK ? lu.solve(b, x) : e;
}

// nsgs-v through the driver's path for p's form (a global p reduced first), as frix_solve
// runs it with options o, but its pushes through W's columns in single precision whatever
// W's size (single = 1) or in double whatever W's size (single = 0).
#include "solvers/entries.hpp"
#include "solvers/kit/sweeps.hpp"

namespace {
frix_error sweeps_single(frix::SolveContext &ctx) { return frix::nsgs::solve_velocity_at(ctx, 0.0); }
frix_error sweeps_double(frix::SolveContext &ctx) { return frix::nsgs::solve_velocity_at(ctx, INFINITY); }
}  // namespace

FRIX_TESTING_HOOK int frix_testing_nsgs_velocity(int single, const frix_problem *p, const frix_options *o,
                                                 double *r, double *u, double *v, frix_info *info) {
    frix::SolverEntry entry = frix::kNsgsVelocityEntry;
    entry.solve = single ? sweeps_single : sweeps_double;
    const frix::Stopwatch clock;
    *info = frix_info();
    info->solver_id = entry.id;
    info->contacts = p->nc;
    info->tolerance = o->d(FRIX_OPT_TOLERANCE);
    if (frix::is_local_form(*p))
        return frix::solve_local_problem(*p, *o, entry, r, u, *info, clock, nullptr, nullptr, true, true);
    return frix::solve_global_problem(*p, *o, entry, r, u, v, *info, clock);
}

// u += W's block column a times dr through SingleColumns (W storing every block), its
// columns read from W's rows where `symmetric` (W must then be symmetric to the bit).
FRIX_TESTING_HOOK int frix_testing_single_push(const frix_matrix *W, int symmetric, int64_t a, const double dr[3],
                                               double *u) {
    frix_matrix copy = *W;
    copy.symmetric = symmetric != 0;
    if (!frix::nsgs::SingleColumns::suits(copy, 0.0) || a < 0 || a >= copy.block_cols) return FRIX_ERR_INVALID_ARGUMENT;
    frix::nsgs::SingleColumns columns;
    columns.build(copy, 0, 0);
    columns.push(a, dr, u);
    return FRIX_OK;
}

// M + rho H H^T as the solvers without W build it (MassPlusContacts), for any contact blocks
// (identity_blocks = 0) or multiples of the identity (1), offered M's ordering: the flops of its
// factorisation, x = (M + rho H H^T)^-1 b and whether it was analysed in M's ordering.
#include "solvers/kit/mass_plus_contacts.hpp"
FRIX_TESTING_HOOK int frix_testing_mass_plus_contacts(int identity_blocks, const frix_matrix *Mm,
                                                      const frix_matrix *Hm, double rho, const double *b,
                                                      double *x, double *flops, int *mass_ordering) {
    frix::Csc M, H;
    int e = frix::to_csc(*Mm, M);
    if (e == FRIX_OK) e = frix::to_csc(*Hm, H);
    if (e) return e;
    const int64_t nc = H.cols / 3;
    using frix::ContactBlocks;
    frix::MassPlusContacts system;
    frix::linalg::FactorCost cost;
    frix::MassSolver mass;
    e = mass.factor(*Mm);
    const ContactBlocks blocks = identity_blocks ? ContactBlocks::kMultiplesOfIdentity : ContactBlocks::kAny;
    if (e == FRIX_OK) e = system.build(M, H, nc, "test", blocks, mass.ordering());
    if (e == FRIX_OK) e = system.analyse(&cost);
    *mass_ordering = e == FRIX_OK && system.ordering() == mass.ordering();
    std::vector<double> S(9 * nc, 0.0);
    for (int64_t a = 0; a < nc; ++a) S[9 * a] = S[9 * a + 4] = S[9 * a + 8] = rho;
    if (e == FRIX_OK) e = system.factor(S.data(), nullptr);
    if (e == FRIX_OK) e = system.solve(b, x);
    *flops = cost.flops;
    return e;
}

// diag[j] = b_j^T M^-1 b_j for B's columns as MassSolver::inverse_diagonal gives them, and the
// same from one full solve a column (by_solves).
FRIX_TESTING_HOOK int frix_testing_inverse_diagonal(const frix_matrix *M, const frix_matrix *Bm, double *diag,
                                                    double *by_solves) {
    frix::Csc B;
    frix::MassSolver ms;
    int e = frix::to_csc(*Bm, B);
    if (e == FRIX_OK) e = ms.factor(*M);
    std::vector<double> d;
    if (e == FRIX_OK) e = ms.inverse_diagonal(B, d);
    if (e) return e;
    std::vector<double> b(B.rows), x(B.rows);
    for (int64_t j = 0; j < B.cols; ++j) {
        diag[j] = d[j];
        std::fill(b.begin(), b.end(), 0.0);
        for (int64_t k = B.colptr[j]; k < B.colptr[j + 1]; ++k) b[B.rowind[k]] = B.val[k];
        if ((e = ms.solve(b.data(), x.data()))) return e;
        by_solves[j] = 0.0;
        for (int64_t k = B.colptr[j]; k < B.colptr[j + 1]; ++k) by_solves[j] += B.val[k] * x[B.rowind[k]];
    }
    return FRIX_OK;
}

#include "src/memory.hpp"

FRIX_TESTING_HOOK int frix_testing_advised_arrays(const int64_t *sizes, int count, const double *values) {
    std::vector<double> v;
    for (int k = 0; k < count; ++k) {
        const size_t n = (size_t)sizes[k];
        const size_t capacity = v.capacity();
        const double *storage = v.data();
        frix::assign_advised(v, n, (double)(k + 1));
        if (v.size() != n || std::any_of(v.begin(), v.end(), [k](double x) { return x != (double)(k + 1); }))
            return k + 1;
        if (n <= capacity && v.data() != storage) return k + 1;
    }
    frix::copy_advised(v, values, (size_t)count);
    if (v.size() != (size_t)count || !std::equal(v.begin(), v.end(), values)) return count + 1;
    // Advice on nothing, on a small array and on an unaligned span is no error.
    frix::advise_huge_pages(nullptr, frix::kHugeArrayBytes);
    frix::advise_huge_pages(v.data(), v.size() * sizeof(double));
    std::vector<char> odd((size_t)frix::kHugeArrayBytes + 4096 + 3);
    frix::advise_huge_pages(odd.data() + 3, odd.size() - 3);
    return 0;
}

#include "src/existence.hpp"

FRIX_TESTING_HOOK int frix_testing_symmetric_part_psd(const frix_problem *p, double tolerance) {
    switch (frix::symmetric_part_psd(*p, tolerance)) {
        case frix::Psd::Yes: return 0;
        case frix::Psd::No: return 1;
        default: return 2;
    }
}

FRIX_TESTING_HOOK int frix_testing_matrix_from_csc_taking(int64_t nrows, int64_t ncols, const int64_t *colptr,
                                                          const int64_t *rowind, const double *values, int64_t nnz,
                                                          frix_matrix **out, int *taken) {
    std::vector<int64_t> p(colptr, colptr + ncols + 1), i(rowind, rowind + nnz);
    std::vector<double> x(values, values + nnz);
    const int e = frix::matrix_from_csc_taking(nrows, ncols, p, i, x, out);
    const bool intact = std::equal(p.begin(), p.end(), colptr) && i.size() == (size_t)nnz &&
                        std::equal(i.begin(), i.end(), rowind) && x.size() == (size_t)nnz &&
                        std::equal(x.begin(), x.end(), values);
    *taken = p.empty() && i.empty() && x.empty() ? 1 : intact ? 0 : -1;
    return e;
}

FRIX_TESTING_HOOK void frix_testing_load_span(int64_t n, const int64_t *colptr, const int64_t *rowind,
                                              const double *values, int k, const double *F, const double *X,
                                              double *answers, int *from_span) {
    frix::LoadSpan span;
    const frix::linalg::CscView M{n, n, colptr, rowind, values};
    for (int i = 0; i < k; ++i) {
        const size_t at = (size_t)i * (size_t)n;
        from_span[i] = span.answer(F + at, M, answers + at) ? 1 : 0;
        if (from_span[i]) continue;
        std::copy(X + at, X + at + n, answers + at);
        span.add(F + at, X + at, n);
    }
}

FRIX_TESTING_HOOK int frix_testing_mass_loads(const frix_matrix *M, const frix_matrix *M2, const double *f,
                                              double s, double *x0, double *x1) {
    frix::MassSolver ms;
    const int64_t n = M->rows;
    if (frix_error e = ms.factor(*M)) return e;
    if (frix_error e = ms.solve_load(f, n, x0, true)) return e;
    if (frix_error e = ms.factor(*M2)) return e;
    std::vector<double> g(f, f + n);
    for (double &v : g) v *= s;
    return ms.solve_load(g.data(), n, x1, true);
}
