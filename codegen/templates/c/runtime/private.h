/* <standalone> */
#ifndef URWIRE_RUNTIME_PRIVATE_H
#define URWIRE_RUNTIME_PRIVATE_H
#include <string.h>
#include "runtime_spec.h"
#include "value.h"
#include "visitor.h"
/* </standalone> */
/* ---- what the runtime and the generated layouts share ------------------------------------- */

/* Private functions live in urwire.c alone. */
#define URWIRE__PRIVATE static
/* <standalone> */
#undef URWIRE__PRIVATE
#define URWIRE__PRIVATE /* a runtime file compiled on its own exports them to its unit tests */
/* </standalone> */

#define URWIRE__COUNT(a) (sizeof(a) / sizeof((a)[0]))

/* One field of a fixed run of fields, read after one bounds check of the whole run. A table
 * of them (ended by a NULL path) names the field that a short run stops in. */
typedef struct urwire__span {
    const char *path;
    uint32_t offset;
    uint32_t size;
} urwire__span;

/* ---- the tables the generated part fills ---- */

/* What each layout (a sub-package or a message subtype) has: a decoder into its struct, an
 * encoder from it and a visitor of it, all taking the struct as void *. */
typedef bool (*urwire__decode_fn)(const uint8_t *msg, size_t *at, size_t end, urwire_sw_version version,
                                  void *out, urwire_error *err);
typedef bool (*urwire__encode_fn)(const void *in, urwire_sw_version version, uint8_t *out, size_t cap,
                                  size_t *at, urwire_error *err);
typedef void (*urwire__visit_fn)(const void *in, urwire_sw_version version, const urwire_visitor *v);

/* A sub-package type, indexed by its code; name is NULL for a code with no layout. Its decoder
 * is reached through the generated urwire__decode_package(type, ...) and, into a robot state,
 * urwire__decode_member(type, ...): switches, for speed (see there). */
typedef struct urwire__package_kind {
    const char *name;               /* the record's type: "joint_data" */
    urwire__encode_fn encode;
    urwire__visit_fn visit;
} urwire__package_kind;

/* A top-level message type with a layout: a list of sub-packages, or a common header and a
 * subtype byte that chooses the layout of the rest. */
typedef struct urwire__message_type {
    uint8_t code;                   /* urwire_message_type */
    bool packages;                  /* a list of sub-packages (no header, no subtype) */
    size_t body;                    /* where the subtype's layout starts: the header's size */
    const urwire__span *header;     /* the header's fields, for a message too short for them */
    /* Reads the header into m->header and returns the subtype code. */
    int64_t (*read_header)(urwire_message *m);
    /* The header's fields, the subtype first when it is not named by a layout. */
    void (*visit_header)(const urwire_message *m, bool subtype, const urwire_visitor *v);
    /* Writes m->header into out[0..body). */
    void (*put_header)(const urwire_message *m, uint8_t *out);
} urwire__message_type;

/* An urwire_message_kind, indexed by it: the record's type and the functions of its layout
 * (NULL for the unknown kinds and for a sub-package list, which the runtime walks itself). */
typedef struct urwire__message_kind {
    const char *name;                   /* "version", "robot_state", "unknown" */
    const urwire__message_type *type;   /* NULL for the unknown kinds */
    int64_t subtype;                    /* its code in its type's subtype byte */
    urwire__decode_fn decode;
    urwire__encode_fn encode;
    urwire__visit_fn visit;
} urwire__message_kind;

/* A range of software versions; a missing bound is open. */
typedef struct urwire__versions {
    bool has_low;
    urwire_sw_version low;
    bool has_high;
    urwire_sw_version high;
} urwire__versions;

/* How the data of a global-variable value type is laid out, whatever its code. */
typedef enum urwire__layout {
    URWIRE__LAYOUT_EMPTY,
    URWIRE__LAYOUT_SCALAR,
    URWIRE__LAYOUT_ARRAY,
    URWIRE__LAYOUT_STRING,
    URWIRE__LAYOUT_LIST,
    URWIRE__LAYOUT_MATRIX
} urwire__layout;

/* The items of a SCALAR or ARRAY value. */
typedef enum urwire__item {
    URWIRE__ITEM_NONE,
    URWIRE__ITEM_BOOL,
    URWIRE__ITEM_I32,
    URWIRE__ITEM_F32
} urwire__item;

typedef struct urwire__value_entry {
    uint8_t code;
    urwire_value_kind kind;
    const char *name;
    urwire__layout layout;
    urwire__item item;
    uint8_t count;                  /* array items */
} urwire__value_entry;

/* The value types of a range of software versions. */
typedef struct urwire__value_table {
    urwire__versions versions;
    const urwire__value_entry *entries;
    size_t count;
} urwire__value_table;

/* Text written into a caller's buffer, cut to fit; n counts what did not fit too. */
typedef struct urwire__text {
    char *out;
    size_t cap;
    size_t n;
} urwire__text;

/* ---- the runtime's functions that other files call, file by file ---- */
/* (A helper that only its own file calls is static there.) */

/* views.c */
URWIRE__PRIVATE urwire_bytes urwire__view(const uint8_t *ptr, size_t len);
URWIRE__PRIVATE urwire_seq urwire__seq(const uint8_t *msg, size_t pos, urwire_sw_version version, int terminator);
URWIRE__PRIVATE urwire_bytes urwire__seq_bytes(const urwire_seq *s);
/* version.c */
URWIRE__PRIVATE int urwire__version_cmp(urwire_sw_version v, int major, int minor);
URWIRE__PRIVATE bool urwire__in_versions(urwire_sw_version v, const urwire__versions *range);
/* format.c */
URWIRE__PRIVATE size_t urwire__digits(char *buf, int64_t v);
URWIRE__PRIVATE void urwire__str(urwire__text *t, const char *s);
URWIRE__PRIVATE void urwire__num(urwire__text *t, int64_t v);
URWIRE__PRIVATE void urwire__hex2(urwire__text *t, int64_t v);
/* errors.c */
URWIRE__PRIVATE bool urwire__fail(urwire_error *e, urwire_status status, size_t offset, const char *path,
                                  int64_t value, int64_t left);
URWIRE__PRIVATE bool urwire__short(urwire_error *e, const char *path, size_t offset, size_t need, size_t end);
URWIRE__PRIVATE bool urwire__short_in_run(urwire_error *e, const urwire__span *run, size_t pos, size_t end);
URWIRE__PRIVATE bool urwire__no_space(urwire_error *e, size_t pos, size_t need, size_t cap);
URWIRE__PRIVATE bool urwire__within(urwire_error *e, const char *name, size_t index);
URWIRE__PRIVATE bool urwire__within2(urwire_error *e, const char *name, size_t index, size_t index2, bool two);
/* text.c */
URWIRE__PRIVATE bool urwire__read_prefixed(const uint8_t *msg, size_t *at, size_t end, size_t size, bool is_signed,
                                           const char *path, urwire_bytes *out, urwire_error *err);
URWIRE__PRIVATE void urwire__read_texts(const uint8_t *msg, size_t *at, size_t end, uint8_t terminator,
                                        urwire_seq *out);
/* put.c */
URWIRE__PRIVATE bool urwire__put_view(uint8_t *out, size_t cap, size_t *pos, urwire_bytes b, urwire_error *err);
URWIRE__PRIVATE bool urwire__put_prefixed(uint8_t *out, size_t cap, size_t *pos, size_t size, uint64_t max,
                                          urwire_bytes b, const char *path, urwire_error *err);
/* values.c */
URWIRE__PRIVATE const urwire__value_table *urwire__values_of(urwire_sw_version v);
URWIRE__PRIVATE const urwire__value_entry *urwire__value_entry_of(const urwire__value_table *t, uint8_t code);
URWIRE__PRIVATE bool urwire__read_values(const uint8_t *msg, size_t *at, size_t end, urwire_sw_version version,
                                         uint8_t terminator, const char *path, urwire_seq *out, urwire_error *err);
/* kinds.c */
URWIRE__PRIVATE const urwire__message_type *urwire__message_type_of(uint8_t code);
URWIRE__PRIVATE const urwire__message_kind *urwire__message_kind_of(urwire_message_kind kind);
URWIRE__PRIVATE const urwire__package_kind *urwire__package_kind_of(uint8_t type);
URWIRE__PRIVATE const urwire__message_type *urwire__header_type(const urwire_message *m);
/* visit.c */
URWIRE__PRIVATE void urwire__visit_texts(const urwire_seq *names, const char *key, const urwire_visitor *v);
URWIRE__PRIVATE void urwire__visit_values(const urwire_seq *values, const char *key, const urwire_visitor *v);
/* <standalone> */
#endif
/* </standalone> */
