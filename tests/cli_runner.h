/* Shared by the tests that run the `frix` executable (FRIX_CLI) in a child process. Include
 * after the system headers (needs _POSIX_C_SOURCE). */
#ifndef FRIX_CLI_RUNNER_H
#define FRIX_CLI_RUNNER_H

#include <check.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include "files.h"

typedef struct {
    int code; /* exit code, or 128 + signal */
    char *out, *err;
} cli_run;

/* Runs `program` with the NULL-terminated arguments; stdout and stderr go through files
 * (no pipe can fill up and block the child). address_bytes > 0: the child's address space is
 * limited to that (OpenBLAS on one thread: its thread pool would spin on a failed allocation). */
static inline cli_run run_program_within(const char *program, const char *const *args, double address_bytes) {
    char out_path[512], err_path[512];
    snprintf(out_path, sizeof out_path, "%s/cli_%ld.out", FRIX_TEST_TMPDIR, (long)getpid());
    snprintf(err_path, sizeof err_path, "%s/cli_%ld.err", FRIX_TEST_TMPDIR, (long)getpid());
    const char *argv[32];
    int argc = 0;
    argv[argc++] = program;
    for (; args[argc - 1] != NULL; ++argc) {
        ck_assert_int_lt(argc, 31);
        argv[argc] = args[argc - 1];
    }
    argv[argc] = NULL;

    fflush(stdout);
    fflush(stderr);
    pid_t pid = fork();
    ck_assert_int_ge(pid, 0);
    if (pid == 0) {
        int fo = open(out_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        int fe = open(err_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (fo < 0 || fe < 0 || dup2(fo, 1) < 0 || dup2(fe, 2) < 0) _exit(126);
        if (address_bytes > 0.0) {
            struct rlimit lim = {(rlim_t)address_bytes, (rlim_t)address_bytes};
            if (setrlimit(RLIMIT_AS, &lim) != 0) _exit(126);
            setenv("OPENBLAS_NUM_THREADS", "1", 1);
        }
        execv(program, (char *const *)argv);
        _exit(127);
    }
    int status = 0;
    ck_assert_int_eq(waitpid(pid, &status, 0), pid);
    cli_run r;
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    r.out = slurp(out_path, NULL);
    r.err = slurp(err_path, NULL);
    unlink(out_path);
    unlink(err_path);
    return r;
}

static inline cli_run run_program(const char *program, const char *const *args) {
    return run_program_within(program, args, 0.0);
}

/* Runs FRIX_CLI (the `frix` executable) with the NULL-terminated arguments. */
static inline cli_run run_cli(const char *const *args) { return run_program(FRIX_CLI, args); }

static inline void run_free(cli_run *r) {
    free(r->out);
    free(r->err);
}

/* A valid Siconos .dat local problem of nc contacts, W = I stored dense: 9 nc^2 numbers (tens
 * of MB), slow to read, trivial to solve. */
static inline void frix_test_write_slow_dat(const char *path, int nc) {
    FILE *f = fopen(path, "wb");
    ck_assert_msg(f != NULL, "cannot write %s", path);
    const int n = 3 * nc;
    fprintf(f, "3 %d\n0 %d %d\n%d %d\n", nc, n, n, n, n);
    char *col = malloc(2 * (size_t)n);
    ck_assert_ptr_nonnull(col);
    for (int i = 0; i < n; ++i) col[2 * i] = '0', col[2 * i + 1] = ' ';
    col[2 * n - 1] = '\n';
    for (int j = 0; j < n; ++j) {
        col[2 * j] = '1';
        ck_assert_int_eq(fwrite(col, 1, 2 * (size_t)n, f), 2 * (size_t)n);
        col[2 * j] = '0';
    }
    free(col);
    for (int a = 0; a < nc; ++a) fputs("-1 0 0 ", f);
    fputs("\n", f);
    for (int a = 0; a < nc; ++a) fputs("0.5 ", f);
    fputs("\n", f);
    ck_assert_int_eq(fclose(f), 0);
}

#endif
