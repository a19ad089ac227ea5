/* Compiled, never run, by the abi_plugin_table test: every member of the frozen version-1
 * table (abi/frix_plugin_table_v1.h) keeps its offset and type in frix_plugin_table. */
#include <stddef.h>

#include "frix_plugin_table_v1.h"

#define FRIX_SAME_MEMBER(m)                                                                 \
    _Static_assert(offsetof(frix_plugin_table, m) == offsetof(frix_plugin_table_v1, m),     \
                   "frix_plugin_table." #m " moved: members may only be appended");         \
    _Static_assert(__builtin_types_compatible_p(__typeof__(((frix_plugin_table *)0)->m),    \
                                                __typeof__(((frix_plugin_table_v1 *)0)->m)), \
                   "frix_plugin_table." #m " changed type (or the function it points to did)");
FRIX_PLUGIN_TABLE_V1_MEMBERS(FRIX_SAME_MEMBER)

_Static_assert(sizeof(frix_plugin_table) >= sizeof(frix_plugin_table_v1), "the table shrank");
