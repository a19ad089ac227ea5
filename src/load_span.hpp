// The loads a factorised M has been solved for, and their answers, so that a load that is a
// combination of them is answered without a solve. A host stepping along a load path (loads
// that combine a few: a prescribed displacement and a force, each scaled) then solves with M
// once a step (for v) instead of twice (for q as well).
#pragma once

#include <cstdint>
#include <vector>

#include "linalg/linalg.hpp"

namespace frix {

// At most this many loads are kept (an orthonormal basis of their span, and each one's answer).
constexpr int kLoadSpan = 4;

class LoadSpan {
   public:
    // Forgets every load (M changed, or an allocation failed midway).
    void clear();
    // x = M^-1 f as the combination x = sum c_i x_i of the kept answers (x_i = M^-1 f_i, M the
    // matrix they were solved with), where f lies in the kept loads' span to round-off and the
    // combination is as accurate as a solve: its normwise backward error
    // |f - M x| / (|M| |x| + |f|) (max norms) within a few times that of the kept solves it
    // combines. A load off the span, or a combination that cancels large terms
    // (sum |c_i| |f_i| far above |f|), is not tried: that test costs a few products of n
    // values, the backward error a product with M. False: x is untouched, and the caller
    // solves. f and x: n values each, distinct arrays. May throw std::bad_alloc (then clear()).
    bool answer(const double *f, const linalg::CscView &M, double *x);
    // After a solve x = M^-1 f (distinct arrays): f joins the span where it adds a direction
    // (its part off the span at least kNewDirection of |f|), the span starting over from f
    // where kLoadSpan are kept; a load in the span (whose combination was not taken: far along
    // a line the kept loads span it only near its start) replaces the oldest where the others
    // and it still span as much, so that combinations stay short. An answer that is not
    // finite is not kept. May throw std::bad_alloc (then clear()).
    void add(const double *f, const double *x, int64_t n);
    int loads() const { return k_; }

   private:
    double backward_error(const double *f, const double *x, const linalg::CscView &M);
    // y minus its part on Q's first `count` columns (Gram-Schmidt twice), the coefficients of
    // that part into h (kLoadSpan values, zero past count); returns the rest's 2-norm.
    double take_off_span(int count, double *y, double *h) const;
    // Column i of Q and R from load i and the columns before it (Gram-Schmidt twice); false
    // where the load adds no direction to them (Q and R then hold i columns).
    bool orthonormalise(int i);
    // The kept loads' pair i forgotten (the later ones move down), Q and R taken anew.
    void forget(int i);
    int64_t n_ = 0;
    int k_ = 0;
    // The kept loads F (k_ columns of n_) and their answers X; F = Q R to round-off (Q: k_
    // orthonormal columns; R upper triangular, column-major kLoadSpan x kLoadSpan); each
    // solve's backward error (NaN until measured, at the first combination that uses it).
    std::vector<double> f_, x_, q_, backward_;
    double r_[kLoadSpan * kLoadSpan] = {};
    double m_norm_ = -1.0;  // |M|_inf, measured with the first backward error (-1: not yet)
    std::vector<double> work_, product_;
};

}  // namespace frix
