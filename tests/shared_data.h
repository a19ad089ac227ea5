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

/* The 28 local problems of ../shared/fclib (local/ and converted/, as its MANIFEST advises). */
static const char *const kFclibLocalProblems[] = {
    "local/Capsules-i125-1213.hdf5",
    "local/LMGC_100_PR_PerioBox-i00361-60-03000.hdf5",
    "local/local_problem_test.hdf5",
    "converted/Box_Stacks-i0035-31-0.reduced.hdf5",
    "converted/Capsules-i100-1090.from_dat.hdf5",
    "converted/Capsules-i101-404.from_dat.hdf5",
    "converted/Confeti-ex03-Fc3D-SBM.from_dat.hdf5",
    "converted/Confeti-ex13-4contact-Fc3D-SBM.from_dat.hdf5",
    "converted/CubeH8.reduced.hdf5",
    "converted/FC3D_Example1.from_dat.hdf5",
    "converted/FrictionContact3D_1c.from_dat.hdf5",
    "converted/GFC3D_Example0.from_dat.hdf5",
    "converted/GFC3D_Example00_badly_scaled.from_dat.hdf5",
    "converted/GFC3D_Example1_v2.from_dat.hdf5",
    "converted/GFC3D_TwoRods1.from_dat.hdf5",
    "converted/LMGC_GFC3D-i00501-4-00000.reduced.hdf5",
    "converted/NESpheres_10_1.from_dat.hdf5",
    "converted/OneObject-i100000-316.from_dat.hdf5",
    "converted/OneObject-i1028-138.from_dat.hdf5",
    "converted/RockPile_tob1.from_dat.hdf5",
    "converted/Rover1039.from_dat.hdf5",
    "converted/Rover1040.from_dat.hdf5",
    "converted/Rover11035.from_dat.hdf5",
    "converted/Rover3865.from_dat.hdf5",
    "converted/Rover4396.from_dat.hdf5",
    "converted/Rover4516.from_dat.hdf5",
    "converted/Rover4613.from_dat.hdf5",
    "converted/spheres-in-a-box-98-i10000-256-10.reduced.hdf5",
};
#define FRIX_FCLIB_LOCAL_COUNT ((int)(sizeof kFclibLocalProblems / sizeof kFclibLocalProblems[0]))

#endif
