#include "input_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "fclib_error.hpp"

namespace frix::fclib {

const char *file_kind(mode_t mode) {
    if (S_ISDIR(mode)) return "a directory";
    if (S_ISFIFO(mode)) return "a FIFO";
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISSOCK(mode)) return "a socket";
    return "of another kind";
}

InputFile open_regular_file(const char *path) {
    struct stat st;
    if (stat(path, &st) != 0) raise(FRIX_ERR_IO, "cannot open '%s': %s", path, std::strerror(errno));
    if (!S_ISREG(st.st_mode))
        raise(FRIX_ERR_IO, "cannot open '%s': it is %s, not a regular file", path, file_kind(st.st_mode));
    const int fd = open(path, O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
    if (fd < 0) raise(FRIX_ERR_IO, "cannot open '%s': %s", path, std::strerror(errno));
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        const int saved = errno;
        close(fd);
        if (!S_ISREG(st.st_mode))
            raise(FRIX_ERR_IO, "cannot open '%s': it is %s, not a regular file", path, file_kind(st.st_mode));
        raise(FRIX_ERR_IO, "cannot open '%s': %s", path, std::strerror(saved));
    }
    InputFile in;
    in.file.reset(fdopen(fd, "rb"));
    if (!in.file) {
        const int saved = errno;
        close(fd);
        raise(FRIX_ERR_IO, "cannot open '%s': %s", path, std::strerror(saved));
    }
    in.size = static_cast<uint64_t>(st.st_size);
    in.device = st.st_dev;
    in.inode = st.st_ino;
    return in;
}

}  // namespace frix::fclib
