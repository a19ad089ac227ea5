// The version of the loaded library, for callers built against another header version.
#include <frix/frix.h>

extern "C" {
FRIX_API const char *frix_version_string(void) { return FRIX_VERSION_STRING; }
FRIX_API int frix_version_number(void) { return FRIX_VERSION_NUMBER; }
}
