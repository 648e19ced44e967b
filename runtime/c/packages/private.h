/* <standalone> */
#ifndef URWIRE_RUNTIME_PRIVATE_H
#define URWIRE_RUNTIME_PRIVATE_H
#include <string.h>
#include "macros.h"
#include "buffer.h"
#include "version_text.h"
#include "runtime_spec.h"
#include "value.h"
#include "visitor.h"
/* </standalone> */
/* ---- what the runtime and the generated layouts share ------------------------------------- */

/* A range of software versions; a missing bound is open. */
typedef struct urwire__versions {
    bool has_low;
    urwire_sw_version low;
    bool has_high;
    urwire_sw_version high;
} urwire__versions;

#define URWIRE__COUNT(a) (sizeof(a) / sizeof((a)[0]))

/* Tests that the robot-state fast path passes (or fails) almost always: gcc and clang then lay
 * that path out straight, with no jump taken (a few ns per robot state). */
#if defined(__GNUC__)
#define URWIRE__LIKELY(x) __builtin_expect(!!(x), 1)
#define URWIRE__UNLIKELY(x) __builtin_expect(!!(x), 0)
#else
#define URWIRE__LIKELY(x) (x)
#define URWIRE__UNLIKELY(x) (x)
#endif

/* A software version as one number that orders as the spec's (major, minor, bugfix) tuples do
 * against every version the spec names: the generated conditions are one comparison with
 * URWIRE__V(major, minor, bugfix) of a bound. Each part counts from -1 (0 stands for any
 * negative part) and stops just past the largest the spec could name (a major above 2^21, or a
 * minor or bugfix above 2^20, compares with every bound as that limit does). */
#define URWIRE__V(major, minor, bugfix) \
    (((uint64_t)(major) + 1u) << 42 | ((uint64_t)(minor) + 1u) << 21 | ((uint64_t)(bugfix) + 1u))

/* The version key is inlined where speed is asked for (-O2, -O3); at -Os (__OPTIMIZE_SIZE__) it
 * is one function: inlined, its 64-bit shifts and compares cost a 32-bit CPU some 100 bytes at
 * each of the dozen places that key a version. */
#if defined(__OPTIMIZE_SIZE__) && defined(__GNUC__)
#define URWIRE__KEY_INLINE static __attribute__((noinline, unused))
#else
#define URWIRE__KEY_INLINE URWIRE__INLINE
#endif

URWIRE__INLINE uint64_t urwire__version_part(int part, int most)
{
    return part < 0 ? 0u : part > most ? (uint64_t)most + 1u : (uint64_t)part + 1u;
}

URWIRE__KEY_INLINE uint64_t urwire__version_key(urwire_sw_version v)
{
    /* Every real version in one test: no part negative or above 2^20. */
    if (URWIRE__LIKELY(((unsigned)v.major | (unsigned)v.minor | (unsigned)v.bugfix) <= 1u << 20))
        return URWIRE__V((unsigned)v.major, (unsigned)v.minor, (unsigned)v.bugfix);
    return urwire__version_part(v.major, 1 << 21) << 42 | urwire__version_part(v.minor, 1 << 20) << 21 |
           urwire__version_part(v.bugfix, 1 << 20);
}

/* A field's path where an error names it, as the generated part spells it. A build with
 * URWIRE_NO_NAMES (-DURWIRE_NO_NAMES) names no field: its errors keep their status, offset,
 * numbers and the indexes of their path, with every name empty, and a firmware then links none
 * of the names (with the smaller span rows below, 3.5 KB of flash on Cortex-M4 -Os for the
 * pinned robot-state firmware). */
#if defined(URWIRE_NO_NAMES)
#define URWIRE__NAME(text) ""
#else
#define URWIRE__NAME(text) text
#endif

/* One field of a fixed run of fields, read after one bounds check of the whole run. A table
 * of them (ended by a row of size 0) names the field that a short run stops in. A group's
 * elements after the first are one repeat row: size URWIRE__REPEAT | the number of elements,
 * offset the stride, index the number of rows of element 0, just before it
 * (urwire__short_in_run). Built with URWIRE_NO_NAMES, a span has no path: 4 bytes, not 8, on a
 * 32-bit CPU. The generated tables spell each row URWIRE__SPAN(path, offset, size, index). */
typedef struct urwire__span {
#if !defined(URWIRE_NO_NAMES)
    const char *path;               /* an element's: its index left out, "joints[].q_actual" */
#endif
    uint16_t offset;                /* within a layout: the generator refuses larger ones */
    uint8_t size;
    uint8_t index;                  /* the element's, that goes into the path's "[]"; else: */
} urwire__span;
#define URWIRE__NO_INDEX 0xffu
#define URWIRE__REPEAT 0x80u
#if defined(URWIRE_NO_NAMES)
#define URWIRE__SPAN(path, offset, size, index) {offset, size, index}
#define URWIRE__SPAN_PATH(s) ""
#else
#define URWIRE__SPAN(path, offset, size, index) {path, offset, size, index}
#define URWIRE__SPAN_PATH(s) ((s)->path)
#endif

/* A software version as the layouts read it: the version, and its key (urwire__version_key),
 * which their version conditions compare. */
typedef struct urwire__ver {
    urwire_sw_version version;
    uint64_t key;
} urwire__ver;

URWIRE__KEY_INLINE urwire__ver urwire__ver_of(urwire_sw_version version)
{
    urwire__ver v;
    v.version = version;
    v.key = urwire__version_key(version);
    return v;
}

/* What must stay out of line so that its locals do not weigh on every path through its caller
 * (a firmware's stack is the deepest path's frames added up). */
#if defined(__GNUC__)
#define URWIRE__NOINLINE __attribute__((noinline))
#else
#define URWIRE__NOINLINE
#endif

/* ---- the tables the generated part fills ---- */

/* What each layout (a sub-package or a message subtype) has: a decoder into its struct, an
 * encoder from it and a visitor of it, all taking the struct as void *. */
typedef bool (*urwire__decode_fn)(const uint8_t *msg, size_t *at, size_t end, const urwire__ver *ver, void *out,
                                  urwire_error *err);
typedef bool (*urwire__encode_fn)(const void *in, const urwire__ver *ver, uint8_t *out, size_t cap, size_t *at,
                                  urwire_error *err);
typedef void (*urwire__visit_fn)(const void *in, const urwire__ver *ver, const urwire_visitor *v);

/* A sub-package layout, indexed by its urwire_package_layout; its decoders (the layout's, or one
 * per form) are reached through the generated urwire__decode_package(form, ...) and, into a
 * robot state, urwire__decode_member(type, form, ...): switches, for speed (see there). */
typedef struct urwire__package_kind {
    const char *name;               /* the record's type: "joint_data" */
    urwire__encode_fn encode;
    urwire__visit_fn visit;
} urwire__package_kind;

/* One form a type code takes on the wire (the plan's Variant): the layout it is read in, the
 * exact body sizes it can have (nsizes of them; none: open-ended, at least min_size), and rep,
 * the version a stream is taken to run when this form is recognised by its length alone. */
typedef struct urwire__form {
    uint8_t layout;                 /* a urwire_package_layout, or a urwire_message_kind */
    uint8_t nsizes;
    uint32_t sizes[URWIRE__FORM_SIZES];
    uint32_t min_size;
    urwire_sw_version rep;
} urwire__form;

/* Whether a body of `size` bytes fits a form (inlined on the robot-state fast path). */
URWIRE__INLINE bool urwire__fits(const urwire__form *f, size_t size)
{
    uint8_t k;
    if (f->nsizes == 0)
        return size >= f->min_size;
    for (k = 0; k < f->nsizes; k++)
        if (f->sizes[k] == size)
            return true;
    return false;
}

/* The robot-state fast path's brief of the version's form of each sub-package type
 * (urwire__package_first_sizes): its first exact size, or URWIRE__OPEN(its least size) when
 * it is open-ended, or URWIRE__NONE when the version sends no form of that type. */
#define URWIRE__OPEN(least) (0x80000000u | (least))
#define URWIRE__NONE URWIRE__OPEN(0x7fffffffu)

/* Whether a body of `size` bytes fits such a brief (URWIRE__NONE never does). */
URWIRE__INLINE bool urwire__fits_brief(uint32_t brief, size_t size)
{
    return brief == size || ((brief & 0x80000000u) && size >= (brief & 0x7fffffffu));
}

/* A body size that exactly one fixed-size form of a type code has, and that form's index among
 * the code's forms: a body of that size alone says which form it is. */
typedef struct urwire__recognised {
    uint32_t size;
    uint8_t form;
} urwire__recognised;

/* The forms of one type code, in a table of all the forms of its type byte (count 0: the code
 * has no layout), and the sizes that recognise one of them. */
typedef struct urwire__forms {       /* the pointers first: no padding between the counts */
    const urwire__form *forms;
    const urwire__recognised *by_length;
    uint8_t count;
    uint8_t nby_length;
} urwire__forms;

/* The forms of the codes of one type byte (sub-package types, or the subtypes of a message):
 * `codes` by code, and which form each segment of the version axis sends, `mine[segment *
 * ncodes + code]`: its number in `all` plus one, 0 for none. */
/* In a segment's row: the form is that of the nearest version below (no form is sent there). */
#define URWIRE__NEAREST 0x80u

typedef struct urwire__form_table {
    const urwire__form *all;
    const urwire__forms *codes;
    size_t ncodes;
    const uint8_t *mine;
} urwire__form_table;

/* The bits a robot state's fast path gathers, in registers, before they go to its
 * urwire_robot_state (urwire__fast_member). */
typedef struct urwire__fast_bits {
    uint32_t present;
    uint32_t malformed;
    uint32_t layouts;
} urwire__fast_bits;

/* How to reach the numbers of a Version message before its layout is chosen: fixed bytes,
 * then a string whose length prefix has `prefix` bytes (signed or not). */
typedef struct urwire__version_skip {
    uint8_t fixed;
    uint8_t prefix;
    bool is_signed;
} urwire__version_skip;

/* A top-level message type with a layout: a list of sub-packages, or a common header and a
 * subtype byte that chooses the layout of the rest. */
typedef struct urwire__message_type {
    uint8_t code;                   /* urwire_message_type */
    bool packages;                  /* a list of sub-packages (no header, no subtype) */
    size_t body;                    /* where the subtype's layout starts: the header's size */
    const urwire__form_table *forms; /* its subtypes' */
    const urwire__span *header;     /* the header's fields, for a message too short for them */
    /* Reads the header into m->header and returns the subtype code; NULL for a body message:
     * one layout right after the message header, with no header fields and no subtype byte,
     * code 0 of its form table. */
    int64_t (*read_header)(urwire_message *m);
} urwire__message_type;

/* The other header functions of a message type (NULL for a body message), in a table of their
 * own indexed as the types (urwire__message_headers): a firmware that only decodes links
 * neither them nor what they call. */
typedef struct urwire__message_header {
    /* The header's fields, the subtype first when it is not named by a layout. */
    void (*visit)(const urwire_message *m, bool subtype, const urwire_visitor *v);
    /* Writes m->header into out[0..body). */
    void (*put)(const urwire_message *m, uint8_t *out);
} urwire__message_header;

/* An urwire_message_kind, indexed by it: the record's type and the functions of its layout
 * (NULL for the unknown kinds and for a sub-package list, which the runtime walks itself).
 * Its decoder is in urwire__message_decoders, indexed the same way: decoding links neither the
 * encoders nor the visitors. */
typedef struct urwire__message_kind {
    const char *name;                   /* "version", "robot_state", "unknown" */
    const urwire__message_type *type;   /* NULL for the unknown kinds */
    urwire__encode_fn encode;
    urwire__visit_fn visit;
} urwire__message_kind;


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

typedef struct urwire__value_entry {   /* widest first: no padding between the bytes */
    const char *name;
    urwire_value_kind kind;
    urwire__layout layout;
    urwire__item item;
    uint8_t code;
    uint8_t count;                  /* array items */
} urwire__value_entry;

/* The value types of a range of software versions (urwire__value_ranges, beside them). */
typedef struct urwire__value_table {
    const urwire__value_entry *entries;
    size_t count;
    size_t min_size;                /* the fewest bytes a value takes: bounds LIST/MATRIX counts */
} urwire__value_table;

/* ---- the runtime's functions that other files call, file by file ---- */
/* (A helper that only its own file calls is static there.) */

/* A function that only some layouts call (the global variables' names and values): a subset of the
 * spec (python -m codegen --select) may call none, and that is no warning. */
#if defined(__GNUC__)
#define URWIRE__OPTIONAL URWIRE__PRIVATE __attribute__((unused))
#else
#define URWIRE__OPTIONAL URWIRE__PRIVATE
#endif

/* views.c */
URWIRE__PRIVATE urwire_bytes urwire__view(const uint8_t *ptr, size_t len);
URWIRE__PRIVATE void urwire__init_seq(urwire_seq *s, const uint8_t *msg, size_t pos, const urwire_sw_version *version,
                                      int terminator);
URWIRE__OPTIONAL urwire_bytes urwire__seq_bytes(const urwire_seq *s);
/* version.c */
URWIRE__PRIVATE int urwire__version_cmp(urwire_sw_version v, int major, int minor, int bugfix);
URWIRE__PRIVATE bool urwire__in_versions(urwire_sw_version v, const urwire__versions *range);
URWIRE__PRIVATE size_t urwire__table_index(urwire_sw_version v, const urwire__versions *ranges, size_t count);
/* format.c */
URWIRE__PRIVATE size_t urwire__digits(char *buf, int64_t v);
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
URWIRE__OPTIONAL void urwire__read_texts(const uint8_t *msg, size_t *at, size_t end, uint8_t terminator,
                                         urwire_seq *out);
/* put.c */
URWIRE__PRIVATE bool urwire__put_view(uint8_t *out, size_t cap, size_t *pos, urwire_bytes b, urwire_error *err);
URWIRE__PRIVATE bool urwire__put_prefixed(uint8_t *out, size_t cap, size_t *pos, size_t size, uint64_t max,
                                          urwire_bytes b, const char *path, urwire_error *err);
/* values.c */
URWIRE__PRIVATE const urwire__value_table *urwire__values_of(urwire_sw_version v);
URWIRE__PRIVATE const urwire__value_entry *urwire__value_entry_of(const urwire__value_table *t, uint8_t code);
URWIRE__OPTIONAL bool urwire__read_values(const uint8_t *msg, size_t *at, size_t end, const urwire_sw_version *version,
                                          uint8_t terminator, const char *path, urwire_seq *out, urwire_error *err);
/* kinds.c */
URWIRE__PRIVATE const urwire__message_type *urwire__message_type_of(uint8_t code);
URWIRE__PRIVATE const urwire__message_kind *urwire__message_kind_of(urwire_message_kind kind);
URWIRE__PRIVATE const urwire__package_kind *urwire__package_kind_of(urwire_package_layout layout);
URWIRE__PRIVATE const urwire__message_type *urwire__header_type(const urwire_message *m);
URWIRE__PRIVATE const urwire__message_header *urwire__header_of(const urwire__message_type *t);
/* forms.c */
URWIRE__PRIVATE size_t urwire__segment(uint64_t key);
URWIRE__PRIVATE const urwire__form *urwire__mine(const urwire__form_table *t, size_t segment, size_t code,
                                                bool *nearest);
URWIRE__PRIVATE const urwire__form *urwire__choose(const urwire__form_table *t, size_t code, size_t segment,
                                                  size_t size, urwire_sw_version *version, bool *by_length);
URWIRE__PRIVATE bool urwire__peek_version(const uint8_t *msg, size_t len, urwire_sw_version *out);
/* decode.c */
URWIRE__PRIVATE bool urwire__decode_announced(const uint8_t *bytes, size_t len, urwire_sw_version *version,
                                              void *out);
URWIRE__PRIVATE bool urwire__next_package_layout(urwire_seq *seq, size_t *at, const urwire__form **f, urwire__ver *use,
                                                 void *as, bool *failed);
/* Room for a sub-package's layout alone, where the rest of a urwire_package is not wanted: in
 * doubles, aligned for any layout. */
#define URWIRE__LAYOUT_DOUBLES ((sizeof ((urwire_package *)0)->as + sizeof(double) - 1) / sizeof(double))
URWIRE__PRIVATE bool urwire__implied_version(const uint8_t *msg, size_t len, urwire_sw_version *version);
/* visit.c */
URWIRE__OPTIONAL void urwire__visit_texts(const urwire_seq *names, const char *key, const urwire_visitor *v);
URWIRE__OPTIONAL void urwire__visit_values(const urwire_seq *values, const char *key, const urwire_visitor *v);
/* <standalone> */
#endif
/* </standalone> */
