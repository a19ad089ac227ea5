/* FCLIB files, bad input: unreadable and malformed files (each with its error code and a
 * message naming the file and dataset), HDF5 kept silent, and failed writes that leave an
 * existing file untouched. Malformed files are built with the HDF5 C API. */
#define _POSIX_C_SOURCE 200809L /* mkdtemp, dup2, setrlimit under strict C99 */
#include <frix/frix.h>

#include <hdf5.h>

#include <dirent.h>
#include <fcntl.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include "check_main.h"
#include "fclib_fixtures.h"
#include "files.h"

/* Files in `dir` whose name starts with `prefix` (leftover temporary files). */
static int count_prefixed(const char *dir, const char *prefix) {
    DIR *d = opendir(dir);
    ck_assert_ptr_nonnull(d);
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)) != NULL)
        if (strncmp(e->d_name, prefix, strlen(prefix)) == 0) ++n;
    closedir(d);
    return n;
}


START_TEST(test_unreadable_files) {
    expect_read_error(tmp_path("does_not_exist.hdf5"), FRIX_ERR_IO, "No such file");
    expect_read_error(FRIX_TEST_TMPDIR, FRIX_ERR_IO, "directory");

    const char *text = tmp_path("text.hdf5");
    spit(text, "this is not HDF5\n", 17);
    expect_read_error(text, FRIX_ERR_IO, "not an HDF5 file");

    /* Version 0 superblocks found by fuzz_read_problem, refused before HDF5 opens them: a
     * reserved byte set, then the same with the reserved byte clear but a group B-tree rank K
     * of 65525, from which HDF5 1.10 sizes buffers of gigabytes before it fails. */
    static const unsigned char corrupt[49] = {
        0x89, 0x48, 0x44, 0x46, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x00, 0x00, 0x08, 0x08, 0xb8, 0xf5,
        0xff, 0xff, 0xff, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xff, 0xff,
        0x09, 0x00, 0x00, 0xff, 0xff, 0xff, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x08};
    const char *bad = tmp_path("corrupt_superblock.hdf5");
    spit(bad, (const char *)corrupt, (long)sizeof corrupt);
    expect_read_error(bad, FRIX_ERR_FORMAT, "corrupt HDF5 superblock");
    unsigned char bad_rank[49];
    memcpy(bad_rank, corrupt, sizeof bad_rank);
    bad_rank[15] = 0x00;
    spit(bad, (const char *)bad_rank, (long)sizeof bad_rank);
    expect_read_error(bad, FRIX_ERR_FORMAT, "corrupt HDF5 superblock");
    bad_rank[16] = 0x04; /* HDF5's default ranks (4 and 16) pass that check; the file ends inside the superblock */
    bad_rank[17] = 0x00;
    bad_rank[18] = 0x10;
    bad_rank[19] = 0x00;
    spit(bad, (const char *)bad_rank, (long)sizeof bad_rank);
    expect_read_error(bad, FRIX_ERR_FORMAT, "the file ends inside the superblock");

    /* Found by fuzz_read_problem: ranks 255, the file ending in the driver block's address
     * (49 of the superblock's 96 bytes). HDF5 1.10's H5Fopen asked for 4,278,192,152 bytes on
     * it, reading the superblock (H5F__super_read). */
    static const unsigned char cut_short[49] = {
        0x89, 0x48, 0x44, 0x46, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x00, 0x00, 0x08, 0x08, 0x00, 0xff,
        0x00, 0xff, 0x00, 0x00, 0xf5, 0xff, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xff, 0xff,
        0x09, 0x00, 0x00, 0xff, 0xff, 0xff, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x09};
    spit(bad, (const char *)cut_short, (long)sizeof cut_short);
    expect_read_error(bad, FRIX_ERR_FORMAT, "the file ends inside the superblock");
    spit(bad, (const char *)cut_short, 16); /* before the group ranks */
    expect_read_error(bad, FRIX_ERR_FORMAT, "the file ends inside the superblock");

    /* A version 0 superblock (sizes 8 and 8, HDF5's ranks, end of file 128) whose driver
     * information block at 96 declares 0xff000000 bytes: HDF5 1.10 allocates that much before
     * it finds the file short (fuzz_read_problem). Then the same block placed past the end. */
    unsigned char driver[128] = {0x89, 0x48, 0x44, 0x46, 0x0d, 0x0a, 0x1a, 0x0a, 0, 0, 0, 0, 0, 8, 8, 0, 4, 0, 16, 0};
    memset(driver + 32, 0xff, 8); /* no free-space index */
    driver[40] = 128;             /* end of file */
    driver[48] = 96;              /* driver information block */
    driver[96 + 7] = 0xff;        /* its length, little-endian 0xff000000 */
    memcpy(driver + 96 + 8, "NCSAmult", 8);
    spit(bad, (const char *)driver, (long)sizeof driver);
    expect_read_error(bad, FRIX_ERR_FORMAT, "driver information block is longer than the file");
    driver[48] = 0;
    driver[49] = 0x10; /* at 4096 */
    spit(bad, (const char *)driver, (long)sizeof driver);
    expect_read_error(bad, FRIX_ERR_FORMAT, "driver information block lies beyond the end of the file");

    frix_problem *p = (frix_problem *)0x1;
    ck_assert_int_eq(frix_fclib_read(NULL, &p), FRIX_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(frix_fclib_read(text, NULL), FRIX_ERR_INVALID_ARGUMENT);
    int64_t count;
    ck_assert_int_eq(frix_fclib_guess_count(text, &count), FRIX_ERR_IO);
    ck_assert_int_eq(frix_fclib_guess_count(text, NULL), FRIX_ERR_INVALID_ARGUMENT);

    if (have_shared()) {
        long size = 0;
        char *data = slurp(LOCAL_TEST, &size);
        const char *half = tmp_path("truncated.hdf5");
        spit(half, data, size / 2);
        free(data);
        expect_read_error(half, FRIX_ERR_IO, "truncated");
    }
}
END_TEST

START_TEST(test_malformed_content) {
    const char *path = tmp_path("malformed.hdf5");
    crafted c;

    /* The base is valid (so each failure below is the one change). */
    c = crafted_base();
    write_crafted(path, &c);
    frix_problem_free(read_ok(path));

    /* Missing q: written by frix, then the dataset unlinked. */
    small_local s;
    small_local_make(&s, "missing q");
    ck_assert_int_eq(frix_fclib_write(path, s.p, NULL, NULL, NULL, 0, NULL, NULL, NULL), FRIX_OK);
    small_local_free(&s);
    hid_t f = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
    ck_assert(f >= 0);
    ck_assert(H5Ldelete(f, "/fclib_local/vectors/q", H5P_DEFAULT) >= 0);
    H5Fclose(f);
    expect_read_error(path, FRIX_ERR_FORMAT, "/fclib_local/vectors/q is missing");

    c = crafted_base();
    c.nq = 5;
    write_crafted(path, &c);
    expect_read_error(path, FRIX_ERR_FORMAT, "/fclib_local/vectors/q has 5 entries, expected 6");

    c = crafted_base();
    c.nmu = 1;
    write_crafted(path, &c);
    expect_read_error(path, FRIX_ERR_FORMAT, "/fclib_local/vectors/mu");

    static const long long bad_p[] = {0, 2, 1, 4, 5, 6, 7};
    c = crafted_base();
    c.p = bad_p;
    write_crafted(path, &c);
    expect_read_error(path, FRIX_ERR_FORMAT, "/fclib_local/W/p decreases");

    static const long long bad_i[] = {0, 3, 1, 2, 3, 4, 6};
    c = crafted_base();
    c.i = bad_i;
    write_crafted(path, &c);
    expect_read_error(path, FRIX_ERR_FORMAT, "/fclib_local/W/i");

    c = crafted_base();
    c.n = 9;
    write_crafted(path, &c);
    expect_read_error(path, FRIX_ERR_FORMAT, "expected square");

    c = crafted_base();
    c.spacedim = 2;
    write_crafted(path, &c);
    expect_read_error(path, FRIX_ERR_UNSUPPORTED, "spacedim");

    /* m not a multiple of spacedim. */
    static const double q4[] = {-1, 0, 0, -1};
    static const long long p4[] = {0, 1, 2, 3, 4};
    c = crafted_base();
    c.m = c.n = 4;
    c.p = p4;
    c.np = 5;
    c.q = q4;
    c.nq = 4;
    write_crafted(path, &c);
    expect_read_error(path, FRIX_ERR_FORMAT, "multiple of spacedim");

    /* Huge declared sizes with small arrays: refused before anything that size exists. */
    c = crafted_base();
    c.int64 = 1;
    c.m = c.n = 3LL << 38;
    write_crafted(path, &c);
    expect_read_error(path, FRIX_ERR_FORMAT, "/fclib_local/vectors/q");
    c = crafted_base();
    c.int64 = 1;
    c.nz = 1LL << 40;
    c.nzmax = 1LL << 40;
    write_crafted(path, &c);
    expect_read_error(path, FRIX_ERR_FORMAT, "triplet count");
    c = crafted_base();
    c.nz = 7;
    c.nzmax = 5; /* fewer than the nz triplets */
    write_crafted(path, &c);
    expect_read_error(path, FRIX_ERR_FORMAT, "nzmax");
    c = crafted_base();
    c.nzmax = 3; /* fewer than the 7 entries p says */
    write_crafted(path, &c);
    expect_read_error(path, FRIX_ERR_FORMAT, "nzmax");

    c = crafted_base();
    c.nz = -3;
    write_crafted(path, &c);
    expect_read_error(path, FRIX_ERR_FORMAT, "/fclib_local/W/nz");

    static const double q_nan[] = {-1, NAN, 0, -1, 0, 0};
    c = crafted_base();
    c.q = q_nan;
    write_crafted(path, &c);
    expect_read_error(path, FRIX_ERR_FORMAT, "/fclib_local/vectors/q: entry 1");

    static const double mu_neg[] = {0.3, -0.5};
    c = crafted_base();
    c.mu = mu_neg;
    write_crafted(path, &c);
    expect_read_error(path, FRIX_ERR_FORMAT, "/fclib_local/vectors/mu: entry 1");

    /* A dataset whose extent is forged far beyond what the file stores. */
    c = crafted_base();
    c.int64 = 1;
    c.m = c.n = 3LL << 31;
    c.q = NULL;
    write_crafted(path, &c);
    f = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
    hsize_t dim = 3ULL << 31;
    hid_t sp = H5Screate_simple(1, &dim, NULL);
    hid_t ds = H5Dcreate2(f, "/fclib_local/vectors/q", H5T_IEEE_F64LE, sp, H5P_DEFAULT,
                          H5P_DEFAULT, H5P_DEFAULT);
    ck_assert(ds >= 0);
    H5Dclose(ds);
    H5Sclose(sp);
    H5Fclose(f);
    expect_read_error(path, FRIX_ERR_FORMAT, "stores only");

    /* An HDF5 file with no FCLIB group. */
    f = H5Fcreate(path, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    H5Fclose(f);
    expect_read_error(path, FRIX_ERR_FORMAT, "/fclib_local");
    /* The rolling-friction groups' bad input: test_rolling_io. */
}
END_TEST

/* Failing reads print nothing, and HDF5's error handler is the caller's again afterwards. */
START_TEST(test_hdf5_stays_silent) {
    H5E_auto2_t before_fn = NULL, after_fn = NULL;
    void *before_data = NULL, *after_data = NULL;
    ck_assert(H5Eget_auto2(H5E_DEFAULT, &before_fn, &before_data) >= 0);
    ck_assert_ptr_nonnull((void *)before_fn); /* HDF5's default printer */

    const char *text = tmp_path("silent.hdf5");
    spit(text, "not HDF5 at all, but long enough to be probed by the library......", 66);
    const char *captured = tmp_path("stderr.txt");
    fflush(stderr);
    int saved = dup(2);
    int fd = open(captured, O_CREAT | O_TRUNC | O_WRONLY, 0644);
    ck_assert(saved >= 0 && fd >= 0);
    dup2(fd, 2);
    frix_problem *p = NULL;
    frix_error e1 = frix_fclib_read(text, &p);
    /* A rolling-friction problem (/fclib_global_rolling, written by Siconos) reads, silently. */
    frix_error e2 = have_shared() ? frix_fclib_read(ROLLING, &p) : FRIX_OK;
    frix_problem_free(p);
    p = NULL;
    crafted c = crafted_base();
    c.nz = -3;
    write_crafted(tmp_path("silent2.hdf5"), &c);
    frix_error e3 = frix_fclib_read(tmp_path("silent2.hdf5"), &p);
    small_local s;
    small_local_make(&s, "silent");
    frix_error e4 = frix_fclib_write(FRIX_TEST_TMPDIR "/no/such/dir/x.hdf5", s.p, NULL, NULL,
                                     NULL, 0, NULL, NULL, NULL);
    frix_error e5 = frix_fclib_write(FRIX_TEST_TMPDIR, s.p, NULL, NULL, NULL, 0, NULL, NULL, NULL);
    small_local_free(&s);
    fflush(stderr);
    dup2(saved, 2);
    close(saved);
    close(fd);
    ck_assert_int_eq(e1, FRIX_ERR_IO);
    ck_assert_int_eq(e2, FRIX_OK);
    ck_assert_int_eq(e3, FRIX_ERR_FORMAT);
    ck_assert_int_eq(e4, FRIX_ERR_IO);
    ck_assert_int_eq(e5, FRIX_ERR_IO);
    struct stat st;
    ck_assert_int_eq(stat(captured, &st), 0);
    ck_assert_msg(st.st_size == 0, "frix printed %lld bytes to stderr", (long long)st.st_size);

    ck_assert(H5Eget_auto2(H5E_DEFAULT, &after_fn, &after_data) >= 0);
    ck_assert(after_fn == before_fn);
    ck_assert_ptr_eq(after_data, before_data);
}
END_TEST

/* A failed write leaves the file that was there byte for byte, and no temporary file. */
START_TEST(test_failed_write_keeps_existing_file) {
    /* A fresh directory, so the leftover check cannot see files of an earlier run. */
    char dir[1024];
    snprintf(dir, sizeof dir, "%s", tmp_path("writefail.XXXXXX"));
    ck_assert_ptr_nonnull(mkdtemp(dir));
    char target[1100];
    snprintf(target, sizeof target, "%s/problem.hdf5", dir);

    small_local s;
    small_local_make(&s, "original");
    ck_assert_int_eq(frix_fclib_write(target, s.p, NULL, NULL, NULL, 0, NULL, NULL, NULL),
                     FRIX_OK);
    long size0 = 0;
    char *before = slurp(target, &size0);

    /* The write runs out of room half-way (a file size limit stands in for a full disk). */
    small_local big;
    small_local_make(&big, "replacement");
    const int64_t n_guesses = 2000; /* ~200 KB of guesses */
    double *g = calloc((size_t)(6 * n_guesses), sizeof(double));
    struct rlimit old_limit, limit;
    ck_assert_int_eq(getrlimit(RLIMIT_FSIZE, &old_limit), 0);
    limit = old_limit;
    limit.rlim_cur = 16 * 1024;
    void (*old_handler)(int) = signal(SIGXFSZ, SIG_IGN);
    ck_assert_int_eq(setrlimit(RLIMIT_FSIZE, &limit), 0);
    frix_error err = frix_fclib_write(target, big.p, NULL, NULL, NULL, n_guesses, g, g, NULL);
    setrlimit(RLIMIT_FSIZE, &old_limit);
    signal(SIGXFSZ, old_handler);
    ck_assert_msg(err == FRIX_ERR_IO, "got %d: %s", err, frix_last_error_message());
    ck_assert(strstr(frix_last_error_message(), target) != NULL);
    free(g);

    /* The path is a directory: refused, the directory stays. */
    char as_dir[1100];
    snprintf(as_dir, sizeof as_dir, "%s/a_directory", dir);
    mkdir(as_dir, 0755);
    ck_assert_int_eq(frix_fclib_write(as_dir, s.p, NULL, NULL, NULL, 0, NULL, NULL, NULL),
                     FRIX_ERR_IO);
    struct stat st;
    ck_assert(stat(as_dir, &st) == 0 && S_ISDIR(st.st_mode));

    /* The directory does not exist. */
    char missing[1100];
    snprintf(missing, sizeof missing, "%s/no_such_dir/problem.hdf5", dir);
    ck_assert_int_eq(frix_fclib_write(missing, s.p, NULL, NULL, NULL, 0, NULL, NULL, NULL),
                     FRIX_ERR_IO);
    ck_assert(strstr(frix_last_error_message(), "no_such_dir") != NULL);

    /* Refused arguments never touch the file. */
    ck_assert_int_eq(frix_fclib_write(target, NULL, NULL, NULL, NULL, 0, NULL, NULL, NULL),
                     FRIX_ERR_INVALID_ARGUMENT);

    long size1 = 0;
    char *after = slurp(target, &size1);
    ck_assert_int_eq(size0, size1);
    ck_assert(memcmp(before, after, (size_t)size0) == 0);
    ck_assert_int_eq(count_prefixed(dir, "problem.hdf5.tmp."), 0);
    ck_assert_int_eq(count_prefixed(dir, "a_directory.tmp."), 0);
    frix_problem *p = read_ok(target);
    ck_assert_str_eq(frix_problem_title(p), "original");
    frix_problem_free(p);

    /* And a successful write replaces it. */
    ck_assert_int_eq(frix_fclib_write(target, big.p, NULL, NULL, NULL, 0, NULL, NULL, NULL),
                     FRIX_OK);
    p = read_ok(target);
    ck_assert_str_eq(frix_problem_title(p), "replacement");
    frix_problem_free(p);
    ck_assert_int_eq(count_prefixed(dir, "problem.hdf5.tmp."), 0);

    free(before);
    free(after);
    small_local_free(&big);
    small_local_free(&s);
    ck_assert_int_eq(unlink(target), 0);
    ck_assert_int_eq(rmdir(as_dir), 0);
    ck_assert_int_eq(rmdir(dir), 0); /* fails if anything else was left behind */
}
END_TEST

int main(void) {
    Suite *s = suite_create("fclib");
    TCase *bad = tcase_create("bad_input");
    tcase_add_test(bad, test_unreadable_files);
    tcase_add_test(bad, test_malformed_content);
    tcase_add_test(bad, test_hdf5_stays_silent);
    tcase_add_test(bad, test_failed_write_keeps_existing_file);
    suite_add_tcase(s, bad);
    return frix_run_suite(s);
}
