// The check of a libfrix handle's release (src/handle_header.hpp) before it is read.
#include "mpi/distributed.hpp"
#include "src/error_state.hpp"

namespace frix {
namespace mpi {

frix_error check_release(const HandleHeader &given, const HandleHeader &own, const char *where, const char *what) {
    if (given.size == own.size && given.version == own.version) return FRIX_OK;
    const auto major = [](uint32_t v) { return v / 10000; };
    const auto minor = [](uint32_t v) { return v / 100 % 100; };
    const auto patch = [](uint32_t v) { return v % 100; };
    return fail(FRIX_ERR_UNSUPPORTED,
                "%s: libfrix %u.%u.%u made the %s (a record of %u bytes), and this is libfrix_mpi %u.%u.%u "
                "(%u bytes): libfrix and libfrix_mpi must come from the same release",
                where, major(given.version), minor(given.version), patch(given.version), what, given.size,
                major(own.version), minor(own.version), patch(own.version), own.size);
}

}  // namespace mpi
}  // namespace frix
