// Typed writes into a new HDF5 file, in the encodings libfclib uses (so its reader and
// Siconos accept what frix writes): integers as little-endian int32 1-D arrays (scalars
// as 1-element arrays), reals as IEEE float64 1-D arrays, strings as scalar fixed-length
// NUL-terminated ASCII, exactly what H5LTmake_dataset_{int,double,string} produce.
//
// The file is built in memory (HDF5's core driver, no backing store) and handed over as a
// byte image that the caller writes to disk itself. HDF5 thus never meets a disk error: a
// failed write inside HDF5 leaves a file that cannot be closed and crashes the library at
// exit, while a failed write(2) is an ordinary error.
// Failures raise FRIX_ERR_IO naming the final path.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "hdf5_file.hpp"

namespace frix::fclib {

class FileWriter {
   public:
    // Starts an empty in-memory file; messages name `shown_path`. Arrays of kCompressFrom
    // entries or more are deflated at `deflate_level` (1..9; 0: none). Requires a live Session.
    FileWriter(const std::string &shown_path, int deflate_level);

    static constexpr int64_t kCompressFrom = 1024;
    static constexpr int kDefaultDeflateLevel = 4;

    // Names are absolute ("/fclib_local/W/p"); parents must have been created first.
    void create_group(const std::string &name);
    void write_int32s(const std::string &name, const std::vector<int32_t> &values);
    void write_int32_scalar(const std::string &name, int32_t value);
    void write_doubles(const std::string &name, const double *values, int64_t count);
    void write_text(const std::string &name, const std::string &text);

    // The complete file, as the bytes to store on disk.
    std::vector<unsigned char> image();

   private:
    void write_array(const std::string &name, hid_t filetype, hid_t memtype, const void *data,
                     int64_t count);
    [[noreturn]] void failed(const char *what, const std::string &name) const;

    std::string shown_path_;
    int deflate_level_;
    Handle file_;
};

}  // namespace frix::fclib
