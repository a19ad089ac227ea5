/* The granular client on the ranks of an MPI job: the scene of granular.c (spheres poured
 * into a box, Moreau-Jean steps), each step's problem solved by all ranks together with
 * libfrix_mpi, in product form (blocks of H^T and the spheres' mass blocks; W is never formed).
 *
 *   mpirun -np N granular_mpi [--spheres N] [--aspect A] [--steps S] [--step H] [--mu MU]
 *                             [--radius R] [--seed K] [--tol T] [--max-iter I] [--every K]
 *                             [--check] [--quiet]
 *
 * Every rank holds the whole scene (positions and velocities, the same bits on every rank) and
 * runs the broad phase. The bodies are split by space: the box is cut into N slabs along x,
 * and each rank owns the spheres whose centre lies in its slab at the start of the step and
 * the contacts whose first sphere it owns. It gives libfrix_mpi its contacts and the spheres
 * they act on, and its own spheres; the ranks solve (nsgs), warm-started from last step's
 * impulses of the same pairs; then each rank sends all the others its spheres' new velocities
 * and its contacts' impulses, and every rank moves every sphere.
 *
 * --steps S runs steps 0 to S-1. Rank 0 prints a line per step (every K-th with --every, and
 * the last): step, contacts, sweeps, error, solve time, energy, and the boundary contacts and
 * messages a sweep of all ranks; a step that did not converge is reported on stderr, and their
 * count at the end. --check exits with 1 unless every step converged and the energy never grew
 * by more than the step's tolerance allows (as granular.c). Exit status 2 for a usage or
 * library error; --help prints the options.
 */
#include <frix/frix.h>
#include <frix/frix_mpi.h>

#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "pour.h"

typedef struct {
    scene_settings scene;
    int check, quiet;
} settings;

static const char kUsage[] =
    "usage: mpirun -np N granular_mpi [--spheres N] [--aspect A] [--steps S] [--step H] [--mu MU]\n"
    "         [--radius R] [--seed K] [--tol T] [--max-iter I] [--every K] [--check] [--quiet]\n";

static int usage(int rank, const char *msg, const char *arg) {
    if (rank == 0) fprintf(stderr, "granular_mpi: %s%s%s\n%s", msg, arg ? ": " : "", arg ? arg : "", kUsage);
    return 2;
}

static void help(int rank) {
    if (rank != 0) return;
    fputs(kUsage, stdout);
    fputs("Pours spheres into a box under gravity, as granular does; every step's problem is solved by all\n"
          "ranks together (libfrix_mpi, nsgs), each rank owning the spheres of a slab along x.\n",
          stdout);
    scene_help(stdout);
    fputs("  --check          exit 1 unless every step converged and the energy never grew\n"
          "  --quiet          no line per step (unconverged steps are still reported on stderr)\n"
          "  --help           this text\n"
          "Exit status: 0 done (with --check: and the checks held), 1 a check failed, 2 usage or library error.\n",
          stdout);
}

static int parse(int argc, char **argv, settings *st, int rank) {
    *st = (settings){.check = 0, .quiet = 0};
    scene_defaults(&st->scene);
    for (int i = 1; i < argc; ++i) {
        const char *o = argv[i], *a = i + 1 < argc ? argv[i + 1] : NULL;
        int ok = 1, takes = 1;
        if (!strcmp(o, "--help") || !strcmp(o, "-h")) return help(rank), 3;
        if (!strcmp(o, "--check")) st->check = 1, takes = 0;
        else if (!strcmp(o, "--quiet")) st->quiet = 1, takes = 0;
        else if (!a) return usage(rank, "missing value after", o);
        else if (parse_scene_option(o, a, &st->scene, &ok)) {
            /* a scene option; ok: whether its value is valid */
        }
        else return usage(rank, "unknown option", o);
        if (!ok) return usage(rank, "bad value", a);
        i += takes;
    }
    return 0;
}

/* The rank whose slab holds sphere i's centre. */
static int slab_of(const world *w, int64_t i, int ranks) {
    const int k = (int)floor(w->x[3 * i] / w->box[0] * ranks);
    return k < 0 ? 0 : (k >= ranks ? ranks - 1 : k);
}

/* What a rank keeps from step to step; every array grows as needed. */
typedef struct {
    int64_t *owner_of_sphere;  /* n */
    int64_t *order;            /* contacts by owner rank: order[k] = the contact (sorted by pair) k-th */
    int64_t *bodies, *held;    /* 2 per owned contact; the spheres given */
    double *G, *wv, *mu, *M, *f, *r_all, *r_mine, *u_mine, *v_held, *r_before, *v_all, *r_ranked;
    int *counts, *displs;
    int64_t contact_capacity, held_capacity;
} buffers;

static int grow_all(buffers *b, int64_t nc, int64_t n) {
    if (nc > b->contact_capacity || !b->order) {
        const int64_t cap = nc > 2 * b->contact_capacity ? nc + 1 : 2 * b->contact_capacity + 1;
        if (!grow_indices(&b->order, cap) || !grow_indices(&b->bodies, 2 * cap) || !grow_doubles(&b->G, 36 * cap) ||
            !grow_doubles(&b->wv, 3 * cap) || !grow_doubles(&b->mu, cap) || !grow_doubles(&b->r_all, 3 * cap) ||
            !grow_doubles(&b->r_mine, 3 * cap) || !grow_doubles(&b->u_mine, 3 * cap) ||
            !grow_doubles(&b->r_before, 3 * cap) || !grow_doubles(&b->r_ranked, 3 * cap))
            return 0;
        b->contact_capacity = cap;
    }
    if (!b->held) {
        b->held_capacity = n + 1;
        if (!grow_indices(&b->held, n + 1) || !grow_doubles(&b->M, 36 * (n + 1)) || !grow_doubles(&b->f, 6 * (n + 1)) ||
            !grow_doubles(&b->v_held, 6 * (n + 1)) || !grow_indices(&b->owner_of_sphere, n + 1) ||
            !grow_doubles(&b->v_all, 6 * (n + 1)))
            return 0;
    }
    return 1;
}

static void free_buffers(buffers *b) {
    free(b->owner_of_sphere);
    free(b->order);
    free(b->bodies);
    free(b->held);
    free(b->G);
    free(b->wv);
    free(b->mu);
    free(b->M);
    free(b->f);
    free(b->r_all);
    free(b->r_mine);
    free(b->u_mine);
    free(b->v_held);
    free(b->r_before);
    free(b->v_all);
    free(b->r_ranked);
    free(b->counts);
    free(b->displs);
}

static int run(const settings *st, int rank, int ranks) {
    world w;
    memset(&w, 0, sizeof w);
    buffers b;
    memset(&b, 0, sizeof b);
    contacts now = {0}, before = {0};
    int64_t *cell_start = NULL, cells_capacity = 0, *grid_order = NULL;
    double *reach = NULL;
    char *mark = NULL;
    frix_mpi_context *ctx = NULL;
    frix_options *opts = NULL;
    frix_info *info = NULL;
    int status = 0;
    if (!make_world(&st->scene, &w) ||
        !(grid_order = malloc(sizeof *grid_order * (size_t)w.n)) || !(reach = malloc(sizeof *reach * (size_t)w.n)) ||
        !(mark = calloc((size_t)w.n, 1)) || !(b.counts = malloc(sizeof *b.counts * (size_t)ranks)) ||
        !(b.displs = malloc(sizeof *b.displs * (size_t)(ranks + 1))) || !grow_all(&b, 0, w.n)) {
        fprintf(stderr, "granular_mpi: out of memory (rank %d)\n", rank);
        status = 2;
        goto done;
    }
    if (frix_mpi_context_create(MPI_COMM_WORLD, &ctx) || frix_options_create(FRIX_SOLVER_NSGS, &opts) ||
        frix_options_set_double(opts, FRIX_OPT_TOLERANCE, st->scene.tol) ||
        (st->scene.max_iter && frix_options_set_int(opts, FRIX_OPT_MAX_ITER, st->scene.max_iter)) || frix_info_create(&info)) {
        if (rank == 0) fprintf(stderr, "granular_mpi: %s %s\n", frix_mpi_last_error_message(), frix_last_error_message());
        status = 2;
        goto done;
    }
    const int64_t n = w.n;
    if (rank == 0 && !st->quiet)
        printf("# step contacts sweeps error time_s energy_J boundary_contacts messages_per_sweep\n");
    const double e0 = energy(&w);
    double e_before = e0;
    int64_t unconverged = 0;
    for (int64_t step = 0; step < st->scene.steps; ++step) {
        step_reach(&w, st->scene.h, reach);
        for (int64_t i = 0; i < n; ++i) b.owner_of_sphere[i] = slab_of(&w, i, ranks);
        contacts t = before;
        before = now;
        now = t;
        if (!find_contacts(&w, 0.05 * w.rmin, reach, &now, &cell_start, &grid_order, &cells_capacity) ||
            !grow_all(&b, now.count, n)) {
            fprintf(stderr, "granular_mpi: out of memory (rank %d)\n", rank);
            status = 2;
            goto done;
        }
        const int64_t nc = now.count;
        /* The contacts rank by rank (a contact is its first sphere's owner's), each rank's in
         * the order of their pairs. */
        for (int k = 0; k <= ranks; ++k) b.displs[k] = 0;
        for (int64_t a = 0; a < nc; ++a) ++b.displs[b.owner_of_sphere[now.c[a].a] + 1];
        for (int k = 0; k < ranks; ++k) b.displs[k + 1] += b.displs[k];
        for (int k = 0; k < ranks; ++k) b.counts[k] = b.displs[k];
        for (int64_t a = 0; a < nc; ++a) b.order[b.counts[b.owner_of_sphere[now.c[a].a]]++] = a;
        const int64_t first = b.displs[rank], owned = b.displs[rank + 1] - first;
        warm_start(&now, &before, 3, b.r_before, b.r_all);
        /* This rank's contacts: bodies (-1 for a wall), blocks of H^T, w, mu, warm start; the
         * spheres given: those its contacts touch and its own. */
        for (int64_t i = 0; i < owned; ++i) {
            const contact *c = &now.c[b.order[first + i]];
            b.bodies[2 * i] = c->a;
            b.bodies[2 * i + 1] = c->b < n ? c->b : -1;
            contact_blocks(&w, c, &b.G[36 * i]);
            b.wv[3 * i] = fmax(c->gap, 0.0) / st->scene.h;
            b.wv[3 * i + 1] = b.wv[3 * i + 2] = 0.0;
            b.mu[i] = st->scene.mu;
            for (int q = 0; q < 3; ++q) b.r_mine[3 * i + q] = b.r_all[3 * b.order[first + i] + q];
            mark[c->a] = 1;
            if (c->b < n) mark[c->b] = 1;
        }
        int64_t held = 0;
        for (int64_t i = 0; i < n; ++i) {
            if (!mark[i] && b.owner_of_sphere[i] != rank) continue;
            mark[i] = 0;
            b.held[held] = i;
            double *M = &b.M[36 * held];
            for (int e = 0; e < 36; ++e) M[e] = 0.0;
            for (int q = 0; q < 6; ++q) {
                const double m = q < 3 ? w.mass[i] : w.inertia[i];
                M[7 * q] = m;
                b.f[6 * held + q] = m * w.v[6 * i + q] - (q == 2 ? st->scene.h * w.mass[i] * GRAVITY : 0.0);
            }
            ++held;
        }
        frix_mpi_problem *p = NULL;
        if (frix_mpi_problem_rigid(ctx, first, owned, b.bodies, b.G, b.wv, b.mu, held, b.held, b.M, b.f, &p) ||
            frix_mpi_solve(p, opts, b.r_mine, b.u_mine, info) || frix_mpi_problem_velocities(p, b.v_held)) {
            if (rank == 0) fprintf(stderr, "granular_mpi: step %lld: %s\n", (long long)step, frix_mpi_last_error_message());
            frix_mpi_problem_free(p);
            status = 2;
            goto done;
        }
        int64_t boundary = 0, messages = 0;
        frix_mpi_problem_get_int(p, FRIX_MPI_BOUNDARY, &boundary);
        frix_mpi_problem_get_int(p, FRIX_MPI_MESSAGES_SENT, &messages);
        frix_mpi_problem_free(p);
        long long sums[2] = {(long long)boundary, (long long)messages};
        MPI_Allreduce(MPI_IN_PLACE, sums, 2, MPI_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
        /* Every rank's impulses and its spheres' velocities, to every rank: the scene stays the
         * same everywhere. */
        for (int k = 0; k < ranks; ++k) {
            b.counts[k] = 3 * (b.displs[k + 1] - b.displs[k]);
            b.displs[k] *= 3;
        }
        b.displs[ranks] *= 3;
        MPI_Allgatherv(b.r_mine, (int)(3 * owned), MPI_DOUBLE, b.r_ranked, b.counts, b.displs, MPI_DOUBLE,
                       MPI_COMM_WORLD);
        for (int64_t k = 0; k < nc; ++k)
            for (int q = 0; q < 3; ++q) b.r_before[3 * b.order[k] + q] = b.r_ranked[3 * k + q];
        for (int k = 0; k <= ranks; ++k) b.displs[k] = 0;
        for (int64_t i = 0; i < n; ++i) b.displs[b.owner_of_sphere[i] + 1] += 6;
        for (int k = 0; k < ranks; ++k) {
            b.displs[k + 1] += b.displs[k];
            b.counts[k] = b.displs[k + 1] - b.displs[k];
        }
        /* In place: this rank's spheres go where the gather puts them. */
        int64_t mine = b.displs[rank];
        for (int64_t h = 0; h < held; ++h)
            if (b.owner_of_sphere[b.held[h]] == rank) {
                for (int q = 0; q < 6; ++q) b.v_all[mine + q] = b.v_held[6 * h + q];
                mine += 6;
            }
        MPI_Allgatherv(MPI_IN_PLACE, 0, MPI_DOUBLE, b.v_all, b.counts, b.displs, MPI_DOUBLE, MPI_COMM_WORLD);
        /* v_all holds the spheres rank by rank, each rank's in increasing index. */
        for (int k = 0; k < ranks; ++k) b.counts[k] = b.displs[k];
        for (int64_t i = 0; i < n; ++i) {
            const int64_t at = b.counts[b.owner_of_sphere[i]];
            b.counts[b.owner_of_sphere[i]] += 6;
            for (int q = 0; q < 6; ++q) w.v[6 * i + q] = b.v_all[at + q];
        }
        for (int64_t i = 0; i < n; ++i)
            for (int q = 0; q < 3; ++q) w.x[3 * i + q] += st->scene.h * w.v[6 * i + q];
        const double en = energy(&w);
        const frix_status s = frix_info_status(info);
        const double err = frix_info_error(info);
        if (rank == 0 && !st->quiet && (step % st->scene.every == 0 || step == st->scene.steps - 1))
            printf("%lld %lld %lld %.3e %.4f %.9g %lld %lld\n", (long long)step, (long long)nc,
                   (long long)frix_info_iterations(info), err, frix_info_solve_time(info), en, sums[0], sums[1]);
        /* Always said: the next steps start from an inexact answer. */
        if (s != FRIX_STATUS_CONVERGED) {
            if (rank == 0)
                fprintf(stderr, "granular_mpi: step %lld did not converge: %s, error %.3e\n", (long long)step,
                        frix_status_string(s), err);
            ++unconverged;
            if (st->check) status = 1;
        }
        if (st->check) {
            if (en > e_before + 10.0 * st->scene.tol * fabs(e0)) {
                if (rank == 0)
                    fprintf(stderr, "granular_mpi: step %lld: the energy grew from %.9g to %.9g J\n", (long long)step,
                            e_before, en);
                status = 1;
            }
        }
        e_before = en;
    }
    if (rank == 0 && unconverged > 0)
        fprintf(stderr, "granular_mpi: %lld of %lld steps did not converge\n", (long long)unconverged,
                (long long)st->scene.steps);
done:
    frix_info_free(info);
    frix_options_free(opts);
    frix_mpi_context_free(ctx);
    free(now.c);
    free(before.c);
    free(cell_start);
    free(grid_order);
    free(reach);
    free(mark);
    free_buffers(&b);
    free_world(&w);
    return status;
}

int main(int argc, char **argv) {
    int rank = 0, ranks = 1, status;
    settings st;
    keep_freed_memory(); /* before MPI_Init: MPI's own buffers come from the same allocator */
    MPI_Init(&argc, &argv);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &ranks);
    status = parse(argc, argv, &st, rank);
    if (status == 0)
        status = run(&st, rank, ranks);
    else if (status == 3) /* --help */
        status = 0;
    /* Every rank's verdict: the worst. */
    MPI_Allreduce(MPI_IN_PLACE, &status, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    MPI_Finalize();
    return status;
}
