/* ---- the RTDE API's basic types: limits, views, errors, values ----------------------------- */

/* Limits of the caller-owned state (rtde_conversation); define them before including rtde.h to
 * change them. The guide bounds a setup's names at 2048 bytes. */
#ifndef RTDE_MAX_RECIPES
#define RTDE_MAX_RECIPES 8          /* recipes kept per connection, both directions */
#endif
#ifndef RTDE_MAX_VARIABLES
#define RTDE_MAX_VARIABLES 64       /* variables in one recipe */
#endif
#ifndef RTDE_MAX_NAMES
#define RTDE_MAX_NAMES 2048         /* bytes of a setup's comma-separated names */
#endif

/* Bytes in the caller's buffer: a text or a list of names, never copied. */
typedef struct rtde_text {
    const uint8_t *data;
    size_t length;
} rtde_text;

typedef enum rtde_error {
    RTDE_OK = 0,
    RTDE_NEED_MORE,         /* fewer bytes than the header or the message's size */
    RTDE_BAD_HEADER,        /* a size below the header's, or a type code no layout has */
    RTDE_SHORT,             /* the message ends inside a field */
    RTDE_EXTRA,             /* bytes after the layout */
    RTDE_UNKNOWN_TYPE,      /* a type code with no layout in this direction and protocol */
    RTDE_UNKNOWN_RECIPE,    /* a data package of a recipe this connection did not set up */
    RTDE_TOO_MANY,          /* more names, recipes or pending setups than the RTDE_MAX_* limits */
    RTDE_NO_ROOM            /* the output buffer is too small */
} rtde_error;

/* One value of a recipe: `count` items (6 for a VECTOR6D) of its type. */
typedef struct rtde_value {
    uint8_t type;           /* an rtde_value_type */
    uint8_t count;
    union {
        double f64;
        int64_t i64;        /* INT32 and the VECTOR6INT32 items */
        uint64_t u64;       /* BOOL, UINT8, UINT32, UINT64 and the VECTOR6UINT32 items */
    } item[6];
} rtde_value;
