// Ownership of HDF5 identifiers, and the session every FCLIB entry point holds while it
// calls HDF5.
#pragma once

#include <hdf5.h>

#include <cstdio>
#include <mutex>
#include <string>

namespace frix::fclib {

// One HDF5 identifier, closed with the function of its kind when the owner goes away, so
// that every early return or thrown failure releases what was opened.
class Handle {
   public:
    using Closer = herr_t (*)(hid_t);

    Handle() = default;
    Handle(hid_t id, Closer closer) : id_(id), closer_(closer) {}
    Handle(Handle &&other) noexcept : id_(other.id_), closer_(other.closer_) { other.id_ = -1; }
    Handle &operator=(Handle &&other) noexcept;
    Handle(const Handle &) = delete;
    Handle &operator=(const Handle &) = delete;
    ~Handle() { reset(); }

    hid_t get() const { return id_; }
    bool valid() const { return id_ >= 0; }

    // Closes now and says whether HDF5 succeeded. Closing a file being written is where
    // HDF5 flushes its metadata, so the writer must see that result.
    bool close();

   private:
    void reset();

    hid_t id_ = -1;
    Closer closer_ = nullptr;
};

inline Handle file_handle(hid_t id) { return Handle(id, H5Fclose); }
inline Handle group_handle(hid_t id) { return Handle(id, H5Gclose); }
inline Handle dataset_handle(hid_t id) { return Handle(id, H5Dclose); }
inline Handle space_handle(hid_t id) { return Handle(id, H5Sclose); }
inline Handle type_handle(hid_t id) { return Handle(id, H5Tclose); }
inline Handle plist_handle(hid_t id) { return Handle(id, H5Pclose); }

// Held for the whole of an entry point. It serialises frix's use of HDF5 (a serial HDF5
// build is not thread-safe) and turns off HDF5's automatic printing of its error stack
// (frix never prints), restoring the caller's handler on exit so the process-wide HDF5
// state is left as found.
class Session {
   public:
    Session();
    ~Session();
    Session(const Session &) = delete;
    Session &operator=(const Session &) = delete;

   private:
    std::unique_lock<std::mutex> lock_;
    H5E_auto2_t saved_func_ = nullptr;
    void *saved_data_ = nullptr;
    bool saved_ = false;
};

// The description of the innermost error on HDF5's error stack (where the failure was
// first detected, e.g. "file signature not found"), or "" when the stack is empty. Must be
// called right after the failing HDF5 call: the next HDF5 call clears the stack.
std::string hdf5_error_detail();

// Where HDF5's 8-byte signature (and so the superblock) starts: offset 0, or after a user
// block of 512, 1024, 2048, ... bytes, as HDF5 itself searches; -1 when there is none.
long hdf5_signature_offset(std::FILE *file);

}  // namespace frix::fclib
