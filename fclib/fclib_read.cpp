// frix_fclib_read: an FCLIB file's local (/fclib_local) or global (/fclib_global) problem.
#include <frix/frix.h>

#include <memory>
#include <string>
#include <vector>

#include "error_state.hpp"
#include "fclib_error.hpp"
#include "fclib_matrix.hpp"
#include "hdf5_reader.hpp"
#include "problem.hpp"

namespace frix::fclib {

namespace {

using ProblemPtr = std::unique_ptr<frix_problem, void (*)(frix_problem *)>;

void check_spacedim(const FileReader &file, const std::string &root) {
    const int64_t d = file.read_int_scalar(root + "/spacedim");
    if (d != 3)
        raise(FRIX_ERR_UNSUPPORTED, "'%s': %s/spacedim is %lld; frix solves 3D contact (spacedim 3)",
              file.path(), root.c_str(), static_cast<long long>(d));
}

void check_mu(const FileReader &file, const std::string &name, const std::vector<double> &mu) {
    for (size_t k = 0; k < mu.size(); ++k)
        if (mu[k] < 0)
            raise(FRIX_ERR_FORMAT, "'%s': dataset %s: entry %zu is %g, friction must be >= 0",
                  file.path(), name.c_str(), k, mu[k]);
}

// W.m / 3 with the message FCLIB files need when it is not whole.
int64_t contacts_of(const FileReader &file, const std::string &matrix, int64_t contact_dofs,
                    const char *what) {
    if (contact_dofs % 3 != 0)
        raise(FRIX_ERR_FORMAT, "'%s': %s has %lld %s, not a multiple of spacedim 3", file.path(),
              matrix.c_str(), static_cast<long long>(contact_dofs), what);
    return contact_dofs / 3;
}

ProblemPtr read_local(const FileReader &file) {
    const std::string root = "/fclib_local";
    check_spacedim(file, root);
    if (file.exists(root + "/V") || file.exists(root + "/R"))
        raise(FRIX_ERR_UNSUPPORTED,
              "'%s': the local problem has V and R (equality constraints), which frix does not "
              "solve",
              file.path());
    const MatrixHeader W = read_matrix_header(file, root + "/W");
    if (W.m != W.n)
        raise(FRIX_ERR_FORMAT, "'%s': %s is %lld x %lld, expected square", file.path(),
              W.group.c_str(), static_cast<long long>(W.m), static_cast<long long>(W.n));
    const int64_t nc = contacts_of(file, W.group, W.m, "rows");
    std::vector<double> q = file.read_vector(root + "/vectors/q", W.m, "rows of /fclib_local/W");
    std::vector<double> mu =
        file.read_vector(root + "/vectors/mu", nc, "contacts: rows of /fclib_local/W / 3");
    check_mu(file, root + "/vectors/mu", mu);
    std::unique_ptr<frix_matrix> matrix = read_matrix(file, W);

    frix_problem *raw = nullptr;
    const frix_error err =
        make_owned_local_problem(std::move(matrix), std::move(q), std::move(mu), &raw);
    ProblemPtr problem(raw, frix_problem_free);
    if (err != FRIX_OK) raise_from_core(err, std::string("'") + file.path() + "'");
    return problem;
}

ProblemPtr read_global(const FileReader &file) {
    const std::string root = "/fclib_global";
    check_spacedim(file, root);
    if (file.exists(root + "/G"))
        raise(FRIX_ERR_UNSUPPORTED,
              "'%s': the global problem has G (equality constraints), which frix does not solve",
              file.path());
    const MatrixHeader M = read_matrix_header(file, root + "/M");
    const MatrixHeader H = read_matrix_header(file, root + "/H");
    if (M.m != M.n)
        raise(FRIX_ERR_FORMAT, "'%s': %s is %lld x %lld, expected square", file.path(),
              M.group.c_str(), static_cast<long long>(M.m), static_cast<long long>(M.n));
    if (H.m != M.m)
        raise(FRIX_ERR_FORMAT, "'%s': %s has %lld rows, expected %lld (the size of %s)",
              file.path(), H.group.c_str(), static_cast<long long>(H.m),
              static_cast<long long>(M.m), M.group.c_str());
    const int64_t nc = contacts_of(file, H.group, H.n, "columns");
    std::vector<double> f = file.read_vector(root + "/vectors/f", M.m, "size of /fclib_global/M");
    std::vector<double> w =
        file.read_vector(root + "/vectors/w", H.n, "columns of /fclib_global/H");
    std::vector<double> mu =
        file.read_vector(root + "/vectors/mu", nc, "contacts: columns of /fclib_global/H / 3");
    check_mu(file, root + "/vectors/mu", mu);
    std::unique_ptr<frix_matrix> Mm = read_matrix(file, M);
    std::unique_ptr<frix_matrix> Hm = read_matrix(file, H);

    frix_problem *raw = nullptr;
    const frix_error err = make_owned_global_problem(std::move(Mm), std::move(Hm), std::move(f),
                                                     std::move(w), std::move(mu), &raw);
    ProblemPtr problem(raw, frix_problem_free);
    if (err != FRIX_OK) raise_from_core(err, std::string("'") + file.path() + "'");
    return problem;
}

// The info group's texts, each optional (FCLIB makes the group and its members optional).
// Control characters are escaped as in messages; the description and math info keep their
// line breaks and tabs, which multi-line text needs. Escaping lengthens a text, so the limit
// holds for what the problem gets, not only for what the file stores.
void read_info(const FileReader &file, const std::string &root, frix_problem &problem) {
    struct Field {
        const char *name;
        std::string frix_problem::*text;
        bool multi_line;
    };
    static const Field fields[] = {{"title", &frix_problem::title, false},
                                   {"description", &frix_problem::description, true},
                                   {"math_info", &frix_problem::math_info, true}};
    for (const Field &field : fields) {
        const std::string name = root + "/info/" + field.name;
        if (!file.exists(name)) continue;
        std::string text = printable(file.read_text(name, kMaxProblemText), field.multi_line);
        if (text.size() > kMaxProblemText)
            raise(FRIX_ERR_FORMAT,
                  "'%s': dataset %s takes %zu bytes with its control characters escaped, more "
                  "than the %zu frix reads",
                  file.path(), name.c_str(), text.size(), kMaxProblemText);
        problem.*field.text = std::move(text);
    }
}

}  // namespace

}  // namespace frix::fclib

extern "C" FRIX_API frix_error frix_fclib_read(const char *path, frix_problem **out) {
    using namespace frix::fclib;
    return frix::guard("frix_fclib_read", [&]() -> frix_error {
        if (out == nullptr) return frix::fail(FRIX_ERR_INVALID_ARGUMENT, "frix_fclib_read: out is NULL");
        *out = nullptr;
        if (path == nullptr) return frix::fail(FRIX_ERR_INVALID_ARGUMENT, "frix_fclib_read: path is NULL");
        Session session;
        const FileReader file(path);
        const bool local = file.exists("/fclib_local"), global = file.exists("/fclib_global");
        if (local && global)
            raise(FRIX_ERR_FORMAT, "'%s' holds both /fclib_local and /fclib_global", path);
        if (!local && !global) {
            if (file.exists("/fclib_global_rolling"))
                raise(FRIX_ERR_UNSUPPORTED,
                      "'%s' holds a rolling-friction problem (/fclib_global_rolling), which "
                      "frix does not solve",
                      path);
            raise(FRIX_ERR_FORMAT,
                  "'%s' is not an FCLIB problem file: it has no /fclib_local or /fclib_global "
                  "group",
                  path);
        }
        const std::string root = local ? "/fclib_local" : "/fclib_global";
        if (!file.is_group(root))
            raise(FRIX_ERR_FORMAT, "'%s': %s is not a group", path, root.c_str());
        ProblemPtr problem = local ? read_local(file) : read_global(file);
        read_info(file, root, *problem);
        *out = problem.release();
        return FRIX_OK;
    });
}
