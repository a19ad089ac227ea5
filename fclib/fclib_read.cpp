// frix_fclib_read: an FCLIB file's local (/fclib_local) or global (/fclib_global) problem, or
// a rolling-friction one (/fclib_global_rolling, FCLIB's and Siconos's; /fclib_local_rolling,
// frix's, the local group with mu_r; docs/rolling.md), with spinning friction when its spacedim
// is 6 (frix's extension: mu_s in vectors).
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

// Which group the file holds: the entries a contact (spacedim; 5 for a rolling group, which
// may say 6) and whether mu_r comes along.
struct Group {
    std::string root;
    int dim;
    bool rolling;
};

// The entries a contact: the group's, or for a rolling group 5 or 6 (spinning friction, with
// vectors/mu_s). A rolling group of spacedim 5 with mu_s says two things and is refused.
int read_spacedim(const FileReader &file, const Group &g) {
    const int64_t d = file.read_int_scalar(g.root + "/spacedim");
    const bool spinning = g.rolling && d == 6;
    if (d != g.dim && !spinning)
        raise(FRIX_ERR_UNSUPPORTED, "'%s': %s/spacedim is %lld; frix solves 3D %scontact (spacedim %s)",
              file.path(), g.root.c_str(), static_cast<long long>(d), g.rolling ? "rolling-friction " : "",
              g.rolling ? "5, or 6 with spinning friction" : "3");
    if (g.rolling && !spinning && file.exists(g.root + "/vectors/mu_s"))
        raise(FRIX_ERR_FORMAT,
              "'%s': %s/spacedim is 5 (no spinning friction) but the group has vectors/mu_s, which "
              "needs spacedim 6",
              file.path(), g.root.c_str());
    return static_cast<int>(d);
}

void check_mu(const FileReader &file, const std::string &name, const std::vector<double> &mu) {
    for (size_t k = 0; k < mu.size(); ++k)
        if (mu[k] < 0)
            raise(FRIX_ERR_FORMAT, "'%s': dataset %s: entry %zu is %g, friction must be >= 0",
                  file.path(), name.c_str(), k, mu[k]);
}

// W.m / spacedim with the message FCLIB files need when it is not whole.
int64_t contacts_of(const FileReader &file, const std::string &matrix, int64_t contact_dofs,
                    const char *what, int dim) {
    if (contact_dofs % dim != 0)
        raise(FRIX_ERR_FORMAT, "'%s': %s has %lld %s, not a multiple of spacedim %d", file.path(),
              matrix.c_str(), static_cast<long long>(contact_dofs), what, dim);
    return contact_dofs / dim;
}

// The friction coefficients: mu, and the law's others (mu_r for a rolling group, mu_s with
// spinning friction), nc values each, >= 0.
struct Coefficients {
    std::vector<double> mu;
    OwnedContactLaw law;
};

Coefficients read_coefficients(const FileReader &file, const Group &g, int dim, int64_t nc,
                               const std::string &counted) {
    Coefficients c;
    c.law.dim = g.rolling ? dim : 3;
    const char *names[3] = {"mu", "mu_r", "mu_s"};
    std::vector<double> *values[3] = {&c.mu, &c.law.mu_r, &c.law.mu_s};
    const int count = c.law.dim == 6 ? 3 : c.law.dim == 5 ? 2 : 1;
    for (int k = 0; k < count; ++k) {
        const std::string name = g.root + "/vectors/" + names[k];
        *values[k] = file.read_vector(name, nc, counted.c_str());
        check_mu(file, name, *values[k]);
    }
    return c;
}

ProblemPtr read_local(const FileReader &file, const Group &g) {
    const std::string &root = g.root;
    const int dim = read_spacedim(file, g);
    if (file.exists(root + "/V") || file.exists(root + "/R"))
        raise(FRIX_ERR_UNSUPPORTED,
              "'%s': the local problem has V and R (equality constraints), which frix does not "
              "solve",
              file.path());
    const MatrixHeader W = read_matrix_header(file, root + "/W");
    if (W.m != W.n)
        raise(FRIX_ERR_FORMAT, "'%s': %s is %lld x %lld, expected square", file.path(),
              W.group.c_str(), static_cast<long long>(W.m), static_cast<long long>(W.n));
    const int64_t nc = contacts_of(file, W.group, W.m, "rows", dim);
    std::vector<double> q = file.read_vector(root + "/vectors/q", W.m, ("rows of " + W.group).c_str());
    Coefficients c = read_coefficients(file, g, dim, nc, "contacts: rows of " + W.group + " / " + std::to_string(dim));
    std::unique_ptr<frix_matrix> matrix = read_matrix(file, W);

    frix_problem *raw = nullptr;
    const frix_error err =
        make_owned_local_problem_of(std::move(c.law), std::move(matrix), std::move(q), std::move(c.mu), &raw);
    ProblemPtr problem(raw, frix_problem_free);
    if (err != FRIX_OK) raise_from_core(err, std::string("'") + file.path() + "'");
    return problem;
}

ProblemPtr read_global(const FileReader &file, const Group &g) {
    const std::string &root = g.root;
    const int dim = read_spacedim(file, g);
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
    const int64_t nc = contacts_of(file, H.group, H.n, "columns", dim);
    std::vector<double> f = file.read_vector(root + "/vectors/f", M.m, ("size of " + M.group).c_str());
    std::vector<double> w = file.read_vector(root + "/vectors/w", H.n, ("columns of " + H.group).c_str());
    Coefficients c =
        read_coefficients(file, g, dim, nc, "contacts: columns of " + H.group + " / " + std::to_string(dim));
    std::unique_ptr<frix_matrix> Mm = read_matrix(file, M);
    std::unique_ptr<frix_matrix> Hm = read_matrix(file, H);

    frix_problem *raw = nullptr;
    const frix_error err = make_owned_global_problem_of(std::move(c.law), std::move(Mm), std::move(Hm), std::move(f),
                                                        std::move(w), std::move(c.mu), &raw);
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
        static const Group kGroups[] = {{"/fclib_local", 3, false},
                                        {"/fclib_global", 3, false},
                                        {"/fclib_local_rolling", 5, true},
                                        {"/fclib_global_rolling", 5, true}};
        const Group *found = nullptr;
        for (const Group &g : kGroups) {
            if (!file.exists(g.root)) continue;
            if (found)
                raise(FRIX_ERR_FORMAT, "'%s' holds both %s and %s", path, found->root.c_str(), g.root.c_str());
            found = &g;
        }
        if (!found)
            raise(FRIX_ERR_FORMAT,
                  "'%s' is not an FCLIB problem file: it has no /fclib_local, /fclib_global, "
                  "/fclib_local_rolling or /fclib_global_rolling group",
                  path);
        const std::string &root = found->root;
        if (!file.is_group(root))
            raise(FRIX_ERR_FORMAT, "'%s': %s is not a group", path, root.c_str());
        const bool local = root == "/fclib_local" || root == "/fclib_local_rolling";
        ProblemPtr problem = local ? read_local(file, *found) : read_global(file, *found);
        read_info(file, root, *problem);
        *out = problem.release();
        return FRIX_OK;
    });
}
