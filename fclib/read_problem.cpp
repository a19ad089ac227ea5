// frix_read_problem: FCLIB or Siconos text, told apart by the HDF5 signature.
#include <frix/frix.h>

#include "error_state.hpp"
#include "hdf5_file.hpp"
#include "input_file.hpp"

extern "C" FRIX_API frix_error frix_read_problem(const char *path, frix_problem **out) {
    return frix::guard("frix_read_problem", [&]() -> frix_error {
        if (out == nullptr) return frix::fail(FRIX_ERR_INVALID_ARGUMENT, "frix_read_problem: out is NULL");
        *out = nullptr;
        if (path == nullptr) return frix::fail(FRIX_ERR_INVALID_ARGUMENT, "frix_read_problem: path is NULL");
        bool hdf5;
        {
            const frix::fclib::InputFile file = frix::fclib::open_regular_file(path);
            hdf5 = frix::fclib::hdf5_signature_offset(file.file.get()) >= 0;
        }
        return hdf5 ? frix_fclib_read(path, out) : frix_dat_read(path, out);
    });
}
