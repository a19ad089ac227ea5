#include "hdf5_reader.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "fclib_error.hpp"
#include "input_file.hpp"
#include "memory.hpp"

namespace frix::fclib {

namespace {

// What one reader may allocate for a file's data in all: 64 bytes per byte of the file
// (compressed data expands, int32 widens to int64) plus 64 MiB for small files.
constexpr double kAllocationPerFileByte = 64.0;
constexpr double kAllocationSlack = 64.0 * 1024 * 1024;
// HDF5 itself stops after 16 soft links in a row (H5L_NUM_LINKS).
constexpr int kMaxSoftLinks = 16;
constexpr size_t kMaxLinkValue = 4096;
// Where external raw data and virtual-dataset sources would be looked for: /dev/null is
// not a directory, so nothing under it can ever be opened.
constexpr const char *kNoSourceDirectory = "/dev/null/";

// Refuses every external link traversal: the file is read alone.
herr_t refuse_external_link(const char *, const char *, const char *, const char *, unsigned *,
                            hid_t, void *) {
    return -1;
}

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
H5I_type_t object_type(hid_t file, const std::string &name, hid_t links) {
    Handle object(H5Oopen(file, name.c_str(), links), H5Oclose);
    return object.valid() ? H5Iget_type(object.get()) : H5I_BADID;
}

// What is wrong with a version 0 or 1 superblock that HDF5 1.10 would size buffers from
// before it fails (it asks for gigabytes on some corrupt files), or nullptr. Checked: the
// reserved bytes are zero; the sizes of offsets and lengths are among 2, 4, 8, 16, 32 (the
// format's); the groups' B-tree ranks K are within 1..kMaxGroupRank (writers keep HDF5's
// defaults, 4 and 16); the file holds the whole superblock (on one cut short in its
// addresses HDF5 asked for 4 GB); a driver information block lies, with the length it
// declares, inside the file. Other versions and a file without the signature are left to
// HDF5.
const char *corrupt_superblock(std::FILE *file, uint64_t file_size) {
    const long at = hdf5_signature_offset(file);
    unsigned char sb[256];  // the longest version 0 or 1 superblock: 52 + 6 x 32 bytes
    if (at < 0 || std::fseek(file, at, SEEK_SET) != 0) return nullptr;
    const size_t got = std::fread(sb, 1, sizeof sb, file);
    if (got < 9 || sb[8] > 1) return nullptr;
    constexpr const char *kCutShort = "the file ends inside the superblock";
    const size_t fixed = sb[8] == 0 ? 24 : 28;  // up to the addresses
    if (got < fixed) return kCutShort;
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
    // The four addresses, then the root group's symbol table entry (two addresses and 24 bytes).
    if (got < fixed + 6 * size_t{offsets} + 24) return kCutShort;
    const size_t driver_field = fixed + 3 * size_t{offsets};
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
    // instead of as HDF5's internal error stack, and so that HDF5 never opens a FIFO or a
    // device.
    InputFile probe = open_regular_file(path);
    file_size_ = probe.size;
    allocation_limit_ = kAllocationPerFileByte * static_cast<double>(file_size_) + kAllocationSlack;
    const char *corrupt = corrupt_superblock(probe.file.get(), file_size_);
    if (corrupt != nullptr) raise(FRIX_ERR_FORMAT, "cannot read '%s': a corrupt HDF5 superblock (%s)", path, corrupt);
    if (hdf5_signature_offset(probe.file.get()) < 0) raise(FRIX_ERR_IO, "cannot read '%s': not an HDF5 file", path);

    auto setup_failed = [&]() {
        const std::string detail = hdf5_error_detail();
        raise(FRIX_ERR_IO, "cannot read '%s': cannot set up HDF5: %s", path, detail.c_str());
    };
    links_ = plist_handle(H5Pcreate(H5P_LINK_ACCESS));
    access_ = plist_handle(H5Pcreate(H5P_DATASET_ACCESS));
    Handle file_access = plist_handle(H5Pcreate(H5P_FILE_ACCESS));
    if (!links_.valid() || !access_.valid() || !file_access.valid() ||
        H5Pset_elink_cb(links_.get(), refuse_external_link, nullptr) < 0 ||
        H5Pset_elink_cb(access_.get(), refuse_external_link, nullptr) < 0 ||
        H5Pset_efile_prefix(access_.get(), kNoSourceDirectory) < 0 ||
        H5Pset_virtual_prefix(access_.get(), kNoSourceDirectory) < 0 ||
        H5Pset_fapl_sec2(file_access.get()) < 0)
        setup_failed();

    file_ = file_handle(H5Fopen(path, H5F_ACC_RDONLY, file_access.get()));
    if (!file_.valid()) {
        const std::string detail = hdf5_error_detail();
        raise(FRIX_ERR_IO, "cannot read '%s' as an HDF5 file: %s", path,
              detail.empty() ? "unknown HDF5 error" : detail.c_str());
    }
    // HDF5 opened the path again: it must still be the file checked above.
    void *handle = nullptr;
    struct stat opened;
    if (H5Fget_vfd_handle(file_.get(), file_access.get(), &handle) < 0 || handle == nullptr ||
        fstat(*static_cast<int *>(handle), &opened) != 0 || opened.st_dev != probe.device ||
        opened.st_ino != probe.inode)
        raise(FRIX_ERR_IO, "cannot read '%s': the file was replaced while being opened", path);
}

void FileReader::check_link(const std::string &name, int depth) const {
    H5L_info_t info;
    if (H5Lget_info(file_.get(), name.c_str(), &info, links_.get()) < 0) {
        const std::string detail = hdf5_error_detail();
        raise(FRIX_ERR_IO, "'%s': cannot query link %s: %s", path(), printable(name).c_str(),
              detail.c_str());
    }
    if (info.type == H5L_TYPE_HARD) return;
    if (info.type != H5L_TYPE_SOFT && info.type != H5L_TYPE_EXTERNAL)
        raise(FRIX_ERR_FORMAT, "'%s': %s is a user-defined link (type %d), which frix does not follow",
              path(), printable(name).c_str(), static_cast<int>(info.type));
    if (info.u.val_size == 0 || info.u.val_size > kMaxLinkValue)
        raise(FRIX_ERR_FORMAT, "'%s': link %s has a target of %zu bytes", path(),
              printable(name).c_str(), info.u.val_size);
    std::vector<char> value(info.u.val_size + 1, '\0');
    if (H5Lget_val(file_.get(), name.c_str(), value.data(), info.u.val_size, links_.get()) < 0) {
        const std::string detail = hdf5_error_detail();
        raise(FRIX_ERR_IO, "'%s': cannot read link %s: %s", path(), printable(name).c_str(),
              detail.c_str());
    }
    if (info.type == H5L_TYPE_EXTERNAL) {
        const char *other_file = nullptr, *other_object = nullptr;
        unsigned flags = 0;
        if (H5Lunpack_elink_val(value.data(), info.u.val_size, &flags, &other_file, &other_object) < 0)
            other_file = other_object = "?";
        raise(FRIX_ERR_FORMAT,
              "'%s': %s is an external link (to %s in '%s'); frix reads nothing outside the file",
              path(), printable(name).c_str(), printable(other_object).c_str(),
              printable(other_file).c_str());
    }
    // A soft link names a path in this file, relative to the group holding the link; that
    // path must itself exist and be made of links frix follows.
    const std::string target(value.data());
    if (depth >= kMaxSoftLinks)
        raise(FRIX_ERR_FORMAT, "'%s': soft link %s is the %dth soft link in a row (a loop?)", path(),
              printable(name).c_str(), depth + 1);
    const std::string parent = name.substr(0, name.find_last_of('/'));
    const std::string absolute = !target.empty() && target[0] == '/' ? target : parent + "/" + target;
    if (!walk_links(absolute, depth + 1))
        raise(FRIX_ERR_FORMAT, "'%s': %s is a soft link to %s, which does not exist in the file",
              path(), printable(name).c_str(), printable(target).c_str());
}

bool FileReader::walk_links(const std::string &name, int depth) const {
    // H5Lexists fails (rather than answering no) when an intermediate group is missing, so
    // the path is checked one component at a time, each link before anything goes through it.
    std::string::size_type pos = 0;
    while (pos != std::string::npos) {
        pos = name.find('/', pos + 1);
        const std::string prefix = name.substr(0, pos);
        if (prefix.empty() || prefix == "/" || prefix.back() == '/') continue;
        if (H5Lexists(file_.get(), prefix.c_str(), links_.get()) <= 0) return false;
        check_link(prefix, depth);
        if (pos != std::string::npos) {
            // Only groups can have children; a dataset in the middle of the path means no.
            if (object_type(file_.get(), prefix, links_.get()) != H5I_GROUP) return false;
        }
    }
    return true;
}

bool FileReader::exists(const std::string &name) const { return walk_links(name, 0); }

bool FileReader::is_group(const std::string &name) const {
    return exists(name) && object_type(file_.get(), name, links_.get()) == H5I_GROUP;
}

int64_t FileReader::link_count(const std::string &group) const {
    H5G_info_t info;
    if (H5Gget_info_by_name(file_.get(), group.c_str(), &info, links_.get()) < 0) {
        const std::string detail = hdf5_error_detail();
        raise(FRIX_ERR_IO, "'%s': cannot list group %s: %s", path(), group.c_str(),
              detail.c_str());
    }
    return static_cast<int64_t>(info.nlinks);
}

FileReader::Dataset FileReader::open_dataset(const std::string &name) const {
    if (!exists(name)) raise(FRIX_ERR_FORMAT, "'%s': dataset %s is missing", path(), name.c_str());
    Dataset d;
    d.id = dataset_handle(H5Dopen2(file_.get(), name.c_str(), access_.get()));
    if (!d.id.valid()) {
        if (is_group(name))
            raise(FRIX_ERR_FORMAT, "'%s': %s is a group, expected a dataset", path(), name.c_str());
        const std::string detail = hdf5_error_detail();
        raise(FRIX_ERR_IO, "'%s': cannot open dataset %s: %s", path(), name.c_str(),
              detail.c_str());
    }
    auto query_failed = [&]() {
        const std::string detail = hdf5_error_detail();
        raise(FRIX_ERR_IO, "'%s': cannot query dataset %s: %s", path(), name.c_str(),
              detail.c_str());
    };
    // Where the data lives, before anything else is asked of the dataset: only in this file.
    Handle creation = plist_handle(H5Dget_create_plist(d.id.get()));
    if (!creation.valid()) query_failed();
    const H5D_layout_t layout = H5Pget_layout(creation.get());
    if (layout == H5D_VIRTUAL)
        raise(FRIX_ERR_FORMAT,
              "'%s': dataset %s is a virtual dataset (its data lives in other datasets or files), "
              "which frix does not read",
              path(), name.c_str());
    if (H5Pget_external_count(creation.get()) != 0)
        raise(FRIX_ERR_FORMAT,
              "'%s': dataset %s stores its data in external files; frix reads nothing outside "
              "the file",
              path(), name.c_str());

    d.type = type_handle(H5Dget_type(d.id.get()));
    Handle space = space_handle(H5Dget_space(d.id.get()));
    if (!d.type.valid() || !space.valid()) query_failed();
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

    // Numbers are read as 8-byte int64 or double whatever their size in the file, so they
    // count at that size.
    const size_t file_bytes = H5Tget_size(d.type.get());
    const bool numeric = d.cls == H5T_INTEGER || d.cls == H5T_FLOAT;
    const double element = static_cast<double>(numeric ? std::max<size_t>(file_bytes, 8) : file_bytes);
    const double declared = static_cast<double>(d.count) * element;
    if (declared > allocation_limit_)
        raise(FRIX_ERR_FORMAT,
              "'%s': dataset %s declares %lld entries (%.0f bytes) but stores only %llu bytes, "
              "more than a file of %llu bytes can back (at most %.0f bytes)",
              path(), name.c_str(), static_cast<long long>(d.count), declared,
              static_cast<unsigned long long>(H5Dget_storage_size(d.id.get())),
              static_cast<unsigned long long>(file_size_), allocation_limit_);
    // HDF5 reads a chunked dataset one whole chunk at a time, whatever its extent.
    if (layout == H5D_CHUNKED) {
        hsize_t chunk[H5S_MAX_RANK] = {0};
        const int chunk_rank = H5Pget_chunk(creation.get(), H5S_MAX_RANK, chunk);
        if (chunk_rank < 0) query_failed();
        double chunk_bytes = element;
        for (int k = 0; k < chunk_rank; ++k) chunk_bytes *= static_cast<double>(chunk[k]);
        if (chunk_bytes > allocation_limit_)
            raise(FRIX_ERR_FORMAT,
                  "'%s': dataset %s has chunks of %.0f bytes, more than a file of %llu bytes "
                  "can back (at most %.0f bytes)",
                  path(), name.c_str(), chunk_bytes, static_cast<unsigned long long>(file_size_),
                  allocation_limit_);
    }
    return d;
}

void FileReader::check_written(const Dataset &d, const std::string &name, Unwritten unwritten) const {
    if (unwritten == Unwritten::read_fill) return;
    H5D_space_status_t status;
    if (H5Dget_space_status(d.id.get(), &status) < 0) {
        const std::string detail = hdf5_error_detail();
        raise(FRIX_ERR_IO, "'%s': cannot query dataset %s: %s", path(), name.c_str(),
              detail.c_str());
    }
    // Unwritten data would read as HDF5's fill value: zeros that the file never held.
    if (status == H5D_SPACE_STATUS_NOT_ALLOCATED)
        raise(FRIX_ERR_FORMAT, "'%s': dataset %s was never written", path(), name.c_str());
    if (status == H5D_SPACE_STATUS_PART_ALLOCATED && !all_chunks_written(d))
        raise(FRIX_ERR_FORMAT, "'%s': dataset %s was only partly written", path(), name.c_str());
}

// A compressed (chunked, filtered) dataset stores less than its extent, and HDF5 then calls it
// partly allocated however whole it is: it is whole when every chunk its extent covers exists.
bool FileReader::all_chunks_written(const Dataset &d) const {
    Handle creation = plist_handle(H5Dget_create_plist(d.id.get()));
    Handle space = space_handle(H5Dget_space(d.id.get()));
    if (!creation.valid() || !space.valid() || H5Pget_layout(creation.get()) != H5D_CHUNKED) return false;
    hsize_t chunk[H5S_MAX_RANK] = {0}, extent[H5S_MAX_RANK] = {0};
    const int rank = H5Pget_chunk(creation.get(), H5S_MAX_RANK, chunk);
    if (rank < 0 || H5Sget_simple_extent_dims(space.get(), extent, nullptr) != rank) return false;
    hsize_t expected = 1;
    for (int k = 0; k < rank; ++k) {
        if (chunk[k] == 0) return false;
        expected *= (extent[k] + chunk[k] - 1) / chunk[k];
    }
    hsize_t stored = 0;
    return H5Dget_num_chunks(d.id.get(), space.get(), &stored) >= 0 && stored == expected;
}

void FileReader::charge(const std::string &name, double bytes) const {
    if (allocated_ + bytes > allocation_limit_)
        raise(FRIX_ERR_FORMAT,
              "'%s': reading dataset %s (%.0f bytes) would take the memory allocated for the "
              "file to %.0f bytes, more than a file of %llu bytes can back (at most %.0f bytes)",
              path(), name.c_str(), bytes, allocated_ + bytes,
              static_cast<unsigned long long>(file_size_), allocation_limit_);
    allocated_ += bytes;
}

int64_t FileReader::length(const std::string &name) const {
    Dataset d = open_dataset(name);
    if (d.cls != H5T_INTEGER && d.cls != H5T_FLOAT)
        raise(FRIX_ERR_FORMAT, "'%s': dataset %s is %s, expected numbers", path(), name.c_str(),
              class_name(d.cls));
    return d.count;
}

template <class T>
std::vector<T> FileReader::read_numeric(const std::string &name, hid_t memtype, bool integer,
                                        int64_t count, Unwritten unwritten) const {
    Dataset d = open_dataset(name);
    // Integers are read into doubles without loss below 2^53; floats are never silently
    // truncated into indices.
    const bool ok = integer ? d.cls == H5T_INTEGER : (d.cls == H5T_FLOAT || d.cls == H5T_INTEGER);
    if (!ok)
        raise(FRIX_ERR_FORMAT, "'%s': dataset %s is %s, expected %s", path(), name.c_str(),
              class_name(d.cls), integer ? "integers" : "floating-point numbers");
    const bool whole = count < 0;
    if (whole) count = d.count;
    if (count > d.count)
        raise(FRIX_ERR_FORMAT, "'%s': dataset %s has %lld entries, expected at least %lld", path(),
              name.c_str(), static_cast<long long>(d.count), static_cast<long long>(count));
    if (count == 0) return {};
    check_written(d, name, unwritten);
    charge(name, static_cast<double>(count) * sizeof(T));
    std::vector<T> values;
    frix::assign_advised(values, static_cast<size_t>(count));

    auto read_failed = [&]() {
        const std::string detail = hdf5_error_detail();
        raise(FRIX_ERR_IO, "'%s': cannot read dataset %s: %s", path(), name.c_str(),
              detail.c_str());
    };
    if (whole) {
        if (H5Dread(d.id.get(), memtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()) < 0)
            read_failed();
        return values;
    }
    const hsize_t start = 0, first = static_cast<hsize_t>(count);
    Handle file_space = space_handle(H5Dget_space(d.id.get()));
    Handle memory_space = space_handle(H5Screate_simple(1, &first, nullptr));
    if (!file_space.valid() || !memory_space.valid() ||
        H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, &start, nullptr, &first, nullptr) < 0 ||
        H5Dread(d.id.get(), memtype, memory_space.get(), file_space.get(), H5P_DEFAULT, values.data()) < 0)
        read_failed();
    return values;
}

std::vector<int64_t> FileReader::read_ints(const std::string &name) const {
    return read_numeric<int64_t>(name, H5T_NATIVE_INT64, true, -1, Unwritten::refuse);
}

std::vector<int64_t> FileReader::read_first_ints(const std::string &name, int64_t count) const {
    return read_numeric<int64_t>(name, H5T_NATIVE_INT64, true, count, Unwritten::refuse);
}

std::vector<double> FileReader::read_first_doubles(const std::string &name, int64_t count) const {
    return read_numeric<double>(name, H5T_NATIVE_DOUBLE, false, count, Unwritten::refuse);
}

int64_t FileReader::read_int_scalar(const std::string &name) const {
    const int64_t n = length(name);
    if (n != 1)
        raise(FRIX_ERR_FORMAT, "'%s': dataset %s has %lld entries, expected 1", path(),
              name.c_str(), static_cast<long long>(n));
    return read_ints(name)[0];
}

std::vector<double> FileReader::read_vector(const std::string &name, int64_t expected,
                                            const char *expected_from, Unwritten unwritten) const {
    const int64_t n = length(name);
    if (n != expected)
        raise(FRIX_ERR_FORMAT, "'%s': dataset %s has %lld entries, expected %lld (%s)", path(),
              name.c_str(), static_cast<long long>(n), static_cast<long long>(expected),
              expected_from);
    std::vector<double> v = read_numeric<double>(name, H5T_NATIVE_DOUBLE, false, -1, unwritten);
    for (size_t k = 0; k < v.size(); ++k)
        if (!std::isfinite(v[k]))
            raise(FRIX_ERR_FORMAT, "'%s': dataset %s: entry %zu is %g", path(), name.c_str(), k,
                  v[k]);
    return v;
}

std::string FileReader::read_text(const std::string &name, size_t max_bytes) const {
    Dataset d = open_dataset(name);
    if (d.cls != H5T_STRING)
        raise(FRIX_ERR_FORMAT, "'%s': dataset %s is %s, expected a string", path(), name.c_str(),
              class_name(d.cls));
    if (d.count != 1)
        raise(FRIX_ERR_FORMAT, "'%s': dataset %s holds %lld strings, expected 1", path(),
              name.c_str(), static_cast<long long>(d.count));
    check_written(d, name, Unwritten::refuse);

    auto read_failed = [&]() {
        const std::string detail = hdf5_error_detail();
        raise(FRIX_ERR_IO, "'%s': cannot read dataset %s: %s", path(), name.c_str(),
              detail.c_str());
    };
    // The memory type copies the file's character set: HDF5 refuses to convert between
    // ASCII and UTF-8, and frix wants the bytes as stored (titles need not be UTF-8).
    Handle memtype = type_handle(H5Tcopy(d.type.get()));
    if (!memtype.valid()) read_failed();
    auto too_long = [&](double bytes) {
        raise(FRIX_ERR_FORMAT, "'%s': dataset %s holds a string of %.0f bytes, more than the %zu "
              "frix reads", path(), name.c_str(), bytes, max_bytes);
    };
    std::string text;
    if (H5Tis_variable_str(d.type.get()) > 0) {
        // HDF5 sizes the string from its heap object, which the file holds in full (so it is
        // bounded by the file's size); its length is checked once read.
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
        charge(name, static_cast<double>(text.size()));
    } else {
        const size_t size = H5Tget_size(d.type.get());
        if (size > max_bytes + 1) too_long(static_cast<double>(size));
        charge(name, static_cast<double>(size) + 1);
        std::vector<char> buffer(size + 1, '\0');
        if (H5Dread(d.id.get(), memtype.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, buffer.data()) < 0)
            read_failed();
        text.assign(buffer.data(), std::strlen(buffer.data()));
        if (H5Tget_strpad(d.type.get()) == H5T_STR_SPACEPAD) {
            const auto end = text.find_last_not_of(' ');
            text.erase(end == std::string::npos ? 0 : end + 1);
        }
    }
    if (text.size() > max_bytes) too_long(static_cast<double>(text.size()));
    return text;
}

}  // namespace frix::fclib
