// analyze_symmetric (ordering.hpp): CHOLMOD's default choice between AMD and METIS, with METIS
// run on the graph of column groups.
#include "ordering.hpp"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace frix::linalg {

namespace {

// CHOLMOD's test for trying nested dissection after AMD (its default strategy): AMD's factor
// does at least this many flops per entry, and has at least this many entries per entry of A's
// triangle.
constexpr double kNestedFlopsPerEntry = 500.0, kNestedFill = 5.0;

// METIS costs 0.3-1.1 us per vertex and entry (item) of the graph it orders. Where AMD's
// factorisation does fewer flops than this many per item of the groups' graph, METIS cost
// more than it saved in a factorisation and the solves of a one-shot ADMM, and AMD's ordering
// is kept; a little above, it pays over repeated factorisations or many solves
// (notes/2026-11-30-amd-where-metis-costs-more.md).
constexpr double kNestedFlopsPerGraphItem = 3e4;

// Two consecutive columns join one group when they share at least this part of the union of
// their patterns: the dofs of one mesh node share most of their neighbourhood (exact zeros of
// the element matrices aside), neighbouring nodes less (notes/2026-11-28-fem-setup.md). A
// group too coarse or too fine costs fill, never correctness.
constexpr double kGroupOverlap = 2.0 / 3.0;

int64_t common_entries(const int64_t *a, const int64_t *a_end, const int64_t *b, const int64_t *b_end) {
    int64_t common = 0;
    while (a < a_end && b < b_end) {
        if (*a == *b) ++common, ++a, ++b;
        else if (*a < *b) ++a;
        else ++b;
    }
    return common;
}

// Groups of consecutive columns of A: group[j], and the first column of each group (with n at
// the end). Each column is compared with its group's first one (no chains of near matches).
void column_groups(const cholmod_sparse &A, std::vector<int64_t> &group, std::vector<int64_t> &first) {
    const int64_t n = (int64_t)A.ncol;
    const int64_t *p = static_cast<const int64_t *>(A.p), *i = static_cast<const int64_t *>(A.i);
    group.assign((size_t)n, 0);
    first.clear();
    for (int64_t j = 0; j < n; ++j) {
        bool join = false;
        if (!first.empty()) {
            const int64_t f = first.back();
            const double common = (double)common_entries(i + p[f], i + p[f + 1], i + p[j], i + p[j + 1]);
            const double together = (double)(p[f + 1] - p[f] + p[j + 1] - p[j]) - common;
            join = common >= kGroupOverlap * together;
        }
        if (!join) first.push_back(j);
        group[(size_t)j] = (int64_t)first.size() - 1;
    }
    first.push_back(n);
}

// The graph of A's column groups (an edge where A couples two of their columns, from A's upper
// triangle), in CSC: upper triangle, rows sorted.
struct GroupGraph {
    std::vector<int64_t> group, first;  // column_groups
    std::vector<int64_t> p, i;
    int64_t groups() const { return (int64_t)first.size() - 1; }
    double items() const { return (double)groups() + (double)i.size(); }  // vertices and entries
};

void group_graph(const cholmod_sparse &A, GroupGraph &g) {
    const int64_t *p = static_cast<const int64_t *>(A.p), *i = static_cast<const int64_t *>(A.i);
    column_groups(A, g.group, g.first);
    const int64_t ng = g.groups();
    // Group k's column holds the earlier groups its columns meet in A's upper triangle (groups
    // are consecutive, so an entry i <= j lands at or above the diagonal).
    std::vector<int64_t> mark((size_t)ng, -1);
    g.p.assign((size_t)ng + 1, 0);
    g.i.clear();
    for (int64_t k = 0; k < ng; ++k) {
        const size_t start = g.i.size();
        for (int64_t j = g.first[(size_t)k]; j < g.first[(size_t)k + 1]; ++j)
            for (int64_t e = p[j]; e < p[j + 1] && i[e] <= j; ++e) {
                const int64_t h = g.group[(size_t)i[e]];
                if (mark[(size_t)h] != k) mark[(size_t)h] = k, g.i.push_back(h);
            }
        std::sort(g.i.begin() + (std::ptrdiff_t)start, g.i.end());
        g.p[(size_t)k + 1] = (int64_t)g.i.size();
    }
}

// A METIS ordering of A's columns: METIS on the groups' graph, each group's columns then in
// their order. False where METIS fails (c.status says why).
bool group_nested_dissection(const cholmod_sparse &A, const GroupGraph &g, cholmod_common &c,
                             std::vector<int64_t> &perm) {
    const int64_t ng = g.groups(), none = 0;
    cholmod_sparse G = view_of({ng, ng, g.p.data(), g.i.empty() ? &none : g.i.data(), nullptr}, 1);
    G.nzmax = std::max<size_t>(G.nzmax, 1);  // CHOLMOD wants storage for one entry at least
    std::vector<int64_t> order((size_t)ng);
    if (!cholmod_l_metis(&G, nullptr, 0, 0, order.data(), &c) || c.status != CHOLMOD_OK) return false;
    perm.clear();
    perm.reserve(A.ncol);
    for (int64_t k : order)
        for (int64_t j = g.first[(size_t)k]; j < g.first[(size_t)k + 1]; ++j) perm.push_back(j);
    return true;
}

// Entries of A's upper triangle (CHOLMOD's anz).
double upper_entries(const cholmod_sparse &A) {
    const int64_t *p = static_cast<const int64_t *>(A.p), *i = static_cast<const int64_t *>(A.i);
    double count = 0.0;
    for (int64_t j = 0; j < (int64_t)A.ncol; ++j)
        for (int64_t e = p[j]; e < p[j + 1] && i[e] <= j; ++e) count += 1.0;
    return count;
}

}  // namespace

cholmod_sparse view_of(const CscView &A, int stype) {
    cholmod_sparse s{};
    s.nrow = (size_t)A.rows;
    s.ncol = (size_t)A.cols;
    s.nzmax = (size_t)A.nnz();
    s.p = const_cast<int64_t *>(A.colptr);
    s.i = const_cast<int64_t *>(A.rowind);
    s.nz = nullptr;
    s.x = const_cast<double *>(A.values);
    s.z = nullptr;
    s.stype = stype;
    s.itype = CHOLMOD_LONG;
    s.xtype = A.values ? CHOLMOD_REAL : CHOLMOD_PATTERN;
    s.dtype = CHOLMOD_DOUBLE;
    s.sorted = 1;
    s.packed = 1;
    return s;
}

cholmod_factor *analyze_symmetric(cholmod_sparse &a, cholmod_common &c, Orderings orderings) {
    const int nmethods = c.nmethods, ordering = c.method[0].ordering;
    c.nmethods = 1;
    c.method[0].ordering = CHOLMOD_AMD;
    cholmod_factor *L = cholmod_l_analyze(&a, &c);
    const double fl = c.fl, lnz = c.lnz;
    bool nested = L && orderings == Orderings::kAmdOrNested && fl >= kNestedFlopsPerEntry * lnz &&
                  lnz >= kNestedFill * upper_entries(a);
    GroupGraph g;
    if (nested) {
        group_graph(a, g);
        nested = fl >= kNestedFlopsPerGraphItem * g.items();
    }
    if (nested) {
        std::vector<int64_t> perm;
        if (group_nested_dissection(a, g, c, perm)) {
            c.method[0].ordering = CHOLMOD_GIVEN;
            cholmod_factor *nd = cholmod_l_analyze_p(&a, perm.data(), nullptr, 0, &c);
            // CHOLMOD's rule between orderings: the fewer entries of L.
            if (nd && c.lnz < lnz) {
                cholmod_l_free_factor(&L, &c);
                L = nd;
            } else {
                if (nd) cholmod_l_free_factor(&nd, &c);
                c.fl = fl;
                c.lnz = lnz;
            }
        }
        c.status = CHOLMOD_OK;  // a METIS that failed leaves AMD's analysis, as CHOLMOD does
    }
    c.nmethods = nmethods;
    c.method[0].ordering = ordering;
    return L;
}

}  // namespace frix::linalg
