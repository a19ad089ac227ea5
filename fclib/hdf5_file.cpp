#include "hdf5_file.hpp"

#include <cstring>

#include "fclib_error.hpp"

namespace frix::fclib {

Handle &Handle::operator=(Handle &&other) noexcept {
    if (this != &other) {
        reset();
        id_ = other.id_;
        closer_ = other.closer_;
        other.id_ = -1;
    }
    return *this;
}

bool Handle::close() {
    if (id_ < 0) return true;
    const herr_t status = closer_(id_);
    id_ = -1;
    return status >= 0;
}

void Handle::reset() {
    if (id_ >= 0 && closer_ != nullptr) closer_(id_);
    id_ = -1;
}

namespace {
std::mutex &hdf5_mutex() {
    static std::mutex m;
    return m;
}
}  // namespace

Session::Session() : lock_(hdf5_mutex()) {
    // If the application installed an old-style (H5Eset_auto1) handler, H5Eget_auto2 fails;
    // then the handler is left alone rather than replaced by one frix cannot restore.
    if (H5Eget_auto2(H5E_DEFAULT, &saved_func_, &saved_data_) >= 0) {
        saved_ = true;
        H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    }
}

Session::~Session() {
    if (saved_) H5Eset_auto2(H5E_DEFAULT, saved_func_, saved_data_);
}

namespace {
herr_t keep_innermost(unsigned n, const H5E_error2_t *err, void *data) {
    // Walking upward, entry 0 is the innermost: the place the error was detected.
    if (n == 0 && err != nullptr && err->desc != nullptr)
        *static_cast<std::string *>(data) = err->desc;
    return 0;
}
}  // namespace

std::string hdf5_error_detail() {
    std::string detail;
    H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, keep_innermost, &detail);
    // HDF5 quotes names from the file in some descriptions.
    return printable(detail);
}

long hdf5_signature_offset(std::FILE *file) {
    static const unsigned char kSignature[8] = {0x89, 'H', 'D', 'F', '\r', '\n', 0x1a, '\n'};
    for (long offset = 0; offset <= (1L << 30); offset = offset == 0 ? 512 : 2 * offset) {
        unsigned char head[8];
        if (std::fseek(file, offset, SEEK_SET) != 0 || std::fread(head, 1, 8, file) != 8) return -1;
        if (std::memcmp(head, kSignature, 8) == 0) return offset;
    }
    return -1;
}

}  // namespace frix::fclib
