// SingleSupernodalFactor: solves with a single-precision copy of a supernodal Cholesky factor.
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "linalg.hpp"

extern "C" {
void strsv_(const char *uplo, const char *trans, const char *diag, const int *n, const float *a, const int *lda,
            float *x, const int *incx, size_t, size_t, size_t);
void sgemv_(const char *trans, const int *m, const int *n, const float *alpha, const float *a, const int *lda,
            const float *x, const int *incx, const float *beta, float *y, const int *incy, size_t);
}

namespace frix::linalg {

namespace {

// Supernodes of up to this many entries are solved by plain loops: below it a BLAS call costs
// more than the supernode's work (most supernodes of a 3D body's factor hold a few columns).
constexpr int64_t kLoopEntries = 256;
// Powers of two up to which a scaling multiplies by 2^k (a normal double, exact) rather than
// calling ldexp on every entry.
constexpr int kPlainPowers = 1000;

// v -> v 2^k, exact where v 2^k is a normal double.
class PowerOfTwo {
   public:
    explicit PowerOfTwo(int k) : k_(k), by_(std::abs(k) <= kPlainPowers ? std::ldexp(1.0, k) : 0.0) {}
    double operator()(double v) const { return by_ != 0.0 ? v * by_ : std::ldexp(v, k_); }

   private:
    int k_;
    double by_;  // 2^k, or 0 where it is not a normal double
};

}  // namespace

bool SingleSupernodalFactor::copy(const SupernodalLayout &L, const FactorBudget &budget) {
    clear();
    int64_t tallest = 0;  // rows of the tallest supernode: the workspace of its rows below
    for (int64_t s = 0; s < L.nsuper; ++s) tallest = std::max(tallest, L.pi[s + 1] - L.pi[s]);
    const double bytes = 4.0 * ((double)L.value_count + (double)L.n + (double)tallest);
    if (budget && budget(FactorPrice{0.0, NAN, bytes}) != FRIX_STATUS_NOT_RUN) return false;
    double largest = 0.0;
    for (int64_t e = 0; e < L.value_count; ++e) largest = std::max(largest, std::fabs(L.values[e]));
    if (!(largest > 0.0) || !std::isfinite(largest)) return false;
    const int exponent = -std::ilogb(largest);  // the largest value scaled into [1, 2)
    values_.resize(L.value_count);
    const PowerOfTwo scaled(exponent);
    for (int64_t e = 0; e < L.value_count; ++e) values_[e] = (float)scaled(L.values[e]);
    // The diagonal divides every solve: each entry must stay a normal float.
    for (int64_t s = 0; s < L.nsuper; ++s) {
        const int64_t nc = L.super[s + 1] - L.super[s], nr = L.pi[s + 1] - L.pi[s];
        for (int64_t j = 0; j < nc; ++j)
            if (!(std::fabs(values_[L.px[s] + j + j * nr]) >= std::numeric_limits<float>::min())) {
                clear();
                return false;
            }
    }
    exponent_ = exponent;
    work_.assign(L.n + tallest, 0.0f);
    return true;
}

void SingleSupernodalFactor::clear() {
    std::vector<float>().swap(values_);
    std::vector<float>().swap(work_);
    exponent_ = 0;
}

// L y = P b, then L^T z = y, x = P^T z, supernode by supernode: the diagonal block's triangular
// solve, and the rows below it updated (forward) or read (backward) through a gathered vector.
void SingleSupernodalFactor::solve(const SupernodalLayout &L, const double *b, double *x) const {
    const int64_t n = L.n;
    float *y = work_.data(), *t = y + n;
    double largest = 0.0;
    for (int64_t i = 0; i < n; ++i) largest = std::max(largest, std::fabs(b[i]));
    if (!(largest > 0.0)) {
        std::fill(x, x + n, 0.0);
        return;
    }
    // b scaled into [1, 2) at its largest; A = 2^(-2 e) (L~ L~^T) for the copy L~ = 2^e L.
    const int scale = -std::ilogb(largest);
    const PowerOfTwo in(scale), out(2 * exponent_ - scale);
    for (int64_t i = 0; i < n; ++i) y[i] = (float)in(b[L.perm[i]]);
    const int one = 1;
    const float plus = 1.0f, minus = -1.0f, zero = 0.0f;
    for (int64_t s = 0; s < L.nsuper; ++s) {
        const int64_t k = L.super[s], nc = L.super[s + 1] - k, nr = L.pi[s + 1] - L.pi[s], nb = nr - nc;
        const float *a = values_.data() + L.px[s];  // nr x nc, column-major
        const int64_t *below = L.rows + L.pi[s] + nc;
        float *ys = y + k;
        if (nc * nr <= kLoopEntries) {
            for (int64_t j = 0; j < nc; ++j) {
                const float yj = ys[j] / a[j + j * nr];
                ys[j] = yj;
                for (int64_t i = j + 1; i < nc; ++i) ys[i] -= a[i + j * nr] * yj;
                for (int64_t i = 0; i < nb; ++i) y[below[i]] -= a[nc + i + j * nr] * yj;
            }
            continue;
        }
        const int cols = (int)nc, ld = (int)nr, rows = (int)nb;
        strsv_("L", "N", "N", &cols, a, &ld, ys, &one, 1, 1, 1);
        if (nb == 0) continue;
        sgemv_("N", &rows, &cols, &plus, a + nc, &ld, ys, &one, &zero, t, &one, 1);
        for (int64_t i = 0; i < nb; ++i) y[below[i]] -= t[i];
    }
    for (int64_t s = L.nsuper - 1; s >= 0; --s) {
        const int64_t k = L.super[s], nc = L.super[s + 1] - k, nr = L.pi[s + 1] - L.pi[s], nb = nr - nc;
        const float *a = values_.data() + L.px[s];
        const int64_t *below = L.rows + L.pi[s] + nc;
        float *ys = y + k;
        if (nc * nr <= kLoopEntries) {
            for (int64_t j = nc - 1; j >= 0; --j) {
                float acc = ys[j];
                for (int64_t i = 0; i < nb; ++i) acc -= a[nc + i + j * nr] * y[below[i]];
                for (int64_t i = j + 1; i < nc; ++i) acc -= a[i + j * nr] * ys[i];
                ys[j] = acc / a[j + j * nr];
            }
            continue;
        }
        const int cols = (int)nc, ld = (int)nr, rows = (int)nb;
        if (nb > 0) {
            for (int64_t i = 0; i < nb; ++i) t[i] = y[below[i]];
            sgemv_("T", &rows, &cols, &minus, a + nc, &ld, t, &one, &plus, ys, &one, 1);
        }
        strsv_("L", "T", "N", &cols, a, &ld, ys, &one, 1, 1, 1);
    }
    for (int64_t i = 0; i < n; ++i) x[L.perm[i]] = out((double)y[i]);
}

}  // namespace frix::linalg
