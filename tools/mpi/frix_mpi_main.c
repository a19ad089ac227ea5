/* frix-mpi: solves an FCLIB (or .dat) problem on the ranks of an MPI job.
 *
 *   mpirun -np N frix-mpi solve FILE [--solver nsgs|nsn-ac|gnsn-ac] [--tol T] [--max-iter N] [--time-limit S]
 *                                    [--parts scotch|blocks] [--set NAME=VALUE]...
 *                                    [--verbose] [--out FILE]
 *
 * Rank 0 reads the file (the HDF5 library is serial), the contacts are cut into one part a
 * rank (Scotch on the contact graph; or blocks of the stored order), and
 * rank 0 sends each rank its part; the ranks solve with nsgs (libfrix_mpi); rank 0 gathers the reactions, measures
 * them with libfrix (the error measure frix solve prints), prints the report and, with
 * --out, writes the problem with its solution. The program's communicator is MPI_COMM_WORLD;
 * the library works on a duplicate of it.
 *
 * Exit status: 0 converged, 1 the solve ran but did not converge, 2 usage error, unreadable
 * or invalid input, or refused by the library. */
#include <frix/frix.h>
#include <frix/frix_mpi.h>

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char kUsage[] =
    "usage: mpirun -np N frix-mpi solve FILE [--solver nsgs|nsn-ac|gnsn-ac] [--tol T] [--max-iter N] [--time-limit S]\n"
    "                                  [--parts scotch|blocks] [--set NAME=VALUE]...\n"
    "                                  [--verbose] [--out FILE]\n";

typedef struct {
    const char *file, *out, *solver;
    int blocks; /* --parts blocks */
    double tol, time_limit;
    long long max_iter;
    int verbose;
    const char *sets[64];
    int nsets;
} args_t;

/* 0, or 2 with a message on rank 0. */
static int parse(int argc, char **argv, args_t *a, int rank) {
    int i;
    memset(a, 0, sizeof *a);
    a->tol = -1.0;
    a->time_limit = -1.0;
    a->max_iter = -1;
    if (argc < 3 || strcmp(argv[1], "solve") != 0) {
        if (rank == 0) fputs(kUsage, stderr);
        return 2;
    }
    a->file = argv[2];
    for (i = 3; i < argc; ++i) {
        const char *o = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        char *end = NULL;
        if (strcmp(o, "--verbose") == 0) {
            a->verbose = 1;
            continue;
        }
        if (!v) {
            if (rank == 0) fprintf(stderr, "frix-mpi: %s needs a value\n%s", o, kUsage);
            return 2;
        }
        ++i;
        if (strcmp(o, "--tol") == 0) {
            a->tol = strtod(v, &end);
        } else if (strcmp(o, "--time-limit") == 0) {
            a->time_limit = strtod(v, &end);
        } else if (strcmp(o, "--max-iter") == 0) {
            a->max_iter = strtoll(v, &end, 10);
        } else if (strcmp(o, "--out") == 0) {
            a->out = v;
            continue;
        } else if (strcmp(o, "--solver") == 0) {
            a->solver = v;
            continue;
        } else if (strcmp(o, "--parts") == 0) {
            if (strcmp(v, "blocks") != 0 && strcmp(v, "scotch") != 0) {
                if (rank == 0) fprintf(stderr, "frix-mpi: --parts %s: expected scotch or blocks\n", v);
                return 2;
            }
            a->blocks = strcmp(v, "blocks") == 0;
            continue;
        } else if (strcmp(o, "--set") == 0) {
            if (a->nsets == (int)(sizeof a->sets / sizeof a->sets[0])) {
                if (rank == 0) fprintf(stderr, "frix-mpi: too many --set\n");
                return 2;
            }
            a->sets[a->nsets++] = v;
            continue;
        } else {
            if (rank == 0) fprintf(stderr, "frix-mpi: unknown option %s\n%s", o, kUsage);
            return 2;
        }
        if (end == v || *end != '\0') {
            if (rank == 0) fprintf(stderr, "frix-mpi: %s: '%s' is not a number\n", o, v);
            return 2;
        }
    }
    return 0;
}

/* Applies --set NAME=VALUE (an integer or a double, as the key is typed). */
static int apply_set(frix_options *opts, const char *spec, int rank) {
    char name[64];
    const char *eq = strchr(spec, '=');
    frix_option_key key;
    double lo, hi;
    int is_int;
    char *end = NULL;
    if (!eq || (size_t)(eq - spec) >= sizeof name) {
        if (rank == 0) fprintf(stderr, "frix-mpi: --set %s: expected NAME=VALUE\n", spec);
        return 2;
    }
    memcpy(name, spec, (size_t)(eq - spec));
    name[eq - spec] = '\0';
    if (frix_option_by_name(name, &key) != FRIX_OK ||
        frix_options_bounds(opts, key, &lo, &hi, &is_int) != FRIX_OK) {
        if (rank == 0) fprintf(stderr, "frix-mpi: --set %s: %s\n", spec, frix_last_error_message());
        return 2;
    }
    if (is_int) {
        long long v = strtoll(eq + 1, &end, 10);
        if (end == eq + 1 || *end != '\0' || frix_options_set_int(opts, key, v) != FRIX_OK) {
            if (rank == 0) fprintf(stderr, "frix-mpi: --set %s: %s\n", spec, end == eq + 1 || *end ? "not an integer" : frix_last_error_message());
            return 2;
        }
    } else {
        double v = strtod(eq + 1, &end);
        if (end == eq + 1 || *end != '\0' || frix_options_set_double(opts, key, v) != FRIX_OK) {
            if (rank == 0) fprintf(stderr, "frix-mpi: --set %s: %s\n", spec, end == eq + 1 || *end ? "not a number" : frix_last_error_message());
            return 2;
        }
    }
    return 0;
}

static int make_options(const args_t *a, frix_options **out, int rank) {
    frix_options *o = NULL;
    int i;
    int id = FRIX_SOLVER_NSGS;
    if (a->solver && frix_solver_by_name(a->solver, &id) != FRIX_OK) {
        if (rank == 0) fprintf(stderr, "frix-mpi: --solver %s: %s\n", a->solver, frix_last_error_message());
        return 2;
    }
    if (frix_options_create(id, &o) != FRIX_OK) {
        if (rank == 0) fprintf(stderr, "frix-mpi: %s\n", frix_last_error_message());
        return 2;
    }
    if ((a->tol >= 0.0 && frix_options_set_double(o, FRIX_OPT_TOLERANCE, a->tol) != FRIX_OK) ||
        (a->time_limit >= 0.0 && frix_options_set_double(o, FRIX_OPT_TIME_LIMIT, a->time_limit) != FRIX_OK) ||
        (a->max_iter >= 0 && frix_options_set_int(o, FRIX_OPT_MAX_ITER, a->max_iter) != FRIX_OK) ||
        (a->verbose && frix_options_set_int(o, FRIX_OPT_VERBOSITY, 1) != FRIX_OK)) {
        if (rank == 0) fprintf(stderr, "frix-mpi: %s\n", frix_last_error_message());
        frix_options_free(o);
        return 2;
    }
    for (i = 0; i < a->nsets; ++i)
        if (apply_set(o, a->sets[i], rank) != 0) {
            frix_options_free(o);
            return 2;
        }
    *out = o;
    return 0;
}

/* Sums (or takes the maximum of) one figure of the distribution over the ranks, on rank 0. */
static long long over_ranks(const frix_mpi_problem *p, frix_mpi_key key, MPI_Op op) {
    int64_t mine = 0;
    long long all = 0, v;
    frix_mpi_problem_get_int(p, key, &mine);
    v = (long long)mine;
    MPI_Reduce(&v, &all, 1, MPI_LONG_LONG, op, 0, MPI_COMM_WORLD);
    return all;
}

static int run(const args_t *a, int rank, int size) {
    frix_problem *problem = NULL;
    frix_options *opts = NULL;
    frix_mpi_context *ctx = NULL;
    frix_mpi_problem *part = NULL;
    frix_info *info = NULL;
    double *r = NULL, *u = NULL, *r_all = NULL, *u_all = NULL, *v = NULL, *v_all = NULL;
    int *v_counts = NULL, *v_at = NULL, global_rows = 0;
    int64_t dofs = 0, n = 0;
    int status = 2, read_ok = 1, *parts = NULL;
    double partition_time = 0.0;
    int64_t owned = 0, total = 0;
    long long boundary, ghosts, messages, colours;

    if (rank == 0 && frix_read_problem(a->file, &problem) != FRIX_OK) {
        fprintf(stderr, "frix-mpi: %s\n", frix_last_error_message());
        read_ok = 0;
    }
    MPI_Bcast(&read_ok, 1, MPI_INT, 0, MPI_COMM_WORLD);
    if (!read_ok) return 2;
    if (make_options(a, &opts, rank) != 0 || frix_info_create(&info) != FRIX_OK) goto done;
    if (rank == 0 && !a->blocks) {
        parts = (int *)calloc((size_t)frix_problem_contacts(problem) + 1, sizeof(int));
        if (!parts) {
            fprintf(stderr, "frix-mpi: out of memory\n");
            MPI_Abort(MPI_COMM_WORLD, 2);
        }
    }
    /* gnsn-ac takes a global problem's rows of M and H^T as they are; the others its W. */
    global_rows = frix_options_solver(opts) == FRIX_SOLVER_GLOBAL_NSN_AC;
    partition_time = MPI_Wtime();
    if (frix_mpi_context_create(MPI_COMM_WORLD, &ctx) != FRIX_OK ||
        (!a->blocks && frix_mpi_partition(ctx, 0, problem, parts) != FRIX_OK) ||
        (partition_time = MPI_Wtime() - partition_time,
         (global_rows ? frix_mpi_problem_scatter_global : frix_mpi_problem_scatter)(ctx, 0, problem, parts, &part) !=
             FRIX_OK)) {
        if (rank == 0) fprintf(stderr, "frix-mpi: %s\n", frix_mpi_last_error_message());
        goto done;
    }
    frix_mpi_problem_get_int(part, FRIX_MPI_OWNED, &owned);
    frix_mpi_problem_get_int(part, FRIX_MPI_CONTACTS, &total);
    frix_mpi_problem_get_int(part, FRIX_MPI_DOFS, &dofs);
    if (rank == 0 && global_rows) n = frix_problem_dofs(problem);
    v = (double *)calloc((size_t)(dofs + 1), sizeof(double));
    v_counts = (int *)calloc((size_t)size, sizeof(int));
    v_at = (int *)calloc((size_t)size, sizeof(int));
    if (rank == 0) v_all = (double *)calloc((size_t)(n + 1), sizeof(double));
    if (!v || !v_counts || !v_at || (rank == 0 && !v_all)) {
        fprintf(stderr, "frix-mpi: out of memory (rank %d)\n", rank);
        MPI_Abort(MPI_COMM_WORLD, 2);
    }
    r = (double *)calloc((size_t)(3 * owned + 1), sizeof(double));
    u = (double *)calloc((size_t)(3 * owned + 1), sizeof(double));
    if (rank == 0) {
        r_all = (double *)calloc((size_t)(3 * total + 1), sizeof(double));
        u_all = (double *)calloc((size_t)(3 * total + 1), sizeof(double));
    }
    if (!r || !u || (rank == 0 && (!r_all || !u_all))) {
        fprintf(stderr, "frix-mpi: out of memory (rank %d)\n", rank);
        MPI_Abort(MPI_COMM_WORLD, 2);
    }
    if (frix_mpi_solve(part, opts, r, u, info) != FRIX_OK) {
        if (rank == 0) fprintf(stderr, "frix-mpi: %s\n", frix_mpi_last_error_message());
        goto done;
    }
    boundary = over_ranks(part, FRIX_MPI_BOUNDARY, MPI_SUM);
    ghosts = over_ranks(part, FRIX_MPI_GHOSTS, MPI_SUM);
    messages = over_ranks(part, FRIX_MPI_MESSAGES_SENT, MPI_SUM);
    colours = over_ranks(part, FRIX_MPI_COLOURS, MPI_MAX);
    if (frix_mpi_gather(part, 0, r, r_all) != FRIX_OK || frix_mpi_gather(part, 0, u, u_all) != FRIX_OK) {
        if (rank == 0) fprintf(stderr, "frix-mpi: %s\n", frix_mpi_last_error_message());
        goto done;
    }
    if (global_rows) { /* v: the ranks' dofs, in rank order */
        int i, mine = (int)dofs;
        frix_mpi_problem_velocities(part, v);
        MPI_Gather(&mine, 1, MPI_INT, v_counts, 1, MPI_INT, 0, MPI_COMM_WORLD);
        for (i = 1; i < size; ++i) v_at[i] = v_at[i - 1] + v_counts[i - 1];
        MPI_Gatherv(v, mine, MPI_DOUBLE, v_all, v_counts, v_at, MPI_DOUBLE, 0, MPI_COMM_WORLD);
    }
    status = frix_info_status(info) == FRIX_STATUS_CONVERGED ? 0 : 1;
    if (rank == 0) {
        double error = 0.0, tol = 0.0;
        frix_options_get_double(opts, FRIX_OPT_TOLERANCE, &tol);
        const int global = frix_problem_get_kind(problem) == FRIX_PROBLEM_GLOBAL;
        if ((!global || global_rows) &&
            frix_problem_error(problem, r_all, global_rows ? v_all : NULL, &error) != FRIX_OK) {
            fprintf(stderr, "frix-mpi: %s\n", frix_last_error_message());
            status = 2;
            goto done;
        }
        printf("%-16s %s\n", "file", a->file);
        printf("%-16s %s, %lld contacts\n", "problem",
               global_rows ? "global (M's and H^T's rows on the ranks)" : global ? "global (reduced on rank 0)" : "local",
               (long long)total);
        if (global_rows)
            printf("%-16s %d, contacts by %s, dofs in blocks\n", "ranks", size, a->blocks ? "blocks" : "Scotch");
        else
            printf("%-16s %d, %s (%lld boundary contacts, %lld ghosts, %lld colours, %lld messages a sweep)\n",
                   "ranks", size, a->blocks ? "blocks" : "Scotch", boundary, ghosts, colours, messages);
        if (!a->blocks) printf("%-16s %.3g s\n", "partition", partition_time);
        printf("%-16s %s (id %d)\n", "solver", frix_solver_name(frix_options_solver(opts)), frix_options_solver(opts));
        printf("%-16s %s\n", "status", frix_status_string(frix_info_status(info)));
        printf("%-16s %lld\n", "iterations", (long long)frix_info_iterations(info));
        printf("%-16s %.3e (relative, tolerance %.1e)\n", "error", frix_info_error(info), tol);
        if (!global || global_rows)
            printf("%-16s %.3e (the gathered %s, measured by libfrix)\n", "check", error, global_rows ? "r and v" : "r");
        printf("%-16s %.3g s\n", "time", frix_info_solve_time(info));
        if (a->out &&
            frix_fclib_write(a->out, problem, r_all, u_all, global_rows ? v_all : NULL, 0, NULL, NULL, NULL) != FRIX_OK) {
            fprintf(stderr, "frix-mpi: %s\n", frix_last_error_message());
            status = 2;
        }
    }
done:
    MPI_Bcast(&status, 1, MPI_INT, 0, MPI_COMM_WORLD);
    free(r);
    free(u);
    free(r_all);
    free(u_all);
    free(v);
    free(v_all);
    free(v_counts);
    free(v_at);
    free(parts);
    frix_info_free(info);
    frix_mpi_problem_free(part);
    frix_mpi_context_free(ctx);
    frix_options_free(opts);
    frix_problem_free(problem);
    return status;
}

int main(int argc, char **argv) {
    int rank = 0, size = 1, status;
    args_t a;
    MPI_Init(&argc, &argv);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    status = parse(argc, argv, &a, rank);
    if (status == 0) status = run(&a, rank, size);
    MPI_Finalize();
    return status;
}
