/* Internal hooks that let the C tests reach kernels behind the public API. They are
 * defined in src/testing_hooks.cpp with hidden visibility: present in libfrix.a (which the
 * tests link), never exported from libfrix.so. Not an API: they change with the internals. */
#ifndef FRIX_TESTING_H
#define FRIX_TESTING_H

#ifdef __cplusplus
extern "C" {
#endif

/* ---- One-contact kernels (solvers/local3x3.hpp). Vectors normal first, W column-major. */

/* Outcomes of frix_testing_solve_contact (the values of frix::local::Outcome). */
enum {
    FRIX_TESTING_TAKE_OFF = 1,
    FRIX_TESTING_STICK = 2,
    FRIX_TESTING_SLIDE = 3,
    FRIX_TESTING_ITERATED = 4,
    FRIX_TESTING_NOT_CONVERGED = 5,
    FRIX_TESTING_NO_SOLUTION = 6,
    FRIX_TESTING_STEP = 7
};

void frix_testing_project_on_cone(double r[3], double mu);
void frix_testing_project_on_disk(double r[3], double radius);

/* One contact: r is the warm start in, the result out. local_solver 552 or 553;
 * exact_slide = 0 makes 553 use projected iterations only (no sliding-angle root). */
int frix_testing_solve_contact(const double W[9], const double q[3], double mu, double r[3],
                               int local_solver, double tol, int max_iter);

/* The sliding root alone: 1 and r set if a valid sliding solution was found. */
int frix_testing_solve_slide(const double W[9], const double q[3], double mu,
                             const double hint[3], double r[3]);

/* |r - P_K(r - u^)| with u = W r + q; *relative (may be NULL) gets it / max(|q|,|r|,|u|). */
double frix_testing_contact_residual(const double W[9], const double q[3], double mu,
                                     const double r[3], double *relative);

#ifdef __cplusplus
}
#endif

#endif /* FRIX_TESTING_H */
