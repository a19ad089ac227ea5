// Opening a file named by the caller for reading, only if it is a regular file: a FIFO
// would block the reader forever, a device would feed it endless or side-effecting input,
// and neither has a size to bound allocations by.
#pragma once

#include <sys/stat.h>

#include <cstdint>
#include <cstdio>
#include <memory>

namespace frix::fclib {

struct FileCloser {
    void operator()(std::FILE *f) const { std::fclose(f); }
};
using FilePtr = std::unique_ptr<std::FILE, FileCloser>;

// "a directory", "a FIFO", ... for messages about what a path is instead of a regular file.
const char *file_kind(mode_t mode);

struct InputFile {
    FilePtr file;
    uint64_t size = 0;  // bytes on disk when opened
    dev_t device = 0;   // with inode: which file was checked, to recognise it when reopened
    ino_t inode = 0;
};

// Opens `path` for binary reading. FRIX_ERR_IO naming it when it is missing, unreadable or
// not a regular file. Never blocks: the type is checked with stat() before opening, and the
// open is non-blocking and checked again on the descriptor, in case the path was replaced
// in between.
InputFile open_regular_file(const char *path);

}  // namespace frix::fclib
