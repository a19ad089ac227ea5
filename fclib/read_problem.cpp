// frix_read_problem: FCLIB or Siconos text, told apart by the HDF5 signature.
#include <frix/frix.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>

#include "error_state.hpp"
#include "hdf5_file.hpp"

namespace {

struct FileCloser {
    void operator()(std::FILE *f) const { std::fclose(f); }
};

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
            hdf5 = frix::fclib::hdf5_signature_offset(file.get()) >= 0;
        }
        return hdf5 ? frix_fclib_read(path, out) : frix_dat_read(path, out);
    });
}
