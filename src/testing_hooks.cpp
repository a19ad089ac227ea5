// The frix_testing_* hooks of tests/frix_testing.h: thin wrappers over internal kernels,
// hidden so that libfrix.so never exports them.
#include "local3x3.hpp"

#define FRIX_TESTING_HOOK extern "C" __attribute__((visibility("hidden")))

namespace {
using frix::local::Outcome;
static_assert((int)Outcome::TakeOff == 1 && (int)Outcome::Stick == 2 && (int)Outcome::Slide == 3 &&
                  (int)Outcome::Iterated == 4 && (int)Outcome::NotConverged == 5 &&
                  (int)Outcome::NoSolution == 6 && (int)Outcome::Step == 7,
              "tests/frix_testing.h mirrors these values");
}  // namespace

FRIX_TESTING_HOOK void frix_testing_project_on_cone(double r[3], double mu) {
    frix::local::project_on_cone(r, mu);
}

FRIX_TESTING_HOOK void frix_testing_project_on_disk(double r[3], double radius) {
    frix::local::project_on_disk(r, radius);
}

FRIX_TESTING_HOOK int frix_testing_solve_contact(const double W[9], const double q[3], double mu,
                                                 double r[3], int local_solver, double tol,
                                                 int max_iter) {
    frix::local::Contact c;
    frix::local::contact_setup(W, mu, c);
    frix::local::Params p;
    p.solver = local_solver;
    p.tol = tol;
    p.max_iter = max_iter;
    return (int)frix::local::solve_contact(c, q, r, p);
}

FRIX_TESTING_HOOK int frix_testing_solve_slide(const double W[9], const double q[3], double mu,
                                               const double hint[3], double r[3]) {
    frix::local::Contact c;
    frix::local::contact_setup(W, mu, c);
    return frix::local::solve_slide(c, q, hint, r) ? 1 : 0;
}

FRIX_TESTING_HOOK double frix_testing_contact_residual(const double W[9], const double q[3],
                                                       double mu, const double r[3],
                                                       double *relative) {
    return frix::local::contact_residual(W, q, mu, r, relative);
}
