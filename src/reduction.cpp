#include "reduction.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "disjoint_sets.hpp"
#include "monitor.hpp"

namespace frix {

namespace {

// Where W could take more than kStructureAbove, its structure is looked at for a tighter
// bound (forming W reserves that much address space).
constexpr double kStructureAbove = 256e6;

}  // namespace

frix_error to_csc(const frix_matrix &A, Csc &out) {
    out.rows = A.rows;
    out.cols = A.cols;
    int64_t nnz = 0;
    if (frix_error e = frix_matrix_to_csc(&A, &nnz, nullptr, nullptr, nullptr)) return e;
    out.colptr.resize(A.cols + 1);
    out.rowind.resize(std::max<int64_t>(nnz, 1));
    out.val.resize(std::max<int64_t>(nnz, 1));
    return frix_matrix_to_csc(&A, &nnz, out.colptr.data(), out.rowind.data(), out.val.data());
}

double relative_asymmetry(const Csc &M) {
    double amax = 0.0, skew = 0.0;
    for (double x : M.val) amax = std::max(amax, std::fabs(x));
    for (int64_t j = 0; j < M.cols; ++j)
        for (int64_t e = M.colptr[j]; e < M.colptr[j + 1]; ++e) {
            const int64_t i = M.rowind[e];
            // M(j, i) by binary search in column i.
            auto first = M.rowind.begin() + M.colptr[i], last = M.rowind.begin() + M.colptr[i + 1];
            auto it = std::lower_bound(first, last, j);
            const double mji = (it != last && *it == j) ? M.val[it - M.rowind.begin()] : 0.0;
            skew = std::max(skew, std::fabs(mji - M.val[e]));
        }
    return amax > 0.0 ? skew / amax : 0.0;
}

bool is_symmetric(const Csc &M) { return relative_asymmetry(M) <= 1e-12; }

ReductionSize reduction_size(const frix_problem &p) {
    ReductionSize size;
    DisjointSets components(p.n);
    // Exact zeros (of a stored 3x3 block) couple nothing.
    for_each_entry(*p.M, [&](int64_t i, int64_t j, double v) {
        if (v == 0.0) return;
        components.unite(i, j);
        size.input_entries += 1.0;
    });
    // (component, column of H) pairs, each counted once.
    std::vector<std::pair<int64_t, int64_t>> touches;
    if (p.nc > 0)
        for_each_entry(*p.H, [&](int64_t i, int64_t c, double v) {
            if (v != 0.0) touches.emplace_back(components.find(i), c);
        });
    size.input_entries += (double)touches.size();
    std::sort(touches.begin(), touches.end());
    touches.erase(std::unique(touches.begin(), touches.end()), touches.end());
    for (const auto &t : touches) size.product_entries += (double)components.size_of_root(t.first);
    for (int64_t i = 0; i < p.n; ++i)
        if (components.find(i) == i) size.largest_component = std::max(size.largest_component, components.size_of_root(i));
    // Per component, the columns and the contacts (3 columns each, in order) touching it.
    double bound = 0.0, block_bound = 0.0;
    for (size_t k = 0; k < touches.size();) {
        size_t end = k;
        double contacts = 0.0;
        for (int64_t last_contact = -1; end < touches.size() && touches[end].first == touches[k].first; ++end)
            if (touches[end].second / 3 != last_contact) last_contact = touches[end].second / 3, contacts += 1.0;
        const double columns = (double)(end - k);
        bound += columns * columns;
        block_bound += contacts * contacts;
        k = end;
    }
    const double full = 3.0 * (double)p.nc;
    size.w_entries = std::min(bound, full * full);
    size.w_blocks = std::min(block_bound, (double)p.nc * (double)p.nc);
    return size;
}

ReductionSize reduction_bound(const frix_problem &p) {
    // W has at most nc^2 blocks: the structure is looked at only where that much could be
    // worth it (above 1800 contacts or so; on rigid bodies W has far fewer).
    ReductionSize size;
    size.w_blocks = (double)p.nc * (double)p.nc;
    size.w_entries = 9.0 * size.w_blocks;
    if (kBytesPerReducedBlock * size.w_blocks >= kStructureAbove) size = reduction_size(p);
    return size;
}

ReductionMemory reduction_memory(const ReductionSize &size, const Monitor &monitor) {
    ReductionMemory m;
    m.needed = kBytesPerReducedBlock * size.w_blocks;
    m.fits = monitor.fits_memory(m.needed);
    if (!m.fits) m.available = monitor.memory_left();
    return m;
}

frix_error recover_velocity(const frix_problem &p, const MassSolver &ms, const double *r, double *v) {
    std::vector<double> b(p.f, p.f + p.n);
    if (p.nc > 0) matrix_gemv(*p.H, 1.0, r, 1.0, b.data());
    return ms.solve(b.data(), v);
}

}  // namespace frix
