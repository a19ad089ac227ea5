// Typed reads from an HDF5 file opened read-only. Every dataset is opened, its rank, type
// class and extent checked, and only then read (converted by HDF5 to the native type asked
// for, so int32 and int64 files read alike). Failures raise FRIX_ERR_IO when HDF5 cannot
// read and FRIX_ERR_FORMAT when the content is not what FCLIB prescribes; messages name the
// file and the dataset.
//
// Nothing in the file is trusted: only hard links, and soft links to objects of the same
// file, are followed (external and user-defined links are refused, as are datasets whose
// data lives in other files: external raw storage, virtual datasets); every buffer is
// sized from a dataset only after its declared size and its chunks are checked against the
// file's size, and all buffers of one reader together stay within a bound set by that size.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "hdf5_file.hpp"

namespace frix::fclib {

// How a dataset that exists but was never written reads. Problem data must have been
// written; the vectors of /solution and /guesses keep HDF5's fill value (zeros), because
// the files of the FCLIB collection store the parts of a solution they lack that way.
enum class Unwritten { refuse, read_fill };

class FileReader {
   public:
    // Opens `path` read-only (FRIX_ERR_IO if it is missing, unreadable, not a regular file
    // or not HDF5). Requires a live Session.
    explicit FileReader(const char *path);

    const char *path() const { return path_.c_str(); }

    // Whether every component of the absolute link name exists. A link on the way that
    // frix does not follow raises FRIX_ERR_FORMAT naming it.
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
    // The first `count` entries (the dataset must hold at least that many): matrix arrays
    // may be longer than the entries they hold, and only those are read.
    std::vector<int64_t> read_first_ints(const std::string &name, int64_t count) const;
    std::vector<double> read_first_doubles(const std::string &name, int64_t count) const;
    // Exactly `expected` finite values; `expected_from` says where that size comes from,
    // for the message ("rows of /fclib_local/W").
    std::vector<double> read_vector(const std::string &name, int64_t expected,
                                    const char *expected_from,
                                    Unwritten unwritten = Unwritten::refuse) const;
    // A string dataset, fixed or variable length, as raw bytes up to the first NUL; one
    // longer than max_bytes is refused (a fixed-length one by its type, before it is read).
    std::string read_text(const std::string &name, size_t max_bytes) const;

   private:
    struct Dataset;
    Dataset open_dataset(const std::string &name) const;
    template <class T>
    std::vector<T> read_numeric(const std::string &name, hid_t memtype, bool integer,
                                int64_t count, Unwritten unwritten) const;
    bool walk_links(const std::string &name, int depth) const;
    void check_link(const std::string &name, int depth) const;
    void check_written(const Dataset &d, const std::string &name, Unwritten unwritten) const;
    bool all_chunks_written(const Dataset &d) const;
    void charge(const std::string &name, double bytes) const;

    std::string path_;
    uint64_t file_size_ = 0;
    // What this reader may allocate for the file's data in all: 64 times the file's size
    // plus 64 MiB. Declared sizes and chunks above it are refused before anything is read.
    double allocation_limit_ = 0;
    // Bytes allocated so far for datasets; reads are accounting, not changes of the file.
    mutable double allocated_ = 0;
    Handle links_;    // link access: external links fail to traverse
    Handle access_;   // dataset access: the same, and no path to external or virtual sources
    Handle file_;
};

}  // namespace frix::fclib
