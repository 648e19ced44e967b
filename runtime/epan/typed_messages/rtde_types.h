/* The shapes of the tables the generator writes for an RTDE dissector (packet-rtde.c): message
 * layouts by type code, direction and protocol version, their steps, value types and the variable
 * table. Joined into the generated file before its tables; runtime/epan/typed_messages/rtde_state.c and
 * rtde_dissect.c walk them. */
/* <standalone> */
#include <glib.h>
/* </standalone> */

/* What a step keeps of its value for the conversation's state (runtime/epan/typed_messages/rtde_state.c). */
typedef enum {
    RTDE_SLOT_NONE,
    RTDE_SLOT_PROTOCOL_VERSION,
    RTDE_SLOT_ACCEPTED,
    RTDE_SLOT_RECIPE_ID,
    RTDE_SLOT_VARIABLES,
    RTDE_SLOT_TYPES
} rtde_slot;

typedef enum {
    RTDE_STEP_SCALAR,           /* size bytes, big-endian */
    RTDE_STEP_PREFIXED_TEXT,    /* a size-byte length, then that many bytes of text */
    RTDE_STEP_REST_TEXT,        /* text to the end of the message */
    RTDE_STEP_NAMES,            /* names joined by commas, to the end of the message */
    RTDE_STEP_VALUES            /* the values of the message's recipe */
} rtde_step_kind;

typedef struct {
    rtde_step_kind kind;
    int field;                  /* index into hf_rtde */
    guint8 size;                /* a scalar's size, or a text's length prefix */
    gboolean integer;           /* a scalar read as an integer (kept for the state) */
    rtde_slot slot;
    const char *name;           /* the field's name, for the expert of a message cut short */
    const char *unit;           /* text after a scalar's value, as the Lua dissector appends it */
} rtde_step;

/* What a message means to the conversation's state. */
typedef enum {
    RTDE_ROLE_NONE,
    RTDE_ROLE_VERSION_REQUEST,
    RTDE_ROLE_VERSION_REPLY,
    RTDE_ROLE_SETUP_REQUEST,    /* of recipe kind `kind` */
    RTDE_ROLE_SETUP_REPLY,      /* of recipe kind `kind` */
    RTDE_ROLE_START_REPLY,
    RTDE_ROLE_DATA              /* values by the recipe of its direction's kind */
} rtde_role;

typedef struct {
    const char *name;
    const char *label;
    rtde_role role;
    int kind;                   /* the recipe kind of a setup message, else -1 */
    gboolean recipe_id_first;   /* a data package whose first byte is its recipe id */
    const rtde_step *steps;
    guint n_steps;
} rtde_layout;

/* One value of an RTDE type: count items of size bytes; `field` shows an item where a setup reply
 * types a variable otherwise than the variable table. */
typedef struct {
    const char *name;
    guint8 size;
    guint8 count;
    int field;
} rtde_value_type;

/* The variable table, sorted by name (byte order): a recipe finds each name's field once, when
 * its setup reply arrives, never per data package. */
typedef struct {
    const char *name;
    int field;
    const char *unit;           /* a double's unit, appended to its items' text; NULL for none */
    guint8 type;                /* its value type in the table (index into rtde_value_types) */
    guint8 n_flags;             /* its flags' fields, which follow its own in hf_rtde */
    const char *group;          /* a vector with named items: its subtree's text; its items' fields follow
                                 * `field`, one per item; NULL for another */
    const char *const *units;   /* the text after each named item's value, or NULL for none */
} rtde_variable;

typedef struct {
    guint8 code;
    const char *name;
    const char *label;
} rtde_undocumented;
