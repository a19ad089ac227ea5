#include "secant_start.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "coulomb.hpp"
#include "problem.hpp"
#include "vec.hpp"

namespace frix {

namespace {

// The largest |step - alpha last step| / |step| of a block still on the line: rounding passes,
// a new direction of the load does not.
constexpr double kOffLine = 0.1;
// The farthest the secant is carried, in last steps: past it the line's extrapolation of the
// answers is a guess.
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
    // The caller continues from the last answer, or chose its own start.
    if (std::memcmp(r, r_.data(), sizeof(double) * m) != 0) return false;
    Block blocks[2];
    const int block_count = blocks_of(p, blocks);
    // Per block: this step (the data now less the last solve's), and its products with itself
    // and with the last step.
    double step_step[2], step_last[2], last_last[2];
    std::vector<double> step(data_.size());
    for (int b = 0; b < block_count; ++b) {
        const Block &k = blocks[b];
        for (size_t i = 0; i < k.size; ++i) step[k.offset + i] = k.now[i] - data_[k.offset + i];
        const double *s = step.data() + k.offset, *l = last_step_.data() + k.offset;
        step_step[b] = vec::dot(s, s, (int64_t)k.size);
        step_last[b] = vec::dot(s, l, (int64_t)k.size);
        last_last[b] = vec::dot(l, l, (int64_t)k.size);
    }
    // alpha: the least-squares multiple of the last step nearest to this one, on the block
    // whose last step was the largest for its size (a block that only kept still, or moved by
    // rounding, says nothing of the line).
    int widest = -1;
    double widest_share = 0.0;
    for (int b = 0; b < block_count; ++b) {
        const Block &k = blocks[b];
        const double size2 = vec::dot(data_.data() + k.offset, data_.data() + k.offset, (int64_t)k.size);
        const double share = last_last[b] > 0.0 ? last_last[b] / std::max(size2, last_last[b]) : 0.0;
        if (share > widest_share) widest = b, widest_share = share;
    }
    if (widest < 0) return false;
    const double alpha = step_last[widest] / last_last[widest];
    if (!(std::fabs(alpha) > 0.0 && std::fabs(alpha) <= kMaxSteps)) return false;
    // Every block's step alpha times its last one, to kOffLine of the step:
    // |s - alpha l|^2 = s.s - 2 alpha s.l + alpha^2 l.l.
    for (int b = 0; b < block_count; ++b) {
        const double off = step_step[b] - 2.0 * alpha * step_last[b] + alpha * alpha * last_last[b];
        if (!(off <= kOffLine * kOffLine * step_step[b])) return false;
    }
    for (size_t i = 0; i < m; ++i) r[i] = r_[i] + alpha * last_r_step_[i];
    coulomb::project_on_cones(r, p.mu, p.nc);
    return true;
}

void SecantStart::record(const frix_problem &p, const SolveCache &versions, const double *r, bool converged) {
    const size_t m = 3 * (size_t)p.nc;
    const int held = count_ > 0 && same_setting(p, versions) ? count_ : 0;
    count_ = 0;  // until the history is whole again (an allocation below may fail)
    if (!converged || contact_size(p) != 3 || !vec::all_finite(r, (int64_t)m)) return;
    if (held == 0) {
        setting_.kind = (int)p.kind;
        setting_.nc = p.nc;
        setting_.n = p.n;
        setting_.w_values = versions.w_values;
        setting_.w_pattern = versions.w_pattern;
        setting_.m_values = versions.m_values;
        setting_.h_values = versions.h_values;
        setting_.mu.assign(p.mu, p.mu + p.nc);
    }
    // (With no solve held, the steps below are of no use: the next record makes them.)
    Block blocks[2];
    const int block_count = blocks_of(p, blocks);
    const size_t size = blocks[block_count - 1].offset + blocks[block_count - 1].size;
    data_.resize(size);
    last_step_.resize(size);
    r_.resize(m);
    last_r_step_.resize(m);
    for (int b = 0; b < block_count; ++b)
        for (size_t i = 0; i < blocks[b].size; ++i) {
            const size_t at = blocks[b].offset + i;
            last_step_[at] = blocks[b].now[i] - data_[at];
            data_[at] = blocks[b].now[i];
        }
    for (size_t i = 0; i < m; ++i) {
        last_r_step_[i] = r[i] - r_[i];
        r_[i] = r[i];
    }
    count_ = std::min(held + 1, 2);
}

}  // namespace frix
