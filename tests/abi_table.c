/* Compiled, never run, by the abi_plugin_table test: every member of each frozen table version
 * (abi/frix_plugin_table_v1.h to _v6.h) keeps its offset and type in frix_plugin_table. */
#include <stddef.h>

#include "frix_plugin_table_v1.h"
#include "frix_plugin_table_v2.h"
#include "frix_plugin_table_v3.h"
#include "frix_plugin_table_v4.h"
#include "frix_plugin_table_v5.h"
#include "frix_plugin_table_v6.h"

#define FRIX_SAME_MEMBER_OF(frozen, m)                                                     \
    _Static_assert(offsetof(frix_plugin_table, m) == offsetof(frozen, m),                   \
                   "frix_plugin_table." #m " moved: members may only be appended");         \
    _Static_assert(__builtin_types_compatible_p(__typeof__(((frix_plugin_table *)0)->m),    \
                                                __typeof__(((frozen *)0)->m)),              \
                   "frix_plugin_table." #m " changed type (or the function it points to did)");
#define FRIX_SAME_MEMBER_V1(m) FRIX_SAME_MEMBER_OF(frix_plugin_table_v1, m)
#define FRIX_SAME_MEMBER_V2(m) FRIX_SAME_MEMBER_OF(frix_plugin_table_v2, m)
#define FRIX_SAME_MEMBER_V3(m) FRIX_SAME_MEMBER_OF(frix_plugin_table_v3, m)
#define FRIX_SAME_MEMBER_V4(m) FRIX_SAME_MEMBER_OF(frix_plugin_table_v4, m)
#define FRIX_SAME_MEMBER_V5(m) FRIX_SAME_MEMBER_OF(frix_plugin_table_v5, m)
#define FRIX_SAME_MEMBER_V6(m) FRIX_SAME_MEMBER_OF(frix_plugin_table_v6, m)
FRIX_PLUGIN_TABLE_V1_MEMBERS(FRIX_SAME_MEMBER_V1)
FRIX_PLUGIN_TABLE_V2_MEMBERS(FRIX_SAME_MEMBER_V2)
FRIX_PLUGIN_TABLE_V3_MEMBERS(FRIX_SAME_MEMBER_V3)
FRIX_PLUGIN_TABLE_V4_MEMBERS(FRIX_SAME_MEMBER_V4)
FRIX_PLUGIN_TABLE_V5_MEMBERS(FRIX_SAME_MEMBER_V5)
FRIX_PLUGIN_TABLE_V6_MEMBERS(FRIX_SAME_MEMBER_V6)

_Static_assert(sizeof(frix_plugin_table) >= sizeof(frix_plugin_table_v6), "the table shrank");
/* Version 1 is a prefix of version 2: the library serves it as the table cut before the first
 * member of version 2. */
_Static_assert(offsetof(frix_plugin_table_v2, persistent_create) >= sizeof(frix_plugin_table_v1),
               "version 2 does not extend version 1");
_Static_assert(offsetof(frix_plugin_table_v3, persistent_set_contacts_local) >= sizeof(frix_plugin_table_v2),
               "version 3 does not extend version 2");
_Static_assert(offsetof(frix_plugin_table_v4, option_choice_name) >= sizeof(frix_plugin_table_v3),
               "version 4 does not extend version 3");
_Static_assert(offsetof(frix_plugin_table_v5, problem_rolling_local) >= sizeof(frix_plugin_table_v4),
               "version 5 does not extend version 4");
_Static_assert(offsetof(frix_plugin_table_v6, problem_spinning_local) >= sizeof(frix_plugin_table_v5),
               "version 6 does not extend version 5");
