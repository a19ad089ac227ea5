// A temporary file next to a target path, renamed over the target only when complete.
// The rename is atomic within a directory, so readers of the target see either the old
// file or the whole new one, and a failed write leaves the old file untouched.
#pragma once

#include <cstddef>
#include <string>

namespace frix::fclib {

class TempFile {
   public:
    // Creates `target` + ".tmp.XXXXXX" in the target's directory (FRIX_ERR_IO on failure,
    // e.g. when the directory does not exist or is not writable).
    explicit TempFile(const std::string &target);
    // Removes the temporary file unless commit() succeeded.
    ~TempFile();
    TempFile(const TempFile &) = delete;
    TempFile &operator=(const TempFile &) = delete;

    // Appends bytes (FRIX_ERR_IO on failure, e.g. a full disk).
    void write(const void *data, size_t size);

    // Syncs the completed temporary file to disk and renames it over the target
    // (FRIX_ERR_IO on failure; the temporary file is then removed by the destructor).
    void commit();

   private:
    std::string target_;
    std::string name_;
    int fd_ = -1;
    bool committed_ = false;
};

}  // namespace frix::fclib
