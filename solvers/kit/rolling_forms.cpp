#include "solvers/kit/rolling_forms.hpp"

#include <algorithm>
#include <cmath>

#include "solvers/kit/pairs_by_key.hpp"
#include "src/error_state.hpp"
#include "src/matrix.hpp"
#include "src/reduction.hpp"

namespace frix::rolling {

void BlockRows::multiply(const double *x, double *y) const {
    const int64_t nc = (int64_t)row_ptr.size() - 1;
    for (int64_t a = 0; a < nc; ++a) {
        double s[5] = {0, 0, 0, 0, 0};
        for (int64_t k = row_ptr[(size_t)a]; k < row_ptr[(size_t)a + 1]; ++k) {
            const double *B = &val[25 * (size_t)k], *xb = x + 5 * block_col[(size_t)k];
            for (int j = 0; j < 5; ++j)
                for (int i = 0; i < 5; ++i) s[i] += B[i + 5 * j] * xb[j];
        }
        std::copy(s, s + 5, y + 5 * a);
    }
}

RowForm::RowForm(const frix_problem &p) : p_(p) {
    const int64_t nc = p.nc;
    // The blocks of each row: every (row, column) contact pair an entry falls in, once.
    unique_pairs_by_key(
        nc, [&](auto &&emit) { for_each_entry(*p.W, [&](int64_t i, int64_t j, double) { emit(i / 5, j / 5); }); },
        w_.row_ptr, w_.block_col);
    w_.val.assign(25 * w_.block_col.size(), 0.0);
    // Each entry into its block; consecutive entries mostly share one, found once.
    int64_t last_a = -1, last_b = -1, k = 0;
    for_each_entry(*p.W, [&](int64_t i, int64_t j, double v) {
        const int64_t a = i / 5, b = j / 5;
        if (a != last_a || b != last_b) {
            const auto first = w_.block_col.begin() + w_.row_ptr[(size_t)a];
            const auto last = w_.block_col.begin() + w_.row_ptr[(size_t)a + 1];
            k = std::lower_bound(first, last, b) - w_.block_col.begin();
            last_a = a, last_b = b;
        }
        w_.val[25 * (size_t)k + (size_t)(i % 5) + 5 * (size_t)(j % 5)] += v;
    });
    w_.diag.assign((size_t)nc, -1);
    for (int64_t a = 0; a < nc; ++a)
        for (int64_t kk = w_.row_ptr[(size_t)a]; kk < w_.row_ptr[(size_t)a + 1]; ++kk)
            if (w_.block_col[(size_t)kk] == a) w_.diag[(size_t)a] = kk;
}

const double *RowForm::diagonal_block(int64_t a) const {
    return w_.diag[(size_t)a] >= 0 ? &w_.val[25 * (size_t)w_.diag[(size_t)a]] : zero_;
}

void RowForm::local_q(int64_t a, const double *r, double *ql) const {
    for (int i = 0; i < 5; ++i) ql[i] = p_.q[5 * a + i];
    for (int64_t k = w_.row_ptr[(size_t)a]; k < w_.row_ptr[(size_t)a + 1]; ++k) {
        const int64_t b = w_.block_col[(size_t)k];
        if (b == a) continue;  // stepped over, not subtracted: no cancellation
        const double *B = &w_.val[25 * (size_t)k], *rb = r + 5 * b;
        for (int j = 0; j < 5; ++j)
            for (int i = 0; i < 5; ++i) ql[i] += B[i + 5 * j] * rb[j];
    }
}

frix_error BodyForm::setup(const double *r, const char *who) {
    {
        Csc M;
        if (frix_error e = to_csc(*p_.M, M)) return e;
        if (frix_error e = bodies_.setup(M, who)) return e;
    }
    const int64_t nc = p_.nc;
    {
        ContactBodies cb;
        cb.find(*p_.H, bodies_, 5, nc);
        cp_.build(*p_.H, bodies_, cb, 5, nc, nullptr, false);
    }
    blocks_.assign(25 * (size_t)nc, 0.0);
    for (int64_t a = 0; a < nc; ++a) cp_.add_diagonal_block(a, &blocks_[25 * (size_t)a]);
    v0_.assign((size_t)p_.n, 0.0);
    bodies_.apply_inverse(p_.f, v0_.data());
    v_ = v0_;
    for (int64_t a = 0; a < nc; ++a) add_g(a, r + 5 * a, v_.data());
    return FRIX_OK;
}

void BodyForm::reduce(BlockRows &W, double *q) const {
    const int64_t nc = p_.nc, nb = bodies_.count();
    // Each body's contacts, with where the body's dofs start among the contact's (a contact
    // holds its bodies whole, in increasing order, each from its place 0).
    std::vector<int64_t> ptr((size_t)nb + 1, 0);
    for (int64_t t = 0; t < cp_.dof_ptr[(size_t)nc]; ++t)
        if (bodies_.place[cp_.dofs[(size_t)t]] == 0) ++ptr[(size_t)bodies_.body_of[cp_.dofs[(size_t)t]] + 1];
    for (int64_t b = 0; b < nb; ++b) ptr[(size_t)b + 1] += ptr[(size_t)b];
    std::vector<int64_t> contact((size_t)ptr[(size_t)nb]), start((size_t)ptr[(size_t)nb]);
    std::vector<int64_t> fill(ptr.begin(), ptr.end() - 1);
    for (int64_t a = 0; a < nc; ++a)
        for (int64_t t = cp_.dof_ptr[(size_t)a]; t < cp_.dof_ptr[(size_t)a + 1]; ++t)
            if (bodies_.place[cp_.dofs[(size_t)t]] == 0) {
                const int64_t at = fill[(size_t)bodies_.body_of[cp_.dofs[(size_t)t]]]++;
                contact[(size_t)at] = a, start[(size_t)at] = t;
            }
    W.row_ptr.assign((size_t)nc + 1, 0);
    W.block_col.clear();
    W.diag.assign((size_t)nc, -1);
    std::vector<int64_t> cols;
    for (int pass = 0; pass < 2; ++pass)
        for (int64_t a = 0; a < nc; ++a) {
            cols.clear();
            for (int64_t t = cp_.dof_ptr[(size_t)a]; t < cp_.dof_ptr[(size_t)a + 1]; ++t) {
                if (bodies_.place[cp_.dofs[(size_t)t]] != 0) continue;
                const int64_t b = bodies_.body_of[cp_.dofs[(size_t)t]];
                if (pass == 0) {
                    for (int64_t e = ptr[(size_t)b]; e < ptr[(size_t)b + 1]; ++e) cols.push_back(contact[(size_t)e]);
                    continue;
                }
                // W_ac += sum over the body's dofs of (H_a)_x (M^-1 H_c)_x^T.
                for (int64_t e = ptr[(size_t)b]; e < ptr[(size_t)b + 1]; ++e) {
                    const auto first = W.block_col.begin() + W.row_ptr[(size_t)a];
                    const auto last = W.block_col.begin() + W.row_ptr[(size_t)a + 1];
                    double *blk = &W.val[25 * (size_t)(std::lower_bound(first, last, contact[(size_t)e]) -
                                                       W.block_col.begin())];
                    for (int64_t j = 0; j < bodies_.size(b); ++j) {
                        const double *h = &cp_.hd[5 * (size_t)(t + j)], *g = &cp_.gd[5 * (size_t)(start[(size_t)e] + j)];
                        for (int f = 0; f < 5; ++f)
                            for (int i = 0; i < 5; ++i) blk[i + 5 * f] += h[i] * g[f];
                    }
                }
            }
            if (pass == 1) continue;
            std::sort(cols.begin(), cols.end());
            cols.erase(std::unique(cols.begin(), cols.end()), cols.end());
            for (const int64_t c : cols) {
                if (c == a) W.diag[(size_t)a] = (int64_t)W.block_col.size();
                W.block_col.push_back(c);
            }
            W.row_ptr[(size_t)a + 1] = (int64_t)W.block_col.size();
            if (a == nc - 1) W.val.assign(25 * W.block_col.size(), 0.0);
        }
    for (int64_t a = 0; a < nc; ++a) contact_velocity(a, v0_.data(), q + 5 * a);
}

void BodyForm::add_g(int64_t a, const double *x, double *v) const {
    for (int64_t t = cp_.dof_ptr[(size_t)a]; t < cp_.dof_ptr[(size_t)a + 1]; ++t) {
        const double *g = &cp_.gd[5 * (size_t)t];
        v[cp_.dofs[(size_t)t]] += g[0] * x[0] + g[1] * x[1] + g[2] * x[2] + g[3] * x[3] + g[4] * x[4];
    }
}

void BodyForm::contact_velocity(int64_t a, const double *v, double *s) const {
    for (int i = 0; i < 5; ++i) s[i] = p_.w[5 * a + i];
    for (int64_t t = cp_.dof_ptr[(size_t)a]; t < cp_.dof_ptr[(size_t)a + 1]; ++t) {
        const double x = v[cp_.dofs[(size_t)t]], *h = &cp_.hd[5 * (size_t)t];
        for (int i = 0; i < 5; ++i) s[i] += h[i] * x;
    }
}

void BodyForm::local_q(int64_t a, const double *r, double *ql) const {
    double s[5];
    contact_velocity(a, v_.data(), s);
    const double *W = &blocks_[25 * (size_t)a], *ra = r + 5 * a;
    for (int i = 0; i < 5; ++i) {
        double wr = 0.0;
        for (int j = 0; j < 5; ++j) wr += W[i + 5 * j] * ra[j];
        ql[i] = s[i] - wr;
    }
}

void BodyForm::restart(const double *r) {
    v_ = v0_;
    for (int64_t a = 0; a < p_.nc; ++a) add_g(a, r + 5 * a, v_.data());
}

Measures BodyForm::exact(const double *r, double *u) {
    restart(r);
    for (int64_t a = 0; a < p_.nc; ++a) contact_velocity(a, v_.data(), u + 5 * a);
    return rolling_measures_from_ru(p_, r, u, norm2(p_.w, 5 * p_.nc), free_velocity(p_));
}

std::vector<local5::Contact> contacts_of(const SweepForm &form, const frix_problem &p) {
    std::vector<local5::Contact> contacts((size_t)p.nc);
    for (int64_t a = 0; a < p.nc; ++a)
        local5::contact_setup(form.diagonal_block(a), p.mu[a], p.mu_r[a], contacts[(size_t)a]);
    return contacts;
}

SweepStats sweep(SweepForm &form, std::vector<local5::Contact> &contacts, const local5::Params &lp, double *r) {
    SweepStats st;
    const int64_t nc = (int64_t)contacts.size();
    for (int64_t a = 0; a < nc; ++a) {
        double *ra = r + 5 * a, ql[5], rn[5];
        form.local_q(a, r, ql);
        std::copy(ra, ra + 5, rn);
        const local5::Outcome out = local5::solve_contact(contacts[(size_t)a], ql, rn, lp);
        if (out == local5::Outcome::NotConverged || out == local5::Outcome::NoSolution) ++st.unsolved;
        double dr[5], d2 = 0.0;
        bool finite = true;
        for (int i = 0; i < 5; ++i) {
            dr[i] = rn[i] - ra[i];
            d2 += dr[i] * dr[i];
            finite = finite && std::isfinite(rn[i]);
        }
        if (!finite) {
            ++st.rejected;
        } else if (d2 > 0.0) {
            std::copy(rn, rn + 5, ra);
            form.moved(a, dr);
            st.dr2 += d2;
        }
        for (int i = 0; i < 5; ++i) st.r2 += ra[i] * ra[i];
    }
    return st;
}

}  // namespace frix::rolling
