/* Hostile input files: the readers trust nothing in them. FCLIB files whose links or storage
 * lead outside the file (external, soft and user-defined links, external raw storage,
 * virtual datasets) are refused before any data is read; sizes, chunks and matrix arrays are
 * bounded by the file's size; datasets that were never written are errors, not zeros; paths
 * that are not regular files are refused without blocking; .dat files are streamed with NUL
 * bytes and overlong tokens refused; control characters from files reach neither messages
 * nor titles raw. Every file is built here, small, in a temporary directory. */
#define _POSIX_C_SOURCE 200809L
#include <frix/frix.h>

#include <hdf5.h>

#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include "check_main.h"
#include "files.h"

static const char *tmp_path(const char *name) {
    static char buf[8][1024];
    static int next = 0;
    char *out = buf[next++ % 8];
    snprintf(out, sizeof buf[0], "%s/hostile_%s", FRIX_TEST_TMPDIR, name);
    return out;
}

/* ---- A valid local problem, then damaged ----------------------------------------------- */

static void put_int32s(hid_t loc, const char *name, const int *v, hsize_t n) {
    hid_t sp = H5Screate_simple(1, &n, NULL);
    hid_t ds = H5Dcreate2(loc, name, H5T_STD_I32LE, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    ck_assert(ds >= 0);
    ck_assert(H5Dwrite(ds, H5T_NATIVE_INT, H5S_ALL, H5S_ALL, H5P_DEFAULT, v) >= 0);
    H5Dclose(ds);
    H5Sclose(sp);
}

static void put_doubles(hid_t loc, const char *name, const double *v, hsize_t n) {
    hid_t sp = H5Screate_simple(1, &n, NULL);
    hid_t ds = H5Dcreate2(loc, name, H5T_IEEE_F64LE, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    ck_assert(ds >= 0);
    ck_assert(H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v) >= 0);
    H5Dclose(ds);
    H5Sclose(sp);
}

static void put_int(hid_t loc, const char *name, int value) { put_int32s(loc, name, &value, 1); }

static void put_title(hid_t loc, const char *name, const char *title) {
    hid_t t = H5Tcopy(H5T_C_S1);
    H5Tset_size(t, H5T_VARIABLE);
    hid_t sp = H5Screate(H5S_SCALAR);
    hid_t ds = H5Dcreate2(loc, name, t, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    ck_assert(ds >= 0);
    if (title != NULL) ck_assert(H5Dwrite(ds, t, H5S_ALL, H5S_ALL, H5P_DEFAULT, &title) >= 0);
    H5Dclose(ds);
    H5Sclose(sp);
    H5Tclose(t);
}

static const double base_q[3] = {-1, 0, 0};

/* One contact, W the 3x3 identity in CSR, q = (-1, 0, 0), mu = 0.3, with a title. */
static void write_base(const char *path) {
    hid_t f = H5Fcreate(path, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    ck_assert(f >= 0);
    hid_t g = H5Gcreate2(f, "/fclib_local", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    put_int(g, "spacedim", 3);
    hid_t w = H5Gcreate2(g, "W", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    static const int p[] = {0, 1, 2, 3}, i[] = {0, 1, 2};
    static const double x[] = {1, 1, 1};
    put_int(w, "nzmax", 3);
    put_int(w, "m", 3);
    put_int(w, "n", 3);
    put_int(w, "nz", -2);
    put_int32s(w, "p", p, 4);
    put_int32s(w, "i", i, 3);
    put_doubles(w, "x", x, 3);
    H5Gclose(w);
    hid_t v = H5Gcreate2(g, "vectors", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    const double mu = 0.3;
    put_doubles(v, "q", base_q, 3);
    put_doubles(v, "mu", &mu, 1);
    H5Gclose(v);
    hid_t info = H5Gcreate2(g, "info", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    put_title(info, "title", "hostile");
    H5Gclose(info);
    H5Gclose(g);
    ck_assert(H5Fclose(f) >= 0);
}

/* The base file opened for a change, with `name` (if not NULL) removed first. */
static hid_t reopen_without(const char *path, const char *name) {
    hid_t f = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
    ck_assert(f >= 0);
    if (name != NULL) ck_assert_msg(H5Ldelete(f, name, H5P_DEFAULT) >= 0, "cannot delete %s", name);
    return f;
}

/* Another file holding /q = base_q, for links and sources that lead out of the problem file. */
static const char *write_other_file(void) {
    const char *other = tmp_path("other.hdf5");
    hid_t f = H5Fcreate(other, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    ck_assert(f >= 0);
    put_doubles(f, "q", base_q, 3);
    ck_assert(H5Fclose(f) >= 0);
    return other;
}

static int has_control_byte(const char *s) {
    for (; *s != '\0'; ++s)
        if ((unsigned char)*s < 0x20 || (unsigned char)*s == 0x7f) return 1;
    return 0;
}

/* Reading fails with `code`; the message names the file, contains `needle`, and carries no
 * raw control character. */
static void expect_refused(frix_error (*reader)(const char *, frix_problem **), const char *path,
                           frix_error code, const char *needle) {
    frix_problem *p = (frix_problem *)0x1;
    const frix_error err = reader(path, &p);
    const char *msg = frix_last_error_message();
    ck_assert_msg(err == code, "%s (%s): expected error %d, got %d (%s)", path, needle, code, err, msg);
    ck_assert_ptr_null(p);
    ck_assert_msg(strstr(msg, path) != NULL, "message does not name the file: %s", msg);
    ck_assert_msg(strstr(msg, needle) != NULL, "message lacks '%s': %s", needle, msg);
    ck_assert_msg(!has_control_byte(msg), "message holds a raw control character: %s", msg);
}

static void expect_read_error(const char *path, frix_error code, const char *needle) {
    expect_refused(frix_fclib_read, path, code, needle);
}

static void expect_read_ok(const char *path) {
    frix_problem *p = NULL;
    ck_assert_msg(frix_fclib_read(path, &p) == FRIX_OK, "%s: %s", path, frix_last_error_message());
    ck_assert_double_eq(frix_problem_q(p)[0], -1.0);
    frix_problem_free(p);
}

/* ---- Links ------------------------------------------------------------------------------- */

START_TEST(external_links_are_refused) {
    const char *path = tmp_path("elink.hdf5"), *other = write_other_file();
    /* q through an external link. */
    write_base(path);
    hid_t f = reopen_without(path, "/fclib_local/vectors/q");
    ck_assert(H5Lcreate_external(other, "/q", f, "/fclib_local/vectors/q", H5P_DEFAULT, H5P_DEFAULT) >= 0);
    H5Fclose(f);
    expect_read_error(path, FRIX_ERR_FORMAT, "/fclib_local/vectors/q is an external link");

    /* A whole group through an external link (the other file then needs the group's path). */
    write_base(path);
    f = reopen_without(path, NULL);
    ck_assert(H5Lmove(f, "/fclib_local/vectors", f, "/kept_vectors", H5P_DEFAULT, H5P_DEFAULT) >= 0);
    ck_assert(H5Lcreate_external(path, "/kept_vectors", f, "/fclib_local/vectors", H5P_DEFAULT, H5P_DEFAULT) >= 0);
    H5Fclose(f);
    expect_read_error(path, FRIX_ERR_FORMAT, "/fclib_local/vectors is an external link");
}
END_TEST

START_TEST(soft_links_stay_inside_the_file) {
    const char *path = tmp_path("softlink.hdf5"), *other = write_other_file();
    /* Inside the file and resolvable, absolute or relative: read as before. */
    write_base(path);
    hid_t f = reopen_without(path, NULL);
    ck_assert(H5Lmove(f, "/fclib_local/vectors/q", f, "/fclib_local/vectors/q_data", H5P_DEFAULT, H5P_DEFAULT) >= 0);
    ck_assert(H5Lcreate_soft("q_data", f, "/fclib_local/vectors/q", H5P_DEFAULT, H5P_DEFAULT) >= 0);
    H5Fclose(f);
    expect_read_ok(path);
    f = reopen_without(path, "/fclib_local/vectors/q");
    ck_assert(H5Lcreate_soft("/fclib_local/vectors/q_data", f, "/fclib_local/vectors/q", H5P_DEFAULT, H5P_DEFAULT) >= 0);
    H5Fclose(f);
    expect_read_ok(path);

    /* Dangling, with a terminal escape in its target. */
    write_base(path);
    f = reopen_without(path, "/fclib_local/vectors/q");
    ck_assert(H5Lcreate_soft("/nowhere\x1b[2J", f, "/fclib_local/vectors/q", H5P_DEFAULT, H5P_DEFAULT) >= 0);
    H5Fclose(f);
    expect_read_error(path, FRIX_ERR_FORMAT, "/fclib_local/vectors/q is a soft link to /nowhere\\x1b[2J");

    /* Through an external link: leaves the file. */
    write_base(path);
    f = reopen_without(path, "/fclib_local/vectors/q");
    ck_assert(H5Lcreate_external(other, "/", f, "/elsewhere", H5P_DEFAULT, H5P_DEFAULT) >= 0);
    ck_assert(H5Lcreate_soft("/elsewhere/q", f, "/fclib_local/vectors/q", H5P_DEFAULT, H5P_DEFAULT) >= 0);
    H5Fclose(f);
    expect_read_error(path, FRIX_ERR_FORMAT, "/elsewhere is an external link");

    /* A loop. */
    write_base(path);
    f = reopen_without(path, "/fclib_local/vectors/q");
    ck_assert(H5Lcreate_soft("/fclib_local/vectors/q", f, "/fclib_local/vectors/q", H5P_DEFAULT, H5P_DEFAULT) >= 0);
    H5Fclose(f);
    expect_read_error(path, FRIX_ERR_FORMAT, "soft link");
}
END_TEST

/* A user-defined link class whose traversal opens the object its data names, relative to the
 * group holding the link: registered in this process, so HDF5 itself would follow it. */
static hid_t traverse_by_name(const char *link_name, hid_t cur_group, const void *data, size_t size,
                              hid_t lapl, hid_t dxpl) {
    (void)link_name;
    (void)size;
    (void)dxpl;
    return H5Oopen(cur_group, (const char *)data, lapl);
}

START_TEST(user_defined_links_are_refused) {
    const H5L_type_t type = (H5L_type_t)(H5L_TYPE_UD_MIN + 35);
    const H5L_class_t by_name = {H5L_LINK_CLASS_T_VERS, type, "by name", NULL, NULL, NULL,
                                 traverse_by_name, NULL, NULL};
    ck_assert(H5Lregister(&by_name) >= 0);
    const char *path = tmp_path("udlink.hdf5");
    write_base(path);
    hid_t f = reopen_without(path, NULL);
    ck_assert(H5Lmove(f, "/fclib_local/vectors/q", f, "/fclib_local/vectors/q_data", H5P_DEFAULT, H5P_DEFAULT) >= 0);
    static const char target[] = "q_data";
    ck_assert(H5Lcreate_ud(f, "/fclib_local/vectors/q", type, target, sizeof target, H5P_DEFAULT, H5P_DEFAULT) >= 0);
    H5Fclose(f);
    expect_read_error(path, FRIX_ERR_FORMAT, "/fclib_local/vectors/q is a user-defined link");
    H5Lunregister(type);
}
END_TEST

/* ---- Data stored outside the file ---------------------------------------------------------- */

START_TEST(external_raw_storage_is_refused) {
    const char *path = tmp_path("efile.hdf5"), *raw = tmp_path("q.raw");
    write_base(path);
    hid_t f = reopen_without(path, "/fclib_local/vectors/q");
    hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
    ck_assert(H5Pset_external(dcpl, raw, 0, 3 * sizeof(double)) >= 0);
    hsize_t n = 3;
    hid_t sp = H5Screate_simple(1, &n, NULL);
    hid_t ds = H5Dcreate2(f, "/fclib_local/vectors/q", H5T_NATIVE_DOUBLE, sp, H5P_DEFAULT, dcpl, H5P_DEFAULT);
    ck_assert(ds >= 0);
    ck_assert(H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, base_q) >= 0);
    H5Dclose(ds);
    H5Sclose(sp);
    H5Pclose(dcpl);
    H5Fclose(f);
    expect_read_error(path, FRIX_ERR_FORMAT, "dataset /fclib_local/vectors/q stores its data in external files");
}
END_TEST

START_TEST(virtual_datasets_are_refused) {
    const char *path = tmp_path("vds.hdf5"), *other = write_other_file();
    write_base(path);
    hid_t f = reopen_without(path, "/fclib_local/vectors/q");
    hsize_t n = 3;
    hid_t sp = H5Screate_simple(1, &n, NULL), src = H5Screate_simple(1, &n, NULL);
    hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
    ck_assert(H5Pset_virtual(dcpl, sp, other, "/q", src) >= 0);
    hid_t ds = H5Dcreate2(f, "/fclib_local/vectors/q", H5T_NATIVE_DOUBLE, sp, H5P_DEFAULT, dcpl, H5P_DEFAULT);
    ck_assert(ds >= 0);
    H5Dclose(ds);
    H5Pclose(dcpl);
    H5Sclose(src);
    H5Sclose(sp);
    H5Fclose(f);
    expect_read_error(path, FRIX_ERR_FORMAT, "dataset /fclib_local/vectors/q is a virtual dataset");
}
END_TEST

/* ---- Sizes --------------------------------------------------------------------------------- */

/* An empty dataset of `n` entries of `type`, never written, chunked by `chunk` when non-zero. */
static void put_unwritten(hid_t loc, const char *name, hid_t type, hsize_t n, hsize_t chunk) {
    hsize_t unlimited = H5S_UNLIMITED;
    hid_t sp = H5Screate_simple(1, &n, chunk != 0 ? &unlimited : NULL);
    hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
    if (chunk != 0) ck_assert(H5Pset_chunk(dcpl, 1, &chunk) >= 0);
    hid_t ds = H5Dcreate2(loc, name, type, sp, H5P_DEFAULT, dcpl, H5P_DEFAULT);
    ck_assert(ds >= 0);
    H5Dclose(ds);
    H5Pclose(dcpl);
    H5Sclose(sp);
}

START_TEST(chunks_are_bounded_by_the_file_size) {
    /* A solution vector may be unwritten (it reads as zeros), but its chunks of 128 MB are
     * more than a file of a few KB can back. */
    const char *path = tmp_path("chunk.hdf5");
    write_base(path);
    hid_t f = reopen_without(path, NULL);
    hid_t g = H5Gcreate2(f, "/solution", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    put_unwritten(g, "r", H5T_IEEE_F64LE, 3, (hsize_t)1 << 24);
    H5Gclose(g);
    H5Fclose(f);
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_fclib_read(path, &p), FRIX_OK);
    double r[3] = {5, 5, 5};
    ck_assert_int_eq(frix_fclib_read_solution(path, p, r, NULL, NULL), FRIX_ERR_FORMAT);
    ck_assert_msg(strstr(frix_last_error_message(), "/solution/r has chunks of 134217728 bytes") != NULL,
                  "%s", frix_last_error_message());
    ck_assert(r[0] == 5);
    frix_problem_free(p);
}
END_TEST

START_TEST(int32_counts_at_its_widened_size) {
    /* 12.5 million int32: 50 MB in the file's type, within 64 x a small file + 64 MiB, but
     * 100 MB once read as int64, which is not. */
    const char *path = tmp_path("widened.hdf5");
    write_base(path);
    hid_t f = reopen_without(path, "/fclib_local/W/nzmax");
    put_unwritten(f, "/fclib_local/W/nzmax", H5T_STD_I32LE, 12500000, 0);
    H5Fclose(f);
    expect_read_error(path, FRIX_ERR_FORMAT, "/fclib_local/W/nzmax declares 12500000 entries (100000000 bytes)");
}
END_TEST

START_TEST(matrix_arrays_are_read_up_to_nnz) {
    const char *path = tmp_path("nnz.hdf5");
    /* x longer than nnz, within nzmax: the entries past nnz (NaN here) are not read. */
    write_base(path);
    hid_t f = reopen_without(path, "/fclib_local/W/x");
    static const double x_long[] = {1, 1, 1, 0.0 / 0.0, 0.0 / 0.0};
    put_doubles(f, "/fclib_local/W/x", x_long, 5);
    ck_assert(H5Ldelete(f, "/fclib_local/W/nzmax", H5P_DEFAULT) >= 0);
    put_int(f, "/fclib_local/W/nzmax", 5);
    H5Fclose(f);
    expect_read_ok(path);
    /* Longer than the capacity nzmax the matrix declares: refused. */
    write_base(path);
    f = reopen_without(path, "/fclib_local/W/i");
    static const int i_long[] = {0, 1, 2, 0};
    put_int32s(f, "/fclib_local/W/i", i_long, 4);
    H5Fclose(f);
    expect_read_error(path, FRIX_ERR_FORMAT, "/fclib_local/W/i has 4 entries, more than nzmax 3");
}
END_TEST

/* ---- Unwritten and missing datasets --------------------------------------------------------- */

START_TEST(unwritten_datasets_are_errors) {
    const char *path = tmp_path("unwritten.hdf5");
    static const char *const doubles[] = {"/fclib_local/vectors/q", "/fclib_local/W/x"};
    for (size_t k = 0; k < 2; ++k) {
        write_base(path);
        hid_t f = reopen_without(path, doubles[k]);
        put_unwritten(f, doubles[k], H5T_IEEE_F64LE, 3, 0);
        H5Fclose(f);
        char needle[128];
        snprintf(needle, sizeof needle, "dataset %s was never written", doubles[k]);
        expect_read_error(path, FRIX_ERR_FORMAT, needle);
    }
    write_base(path);
    hid_t f = reopen_without(path, "/fclib_local/W/m");
    put_unwritten(f, "/fclib_local/W/m", H5T_STD_I32LE, 1, 0);
    H5Fclose(f);
    expect_read_error(path, FRIX_ERR_FORMAT, "dataset /fclib_local/W/m was never written");

    write_base(path);
    f = reopen_without(path, "/fclib_local/info/title");
    put_title(f, "/fclib_local/info/title", NULL);
    H5Fclose(f);
    expect_read_error(path, FRIX_ERR_FORMAT, "dataset /fclib_local/info/title was never written");

    /* Chunked, one chunk of two written. */
    write_base(path);
    f = reopen_without(path, "/fclib_local/vectors/q");
    put_unwritten(f, "/fclib_local/vectors/q", H5T_IEEE_F64LE, 3, 2);
    hid_t ds = H5Dopen2(f, "/fclib_local/vectors/q", H5P_DEFAULT);
    hid_t fs = H5Dget_space(ds);
    const hsize_t start = 0, two = 2;
    hid_t ms = H5Screate_simple(1, &two, NULL);
    ck_assert(H5Sselect_hyperslab(fs, H5S_SELECT_SET, &start, NULL, &two, NULL) >= 0);
    ck_assert(H5Dwrite(ds, H5T_NATIVE_DOUBLE, ms, fs, H5P_DEFAULT, base_q) >= 0);
    H5Sclose(ms);
    H5Sclose(fs);
    H5Dclose(ds);
    H5Fclose(f);
    expect_read_error(path, FRIX_ERR_FORMAT, "dataset /fclib_local/vectors/q was only partly written");

    /* Deflated in chunks (as FCLIB's files and frix's own larger arrays are): whole, it is
     * read, though HDF5 calls a filtered dataset part-allocated; with a chunk missing, refused. */
    for (int whole = 1; whole >= 0; --whole) {
        write_base(path);
        f = reopen_without(path, "/fclib_local/vectors/q");
        const hsize_t n = 3, chunk = 2, count = whole ? 3 : 2;
        hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
        ck_assert(H5Pset_chunk(dcpl, 1, &chunk) >= 0 && H5Pset_deflate(dcpl, 4) >= 0);
        hid_t space = H5Screate_simple(1, &n, NULL);
        ds = H5Dcreate2(f, "/fclib_local/vectors/q", H5T_IEEE_F64LE, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
        ck_assert(ds >= 0);
        fs = H5Dget_space(ds);
        ms = H5Screate_simple(1, &count, NULL);
        ck_assert(H5Sselect_hyperslab(fs, H5S_SELECT_SET, &start, NULL, &count, NULL) >= 0);
        ck_assert(H5Dwrite(ds, H5T_NATIVE_DOUBLE, ms, fs, H5P_DEFAULT, base_q) >= 0);
        H5Sclose(ms);
        H5Sclose(fs);
        H5Sclose(space);
        H5Pclose(dcpl);
        H5Dclose(ds);
        H5Fclose(f);
        if (whole)
            expect_read_ok(path);
        else
            expect_read_error(path, FRIX_ERR_FORMAT, "dataset /fclib_local/vectors/q was only partly written");
    }

    /* Missing stays an error. */
    write_base(path);
    H5Fclose(reopen_without(path, "/fclib_local/vectors/mu"));
    expect_read_error(path, FRIX_ERR_FORMAT, "dataset /fclib_local/vectors/mu is missing");
}
END_TEST

/* ---- Paths that are not regular files ------------------------------------------------------- */

START_TEST(non_regular_files_are_refused_without_blocking) {
    const char *fifo = tmp_path("fifo");
    unlink(fifo);
    ck_assert_int_eq(mkfifo(fifo, 0600), 0);
    /* Nobody writes the FIFO: opening it for reading would wait forever. */
    expect_refused(frix_fclib_read, fifo, FRIX_ERR_IO, "it is a FIFO, not a regular file");
    expect_refused(frix_dat_read, fifo, FRIX_ERR_IO, "it is a FIFO, not a regular file");
    expect_refused(frix_read_problem, fifo, FRIX_ERR_IO, "it is a FIFO, not a regular file");
    int64_t count = 0;
    ck_assert_int_eq(frix_fclib_guess_count(fifo, &count), FRIX_ERR_IO);
    unlink(fifo);

    expect_refused(frix_read_problem, "/dev/null", FRIX_ERR_IO, "a character device, not a regular file");
    expect_refused(frix_dat_read, "/dev/zero", FRIX_ERR_IO, "a character device, not a regular file");
    expect_refused(frix_dat_read, FRIX_TEST_TMPDIR, FRIX_ERR_IO, "a directory, not a regular file");
}
END_TEST

/* ---- .dat files ------------------------------------------------------------------------------- */

static const char *write_dat(const char *name, const char *text, size_t size) {
    const char *path = tmp_path(name);
    spit(path, text, (long)size);
    return path;
}

START_TEST(dat_nul_bytes_are_refused) {
    /* strtoll stops at the NUL: "3<NUL>" would read as 3. */
    static const char text[] = "3 1\n0 3 3\n3 3\0\n1 0 0 0 1 0 0 0 1\n-1 0 0 0.3\n";
    const char *path = write_dat("nul.dat", text, sizeof text - 1);
    expect_refused(frix_dat_read, path, FRIX_ERR_FORMAT, "line 3: a NUL byte at byte offset 13");
}
END_TEST

START_TEST(dat_overlong_tokens_are_refused) {
    char text[1024];
    int at = snprintf(text, sizeof text, "3 1\n0 3 3\n3 3\n");
    for (int k = 0; k < 300; ++k) text[at++] = '0';
    snprintf(text + at, sizeof text - (size_t)at, "1 0 0 0 1 0 0 0 1\n-1 0 0 0.3\n");
    const char *path = write_dat("long.dat", text, strlen(text));
    expect_refused(frix_dat_read, path, FRIX_ERR_FORMAT,
                   "line 4: the token at byte offset 14 is longer than 256 characters");
}
END_TEST

/* A file of 1 GiB whose bytes after the first four are a hole (NULs, no disk): the reader
 * must stop at the first NUL instead of loading the whole file, here within an address
 * space of 256 MB more than the test uses. */
START_TEST(dat_is_streamed_not_loaded) {
#if defined(__SANITIZE_ADDRESS__)
    return; /* AddressSanitizer reserves terabytes of address space: no limit can be set */
#else
    const char *path = write_dat("hole.dat", "3 1\n", 4);
    ck_assert_int_eq(truncate(path, (off_t)1 << 30), 0);
    FILE *statm = fopen("/proc/self/statm", "r");
    if (statm == NULL) return; /* not Linux: no way to size the limit */
    unsigned long pages = 0;
    ck_assert_int_eq(fscanf(statm, "%lu", &pages), 1);
    fclose(statm);
    const rlim_t limit = (rlim_t)pages * (rlim_t)sysconf(_SC_PAGESIZE) + ((rlim_t)256 << 20);
    const struct rlimit rl = {limit, limit};
    ck_assert_int_eq(setrlimit(RLIMIT_AS, &rl), 0);
    expect_refused(frix_dat_read, path, FRIX_ERR_FORMAT, "a NUL byte at byte offset 4");
    unlink(path);
#endif
}
END_TEST

/* ---- Control characters --------------------------------------------------------------------- */

START_TEST(control_characters_are_escaped) {
    const char *path = tmp_path("title.hdf5");
    write_base(path);
    hid_t f = reopen_without(path, "/fclib_local/info/title");
    put_title(f, "/fclib_local/info/title", "\x1b[31mred\x07\n\x7f!");
    H5Fclose(f);
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_fclib_read(path, &p), FRIX_OK);
    ck_assert_str_eq(frix_problem_title(p), "\\x1b[31mred\\x07\\x0a\\x7f!");
    frix_problem_free(p);

    static const char text[] = "3 1\n0 3 3\n3 3\n1 0 0 0 \x1b[2J 0 0 0 1\n-1 0 0 0.3\n";
    const char *dat = write_dat("escape.dat", text, sizeof text - 1);
    expect_refused(frix_dat_read, dat, FRIX_ERR_FORMAT, "found '\\x1b[2J'");
    static const char integer[] = "3 1\n\x1b" "0 3 3\n";
    dat = write_dat("escape_int.dat", integer, sizeof integer - 1);
    expect_refused(frix_dat_read, dat, FRIX_ERR_FORMAT, "found '\\x1b0'");
}
END_TEST

/* The description and math info keep line breaks and tabs; other control characters are
 * escaped as in titles. */
START_TEST(descriptions_keep_line_breaks_only) {
    const char *path = tmp_path("description.hdf5");
    write_base(path);
    hid_t f = reopen_without(path, NULL);
    hid_t info = H5Gopen2(f, "/fclib_local/info", H5P_DEFAULT);
    put_title(info, "description", "line\n\ttabbed\r\x1b[2J");
    put_title(info, "math_info", "a\nb\x07");
    H5Gclose(info);
    H5Fclose(f);
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_fclib_read(path, &p), FRIX_OK);
    ck_assert_str_eq(frix_problem_description(p), "line\n\ttabbed\\x0d\\x1b[2J");
    ck_assert_str_eq(frix_problem_math_info(p), "a\nb\\x07");
    frix_problem_free(p);
}
END_TEST

/* A fixed-length string dataset of `size` bytes holding `text`. */
static void put_fixed_text(hid_t loc, const char *name, const char *text, size_t size) {
    hid_t t = H5Tcopy(H5T_C_S1);
    ck_assert(H5Tset_size(t, size) >= 0);
    hid_t sp = H5Screate(H5S_SCALAR);
    hid_t ds = H5Dcreate2(loc, name, t, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    ck_assert(ds >= 0);
    char *buffer = calloc(size, 1);
    ck_assert_ptr_nonnull(buffer);
    memcpy(buffer, text, strlen(text) < size ? strlen(text) : size);
    ck_assert(H5Dwrite(ds, t, H5S_ALL, H5S_ALL, H5P_DEFAULT, buffer) >= 0);
    free(buffer);
    H5Dclose(ds);
    H5Sclose(sp);
    H5Tclose(t);
}

/* The info texts are bounded (65536 bytes): longer ones are refused, variable-length or
 * fixed-length (those by their type, before they are read), and so is one that escaping takes
 * over the bound. */
START_TEST(info_texts_are_bounded) {
    const char *path = tmp_path("long_text.hdf5");
    char *text = malloc(70001);
    ck_assert_ptr_nonnull(text);
    memset(text, 'd', 70000);
    text[70000] = '\0';

    write_base(path);
    hid_t f = reopen_without(path, NULL);
    put_title(f, "/fclib_local/info/description", text);
    H5Fclose(f);
    expect_read_error(path, FRIX_ERR_FORMAT,
                      "dataset /fclib_local/info/description holds a string of 70000 bytes, more than the 65536");

    write_base(path);
    f = reopen_without(path, "/fclib_local/info/title");
    put_fixed_text(f, "/fclib_local/info/title", "short", 70000);
    H5Fclose(f);
    expect_read_error(path, FRIX_ERR_FORMAT, "dataset /fclib_local/info/title holds a string of 70000 bytes");

    /* 65536 bytes read; with one control character in them, escaping makes 65539. */
    text[65536] = '\0';
    write_base(path);
    f = reopen_without(path, NULL);
    put_title(f, "/fclib_local/info/math_info", text);
    H5Fclose(f);
    frix_problem *p = NULL;
    ck_assert_int_eq(frix_fclib_read(path, &p), FRIX_OK);
    ck_assert_uint_eq(strlen(frix_problem_math_info(p)), 65536);
    frix_problem_free(p);
    text[0] = '\x1b';
    write_base(path);
    f = reopen_without(path, NULL);
    put_title(f, "/fclib_local/info/math_info", text);
    H5Fclose(f);
    expect_read_error(path, FRIX_ERR_FORMAT, "takes 65539 bytes with its control characters escaped");
    free(text);
}
END_TEST

int main(void) {
    Suite *s = suite_create("hostile_files");
    TCase *links = tcase_create("links and storage");
    tcase_add_test(links, external_links_are_refused);
    tcase_add_test(links, soft_links_stay_inside_the_file);
    tcase_add_test(links, user_defined_links_are_refused);
    tcase_add_test(links, external_raw_storage_is_refused);
    tcase_add_test(links, virtual_datasets_are_refused);
    suite_add_tcase(s, links);
    TCase *sizes = tcase_create("sizes and unwritten data");
    tcase_add_test(sizes, chunks_are_bounded_by_the_file_size);
    tcase_add_test(sizes, int32_counts_at_its_widened_size);
    tcase_add_test(sizes, matrix_arrays_are_read_up_to_nnz);
    tcase_add_test(sizes, unwritten_datasets_are_errors);
    suite_add_tcase(s, sizes);
    TCase *files = tcase_create("files and text");
    /* A reader that blocks on the FIFO fails here, not at the suite's timeout. */
    tcase_set_timeout(files, 30);
    tcase_add_test(files, non_regular_files_are_refused_without_blocking);
    tcase_add_test(files, dat_nul_bytes_are_refused);
    tcase_add_test(files, dat_overlong_tokens_are_refused);
    tcase_add_test(files, dat_is_streamed_not_loaded);
    tcase_add_test(files, control_characters_are_escaped);
    tcase_add_test(files, descriptions_keep_line_breaks_only);
    tcase_add_test(files, info_texts_are_bounded);
    suite_add_tcase(s, files);
    return frix_run_suite(s);
}
