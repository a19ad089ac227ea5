/* A one-shot reduction of a global problem with a large dense W forms W for the contacts the
 * free motion presses first (q_N < 0), and again with those that end up penetrating: the
 * answer is the whole problem's, measured on every contact. */
#include <frix/frix.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check_main.h"
#include "elastic_grid.h"

typedef struct {
    int lines;             /* "reduction: W for the N of NC contacts ..." */
    int64_t formed[4];     /* N of each */
    int penetrating_lines; /* of those, the ones after a round found contacts penetrating */
} part_log;

static void note_part(void *data, const char *line) {
    part_log *c = data;
    const char *at = strstr(line, "reduction: W for the ");
    if (!at) return;
    if (c->lines < 4) c->formed[c->lines] = atoll(at + strlen("reduction: W for the "));
    ++c->lines;
    if (strstr(line, "penetrating")) ++c->penetrating_lines;
}

typedef struct {
    int64_t calls, last, decreasing;
    int64_t stop_from; /* > 0: the callback stops the solve at this iteration or later */
} progress;

/* Counts its calls and stops at the first. */
static int stop_at_once(void *data, int64_t iteration, double error, double elapsed) {
    (void)iteration, (void)error, (void)elapsed;
    ++((progress *)data)->calls;
    return 1;
}

static int watch(void *data, int64_t iteration, double error, double elapsed) {
    (void)error, (void)elapsed;
    progress *w = data;
    if (w->calls > 0 && iteration < w->last) ++w->decreasing;
    w->last = iteration;
    ++w->calls;
    return w->stop_from > 0 && iteration >= w->stop_from;
}

typedef struct {
    frix_status status;
    int64_t iterations;
    double error; /* frix_problem_error of (r, v) */
    double *r, *v;
    part_log log;
    progress seen;
} outcome;

static frix_options *nsgs_v_options(part_log *log, progress *seen) {
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_NSGS_VELOCITY, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 1e-8), FRIX_OK);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_VERBOSITY, 1), FRIX_OK);
    ck_assert_int_eq(frix_options_set_log(o, note_part, log), FRIX_OK);
    if (seen) ck_assert_int_eq(frix_options_set_callback(o, watch, seen), FRIX_OK);
    return o;
}

/* nsgs-v from r0 (null: 0) with at most max_iter iterations (0: the default), by frix_solve or
 * (persistent) by a persistent solver's first step; the callback stops it from iteration
 * stop_from on (0: never). */
static outcome solve_stopped(const frix_problem *p, int persistent, const double *r0, int64_t max_iter,
                             int64_t stop_from) {
    outcome out;
    memset(&out, 0, sizeof out);
    out.seen.stop_from = stop_from;
    const int64_t m = frix_problem_contact_dofs(p), n = frix_problem_dofs(p);
    out.r = calloc((size_t)m, sizeof *out.r);
    if (r0) memcpy(out.r, r0, sizeof *out.r * (size_t)m);
    out.v = calloc((size_t)n, sizeof *out.v);
    double *u = calloc((size_t)m, sizeof *u);
    ck_assert(out.r && out.v && u);
    frix_options *o = nsgs_v_options(&out.log, &out.seen);
    if (max_iter > 0) ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_MAX_ITER, max_iter), FRIX_OK);
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    if (persistent) {
        frix_persistent *ps = NULL;
        ck_assert_int_eq(frix_persistent_create(p, o, &ps), FRIX_OK);
        ck_assert_int_eq(frix_persistent_solve(ps, out.r, u, out.v, info), FRIX_OK);
        frix_persistent_free(ps);
    } else {
        ck_assert_int_eq(frix_solve(p, o, out.r, u, out.v, info), FRIX_OK);
    }
    out.status = frix_info_status(info);
    out.iterations = frix_info_iterations(info);
    ck_assert_int_eq(frix_problem_error(p, out.r, out.v, &out.error), FRIX_OK);
    frix_info_free(info);
    frix_options_free(o);
    free(u);
    return out;
}

static outcome solve_from(const frix_problem *p, int persistent, const double *r0, int64_t max_iter) {
    return solve_stopped(p, persistent, r0, max_iter, 0);
}

static outcome solve(const frix_problem *p, int persistent) { return solve_from(p, persistent, NULL, 0); }

static void outcome_free(outcome *x) { free(x->r), free(x->v); }

/* |a - b| / |b| */
static double distance(const double *a, const double *b, int64_t m) {
    double d = 0.0, s = 0.0;
    for (int64_t i = 0; i < m; ++i) d += (a[i] - b[i]) * (a[i] - b[i]), s += b[i] * b[i];
    return sqrt(d / s);
}

/* An elastic grid of 27 x 27 nodes on 2 layers (W of 729 contacts, 42 MB) whose nodes lie up to
 * 2 above the plane: the free motion presses 400 of them. The one-shot solve forms W for those,
 * and its answer is the persistent solver's, which forms the whole W for its next steps. */
START_TEST(pressed_contacts_first_on_a_grid) {
    frix_elastic_grid g;
    ck_assert_int_eq(frix_elastic_grid_make(27, 27, 2, 2.0, 1e4, &g), FRIX_OK);
    const int64_t m = frix_problem_contact_dofs(g.problem), n = frix_problem_dofs(g.problem);
    outcome part = solve(g.problem, 0), whole = solve(g.problem, 1);
    ck_assert_int_eq(part.status, FRIX_STATUS_CONVERGED);
    ck_assert_int_eq(whole.status, FRIX_STATUS_CONVERGED);
    ck_assert_double_le(part.error, 1e-8);
    ck_assert_int_eq(part.log.lines, 1);
    ck_assert(part.log.formed[0] > 0 && part.log.formed[0] < m / 3);
    ck_assert_int_eq(whole.log.lines, 0);
    /* W is regular (a deformable body): one solution, met by both to about the tolerance. */
    ck_assert_double_le(distance(part.r, whole.r, m), 1e-6);
    ck_assert_double_le(distance(part.v, whole.v, n), 1e-6);
    outcome_free(&part), outcome_free(&whole);
    frix_elastic_grid_free(&g);
}
END_TEST

/* A body whose normal dofs all pull on one another: M = I + beta J / nc on them (the identity on
 * the tangential ones), H = I (a contact a dof triple, normal first), so that W's normal part
 * (I - c J / nc, c = beta / (1 + beta)) is dense with negative couplings: the contacts pressed
 * (q_N = -1) pull the others down. `pressed` of the nc contacts are pressed, `near` have
 * q_N = 0.1 (pulled into touch) and the rest q_N = 10 (stay open). skew != 0: M's tangential
 * 2 x 2 blocks [1 skew; -skew 1], not symmetric (M factorised by LU). */
typedef struct {
    frix_matrix *M, *H;
    double *f, *w, *mu;
    frix_problem *p;
} pulling_body;

static pulling_body pulling_body_make(int64_t nc, int64_t pressed, int64_t near, double beta, double skew) {
    pulling_body b;
    const int64_t n = 3 * nc, nnz = nc * nc + 4 * nc;
    int64_t *colptr = malloc(sizeof *colptr * (size_t)(n + 1)), *rowind = malloc(sizeof *rowind * (size_t)nnz);
    int64_t *ident_ptr = malloc(sizeof *ident_ptr * (size_t)(n + 1));
    int64_t *ident_row = malloc(sizeof *ident_row * (size_t)n);
    double *values = malloc(sizeof *values * (size_t)nnz), *ones = malloc(sizeof *ones * (size_t)n);
    ck_assert(colptr && rowind && ident_ptr && ident_row && values && ones);
    int64_t e = 0;
    for (int64_t j = 0; j < n; ++j) {
        colptr[j] = e;
        if (j % 3 == 0) {
            for (int64_t a = 0; a < nc; ++a)
                rowind[e] = 3 * a, values[e++] = (3 * a == j ? 1.0 : 0.0) + beta / (double)nc;
        } else {
            const int64_t other = j % 3 == 1 ? j + 1 : j - 1; /* the contact's other tangential dof */
            if (skew != 0.0 && other < j) rowind[e] = other, values[e++] = skew;
            rowind[e] = j, values[e++] = 1.0;
            if (skew != 0.0 && other > j) rowind[e] = other, values[e++] = -skew;
        }
        ident_ptr[j] = j, ident_row[j] = j, ones[j] = 1.0;
    }
    colptr[n] = e, ident_ptr[n] = n;
    ck_assert_int_eq(frix_matrix_from_csc(n, n, colptr, rowind, values, &b.M), FRIX_OK);
    ck_assert_int_eq(frix_matrix_from_csc(n, n, ident_ptr, ident_row, ones, &b.H), FRIX_OK);
    b.f = calloc((size_t)n, sizeof *b.f);
    b.w = calloc((size_t)n, sizeof *b.w);
    b.mu = malloc(sizeof *b.mu * (size_t)nc);
    ck_assert(b.f && b.w && b.mu);
    for (int64_t a = 0; a < nc; ++a) {
        b.w[3 * a] = a < pressed ? -1.0 : a < pressed + near ? 0.1 : 10.0;
        b.mu[a] = 0.3;
    }
    ck_assert_int_eq(frix_problem_global(b.M, b.H, b.f, b.w, b.mu, nc, &b.p), FRIX_OK);
    free(colptr), free(rowind), free(ident_ptr), free(ident_row), free(values), free(ones);
    return b;
}

static void pulling_body_free(pulling_body *b) {
    frix_problem_free(b->p);
    frix_matrix_free(b->M), frix_matrix_free(b->H);
    free(b->f), free(b->w), free(b->mu);
}

/* The body most tests take: 720 contacts (W of 41 MB), 360 pressed, 72 pulled into touch. */
enum { kContacts = 720, kPressed = 360, kNear = 72 };

static pulling_body pulling_body_near(double skew) {
    return pulling_body_make(kContacts, kPressed, kNear, 1.0, skew);
}

/* 720 contacts (W of 41 MB), 360 pressed, 72 pulled into touch: a second round forms W for 432,
 * and the 288 others stay open at r = 0. The callback's iterations rise across the rounds. */
START_TEST(penetrating_contacts_join_the_part) {
    pulling_body b = pulling_body_near(0.0);
    outcome out = solve(b.p, 0);
    ck_assert_int_eq(out.status, FRIX_STATUS_CONVERGED);
    ck_assert_double_le(out.error, 1e-8);
    ck_assert_int_eq(out.log.lines, 2);
    ck_assert_int_eq(out.log.formed[0], kPressed);
    ck_assert_int_eq(out.log.formed[1], kPressed + kNear);
    ck_assert_int_eq(out.log.penetrating_lines, 1);
    for (int64_t a = 0; a < kContacts; ++a) {
        if (a < kPressed + kNear) ck_assert_double_gt(out.r[3 * a], 0.0);
        else ck_assert(out.r[3 * a] == 0.0 && out.r[3 * a + 1] == 0.0 && out.r[3 * a + 2] == 0.0);
    }
    ck_assert_int_gt(out.seen.calls, 2);
    ck_assert_int_eq(out.seen.decreasing, 0);
    ck_assert_int_le(out.seen.last, out.iterations);
    outcome_free(&out);
    pulling_body_free(&b);
}
END_TEST

/* Where the contacts pulled into touch take the part past its share (360 + 360 of 720), the
 * whole W is formed after the first round, from its answer. */
START_TEST(a_part_grown_past_its_share_goes_to_the_whole_w) {
    pulling_body b = pulling_body_make(kContacts, kPressed, kContacts - kPressed, 1.0, 0.0);
    outcome out = solve(b.p, 0);
    ck_assert_int_eq(out.status, FRIX_STATUS_CONVERGED);
    ck_assert_double_le(out.error, 1e-8);
    ck_assert_int_eq(out.log.lines, 1);
    for (int64_t a = 0; a < kContacts; ++a) ck_assert_double_gt(out.r[3 * a], 0.0);
    ck_assert_int_eq(out.seen.decreasing, 0);
    ck_assert_int_le(out.seen.last, out.iterations); /* the round's iterations count too */
    ck_assert_int_gt(out.seen.last, 0);
    outcome_free(&out);
    pulling_body_free(&b);
}
END_TEST

/* From the answer (the 72 contacts pulled into touch hold r != 0): W for the 432 at once, and
 * the answer comes back within the tolerance. */
START_TEST(a_warm_starts_contacts_join_the_first_part) {
    pulling_body b = pulling_body_near(0.0);
    outcome cold = solve(b.p, 0), warm = solve_from(b.p, 0, cold.r, 0);
    ck_assert_int_eq(warm.status, FRIX_STATUS_CONVERGED);
    ck_assert_double_le(warm.error, 1e-8);
    ck_assert_int_eq(warm.log.lines, 1);
    ck_assert_int_eq(warm.log.formed[0], kPressed + kNear);
    ck_assert_int_lt(warm.iterations, cold.iterations);
    outcome_free(&cold), outcome_free(&warm);
    pulling_body_free(&b);
}
END_TEST

/* max_iter holds across the rounds: every cap k below the run's own count ends at k or
 * before (converged or not: the part's own scale is stricter than the whole problem's). */
START_TEST(the_rounds_share_max_iter) {
    pulling_body b = pulling_body_near(0.0);
    outcome all = solve(b.p, 0);
    ck_assert_int_gt(all.iterations, 2);
    for (int64_t k = 1; k < all.iterations; ++k) {
        outcome capped = solve_from(b.p, 0, NULL, k);
        ck_assert_msg(capped.iterations <= k, "max_iter %lld: %lld iterations", (long long)k,
                      (long long)capped.iterations);
        ck_assert(capped.status == FRIX_STATUS_CONVERGED || capped.status == FRIX_STATUS_MAX_ITER);
        outcome_free(&capped);
    }
    outcome_free(&all);
    pulling_body_free(&b);
}
END_TEST

/* The callback's stop in the second round ends the solve there, stopped, the answer measured on
 * the whole problem as any stopped solve's is. */
START_TEST(a_stop_in_the_second_round_ends_the_solve) {
    pulling_body b = pulling_body_near(0.0);
    outcome all = solve(b.p, 0);
    const int64_t stop_from = all.iterations - 2;
    outcome out = solve_stopped(b.p, 0, NULL, 0, stop_from);
    ck_assert_int_eq(out.log.lines, 2); /* the stop came in the second round */
    ck_assert_int_eq(out.status, FRIX_STATUS_STOPPED_BY_CALLBACK);
    ck_assert_int_ge(out.iterations, stop_from);
    ck_assert_int_lt(out.iterations, all.iterations);
    ck_assert_int_eq(out.seen.decreasing, 0);
    outcome_free(&all), outcome_free(&out);
    pulling_body_free(&b);
}
END_TEST

/* With callback_estimates = 0 the callback hears the whole problem's measured error before the
 * part's W is formed, and may stop the solve there: no W formed, r = 0. */
START_TEST(the_callback_may_stop_before_the_parts_w) {
    pulling_body b = pulling_body_near(0.0);
    const int64_t m = 3 * kContacts, n = 3 * kContacts;
    double *r = calloc((size_t)m, sizeof *r), *u = calloc((size_t)m, sizeof *u), *v = calloc((size_t)n, sizeof *v);
    part_log log;
    memset(&log, 0, sizeof log);
    progress seen;
    memset(&seen, 0, sizeof seen);
    frix_options *o = nsgs_v_options(&log, NULL);
    ck_assert_int_eq(frix_options_set_int(o, FRIX_OPT_CALLBACK_ESTIMATES, 0), FRIX_OK);
    ck_assert_int_eq(frix_options_set_callback(o, stop_at_once, &seen), FRIX_OK);
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_solve(b.p, o, r, u, v, info), FRIX_OK);
    ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_STOPPED_BY_CALLBACK);
    ck_assert_int_eq(frix_info_iterations(info), 0);
    ck_assert_int_eq(seen.calls, 1);
    ck_assert_int_eq(log.lines, 0);
    for (int64_t i = 0; i < m; ++i) ck_assert(r[i] == 0.0);
    frix_info_free(info), frix_options_free(o);
    free(r), free(u), free(v);
    pulling_body_free(&b);
}
END_TEST

/* M not symmetric (its LU forms W column by column): the same rounds and a converged answer. */
START_TEST(rounds_on_an_lu_factorised_m) {
    pulling_body b = pulling_body_near(0.2);
    outcome out = solve(b.p, 0);
    ck_assert_int_eq(out.status, FRIX_STATUS_CONVERGED);
    ck_assert_double_le(out.error, 1e-8);
    ck_assert_int_eq(out.log.lines, 2);
    ck_assert_int_eq(out.log.formed[1], kPressed + kNear);
    outcome_free(&out);
    pulling_body_free(&b);
}
END_TEST

int main(void) {
    Suite *s = suite_create("pressed_first");
    TCase *tc = tcase_create("core");
    tcase_set_timeout(tc, 300);
    tcase_add_test(tc, pressed_contacts_first_on_a_grid);
    tcase_add_test(tc, penetrating_contacts_join_the_part);
    tcase_add_test(tc, a_part_grown_past_its_share_goes_to_the_whole_w);
    tcase_add_test(tc, a_warm_starts_contacts_join_the_first_part);
    tcase_add_test(tc, the_rounds_share_max_iter);
    tcase_add_test(tc, rounds_on_an_lu_factorised_m);
    tcase_add_test(tc, a_stop_in_the_second_round_ends_the_solve);
    tcase_add_test(tc, the_callback_may_stop_before_the_parts_w);
    suite_add_tcase(s, tc);
    return frix_run_suite(s);
}
