/* Builds a local problem u = W r + q from compressed sparse columns and solves it. */
#include <frix/frix.h>
#include <stdio.h>

int main(void) {
    /* Two contacts (normal component first), coupled through their normals. W is given by
     * columns: colptr[j]..colptr[j+1]-1 index the row numbers and values of column j. */
    const int64_t colptr[7] = {0, 2, 3, 4, 6, 7, 8};
    const int64_t rowind[8] = {0, 3, 1, 2, 0, 3, 4, 5};
    const double values[8] = {2.0, 0.5, 1.0, 1.0, 0.5, 2.0, 1.0, 1.0};
    const double q[6] = {-1.0, 0.4, 0.0, -0.5, 0.0, -0.2}, mu[2] = {0.3, 0.5};
    double r[6] = {0}, u[6]; /* r is also the initial guess */
    frix_matrix *W = NULL;
    frix_problem *problem = NULL; /* borrows W, q and mu: keep them alive */
    frix_options *options = NULL;
    frix_info *info = NULL;
    frix_error err = frix_matrix_from_csc(6, 6, colptr, rowind, values, &W);
    if (!err) err = frix_problem_local(W, q, mu, 2, &problem);
    if (!err) err = frix_options_create(FRIX_SOLVER_NSGS, &options);
    if (!err) err = frix_options_set_double(options, FRIX_OPT_TOLERANCE, 1e-12);
    if (!err) err = frix_info_create(&info);
    if (!err) err = frix_solve(problem, options, r, u, NULL, info);
    if (err) {
        fprintf(stderr, "frix: %s\n", frix_last_error_message());
    } else {
        printf("%s in %lld iterations, error %.1e\n", frix_status_string(frix_info_status(info)),
               (long long)frix_info_iterations(info), frix_info_error(info));
        for (int a = 0; a < 2; ++a)
            printf("contact %d: r = (%.5f, %.5f, %.5f)  u = (%.5f, %.5f, %.5f)\n", a, r[3 * a],
                   r[3 * a + 1], r[3 * a + 2], u[3 * a], u[3 * a + 1], u[3 * a + 2]);
    }
    int converged = !err && frix_info_status(info) == FRIX_STATUS_CONVERGED;
    frix_info_free(info);
    frix_options_free(options);
    frix_problem_free(problem);
    frix_matrix_free(W);
    return converged ? 0 : 1;
}
