/* Outputs never lose data: frix_fclib_write and the `frix` commands that write (solve
 * --output, convert) refuse a target that is the input file, not a regular file (FIFO,
 * directory, device, socket) or read-only, check it before a solve starts, follow a
 * symbolic link to the file it points to (the link stays a link), and leave an existing file
 * intact, with no temporary file, when a write fails. Every case runs in a fresh directory. */
#define _XOPEN_SOURCE 700

#include <frix/frix.h>

#include <dirent.h>
#include <errno.h>
#include <ftw.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/un.h>
#include <unistd.h>

#include "check_main.h"
#include "cli_runner.h"

/* ---- Fixtures --------------------------------------------------------------------- */

/* A fresh directory per test, so leftover checks cannot see files of another run. */
static char g_dir[1024];

static void make_dir(void) {
    snprintf(g_dir, sizeof g_dir, "%s/outputs.XXXXXX", FRIX_TEST_TMPDIR);
    ck_assert_ptr_nonnull(mkdtemp(g_dir));
}

/* A path inside the test's directory, in one of 4 rotating buffers: a path used after
 * further calls is copied first. */
static const char *in_dir(const char *name) {
    static char buf[4][1200];
    static int next = 0;
    char *out = buf[next++ % 4];
    snprintf(out, sizeof buf[0], "%s/%s", g_dir, name);
    return out;
}

static int remove_entry(const char *path, const struct stat *st, int flag, struct FTW *ftw) {
    (void)st;
    (void)flag;
    (void)ftw;
    return remove(path);
}

static void remove_dir(void) {
    ck_assert_int_eq(nftw(g_dir, remove_entry, 16, FTW_DEPTH | FTW_PHYS), 0);
}

/* Two coupled contacts, titled so that a replaced file is told from the original. */
static void write_problem(const char *path, const char *title) {
    double a[36] = {0};
    for (int k = 0; k < 6; ++k) a[k * 6 + k] = 2.0 + k;
    a[0 * 6 + 3] = a[3 * 6 + 0] = 0.5;
    const double q[6] = {-1, 0.25, 0, -2, 0, 0.125}, mu[2] = {0.3, 0.5};
    frix_matrix *W = NULL;
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_matrix_from_dense(6, 6, a, 6, &W), FRIX_OK);
    ck_assert_int_eq(frix_problem_local(W, q, mu, 2, &p), FRIX_OK);
    ck_assert_int_eq(frix_problem_set_title(p, title), FRIX_OK);
    ck_assert_msg(frix_fclib_write(path, p, NULL, NULL, NULL, 0, NULL, NULL, NULL) == FRIX_OK,
                  "%s", frix_last_error_message());
    frix_problem_free(p);
    frix_matrix_free(W);
}

/* The problem of an FCLIB file, or NULL when it does not read. */
static frix_problem *read_or_null(const char *path) {
    frix_problem *p = NULL;
    if (frix_fclib_read(path, &p) != FRIX_OK) return NULL;
    return p;
}

static void expect_title(const char *path, const char *title) {
    frix_problem *p = read_or_null(path);
    ck_assert_msg(p != NULL, "%s: %s", path, frix_last_error_message());
    ck_assert_str_eq(frix_problem_title(p), title);
    frix_problem_free(p);
}

static void expect_same_bytes(const char *path, const char *before, long before_size) {
    long size = 0;
    char *now = slurp(path, &size);
    ck_assert_msg(size == before_size && memcmp(now, before, (size_t)size) == 0,
                  "%s was changed (%ld bytes, was %ld)", path, size, before_size);
    free(now);
}

/* Temporary files ("NAME.tmp.XXXXXX") left in a directory. */
static int leftovers(const char *dir) {
    DIR *d = opendir(dir);
    ck_assert_ptr_nonnull(d);
    int n = 0;
    for (struct dirent *e; (e = readdir(d)) != NULL;)
        if (strstr(e->d_name, ".tmp.") != NULL) ++n;
    closedir(d);
    return n;
}

static mode_t kind(const char *path) {
    struct stat st;
    ck_assert_msg(lstat(path, &st) == 0, "%s: %s", path, strerror(errno));
    return st.st_mode & S_IFMT;
}

static void expect_link_to(const char *link, const char *target) {
    ck_assert_msg(kind(link) == S_IFLNK, "%s is no longer a symbolic link", link);
    char buf[1200];
    ssize_t n = readlink(link, buf, sizeof buf - 1);
    ck_assert_int_gt(n, 0);
    buf[n] = '\0';
    ck_assert_str_eq(buf, target);
}

/* A listening-free Unix socket bound at `path` (0 if the system refuses one). */
static int make_socket(const char *path) {
    struct sockaddr_un addr;
    memset(&addr, 0, sizeof addr);
    addr.sun_family = AF_UNIX;
    if (strlen(path) >= sizeof addr.sun_path) return 0;
    strcpy(addr.sun_path, path);
    int fd = socket(AF_UNIX, SOCK_STREAM, 0);
    if (fd < 0) return 0;
    int ok = bind(fd, (struct sockaddr *)&addr, sizeof addr) == 0;
    close(fd); /* the socket file stays */
    return ok;
}

/* A character device node standing for /dev/null: made with mknod where allowed (root in
 * most containers), else /dev/null itself, which only root could replace. NULL if neither
 * can be tested safely. */
static const char *device_node(void) {
    static char node[1200];
    snprintf(node, sizeof node, "%s", in_dir("null_device"));
    if (mknod(node, S_IFCHR | 0666, makedev(1, 3)) == 0) return node;
    if (geteuid() != 0) return "/dev/null";
    printf("test_outputs: cannot create a device node: device case skipped\n");
    return NULL;
}

/* Runs the CLI; expects exit 2 with `must_contain` in its one-line message and nothing on
 * stdout (for solve: the refusal came before the solve, which prints a report). */
static void expect_refused(const char *const *args, const char *must_contain) {
    cli_run r = run_cli(args);
    ck_assert_msg(r.code == 2, "frix %s: exit %d, stdout '%s', stderr '%s'", args[0], r.code,
                  r.out, r.err);
    ck_assert_msg(strstr(r.err, must_contain) != NULL, "stderr lacks '%s': %s", must_contain,
                  r.err);
    ck_assert_msg(strchr(r.err, '\n') == r.err + strlen(r.err) - 1, "stderr is not one line: '%s'",
                  r.err);
    ck_assert_msg(r.out[0] == '\0', "stdout not empty: %s", r.out);
    run_free(&r);
}

static void expect_success(const char *const *args) {
    cli_run r = run_cli(args);
    /* A solve may end unconverged (exit 1); the file is written either way. */
    ck_assert_msg(r.code == 0 || (strcmp(args[0], "solve") == 0 && r.code == 1),
                  "frix %s: exit %d: %s%s", args[0], r.code, r.out, r.err);
    run_free(&r);
}

/* ---- The library writer ----------------------------------------------------------- */

/* A symbolic link as target: the file it points to is replaced and the link stays, also
 * relative, chained and dangling links; the temporary file goes next to the real file. */
START_TEST(test_write_through_symlink) {
    make_dir();
    ck_assert_int_eq(mkdir(in_dir("sub"), 0755), 0);
    write_problem(in_dir("real.hdf5"), "old");
    ck_assert_int_eq(symlink("../real.hdf5", in_dir("sub/link.hdf5")), 0);
    ck_assert_int_eq(symlink("sub/link.hdf5", in_dir("chain.hdf5")), 0);

    write_problem(in_dir("sub/link.hdf5"), "through the link");
    expect_link_to(in_dir("sub/link.hdf5"), "../real.hdf5");
    ck_assert(kind(in_dir("real.hdf5")) == S_IFREG);
    expect_title(in_dir("real.hdf5"), "through the link");

    write_problem(in_dir("chain.hdf5"), "through two links");
    expect_link_to(in_dir("chain.hdf5"), "sub/link.hdf5");
    expect_link_to(in_dir("sub/link.hdf5"), "../real.hdf5");
    expect_title(in_dir("real.hdf5"), "through two links");

    /* A dangling link: the file it names is created. */
    ck_assert_int_eq(symlink("sub/made.hdf5", in_dir("dangling.hdf5")), 0);
    write_problem(in_dir("dangling.hdf5"), "created");
    expect_link_to(in_dir("dangling.hdf5"), "sub/made.hdf5");
    expect_title(in_dir("sub/made.hdf5"), "created");

    ck_assert_int_eq(leftovers(g_dir), 0);
    ck_assert_int_eq(leftovers(in_dir("sub")), 0);
    remove_dir();
}
END_TEST

/* Expects frix_fclib_write to refuse `path` with FRIX_ERR_IO and `what` in the message. */
static void expect_write_refused(const char *path, const char *what) {
    double a[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    const double q[3] = {-1, 0, 0}, mu[1] = {0.5};
    frix_matrix *W = NULL;
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_matrix_from_dense(3, 3, a, 3, &W), FRIX_OK);
    ck_assert_int_eq(frix_problem_local(W, q, mu, 1, &p), FRIX_OK);
    const frix_error err = frix_fclib_write(path, p, NULL, NULL, NULL, 0, NULL, NULL, NULL);
    ck_assert_msg(err == FRIX_ERR_IO, "%s: got %d: %s", path, err, frix_last_error_message());
    ck_assert_msg(strstr(frix_last_error_message(), what) != NULL, "message lacks '%s': %s", what,
                  frix_last_error_message());
    frix_problem_free(p);
    frix_matrix_free(W);
}

/* A target that is not a regular file is refused and stays what it is: renaming a file
 * over it would destroy a FIFO, socket or device node. A FIFO is never opened (no hang). */
START_TEST(test_write_refuses_non_regular) {
    make_dir();
    ck_assert_int_eq(mkfifo(in_dir("fifo"), 0644), 0);
    expect_write_refused(in_dir("fifo"), "FIFO");
    ck_assert(kind(in_dir("fifo")) == S_IFIFO);

    /* Behind a symbolic link too; the link stays. */
    ck_assert_int_eq(symlink("fifo", in_dir("to_fifo")), 0);
    expect_write_refused(in_dir("to_fifo"), "FIFO");
    expect_link_to(in_dir("to_fifo"), "fifo");
    ck_assert(kind(in_dir("fifo")) == S_IFIFO);

    ck_assert_int_eq(mkdir(in_dir("adir"), 0755), 0);
    expect_write_refused(in_dir("adir"), "directory");
    ck_assert(kind(in_dir("adir")) == S_IFDIR);

    if (make_socket(in_dir("sock"))) {
        expect_write_refused(in_dir("sock"), "socket");
        ck_assert(kind(in_dir("sock")) == S_IFSOCK);
    } else {
        printf("test_outputs: cannot bind a Unix socket: socket case skipped\n");
    }

    const char *dev = device_node();
    if (dev != NULL) {
        expect_write_refused(dev, "character device");
        ck_assert(kind(dev) == S_IFCHR);
    }
    ck_assert_int_eq(leftovers(g_dir), 0);
    remove_dir();
}
END_TEST

/* A read-only file is not replaced, though the directory would allow the rename.
 * Root passes access(W_OK) on any file, so the writer also treats "no write bit for anyone"
 * as read-only; that is what this test relies on when it runs as root. */
START_TEST(test_write_refuses_read_only) {
    make_dir();
    char ro[1200];
    snprintf(ro, sizeof ro, "%s", in_dir("ro.hdf5"));
    write_problem(ro, "keep");
    ck_assert_int_eq(chmod(ro, 0444), 0);
    long size = 0;
    char *before = slurp(ro, &size);
    expect_write_refused(ro, "read-only");
    expect_same_bytes(ro, before, size);
    struct stat st;
    ck_assert_int_eq(stat(ro, &st), 0);
    ck_assert_int_eq(st.st_mode & 07777, 0444);
    ck_assert_int_eq(leftovers(g_dir), 0);
    free(before);
    remove_dir();
}
END_TEST

/* ---- The CLI ---------------------------------------------------------------------- */

/* The output is the input (same file, by name, hard link or symbolic link, either way
 * round): refused with a message naming --force, and the input is unchanged; --force
 * allows it. */
START_TEST(test_cli_output_is_input) {
    make_dir();
    char in[1200];
    snprintf(in, sizeof in, "%s", in_dir("in.hdf5"));
    write_problem(in, "input");
    long size = 0;
    char *before = slurp(in, &size);
    char hard[1200], sym[1200];
    snprintf(hard, sizeof hard, "%s", in_dir("hard.hdf5"));
    snprintf(sym, sizeof sym, "%s", in_dir("sym.hdf5"));
    ck_assert_int_eq(link(in, hard), 0);
    ck_assert_int_eq(symlink("in.hdf5", sym), 0);

    const char *c1[] = {"convert", in, in, NULL};
    expect_refused(c1, "is the input file");
    const char *c2[] = {"convert", in, hard, NULL};
    expect_refused(c2, "--force");
    const char *c3[] = {"convert", in, sym, NULL};
    expect_refused(c3, "is the input file");
    const char *c4[] = {"convert", sym, in, NULL};
    expect_refused(c4, "is the input file");
    /* Before the solve: nothing on stdout. */
    const char *s1[] = {"solve", in, "--output", in, NULL};
    expect_refused(s1, "is the input file");
    const char *s2[] = {"solve", sym, "--output", hard, "--json", NULL};
    expect_refused(s2, "is the input file");
    expect_same_bytes(in, before, size);
    expect_link_to(sym, "in.hdf5");

    /* --force: the input is replaced (atomically, like any output). */
    const char *f1[] = {"convert", in, sym, "--title", "forced", "--force", NULL};
    expect_success(f1);
    expect_link_to(sym, "in.hdf5");
    expect_title(in, "forced");
    const char *f2[] = {"solve", in, "--force", "--output", in, NULL};
    expect_success(f2);
    frix_problem *p = read_or_null(in);
    ck_assert_ptr_nonnull(p);
    double r[6], u[6];
    ck_assert_msg(frix_fclib_read_solution(in, p, r, u, NULL) == FRIX_OK, "%s",
                  frix_last_error_message());
    frix_problem_free(p);
    ck_assert_int_eq(leftovers(g_dir), 0);
    free(before);
    remove_dir();
}
END_TEST

/* A Siconos .dat input is never replaced by its HDF5 conversion, by name or through a link. */
START_TEST(test_cli_dat_input_kept) {
    make_dir();
    char dat[1200];
    snprintf(dat, sizeof dat, "%s", in_dir("p.dat"));
    const char *text = "3 1\n0 3 3\n3 3\n2 0 0  1 3 0  0 0 4\n-1 0 0\n0.5\n";
    spit_text(dat, text);
    ck_assert_int_eq(symlink("p.dat", in_dir("p.hdf5")), 0);

    const char *c1[] = {"convert", dat, dat, NULL};
    expect_refused(c1, "is the input file");
    const char *c2[] = {"convert", dat, in_dir("p.hdf5"), NULL};
    expect_refused(c2, "is the input file");
    const char *s1[] = {"solve", dat, "--output", dat, NULL};
    expect_refused(s1, "is the input file");
    expect_same_bytes(dat, text, (long)strlen(text));

    /* Another output is fine. */
    const char *c3[] = {"convert", dat, in_dir("out.hdf5"), NULL};
    expect_success(c3);
    frix_problem *p = read_or_null(in_dir("out.hdf5"));
    ck_assert_ptr_nonnull(p);
    ck_assert_int_eq(frix_problem_contacts(p), 1);
    frix_problem_free(p);
    remove_dir();
}
END_TEST

/* An output that exists and is not a regular file is refused before anything is opened or
 * solved (a FIFO would block an open until a reader comes), and stays what it is. */
START_TEST(test_cli_output_not_regular) {
    make_dir();
    char in[1200];
    snprintf(in, sizeof in, "%s", in_dir("in.hdf5"));
    write_problem(in, "input");

    ck_assert_int_eq(mkfifo(in_dir("fifo"), 0644), 0);
    const char *c1[] = {"convert", in, in_dir("fifo"), NULL};
    expect_refused(c1, "FIFO");
    const char *s1[] = {"solve", in, "--output", in_dir("fifo"), NULL};
    expect_refused(s1, "FIFO");
    ck_assert(kind(in_dir("fifo")) == S_IFIFO);
    ck_assert_int_eq(symlink("fifo", in_dir("to_fifo")), 0);
    const char *s2[] = {"solve", in, "--output", in_dir("to_fifo"), NULL};
    expect_refused(s2, "FIFO");
    expect_link_to(in_dir("to_fifo"), "fifo");

    ck_assert_int_eq(mkdir(in_dir("adir"), 0755), 0);
    const char *s3[] = {"solve", in, "--output", in_dir("adir"), NULL};
    expect_refused(s3, "directory");
    ck_assert(kind(in_dir("adir")) == S_IFDIR);

    if (make_socket(in_dir("sock"))) {
        const char *c2[] = {"convert", in, in_dir("sock"), NULL};
        expect_refused(c2, "socket");
        ck_assert(kind(in_dir("sock")) == S_IFSOCK);
    } else {
        printf("test_outputs: cannot bind a Unix socket: socket case skipped\n");
    }

    const char *dev = device_node();
    if (dev != NULL) {
        const char *s4[] = {"solve", in, "--output", dev, NULL};
        expect_refused(s4, "character device");
        ck_assert(kind(dev) == S_IFCHR);
    }
    ck_assert_int_eq(leftovers(g_dir), 0);
    remove_dir();
}
END_TEST

/* A read-only output file is refused, before the solve, and kept byte for byte. Root passes
 * access(W_OK) on any file, so the CLI also treats "no write bit for anyone" as read-only;
 * that is what this test relies on when it runs as root. */
START_TEST(test_cli_output_read_only) {
    make_dir();
    char in[1200];
    snprintf(in, sizeof in, "%s", in_dir("in.hdf5"));
    char ro[1200];
    snprintf(ro, sizeof ro, "%s", in_dir("ro.hdf5"));
    write_problem(in, "input");
    write_problem(ro, "keep");
    ck_assert_int_eq(chmod(ro, 0444), 0);
    long size = 0;
    char *before = slurp(ro, &size);
    const char *c1[] = {"convert", in, ro, NULL};
    expect_refused(c1, "read-only");
    const char *s1[] = {"solve", in, "--output", ro, NULL};
    expect_refused(s1, "read-only");
    /* --force is about the input only; it does not override a read-only output. */
    const char *s2[] = {"solve", in, "--output", ro, "--force", NULL};
    expect_refused(s2, "read-only");
    expect_same_bytes(ro, before, size);
    ck_assert_int_eq(leftovers(g_dir), 0);
    free(before);
    remove_dir();
}
END_TEST

/* An output directory that does not exist, or cannot be written, is reported before the
 * solve: no report on stdout, one error line. */
START_TEST(test_cli_output_checked_before_solve) {
    make_dir();
    char in[1200];
    snprintf(in, sizeof in, "%s", in_dir("in.hdf5"));
    write_problem(in, "input");
    const char *s1[] = {"solve", in, "--output", in_dir("no_such_dir/out.hdf5"), NULL};
    expect_refused(s1, "no_such_dir");
    const char *c1[] = {"convert", in, in_dir("no_such_dir/out.hdf5"), NULL};
    expect_refused(c1, "no_such_dir");
    /* A path through a regular file. */
    const char *s2[] = {"solve", in, "--output", in_dir("in.hdf5/out.hdf5"), "--json", NULL};
    expect_refused(s2, "cannot write");

    /* Root writes into any directory, so the unwritable one is tested for others only. */
    if (geteuid() != 0) {
        ck_assert_int_eq(mkdir(in_dir("locked"), 0555), 0);
        const char *s3[] = {"solve", in, "--output", in_dir("locked/out.hdf5"), NULL};
        expect_refused(s3, "not writable");
        ck_assert_int_eq(chmod(in_dir("locked"), 0755), 0);
    }
    remove_dir();
}
END_TEST

/* An output that is a symbolic link keeps pointing where it points: the file it names is
 * replaced, and the temporary file is made next to that file, not next to the link. */
START_TEST(test_cli_output_symlink) {
    make_dir();
    char in[1200];
    snprintf(in, sizeof in, "%s", in_dir("in.hdf5"));
    write_problem(in, "input");
    ck_assert_int_eq(mkdir(in_dir("results"), 0755), 0);
    write_problem(in_dir("results/real.hdf5"), "old");
    ck_assert_int_eq(symlink("results/real.hdf5", in_dir("latest.hdf5")), 0);

    const char *c1[] = {"convert", in, in_dir("latest.hdf5"), "--title", "converted", NULL};
    expect_success(c1);
    expect_link_to(in_dir("latest.hdf5"), "results/real.hdf5");
    expect_title(in_dir("results/real.hdf5"), "converted");

    const char *s1[] = {"solve", in, "--output", in_dir("latest.hdf5"), NULL};
    expect_success(s1);
    expect_link_to(in_dir("latest.hdf5"), "results/real.hdf5");
    frix_problem *p = read_or_null(in_dir("results/real.hdf5"));
    ck_assert_ptr_nonnull(p);
    double r[6], u[6];
    ck_assert_msg(frix_fclib_read_solution(in_dir("results/real.hdf5"), p, r, u, NULL) == FRIX_OK,
                  "%s", frix_last_error_message());
    frix_problem_free(p);
    ck_assert_int_eq(leftovers(g_dir), 0);
    ck_assert_int_eq(leftovers(in_dir("results")), 0);
    remove_dir();
}
END_TEST

/* A write that fails half-way (a file size limit stands in for a full disk) leaves the old
 * output byte for byte and no temporary file. The limit is set by a shell around the CLI
 * only: in this process it would also cut Check's own message file. */
START_TEST(test_cli_failed_write_keeps_old_file) {
    make_dir();
    char in[1200];
    snprintf(in, sizeof in, "%s", in_dir("in.hdf5"));
    char out[1200];
    snprintf(out, sizeof out, "%s", in_dir("out.hdf5"));
    write_problem(in, "input");
    spit_text(out, "the previous output\n");
    long size = 0;
    char *before = slurp(out, &size);
    long in_size = 0;
    free(slurp(in, &in_size));
    /* ulimit -f 2: 1 KiB or 2 KiB (by the shell's block size), above the CLI's one-line
     * message and below the file it writes (which is in's size). */
    ck_assert_int_gt(in_size, 2048);
    /* An ignored SIGXFSZ stays ignored across exec: write() then fails with EFBIG. */
    const char *script = "trap '' XFSZ; ulimit -f 2 && exec \"$0\" convert \"$1\" \"$2\"";
    const char *args[] = {"-c", script, FRIX_CLI, in, out, NULL};
    cli_run r = run_program("/bin/sh", args);
    ck_assert_msg(r.code == 2 && strstr(r.err, "cannot write") != NULL, "exit %d: %s", r.code,
                  r.err);
    run_free(&r);
    expect_same_bytes(out, before, size);
    ck_assert_int_eq(leftovers(g_dir), 0);
    free(before);
    remove_dir();
}
END_TEST

static Suite *outputs_suite(void) {
    Suite *s = suite_create("outputs");
    TCase *lib = tcase_create("library");
    tcase_add_test(lib, test_write_through_symlink);
    tcase_add_test(lib, test_write_refuses_non_regular);
    tcase_add_test(lib, test_write_refuses_read_only);
    suite_add_tcase(s, lib);
    TCase *cli = tcase_create("cli");
    tcase_add_test(cli, test_cli_output_is_input);
    tcase_add_test(cli, test_cli_dat_input_kept);
    tcase_add_test(cli, test_cli_output_not_regular);
    tcase_add_test(cli, test_cli_output_read_only);
    tcase_add_test(cli, test_cli_output_checked_before_solve);
    tcase_add_test(cli, test_cli_output_symlink);
    tcase_add_test(cli, test_cli_failed_write_keeps_old_file);
    suite_add_tcase(s, cli);
    return s;
}

int main(void) { return frix_run_suite(outputs_suite()); }
