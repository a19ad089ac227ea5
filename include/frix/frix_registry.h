/* frix — the solver registry: ids, names, descriptions. */
#ifndef FRIX_REGISTRY_H
#define FRIX_REGISTRY_H

#include <stdint.h>
#include "frix_export.h"
#include "frix_errors.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- Registry. Ids are stable and never renumbered; where an algorithm is the one of a
 * Siconos 4.4 FC3D solver it has that solver's number. Only solvers that really solve are
 * listed. */
enum {
    FRIX_SOLVER_NSGS = 500,
    FRIX_SOLVER_NSGS_VELOCITY = 501, /* NSGS keeping u = W r + q up to date */
    FRIX_SOLVER_PROX = 502,        /* proximal point, a Newton solver inside */
    FRIX_SOLVER_TFP = 503,         /* Tresca fixed point, NSGS inside */
    FRIX_SOLVER_NSN_AC = 504,      /* semismooth Newton, Alart-Curnier */
    FRIX_SOLVER_VI_FPP = 506,      /* VI fixed-point projection, self-adaptive step */
    FRIX_SOLVER_VI_EG = 507,       /* VI extragradient, self-adaptive step */
    FRIX_SOLVER_HP = 508,          /* hyperplane projection */
    FRIX_SOLVER_NSN_FB = 513,      /* semismooth Newton, Fischer-Burmeister */
    FRIX_SOLVER_ACLM = 516,        /* Acary-Cadoux-Lemarechal-Malick fixed point on s = |u_T| */
    FRIX_SOLVER_NSN_NM = 520,      /* semismooth Newton, natural map */
    FRIX_SOLVER_ADMM = 523,        /* ADMM on r = xi, W + rho I factorised */
    FRIX_SOLVER_IPM = 524,         /* interior-point method, then Newton from its best point */
    FRIX_SOLVER_GLOBAL_NSN_AC = 607, /* global (M, H) problems: Newton on (v, r), W never formed */
    FRIX_SOLVER_GLOBAL_ADMM = 613,   /* global problems: ADMM, M + rho H H^T factorised, no W */
    FRIX_SOLVER_AUTO = 900,        /* the default: analyses the problem, splits it into
                                      independent islands and runs a watched sequence of the
                                      solvers above on each (see docs/auto.md) */
    FRIX_SOLVER_GLOBAL_AL_NEWTON = 901, /* global problems: augmented Lagrangian, Newton on v,
                                           M + rho H J H^T factorised, no W */
    FRIX_SOLVER_GLOBAL_NSGS = 902, /* global problems with block-diagonal M (rigid bodies):
                                      NSGS on H and M^-1 H, no W */
    FRIX_SOLVER_IPM_ANM = 903,     /* interior-point path followed by Taylor series, then
                                      Newton from its best point */
    FRIX_SOLVER_ROLLING_NSGS = 3000, /* rolling-friction problems (local, and global of rigid
                                        bodies without W): nonsmooth Gauss-Seidel */
    FRIX_SOLVER_ROLLING_NSN = 3010   /* rolling-friction problems: semismooth Newton (natural
                                        map), for tight tolerances */
};

FRIX_API int64_t frix_solver_count(void);
/* Id of the index-th registered solver (0 <= index < count), -1 if out of range. */
FRIX_API int frix_solver_id_at(int64_t index);
/* Short lower-case name ("nsgs"), NULL if the id is unknown. */
FRIX_API const char *frix_solver_name(int solver_id);
/* One paragraph: the algorithm and its options. NULL if unknown. */
FRIX_API const char *frix_solver_describe(int solver_id);
/* Accepts the frix name ("nsgs"), the Siconos spelling ("FRICTION_3D_NSGS" or "FC3D_NSGS",
 * any case) or the id as a decimal string. */
FRIX_API frix_error frix_solver_by_name(const char *name, int *solver_id);

#ifdef __cplusplus
}
#endif

#endif /* FRIX_REGISTRY_H */
