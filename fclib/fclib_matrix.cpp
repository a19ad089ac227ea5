#include "fclib_matrix.hpp"

#include <cmath>
#include <cstdint>
#include <limits>

#include "fclib_error.hpp"
#include "matrix.hpp"

namespace frix::fclib {

namespace {

// Far above any real problem, far below where m + 1 or 3 * m could overflow.
constexpr int64_t kMaxDimension = int64_t{1} << 48;

using Index = std::vector<int64_t>;

void check_pointers(const FileReader &file, const std::string &name, const Index &p,
                    int64_t outer, const char *what) {
    if (static_cast<int64_t>(p.size()) != outer + 1)
        raise(FRIX_ERR_FORMAT, "'%s': dataset %s has %zu entries, expected %lld (%s + 1)",
              file.path(), name.c_str(), p.size(), static_cast<long long>(outer + 1), what);
    if (p[0] != 0)
        raise(FRIX_ERR_FORMAT, "'%s': dataset %s starts at %lld, expected 0", file.path(),
              name.c_str(), static_cast<long long>(p[0]));
    for (size_t k = 0; k + 1 < p.size(); ++k)
        if (p[k + 1] < p[k])
            raise(FRIX_ERR_FORMAT, "'%s': dataset %s decreases at entry %zu (%lld then %lld)",
                  file.path(), name.c_str(), k + 1, static_cast<long long>(p[k]),
                  static_cast<long long>(p[k + 1]));
}

void check_indices(const FileReader &file, const std::string &name, const Index &idx,
                   int64_t count, int64_t bound, const char *what) {
    for (int64_t k = 0; k < count; ++k)
        if (idx[k] < 0 || idx[k] >= bound)
            raise(FRIX_ERR_FORMAT, "'%s': dataset %s: entry %lld is %lld, outside the %lld %s",
                  file.path(), name.c_str(), static_cast<long long>(k),
                  static_cast<long long>(idx[k]), static_cast<long long>(bound), what);
}

// An index or value array holds the matrix's first nnz entries; it may be longer (up to the
// capacity nzmax, as real files store it), and then only those nnz entries are read. An
// array longer than the capacity the group declares is not a matrix frix reads.
void check_length(const FileReader &file, const MatrixHeader &h, const std::string &name,
                  int64_t nnz, const char *why) {
    const int64_t have = file.length(name);
    if (have < nnz)
        raise(FRIX_ERR_FORMAT, "'%s': dataset %s has %lld entries, expected at least %lld (%s)",
              file.path(), name.c_str(), static_cast<long long>(have), static_cast<long long>(nnz),
              why);
    if (have > h.nzmax)
        raise(FRIX_ERR_FORMAT, "'%s': dataset %s has %lld entries, more than nzmax %lld of %s",
              file.path(), name.c_str(), static_cast<long long>(have),
              static_cast<long long>(h.nzmax), h.group.c_str());
}

void check_values(const FileReader &file, const std::string &name, const std::vector<double> &x,
                  int64_t count) {
    for (int64_t k = 0; k < count; ++k)
        if (!std::isfinite(x[k]))
            raise(FRIX_ERR_FORMAT, "'%s': dataset %s: entry %lld is %g", file.path(),
                  name.c_str(), static_cast<long long>(k), x[k]);
}

}  // namespace

MatrixHeader read_matrix_header(const FileReader &file, const std::string &group) {
    if (!file.is_group(group))
        raise(FRIX_ERR_FORMAT, "'%s': group %s is missing", file.path(), group.c_str());
    MatrixHeader h;
    h.group = group;
    h.m = file.read_int_scalar(group + "/m");
    h.n = file.read_int_scalar(group + "/n");
    h.nz = file.read_int_scalar(group + "/nz");
    h.nzmax = file.read_int_scalar(group + "/nzmax");
    if (h.m < 0 || h.m > kMaxDimension || h.n < 0 || h.n > kMaxDimension)
        raise(FRIX_ERR_FORMAT, "'%s': %s has invalid dimensions %lld x %lld (datasets m, n)",
              file.path(), group.c_str(), static_cast<long long>(h.m),
              static_cast<long long>(h.n));
    if (h.nz < -2)
        raise(FRIX_ERR_FORMAT,
              "'%s': dataset %s/nz is %lld: not a storage FCLIB defines (-1 CSC, -2 CSR, "
              ">= 0 triplets)",
              file.path(), group.c_str(), static_cast<long long>(h.nz));
    if (h.nzmax < 0)
        raise(FRIX_ERR_FORMAT, "'%s': dataset %s/nzmax is %lld", file.path(), group.c_str(),
              static_cast<long long>(h.nzmax));
    return h;
}

std::unique_ptr<frix_matrix> read_matrix(const FileReader &file, const MatrixHeader &h) {
    const std::string p_name = h.group + "/p", i_name = h.group + "/i", x_name = h.group + "/x";
    frix_matrix *raw = nullptr;
    frix_error err = FRIX_OK;

    if (h.nz < 0) {
        const bool csc = h.nz == -1;
        const int64_t outer = csc ? h.n : h.m;
        const int64_t inner = csc ? h.m : h.n;
        // The length is checked before reading so a wrong p is refused without being loaded.
        const int64_t p_length = file.length(p_name);
        if (p_length != outer + 1)
            raise(FRIX_ERR_FORMAT, "'%s': dataset %s has %lld entries, expected %lld (%s + 1)",
                  file.path(), p_name.c_str(), static_cast<long long>(p_length),
                  static_cast<long long>(outer + 1), csc ? "columns" : "rows");
        Index p = file.read_ints(p_name);
        check_pointers(file, p_name, p, outer, csc ? "columns" : "rows");
        const int64_t nnz = p[static_cast<size_t>(outer)];
        if (nnz > h.nzmax)
            raise(FRIX_ERR_FORMAT, "'%s': %s holds %lld entries (last of p) but nzmax is %lld",
                  file.path(), h.group.c_str(), static_cast<long long>(nnz),
                  static_cast<long long>(h.nzmax));
        check_length(file, h, i_name, nnz, "last entry of p");
        check_length(file, h, x_name, nnz, "last entry of p");
        Index idx = file.read_first_ints(i_name, nnz);
        std::vector<double> x = file.read_first_doubles(x_name, nnz);
        check_indices(file, i_name, idx, nnz, inner, csc ? "rows" : "columns");
        check_values(file, x_name, x, nnz);
        // By columns, the arrays just read become the matrix's where it keeps them as stored.
        err = csc ? frix::matrix_from_csc_taking(h.m, h.n, p, idx, x, &raw)
                  : frix_matrix_from_csr(h.m, h.n, p.data(), idx.data(), x.data(), &raw);
    } else {
        const int64_t nnz = h.nz;
        // Real files store nz entries with nzmax >= nz (Box_Stacks H: 485 of 744); only the
        // first nz of each array are entries.
        if (nnz > h.nzmax)
            raise(FRIX_ERR_FORMAT, "'%s': %s holds %lld triplets (nz) but nzmax is %lld",
                  file.path(), h.group.c_str(), static_cast<long long>(nnz),
                  static_cast<long long>(h.nzmax));
        check_length(file, h, i_name, nnz, "the triplet count nz");
        check_length(file, h, p_name, nnz, "the triplet count nz");
        check_length(file, h, x_name, nnz, "the triplet count nz");
        const Index rows = file.read_first_ints(i_name, nnz);
        const Index cols = file.read_first_ints(p_name, nnz);
        const std::vector<double> x = file.read_first_doubles(x_name, nnz);
        check_indices(file, i_name, rows, nnz, h.m, "rows");
        check_indices(file, p_name, cols, nnz, h.n, "columns");
        check_values(file, x_name, x, nnz);
        err = frix_matrix_from_triplets(h.m, h.n, nnz, rows.data(), cols.data(), x.data(), &raw);
    }
    std::unique_ptr<frix_matrix> matrix(raw);
    if (err != FRIX_OK)
        raise_from_core(err, std::string("'") + file.path() + "': matrix " + h.group);
    return matrix;
}

Csc32 to_csc32(const frix_matrix &A, const char *name) {
    constexpr int64_t kMax = std::numeric_limits<int32_t>::max();
    const int64_t rows = frix_matrix_rows(&A), cols = frix_matrix_cols(&A);
    int64_t nnz = 0;
    frix_error err = frix_matrix_to_csc(&A, &nnz, nullptr, nullptr, nullptr);
    if (err != FRIX_OK) reraise(err, std::string("exporting ") + name);
    if (rows > kMax || cols > kMax || nnz > kMax)
        raise(FRIX_ERR_UNSUPPORTED,
              "%s is %lld x %lld with %lld entries: FCLIB files store 32-bit indices (at most "
              "%lld)",
              name, static_cast<long long>(rows), static_cast<long long>(cols),
              static_cast<long long>(nnz), static_cast<long long>(kMax));
    std::vector<int64_t> p(static_cast<size_t>(cols) + 1), i(static_cast<size_t>(nnz));
    Csc32 out;
    out.x.resize(static_cast<size_t>(nnz));
    err = frix_matrix_to_csc(&A, &nnz, p.data(), i.data(), out.x.data());
    if (err != FRIX_OK) reraise(err, std::string("exporting ") + name);
    out.m = static_cast<int32_t>(rows);
    out.n = static_cast<int32_t>(cols);
    out.p.reserve(p.size());
    for (int64_t v : p) out.p.push_back(static_cast<int32_t>(v));
    out.i.reserve(i.size());
    for (int64_t v : i) out.i.push_back(static_cast<int32_t>(v));
    return out;
}

void write_matrix(FileWriter &file, const std::string &group, const Csc32 &A) {
    const int32_t nnz = A.p.empty() ? 0 : A.p.back();
    file.create_group(group);
    file.write_int32_scalar(group + "/nzmax", nnz);
    file.write_int32_scalar(group + "/m", A.m);
    file.write_int32_scalar(group + "/n", A.n);
    file.write_int32_scalar(group + "/nz", -1);
    file.write_int32s(group + "/p", A.p);
    file.write_int32s(group + "/i", A.i);
    file.write_doubles(group + "/x", A.x.data(), static_cast<int64_t>(A.x.size()));
}

}  // namespace frix::fclib
