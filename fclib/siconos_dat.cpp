// frix_dat_read: the text problem format of Siconos (its test collection's .dat files).
//
// The layout, pinned down from the files themselves and checked bit for bit against their
// FCLIB conversions (tests/test_dat.c). Whitespace-separated numbers; line breaks carry no
// meaning:
//   local:   d nc  MATRIX(W, 3nc x 3nc)  q[3nc]  mu[nc]  [flag]
//   global:  d nc  MATRIX(M, n x n)  MATRIX(H, n x 3nc)  f[n]  w[3nc]  mu[nc]  [flag]
//   rolling: 5 nc  MATRIX(W, 5nc x 5nc)  q[5nc]  mu[nc]  mu_r[nc]   (local form only)
//   MATRIX:  storage size0 size1 BODY
//     storage 0 (dense):         size0 size1 again, then size0*size1 values column-major
//     storage 1 (sparse-block):  nbblocks nbrows nbcols  rowsizes[nbrows] colsizes[nbcols]
//                                (cumulative)  filled1 filled2  rowptr[filled1]
//                                blockcol[filled2], then per block, in storage order, its
//                                number and its rows*cols values column-major
// The optional final integer (0 or 1) appears in some files only and carries nothing frix
// needs. Local and global files are told apart by what follows the first matrix: exactly
// q and mu (and the flag) for a local problem; a global problem has H in between.
#include <frix/frix.h>

#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "error_state.hpp"
#include "fclib_error.hpp"
#include "problem.hpp"
#include "text_tokens.hpp"

namespace frix::fclib {

namespace {

constexpr int64_t kMaxSize = std::numeric_limits<int32_t>::max();

std::unique_ptr<frix_matrix> built(TextTokens &in, const std::string &name, frix_error err,
                                   frix_matrix *m) {
    std::unique_ptr<frix_matrix> out(m);
    if (err != FRIX_OK) raise_from_core(err, std::string("'") + in.path() + "': matrix " + name);
    return out;
}

std::unique_ptr<frix_matrix> read_dense(TextTokens &in, const std::string &name, int64_t rows,
                                        int64_t cols) {
    // Siconos writes the sizes of a dense matrix twice; the copies must agree.
    const std::string what = "the sizes of dense " + name + " (repeated)";
    in.integer(what.c_str(), rows, rows);
    in.integer(what.c_str(), cols, cols);
    const size_t count = static_cast<size_t>(rows) * static_cast<size_t>(cols);
    const std::string values = "dense " + name;
    in.require(count, values.c_str());
    std::vector<double> x(count);
    for (double &v : x) v = in.real(values.c_str());
    frix_matrix *m = nullptr;
    const frix_error err = frix_matrix_from_dense(rows, cols, x.data(), rows > 0 ? rows : 1, &m);
    return built(in, name, err, m);
}

// Cumulative block sizes: increasing, the last one the matrix size.
std::vector<int64_t> read_cumulative(TextTokens &in, const std::string &what, int64_t count,
                                     int64_t total) {
    in.require(static_cast<size_t>(count), what.c_str());
    std::vector<int64_t> sizes(static_cast<size_t>(count));
    int64_t previous = 0;
    for (int64_t &s : sizes) {
        s = in.integer(what.c_str(), previous + 1, total);
        previous = s;
    }
    if (count > 0 && previous != total)
        in.error(what + " end at " + std::to_string(previous) + ", not at the matrix size " +
                 std::to_string(total));
    return sizes;
}

std::unique_ptr<frix_matrix> read_sparse_block(TextTokens &in, const std::string &name,
                                               int64_t rows, int64_t cols) {
    const std::string sbm = "sparse-block " + name;
    const int64_t nblocks = in.integer((sbm + " block count").c_str(), 0, kMaxSize);
    const int64_t nbr = in.integer((sbm + " block rows").c_str(), 0, rows);
    const int64_t nbc = in.integer((sbm + " block columns").c_str(), 0, cols);
    const std::vector<int64_t> row_end = read_cumulative(in, sbm + " row block sizes", nbr, rows);
    const std::vector<int64_t> col_end = read_cumulative(in, sbm + " column block sizes", nbc, cols);
    const int64_t filled1 = in.integer((sbm + " filled1 (block rows + 1)").c_str(), 1, nbr + 1);
    const int64_t filled2 = in.integer((sbm + " filled2 (blocks)").c_str(), nblocks, nblocks);
    const std::string ptr_what = sbm + " block row pointers";
    in.require(static_cast<size_t>(filled1 + filled2), ptr_what.c_str());
    std::vector<int64_t> row_ptr(static_cast<size_t>(filled1));
    for (int64_t i = 0; i < filled1; ++i)
        row_ptr[i] = in.integer(ptr_what.c_str(), i == 0 ? 0 : row_ptr[i - 1], i == 0 ? 0 : filled2);
    if (row_ptr.back() != filled2)
        in.error(ptr_what + " end at " + std::to_string(row_ptr.back()) + ", not at the block count " +
                 std::to_string(filled2));
    std::vector<int64_t> block_col(static_cast<size_t>(filled2));
    for (int64_t &c : block_col) c = in.integer((sbm + " block column").c_str(), 0, nbc - 1);

    // Every entry of a stored block is kept, explicit zeros too, as Siconos stores them.
    std::vector<int64_t> r, c;
    std::vector<double> x;
    for (int64_t i = 0; i + 1 < filled1; ++i) {
        const int64_t r0 = i == 0 ? 0 : row_end[i - 1], nr = row_end[i] - r0;
        for (int64_t b = row_ptr[i]; b < row_ptr[i + 1]; ++b) {
            const int64_t j = block_col[b];
            const int64_t c0 = j == 0 ? 0 : col_end[j - 1], ncol = col_end[j] - c0;
            in.integer((sbm + " block number").c_str(), b, b);
            const std::string values = sbm + " block " + std::to_string(b);
            in.require(static_cast<size_t>(nr * ncol), values.c_str());
            for (int64_t jj = 0; jj < ncol; ++jj)
                for (int64_t ii = 0; ii < nr; ++ii) {
                    r.push_back(r0 + ii);
                    c.push_back(c0 + jj);
                    x.push_back(in.real(values.c_str()));
                }
        }
    }
    frix_matrix *m = nullptr;
    const frix_error err = frix_matrix_from_triplets(rows, cols, static_cast<int64_t>(x.size()),
                                                     r.data(), c.data(), x.data(), &m);
    return built(in, name, err, m);
}

// A matrix that must be rows x cols (-1: any).
std::unique_ptr<frix_matrix> read_matrix(TextTokens &in, const std::string &name, int64_t rows,
                                         int64_t cols) {
    const int64_t storage = in.integer(("storage type of " + name).c_str(), 0, 2);
    if (storage == 2)
        raise(FRIX_ERR_UNSUPPORTED,
              "'%s': matrix %s has storage type 2 (Siconos NM_SPARSE), which frix does not read; "
              "write it dense (0) or sparse-block (1), or convert the problem to FCLIB",
              in.path(), name.c_str());
    const std::string rows_what = "rows of " + name, cols_what = "columns of " + name;
    const int64_t m = in.integer(rows_what.c_str(), rows < 0 ? 0 : rows, rows < 0 ? kMaxSize : rows);
    const int64_t n = in.integer(cols_what.c_str(), cols < 0 ? 0 : cols, cols < 0 ? kMaxSize : cols);
    if (rows < 0 || cols < 0) {
        // W or M, whose sizes nothing read so far bounds, is square and no larger than the file
        // can back: storage grows with the size even without entries (16 bytes declaring a
        // 0 x 1.4e9 matrix made the fuzzer allocate 3.8 GB). Dense, its m^2 values must be
        // there; sparse-block, the vector that follows it (q or f, as many numbers as rows).
        if (m != n)
            in.error(name + " is " + std::to_string(m) + " x " + std::to_string(n) + ", not square");
        if (storage == 1) in.require(static_cast<size_t>(m), (name + " and the vector after it").c_str());
    }
    return storage == 0 ? read_dense(in, name, m, n) : read_sparse_block(in, name, m, n);
}

std::vector<double> read_vector(TextTokens &in, const char *name, int64_t n) {
    in.require(static_cast<size_t>(n), name);
    std::vector<double> v(static_cast<size_t>(n));
    for (double &x : v) x = in.real(name);
    return v;
}

void read_end(TextTokens &in) {
    if (in.remaining() == 1) in.integer("the final flag after mu", 0, 1);
    if (in.remaining() > 0)
        in.error(std::to_string(in.remaining()) + " numbers follow mu, where the file should end");
}

frix_problem *finish(TextTokens &in, frix_error err, frix_problem *raw) {
    std::unique_ptr<frix_problem, void (*)(frix_problem *)> problem(raw, frix_problem_free);
    if (err != FRIX_OK) raise_from_core(err, std::string("'") + in.path() + "'");
    return problem.release();
}

// Siconos's rolling-friction local problem (rollingFrictionContact_printInFile): dimension 5,
// the number of contacts, W, q, mu and mu_r, nothing after.
frix_problem *read_rolling_dat(TextTokens &in) {
    const int64_t nc = in.integer("the number of contacts", 0, kMaxSize / 5);
    std::unique_ptr<frix_matrix> W = read_matrix(in, "W", -1, -1);
    if (W->rows != 5 * nc)
        raise(FRIX_ERR_FORMAT, "'%s': W is %lld x %lld but %lld rolling contacts need %lld x %lld", in.path(),
              static_cast<long long>(W->rows), static_cast<long long>(W->cols), static_cast<long long>(nc),
              static_cast<long long>(5 * nc), static_cast<long long>(5 * nc));
    std::vector<double> q = read_vector(in, "q", 5 * nc);
    std::vector<double> mu = read_vector(in, "mu", nc);
    std::vector<double> mu_r = read_vector(in, "mu_r", nc);
    if (in.remaining() > 0)
        in.error(std::to_string(in.remaining()) + " numbers follow mu_r, where the file should end");
    frix_problem *raw = nullptr;
    const frix_error err =
        make_owned_rolling_local_problem(std::move(W), std::move(q), std::move(mu), std::move(mu_r), &raw);
    return finish(in, err, raw);
}

frix_problem *read_dat(const char *path) {
    TextTokens in(path);
    const int64_t d = in.integer("the dimension", 0, kMaxSize);
    if (d == 5) return read_rolling_dat(in);
    if (d != 3)
        raise(FRIX_ERR_UNSUPPORTED,
              "'%s': dimension %lld; frix solves 3D contact (dimension 3, or 5 with rolling friction)",
              path, static_cast<long long>(d));
    const int64_t nc = in.integer("the number of contacts", 0, kMaxSize / 3);
    std::unique_ptr<frix_matrix> first = read_matrix(in, "W or M", -1, -1);
    if (in.remaining() <= static_cast<size_t>(4 * nc + 1)) {
        if (first->rows != 3 * nc || first->cols != 3 * nc)
            raise(FRIX_ERR_FORMAT, "'%s': W is %lld x %lld but %lld contacts need %lld x %lld",
                  path, static_cast<long long>(first->rows), static_cast<long long>(first->cols),
                  static_cast<long long>(nc), static_cast<long long>(3 * nc),
                  static_cast<long long>(3 * nc));
        std::vector<double> q = read_vector(in, "q", 3 * nc);
        std::vector<double> mu = read_vector(in, "mu", nc);
        read_end(in);
        frix_problem *raw = nullptr;
        const frix_error err =
            make_owned_local_problem(std::move(first), std::move(q), std::move(mu), &raw);
        return finish(in, err, raw);
    }
    const int64_t n = first->rows;
    if (first->cols != n)
        raise(FRIX_ERR_FORMAT, "'%s': M is %lld x %lld, expected square", path,
              static_cast<long long>(n), static_cast<long long>(first->cols));
    std::unique_ptr<frix_matrix> H = read_matrix(in, "H", n, 3 * nc);
    std::vector<double> f = read_vector(in, "f (Siconos q)", n);
    std::vector<double> w = read_vector(in, "w (Siconos b)", 3 * nc);
    std::vector<double> mu = read_vector(in, "mu", nc);
    read_end(in);
    frix_problem *raw = nullptr;
    const frix_error err = make_owned_global_problem(std::move(first), std::move(H), std::move(f),
                                                     std::move(w), std::move(mu), &raw);
    return finish(in, err, raw);
}

}  // namespace

}  // namespace frix::fclib

extern "C" FRIX_API frix_error frix_dat_read(const char *path, frix_problem **out) {
    return frix::guard("frix_dat_read", [&]() -> frix_error {
        if (out == nullptr) return frix::fail(FRIX_ERR_INVALID_ARGUMENT, "frix_dat_read: out is NULL");
        *out = nullptr;
        if (path == nullptr) return frix::fail(FRIX_ERR_INVALID_ARGUMENT, "frix_dat_read: path is NULL");
        *out = frix::fclib::read_dat(path);
        return FRIX_OK;
    });
}
