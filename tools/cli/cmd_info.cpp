// `frix info FILE.hdf5 [--json]`: what a problem file holds, without solving it.
#include "args.hpp"
#include "cli.hpp"
#include "json.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace frix_cli {
namespace {

struct MatrixFacts {
    bool present = false;
    int64_t rows = 0, cols = 0, nnz = 0, blocks = 0;
};

struct Facts {
    std::string path, title, description, math_info;
    frix_problem_kind kind = FRIX_PROBLEM_LOCAL;
    int64_t contacts = 0, contact_dofs = 0, dofs = 0;
    MatrixFacts W, M, H;
    double mu_min = NAN, mu_max = NAN, mu_r_min = NAN, mu_r_max = NAN, mu_s_min = NAN, mu_s_max = NAN;
    bool local = true, rolling = false, spinning = false;
    double norm_q = NAN, norm_f = NAN, norm_w = NAN;
    bool has_solution = false;
    double solution_error = NAN;        // the stored solution's relative error, if any
    double solution_equilibrium = NAN;  // and, for a global problem, its equilibrium residual
    int64_t guesses = 0;
};

MatrixFacts matrix_facts(const frix_matrix *m) {
    MatrixFacts f;
    if (!m) return f;
    f.present = true;
    f.rows = frix_matrix_rows(m);
    f.cols = frix_matrix_cols(m);
    f.nnz = frix_matrix_nnz(m);
    f.blocks = frix_matrix_block_count(m);
    return f;
}

double norm2(const double *x, int64_t n) {
    if (!x) return NAN;
    double s = 0;
    for (int64_t i = 0; i < n; ++i) s += x[i] * x[i];
    return std::sqrt(s);
}

// The smallest and largest of n coefficients (left NaN when there are none).
void range_of(const double *x, int64_t n, double &lo, double &hi) {
    if (!x || n <= 0) return;
    auto range = std::minmax_element(x, x + n);
    lo = *range.first;
    hi = *range.second;
}

// The contact law, named for people (text) and for programs (JSON).
const char *law_text(const Facts &f) {
    return f.spinning ? "Coulomb, rolling and spinning friction" : f.rolling ? "Coulomb and rolling friction" : "Coulomb";
}
const char *law_token(const Facts &f) { return f.spinning ? "spinning" : f.rolling ? "rolling" : "coulomb"; }

std::string one_line(std::string s) {
    std::replace(s.begin(), s.end(), '\n', ' ');
    std::replace(s.begin(), s.end(), '\r', ' ');
    return s;
}

Facts gather(const std::string &path) {
    ProblemPtr p = read_problem(path);
    Facts f;
    f.path = path;
    f.title = frix_problem_title(p.get());
    f.description = frix_problem_description(p.get());
    f.math_info = frix_problem_math_info(p.get());
    f.kind = frix_problem_get_kind(p.get());
    f.contacts = frix_problem_contacts(p.get());
    f.contact_dofs = frix_problem_contact_dofs(p.get());
    f.dofs = frix_problem_dofs(p.get());
    f.W = matrix_facts(frix_problem_W(p.get()));
    f.M = matrix_facts(frix_problem_M(p.get()));
    f.H = matrix_facts(frix_problem_H(p.get()));
    range_of(frix_problem_mu(p.get()), f.contacts, f.mu_min, f.mu_max);
    range_of(frix_problem_mu_r(p.get()), f.contacts, f.mu_r_min, f.mu_r_max);
    range_of(frix_problem_mu_s(p.get()), f.contacts, f.mu_s_min, f.mu_s_max);
    f.local = f.kind == FRIX_PROBLEM_LOCAL || f.kind == FRIX_PROBLEM_ROLLING_LOCAL;
    f.rolling = f.kind == FRIX_PROBLEM_ROLLING_LOCAL || f.kind == FRIX_PROBLEM_ROLLING_GLOBAL;
    f.spinning = frix_problem_mu_s(p.get()) != nullptr;
    if (f.local) {
        f.norm_q = norm2(frix_problem_q(p.get()), f.contact_dofs);
    } else {
        f.norm_f = norm2(frix_problem_f(p.get()), f.dofs);
        f.norm_w = norm2(frix_problem_w(p.get()), f.contact_dofs);
    }

    // A missing /solution or unreadable guesses are facts to report, not failures.
    std::vector<double> r(static_cast<std::size_t>(std::max<int64_t>(f.contact_dofs, 1)));
    std::vector<double> v(static_cast<std::size_t>(std::max<int64_t>(f.dofs, 1)));
    double *vp = f.local ? nullptr : v.data();
    if (frix_fclib_read_solution(path.c_str(), p.get(), r.data(), nullptr, vp) == FRIX_OK) {
        f.has_solution = true;
        frix_info *info = nullptr;
        if (frix_info_create(&info) == FRIX_OK &&
            frix_problem_measure(p.get(), r.data(), vp, nullptr, info) == FRIX_OK) {
            frix_info_get_double(info, FRIX_INFO_ERROR_RELATIVE, &f.solution_error);
            frix_info_get_double(info, FRIX_INFO_EQUILIBRIUM, &f.solution_equilibrium);
        }
        frix_info_free(info);
    }
    if (frix_fclib_guess_count(path.c_str(), &f.guesses) != FRIX_OK) f.guesses = 0;
    return f;
}

void json_matrix(JsonWriter &w, const char *key, const MatrixFacts &m) {
    if (!m.present) return;
    w.begin_object(key);
    w.integer("rows", m.rows);
    w.integer("cols", m.cols);
    w.integer("nnz", m.nnz);
    w.integer("blocks", m.blocks);
    w.end_object();
}

void print_json(const Facts &f) {
    JsonWriter w;
    w.begin_object();
    w.string("file", f.path);
    w.string("title", f.title);
    w.string("description", f.description);
    w.string("math_info", f.math_info);
    w.string("kind", kind_name(f.kind));
    w.string("law", law_token(f));
    w.integer("contacts", f.contacts);
    w.integer("contact_dofs", f.contact_dofs);
    w.integer("dofs", f.dofs);
    json_matrix(w, "W", f.W);
    json_matrix(w, "M", f.M);
    json_matrix(w, "H", f.H);
    w.number("mu_min", f.mu_min);
    w.number("mu_max", f.mu_max);
    if (f.rolling) {
        w.number("mu_r_min", f.mu_r_min);
        w.number("mu_r_max", f.mu_r_max);
    }
    if (f.spinning) {
        w.number("mu_s_min", f.mu_s_min);
        w.number("mu_s_max", f.mu_s_max);
    }
    if (f.local) {
        w.number("norm_q", f.norm_q);
    } else {
        w.number("norm_f", f.norm_f);
        w.number("norm_w", f.norm_w);
    }
    w.boolean("has_solution", f.has_solution);
    w.number("solution_error", f.solution_error);
    if (!f.local) w.number("solution_equilibrium", f.solution_equilibrium);
    w.integer("guesses", f.guesses);
    w.end_object();
    std::printf("%s\n", w.text().c_str());
}

void print_matrix_line(const char *name, const MatrixFacts &m) {
    if (!m.present) return;
    std::printf("%-16s %lld x %lld, %lld stored entries", name, static_cast<long long>(m.rows),
                static_cast<long long>(m.cols), static_cast<long long>(m.nnz));
    if (m.blocks > 0) std::printf(" (%lld 3x3 blocks)", static_cast<long long>(m.blocks));
    std::printf("\n");
}

void print_text(const Facts &f) {
    std::printf("%-16s %s\n", "file", f.path.c_str());
    std::printf("%-16s %s\n", "title", f.title.empty() ? "-" : one_line(f.title).c_str());
    if (!f.description.empty()) std::printf("%-16s %s\n", "description", one_line(f.description).c_str());
    if (!f.math_info.empty()) std::printf("%-16s %s\n", "math info", one_line(f.math_info).c_str());
    std::printf("%-16s %s\n", "kind", kind_name(f.kind));
    std::printf("%-16s %s\n", "law", law_text(f));
    std::printf("%-16s %lld\n", "contacts", static_cast<long long>(f.contacts));
    if (f.local)
        std::printf("%-16s %lld (r, u)\n", "dofs", static_cast<long long>(f.contact_dofs));
    else
        std::printf("%-16s %lld (v), %lld (r, u)\n", "dofs", static_cast<long long>(f.dofs),
                    static_cast<long long>(f.contact_dofs));
    print_matrix_line("W", f.W);
    print_matrix_line("M", f.M);
    print_matrix_line("H", f.H);
    if (f.contacts > 0)
        std::printf("%-16s %g .. %g\n", "mu", f.mu_min, f.mu_max);
    else
        std::printf("%-16s -\n", "mu");
    if (f.rolling && f.contacts > 0) std::printf("%-16s %g .. %g\n", "mu_r", f.mu_r_min, f.mu_r_max);
    if (f.spinning && f.contacts > 0) std::printf("%-16s %g .. %g\n", "mu_s", f.mu_s_min, f.mu_s_max);
    if (f.local) {
        std::printf("%-16s %.4g\n", "|q|", f.norm_q);
    } else {
        std::printf("%-16s %.4g\n", "|f|", f.norm_f);
        std::printf("%-16s %.4g\n", "|w|", f.norm_w);
    }
    if (f.has_solution && !f.local)
        std::printf("%-16s yes (error %.3e, equilibrium %.3e)\n", "solution", f.solution_error,
                    f.solution_equilibrium);
    else if (f.has_solution)
        std::printf("%-16s yes (error %.3e)\n", "solution", f.solution_error);
    else
        std::printf("%-16s no\n", "solution");
    std::printf("%-16s %lld\n", "guesses", static_cast<long long>(f.guesses));
}

}  // namespace

int cmd_info(int argc, char **argv) {
    const HelpJsonArgs args = parse_help_json_args("info", argc, argv);
    if (args.help) {
        print_info_help(stdout);
        return kExitConverged;
    }
    if (args.positional.size() != 1) usage_error("info", "expected one FILE.hdf5");
    Facts f = gather(args.positional[0]);
    if (args.json)
        print_json(f);
    else
        print_text(f);
    return kExitConverged;
}

}  // namespace frix_cli
