/* libfrix_mpi and the handles a host's libfrix makes (options, info, problems), under mpiexec.
 *
 *   host_handles [same [LIBFRIX_VERSION]]
 *       The libraries of one release: every call that receives a handle accepts it, the solve
 *       fills the host's info, and the context reports its rank and size (on MPI_COMM_WORLD,
 *       on halves of it, on MPI_COMM_SELF). CTest runs it at np 1 and 2.
 *   host_handles refused LIBFRIX_VERSION LIBFRIX_MPI_VERSION
 *       libfrix and libfrix_mpi of different releases (tests/mpi/release_mismatch.sh loads such
 *       a pair): every call that receives a handle refuses it with FRIX_ERR_UNSUPPORTED and a
 *       message naming both releases, and the program ends normally; a solve without handles
 *       still runs.
 * LIBFRIX_VERSION, when given, must be the loaded libfrix's frix_version_string(). Exits 0
 * when every check holds on every rank. Public API only. */
#include <frix/frix.h>
#include <frix/frix_mpi.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define NC 6 /* contacts of the chain */

static int g_rank, g_size, g_failed;

#define EXPECT(cond, ...)                                              \
    do {                                                               \
        if (!(cond)) {                                                 \
            fprintf(stderr, "rank %d: line %d: ", g_rank, __LINE__);   \
            fprintf(stderr, __VA_ARGS__);                              \
            fputc('\n', stderr);                                       \
            g_failed = 1;                                              \
        }                                                              \
    } while (0)

/* A chain of NC contacts, each coupled to its neighbours: W block-tridiagonal (2 I on the
 * diagonal, I / 2 beside it), every contact approaching (q_n = -1). Row a's blocks, in
 * increasing columns, are those of chain_row. */
static int chain_row(int64_t a, int64_t *cols, double *vals) {
    int k = 0, i;
    int64_t b;
    for (b = a - 1; b <= a + 1; ++b) {
        if (b < 0 || b >= NC) continue;
        cols[k] = b;
        for (i = 0; i < 9; ++i) vals[9 * k + i] = i % 4 == 0 ? (b == a ? 2.0 : 0.5) : 0.0;
        ++k;
    }
    return k;
}

static const double g_q[3 * NC] = {-1, 0.2, 0, -1, 0.2, 0, -1, 0.2, 0, -1, 0.2, 0, -1, 0.2, 0, -1, 0.2, 0};
static const double g_mu[NC] = {0.3, 0.3, 0.3, 0.3, 0.3, 0.3};

/* The whole chain as a local problem (W) and as a global one (M = I, H = I, f = 0, w = q). */
static void chain_problems(frix_matrix **W, frix_matrix **I, frix_problem **local, frix_problem **global) {
    int64_t rows[3 * NC], cols[3 * NC], diag[NC];
    double vals[27 * NC], ones[9 * NC], f[3 * NC] = {0};
    int64_t n = 0, a;
    int k, i;
    for (a = 0; a < NC; ++a) {
        k = chain_row(a, cols + n, vals + 9 * n);
        for (i = 0; i < k; ++i) rows[n + i] = a;
        n += k;
        diag[a] = a;
        for (i = 0; i < 9; ++i) ones[9 * a + i] = i % 4 == 0 ? 1.0 : 0.0;
    }
    EXPECT(frix_matrix_from_blocks(NC, NC, n, rows, cols, vals, W) == FRIX_OK, "W: %s", frix_last_error_message());
    EXPECT(frix_matrix_from_blocks(NC, NC, NC, diag, diag, ones, I) == FRIX_OK, "I: %s", frix_last_error_message());
    EXPECT(frix_problem_local(*W, g_q, g_mu, NC, local) == FRIX_OK, "local: %s", frix_last_error_message());
    EXPECT(frix_problem_global(*I, *I, f, g_q, g_mu, NC, global) == FRIX_OK, "global: %s", frix_last_error_message());
}

/* This rank's rows of the chain, in blocks of the ranks (frix_mpi_problem_local). */
static frix_mpi_problem *chain_part(frix_mpi_context *ctx, int64_t *owned) {
    const int64_t first = NC * g_rank / g_size, end = NC * (g_rank + 1) / g_size;
    int64_t row_ptr[NC + 1] = {0}, cols[3 * NC], a;
    double vals[27 * NC];
    frix_mpi_problem *p = NULL;
    for (a = first; a < end; ++a) {
        const int64_t k = row_ptr[a - first];
        row_ptr[a - first + 1] = k + chain_row(a, cols + k, vals + 9 * k);
    }
    *owned = end - first;
    EXPECT(frix_mpi_problem_local(ctx, first, end - first, row_ptr, cols, vals, g_q + 3 * first, g_mu + first, &p) ==
               FRIX_OK,
           "frix_mpi_problem_local: %s", frix_mpi_last_error_message());
    return p;
}

/* The context reports the rank and size of its own communicator. */
static void context_rank_and_size(void) {
    frix_mpi_context *ctx = NULL;
    MPI_Comm half;
    int rank, size;
    EXPECT(frix_mpi_context_rank(NULL) == -1 && frix_mpi_context_size(NULL) == 0, "a NULL context");
    EXPECT(frix_mpi_context_create(MPI_COMM_WORLD, &ctx) == FRIX_OK, "%s", frix_mpi_last_error_message());
    EXPECT(frix_mpi_context_rank(ctx) == g_rank && frix_mpi_context_size(ctx) == g_size,
           "MPI_COMM_WORLD: rank %d of %d", frix_mpi_context_rank(ctx), frix_mpi_context_size(ctx));
    frix_mpi_context_free(ctx);
    /* Halves: ranks 0, 2, 4, ... and 1, 3, 5, ..., in reverse order within each. */
    MPI_Comm_split(MPI_COMM_WORLD, g_rank % 2, -g_rank, &half);
    MPI_Comm_rank(half, &rank);
    MPI_Comm_size(half, &size);
    EXPECT(frix_mpi_context_create(half, &ctx) == FRIX_OK, "%s", frix_mpi_last_error_message());
    EXPECT(frix_mpi_context_rank(ctx) == rank && frix_mpi_context_size(ctx) == size &&
               size == (g_size + (g_rank % 2 == 0)) / 2,
           "a half: rank %d of %d, MPI says %d of %d", frix_mpi_context_rank(ctx), frix_mpi_context_size(ctx), rank,
           size);
    frix_mpi_context_free(ctx);
    MPI_Comm_free(&half);
    EXPECT(frix_mpi_context_create(MPI_COMM_SELF, &ctx) == FRIX_OK, "%s", frix_mpi_last_error_message());
    EXPECT(frix_mpi_context_rank(ctx) == 0 && frix_mpi_context_size(ctx) == 1, "MPI_COMM_SELF");
    frix_mpi_context_free(ctx);
}

/* One release: the host's handles are read and the host's info is filled. */
static void handles_accepted(frix_mpi_context *ctx, const frix_problem *local, const frix_problem *global,
                             frix_options *o, frix_info *info) {
    int part[NC];
    int64_t owned = 0, solver = 0;
    double r[3 * NC] = {0}, u[3 * NC];
    frix_mpi_problem *p = NULL, *pg = NULL;
    EXPECT(frix_mpi_partition(ctx, 0, local, part) == FRIX_OK, "partition: %s", frix_mpi_last_error_message());
    EXPECT(frix_mpi_problem_scatter(ctx, 0, local, g_rank == 0 ? part : NULL, &p) == FRIX_OK, "scatter: %s",
           frix_mpi_last_error_message());
    EXPECT(frix_mpi_problem_scatter_global(ctx, 0, global, NULL, &pg) == FRIX_OK, "scatter_global: %s",
           frix_mpi_last_error_message());
    if (p) {
        frix_mpi_problem_get_int(p, FRIX_MPI_OWNED, &owned);
        EXPECT(frix_mpi_solve(p, o, r, u, info) == FRIX_OK, "solve: %s", frix_mpi_last_error_message());
        frix_info_get_int(info, FRIX_INFO_SOLVER_ID, &solver);
        EXPECT(frix_info_status(info) == FRIX_STATUS_CONVERGED && solver == FRIX_SOLVER_NSGS &&
                   frix_info_iterations(info) > 0 && (owned == 0 || r[0] > 0.0),
               "the host's info: status %d, solver %d", (int)frix_info_status(info), (int)solver);
    }
    frix_mpi_problem_free(p);
    frix_mpi_problem_free(pg);
}

/* msg names both releases and says what to do. */
static void expect_release_message(const char *call, const char *what, const char *libfrix, const char *mpi) {
    const char *msg = frix_mpi_last_error_message();
    char a[64], b[64];
    snprintf(a, sizeof a, "libfrix %s ", libfrix);
    snprintf(b, sizeof b, "libfrix_mpi %s ", mpi);
    EXPECT(strstr(msg, what) && strstr(msg, a) && strstr(msg, b) &&
               strstr(msg, "libfrix and libfrix_mpi must come from the same release"),
           "%s: the message: %s", call, msg);
    if (g_rank == 0) printf("%s refused: %s\n", call, msg);
}

/* Two releases: every call that receives a handle refuses it, and a solve without any runs. */
static void handles_refused(frix_mpi_context *ctx, const frix_problem *local, const frix_problem *global,
                            frix_options *o, frix_info *info, const char *libfrix, const char *mpi) {
    int part[NC];
    int64_t owned = 0;
    double r[3 * NC] = {0}, u[3 * NC];
    frix_mpi_problem *p = NULL, *pg = NULL;
    EXPECT(frix_mpi_partition(ctx, 0, local, part) == FRIX_ERR_UNSUPPORTED, "partition accepted");
    expect_release_message("frix_mpi_partition", "the problem", libfrix, mpi);
    EXPECT(frix_mpi_problem_scatter(ctx, 0, local, NULL, &p) == FRIX_ERR_UNSUPPORTED && !p, "scatter accepted");
    expect_release_message("frix_mpi_problem_scatter", "the problem", libfrix, mpi);
    EXPECT(frix_mpi_problem_scatter_global(ctx, 0, global, NULL, &pg) == FRIX_ERR_UNSUPPORTED && !pg,
           "scatter_global accepted");
    expect_release_message("frix_mpi_problem_scatter_global", "the problem", libfrix, mpi);
    p = chain_part(ctx, &owned);
    if (!p) return;
    EXPECT(frix_mpi_solve(p, o, r, u, NULL) == FRIX_ERR_UNSUPPORTED, "solve accepted the options");
    expect_release_message("frix_mpi_solve", "the options", libfrix, mpi);
    EXPECT(frix_mpi_solve(p, NULL, r, u, info) == FRIX_ERR_UNSUPPORTED, "solve accepted the info");
    expect_release_message("frix_mpi_solve", "the info", libfrix, mpi);
    EXPECT(frix_info_status(info) == FRIX_STATUS_NOT_RUN, "the refused info was written");
    EXPECT(frix_mpi_solve(p, NULL, r, u, NULL) == FRIX_OK, "a solve without handles: %s",
           frix_mpi_last_error_message());
    EXPECT(owned == 0 || r[0] > 0.0, "a solve without handles: r_n = %g", r[0]);
    frix_mpi_problem_free(p);
}

int main(int argc, char **argv) {
    const int refused = argc > 1 && strcmp(argv[1], "refused") == 0;
    const char *libfrix = argc > 2 ? argv[2] : NULL, *mpi = argc > 3 ? argv[3] : NULL;
    frix_matrix *W = NULL, *I = NULL;
    frix_problem *local = NULL, *global = NULL;
    frix_options *o = NULL;
    frix_info *info = NULL;
    frix_mpi_context *ctx = NULL;
    int failed = 0;
    MPI_Init(&argc, &argv);
    MPI_Comm_rank(MPI_COMM_WORLD, &g_rank);
    MPI_Comm_size(MPI_COMM_WORLD, &g_size);
    if ((argc > 1 && !refused && strcmp(argv[1], "same") != 0) || (refused && !mpi)) {
        if (g_rank == 0)
            fprintf(stderr, "usage: %s [same [LIBFRIX_VERSION] | refused LIBFRIX_VERSION LIBFRIX_MPI_VERSION]\n",
                    argv[0]);
        MPI_Finalize();
        return 2;
    }
    EXPECT(!libfrix || strcmp(frix_version_string(), libfrix) == 0, "libfrix %s is loaded, not %s",
           frix_version_string(), libfrix);
    context_rank_and_size();
    chain_problems(&W, &I, &local, &global);
    EXPECT(frix_options_create(FRIX_SOLVER_NSGS, &o) == FRIX_OK && frix_info_create(&info) == FRIX_OK, "%s",
           frix_last_error_message());
    EXPECT(frix_mpi_context_create(MPI_COMM_WORLD, &ctx) == FRIX_OK, "%s", frix_mpi_last_error_message());
    if (!g_failed && refused)
        handles_refused(ctx, local, global, o, info, libfrix, mpi);
    else if (!g_failed)
        handles_accepted(ctx, local, global, o, info);
    frix_mpi_context_free(ctx);
    frix_info_free(info);
    frix_options_free(o);
    frix_problem_free(global);
    frix_problem_free(local);
    frix_matrix_free(I);
    frix_matrix_free(W);
    MPI_Allreduce(&g_failed, &failed, 1, MPI_INT, MPI_LOR, MPI_COMM_WORLD);
    MPI_Finalize();
    if (g_rank == 0) printf("host_handles %s: %s\n", refused ? "refused" : "same", failed ? "FAILED" : "passed");
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
