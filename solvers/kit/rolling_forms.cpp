#include "solvers/kit/rolling_forms.hpp"

#include <algorithm>

#include "src/error_state.hpp"
#include "src/matrix.hpp"
#include "src/reduction.hpp"

namespace frix::rolling {

RowForm::RowForm(const frix_problem &p) : p_(p) {
    const int64_t nc = p.nc;
    // The blocks of each row: every (row, column) contact pair an entry falls in, once.
    std::vector<std::vector<int64_t>> cols((size_t)nc);
    for_each_entry(*p.W, [&](int64_t i, int64_t j, double) { cols[(size_t)(i / 5)].push_back(j / 5); });
    row_ptr_.assign((size_t)nc + 1, 0);
    for (int64_t a = 0; a < nc; ++a) {
        std::vector<int64_t> &c = cols[(size_t)a];
        std::sort(c.begin(), c.end());
        c.erase(std::unique(c.begin(), c.end()), c.end());
        row_ptr_[(size_t)a + 1] = row_ptr_[(size_t)a] + (int64_t)c.size();
    }
    block_col_.reserve((size_t)row_ptr_[(size_t)nc]);
    for (const std::vector<int64_t> &c : cols) block_col_.insert(block_col_.end(), c.begin(), c.end());
    cols = {};
    val_.assign(25 * block_col_.size(), 0.0);
    for_each_entry(*p.W, [&](int64_t i, int64_t j, double v) {
        const int64_t a = i / 5, b = j / 5;
        const auto first = block_col_.begin() + row_ptr_[(size_t)a], last = block_col_.begin() + row_ptr_[(size_t)a + 1];
        const int64_t k = std::lower_bound(first, last, b) - block_col_.begin();
        val_[25 * (size_t)k + (size_t)(i % 5) + 5 * (size_t)(j % 5)] += v;
    });
    diag_.assign((size_t)nc, -1);
    for (int64_t a = 0; a < nc; ++a)
        for (int64_t k = row_ptr_[(size_t)a]; k < row_ptr_[(size_t)a + 1]; ++k)
            if (block_col_[(size_t)k] == a) diag_[(size_t)a] = k;
}

const double *RowForm::diagonal_block(int64_t a) const {
    return diag_[(size_t)a] >= 0 ? &val_[25 * (size_t)diag_[(size_t)a]] : zero_;
}

void RowForm::local_q(int64_t a, const double *r, double *ql) const {
    for (int i = 0; i < 5; ++i) ql[i] = p_.q[5 * a + i];
    for (int64_t k = row_ptr_[(size_t)a]; k < row_ptr_[(size_t)a + 1]; ++k) {
        const int64_t b = block_col_[(size_t)k];
        if (b == a) continue;  // stepped over, not subtracted: no cancellation
        const double *B = &val_[25 * (size_t)k], *rb = r + 5 * b;
        for (int j = 0; j < 5; ++j)
            for (int i = 0; i < 5; ++i) ql[i] += B[i + 5 * j] * rb[j];
    }
}

frix_error BodyForm::setup(const double *r) {
    Csc M, H;
    if (frix_error e = to_csc(*p_.M, M)) return e;
    if (frix_error e = bodies_.setup(M, "rolling-nsgs")) return e;
    const int64_t nc = p_.nc;
    if (nc > 0)
        if (frix_error e = to_csc(*p_.H, H)) return e;
    // Each contact's bodies (those its five columns of H reach), whole, in increasing order.
    std::vector<std::vector<int64_t>> bodies((size_t)nc);
    for (int64_t a = 0; a < nc; ++a) {
        std::vector<int64_t> &b = bodies[(size_t)a];
        for (int64_t c = 5 * a; c < 5 * a + 5; ++c)
            for (int64_t e = H.colptr[c]; e < H.colptr[c + 1]; ++e) b.push_back(bodies_.body_of[H.rowind[e]]);
        std::sort(b.begin(), b.end());
        b.erase(std::unique(b.begin(), b.end()), b.end());
    }
    dof_ptr_.assign((size_t)nc + 1, 0);
    for (int64_t a = 0; a < nc; ++a) {
        int64_t count = 0;
        for (const int64_t b : bodies[(size_t)a]) count += bodies_.size(b);
        dof_ptr_[(size_t)a + 1] = dof_ptr_[(size_t)a] + count;
    }
    const size_t total = (size_t)dof_ptr_[(size_t)nc];
    dofs_.resize(total);
    hd_.assign(5 * total, 0.0);
    gd_.assign(5 * total, 0.0);
    blocks_.assign(25 * (size_t)nc, 0.0);
    std::vector<int64_t> body_at((size_t)bodies_.count(), 0);
    for (int64_t a = 0; a < nc; ++a) {
        int64_t at = dof_ptr_[(size_t)a];
        for (const int64_t b : bodies[(size_t)a]) {
            body_at[(size_t)b] = at;
            for (int64_t j = 0; j < bodies_.size(b); ++j) dofs_[(size_t)(at + j)] = bodies_.body_dofs[bodies_.body_ptr[b] + j];
            at += bodies_.size(b);
        }
        for (int64_t c = 5 * a; c < 5 * a + 5; ++c)
            for (int64_t e = H.colptr[c]; e < H.colptr[c + 1]; ++e) {
                const int64_t row = H.rowind[e];
                hd_[5 * (size_t)(body_at[(size_t)bodies_.body_of[row]] + bodies_.place[row]) + (size_t)(c - 5 * a)] +=
                    H.val[e];
            }
        // M^-1 H_a body by body, and W_aa = H_a^T M^-1 H_a.
        for (const int64_t b : bodies[(size_t)a]) {
            const int64_t size = bodies_.size(b), start = body_at[(size_t)b];
            const double *inv = &bodies_.inverse[bodies_.inverse_ptr[b]], *h = &hd_[5 * (size_t)start];
            double *g = &gd_[5 * (size_t)start];
            for (int64_t x = 0; x < size; ++x)
                for (int f = 0; f < 5; ++f) {
                    double sum = 0.0;
                    for (int64_t j = 0; j < size; ++j) sum += inv[x + size * j] * h[5 * j + f];
                    g[5 * x + f] = sum;
                }
        }
        double *W = &blocks_[25 * (size_t)a];
        for (int64_t t = dof_ptr_[(size_t)a]; t < dof_ptr_[(size_t)a + 1]; ++t)
            for (int f = 0; f < 5; ++f)
                for (int e = 0; e < 5; ++e) W[e + 5 * f] += hd_[5 * (size_t)t + e] * gd_[5 * (size_t)t + f];
    }
    v0_.assign((size_t)p_.n, 0.0);
    bodies_.apply_inverse(p_.f, v0_.data());
    v_ = v0_;
    for (int64_t a = 0; a < nc; ++a) add_g(a, r + 5 * a, v_.data());
    return FRIX_OK;
}

void BodyForm::add_g(int64_t a, const double *x, double *v) const {
    for (int64_t t = dof_ptr_[(size_t)a]; t < dof_ptr_[(size_t)a + 1]; ++t) {
        const double *g = &gd_[5 * (size_t)t];
        v[dofs_[(size_t)t]] += g[0] * x[0] + g[1] * x[1] + g[2] * x[2] + g[3] * x[3] + g[4] * x[4];
    }
}

void BodyForm::contact_velocity(int64_t a, const double *v, double *s) const {
    for (int i = 0; i < 5; ++i) s[i] = p_.w[5 * a + i];
    for (int64_t t = dof_ptr_[(size_t)a]; t < dof_ptr_[(size_t)a + 1]; ++t) {
        const double x = v[dofs_[(size_t)t]], *h = &hd_[5 * (size_t)t];
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
    return rolling_measures_from_ru(r, u, p_.mu, p_.mu_r, p_.weight.data(), p_.nc, norm2(p_.w, 5 * p_.nc),
                                    free_velocity(p_));
}

}  // namespace frix::rolling
