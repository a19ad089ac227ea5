// The first member of the handles libfrix_mpi reads by layout (frix_options, frix_info,
// frix_problem): the record's size and the release of the library that made it.
// libfrix_mpi holds its own copy of the library's objects and reads the host's handles with
// its copy's layout, which another release may change; so every frix_mpi_* that receives
// such a handle first compares this header with its own (mpi/handles.cpp). The header stays
// the first member, of this type, in every release: that is what makes it readable.
#pragma once

#include <frix/frix_version.h>

#include <cstdint>

namespace frix {

struct HandleHeader {
    uint32_t size;     // sizeof the record in the library that made it
    uint32_t version;  // FRIX_VERSION_NUMBER of that library
};

// The header of a Record made by this library (a default member initializer: set by every
// construction, whoever constructs it).
template <class Record>
constexpr HandleHeader header_of() {
    return {(uint32_t)sizeof(Record), (uint32_t)FRIX_VERSION_NUMBER};
}

}  // namespace frix
