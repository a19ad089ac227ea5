/* The persistent solver (frix_persistent.h): bad input, the answers frix_solve gives on a
 * sequence of steps, what it keeps between solves (read from the info's counters), updates
 * of every kind, and the plugin table's versions. */
#include <frix/frix.h>

#include <math.h>
#include <pthread.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "check_main.h"
#include "scenes.h"

/* A pyramid of spheres (redundant contacts, normals in every direction): step k turns the
 * contact frames by 0.01 k and pushes every body sideways a little more. */
typedef struct sequence {
    int steps;
    frix_scene scene[4];
    frix_scene_problems forms[4];
} sequence;

static void make_sequence(sequence *s, int layers) {
    s->steps = 4;
    for (int k = 0; k < s->steps; ++k) {
        frix_scene_params prm;
        frix_scene_defaults(FRIX_SCENE_SPHERES, &prm);
        prm.count = layers;
        prm.frame_angle = 0.01 * k;
        ck_assert_int_eq(frix_scene_build(&prm, &s->scene[k], NULL), FRIX_OK);
        for (int64_t b = 0; b < s->scene[k].bodies; ++b)
            s->scene[k].f[6 * b] += 0.02 * k * prm.step * FRIX_SCENE_GRAVITY / s->scene[k].minv[6 * b];
        ck_assert_int_eq(frix_scene_problems_make(&s->scene[k], &s->forms[k]), FRIX_OK);
    }
}

static void free_sequence(sequence *s) {
    for (int k = 0; k < s->steps; ++k) {
        frix_scene_problems_free(&s->forms[k]);
        frix_scene_free(&s->scene[k]);
    }
}

static int64_t info_int(const frix_info *info, frix_info_key key) {
    int64_t x = -1;
    ck_assert_int_eq(frix_info_get_int(info, key, &x), FRIX_OK);
    return x;
}

START_TEST(test_bad_input) {
    sequence s;
    make_sequence(&s, 2);
    frix_persistent *ps = (frix_persistent *)&s;  /* must be overwritten with NULL */
    ck_assert_int_eq(frix_persistent_create(NULL, NULL, &ps), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_ptr_null(ps);
    ck_assert_int_eq(frix_persistent_create(s.forms[0].local, NULL, NULL), FRIX_ERR_INVALID_ARGUMENT);
    frix_options *global_only = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_GLOBAL_NSN_AC, &global_only), FRIX_OK);
    ck_assert_int_eq(frix_persistent_create(s.forms[0].local, global_only, &ps), FRIX_ERR_UNSUPPORTED);
    frix_options_free(global_only);
    frix_persistent_free(NULL);

    const int64_t nc = s.scene[0].nc, m = 3 * nc;
    double *r = calloc((size_t)m, sizeof *r), *u = calloc((size_t)m, sizeof *u);
    ck_assert_int_eq(frix_persistent_solve(NULL, r, u, NULL, NULL), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_persistent_create(s.forms[0].local, NULL, &ps), FRIX_OK);
    ck_assert_int_eq(frix_persistent_update_local(NULL, NULL, NULL, NULL), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_persistent_update_global(ps, NULL, NULL, NULL, NULL, NULL), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_persistent_solve(ps, NULL, u, NULL, NULL), FRIX_ERR_INVALID_ARGUMENT);

    /* A W of another size, a non-finite q and a negative mu are refused, and nothing of
     * the update is taken: the next solve is that of the first problem. */
    frix_scene_params prm;
    frix_scene_defaults(FRIX_SCENE_SPHERES, &prm);
    prm.count = 3;
    frix_scene bigger;
    frix_scene_problems bigger_forms;
    ck_assert_int_eq(frix_scene_build(&prm, &bigger, NULL), FRIX_OK);
    ck_assert_int_eq(frix_scene_problems_make(&bigger, &bigger_forms), FRIX_OK);
    ck_assert_int_eq(frix_persistent_update_local(ps, bigger_forms.W, s.forms[1].q, NULL), FRIX_ERR_DIMENSION);
    double *bad_q = malloc(sizeof *bad_q * (size_t)m), *bad_mu = malloc(sizeof *bad_mu * (size_t)nc);
    memcpy(bad_q, s.forms[1].q, sizeof *bad_q * (size_t)m);
    bad_q[1] = NAN;
    ck_assert_int_eq(frix_persistent_update_local(ps, NULL, bad_q, NULL), FRIX_ERR_NOT_FINITE);
    for (int64_t a = 0; a < nc; ++a) bad_mu[a] = 0.5;
    bad_mu[0] = -1.0;
    ck_assert_int_eq(frix_persistent_update_local(ps, s.forms[1].W, s.forms[1].q, bad_mu), FRIX_ERR_INVALID_ARGUMENT);
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    double *r1 = calloc((size_t)m, sizeof *r1);
    ck_assert_int_eq(frix_persistent_solve(ps, r, u, NULL, info), FRIX_OK);
    ck_assert_int_eq(frix_solve(s.forms[0].local, NULL, r1, u, NULL, NULL), FRIX_OK);
    for (int64_t i = 0; i < m; ++i) ck_assert_double_eq_tol(r[i], r1[i], 1e-9 * (1.0 + fabs(r1[i])));

    frix_persistent_free(ps);
    frix_info_free(info);
    frix_scene_problems_free(&bigger_forms);
    frix_scene_free(&bigger);
    free(bad_q);
    free(bad_mu);
    free(r);
    free(r1);
    free(u);
    free_sequence(&s);
}
END_TEST

/* Every solver of local problems, step after step from the previous answer: the persistent
 * solver converges where frix_solve does, to the same answer within the tolerance, with no
 * more factorisations. */
static void same_answers(int solver, int global) {
    sequence s;
    make_sequence(&s, 3);
    const int64_t nc = s.scene[0].nc, n = s.scene[0].n, m = 3 * nc;
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(solver, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 1e-8), FRIX_OK);
    double *r1 = calloc((size_t)m, sizeof *r1), *rp = calloc((size_t)m, sizeof *rp);
    double *u = calloc((size_t)m, sizeof *u), *v = calloc((size_t)n, sizeof *v);
    frix_info *i1 = NULL, *ip = NULL;
    ck_assert_int_eq(frix_info_create(&i1), FRIX_OK);
    ck_assert_int_eq(frix_info_create(&ip), FRIX_OK);
    frix_persistent *ps = NULL;
    for (int k = 0; k < s.steps; ++k) {
        frix_problem *p = global ? s.forms[k].global : s.forms[k].local;
        if (k == 0) {
            ck_assert_int_eq(frix_persistent_create(p, o, &ps), FRIX_OK);
        } else if (global) {
            ck_assert_int_eq(frix_persistent_update_global(ps, s.forms[k].M, s.forms[k].H, s.scene[k].f, s.scene[k].w,
                                                           s.scene[k].mu),
                             FRIX_OK);
        } else {
            ck_assert_int_eq(frix_persistent_update_local(ps, s.forms[k].W, s.forms[k].q, s.scene[k].mu), FRIX_OK);
        }
        memcpy(rp, r1, sizeof *r1 * (size_t)m);  /* both from the one-shot answer of step k-1 */
        ck_assert_int_eq(frix_solve(p, o, r1, u, v, i1), FRIX_OK);
        ck_assert_int_eq(frix_persistent_solve(ps, rp, u, v, ip), FRIX_OK);
        ck_assert_int_eq(frix_info_status(ip), frix_info_status(i1));
        ck_assert_int_le(info_int(ip, FRIX_INFO_FACTORIZATIONS), info_int(i1, FRIX_INFO_FACTORIZATIONS));
        ck_assert_int_le(info_int(ip, FRIX_INFO_SYMBOLIC_ANALYSES), info_int(i1, FRIX_INFO_SYMBOLIC_ANALYSES));
        if (frix_info_status(i1) == FRIX_STATUS_CONVERGED) {
            ck_assert_double_le(frix_info_error(ip), 1e-8);
            double scale = 0.0;
            for (int64_t i = 0; i < m; ++i) scale = fmax(scale, fabs(r1[i]));
            double diff = 0.0;
            for (int64_t i = 0; i < m; ++i) diff = fmax(diff, fabs(rp[i] - r1[i]));
            /* The answer is unique in u, not always in r (redundant contacts): compare the
             * answers' errors on each other's problem instead where r differs. */
            if (diff > 1e-5 * scale) {
                double e = 0.0;
                ck_assert_int_eq(frix_problem_error(p, rp, global ? v : NULL, &e), FRIX_OK);
                ck_assert_double_le(e, 1e-8);
            }
        }
    }
    frix_persistent_free(ps);
    frix_info_free(i1);
    frix_info_free(ip);
    frix_options_free(o);
    free(r1);
    free(rp);
    free(u);
    free(v);
    free_sequence(&s);
}

static const int kSolvers[] = {FRIX_SOLVER_NSGS, FRIX_SOLVER_NSN_AC,  FRIX_SOLVER_PROX, FRIX_SOLVER_ADMM,
                               FRIX_SOLVER_IPM,  FRIX_SOLVER_IPM_ANM, FRIX_SOLVER_AUTO};

START_TEST(test_same_answers_local) { same_answers(kSolvers[_i], 0); }
END_TEST

START_TEST(test_same_answers_global) { same_answers(kSolvers[_i], 1); }
END_TEST

START_TEST(test_same_answers_native_global) { same_answers(FRIX_SOLVER_GLOBAL_NSN_AC, 1); }
END_TEST

/* A warm start that already meets the tolerance is the answer, unchanged, after no iteration
 * (a time step at rest); one that does not, or one short of a tighter tolerance, is iterated.
 * frix_solve and the persistent solver alike, for the local form. */
static void start_that_solves(int solver) {
    sequence s;
    make_sequence(&s, 3);
    frix_problem *p = s.forms[0].local;
    const int64_t m = 3 * s.scene[0].nc;
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(solver, &o), FRIX_OK);
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 1e-8), FRIX_OK);
    double *star = calloc((size_t)m, sizeof *star), *r = calloc((size_t)m, sizeof *r);
    double *u = calloc((size_t)m, sizeof *u);
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_solve(p, o, star, u, NULL, info), FRIX_OK);
    ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_CONVERGED);
    ck_assert_int_gt(frix_info_iterations(info), 0);
    const double found = frix_info_error(info);

    memcpy(r, star, sizeof *r * (size_t)m);
    ck_assert_int_eq(frix_solve(p, o, r, u, NULL, info), FRIX_OK);
    ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_CONVERGED);
    ck_assert_int_eq(frix_info_iterations(info), 0);
    ck_assert_double_eq(frix_info_error(info), found);
    ck_assert_mem_eq(r, star, sizeof *r * (size_t)m);

    frix_persistent *ps = NULL;
    ck_assert_int_eq(frix_persistent_create(p, o, &ps), FRIX_OK);
    memcpy(r, star, sizeof *r * (size_t)m);
    ck_assert_int_eq(frix_persistent_solve(ps, r, u, NULL, info), FRIX_OK);
    ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_CONVERGED);
    ck_assert_int_eq(frix_info_iterations(info), 0);
    ck_assert_mem_eq(r, star, sizeof *r * (size_t)m);
    frix_persistent_free(ps);

    /* Half the answer misses the tolerance: iterated. */
    for (int64_t i = 0; i < m; ++i) r[i] = 0.5 * star[i];
    ck_assert_int_eq(frix_solve(p, o, r, u, NULL, info), FRIX_OK);
    ck_assert_int_gt(frix_info_iterations(info), 0);
    /* The answer itself, against a tolerance below its error: iterated too. */
    ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 0.5 * found), FRIX_OK);
    memcpy(r, star, sizeof *r * (size_t)m);
    ck_assert_int_eq(frix_solve(p, o, r, u, NULL, info), FRIX_OK);
    ck_assert_int_gt(frix_info_iterations(info), 0);
    frix_info_free(info);
    frix_options_free(o);
    free(star), free(r), free(u);
    free_sequence(&s);
}

/* Those of kSolvers that solve the pyramid to 1e-8 from r = 0. */
static const int kStartSolvers[] = {FRIX_SOLVER_NSGS, FRIX_SOLVER_ADMM, FRIX_SOLVER_IPM, FRIX_SOLVER_IPM_ANM,
                                    FRIX_SOLVER_AUTO};

START_TEST(test_start_that_solves) { start_that_solves(kStartSolvers[_i]); }
END_TEST

/* A stack of 40 cubes on 4 contacts a face (160 contacts: sparse systems, above the dense
 * sizes), its frames turned by `turn`. */
static void make_stack(frix_scene *scene, frix_scene_problems *forms, double turn) {
    frix_scene_params prm;
    frix_scene_defaults(FRIX_SCENE_STACK, &prm);
    prm.count = 40;
    prm.per_face = 4;
    prm.frame_angle = turn;
    ck_assert_int_eq(frix_scene_build(&prm, scene, NULL), FRIX_OK);
    ck_assert_int_eq(frix_scene_problems_make(scene, forms), FRIX_OK);
}

/* What is kept: solving the same problem twice, the second solve analyses nothing again
 * (Newton: the same active set; admm: the same pattern), and a global problem whose M and H
 * stay is neither factorised nor reduced again. */
START_TEST(test_kept_between_solves) {
    sequence s;
    s.steps = 3;
    for (int k = 0; k < s.steps; ++k) make_stack(&s.scene[k], &s.forms[k], 0.05 * k);
    for (int64_t b = 0; b < s.scene[2].bodies; ++b) s.scene[2].f[6 * b + 1] *= 1.1;
    const int64_t nc = s.scene[1].nc, n = s.scene[1].n, m = 3 * nc;
    double *r = calloc((size_t)m, sizeof *r), *u = calloc((size_t)m, sizeof *u), *v = calloc((size_t)n, sizeof *v);
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    const int solvers[] = {FRIX_SOLVER_NSN_AC, FRIX_SOLVER_ADMM, FRIX_SOLVER_IPM};
    double *q_next = malloc(sizeof *q_next * (size_t)m);  /* a load 5% heavier */
    for (int64_t i = 0; i < m; ++i) q_next[i] = 1.05 * s.forms[1].q[i];
    for (size_t j = 0; j < sizeof solvers / sizeof *solvers; ++j) {
        frix_options *o = NULL;
        ck_assert_int_eq(frix_options_create(solvers[j], &o), FRIX_OK);
        ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 1e-6), FRIX_OK);
        frix_persistent *ps = NULL;
        ck_assert_int_eq(frix_persistent_create(s.forms[1].local, o, &ps), FRIX_OK);
        memset(r, 0, sizeof *r * (size_t)m);
        ck_assert_int_eq(frix_persistent_solve(ps, r, u, NULL, info), FRIX_OK);
        ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_CONVERGED);
        ck_assert_int_ge(info_int(info, FRIX_INFO_SYMBOLIC_ANALYSES), 1);
        const int64_t first_factorizations = info_int(info, FRIX_INFO_FACTORIZATIONS);
        /* The next step (another q, the same W) from the last answer: Newton's active set is
         * the last one's, ipm's and admm's systems have W's pattern. */
        ck_assert_int_eq(frix_persistent_update_local(ps, NULL, q_next, NULL), FRIX_OK);
        ck_assert_int_eq(frix_persistent_solve(ps, r, u, NULL, info), FRIX_OK);
        ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_CONVERGED);
        ck_assert_int_gt(info_int(info, FRIX_INFO_ITERATIONS), 0);
        ck_assert_int_eq(info_int(info, FRIX_INFO_SYMBOLIC_ANALYSES), 0);
        /* Newton and ipm factorise their iterate's system; admm finds its starting rho's
         * factorisation kept. */
        if (solvers[j] == FRIX_SOLVER_ADMM)
            ck_assert_int_lt(info_int(info, FRIX_INFO_FACTORIZATIONS), first_factorizations);
        else
            ck_assert_int_ge(info_int(info, FRIX_INFO_FACTORIZATIONS), 1);
        /* New values of W, same pattern: still no analysis for admm (the pattern of W + rho I
         * is W's). */
        if (solvers[j] == FRIX_SOLVER_ADMM) {
            ck_assert_int_eq(frix_persistent_update_local(ps, s.forms[2].W, s.forms[2].q, NULL), FRIX_OK);
            ck_assert_int_eq(frix_persistent_solve(ps, r, u, NULL, info), FRIX_OK);
            ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_CONVERGED);
            ck_assert_int_eq(info_int(info, FRIX_INFO_SYMBOLIC_ANALYSES), 0);
        }
        frix_persistent_free(ps);
        frix_options_free(o);
    }
    /* Global, nsgs through W = H^T M^-1 H: the first solve factorises M (rigid bodies: M is
     * diagonal, one factorisation), the next ones with a new f only do not. */
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_NSGS, &o), FRIX_OK);
    frix_persistent *ps = NULL;
    ck_assert_int_eq(frix_persistent_create(s.forms[1].global, o, &ps), FRIX_OK);
    ck_assert_int_eq(frix_persistent_solve(ps, r, u, v, info), FRIX_OK);
    ck_assert_int_eq(info_int(info, FRIX_INFO_FACTORIZATIONS), 1);
    ck_assert_int_eq(frix_persistent_update_global(ps, NULL, NULL, s.scene[2].f, NULL, NULL), FRIX_OK);
    double *r1 = malloc(sizeof *r1 * (size_t)m), *v1 = malloc(sizeof *v1 * (size_t)n);
    memcpy(r1, r, sizeof *r1 * (size_t)m);
    ck_assert_int_eq(frix_persistent_solve(ps, r, u, v, info), FRIX_OK);
    ck_assert_int_eq(info_int(info, FRIX_INFO_FACTORIZATIONS), 0);
    /* The same answer as frix_solve on that problem, whose W is the same to the last bit. */
    frix_problem *check = NULL;
    ck_assert_int_eq(frix_problem_global(s.forms[1].M, s.forms[1].H, s.scene[2].f, s.scene[1].w, s.scene[1].mu,
                                         nc, &check),
                     FRIX_OK);
    frix_info *one_shot = NULL;
    ck_assert_int_eq(frix_info_create(&one_shot), FRIX_OK);
    ck_assert_int_eq(frix_solve(check, o, r1, u, v1, one_shot), FRIX_OK);
    ck_assert_int_eq(info_int(one_shot, FRIX_INFO_FACTORIZATIONS), 1);
    ck_assert_int_eq(frix_info_status(info), frix_info_status(one_shot));
    ck_assert_int_eq(frix_info_iterations(info), frix_info_iterations(one_shot));
    for (int64_t i = 0; i < m; ++i) ck_assert_double_eq_tol(r[i], r1[i], 1e-12 * (1.0 + fabs(r1[i])));
    frix_info_free(one_shot);
    free(r1);
    free(v1);
    /* auto keeps the same for the reduction it runs: with M and H kept, fewer factorisations
     * than frix_solve from the same start (which factorises M for the driver and for auto's
     * reduction). */
    {
        frix_persistent *pa = NULL;
        ck_assert_int_eq(frix_persistent_create(s.forms[1].global, NULL, &pa), FRIX_OK);
        memset(r, 0, sizeof *r * (size_t)m);
        ck_assert_int_eq(frix_persistent_solve(pa, r, u, v, info), FRIX_OK);
        ck_assert_int_eq(frix_persistent_update_global(pa, NULL, NULL, s.scene[2].f, NULL, NULL), FRIX_OK);
        double *ra = malloc(sizeof *ra * (size_t)m), *va = malloc(sizeof *va * (size_t)n);
        memcpy(ra, r, sizeof *ra * (size_t)m);
        frix_info *one = NULL;
        ck_assert_int_eq(frix_info_create(&one), FRIX_OK);
        ck_assert_int_eq(frix_solve(check, NULL, ra, u, va, one), FRIX_OK);
        ck_assert_int_eq(frix_persistent_solve(pa, r, u, v, info), FRIX_OK);
        ck_assert_int_eq(frix_info_status(info), frix_info_status(one));
        ck_assert_int_lt(info_int(info, FRIX_INFO_FACTORIZATIONS), info_int(one, FRIX_INFO_FACTORIZATIONS));
        frix_info_free(one);
        free(ra);
        free(va);
        frix_persistent_free(pa);
    }
    /* A new M is factorised again. */
    ck_assert_int_eq(frix_persistent_update_global(ps, s.forms[1].M, NULL, NULL, NULL, NULL), FRIX_OK);
    ck_assert_int_eq(frix_persistent_solve(ps, r, u, v, info), FRIX_OK);
    ck_assert_int_eq(info_int(info, FRIX_INFO_FACTORIZATIONS), 1);
    frix_problem_free(check);
    frix_persistent_free(ps);
    frix_options_free(o);
    frix_info_free(info);
    free(q_next);
    free(r);
    free(u);
    free(v);
    free_sequence(&s);
}
END_TEST

/* A W of another pattern (the same size) is analysed again: each solver then gives what
 * frix_solve gives on the new problem. */
START_TEST(test_new_pattern) {
    frix_scene scene;
    frix_scene_problems forms;
    make_stack(&scene, &forms, 0.0);
    const int64_t nc = scene.nc, m = 3 * nc;
    /* W's diagonal blocks alone: contacts decoupled, another pattern. */
    int64_t *idx = malloc(sizeof *idx * (size_t)nc);
    double *blocks = malloc(sizeof *blocks * 9 * (size_t)nc);
    for (int64_t a = 0; a < nc; ++a) {
        idx[a] = a;
        ck_assert_int_eq(frix_matrix_diagonal_block(forms.W, a, &blocks[9 * a]), FRIX_OK);
    }
    frix_matrix *D = NULL;
    ck_assert_int_eq(frix_matrix_from_blocks(nc, nc, nc, idx, idx, blocks, &D), FRIX_OK);
    frix_problem *pd = NULL;
    ck_assert_int_eq(frix_problem_local(D, forms.q, scene.mu, nc, &pd), FRIX_OK);
    double *r = calloc((size_t)m, sizeof *r), *r1 = calloc((size_t)m, sizeof *r1), *u = calloc((size_t)m, sizeof *u);
    frix_info *info = NULL, *one = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_info_create(&one), FRIX_OK);
    const int solvers[] = {FRIX_SOLVER_NSN_AC, FRIX_SOLVER_PROX,     FRIX_SOLVER_ADMM,
                           FRIX_SOLVER_IPM,    FRIX_SOLVER_IPM_ANM, FRIX_SOLVER_AUTO};
    for (size_t j = 0; j < sizeof solvers / sizeof *solvers; ++j) {
        frix_options *o = NULL;
        ck_assert_int_eq(frix_options_create(solvers[j], &o), FRIX_OK);
        ck_assert_int_eq(frix_options_set_double(o, FRIX_OPT_TOLERANCE, 1e-6), FRIX_OK);
        frix_persistent *ps = NULL;
        ck_assert_int_eq(frix_persistent_create(forms.local, o, &ps), FRIX_OK);
        memset(r, 0, sizeof *r * (size_t)m);
        ck_assert_int_eq(frix_persistent_solve(ps, r, u, NULL, info), FRIX_OK);
        ck_assert_int_eq(frix_persistent_update_local(ps, D, NULL, NULL), FRIX_OK);
        memset(r, 0, sizeof *r * (size_t)m);
        memset(r1, 0, sizeof *r1 * (size_t)m);
        ck_assert_int_eq(frix_persistent_solve(ps, r, u, NULL, info), FRIX_OK);
        ck_assert_int_eq(frix_solve(pd, o, r1, u, NULL, one), FRIX_OK);
        ck_assert_int_eq(frix_info_status(info), frix_info_status(one));
        ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_CONVERGED);
        double e = 0.0;
        ck_assert_int_eq(frix_problem_error(pd, r, NULL, &e), FRIX_OK);
        ck_assert_double_le(e, 1e-6);
        frix_persistent_free(ps);
        frix_options_free(o);
    }
    frix_info_free(info);
    frix_info_free(one);
    frix_problem_free(pd);
    frix_matrix_free(D);
    free(idx);
    free(blocks);
    free(r);
    free(r1);
    free(u);
    frix_scene_problems_free(&forms);
    frix_scene_free(&scene);
}
END_TEST

/* The persistent solver borrows the data, not the problem handle. */
START_TEST(test_problem_handle_freed) {
    sequence s;
    make_sequence(&s, 2);
    const int64_t nc = s.scene[0].nc, m = 3 * nc;
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_problem_local(s.forms[0].W, s.forms[0].q, s.scene[0].mu, nc, &p), FRIX_OK);
    frix_persistent *ps = NULL;
    ck_assert_int_eq(frix_persistent_create(p, NULL, &ps), FRIX_OK);
    frix_problem_free(p);
    double *r = calloc((size_t)m, sizeof *r), *u = calloc((size_t)m, sizeof *u);
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_persistent_solve(ps, r, u, NULL, info), FRIX_OK);
    ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_CONVERGED);
    frix_persistent_free(ps);
    frix_info_free(info);
    free(r);
    free(u);
    free_sequence(&s);
}
END_TEST

/* Two persistent solvers on the same borrowed data, in two threads at once: each gives what
 * it gives alone (the data is only read; nothing else is shared). */
typedef struct worker {
    const sequence *s;
    int solver;
    double *r;  /* 3nc, the last step's answer */
    int64_t iterations;
    frix_error err;
} worker;

static void *run_steps(void *arg) {
    worker *w = arg;
    const sequence *s = w->s;
    const int64_t m = 3 * s->scene[0].nc;
    double *u = calloc((size_t)m, sizeof *u);
    frix_options *o = NULL;
    frix_info *info = NULL;
    frix_persistent *ps = NULL;
    w->err = frix_options_create(w->solver, &o);
    if (!w->err) w->err = frix_info_create(&info);
    if (!w->err) w->err = frix_persistent_create(s->forms[0].local, o, &ps);
    memset(w->r, 0, sizeof *w->r * (size_t)m);
    w->iterations = 0;
    for (int k = 0; k < s->steps && !w->err; ++k) {
        w->err = frix_persistent_update_local(ps, s->forms[k].W, s->forms[k].q, NULL);
        if (!w->err) w->err = frix_persistent_solve(ps, w->r, u, NULL, info);
        w->iterations += frix_info_iterations(info);
    }
    frix_persistent_free(ps);
    frix_info_free(info);
    frix_options_free(o);
    free(u);
    return NULL;
}

START_TEST(test_threads_share_data) {
    sequence s;
    make_sequence(&s, 3);
    const int64_t m = 3 * s.scene[0].nc;
    const int solvers[2] = {FRIX_SOLVER_NSN_AC, FRIX_SOLVER_ADMM};
    worker alone[2], together[2];
    for (int t = 0; t < 2; ++t) {
        alone[t] = (worker){&s, solvers[t], malloc(sizeof(double) * (size_t)m), 0, FRIX_OK};
        together[t] = (worker){&s, solvers[t], malloc(sizeof(double) * (size_t)m), 0, FRIX_OK};
        run_steps(&alone[t]);
        ck_assert_int_eq(alone[t].err, FRIX_OK);
    }
    pthread_t th[2];
    for (int t = 0; t < 2; ++t) ck_assert_int_eq(pthread_create(&th[t], NULL, run_steps, &together[t]), 0);
    for (int t = 0; t < 2; ++t) ck_assert_int_eq(pthread_join(th[t], NULL), 0);
    for (int t = 0; t < 2; ++t) {
        ck_assert_int_eq(together[t].err, FRIX_OK);
        ck_assert_int_eq(together[t].iterations, alone[t].iterations);
        ck_assert_mem_eq(together[t].r, alone[t].r, sizeof(double) * (size_t)m);
        free(alone[t].r);
        free(together[t].r);
    }
    free_sequence(&s);
}
END_TEST

START_TEST(test_plugin_table_versions) {
    const frix_plugin_table *v1 = frix_plugin_api(1), *v2 = frix_plugin_api(2), *v3 = frix_plugin_api(3),
                            *v4 = frix_plugin_api(4), *v5 = frix_plugin_api(5), *v6 = frix_plugin_api(6);
    ck_assert_ptr_nonnull(v1);
    ck_assert_ptr_nonnull(v2);
    ck_assert_ptr_nonnull(v3);
    ck_assert_ptr_nonnull(v4);
    ck_assert_ptr_nonnull(v5);
    ck_assert_ptr_nonnull(v6);
    ck_assert_int_eq(v6->abi_version, 6);
    ck_assert_int_eq(v5->abi_version, 5);
    ck_assert_int_eq(v4->abi_version, 4);
    ck_assert_int_eq(v1->abi_version, 1);
    ck_assert_int_eq(v2->abi_version, 2);
    ck_assert_int_eq(v3->abi_version, 3);
    ck_assert_uint_eq(v1->size, offsetof(frix_plugin_table, persistent_create));
    ck_assert_uint_eq(v2->size, offsetof(frix_plugin_table, persistent_set_contacts_local));
    ck_assert_uint_eq(v3->size, offsetof(frix_plugin_table, option_choice_name));
    ck_assert_uint_eq(v4->size, offsetof(frix_plugin_table, problem_rolling_local));
    ck_assert_uint_eq(v5->size, offsetof(frix_plugin_table, problem_spinning_local));
    ck_assert_uint_eq(v6->size, sizeof(frix_plugin_table));
    ck_assert(FRIX_PLUGIN_HAS(v5, persistent_update_mu_r));
    ck_assert(!FRIX_PLUGIN_HAS(v5, problem_spinning_local));
    ck_assert(FRIX_PLUGIN_HAS(v6, persistent_update_mu_s));
    ck_assert_ptr_eq(v6->problem_spinning_local, frix_problem_spinning_local);
    ck_assert_ptr_eq(v6->problem_spinning_global, frix_problem_spinning_global);
    ck_assert_ptr_eq(v6->problem_mu_s, frix_problem_mu_s);
    ck_assert_ptr_eq(v6->persistent_set_contacts_spinning_local, frix_persistent_set_contacts_spinning_local);
    ck_assert_ptr_eq(v6->persistent_set_contacts_spinning_global, frix_persistent_set_contacts_spinning_global);
    ck_assert_ptr_eq(v6->persistent_update_mu_s, frix_persistent_update_mu_s);
    ck_assert_ptr_eq(v6->problem_rolling_local, v5->problem_rolling_local);
    ck_assert(!FRIX_PLUGIN_HAS(v4, problem_rolling_local));
    ck_assert(FRIX_PLUGIN_HAS(v5, fclib_write_compressed));
    ck_assert_ptr_eq(v5->problem_rolling_global, frix_problem_rolling_global);
    ck_assert_ptr_eq(v5->problem_math_info, frix_problem_math_info);
    ck_assert_ptr_eq(v5->persistent_update_mu_r, frix_persistent_update_mu_r);
    ck_assert(!FRIX_PLUGIN_HAS(v3, options_set_by_name));
    ck_assert(FRIX_PLUGIN_HAS(v4, options_set_by_name));
    ck_assert_ptr_eq(v4->options_set_by_name, frix_options_set_by_name);
    ck_assert(FRIX_PLUGIN_HAS(v1, info_stage_note));
    ck_assert(!FRIX_PLUGIN_HAS(v1, persistent_create));
    ck_assert(FRIX_PLUGIN_HAS(v2, persistent_update_global));
    ck_assert(!FRIX_PLUGIN_HAS(v2, persistent_set_contacts_local));
    ck_assert(FRIX_PLUGIN_HAS(v3, persistent_set_contacts_global));
    ck_assert_ptr_eq(v2->persistent_solve, frix_persistent_solve);
    ck_assert_ptr_eq(v3->persistent_set_contacts_global, frix_persistent_set_contacts_global);
    ck_assert_ptr_eq(v1->solve, v2->solve);
    ck_assert_ptr_null(frix_plugin_api(7));
    ck_assert_ptr_null(frix_plugin_api(0));
}
END_TEST

/* A rolling problem made, described and solved through the version-5 table alone: one contact
 * pressed on (q_N < 0, W = I): r = (-q_N, 0, 0, 0, 0) with u = 0 normal, at rest. */
START_TEST(test_plugin_table_rolling) {
    const frix_plugin_table *fx = frix_plugin_api(5);
    ck_assert(FRIX_PLUGIN_HAS(fx, problem_rolling_local));
    double dense[25] = {0}, q[5] = {-2.0, 0.1, 0.0, 0.05, 0.0}, mu = 0.5, mu_r = 0.1;
    for (int i = 0; i < 5; ++i) dense[6 * i] = 1.0;
    frix_matrix *W = NULL;
    ck_assert_int_eq(fx->matrix_from_dense(5, 5, dense, 5, &W), FRIX_OK);
    frix_problem *p = NULL;
    ck_assert_int_eq(fx->problem_rolling_local(W, q, &mu, &mu_r, 1, &p), FRIX_OK);
    ck_assert_int_eq(fx->problem_get_kind(p), FRIX_PROBLEM_ROLLING_LOCAL);
    ck_assert_double_eq(fx->problem_mu_r(p)[0], 0.1);
    ck_assert_int_eq(fx->problem_set_description(p, "one contact"), FRIX_OK);
    ck_assert_str_eq(fx->problem_description(p), "one contact");
    double r[5] = {0}, u[5] = {0};
    frix_info *info = NULL;
    ck_assert_int_eq(fx->info_create(&info), FRIX_OK);
    ck_assert_int_eq(fx->solve(p, NULL, r, u, NULL, info), FRIX_OK);
    ck_assert_int_eq(fx->info_status(info), FRIX_STATUS_CONVERGED);
    ck_assert_double_eq_tol(r[0], 2.0, 1e-8);
    ck_assert_double_eq_tol(u[0], 0.0, 1e-8);
    fx->info_free(info);
    fx->problem_free(p);
    fx->matrix_free(W);
}
END_TEST

/* A problem with spinning friction made and measured through the version-6 table alone: W = I,
 * q = (-1, 0, 0, 0, 0, 0.05), mu_s = 0.02: r = (1, 0, 0, 0, 0, -0.02) spins against w_S = 0.03
 * on the spinning bound, error 0 (tests/test_spinning.c works the case by hand). */
START_TEST(test_plugin_table_spinning) {
    const frix_plugin_table *fx = frix_plugin_api(6);
    ck_assert(FRIX_PLUGIN_HAS(fx, problem_spinning_local));
    double dense[36] = {0}, q[6] = {-1.0, 0.0, 0.0, 0.0, 0.0, 0.05}, mu = 0.5, mu_r = 0.01, mu_s = 0.02;
    for (int i = 0; i < 6; ++i) dense[7 * i] = 1.0;
    frix_matrix *W = NULL;
    ck_assert_int_eq(fx->matrix_from_dense(6, 6, dense, 6, &W), FRIX_OK);
    frix_problem *p = NULL;
    ck_assert_int_eq(fx->problem_spinning_local(W, q, &mu, &mu_r, &mu_s, 1, &p), FRIX_OK);
    ck_assert_int_eq(fx->problem_get_kind(p), FRIX_PROBLEM_ROLLING_LOCAL);
    ck_assert_int_eq(fx->problem_contact_dofs(p), 6);
    ck_assert_double_eq(fx->problem_mu_s(p)[0], 0.02);
    double r[6] = {1.0, 0.0, 0.0, 0.0, 0.0, -0.02}, u[6] = {0}, e = NAN;
    frix_info *info = NULL;
    ck_assert_int_eq(fx->info_create(&info), FRIX_OK);
    ck_assert_int_eq(fx->problem_measure(p, r, NULL, u, info), FRIX_OK);
    ck_assert_int_eq(fx->info_get_double(info, FRIX_INFO_ERROR_RELATIVE, &e), FRIX_OK);
    ck_assert_double_le(e, 1e-15);
    ck_assert_double_eq_tol(u[5], 0.03, 1e-15);
    /* The global form, and the rolling constructor's refusal of six entries a contact. */
    frix_matrix *M = NULL, *H = NULL;
    ck_assert_int_eq(fx->matrix_from_dense(6, 6, dense, 6, &M), FRIX_OK);
    ck_assert_int_eq(fx->matrix_from_dense(6, 6, dense, 6, &H), FRIX_OK);
    double f[6] = {0}, w[6] = {0};
    frix_problem *g = NULL;
    ck_assert_int_eq(fx->problem_spinning_global(M, H, f, w, &mu, &mu_r, &mu_s, 1, &g), FRIX_OK);
    ck_assert_ptr_eq(fx->problem_mu_s(g), &mu_s);
    fx->problem_free(g);
    ck_assert_int_eq(fx->problem_rolling_local(W, q, &mu, &mu_r, 1, &g), FRIX_ERR_DIMENSION);
    fx->info_free(info);
    fx->problem_free(p);
    fx->matrix_free(H);
    fx->matrix_free(M);
    fx->matrix_free(W);
}
END_TEST

/* r from frix_persistent_solve and from frix_solve of the same problem, both from r = 0:
 * equal within the tolerance's scale. */
static void assert_solves_as_one_shot(frix_persistent *ps, const frix_problem *p) {
    const int64_t m = frix_problem_contact_dofs(p), n = frix_problem_dofs(p);
    double *r = calloc((size_t)m + 1, sizeof *r), *r1 = calloc((size_t)m + 1, sizeof *r1);
    double *u = calloc((size_t)m + 1, sizeof *u), *v = calloc((size_t)n + 1, sizeof *v);
    frix_info *info = NULL;
    ck_assert_int_eq(frix_info_create(&info), FRIX_OK);
    ck_assert_int_eq(frix_persistent_solve(ps, r, u, v, info), FRIX_OK);
    ck_assert_int_eq(frix_info_status(info), FRIX_STATUS_CONVERGED);
    ck_assert_int_eq(frix_solve(p, NULL, r1, u, v, NULL), FRIX_OK);
    double scale = 1.0;
    for (int64_t i = 0; i < m; ++i) scale = fmax(scale, fabs(r1[i]));
    for (int64_t i = 0; i < m; ++i) ck_assert_double_eq_tol(r[i], r1[i], 1e-4 * scale);
    frix_info_free(info);
    free(r);
    free(r1);
    free(u);
    free(v);
}

/* Contacts that come and go: set_contacts gives the next step's contacts whatever their
 * number, local (another scene's W) and global (the same bodies, half the contacts), and
 * back; a refused call replaces nothing. */
START_TEST(test_set_contacts) {
    sequence s;
    make_sequence(&s, 3);
    frix_scene_params prm;
    frix_scene_defaults(FRIX_SCENE_SPHERES, &prm);
    prm.count = 2;
    frix_scene other;
    frix_scene_problems other_forms;
    ck_assert_int_eq(frix_scene_build(&prm, &other, NULL), FRIX_OK);
    ck_assert_int_eq(frix_scene_problems_make(&other, &other_forms), FRIX_OK);
    ck_assert_int_ne(other.nc, s.scene[0].nc);

    frix_persistent *ps = NULL;
    ck_assert_int_eq(frix_persistent_create(s.forms[0].local, NULL, &ps), FRIX_OK);
    ck_assert_int_eq(frix_persistent_set_contacts_local(NULL, other_forms.W, other_forms.q, other.mu, other.nc),
                     FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_persistent_set_contacts_global(ps, other_forms.H, other.w, other.mu, other.nc),
                     FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_persistent_set_contacts_local(ps, other_forms.W, other_forms.q, other.mu, s.scene[0].nc),
                     FRIX_ERR_DIMENSION);
    assert_solves_as_one_shot(ps, s.forms[0].local);
    ck_assert_int_eq(frix_persistent_set_contacts_local(ps, other_forms.W, other_forms.q, other.mu, other.nc), FRIX_OK);
    assert_solves_as_one_shot(ps, other_forms.local);
    ck_assert_int_eq(frix_persistent_set_contacts_local(ps, s.forms[1].W, s.forms[1].q, s.scene[1].mu, s.scene[1].nc),
                     FRIX_OK);
    assert_solves_as_one_shot(ps, s.forms[1].local);
    frix_persistent_free(ps);

    /* The global form: the first half of the contacts (H's first columns), then all again. */
    const frix_scene *sc = &s.scene[0];
    const int64_t half = sc->nc / 2;
    int64_t nnz = 0;
    ck_assert_int_eq(frix_matrix_to_csc(s.forms[0].H, &nnz, NULL, NULL, NULL), FRIX_OK);
    int64_t *colptr = malloc(sizeof *colptr * (size_t)(3 * sc->nc + 1));
    int64_t *rowind = malloc(sizeof *rowind * (size_t)nnz);
    double *values = malloc(sizeof *values * (size_t)nnz);
    ck_assert_int_eq(frix_matrix_to_csc(s.forms[0].H, &nnz, colptr, rowind, values), FRIX_OK);
    frix_matrix *H_half = NULL;
    ck_assert_int_eq(frix_matrix_from_csc(sc->n, 3 * half, colptr, rowind, values, &H_half), FRIX_OK);
    frix_problem *p_half = NULL;
    ck_assert_int_eq(frix_problem_global(s.forms[0].M, H_half, sc->f, sc->w, sc->mu, half, &p_half), FRIX_OK);
    ck_assert_int_eq(frix_persistent_create(s.forms[0].global, NULL, &ps), FRIX_OK);
    ck_assert_int_eq(frix_persistent_set_contacts_local(ps, other_forms.W, other_forms.q, other.mu, other.nc),
                     FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_persistent_set_contacts_global(ps, H_half, sc->w, sc->mu, sc->nc), FRIX_ERR_DIMENSION);
    ck_assert_int_eq(frix_persistent_set_contacts_global(ps, other_forms.H, other.w, other.mu, other.nc),
                     FRIX_ERR_DIMENSION); /* another scene's bodies: H has other rows */
    assert_solves_as_one_shot(ps, s.forms[0].global);
    ck_assert_int_eq(frix_persistent_set_contacts_global(ps, H_half, sc->w, sc->mu, half), FRIX_OK);
    assert_solves_as_one_shot(ps, p_half);
    ck_assert_int_eq(frix_persistent_set_contacts_global(ps, s.forms[0].H, sc->w, sc->mu, sc->nc), FRIX_OK);
    assert_solves_as_one_shot(ps, s.forms[0].global);
    frix_persistent_free(ps);

    frix_problem_free(p_half);
    frix_matrix_free(H_half);
    free(colptr);
    free(rowind);
    free(values);
    frix_scene_problems_free(&other_forms);
    frix_scene_free(&other);
    free_sequence(&s);
}
END_TEST

int main(void) {
    Suite *s = suite_create("persistent");
    TCase *tc = tcase_create("persistent");
    tcase_set_timeout(tc, 600);
    tcase_add_test(tc, test_bad_input);
    tcase_add_loop_test(tc, test_same_answers_local, 0, (int)(sizeof kSolvers / sizeof *kSolvers));
    tcase_add_loop_test(tc, test_same_answers_global, 0, (int)(sizeof kSolvers / sizeof *kSolvers));
    tcase_add_test(tc, test_same_answers_native_global);
    tcase_add_loop_test(tc, test_start_that_solves, 0, (int)(sizeof kStartSolvers / sizeof *kStartSolvers));
    tcase_add_test(tc, test_kept_between_solves);
    tcase_add_test(tc, test_new_pattern);
    tcase_add_test(tc, test_problem_handle_freed);
    tcase_add_test(tc, test_threads_share_data);
    tcase_add_test(tc, test_plugin_table_versions);
    tcase_add_test(tc, test_plugin_table_rolling);
    tcase_add_test(tc, test_plugin_table_spinning);
    tcase_add_test(tc, test_set_contacts);
    suite_add_tcase(s, tc);
    return frix_run_suite(s);
}
