#include "solvers/kit/single_columns.hpp"

#include <algorithm>

#include "src/memory.hpp"

namespace frix {
namespace nsgs {

namespace {

// The panels build() cuts nc contacts into when asked for `wanted`: each starts at a multiple
// of 4 contacts (12 rows, whole chunks), so only the last panel has a partial chunk.
int64_t panel_count(int64_t nc, int64_t wanted) { return std::max<int64_t>(1, std::min(wanted, nc / 4)); }

}  // namespace

bool SingleColumns::suits(const frix_matrix &W, double min_bytes) {
    if (!W.block || W.block_rows != W.block_cols || W.block_rows == 0) return false;
    const double nc = (double)W.block_rows;
    return (double)W.nblocks() == nc * nc && 72.0 * nc * nc >= min_bytes;
}

double SingleColumns::bytes_for(const frix_matrix &W) {
    const double chunks = (double)((3 * W.block_rows + kChunk - 1) / kChunk);
    return (double)W.block_cols * chunks * 3.0 * (double)kChunk * sizeof(float);
}

bool SingleColumns::holds(const frix_matrix &W, uint64_t w_values, uint64_t w_pattern, int64_t panels) const {
    return w_values != 0 && w_values_ == w_values && w_pattern_ == w_pattern && rows_ == W.rows &&
           !values_.empty() && this->panels() == panel_count(W.block_rows, panels);
}

void SingleColumns::build(const frix_matrix &W, uint64_t w_values, uint64_t w_pattern, int64_t panels) {
    const int64_t nc = W.block_rows;
    rows_ = 3 * nc;
    const int64_t count = panel_count(nc, panels);
    panel_.assign((size_t)count + 1, Panel());
    for (int64_t p = 0; p <= count; ++p) panel_[(size_t)p].contact = p == count ? nc : nc * p / count / 4 * 4;
    size_t floats = 0;
    for (int64_t p = 0; p <= count; ++p) {
        Panel &panel = panel_[(size_t)p];
        panel.offset = floats;
        if (p == count) break;
        const int64_t contacts = panel_[(size_t)p + 1].contact - panel.contact;
        panel.stride = (3 * contacts + kChunk - 1) / kChunk * 3 * kChunk;
        floats += (size_t)(panel.stride * nc);
    }
    assign_advised(values_, floats, 0.0f);
    const double *val = W.block_val.data();
    for (int64_t p = 0; p < count; ++p) {
        const Panel &panel = panel_[(size_t)p];
        for (int64_t a = 0; a < nc; ++a) {
            float *column = values_.data() + panel.offset + (size_t)(panel.stride * a);
            for (int64_t b = panel.contact; b < panel_[(size_t)p + 1].contact; ++b)
                for (int64_t t = 0; t < 3; ++t) {
                    const int64_t i = 3 * (b - panel.contact) + t;
                    float *chunk = column + (i / kChunk) * 3 * kChunk + i % kChunk;
                    // W(3b+t, 3a+j): every block is stored, so W_ba is block b*nc + a; a
                    // symmetric W's column a is read from its row a instead (W_ab(j, t)), in order.
                    for (int64_t j = 0; j < 3; ++j)
                        chunk[j * kChunk] = (float)(W.symmetric ? val[9 * (a * nc + b) + j + 3 * t]
                                                                : val[9 * (b * nc + a) + t + 3 * j]);
                }
        }
    }
    w_values_ = w_values;
    w_pattern_ = w_pattern;
}

void dense_restriction(const frix_matrix &W, const std::vector<int64_t> &S, frix_matrix &out) {
    const int64_t nc = W.block_rows, ns = (int64_t)S.size();
    out.rows = out.cols = 3 * ns;
    out.block = true;
    out.block_rows = out.block_cols = ns;
    out.symmetric = W.symmetric;
    out.row_ptr.resize((size_t)ns + 1);
    out.diag_index.resize((size_t)ns);
    reserve_advised(out.block_col, (size_t)(ns * ns));
    out.block_col.resize((size_t)(ns * ns));
    reserve_advised(out.block_val, (size_t)(9 * ns * ns));
    out.block_val.resize((size_t)(9 * ns * ns));
    for (int64_t i = 0; i < ns; ++i) {
        out.row_ptr[(size_t)i] = i * ns;
        out.diag_index[(size_t)i] = i * ns + i;
        const double *row = &W.block_val[(size_t)(9 * S[(size_t)i] * nc)];
        double *to = &out.block_val[(size_t)(9 * i * ns)];
        for (int64_t j = 0; j < ns; ++j) {
            out.block_col[(size_t)(i * ns + j)] = j;
            std::copy_n(row + 9 * S[(size_t)j], 9, to + 9 * j);
        }
    }
    out.row_ptr[(size_t)ns] = ns * ns;
}

void SingleColumns::push(int64_t a, const double *dr, double *u) const {
    for (int64_t p = 0; p < panels(); ++p) push_panel(p, a, dr, u);
}

void SingleColumns::push_panel(int64_t p, int64_t a, const double *dr, double *u) const {
    const float d0 = (float)dr[0], d1 = (float)dr[1], d2 = (float)dr[2];
    const Panel &panel = panel_[(size_t)p];
    const float *c = values_.data() + panel.offset + (size_t)(panel.stride * a);
    const int64_t rows = 3 * (panel_[(size_t)p + 1].contact - panel.contact), whole = rows / kChunk * kChunk;
    u += 3 * panel.contact;
    int64_t i = 0;
    // Four rows a chunk, written out so that the compiler's vectoriser at -O2 takes it.
    for (; i < whole; i += kChunk, c += 3 * kChunk) {
        float s[kChunk];
        for (int64_t t = 0; t < kChunk; ++t) s[t] = c[t] * d0 + c[kChunk + t] * d1 + c[2 * kChunk + t] * d2;
        for (int64_t t = 0; t < kChunk; ++t) u[i + t] += (double)s[t];
    }
    for (int64_t t = 0; i + t < rows; ++t)
        u[i + t] += (double)(c[t] * d0 + c[kChunk + t] * d1 + c[2 * kChunk + t] * d2);
}

}  // namespace nsgs
}  // namespace frix
