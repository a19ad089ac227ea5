#include "hdf5_reader.hpp"

#include <sys/stat.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "fclib_error.hpp"

namespace frix::fclib {

namespace {

// A dataset may declare more entries than it stores (unwritten datasets read as their fill
// value: real files have /solution/r stored that way) and compressed data is smaller than
// its extent, but deflate never exceeds ~1000:1. Anything beyond this bound is a forged
// extent, refused before a buffer of that size is allocated.
constexpr double kMaxExpansion = 4096.0;
constexpr double kMaxUnstoredBytes = 64.0 * 1024 * 1024;

const char *class_name(H5T_class_t c) {
    switch (c) {
        case H5T_INTEGER: return "integer";
        case H5T_FLOAT: return "floating-point";
        case H5T_STRING: return "string";
        case H5T_COMPOUND: return "compound";
        case H5T_ARRAY: return "array";
        case H5T_VLEN: return "variable-length";
        case H5T_ENUM: return "enum";
        default: return "non-numeric";
    }
}

// H5Oopen + H5Iget_type rather than H5Oget_info_by_name, whose signature changed
// between HDF5 1.10 and 1.12.
H5I_type_t object_type(hid_t file, const std::string &name) {
    Handle object(H5Oopen(file, name.c_str(), H5P_DEFAULT), H5Oclose);
    return object.valid() ? H5Iget_type(object.get()) : H5I_BADID;
}

// What is wrong with a version 0 or 1 superblock that HDF5 1.10 would size buffers from
// before it fails (it asks for gigabytes on some corrupt files), or nullptr. Checked: the
// reserved bytes are zero; the sizes of offsets and lengths are among 2, 4, 8, 16, 32 (the
// format's); the groups' B-tree ranks K are within 1..kMaxGroupRank (writers keep HDF5's
// defaults, 4 and 16); a driver information block lies, with the length it declares, inside
// the file. Other versions and a file without the signature are left to HDF5.
const char *corrupt_superblock(std::FILE *file, uint64_t file_size) {
    const long at = hdf5_signature_offset(file);
    unsigned char sb[160];
    if (at < 0 || std::fseek(file, at, SEEK_SET) != 0) return nullptr;
    const size_t got = std::fread(sb, 1, sizeof sb, file);
    if (got < 20 || sb[8] > 1) return nullptr;
    constexpr unsigned kMaxGroupRank = 1024;
    auto size_ok = [](unsigned char v) { return v == 2 || v == 4 || v == 8 || v == 16 || v == 32; };
    auto rank_ok = [](const unsigned char *le16) {
        const unsigned k = le16[0] | (unsigned)le16[1] << 8;
        return k >= 1 && k <= kMaxGroupRank;
    };
    if (sb[11] != 0 || sb[15] != 0) return "a reserved byte is set";
    if (!size_ok(sb[13]) || !size_ok(sb[14])) return "sizes of offsets or lengths";
    if (!rank_ok(sb + 16) || !rank_ok(sb + 18)) return "group B-tree rank";

    // Base, free-space, end-of-file and driver-information addresses follow the flags (and,
    // in version 1, the indexed-storage rank). HDF5 reads an address of all ones as
    // undefined and keeps the low 8 bytes of a longer one; it locates the driver block from
    // where the superblock is.
    const unsigned offsets = sb[13];
    const size_t driver_field = (sb[8] == 0 ? 24 : 28) + 3 * size_t{offsets};
    if (got < driver_field + offsets) return nullptr;
    bool undefined = true;
    uint64_t driver = 0;
    for (unsigned b = 0; b < offsets; ++b) {
        const unsigned char c = sb[driver_field + b];
        undefined = undefined && c == 0xff;
        if (b < 8) driver |= uint64_t{c} << (8 * b);
    }
    if (undefined) return nullptr;
    constexpr uint64_t kDriverHeader = 16;  // version, 3 reserved, 4-byte length, 8-byte name
    const uint64_t start = static_cast<uint64_t>(at) + driver;  // no overflow: checked against the size first
    unsigned char head[kDriverHeader];
    if (file_size < kDriverHeader || driver > file_size || start > file_size - kDriverHeader ||
        std::fseek(file, static_cast<long>(start), SEEK_SET) != 0 || std::fread(head, 1, sizeof head, file) != sizeof head)
        return "the driver information block lies beyond the end of the file";
    const uint64_t length = head[4] | uint64_t{head[5]} << 8 | uint64_t{head[6]} << 16 | uint64_t{head[7]} << 24;
    if (length > file_size - start - kDriverHeader) return "the driver information block is longer than the file";
    return nullptr;
}

}  // namespace

struct FileReader::Dataset {
    Handle id;
    Handle type;
    H5T_class_t cls = H5T_NO_CLASS;
    int64_t count = 0;
};

FileReader::FileReader(const char *path) : path_(path) {
    // Checked before HDF5 so the common failures read plainly ("No such file or directory")
    // instead of as HDF5's internal error stack.
    struct stat st;
    if (stat(path, &st) != 0)
        raise(FRIX_ERR_IO, "cannot open '%s': %s", path, std::strerror(errno));
    if (S_ISDIR(st.st_mode)) raise(FRIX_ERR_IO, "cannot open '%s': it is a directory", path);
    std::FILE *probe = std::fopen(path, "rb");
    if (probe == nullptr) raise(FRIX_ERR_IO, "cannot open '%s': %s", path, std::strerror(errno));
    const char *corrupt = corrupt_superblock(probe, static_cast<uint64_t>(st.st_size));
    std::fclose(probe);
    if (corrupt != nullptr) raise(FRIX_ERR_FORMAT, "cannot read '%s': a corrupt HDF5 superblock (%s)", path, corrupt);

#if H5_VERSION_GE(1, 12, 0)
    const htri_t is_hdf5 = H5Fis_accessible(path, H5P_DEFAULT);
#else
    const htri_t is_hdf5 = H5Fis_hdf5(path);
#endif
    if (is_hdf5 == 0) raise(FRIX_ERR_IO, "cannot read '%s': not an HDF5 file", path);
    file_ = file_handle(H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT));
    if (!file_.valid()) {
        const std::string detail = hdf5_error_detail();
        raise(FRIX_ERR_IO, "cannot read '%s' as an HDF5 file: %s", path,
              detail.empty() ? "unknown HDF5 error" : detail.c_str());
    }
}

bool FileReader::exists(const std::string &name) const {
    // H5Lexists fails (rather than answering no) when an intermediate group is missing, so
    // the path is checked one component at a time.
    std::string::size_type pos = 0;
    while (pos != std::string::npos) {
        pos = name.find('/', pos + 1);
        const std::string prefix = name.substr(0, pos);
        if (prefix.empty() || prefix == "/") continue;
        if (H5Lexists(file_.get(), prefix.c_str(), H5P_DEFAULT) <= 0) return false;
        if (pos != std::string::npos) {
            // Only groups can have children; a dataset in the middle of the path means no.
            if (object_type(file_.get(), prefix) != H5I_GROUP) return false;
        }
    }
    return true;
}

bool FileReader::is_group(const std::string &name) const {
    return exists(name) && object_type(file_.get(), name) == H5I_GROUP;
}

int64_t FileReader::link_count(const std::string &group) const {
    H5G_info_t info;
    if (H5Gget_info_by_name(file_.get(), group.c_str(), &info, H5P_DEFAULT) < 0) {
        const std::string detail = hdf5_error_detail();
        raise(FRIX_ERR_IO, "'%s': cannot list group %s: %s", path(), group.c_str(),
              detail.c_str());
    }
    return static_cast<int64_t>(info.nlinks);
}

FileReader::Dataset FileReader::open_dataset(const std::string &name) const {
    if (!exists(name)) raise(FRIX_ERR_FORMAT, "'%s': dataset %s is missing", path(), name.c_str());
    Dataset d;
    d.id = dataset_handle(H5Dopen2(file_.get(), name.c_str(), H5P_DEFAULT));
    if (!d.id.valid()) {
        if (is_group(name))
            raise(FRIX_ERR_FORMAT, "'%s': %s is a group, expected a dataset", path(), name.c_str());
        const std::string detail = hdf5_error_detail();
        raise(FRIX_ERR_IO, "'%s': cannot open dataset %s: %s", path(), name.c_str(),
              detail.c_str());
    }
    d.type = type_handle(H5Dget_type(d.id.get()));
    Handle space = space_handle(H5Dget_space(d.id.get()));
    if (!d.type.valid() || !space.valid()) {
        const std::string detail = hdf5_error_detail();
        raise(FRIX_ERR_IO, "'%s': cannot query dataset %s: %s", path(), name.c_str(),
              detail.c_str());
    }
    d.cls = H5Tget_class(d.type.get());

    switch (H5Sget_simple_extent_type(space.get())) {
        case H5S_SCALAR: d.count = 1; break;
        case H5S_NULL: d.count = 0; break;
        case H5S_SIMPLE: {
            const int rank = H5Sget_simple_extent_ndims(space.get());
            if (rank != 1)
                raise(FRIX_ERR_FORMAT, "'%s': dataset %s has rank %d, expected a 1-D array",
                      path(), name.c_str(), rank);
            hsize_t dim = 0;
            H5Sget_simple_extent_dims(space.get(), &dim, nullptr);
            if (dim > (hsize_t{1} << 48))
                raise(FRIX_ERR_FORMAT, "'%s': dataset %s declares %llu entries", path(),
                      name.c_str(), static_cast<unsigned long long>(dim));
            d.count = static_cast<int64_t>(dim);
            break;
        }
        default:
            raise(FRIX_ERR_FORMAT, "'%s': dataset %s has an invalid dataspace", path(),
                  name.c_str());
    }

    const double declared = static_cast<double>(d.count) *
                            static_cast<double>(H5Tget_size(d.type.get()));
    const double stored = static_cast<double>(H5Dget_storage_size(d.id.get()));
    if (declared > kMaxExpansion * stored + kMaxUnstoredBytes)
        raise(FRIX_ERR_FORMAT, "'%s': dataset %s declares %lld entries but stores only %.0f bytes",
              path(), name.c_str(), static_cast<long long>(d.count), stored);
    return d;
}

int64_t FileReader::length(const std::string &name) const {
    Dataset d = open_dataset(name);
    if (d.cls != H5T_INTEGER && d.cls != H5T_FLOAT)
        raise(FRIX_ERR_FORMAT, "'%s': dataset %s is %s, expected numbers", path(), name.c_str(),
              class_name(d.cls));
    return d.count;
}

template <class T>
std::vector<T> FileReader::read_numeric(const std::string &name, hid_t memtype,
                                        bool integer) const {
    Dataset d = open_dataset(name);
    // Integers are read into doubles without loss below 2^53; floats are never silently
    // truncated into indices.
    const bool ok = integer ? d.cls == H5T_INTEGER : (d.cls == H5T_FLOAT || d.cls == H5T_INTEGER);
    if (!ok)
        raise(FRIX_ERR_FORMAT, "'%s': dataset %s is %s, expected %s", path(), name.c_str(),
              class_name(d.cls), integer ? "integers" : "floating-point numbers");
    std::vector<T> values(static_cast<size_t>(d.count));
    if (d.count > 0 &&
        H5Dread(d.id.get(), memtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()) < 0) {
        const std::string detail = hdf5_error_detail();
        raise(FRIX_ERR_IO, "'%s': cannot read dataset %s: %s", path(), name.c_str(),
              detail.c_str());
    }
    return values;
}

std::vector<int64_t> FileReader::read_ints(const std::string &name) const {
    return read_numeric<int64_t>(name, H5T_NATIVE_INT64, true);
}

std::vector<double> FileReader::read_doubles(const std::string &name) const {
    return read_numeric<double>(name, H5T_NATIVE_DOUBLE, false);
}

int64_t FileReader::read_int_scalar(const std::string &name) const {
    const std::vector<int64_t> v = read_ints(name);
    if (v.size() != 1)
        raise(FRIX_ERR_FORMAT, "'%s': dataset %s has %zu entries, expected 1", path(),
              name.c_str(), v.size());
    return v[0];
}

std::vector<double> FileReader::read_vector(const std::string &name, int64_t expected,
                                            const char *expected_from) const {
    const int64_t n = length(name);
    if (n != expected)
        raise(FRIX_ERR_FORMAT, "'%s': dataset %s has %lld entries, expected %lld (%s)", path(),
              name.c_str(), static_cast<long long>(n), static_cast<long long>(expected),
              expected_from);
    std::vector<double> v = read_doubles(name);
    for (size_t k = 0; k < v.size(); ++k)
        if (!std::isfinite(v[k]))
            raise(FRIX_ERR_FORMAT, "'%s': dataset %s: entry %zu is %g", path(), name.c_str(), k,
                  v[k]);
    return v;
}

std::string FileReader::read_text(const std::string &name) const {
    Dataset d = open_dataset(name);
    if (d.cls != H5T_STRING)
        raise(FRIX_ERR_FORMAT, "'%s': dataset %s is %s, expected a string", path(), name.c_str(),
              class_name(d.cls));
    if (d.count != 1)
        raise(FRIX_ERR_FORMAT, "'%s': dataset %s holds %lld strings, expected 1", path(),
              name.c_str(), static_cast<long long>(d.count));

    auto read_failed = [&]() {
        const std::string detail = hdf5_error_detail();
        raise(FRIX_ERR_IO, "'%s': cannot read dataset %s: %s", path(), name.c_str(),
              detail.c_str());
    };
    // The memory type copies the file's character set: HDF5 refuses to convert between
    // ASCII and UTF-8, and frix wants the bytes as stored (titles need not be UTF-8).
    Handle memtype = type_handle(H5Tcopy(d.type.get()));
    if (!memtype.valid()) read_failed();
    std::string text;
    if (H5Tis_variable_str(d.type.get()) > 0) {
        char *value = nullptr;
        if (H5Dread(d.id.get(), memtype.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, &value) < 0)
            read_failed();
        if (value != nullptr) text = value;
        Handle space = space_handle(H5Dget_space(d.id.get()));
#if H5_VERSION_GE(1, 12, 0)
        H5Treclaim(memtype.get(), space.get(), H5P_DEFAULT, &value);
#else
        H5Dvlen_reclaim(memtype.get(), space.get(), H5P_DEFAULT, &value);
#endif
    } else {
        const size_t size = H5Tget_size(d.type.get());
        std::vector<char> buffer(size + 1, '\0');
        if (H5Dread(d.id.get(), memtype.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, buffer.data()) < 0)
            read_failed();
        text.assign(buffer.data(), std::strlen(buffer.data()));
        if (H5Tget_strpad(d.type.get()) == H5T_STR_SPACEPAD) {
            const auto end = text.find_last_not_of(' ');
            text.erase(end == std::string::npos ? 0 : end + 1);
        }
    }
    return text;
}

}  // namespace frix::fclib
