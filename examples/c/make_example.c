/* Writes the bundled example problem: one time step of a stack of boxes resting on the
 * ground, reduced to a local FCLIB problem (W, q, mu).
 *
 *   make_example OUT.hdf5 [BOXES]     (3 boxes by default)
 *
 * Each box touches the one below (the ground for the lowest) at the 4 corners of the
 * shared face. Four coplanar contacts per face are how collision detectors report
 * face contacts, and they make W = H^T M^-1 H rank-deficient (12 contacts, 36 unknowns,
 * only 18 body velocities): the contact forces are not unique, which is the usual case
 * solvers must cope with. A horizontal push on the top box (below mu times its weight)
 * makes friction hold it in place, so the solution exercises the friction cone too.
 */
#include <frix/frix.h>

#include <stdio.h>
#include <stdlib.h>

#define MAX_BOXES 64

static const double SIDE = 1.0;  /* cube edge, m */
static const double MASS = 1.0;  /* kg */
static const double MU = 0.5;
static const double STEP = 0.01; /* time step h, s */
static const double GRAVITY = 9.81;
static const double PUSH = 2.0;  /* N on the top box: mu m g = 4.9 N, so it sticks */

/* Contact a lies between body `upper` and body `lower` (-1 for the ground). Its frame is
 * (n, t1, t2) = (e_z, e_x, e_y): n points from lower to upper, so u_N > 0 separates. */
typedef struct {
    int upper, lower;
    double point[3];
} contact;

static void cross(const double a[3], const double b[3], double out[3]) {
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

/* Row i of the 3x6 block G of H^T linking contact c to body b: the contact velocity is
 * u = sum_b G_b (v_b, w_b) with the point velocity v + w x d = v + (d x e_i) . w along e_i.
 * The lower body enters with a minus sign. Returns 0 if b is not part of the contact. */
static int jacobian(const contact *c, int b, double G[3][6]) {
    static const double frame[3][3] = {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}};
    double sign = b == c->upper ? 1.0 : b == c->lower ? -1.0 : 0.0;
    if (sign == 0.0) return 0;
    double center[3] = {0, 0, SIDE / 2 + b * SIDE}, d[3], dxe[3];
    for (int k = 0; k < 3; ++k) d[k] = c->point[k] - center[k];
    for (int i = 0; i < 3; ++i) {
        cross(d, frame[i], dxe);
        for (int k = 0; k < 3; ++k) {
            G[i][k] = sign * frame[i][k];
            G[i][3 + k] = sign * dxe[k];
        }
    }
    return 1;
}

int main(int argc, char **argv) {
    if (argc < 2 || argc > 3) {
        fprintf(stderr, "usage: %s OUT.hdf5 [BOXES]\n", argv[0]);
        return 2;
    }
    int boxes = argc == 3 ? atoi(argv[2]) : 3;
    if (boxes < 1 || boxes > MAX_BOXES) {
        fprintf(stderr, "%s: BOXES must be in 1..%d\n", argv[0], MAX_BOXES);
        return 2;
    }
    const int nc = 4 * boxes;
    static contact contacts[4 * MAX_BOXES];
    for (int b = 0; b < boxes; ++b)
        for (int k = 0; k < 4; ++k) {
            contact *c = &contacts[4 * b + k];
            c->upper = b;
            c->lower = b - 1;
            c->point[0] = (k & 1 ? 0.5 : -0.5) * SIDE;
            c->point[1] = (k & 2 ? 0.5 : -0.5) * SIDE;
            c->point[2] = b * SIDE;
        }

    /* Diagonal of M^-1 per body (translation, then rotation; a cube's inertia is m s^2 / 6
     * about every axis through its centre) and the free velocity v_free = v_prev + h M^-1 f
     * with v_prev = 0: the stack starts at rest. */
    double minv[6], vfree[MAX_BOXES][6];
    for (int k = 0; k < 3; ++k) {
        minv[k] = 1.0 / MASS;
        minv[3 + k] = 6.0 / (MASS * SIDE * SIDE);
    }
    for (int b = 0; b < boxes; ++b) {
        double force[6] = {b == boxes - 1 ? PUSH : 0.0, 0, -MASS * GRAVITY, 0, 0, 0};
        for (int k = 0; k < 6; ++k) vfree[b][k] = STEP * minv[k] * force[k];
    }

    /* W = H^T M^-1 H has a block (a, c) only when contacts a and c share a body; each
     * shared body adds G_a M_b^-1 G_c^T, and frix_matrix_from_blocks sums duplicates, so
     * W is assembled body by body without ever forming H or a dense W. */
    static int64_t brow[MAX_BOXES * 64], bcol[MAX_BOXES * 64];
    static double bval[MAX_BOXES * 64 * 9];
    int64_t nblocks = 0;
    for (int b = 0; b < boxes; ++b) {
        int touching[8], nt = 0; /* 4 contacts below the box, 4 above */
        double G[8][3][6];
        for (int a = 0; a < nc; ++a)
            if (jacobian(&contacts[a], b, G[nt])) touching[nt++] = a;
        for (int i = 0; i < nt; ++i)
            for (int j = 0; j < nt; ++j) {
                double *blk = &bval[9 * nblocks];
                for (int r = 0; r < 3; ++r)
                    for (int c = 0; c < 3; ++c) {
                        double s = 0;
                        for (int k = 0; k < 6; ++k) s += G[i][r][k] * minv[k] * G[j][c][k];
                        blk[r + 3 * c] = s; /* column-major */
                    }
                brow[nblocks] = touching[i];
                bcol[nblocks] = touching[j];
                ++nblocks;
            }
    }

    /* q = H^T v_free: the contact velocities if no contact force acted. */
    static double q[3 * 4 * MAX_BOXES], mu[4 * MAX_BOXES];
    for (int a = 0; a < nc; ++a) {
        double G[3][6];
        mu[a] = MU;
        for (int i = 0; i < 3; ++i) q[3 * a + i] = 0.0;
        for (int b = 0; b < boxes; ++b)
            if (jacobian(&contacts[a], b, G))
                for (int i = 0; i < 3; ++i)
                    for (int k = 0; k < 6; ++k) q[3 * a + i] += G[i][k] * vfree[b][k];
    }

    frix_matrix *W = NULL;
    frix_problem *problem = NULL;
    frix_error err = frix_matrix_from_blocks(nc, nc, nblocks, brow, bcol, bval, &W);
    if (err == FRIX_OK) err = frix_problem_local(W, q, mu, nc, &problem);
    char title[80];
    snprintf(title, sizeof title, "frix example: %d boxes stacked on the ground", boxes);
    if (err == FRIX_OK) err = frix_problem_set_title(problem, title);
    if (err == FRIX_OK)
        err = frix_fclib_write(argv[1], problem, NULL, NULL, NULL, 0, NULL, NULL, NULL);
    if (err != FRIX_OK)
        fprintf(stderr, "%s: %s: %s\n", argv[0], frix_error_string(err), frix_last_error_message());
    else
        printf("wrote %s: %d boxes, %d contacts, W with %lld stored blocks\n", argv[1], boxes, nc,
               (long long)frix_matrix_block_count(W));
    frix_problem_free(problem); /* the problem borrows W, q and mu: free it first */
    frix_matrix_free(W);
    return err == FRIX_OK ? 0 : 1;
}
