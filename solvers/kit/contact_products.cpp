#include "solvers/kit/contact_products.hpp"

#include <algorithm>

#include "solvers/kit/pairs_by_key.hpp"
#include "src/memory.hpp"

namespace frix {

namespace {

// f(row, contact, column within the contact, value) for every non-zero entry of H.
template <class F>
void for_each_contact_entry(const frix_matrix &H, int width, F &&f) {
    for_each_entry(H, [&](int64_t i, int64_t j, double v) {
        if (v != 0.0) f(i, j / width, (int)(j % width), v);
    });
}

}  // namespace

void ContactBodies::find(const frix_matrix &H, const RigidBodies &rigid, int width, int64_t nc) {
    unique_pairs_by_key(
        nc,
        [&](auto &&emit) {
            for_each_contact_entry(H, width, [&](int64_t i, int64_t a, int, double) { emit(a, rigid.body_of[i]); });
        },
        ptr, bodies);
}

void ContactProducts::build(const frix_matrix &H, const RigidBodies &rigid, const ContactBodies &cb, int w,
                            int64_t nc, const int64_t *order, bool one_dof_minv) {
    width = w;
    std::vector<int64_t> position((size_t)nc);  // contact a is at position[a]
    for (int64_t k = 0; k < nc; ++k) position[(size_t)(order ? order[k] : k)] = k;
    const auto contact = [order](int64_t k) { return order ? order[k] : k; };
    dof_ptr.assign((size_t)nc + 1, 0);
    for (int64_t k = 0; k < nc; ++k) {
        const int64_t a = contact(k);
        int64_t count = 0;
        for (int64_t i = cb.ptr[a]; i < cb.ptr[a + 1]; ++i) count += rigid.size(cb.bodies[i]);
        dof_ptr[k + 1] = dof_ptr[k] + count;
    }
    const size_t total = (size_t)dof_ptr[nc];
    assign_advised(dofs, total);
    assign_advised(hd, (size_t)width * total, 0.0);
    g_ptr.assign((size_t)nc, -1);
    int64_t stored = 0;
    for (int64_t k = 0; k < nc; ++k) {
        const int64_t a = contact(k);
        bool one_dof_bodies = one_dof_minv;
        for (int64_t i = cb.ptr[a]; i < cb.ptr[a + 1] && one_dof_bodies; ++i)
            one_dof_bodies = rigid.size(cb.bodies[i]) == 1;
        if (!one_dof_bodies) {
            g_ptr[k] = stored;
            stored += dof_count(k);
        }
    }
    assign_advised(gd, (size_t)width * stored, 0.0);
    assign_advised(minv, one_dof_minv ? total : 0, 0.0);
    for (int64_t k = 0; k < nc; ++k) {
        const int64_t a = contact(k);
        int64_t at = dof_ptr[k];
        for (int64_t i = cb.ptr[a]; i < cb.ptr[a + 1]; ++i) {
            const int64_t b = cb.bodies[i], size = rigid.size(b);
            for (int64_t j = 0; j < size; ++j) dofs[at + j] = rigid.body_dofs[rigid.body_ptr[b] + j];
            if (g_ptr[k] < 0) minv[at] = rigid.inverse[rigid.inverse_ptr[b]];  // a one-dof body
            at += size;
        }
    }
    // Each entry of H at its dof: after the dofs of the contact's bodies before its own (a
    // contact touches a few bodies).
    for_each_contact_entry(H, width, [&](int64_t row, int64_t a, int c, double v) {
        const int64_t k = position[(size_t)a], b = rigid.body_of[row];
        int64_t at = dof_ptr[k];
        for (int64_t i = cb.ptr[a]; cb.bodies[i] != b; ++i) at += rigid.size(cb.bodies[i]);
        hd[(size_t)width * (size_t)(at + rigid.place[row]) + (size_t)c] += v;
    });
    // M^-1 H_a body by body.
    for (int64_t k = 0; k < nc; ++k) {
        if (g_ptr[k] < 0) continue;
        const int64_t a = contact(k);
        int64_t start = dof_ptr[k];
        for (int64_t i = cb.ptr[a]; i < cb.ptr[a + 1]; ++i) {
            const int64_t b = cb.bodies[i], size = rigid.size(b);
            const double *h = hd.data() + (size_t)width * start, *inv = rigid.inverse.data() + rigid.inverse_ptr[b];
            double *g = gd.data() + (size_t)width * (g_ptr[k] + start - dof_ptr[k]);
            for (int64_t x = 0; x < size; ++x)
                for (int f = 0; f < width; ++f) {
                    double sum = 0.0;
                    for (int64_t j = 0; j < size; ++j) sum += inv[x + size * j] * h[width * j + f];
                    g[width * x + f] = sum;
                }
            start += size;
        }
    }
}

void ContactProducts::g_row(int64_t k, int64_t t, double *g) const {
    if (g_ptr[k] >= 0) {
        const double *from = &gd[(size_t)width * (size_t)(g_ptr[k] + t)];
        std::copy(from, from + width, g);
        return;
    }
    const double *h = &hd[(size_t)width * (size_t)(dof_ptr[k] + t)], d = minv[dof_ptr[k] + t];
    for (int f = 0; f < width; ++f) g[f] = d * h[f];
}

void ContactProducts::add_diagonal_block(int64_t k, double *W) const {
    const double *h = hd.data() + (size_t)width * dof_ptr[k];
    double g[8];  // width <= 8: the forms' contacts have 3, 5 or 6 entries
    for (int64_t t = 0; t < dof_count(k); ++t) {
        g_row(k, t, g);
        for (int f = 0; f < width; ++f)
            for (int e = 0; e < width; ++e) W[e + width * f] += h[width * t + e] * g[f];
    }
}

void ContactProducts::renumber_dofs(int64_t n, const int64_t *order, int64_t count, std::vector<int64_t> &slot_of_dof) {
    slot_of_dof.assign((size_t)n, -1);
    int64_t next = 0;
    for (int64_t i = 0; i < count; ++i) {
        const int64_t k = order ? order[i] : i;
        for (int64_t t = dof_ptr[(size_t)k]; t < dof_ptr[(size_t)k + 1]; ++t) {
            int64_t &d = dofs[(size_t)t];
            if (slot_of_dof[(size_t)d] < 0) slot_of_dof[(size_t)d] = next++;
            d = slot_of_dof[(size_t)d];
        }
    }
    for (int64_t &s : slot_of_dof)
        if (s < 0) s = next++;  // dofs no contact touches
}

}  // namespace frix
