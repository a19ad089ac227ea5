/* Siconos 4.4 migration: wherever frix registers a solver under a Siconos 4.4 FC3D id, the
 * Siconos spellings of that solver are accepted too (enum name with and without the
 * SICONOS_ prefix, and the FC3D_ string of solver_options_id_to_name, any case), and the
 * one-contact solver ids 552/553/562 are accepted as NSGS local solvers. */
#include <frix/frix.h>

#include <ctype.h>
#include <stdio.h>
#include <string.h>

#include "check_main.h"

typedef struct siconos_solver {
    int id;
    const char *suffix; /* after SICONOS_FRICTION_3D_ (or SICONOS_GLOBAL_FRICTION_3D_) */
} siconos_solver;

/* Friction_cst.h of Siconos 4.4 (GAMS-only solvers left out). */
static const siconos_solver kLocal[] = {
    {500, "NSGS"}, {501, "NSGSV"}, {502, "PROX"}, {503, "TFP"}, {504, "NSN_AC"}, {505, "DSFP"},
    {506, "VI_FPP"}, {507, "VI_EG"}, {508, "HP"}, {510, "NCPGlockerFBFixedPoint"}, {511, "FPP"},
    {512, "EG"}, {513, "NSN_FB"}, {516, "ACLMFP"}, {517, "SOCLCP"}, {520, "NSN_NM"},
    {521, "NSN_AC_TEST"}, {522, "PFP"}, {523, "ADMM"}};
static const siconos_solver kGlobal[] = {
    {600, "NSGS_WR"}, {601, "NSGSV_WR"}, {602, "PROX_WR"}, {603, "DSFP_WR"}, {604, "TFP_WR"},
    {605, "NSGS"}, {606, "NSN_AC_WR"}, {607, "NSN_AC"}, {610, "VI_FPP"}, {611, "VI_EG"},
    {612, "ACLMFP"}, {613, "ADMM"}, {614, "ADMM_WR"}, {615, "IPM"}};

static void expect_name(const char *name, int id) {
    int got = -1;
    frix_error err = frix_solver_by_name(name, &got);
    ck_assert_msg(err == FRIX_OK && got == id, "'%s' should name solver %d (got %d, %s)", name, id,
                  got, frix_last_error_message());
}

START_TEST(siconos_spellings_of_registered_solvers) {
    char name[128], lower[128];
    int checked = 0;
    for (size_t k = 0; k < sizeof kLocal / sizeof kLocal[0]; ++k) {
        const siconos_solver *s = &kLocal[k];
        if (frix_solver_name(s->id) == NULL) continue; /* frix has no such algorithm */
        snprintf(name, sizeof name, "SICONOS_FRICTION_3D_%s", s->suffix);
        expect_name(name, s->id);
        expect_name(name + strlen("SICONOS_"), s->id);
        snprintf(name, sizeof name, "FC3D_%s", s->suffix);
        expect_name(name, s->id);
        for (size_t i = 0; i <= strlen(name); ++i) lower[i] = (char)tolower((unsigned char)name[i]);
        expect_name(lower, s->id);
        snprintf(name, sizeof name, "%d", s->id);
        expect_name(name, s->id);
        ++checked;
    }
    for (size_t k = 0; k < sizeof kGlobal / sizeof kGlobal[0]; ++k) {
        const siconos_solver *s = &kGlobal[k];
        if (frix_solver_name(s->id) == NULL) continue;
        snprintf(name, sizeof name, "SICONOS_GLOBAL_FRICTION_3D_%s", s->suffix);
        expect_name(name, s->id);
        expect_name(name + strlen("SICONOS_"), s->id);
        ++checked;
    }
    ck_assert_int_ge(checked, 1); /* NSGS at least */
}
END_TEST

START_TEST(siconos_local_solver_ids) {
    frix_options *o = NULL;
    ck_assert_int_eq(frix_options_create(FRIX_SOLVER_NSGS, &o), FRIX_OK);
    const int ids[] = {552, 553, 562};
    for (size_t k = 0; k < 3; ++k)
        ck_assert_msg(frix_options_set_int(o, FRIX_OPT_LOCAL_SOLVER, ids[k]) == FRIX_OK, "%d: %s",
                      ids[k], frix_last_error_message());
    frix_options_free(o);
}
END_TEST

int main(void) {
    Suite *s = suite_create("siconos_names");
    TCase *tc = tcase_create("siconos_names");
    tcase_add_test(tc, siconos_spellings_of_registered_solvers);
    tcase_add_test(tc, siconos_local_solver_ids);
    suite_add_tcase(s, tc);
    return frix_run_suite(s);
}
