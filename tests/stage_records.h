/* Reading a solve's stage records (frix_info.h) in the tests: they read records, never the
 * trace's prose. */
#ifndef FRIX_TEST_STAGE_RECORDS_H
#define FRIX_TEST_STAGE_RECORDS_H

#include <check.h>
#include <frix/frix.h>
#include <math.h>

/* A field of record k of info. */
static inline int64_t stage_int(const frix_info *info, int64_t k, frix_stage_key key) {
    int64_t value = -1;
    ck_assert_int_eq(frix_info_stage_get_int(info, k, key, &value), FRIX_OK);
    return value;
}

static inline double stage_double(const frix_info *info, int64_t k, frix_stage_key key) {
    double value = NAN;
    ck_assert_int_eq(frix_info_stage_get_double(info, k, key, &value), FRIX_OK);
    return value;
}

/* The first record of a run of `solver` at or after record `from`, or -1. */
static inline int64_t find_stage(const frix_info *info, int solver, int64_t from) {
    for (int64_t k = from; k < frix_info_stage_count(info); ++k)
        if (stage_int(info, k, FRIX_STAGE_SOLVER_ID) == solver) return k;
    return -1;
}

/* The first run (solver id > 0) at or after record `from` of a solver other than `solver`,
 * or -1. */
static inline int64_t find_other_run(const frix_info *info, int solver, int64_t from) {
    for (int64_t k = from; k < frix_info_stage_count(info); ++k) {
        const int64_t id = stage_int(info, k, FRIX_STAGE_SOLVER_ID);
        if (id > 0 && id != solver) return k;
    }
    return -1;
}

#endif
