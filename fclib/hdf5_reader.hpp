// Typed reads from an HDF5 file opened read-only. Every dataset is opened, its rank, type
// class and extent checked, and only then read (converted by HDF5 to the native type asked
// for, so int32 and int64 files read alike). Failures raise FRIX_ERR_IO when HDF5 cannot
// read and FRIX_ERR_FORMAT when the content is not what FCLIB prescribes; messages name the
// file and the dataset.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "hdf5_file.hpp"

namespace frix::fclib {

class FileReader {
   public:
    // Opens `path` read-only (FRIX_ERR_IO if it is missing, unreadable or not HDF5).
    // Requires a live Session.
    explicit FileReader(const char *path);

    const char *path() const { return path_.c_str(); }

    // Whether every component of the absolute link name exists.
    bool exists(const std::string &name) const;
    bool is_group(const std::string &name) const;
    // Links in a group (its members).
    int64_t link_count(const std::string &group) const;

    // Entries of a 1-D (or scalar) numeric dataset, without reading it.
    int64_t length(const std::string &name) const;
    // A 1-element integer dataset (FCLIB stores its scalars as shape (1,) arrays).
    int64_t read_int_scalar(const std::string &name) const;
    // The whole dataset, however many entries it holds.
    std::vector<int64_t> read_ints(const std::string &name) const;
    std::vector<double> read_doubles(const std::string &name) const;
    // Exactly `expected` finite values; `expected_from` says where that size comes from,
    // for the message ("rows of /fclib_local/W").
    std::vector<double> read_vector(const std::string &name, int64_t expected,
                                    const char *expected_from) const;
    // A string dataset, fixed or variable length, as raw bytes up to the first NUL.
    std::string read_text(const std::string &name) const;

   private:
    struct Dataset;
    Dataset open_dataset(const std::string &name) const;
    template <class T>
    std::vector<T> read_numeric(const std::string &name, hid_t memtype, bool integer) const;

    std::string path_;
    Handle file_;
};

}  // namespace frix::fclib
