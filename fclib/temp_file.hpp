// A temporary file next to a target path, renamed over the target only when complete.
// The rename is atomic within a directory, so readers of the target see either the old
// file or the whole new one, and a failed write leaves the old file untouched.
// A target that is a symbolic link stands for the file it points to: the temporary file
// goes next to that file and replaces it, so the link stays a link.
#pragma once

#include <cstddef>
#include <string>

namespace frix::fclib {

class TempFile {
   public:
    // Creates `target` + ".tmp.XXXXXX" in the target's directory, `target` being the file
    // a symbolic link at that path resolves to. FRIX_ERR_IO on failure: the directory does
    // not exist or is not writable, or an existing target is not a regular file (a
    // directory, FIFO, device or socket) or is read-only; such a target is never opened.
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
    std::string target_;    // as given, for messages
    std::string resolved_;  // the file actually replaced (symbolic links followed)
    std::string name_;
    int fd_ = -1;
    bool committed_ = false;
};

}  // namespace frix::fclib
