// Solutions (/solution) and initial guesses (/guesses/1, /guesses/2, ...) of FCLIB files.
#include <frix/frix.h>

#include <algorithm>
#include <string>
#include <vector>

#include "error_state.hpp"
#include "fclib_error.hpp"
#include "hdf5_reader.hpp"
#include "problem.hpp"

namespace frix::fclib {

namespace {

// Reads every requested vector before copying any, so that on failure the caller's arrays
// are left as they were.
void read_solution_group(const FileReader &file, const std::string &group,
                         const frix_problem &problem, double *r, double *u, double *v) {
    if (!file.is_group(group))
        raise(FRIX_ERR_FORMAT, "'%s' has no %s group", file.path(), group.c_str());
    const int64_t m = contact_size(problem) * problem.nc;
    const bool global = !is_local_form(problem);
    std::vector<double> rr, uu, vv;
    const Unwritten unwritten = Unwritten::read_fill;
    const std::string counted = std::to_string(contact_size(problem)) + " x contacts of the problem";
    if (r != nullptr) rr = file.read_vector(group + "/r", m, counted.c_str(), unwritten);
    if (u != nullptr) uu = file.read_vector(group + "/u", m, counted.c_str(), unwritten);
    if (global && v != nullptr)
        vv = file.read_vector(group + "/v", problem.n, "dofs of the problem", unwritten);
    std::copy(rr.begin(), rr.end(), r);
    std::copy(uu.begin(), uu.end(), u);
    std::copy(vv.begin(), vv.end(), v);
}

int64_t count_guesses(const FileReader &file) {
    if (!file.exists("/guesses")) return 0;
    if (!file.is_group("/guesses"))
        raise(FRIX_ERR_FORMAT, "'%s': /guesses is not a group", file.path());
    const int64_t count = file.read_int_scalar("/guesses/number_of_guesses");
    // The group holds number_of_guesses itself plus one sub-group per guess.
    const int64_t groups = file.link_count("/guesses") - 1;
    if (count < 0 || count > groups)
        raise(FRIX_ERR_FORMAT,
              "'%s': dataset /guesses/number_of_guesses is %lld but /guesses holds %lld guesses",
              file.path(), static_cast<long long>(count), static_cast<long long>(groups));
    return count;
}

frix_error check_arguments(const char *where, const char *path, const frix_problem *problem) {
    if (path == nullptr) return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: path is NULL", where);
    if (problem == nullptr) return fail(FRIX_ERR_INVALID_ARGUMENT, "%s: problem is NULL", where);
    return FRIX_OK;
}

}  // namespace

}  // namespace frix::fclib

extern "C" FRIX_API frix_error frix_fclib_read_solution(const char *path,
                                                        const frix_problem *problem, double *r,
                                                        double *u, double *v) {
    using namespace frix::fclib;
    const char *where = "frix_fclib_read_solution";
    return frix::guard(where, [&]() -> frix_error {
        if (frix_error err = check_arguments(where, path, problem)) return err;
        Session session;
        const FileReader file(path);
        read_solution_group(file, "/solution", *problem, r, u, v);
        return FRIX_OK;
    });
}

extern "C" FRIX_API frix_error frix_fclib_guess_count(const char *path, int64_t *count) {
    using namespace frix::fclib;
    return frix::guard("frix_fclib_guess_count", [&]() -> frix_error {
        if (path == nullptr)
            return frix::fail(FRIX_ERR_INVALID_ARGUMENT, "frix_fclib_guess_count: path is NULL");
        if (count == nullptr)
            return frix::fail(FRIX_ERR_INVALID_ARGUMENT, "frix_fclib_guess_count: count is NULL");
        Session session;
        const FileReader file(path);
        *count = count_guesses(file);
        return FRIX_OK;
    });
}

extern "C" FRIX_API frix_error frix_fclib_read_guess(const char *path,
                                                     const frix_problem *problem, int64_t index,
                                                     double *r, double *u, double *v) {
    using namespace frix::fclib;
    const char *where = "frix_fclib_read_guess";
    return frix::guard(where, [&]() -> frix_error {
        if (frix_error err = check_arguments(where, path, problem)) return err;
        Session session;
        const FileReader file(path);
        const int64_t count = count_guesses(file);
        if (index < 0 || index >= count)
            return frix::fail(FRIX_ERR_INVALID_ARGUMENT,
                              "%s: guess %lld requested but '%s' holds %lld guesses (numbered "
                              "from 0)",
                              where, static_cast<long long>(index), path,
                              static_cast<long long>(count));
        read_solution_group(file, "/guesses/" + std::to_string(index + 1), *problem, r, u, v);
        return FRIX_OK;
    });
}
