// frix_read_problem: FCLIB or Siconos text, told apart by the HDF5 signature.
#include <frix/frix.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>

#include "error_state.hpp"

namespace {

struct FileCloser {
    void operator()(std::FILE *f) const { std::fclose(f); }
};

// HDF5 puts its 8-byte signature at offset 0, or after a user block of 512, 1024, 2048, ...
// bytes; an FCLIB file may have been written with one.
bool has_hdf5_signature(std::FILE *file) {
    static const unsigned char kSignature[8] = {0x89, 'H', 'D', 'F', '\r', '\n', 0x1a, '\n'};
    for (long offset = 0; offset <= (1L << 30); offset = offset == 0 ? 512 : 2 * offset) {
        unsigned char head[8];
        if (std::fseek(file, offset, SEEK_SET) != 0 || std::fread(head, 1, 8, file) != 8) return false;
        if (std::memcmp(head, kSignature, 8) == 0) return true;
    }
    return false;
}

}  // namespace

extern "C" FRIX_API frix_error frix_read_problem(const char *path, frix_problem **out) {
    return frix::guard("frix_read_problem", [&]() -> frix_error {
        if (out == nullptr) return frix::fail(FRIX_ERR_INVALID_ARGUMENT, "frix_read_problem: out is NULL");
        *out = nullptr;
        if (path == nullptr) return frix::fail(FRIX_ERR_INVALID_ARGUMENT, "frix_read_problem: path is NULL");
        bool hdf5;
        {
            std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path, "rb"));
            if (!file)
                return frix::fail(FRIX_ERR_IO, "cannot open '%s': %s", path, std::strerror(errno));
            hdf5 = has_hdf5_signature(file.get());
        }
        return hdf5 ? frix_fclib_read(path, out) : frix_dat_read(path, out);
    });
}
