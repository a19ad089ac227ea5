#include "temp_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstdio>
#include <cstring>
#include <vector>

#include "fclib_error.hpp"
#include "input_file.hpp"

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

// The file a write to `path` lands on: symbolic links in the last component followed, also
// a dangling one (its target is then created). Renaming onto the link itself would replace
// the link by a regular file and leave the file it pointed to stale.
std::string resolve_links(const std::string &path) {
    std::string p = path;
    for (int hops = 0; hops < 40; ++hops) {  // 40: the kernel's own limit (ELOOP)
        struct stat st;
        if (lstat(p.c_str(), &st) != 0 || !S_ISLNK(st.st_mode)) return p;
        char link[PATH_MAX + 1];
        const ssize_t n = readlink(p.c_str(), link, sizeof link);
        if (n < 0 || static_cast<size_t>(n) >= sizeof link)
            raise(FRIX_ERR_IO, "cannot write '%s': cannot follow the symbolic link %s: %s",
                  path.c_str(), p.c_str(), std::strerror(n < 0 ? errno : ENAMETOOLONG));
        const std::string to(link, static_cast<size_t>(n));
        // A relative target is relative to the link's own directory.
        p = to[0] == '/' || p.find('/') == std::string::npos ? to : directory_of(p) + "/" + to;
    }
    raise(FRIX_ERR_IO, "cannot write '%s': %s", path.c_str(), std::strerror(ELOOP));
}

}  // namespace

TempFile::TempFile(const std::string &target) : target_(target), resolved_(resolve_links(target)) {
    // An existing target must be a regular file that may be written: anything else is
    // refused before a byte is written, since replacing it would destroy what it is (a
    // device node, a FIFO a reader waits on) or what its owner marked to keep.
    const std::string it = resolved_ == target ? "it" : resolved_ + " (where it links)";
    struct stat st;
    const bool exists = lstat(resolved_.c_str(), &st) == 0;
    if (exists && !S_ISREG(st.st_mode))
        raise(FRIX_ERR_IO, "cannot write '%s': %s is %s, not a regular file", target.c_str(),
              it.c_str(), file_kind(st.st_mode));
    // access() is the permission check proper; root passes it on any file, so a file with
    // no write bit for anyone also counts as read-only.
    if (exists && (access(resolved_.c_str(), W_OK) != 0 || (st.st_mode & 0222) == 0))
        raise(FRIX_ERR_IO, "cannot write '%s': %s is read-only", target.c_str(), it.c_str());

    std::vector<char> name(resolved_.begin(), resolved_.end());
    const char suffix[] = ".tmp.XXXXXX";
    name.insert(name.end(), suffix, suffix + sizeof suffix);  // includes the NUL
    const int fd = mkstemp(name.data());
    if (fd < 0)
        raise(FRIX_ERR_IO, "cannot write '%s': cannot create a temporary file in %s: %s",
              target.c_str(), directory_of(resolved_).c_str(), std::strerror(errno));
    name_ = name.data();
    // mkstemp creates the file 0600; replacing a file keeps its permissions, a new file
    // gets the usual ones.
    const mode_t mode = exists ? static_cast<mode_t>(st.st_mode & 07777) : default_file_mode();
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
    if (std::rename(name_.c_str(), resolved_.c_str()) != 0)
        raise(FRIX_ERR_IO, "cannot write '%s': cannot rename %s into place: %s", target_.c_str(),
              name_.c_str(), std::strerror(errno));
    committed_ = true;
    // Makes the rename itself durable; not every file system supports syncing a directory,
    // and the file is complete either way, so a failure here is not reported.
    const int dir = open(directory_of(resolved_).c_str(), O_RDONLY | O_DIRECTORY);
    if (dir >= 0) {
        fsync(dir);
        close(dir);
    }
}

}  // namespace frix::fclib
