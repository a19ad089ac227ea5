// FCLIB matrix groups ({nzmax, m, n, nz, p, i, x}), read into frix matrices and written
// from them.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "hdf5_reader.hpp"
#include "hdf5_writer.hpp"
#include "matrix.hpp"

namespace frix::fclib {

// The scalar fields of a matrix group. They are read first so that the caller can check
// m and n against the problem's vectors (whose extents the file really holds) before
// read_matrix builds anything sized from them.
struct MatrixHeader {
    std::string group;  // e.g. "/fclib_local/W"
    int64_t m = 0;      // rows
    int64_t n = 0;      // columns
    int64_t nz = 0;     // -1 CSC, -2 CSR, >= 0 triplets (that many entries)
    int64_t nzmax = 0;
};

MatrixHeader read_matrix_header(const FileReader &file, const std::string &group);

// Reads p, i, x in the storage nz selects, checks them (pointers, index ranges, finite
// values; FRIX_ERR_FORMAT naming the dataset) and builds the matrix, duplicates summed.
// Triplets follow the data, not fclib.h's comment: i holds row indices, p column indices.
std::unique_ptr<frix_matrix> read_matrix(const FileReader &file, const MatrixHeader &header);

// A matrix in the form frix writes: CSC with the 32-bit indices of libfclib's structs.
struct Csc32 {
    int32_t m = 0;
    int32_t n = 0;
    std::vector<int32_t> p;  // n + 1
    std::vector<int32_t> i;  // row indices, p[n]
    std::vector<double> x;   // p[n]
};

// FRIX_ERR_UNSUPPORTED if a size or index does not fit in int32 (`name` is for the message).
Csc32 to_csc32(const frix_matrix &A, const char *name);

void write_matrix(FileWriter &file, const std::string &group, const Csc32 &A);

}  // namespace frix::fclib
