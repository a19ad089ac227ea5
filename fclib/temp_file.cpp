#include "temp_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <vector>

#include "fclib_error.hpp"

namespace frix::fclib {

namespace {

// The permissions a plain creat() would give. Read from /proc because umask() can only be
// queried by changing it, which races with other threads.
mode_t default_file_mode() {
    mode_t mask = 022;
    if (std::FILE *status = std::fopen("/proc/self/status", "r")) {
        char line[256];
        while (std::fgets(line, sizeof line, status) != nullptr) {
            unsigned value = 0;
            if (std::sscanf(line, "Umask: %o", &value) == 1) {
                mask = static_cast<mode_t>(value);
                break;
            }
        }
        std::fclose(status);
    }
    return static_cast<mode_t>(0666 & ~mask);
}

std::string directory_of(const std::string &path) {
    const auto slash = path.find_last_of('/');
    if (slash == std::string::npos) return ".";
    if (slash == 0) return "/";
    return path.substr(0, slash);
}

}  // namespace

TempFile::TempFile(const std::string &target) : target_(target) {
    std::vector<char> name(target.begin(), target.end());
    const char suffix[] = ".tmp.XXXXXX";
    name.insert(name.end(), suffix, suffix + sizeof suffix);  // includes the NUL
    const int fd = mkstemp(name.data());
    if (fd < 0)
        raise(FRIX_ERR_IO, "cannot write '%s': cannot create a temporary file in %s: %s",
              target.c_str(), directory_of(target).c_str(), std::strerror(errno));
    name_ = name.data();
    // mkstemp creates the file 0600; replacing a file keeps its permissions, a new file
    // gets the usual ones.
    struct stat st;
    const mode_t mode = (stat(target.c_str(), &st) == 0 && S_ISREG(st.st_mode))
                            ? static_cast<mode_t>(st.st_mode & 07777)
                            : default_file_mode();
    fchmod(fd, mode);
    fd_ = fd;
}

TempFile::~TempFile() {
    if (fd_ >= 0) close(fd_);
    if (!committed_ && !name_.empty()) std::remove(name_.c_str());
}

void TempFile::write(const void *data, size_t size) {
    const char *p = static_cast<const char *>(data);
    while (size > 0) {
        const ssize_t done = ::write(fd_, p, size);
        if (done < 0 && errno == EINTR) continue;
        if (done <= 0)
            raise(FRIX_ERR_IO, "cannot write '%s': writing %s failed: %s", target_.c_str(),
                  name_.c_str(), done < 0 ? std::strerror(errno) : "no progress");
        p += done;
        size -= static_cast<size_t>(done);
    }
}

void TempFile::commit() {
    // Without the fsync a crash shortly after the rename could leave the target empty.
    // close() is checked too: some file systems (NFS) report write errors only there.
    const int fd = fd_;
    fd_ = -1;
    int err = fsync(fd) == 0 ? 0 : errno;
    if (close(fd) != 0 && err == 0) err = errno;
    if (err != 0)
        raise(FRIX_ERR_IO, "cannot write '%s': cannot complete %s: %s", target_.c_str(),
              name_.c_str(), std::strerror(err));
    if (std::rename(name_.c_str(), target_.c_str()) != 0)
        raise(FRIX_ERR_IO, "cannot write '%s': cannot rename %s into place: %s", target_.c_str(),
              name_.c_str(), std::strerror(errno));
    committed_ = true;
    // Makes the rename itself durable; not every file system supports syncing a directory,
    // and the file is complete either way, so a failure here is not reported.
    const int dir = open(directory_of(target_).c_str(), O_RDONLY | O_DIRECTORY);
    if (dir >= 0) {
        fsync(dir);
        close(dir);
    }
}

}  // namespace frix::fclib
