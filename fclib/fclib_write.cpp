// frix_fclib_write: a problem, and optionally a solution and guesses, as a new FCLIB file
// in the layout libfclib writes (matrices as CSC, nz = -1).
#include <frix/frix.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "error_state.hpp"
#include "fclib_error.hpp"
#include "fclib_matrix.hpp"
#include "hdf5_writer.hpp"
#include "problem.hpp"
#include "temp_file.hpp"

namespace frix::fclib {

namespace {

constexpr int64_t kInt32Max = std::numeric_limits<int32_t>::max();

struct Vectors {
    const double *r;
    const double *u;
    const double *v;  // NULL for local problems
};

// NaN or Inf in a solution or guess is refused: frix's own reader would refuse the file.
void check_vectors(const char *what, const Vectors &s, int64_t m, int64_t n) {
    auto check = [&](const char *name, const double *x, int64_t count) {
        for (int64_t k = 0; k < count; ++k)
            if (!std::isfinite(x[k]))
                raise(FRIX_ERR_NOT_FINITE, "frix_fclib_write: %s %s: entry %lld is %g", what, name,
                      static_cast<long long>(k), x[k]);
    };
    check("r", s.r, m);
    check("u", s.u, m);
    if (s.v != nullptr) check("v", s.v, n);
}

// A problem without contacts may have no W or H at all; FCLIB still wants the matrix, with
// no columns (W 0 x 0, H n x 0: the reader checks H's rows against M).
Csc32 export_matrix(const frix_matrix *A, const char *name, int64_t rows_if_absent) {
    if (A != nullptr) return to_csc32(*A, name);
    Csc32 empty;
    empty.m = static_cast<int32_t>(rows_if_absent);
    empty.p.assign(1, 0);
    return empty;
}

void write_vectors(FileWriter &file, const std::string &group, const Vectors &s, int64_t m,
                   int64_t n) {
    file.create_group(group);
    file.write_doubles(group + "/r", s.r, m);
    file.write_doubles(group + "/u", s.u, m);
    if (s.v != nullptr) file.write_doubles(group + "/v", s.v, n);
}

void write_info(FileWriter &file, const std::string &root, const frix_problem &problem) {
    file.create_group(root + "/info");
    file.write_text(root + "/info/title", problem.title);
    file.write_text(root + "/info/description",
                    !problem.description.empty()
                        ? problem.description
                        : std::string("written by frix ") + frix_version_string());
    file.write_text(root + "/info/math_info", problem.math_info);
}

// What goes into the file besides the problem.
struct Extras {
    bool with_solution = false;
    Vectors solution{nullptr, nullptr, nullptr};
    int64_t n_guesses = 0;
    Vectors guesses{nullptr, nullptr, nullptr};  // the first guess; the others follow
};

Vectors guess(const Extras &e, int64_t k, int64_t m, int64_t n) {
    return Vectors{e.guesses.r + k * m, e.guesses.u + k * m,
                   e.guesses.v != nullptr ? e.guesses.v + k * n : nullptr};
}

// The argument checks of frix_fclib_write: everything that can refuse the call is checked
// here, before any file exists.
Extras check_arguments(const char *where, const frix_problem &problem, const double *sol_r,
                       const double *sol_u, const double *sol_v, int64_t n_guesses,
                       const double *guess_r, const double *guess_u, const double *guess_v) {
    if (frix_error err = check_problem_vectors(problem)) throw Failure{err};
    const bool global = !is_local_form(problem);
    const int64_t m = contact_size(problem) * problem.nc, n = global ? problem.n : 0;
    Extras e;
    e.with_solution = sol_r != nullptr || sol_u != nullptr || (global && sol_v != nullptr);
    // An array of no entries may be NULL (r and u without contacts, v without dofs), as
    // frix_solve takes them; libfclib's readers take v from every solution and guess of a
    // global problem, so a global file without v would not load there.
    auto given = [](const double *x, int64_t count) { return x != nullptr || count == 0; };
    if (e.with_solution && !(given(sol_r, m) && given(sol_u, m) && (!global || given(sol_v, n))))
        raise(FRIX_ERR_INVALID_ARGUMENT, "%s: a solution needs r and u%s (or all NULL for none)",
              where, global ? " and v" : "");
    if (n_guesses < 0 || n_guesses > kInt32Max)
        raise(FRIX_ERR_INVALID_ARGUMENT, "%s: n_guesses is %lld", where,
              static_cast<long long>(n_guesses));
    if (n_guesses > 0 && !(given(guess_r, m) && given(guess_u, m) && (!global || given(guess_v, n))))
        raise(FRIX_ERR_INVALID_ARGUMENT, "%s: %lld guesses need guess_r and guess_u%s", where,
              static_cast<long long>(n_guesses), global ? " and guess_v" : "");
    // From here on NULL in v means "local problem": an empty array gets a non-NULL pointer.
    static const double kNoEntries[1] = {0.0};
    auto array = [](const double *x) { return x != nullptr ? x : kNoEntries; };
    e.solution = Vectors{array(sol_r), array(sol_u), global ? array(sol_v) : nullptr};
    e.n_guesses = n_guesses;
    e.guesses = Vectors{array(guess_r), array(guess_u), global ? array(guess_v) : nullptr};
    if (e.with_solution) check_vectors("solution", e.solution, m, n);
    for (int64_t k = 0; k < n_guesses; ++k)
        check_vectors(("guess " + std::to_string(k)).c_str(), guess(e, k, m, n), m, n);
    return e;
}

// The whole file, built in memory.
std::vector<unsigned char> build_file(const char *path, const frix_problem &problem,
                                      const Extras &e, int deflate_level) {
    const bool global = !is_local_form(problem), rolling = is_rolling(problem);
    const int64_t m = contact_size(problem) * problem.nc, n = global ? problem.n : 0;
    // The 32-bit conversion can still refuse the problem, so it also comes first.
    Csc32 W, M, H;
    if (global) {
        M = export_matrix(problem.M, "M", 0);
        H = export_matrix(problem.H, "H", M.m);
    } else {
        W = export_matrix(problem.W, "W", 0);
    }

    Session session;
    FileWriter file(path, deflate_level);
    // A rolling problem: FCLIB's /fclib_global_rolling, or frix's /fclib_local_rolling (the
    // local group with mu_r), spacedim 5; with spinning friction spacedim 6 and mu_s, frix's
    // extension (docs/rolling.md).
    const std::string root = std::string(global ? "/fclib_global" : "/fclib_local") + (rolling ? "_rolling" : "");
    file.create_group(root);
    file.write_int32_scalar(root + "/spacedim", contact_size(problem));
    file.create_group(root + "/vectors");
    if (global) {
        write_matrix(file, root + "/M", M);
        write_matrix(file, root + "/H", H);
        file.write_doubles(root + "/vectors/f", problem.f, n);
        file.write_doubles(root + "/vectors/w", problem.w, m);
    } else {
        write_matrix(file, root + "/W", W);
        file.write_doubles(root + "/vectors/q", problem.q, m);
    }
    file.write_doubles(root + "/vectors/mu", problem.mu, problem.nc);
    if (rolling) file.write_doubles(root + "/vectors/mu_r", problem.mu_r, problem.nc);
    if (problem.spinning) file.write_doubles(root + "/vectors/mu_s", problem.mu_s, problem.nc);
    write_info(file, root, problem);

    if (e.with_solution) write_vectors(file, "/solution", e.solution, m, n);
    if (e.n_guesses > 0) {
        file.create_group("/guesses");
        file.write_int32_scalar("/guesses/number_of_guesses", static_cast<int32_t>(e.n_guesses));
        for (int64_t k = 0; k < e.n_guesses; ++k)
            write_vectors(file, "/guesses/" + std::to_string(k + 1), guess(e, k, m, n), m, n);
    }
    return file.image();
}

}  // namespace

}  // namespace frix::fclib

namespace {

frix_error write_file(const char *where, const char *path, const frix_problem *problem,
                      const double *sol_r, const double *sol_u, const double *sol_v,
                      int64_t n_guesses, const double *guess_r, const double *guess_u,
                      const double *guess_v, int level) {
    using namespace frix::fclib;
    return frix::guard(where, [&]() -> frix_error {
        if (path == nullptr || path[0] == '\0')
            return frix::fail(FRIX_ERR_INVALID_ARGUMENT, "%s: path is NULL or empty", where);
        if (problem == nullptr)
            return frix::fail(FRIX_ERR_INVALID_ARGUMENT, "%s: problem is NULL", where);
        if (level < 0 || level > 9)
            return frix::fail(FRIX_ERR_INVALID_ARGUMENT,
                              "%s: the compression level is %d, expected 0 (none) to 9", where,
                              level);
        const Extras extras = check_arguments(where, *problem, sol_r, sol_u, sol_v, n_guesses,
                                              guess_r, guess_u, guess_v);
        const std::vector<unsigned char> image = build_file(path, *problem, extras, level);
        // Only now does the disk come in: the old file is replaced by a complete new one.
        TempFile temp(path);
        temp.write(image.data(), image.size());
        temp.commit();
        return FRIX_OK;
    });
}

}  // namespace

extern "C" FRIX_API frix_error frix_fclib_write(const char *path, const frix_problem *problem,
                                                const double *sol_r, const double *sol_u,
                                                const double *sol_v, int64_t n_guesses,
                                                const double *guess_r, const double *guess_u,
                                                const double *guess_v) {
    return write_file("frix_fclib_write", path, problem, sol_r, sol_u, sol_v, n_guesses, guess_r,
                      guess_u, guess_v, frix::fclib::FileWriter::kDefaultDeflateLevel);
}

extern "C" FRIX_API frix_error frix_fclib_write_compressed(
    const char *path, const frix_problem *problem, const double *sol_r, const double *sol_u,
    const double *sol_v, int64_t n_guesses, const double *guess_r, const double *guess_u,
    const double *guess_v, int level) {
    return write_file("frix_fclib_write_compressed", path, problem, sol_r, sol_u, sol_v,
                      n_guesses, guess_r, guess_u, guess_v, level);
}
