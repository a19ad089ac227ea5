// Internal layout of frix_info.
#pragma once

#include <frix/frix_solve.h>

#include <cmath>
#include <cstdint>

struct frix_info {
    frix_status status = FRIX_STATUS_NOT_RUN;
    int64_t iterations = 0;
    int solver_id = 0;
    int64_t contacts = 0;

    double error = NAN;
    double error_relative = NAN;
    double error_q_relative = NAN;
    double residual_absolute = NAN;
    double cone_violation = NAN;
    double penetration = NAN;
    double complementarity = NAN;
    double equilibrium = NAN;
    double solve_time = 0.0;
    double tolerance = NAN;

    int64_t newton_iterations = 0;
    int64_t line_search_steps = 0;
    int64_t factorizations = 0;
    int64_t symbolic_analyses = 0;
    int64_t hybrid_sweeps = 0;
    int64_t inner_iterations = 0;
    double factorization_time = 0.0;
    double setup_time = 0.0;
};
