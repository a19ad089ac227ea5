/* frix-mpi: solves an FCLIB (or .dat) problem on the ranks of an MPI job.
 *
 *   mpirun -np N frix-mpi solve FILE [--solver nsgs|nsn-ac|gnsn-ac] [--tol T] [--max-iter N] [--time-limit S]
 *                                    [--set NAME=VALUE]... [--parts scotch|blocks]
 *                                    [--output FILE] [--json] [--verbose]
 *
 * The options of `frix solve` keep their names and meaning (--out is accepted for --output),
 * and --json prints one object with the fields of `frix solve --json` (those a distributed
 * solve has) plus an "mpi" object: the ranks, the parts and the distribution.
 *
 * Rank 0 reads the file (the HDF5 library is serial), the contacts are cut into one part a
 * rank (Scotch on the contact graph; or blocks of the stored order), and
 * rank 0 sends each rank its part; the ranks solve with nsgs (libfrix_mpi); rank 0 gathers the reactions, measures
 * them with libfrix (the error measure frix solve prints), prints the report and, with
 * --output, writes the problem with its solution. The program's communicator is MPI_COMM_WORLD;
 * the library works on a duplicate of it.
 *
 * Exit status: 0 converged, 1 the solve ran but did not converge, 2 usage error, unreadable
 * or invalid input, or refused by the library. */
#include <frix/frix.h>
#include <frix/frix_mpi.h>

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char kUsage[] =
    "usage: mpirun -np N frix-mpi solve FILE [--solver nsgs|nsn-ac|gnsn-ac] [--tol T] [--max-iter N] [--time-limit S]\n"
    "                                  [--set NAME=VALUE]... [--parts scotch|blocks]\n"
    "                                  [--output FILE] [--json] [--verbose]\n";

static const char kHelp[] =
    "Solves FILE (FCLIB .hdf5 or Siconos .dat) on the ranks of the job (libfrix_mpi).\n"
    "  --solver NAME|ID     nsgs (default), nsn-ac, or gnsn-ac (a global problem's rows on the ranks)\n"
    "  --tol T              stop when the error is at most T\n"
    "  --max-iter N         at most N sweeps (Newton steps)\n"
    "  --time-limit S       stop after S seconds\n"
    "  --set NAME=VALUE     any other solver option, by name (see frix solvers NAME)\n"
    "  --parts scotch|blocks  cut the contacts by Scotch (default) or in blocks of their order\n"
    "  --output FILE        write the problem with its solution (FCLIB); --out, -o: the same\n"
    "  --json               one JSON object on stdout, the fields of frix solve --json\n"
    "  --verbose            the solver's log (rank 0)\n"
    "Exit status: 0 converged, 1 not converged, 2 usage error or refused input.\n";

typedef struct {
    const char *file, *out, *solver;
    int blocks; /* --parts blocks */
    double tol, time_limit;
    long long max_iter;
    int verbose, json;
    const char *sets[64];
    int nsets;
} args_t;

/* 0; 2 with a message on rank 0; 3 for --help (printed on rank 0). */
static int parse(int argc, char **argv, args_t *a, int rank) {
    int i;
    memset(a, 0, sizeof *a);
    a->tol = -1.0;
    a->time_limit = -1.0;
    a->max_iter = -1;
    for (i = 1; i < argc; ++i)
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            if (rank == 0) printf("%s%s", kUsage, kHelp);
            return 3;
        }
    if (argc < 3 || strcmp(argv[1], "solve") != 0) {
        if (rank == 0) fputs(kUsage, stderr);
        return 2;
    }
    for (i = 2; i < argc; ++i) {
        const char *o = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        char *end = NULL;
        if (o[0] != '-' || o[1] == '\0') {
            if (a->file) {
                if (rank == 0) fprintf(stderr, "frix-mpi: expected one FILE, got %s and %s\n%s", a->file, o, kUsage);
                return 2;
            }
            a->file = o;
            continue;
        }
        if (strcmp(o, "--verbose") == 0 || strcmp(o, "-v") == 0) {
            a->verbose = 1;
            continue;
        }
        if (strcmp(o, "--json") == 0) {
            a->json = 1;
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
        } else if (strcmp(o, "--output") == 0 || strcmp(o, "--out") == 0 || strcmp(o, "-o") == 0) {
            if (*v == '\0') {
                if (rank == 0) fprintf(stderr, "frix-mpi: %s needs a file name\n", o);
                return 2;
            }
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
    if (!a->file) {
        if (rank == 0) fprintf(stderr, "frix-mpi: expected one FILE\n%s", kUsage);
        return 2;
    }
    return 0;
}

/* Applies --set NAME=VALUE (an integer or a double, as the key is typed). */
static int apply_set(frix_options *opts, const char *spec, int rank) {
    char name[64];
    const char *eq = strchr(spec, '=');
    if (!eq || (size_t)(eq - spec) >= sizeof name) {
        if (rank == 0) fprintf(stderr, "frix-mpi: --set %s: expected NAME=VALUE\n", spec);
        return 2;
    }
    memcpy(name, spec, (size_t)(eq - spec));
    name[eq - spec] = '\0';
    /* A number, or a choice's name (shuffle=once), with frix solve's checks and messages. */
    if (frix_options_set_by_name(opts, name, eq + 1) != FRIX_OK) {
        if (rank == 0) fprintf(stderr, "frix-mpi: --set %s: %s\n", spec, frix_last_error_message());
        return 2;
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

/* What rank 0 reports. */
typedef struct {
    const frix_problem *problem;
    const frix_options *opts;
    const frix_info *info;
    int global_rows, ranks, checked, written;
    double check, partition_time; /* partition_time: NaN without Scotch */
    int64_t existence;            /* frix_existence: checked on rank 0 after a failed solve */
    double existence_margin;
    long long boundary, ghosts, colours, messages;
    int64_t total;
} report_t;

/* frix solve's names (tools/cli/common.cpp status_token, cmd_solve.cpp measure_name). */
static const char *status_token(frix_status s) {
    switch (s) {
        case FRIX_STATUS_NOT_RUN: return "not_run";
        case FRIX_STATUS_CONVERGED: return "converged";
        case FRIX_STATUS_MAX_ITER: return "max_iter";
        case FRIX_STATUS_TIME_LIMIT: return "time_limit";
        case FRIX_STATUS_STAGNATED: return "stagnated";
        case FRIX_STATUS_DIVERGED: return "diverged";
        case FRIX_STATUS_NUMERICAL_FAILURE: return "numerical_failure";
        case FRIX_STATUS_STOPPED_BY_CALLBACK: return "stopped_by_callback";
        case FRIX_STATUS_MEMORY_LIMIT: return "memory_limit";
    }
    return "unknown";
}

static const char *measure_name(int64_t m) {
    const char *name = frix_option_choice_name(FRIX_OPT_ERROR_MEASURE, m);
    return name ? name : "unknown";
}

static double info_double(const frix_info *info, frix_info_key key) {
    double v = NAN;
    if (frix_info_get_double(info, key, &v) != FRIX_OK) return NAN;
    return v;
}

static int64_t info_int(const frix_info *info, frix_info_key key) {
    int64_t v = 0;
    if (frix_info_get_int(info, key, &v) != FRIX_OK) return 0;
    return v;
}

/* JSON output: the members of one object on one line. `first` tracks the comma. */
static int json_first = 1;

static void json_key(const char *key) {
    if (!json_first) putchar(',');
    json_first = 0;
    if (key) printf("\"%s\":", key);
}

static void json_string(const char *key, const char *v) {
    const unsigned char *c;
    json_key(key);
    putchar('"');
    for (c = (const unsigned char *)v; *c; ++c) {
        if (*c == '"' || *c == '\\')
            printf("\\%c", *c);
        else if (*c < 0x20)
            printf("\\u%04x", *c);
        else
            putchar(*c);
    }
    putchar('"');
}

/* Non-finite numbers are null, so the line is always valid JSON. */
static void json_number(const char *key, double v) {
    json_key(key);
    if (isfinite(v))
        printf("%.17g", v);
    else
        fputs("null", stdout);
}

static void json_integer(const char *key, long long v) {
    json_key(key);
    printf("%lld", v);
}

static void json_open(const char *key) {
    json_key(key);
    putchar('{');
    json_first = 1;
}

static void json_close(void) {
    putchar('}');
    json_first = 0;
}

static void print_json(const args_t *a, const report_t *r) {
    const frix_status s = frix_info_status(r->info);
    const int id = frix_options_solver(r->opts);
    const char *name = frix_solver_name(id);
    const char *trace = frix_info_trace(r->info);
    int64_t measure = FRIX_MEASURE_SCALED;
    frix_options_get_int(r->opts, FRIX_OPT_ERROR_MEASURE, &measure);
    json_first = 1;
    putchar('{');
    json_string("file", a->file);
    json_string("kind", frix_problem_get_kind(r->problem) == FRIX_PROBLEM_GLOBAL ? "global" : "local");
    json_integer("contacts", (long long)frix_problem_contacts(r->problem));
    json_integer("contact_dofs", (long long)frix_problem_contact_dofs(r->problem));
    json_integer("dofs", (long long)frix_problem_dofs(r->problem));
    json_string("solver", name ? name : "?");
    json_integer("solver_id", id);
    json_string("status", status_token(s));
    json_string("status_text", frix_status_string(s));
    json_key("converged");
    fputs(s == FRIX_STATUS_CONVERGED ? "true" : "false", stdout);
    json_integer("iterations", (long long)frix_info_iterations(r->info));
    json_number("error", frix_info_error(r->info));
    json_string("error_measure", measure_name(measure));
    json_number("tolerance", info_double(r->info, FRIX_INFO_TOLERANCE));
    json_number("time", frix_info_solve_time(r->info));
    json_string("existence", frix_existence_describe((frix_existence)r->existence));
    json_number("existence_margin", r->existence_margin);
    json_open("measures");
    json_number("error_relative", info_double(r->info, FRIX_INFO_ERROR_RELATIVE));
    json_number("error_q_relative", info_double(r->info, FRIX_INFO_ERROR_Q_RELATIVE));
    json_number("residual_absolute", info_double(r->info, FRIX_INFO_RESIDUAL_ABSOLUTE));
    json_number("cone_violation", info_double(r->info, FRIX_INFO_CONE_VIOLATION));
    json_number("penetration", info_double(r->info, FRIX_INFO_PENETRATION));
    json_number("complementarity", info_double(r->info, FRIX_INFO_COMPLEMENTARITY));
    json_number("equilibrium", info_double(r->info, FRIX_INFO_EQUILIBRIUM));
    json_number("equilibrium_scaled", info_double(r->info, FRIX_INFO_EQUILIBRIUM_SCALED));
    json_close();
    json_open("linear_algebra");
    json_integer("newton_iterations", (long long)info_int(r->info, FRIX_INFO_NEWTON_ITERATIONS));
    json_integer("line_search_steps", (long long)info_int(r->info, FRIX_INFO_LINE_SEARCH_STEPS));
    json_integer("hybrid_sweeps", (long long)info_int(r->info, FRIX_INFO_HYBRID_SWEEPS));
    json_integer("factorizations", (long long)info_int(r->info, FRIX_INFO_FACTORIZATIONS));
    json_integer("symbolic_analyses", (long long)info_int(r->info, FRIX_INFO_SYMBOLIC_ANALYSES));
    json_number("factorization_time", info_double(r->info, FRIX_INFO_FACTORIZATION_TIME));
    json_number("setup_time", info_double(r->info, FRIX_INFO_SETUP_TIME));
    json_number("reduction_time", info_double(r->info, FRIX_INFO_REDUCTION_TIME));
    json_close();
    json_key("trace");
    putchar('[');
    json_first = 1;
    while (trace && *trace) { /* one string a line */
        const char *nl = strchr(trace, '\n');
        size_t len = nl ? (size_t)(nl - trace) : strlen(trace);
        char line[1024];
        if (len >= sizeof line) len = sizeof line - 1;
        memcpy(line, trace, len);
        line[len] = '\0';
        if (len > 0) json_string(NULL, line);
        trace = nl ? nl + 1 : trace + strlen(trace);
    }
    putchar(']');
    json_first = 0;
    if (r->written)
        json_string("output", a->out);
    else {
        json_key("output");
        fputs("null", stdout);
    }
    json_open("mpi");
    json_integer("ranks", r->ranks);
    json_string("parts", a->blocks ? "blocks" : "scotch");
    json_string("form", r->global_rows ? "global" : "W");
    json_number("partition_time", r->partition_time);
    json_integer("boundary_contacts", r->boundary);
    json_integer("ghosts", r->ghosts);
    json_integer("colours", r->colours);
    json_integer("messages_per_sweep", r->messages);
    json_number("check", r->checked ? r->check : NAN);
    json_close();
    puts("}");
}

static void print_text(const args_t *a, const report_t *r) {
    double tol = 0.0;
    int64_t measure = FRIX_MEASURE_SCALED;
    const int global = frix_problem_get_kind(r->problem) == FRIX_PROBLEM_GLOBAL;
    frix_options_get_double(r->opts, FRIX_OPT_TOLERANCE, &tol);
    frix_options_get_int(r->opts, FRIX_OPT_ERROR_MEASURE, &measure);
    printf("%-16s %s\n", "file", a->file);
    printf("%-16s %s, %lld contacts\n", "problem",
           r->global_rows ? "global (M's and H^T's rows on the ranks)" : global ? "global (reduced on rank 0)" : "local",
           (long long)r->total);
    if (r->global_rows)
        printf("%-16s %d, contacts by %s, dofs in blocks\n", "ranks", r->ranks, a->blocks ? "blocks" : "Scotch");
    else
        printf("%-16s %d, %s (%lld boundary contacts, %lld ghosts, %lld colours, %lld messages a sweep)\n", "ranks",
               r->ranks, a->blocks ? "blocks" : "Scotch", r->boundary, r->ghosts, r->colours, r->messages);
    if (!a->blocks) printf("%-16s %.3g s\n", "partition", r->partition_time);
    printf("%-16s %s (id %d)\n", "solver", frix_solver_name(frix_options_solver(r->opts)), frix_options_solver(r->opts));
    printf("%-16s %s\n", "status", frix_status_string(frix_info_status(r->info)));
    if (r->existence != FRIX_EXISTENCE_NOT_CHECKED)
        printf("%-16s %s (margin %.2e)\n", "existence", frix_existence_describe((frix_existence)r->existence),
               r->existence_margin);
    printf("%-16s %lld\n", "iterations", (long long)frix_info_iterations(r->info));
    printf("%-16s %.3e (%s, tolerance %.1e)\n", "error", frix_info_error(r->info), measure_name(measure), tol);
    if (r->checked)
        printf("%-16s %.3e (the gathered %s, measured by libfrix)\n", "check", r->check,
               r->global_rows ? "r and v" : "r");
    printf("%-16s %.3g s\n", "time", frix_info_solve_time(r->info));
    if (r->written) printf("%-16s %s\n", "written to", a->out);
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
        report_t rep;
        const int global = frix_problem_get_kind(problem) == FRIX_PROBLEM_GLOBAL;
        rep.check = NAN;
        rep.checked = !global || global_rows;
        if (rep.checked && frix_problem_error(problem, r_all, global_rows ? v_all : NULL, &rep.check) != FRIX_OK) {
            fprintf(stderr, "frix-mpi: %s\n", frix_last_error_message());
            status = 2;
            goto done;
        }
        rep.problem = problem;
        rep.opts = opts;
        rep.info = info;
        rep.global_rows = global_rows;
        rep.ranks = size;
        rep.partition_time = a->blocks ? NAN : partition_time;
        rep.boundary = boundary;
        rep.ghosts = ghosts;
        rep.colours = colours;
        rep.messages = messages;
        rep.total = total;
        /* A failed solve says whether a solution exists at all (as frix solve), on rank 0. */
        rep.existence = FRIX_EXISTENCE_NOT_CHECKED;
        rep.existence_margin = NAN;
        if (status != 0) {
            frix_info *checked = NULL;
            if (frix_info_create(&checked) == FRIX_OK && frix_problem_check_existence(problem, 0.0, checked) == FRIX_OK) {
                frix_info_get_int(checked, FRIX_INFO_EXISTENCE, &rep.existence);
                rep.existence_margin = info_double(checked, FRIX_INFO_EXISTENCE_MARGIN);
            }
            frix_info_free(checked);
        }
        /* Written whatever the status (as frix solve): a non-converged iterate is worth a look. */
        rep.written = 0;
        if (a->out) {
            if (frix_fclib_write(a->out, problem, r_all, u_all, global_rows ? v_all : NULL, 0, NULL, NULL, NULL) !=
                FRIX_OK) {
                fprintf(stderr, "frix-mpi: cannot write %s: %s\n", a->out, frix_last_error_message());
                status = 2;
            } else {
                rep.written = 1;
            }
        }
        if (a->json)
            print_json(a, &rep);
        else
            print_text(a, &rep);
        fflush(stdout);
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
    if (status == 0)
        status = run(&a, rank, size);
    else if (status == 3) /* --help */
        status = 0;
    MPI_Finalize();
    return status;
}
