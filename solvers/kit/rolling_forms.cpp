#include "solvers/kit/rolling_forms.hpp"

#include <algorithm>
#include <cmath>

#include "solvers/kit/pairs_by_key.hpp"
#include "src/error_state.hpp"
#include "src/matrix.hpp"
#include "src/memory.hpp"
#include "src/reduction.hpp"

namespace frix::rolling {

using local_rolling::with_size;

namespace {

// y_a = sum_k B_k x_{b_k} over the blocks k of row a (N x N): W x, row by row.
template <int N>
void multiply_rows(const BlockRows &W, const double *x, double *y) {
    const int64_t nc = (int64_t)W.row_ptr.size() - 1;
    for (int64_t a = 0; a < nc; ++a) {
        double s[N] = {};
        for (int64_t k = W.row_ptr[(size_t)a]; k < W.row_ptr[(size_t)a + 1]; ++k) {
            const double *B = &W.val[N * N * (size_t)k], *xb = x + N * W.block_col[(size_t)k];
            for (int j = 0; j < N; ++j)
                for (int i = 0; i < N; ++i) s[i] += B[i + N * j] * xb[j];
        }
        std::copy(s, s + N, y + N * a);
    }
}

// ql = q_a + sum_{b != a} W_ab r_b (N entries).
template <int N>
void local_q_rows(const BlockRows &W, const double *q, int64_t a, const double *r, double *ql) {
    for (int i = 0; i < N; ++i) ql[i] = q[N * a + i];
    for (int64_t k = W.row_ptr[(size_t)a]; k < W.row_ptr[(size_t)a + 1]; ++k) {
        const int64_t b = W.block_col[(size_t)k];
        if (b == a) continue;  // stepped over, not subtracted: no cancellation
        const double *B = &W.val[N * N * (size_t)k], *rb = r + N * b;
        for (int j = 0; j < N; ++j)
            for (int i = 0; i < N; ++i) ql[i] += B[i + N * j] * rb[j];
    }
}

}  // namespace

void BlockRows::multiply(const double *x, double *y) const {
    with_size(size, [&](auto n) { multiply_rows<decltype(n)::value>(*this, x, y); });
}

RowForm::RowForm(const frix_problem &p) : SweepForm(contact_size(p)), p_(p) {
    const int64_t nc = p.nc, n = size();
    w_.size = (int)n;
    // The blocks of each row: every (row, column) contact pair an entry falls in, once.
    unique_pairs_by_key(
        nc, [&](auto &&emit) { for_each_entry(*p.W, [&](int64_t i, int64_t j, double) { emit(i / n, j / n); }); },
        w_.row_ptr, w_.block_col);
    assign_advised(w_.val, (size_t)(n * n) * w_.block_col.size(), 0.0);
    // Each entry into its block; consecutive entries mostly share one, found once.
    int64_t last_a = -1, last_b = -1, k = 0;
    for_each_entry(*p.W, [&](int64_t i, int64_t j, double v) {
        const int64_t a = i / n, b = j / n;
        if (a != last_a || b != last_b) {
            const auto first = w_.block_col.begin() + w_.row_ptr[(size_t)a];
            const auto last = w_.block_col.begin() + w_.row_ptr[(size_t)a + 1];
            k = std::lower_bound(first, last, b) - w_.block_col.begin();
            last_a = a, last_b = b;
        }
        w_.val[(size_t)(n * n) * (size_t)k + (size_t)(i % n) + (size_t)n * (size_t)(j % n)] += v;
    });
    w_.diag.assign((size_t)nc, -1);
    for (int64_t a = 0; a < nc; ++a)
        for (int64_t kk = w_.row_ptr[(size_t)a]; kk < w_.row_ptr[(size_t)a + 1]; ++kk)
            if (w_.block_col[(size_t)kk] == a) w_.diag[(size_t)a] = kk;
}

void RowForm::diagonal_block(int64_t a, double *out) const {
    const size_t nn = (size_t)(size() * size());
    if (w_.diag[(size_t)a] >= 0)
        std::copy_n(&w_.val[nn * (size_t)w_.diag[(size_t)a]], nn, out);
    else
        std::fill_n(out, nn, 0.0);
}

void RowForm::local_q(int64_t a, const double *r, double *ql) const {
    with_size(size(), [&](auto n) { local_q_rows<decltype(n)::value>(w_, p_.q, a, r, ql); });
}

namespace {

// ql = q_a + sum_{b != a} W_ab r_b (N entries), row N a + i of W read as column N a + i.
template <int N>
void local_q_columns(const frix_matrix &W, const int64_t *diag_first, const int64_t *diag_end, const double *q,
                     int64_t a, const double *r, double *ql) {
    for (int i = 0; i < N; ++i) {
        const int64_t c = N * a + i;
        double s = q[c];
        // The diagonal block's entries are stepped over, not subtracted: no cancellation.
        const auto add = [&](int64_t from, int64_t to) {
            for (int64_t e = from; e < to; ++e) s += W.val[(size_t)e] * r[W.row_ind[(size_t)e]];
        };
        add(W.col_ptr[(size_t)c], diag_first[c]);
        add(diag_end[c], W.col_ptr[(size_t)c + 1]);
        ql[i] = s;
    }
}

// The same from W's 3x3 block rows: where N is not a multiple of 3 a block may straddle two
// contacts, so the diagonal block's columns are stepped over entry by entry in the blocks it
// touches.
template <int N>
void local_q_blocks(const frix_matrix &W, const double *q, int64_t a, const double *r, double *ql) {
    const int64_t first = N * a, end = first + N;
    for (int i = 0; i < N; ++i) {
        const int64_t c = first + i, k = c / 3, ri = c % 3;
        double s = q[c];
        for (int64_t b = W.row_ptr[(size_t)k]; b < W.row_ptr[(size_t)k + 1]; ++b) {
            const double *B = &W.block_val[9 * (size_t)b];
            const int64_t col = 3 * W.block_col[(size_t)b];
            if (col + 3 <= first || col >= end) {
                s += B[ri] * r[col] + B[ri + 3] * r[col + 1] + B[ri + 6] * r[col + 2];
                continue;
            }
            for (int j = 0; j < 3; ++j)
                if (col + j < first || col + j >= end) s += B[ri + 3 * j] * r[col + j];
        }
        ql[i] = s;
    }
}

}  // namespace

StoredForm::StoredForm(const frix_problem &p) : SweepForm(contact_size(p)), p_(p) {
    const frix_matrix &W = *p.W;
    if (W.block) {
        serves_ = true;
        return;
    }
    const int64_t n = size(), m = n * p.nc;
    assign_advised(diag_first_, (size_t)m);
    assign_advised(diag_end_, (size_t)m);
    std::vector<double> diagonal((size_t)m, 0.0);
    for (int64_t c = 0; c < m; ++c) {
        const int64_t first = n * (c / n);
        const auto begin = W.row_ind.begin() + W.col_ptr[(size_t)c], end = W.row_ind.begin() + W.col_ptr[(size_t)c + 1];
        const auto lo = std::lower_bound(begin, end, first);
        const auto hi = std::lower_bound(lo, end, first + n);
        diag_first_[(size_t)c] = lo - W.row_ind.begin();
        diag_end_[(size_t)c] = hi - W.row_ind.begin();
        for (auto e = lo; e != hi; ++e)
            if (*e == c) diagonal[(size_t)c] = W.val[(size_t)(e - W.row_ind.begin())];
    }
    serves_ = symmetric_at_every_scale(linalg::CscView{W.rows, W.cols, W.col_ptr.data(), W.row_ind.data(), W.val.data()},
                                       diagonal.data());
}

void StoredForm::diagonal_block(int64_t a, double *out) const {
    const frix_matrix &W = *p_.W;
    const int64_t n = size(), first = n * a;
    std::fill_n(out, n * n, 0.0);
    for (int64_t j = 0; j < n; ++j) {
        const int64_t c = first + j;
        if (!W.block) {
            for (int64_t e = diag_first_[(size_t)c]; e < diag_end_[(size_t)c]; ++e)
                out[(W.row_ind[(size_t)e] - first) + n * j] = W.val[(size_t)e];
            continue;
        }
        // By block rows: row c of W holds row j of W_aa.
        const int64_t k = c / 3, ri = c % 3;
        for (int64_t b = W.row_ptr[(size_t)k]; b < W.row_ptr[(size_t)k + 1]; ++b)
            for (int i = 0; i < 3; ++i) {
                const int64_t col = 3 * W.block_col[(size_t)b] + i;
                if (col >= first && col < first + n)
                    out[j + n * (col - first)] = W.block_val[9 * (size_t)b + ri + 3 * i];
            }
    }
}

void StoredForm::local_q(int64_t a, const double *r, double *ql) const {
    with_size(size(), [&](auto n) {
        if (p_.W->block)
            local_q_blocks<decltype(n)::value>(*p_.W, p_.q, a, r, ql);
        else
            local_q_columns<decltype(n)::value>(*p_.W, diag_first_.data(), diag_end_.data(), p_.q, a, r, ql);
    });
}

// Domains of the threaded sweeps: about kDomains of them, enough for the threads to share each
// colour's evenly, and none under kMinDomain contacts (a domain's sweep must outweigh handing
// it to a thread; a rolling contact's solve costs several times a three-entry one's). A problem
// of one domain has nothing to share: it is swept in its own order on the caller's thread.
constexpr int64_t kDomains = 128;
constexpr int64_t kMinDomain = 64;

frix_error BodyForm::setup(const double *r, const char *who, int threads) {
    {
        Csc M;
        if (frix_error e = to_csc(*p_.M, M)) return e;
        if (frix_error e = bodies_.setup(M, who)) return e;
    }
    const int64_t nc = p_.nc, n = size();
    {
        ContactBodies cb;
        cb.find(*p_.H, bodies_, (int)n, nc);
        // The domains of one colour share no body: their contacts touch disjoint dofs of v.
        const int64_t domain_size = std::max(kMinDomain, (nc + kDomains - 1) / kDomains);
        if (threads > 0 && nc > domain_size) {
            domains_ = nsgs::make_domains(nc, bodies_.count(), domain_size,
                                          [&cb](int64_t a, std::vector<int64_t> &out) {
                                              out.insert(out.end(), cb.bodies.begin() + cb.ptr[a],
                                                         cb.bodies.begin() + cb.ptr[a + 1]);
                                          });
            team_ = std::make_unique<ThreadTeam>(threads);
            position_.resize((size_t)nc);
            for (int64_t k = 0; k < nc; ++k) position_[(size_t)domains_.contacts[(size_t)k]] = k;
        }
        const int64_t *order = team_ ? domains_.contacts.data() : nullptr;
        cp_.build(*p_.H, bodies_, cb, (int)n, nc, order, false);
        if (order) {
            cp_.renumber_dofs(p_.n, nullptr, nc, slot_of_dof_);
            dof_of_slot_.resize((size_t)p_.n);
            for (int64_t d = 0; d < p_.n; ++d) dof_of_slot_[(size_t)slot_of_dof_[(size_t)d]] = d;
        }
    }
    assign_advised(blocks_, (size_t)(n * n * nc), 0.0);
    assign_advised(w_, (size_t)(n * nc));
    for (int64_t a = 0; a < nc; ++a) {
        cp_.add_diagonal_block(at(a), &blocks_[(size_t)(n * n * at(a))]);
        std::copy(p_.w + n * a, p_.w + n * (a + 1), &w_[(size_t)(n * at(a))]);
    }
    v0_.assign((size_t)p_.n, 0.0);
    bodies_.apply_inverse(p_.f, v0_.data());
    if (!slot_of_dof_.empty()) {
        const std::vector<double> v0 = v0_;
        for (int64_t d = 0; d < p_.n; ++d) v0_[(size_t)slot_of_dof_[(size_t)d]] = v0[(size_t)d];
    }
    norm_w_ = norm2(p_.w, n * nc);
    free_ = free_velocity(p_);
    restart(r);
    return FRIX_OK;
}

void BodyForm::copy_v(double *v) const {
    for (int64_t d = 0; d < p_.n; ++d) v[d] = v_[slot_of_dof_.empty() ? (size_t)d : (size_t)slot_of_dof_[(size_t)d]];
}

bool BodyForm::reduce(BlockRows &W, double *q, const std::function<bool(const BlockRows &pattern)> &fits) const {
    const int64_t nc = p_.nc, nb = bodies_.count(), n = size();
    // The problem's dof of cp_'s t-th entry.
    const auto dof = [this](int64_t t) {
        const int64_t d = cp_.dofs[(size_t)t];
        return dof_of_slot_.empty() ? d : dof_of_slot_[(size_t)d];
    };
    // Each body's contacts, with where the body's dofs start among the contact's (a contact
    // holds its bodies whole, in increasing order, each from its place 0).
    std::vector<int64_t> ptr((size_t)nb + 1, 0);
    for (int64_t t = 0; t < cp_.dof_ptr[(size_t)nc]; ++t)
        if (bodies_.place[dof(t)] == 0) ++ptr[(size_t)bodies_.body_of[dof(t)] + 1];
    for (int64_t b = 0; b < nb; ++b) ptr[(size_t)b + 1] += ptr[(size_t)b];
    std::vector<int64_t> contact((size_t)ptr[(size_t)nb]), start((size_t)ptr[(size_t)nb]);
    std::vector<int64_t> fill(ptr.begin(), ptr.end() - 1);
    for (int64_t a = 0; a < nc; ++a)
        for (int64_t t = cp_.dof_ptr[(size_t)at(a)]; t < cp_.dof_ptr[(size_t)at(a) + 1]; ++t)
            if (bodies_.place[dof(t)] == 0) {
                const int64_t at = fill[(size_t)bodies_.body_of[dof(t)]]++;
                contact[(size_t)at] = a, start[(size_t)at] = t;
            }
    W.size = (int)n;
    W.row_ptr.assign((size_t)nc + 1, 0);
    W.block_col.clear();
    W.diag.assign((size_t)nc, -1);
    std::vector<int64_t> cols;
    for (int pass = 0; pass < 2; ++pass)
        for (int64_t a = 0; a < nc; ++a) {
            cols.clear();
            for (int64_t t = cp_.dof_ptr[(size_t)at(a)]; t < cp_.dof_ptr[(size_t)at(a) + 1]; ++t) {
                if (bodies_.place[dof(t)] != 0) continue;
                const int64_t b = bodies_.body_of[dof(t)];
                if (pass == 0) {
                    for (int64_t e = ptr[(size_t)b]; e < ptr[(size_t)b + 1]; ++e) cols.push_back(contact[(size_t)e]);
                    continue;
                }
                // W_ac += sum over the body's dofs of (H_a)_x (M^-1 H_c)_x^T.
                for (int64_t e = ptr[(size_t)b]; e < ptr[(size_t)b + 1]; ++e) {
                    const auto first = W.block_col.begin() + W.row_ptr[(size_t)a];
                    const auto last = W.block_col.begin() + W.row_ptr[(size_t)a + 1];
                    double *blk = &W.val[(size_t)(n * n) * (size_t)(std::lower_bound(first, last, contact[(size_t)e]) -
                                                                    W.block_col.begin())];
                    for (int64_t j = 0; j < bodies_.size(b); ++j) {
                        const double *h = &cp_.hd[(size_t)(n * (t + j))];
                        const double *g = &cp_.gd[(size_t)(n * (start[(size_t)e] + j))];
                        for (int64_t f = 0; f < n; ++f)
                            for (int64_t i = 0; i < n; ++i) blk[i + n * f] += h[i] * g[f];
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
            if (a < nc - 1) continue;
            if (!fits(W)) {
                W = BlockRows{};
                return false;
            }
            assign_advised(W.val, (size_t)(n * n) * W.block_col.size(), 0.0);
        }
    for (int64_t a = 0; a < nc; ++a) contact_velocity(a, v0_.data(), q + n * a);
    return true;
}

namespace {

// v += M^-1 H_a x (N entries of x): the dofs of the bodies of the contact at position k.
template <int N>
void add_g_sized(const ContactProducts &cp, int64_t k, const double *x, double *v) {
    for (int64_t t = cp.dof_ptr[(size_t)k]; t < cp.dof_ptr[(size_t)k + 1]; ++t) {
        const double *g = &cp.gd[N * (size_t)t];
        double s = g[0] * x[0];
        for (int i = 1; i < N; ++i) s += g[i] * x[i];
        v[cp.dofs[(size_t)t]] += s;
    }
}

// s = w_a + H_a^T v (N entries), the contact at position k (w by position).
template <int N>
void velocity_sized(const ContactProducts &cp, const double *w, int64_t k, const double *v, double *s) {
    for (int i = 0; i < N; ++i) s[i] = w[N * k + i];
    for (int64_t t = cp.dof_ptr[(size_t)k]; t < cp.dof_ptr[(size_t)k + 1]; ++t) {
        const double x = v[cp.dofs[(size_t)t]], *h = &cp.hd[N * (size_t)t];
        for (int i = 0; i < N; ++i) s[i] += h[i] * x;
    }
}

// ql = s - W_aa r_a, s = w_a + H_a^T v (N entries), the contact at position k.
template <int N>
void body_local_q(const ContactProducts &cp, const double *w, const double *blocks, int64_t k, const double *v,
                  const double *ra, double *ql) {
    double s[N];
    velocity_sized<N>(cp, w, k, v, s);
    const double *W = &blocks[N * N * (size_t)k];
    for (int i = 0; i < N; ++i) {
        double wr = 0.0;
        for (int j = 0; j < N; ++j) wr += W[i + N * j] * ra[j];
        ql[i] = s[i] - wr;
    }
}

// Contact a of the sweep (N entries): solved with the others held fixed, kept where finite.
template <int N>
void sweep_contact(SweepForm &form, local_rolling::Contact &c, const local_rolling::Params &lp, int64_t a, double *r,
                   SweepStats &st) {
    double *ra = r + N * a, ql[N], rn[N];
    form.local_q(a, r, ql);
    std::copy(ra, ra + N, rn);
    const local_rolling::Outcome out = local_rolling::solve_contact(c, ql, rn, lp);
    if (out == local_rolling::Outcome::NotConverged || out == local_rolling::Outcome::NoSolution) ++st.unsolved;
    double dr[N], d2 = 0.0;
    bool finite = true;
    for (int i = 0; i < N; ++i) {
        dr[i] = rn[i] - ra[i];
        d2 += dr[i] * dr[i];
        finite = finite && std::isfinite(rn[i]);
    }
    if (!finite) {
        ++st.rejected;
    } else if (d2 > 0.0) {
        std::copy(rn, rn + N, ra);
        form.moved(a, dr);
        st.dr2 += d2;
    }
    for (int i = 0; i < N; ++i) st.r2 += ra[i] * ra[i];
}

}  // namespace

void BodyForm::add_g(int64_t a, const double *x, double *v) const {
    with_size(size(), [&](auto n) { add_g_sized<decltype(n)::value>(cp_, at(a), x, v); });
}

void BodyForm::contact_velocity(int64_t a, const double *v, double *s) const {
    with_size(size(), [&](auto n) { velocity_sized<decltype(n)::value>(cp_, w_.data(), at(a), v, s); });
}

void BodyForm::local_q(int64_t a, const double *r, double *ql) const {
    with_size(size(), [&](auto n) {
        body_local_q<decltype(n)::value>(cp_, w_.data(), blocks_.data(), at(a), v_.data(), r + n * a, ql);
    });
}

template <class F>
void BodyForm::for_positions(F &&f) {
    if (!team_) {
        for (int64_t k = 0; k < p_.nc; ++k) f(k);
        return;
    }
    for (int64_t c = 0; c < domains_.colours(); ++c) {
        const int64_t first = domains_.colour_ptr[(size_t)c];
        team_->for_chunks(domains_.colour_ptr[(size_t)c + 1] - first, 1, [&](int64_t begin, int64_t end) {
            for (int64_t d = first + begin; d < first + end; ++d)
                for (int64_t k = domains_.domain_ptr[(size_t)d]; k < domains_.domain_ptr[(size_t)d + 1]; ++k) f(k);
        });
    }
}

void BodyForm::restart(const double *r) {
    v_ = v0_;
    for_positions([&](int64_t k) { add_g(contact_at(k), r + size() * contact_at(k), v_.data()); });
}

Measures BodyForm::exact(const double *r, double *u) {
    restart(r);
    const int64_t n = size();
    for_positions([&](int64_t k) { contact_velocity(contact_at(k), v_.data(), u + n * contact_at(k)); });
    return rolling_measures_from_ru(p_, r, u, norm_w_, free_);
}

std::vector<local_rolling::Contact> contacts_of(const SweepForm &form, const frix_problem &p) {
    std::vector<local_rolling::Contact> contacts;
    assign_advised(contacts, (size_t)p.nc);
    const nsgs::Domains *dom = form.domains();
    for (int64_t k = 0; k < p.nc; ++k) {
        const int64_t a = dom ? dom->contacts[(size_t)k] : k;
        double Waa[local_rolling::kMaxSize * local_rolling::kMaxSize];
        form.diagonal_block(a, Waa);
        local_rolling::contact_setup(Waa, cones_of(p, a), contacts[(size_t)k]);
    }
    return contacts;
}

SweepStats sweep(SweepForm &form, std::vector<local_rolling::Contact> &contacts, const local_rolling::Params &lp,
                 double *r) {
    SweepStats st;
    const int64_t nc = (int64_t)contacts.size();
    const nsgs::Domains *dom = form.domains();
    if (!dom) {
        with_size(form.size(), [&](auto n) {
            for (int64_t a = 0; a < nc; ++a) sweep_contact<decltype(n)::value>(form, contacts[(size_t)a], lp, a, r, st);
        });
        return st;
    }
    // Each domain's statistics in its own slot, written once at its end.
    std::vector<SweepStats> parts((size_t)dom->domains());
    with_size(form.size(), [&](auto n) {
        const auto sweep_domain = [&](int64_t d) {
            SweepStats part;
            for (int64_t i = dom->domain_ptr[(size_t)d]; i < dom->domain_ptr[(size_t)d + 1]; ++i) {
                sweep_contact<decltype(n)::value>(form, contacts[(size_t)i], lp, dom->contacts[(size_t)i], r, part);
            }
            parts[(size_t)d] = part;
        };
        for (int64_t k = 0; k < dom->colours(); ++k) {
            const int64_t first = dom->colour_ptr[(size_t)k];
            form.team()->for_chunks(dom->colour_ptr[(size_t)k + 1] - first, 1, [&](int64_t begin, int64_t end) {
                for (int64_t d = first + begin; d < first + end; ++d) sweep_domain(d);
            });
        }
    });
    for (const SweepStats &part : parts) {  // in domain order, whatever the threads
        st.dr2 += part.dr2, st.r2 += part.r2;
        st.unsolved += part.unsolved, st.rejected += part.rejected;
    }
    return st;
}

}  // namespace frix::rolling
