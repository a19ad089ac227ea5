#include "secant_start.hpp"

#include <cmath>
#include <cstring>

#include "coulomb.hpp"
#include "problem.hpp"
#include "vec.hpp"

namespace frix {

namespace {

// The data's step off the line through the last two solves' data, against the step itself,
// below which it moved along that line (a load path's proportional steps leave rounding).
constexpr double kOffLine = 0.1;
// The farthest the secant is carried, in steps of the last one: past it the line's
// extrapolation of the answers is a guess.
constexpr double kMaxSteps = 2.0;

// The problem's data as blocks: q, or f and w; each block is tested against the line on its
// own, so that the test does not mix units.
struct Block {
    const double *now;
    size_t offset, size;
};

int blocks_of(const frix_problem &p, Block *out) {
    const size_t m = 3 * (size_t)p.nc;
    if (is_local_form(p)) {
        out[0] = {p.q, 0, m};
        return 1;
    }
    out[0] = {p.f, 0, (size_t)p.n};
    out[1] = {p.w, (size_t)p.n, m};
    return 2;
}

}  // namespace

bool SecantStart::same_setting(const frix_problem &p, const SolveCache &versions) const {
    const Setting &s = setting_;
    return s.kind == (int)p.kind && s.nc == p.nc && s.n == p.n && s.w_values == versions.w_values &&
           s.w_pattern == versions.w_pattern && s.m_values == versions.m_values && s.h_values == versions.h_values &&
           (p.nc == 0 || std::memcmp(s.mu.data(), p.mu, sizeof(double) * (size_t)p.nc) == 0);
}

bool SecantStart::predict(const frix_problem &p, const SolveCache &versions, double *r) const {
    if (count_ < 2 || contact_size(p) != 3 || p.nc == 0 || !same_setting(p, versions)) return false;
    const size_t m = 3 * (size_t)p.nc;
    const std::vector<double> &last_r = r_[last_], &older_r = r_[1 - last_];
    const std::vector<double> &last = data_[last_], &older = data_[1 - last_];
    // The caller continues from the last answer, or chose its own start.
    if (std::memcmp(r, last_r.data(), sizeof(double) * m) != 0) return false;
    Block blocks[2];
    const int count = blocks_of(p, blocks);
    // alpha from the first block that moved at the last step: the least-squares multiple of
    // that step nearest to this one.
    double alpha = NAN;
    for (int b = 0; b < count && std::isnan(alpha); ++b) {
        const Block &k = blocks[b];
        double d0d1 = 0.0, d1d1 = 0.0;
        for (size_t i = 0; i < k.size; ++i) {
            const double d1 = last[k.offset + i] - older[k.offset + i], d0 = k.now[i] - last[k.offset + i];
            d0d1 += d0 * d1;
            d1d1 += d1 * d1;
        }
        if (d1d1 > 0.0) alpha = d0d1 / d1d1;
    }
    if (!(std::fabs(alpha) > 0.0 && std::fabs(alpha) <= kMaxSteps)) return false;
    // Every block's step alpha times its last one, to kOffLine of it.
    for (int b = 0; b < count; ++b) {
        const Block &k = blocks[b];
        double off = 0.0, step = 0.0;
        for (size_t i = 0; i < k.size; ++i) {
            const double d1 = last[k.offset + i] - older[k.offset + i], d0 = k.now[i] - last[k.offset + i];
            off += (d0 - alpha * d1) * (d0 - alpha * d1);
            step += d0 * d0;
        }
        if (!(off <= kOffLine * kOffLine * step)) return false;
    }
    for (size_t i = 0; i < m; ++i) r[i] = last_r[i] + alpha * (last_r[i] - older_r[i]);
    coulomb::project_on_cones(r, p.mu, p.nc);
    return true;
}

void SecantStart::record(const frix_problem &p, const SolveCache &versions, const double *r, bool converged) {
    const size_t m = 3 * (size_t)p.nc;
    if (!converged || contact_size(p) != 3 || !vec::all_finite(r, (int64_t)m)) {
        count_ = 0;
        return;
    }
    if (count_ > 0 && !same_setting(p, versions)) count_ = 0;
    if (count_ == 0) {
        setting_.kind = (int)p.kind;
        setting_.nc = p.nc;
        setting_.n = p.n;
        setting_.w_values = versions.w_values;
        setting_.w_pattern = versions.w_pattern;
        setting_.m_values = versions.m_values;
        setting_.h_values = versions.h_values;
        setting_.mu.assign(p.mu, p.mu + p.nc);
    }
    last_ = 1 - last_;
    Block blocks[2];
    const int count = blocks_of(p, blocks);
    std::vector<double> &data = data_[last_];
    data.resize(blocks[count - 1].offset + blocks[count - 1].size);
    for (int b = 0; b < count; ++b) std::copy(blocks[b].now, blocks[b].now + blocks[b].size, data.begin() + blocks[b].offset);
    r_[last_].assign(r, r + m);
    count_ = count_ < 2 ? count_ + 1 : 2;
}

}  // namespace frix
