/* Shared by the test programs that read problems of ../shared/fclib. */
#ifndef FRIX_SHARED_DATA_H
#define FRIX_SHARED_DATA_H

#include <check.h>
#include <frix/frix.h>
#include <stdio.h>
#include <unistd.h>

#ifndef FRIX_SHARED_DIR
#define FRIX_SHARED_DIR ""
#endif

/* The problem at FRIX_SHARED_DIR/fclib/<relative>, or NULL with a note when the shared data
 * directory is absent (e.g. a bare checkout): such tests then pass instead of failing. */
static inline frix_problem *load(const char *relative) {
    char path[4096];
    snprintf(path, sizeof path, "%s/fclib/%s", FRIX_SHARED_DIR, relative);
    if (access(path, R_OK) != 0) {
        fprintf(stderr, "note: %s not found, test skipped\n", path);
        return NULL;
    }
    frix_problem *p = NULL;
    ck_assert_msg(frix_fclib_read(path, &p) == FRIX_OK, "%s: %s", path, frix_last_error_message());
    return p;
}

#endif
