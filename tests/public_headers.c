/* Compiled, never run, by the public_headers_* tests: the public headers must be valid C89,
 * C99 and C++ (no C++ types, no STL, no // comments, no trailing enum commas), with every
 * warning an error under -pedantic. */
#include <frix/frix.h>

int frix_public_headers_probe(const frix_plugin_table *t);
int frix_public_headers_probe(const frix_plugin_table *t) {
    return FRIX_PLUGIN_HAS(t, solve) && FRIX_VERSION_NUMBER > 0 && FRIX_OK == 0;
}
