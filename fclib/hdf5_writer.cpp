#include "hdf5_writer.hpp"

#include <algorithm>

#include "fclib_error.hpp"

namespace frix::fclib {

namespace {
// Chunks of 64 Ki entries (512 KiB of doubles) stay far below what the reader accepts.
constexpr hsize_t kChunkEntries = hsize_t{1} << 16;
}  // namespace

// Smaller arrays than kCompressFrom are written as they are (a chunk's bookkeeping outweighs
// what deflate saves).
FileWriter::FileWriter(const std::string &shown_path, int deflate_level)
    : shown_path_(shown_path), deflate_level_(deflate_level) {
    // Memory grows in 1 MiB steps. STRONG close degree: closing the file also closes
    // whatever an interrupted write left open, so nothing outlives the writer.
    Handle fapl = plist_handle(H5Pcreate(H5P_FILE_ACCESS));
    if (!fapl.valid() || H5Pset_fapl_core(fapl.get(), size_t{1} << 20, false) < 0 ||
        H5Pset_fclose_degree(fapl.get(), H5F_CLOSE_STRONG) < 0)
        failed("cannot set up", "the in-memory file");
    // The name only identifies the in-memory file: without a backing store nothing is
    // created on disk under it.
    file_ = file_handle(H5Fcreate((shown_path + ".frix-in-memory").c_str(), H5F_ACC_TRUNC,
                                  H5P_DEFAULT, fapl.get()));
    if (!file_.valid()) failed("cannot create", "the in-memory file");
}

void FileWriter::failed(const char *what, const std::string &name) const {
    const std::string detail = hdf5_error_detail();
    raise(FRIX_ERR_IO, "cannot write '%s': %s %s%s%s", shown_path_.c_str(), what, name.c_str(),
          detail.empty() ? "" : ": ", detail.c_str());
}

void FileWriter::create_group(const std::string &name) {
    Handle group = group_handle(
        H5Gcreate2(file_.get(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
    if (!group.valid()) failed("cannot create group", name);
    if (!group.close()) failed("cannot close group", name);
}

void FileWriter::write_array(const std::string &name, hid_t filetype, hid_t memtype,
                             const void *data, int64_t count) {
    const hsize_t dim = static_cast<hsize_t>(count);
    Handle space = space_handle(H5Screate_simple(1, &dim, nullptr));
    if (!space.valid()) failed("cannot create the dataspace of", name);
    Handle create = plist_handle(H5Pcreate(H5P_DATASET_CREATE));
    if (!create.valid()) failed("cannot make the creation properties of", name);
    // Arrays of kCompressFrom entries or more are stored shuffled and deflated, as FCLIB's own
    // files are (a third of the size), where the HDF5 library has the filter.
    if (deflate_level_ > 0 && count >= kCompressFrom && H5Zfilter_avail(H5Z_FILTER_DEFLATE) > 0) {
        const hsize_t chunk = std::min<hsize_t>(dim, kChunkEntries);
        if (H5Pset_chunk(create.get(), 1, &chunk) < 0 || H5Pset_shuffle(create.get()) < 0 ||
            H5Pset_deflate(create.get(), static_cast<unsigned>(deflate_level_)) < 0)
            failed("cannot set the compression of", name);
    }
    Handle dataset = dataset_handle(H5Dcreate2(file_.get(), name.c_str(), filetype, space.get(),
                                               H5P_DEFAULT, create.get(), H5P_DEFAULT));
    if (!dataset.valid()) failed("cannot create dataset", name);
    // An empty dataset has nothing to write, and H5Dwrite rejects the NULL buffer an empty
    // vector may have.
    if (count > 0 && H5Dwrite(dataset.get(), memtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)
        failed("cannot write dataset", name);
    if (!dataset.close()) failed("cannot close dataset", name);
}

void FileWriter::write_int32s(const std::string &name, const std::vector<int32_t> &values) {
    write_array(name, H5T_STD_I32LE, H5T_NATIVE_INT32, values.data(),
                static_cast<int64_t>(values.size()));
}

void FileWriter::write_int32_scalar(const std::string &name, int32_t value) {
    write_array(name, H5T_STD_I32LE, H5T_NATIVE_INT32, &value, 1);
}

void FileWriter::write_doubles(const std::string &name, const double *values, int64_t count) {
    write_array(name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, values, count);
}

void FileWriter::write_text(const std::string &name, const std::string &text) {
    Handle type = type_handle(H5Tcopy(H5T_C_S1));
    if (!type.valid() || H5Tset_size(type.get(), text.size() + 1) < 0)
        failed("cannot make the string type of", name);
    Handle space = space_handle(H5Screate(H5S_SCALAR));
    if (!space.valid()) failed("cannot create the dataspace of", name);
    Handle dataset = dataset_handle(H5Dcreate2(file_.get(), name.c_str(), type.get(),
                                               space.get(), H5P_DEFAULT, H5P_DEFAULT,
                                               H5P_DEFAULT));
    if (!dataset.valid()) failed("cannot create dataset", name);
    if (H5Dwrite(dataset.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, text.c_str()) < 0)
        failed("cannot write dataset", name);
    if (!dataset.close()) failed("cannot close dataset", name);
}

std::vector<unsigned char> FileWriter::image() {
    if (H5Fflush(file_.get(), H5F_SCOPE_LOCAL) < 0) failed("cannot flush", "the in-memory file");
    const ssize_t size = H5Fget_file_image(file_.get(), nullptr, 0);
    if (size < 0) failed("cannot measure", "the in-memory file");
    std::vector<unsigned char> bytes(static_cast<size_t>(size));
    if (H5Fget_file_image(file_.get(), bytes.data(), bytes.size()) != size)
        failed("cannot copy", "the in-memory file");
    return bytes;
}

}  // namespace frix::fclib
