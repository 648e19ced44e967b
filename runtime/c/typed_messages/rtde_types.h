/* ---- the RTDE API's basic types: limits, views, errors, values ----------------------------- */

/* Limits of the state rtde_conversation_init keeps in the conversation itself; define them before
 * including rtde.h to change them. rtde_conversation_init_in keeps the state in the caller's
 * storage instead, with limits given at run time, up to the protocol's own (RTDE_PROTOCOL_*).
 * Past a limit, rtde_decode returns RTDE_TOO_MANY for the message that does not fit, and no reply
 * is paired or data package read by a guess. */
#ifndef RTDE_MAX_RECIPES
#define RTDE_MAX_RECIPES 8          /* recipes kept per connection, both directions */
#endif
#ifndef RTDE_MAX_VARIABLES
#define RTDE_MAX_VARIABLES 64       /* variables in one recipe */
#endif
#ifndef RTDE_MAX_NAMES
#define RTDE_MAX_NAMES 2048         /* bytes of a setup's comma-separated names */
#endif

/* What the protocol itself can carry: a recipe id is a byte (256 recipes each way, and protocol
 * 1's one output recipe), and a message's size a uint16, so a setup's names are at most 65532
 * bytes and a reply names at most 13107 types (each at least "BOOL" and a comma). Limits this
 * large hold everything the robot and a client can say. */
#define RTDE_PROTOCOL_RECIPES 513
#define RTDE_PROTOCOL_VARIABLES 13107
#define RTDE_PROTOCOL_NAMES 65532

/* The limits of one connection's state. */
typedef struct rtde_limits {
    size_t recipes;                 /* recipes kept, both directions */
    size_t variables;               /* variables in one recipe */
    size_t names;                   /* bytes of one setup's comma-separated names */
} rtde_limits;

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
    RTDE_TOO_MANY,          /* more names, variables or recipes than the connection's limits hold */
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
