/* Everything a runtime .c file of runtime/c/ sees when it is joined into
 * urwire.c, for the made-up protocol of runtime_spec.h: the runtime's headers, and in miniature
 * the private numbers and tables that the generated part of urwire.c defines. Included only
 * between a runtime file's <standalone> markers. */
#ifndef URWIRE_RUNTIME_SUPPORT_H
#define URWIRE_RUNTIME_SUPPORT_H

#include <string.h>

#include "runtime_spec.h"
#include "value.h"
#include "messages.h"
#include "visitor.h"
#include "framer.h"
#include "private.h"
#include "loads.h"
#include "held.h"

/* ---- the protocol's numbers ---- */

#define URWIRE__LENGTH(p) urwire__i32(p)
#define URWIRE__PUT_LENGTH(p, n) urwire__put_i32((p), (int32_t)(n))
#define URWIRE__TYPE_AT 4u
#define URWIRE__PACKAGE_LENGTH(p) urwire__i32(p)
#define URWIRE__PUT_PACKAGE_LENGTH(p, n) urwire__put_i32((p), (int32_t)(n))
#define URWIRE__PACKAGE_TYPE_AT 4u
#define URWIRE__PACKAGES_TYPE 16
#define URWIRE__PACKAGES_KIND URWIRE_KIND_STATE
/* No layout announces a version here: type 255 never frames (it is not a known type). */
#define URWIRE__VERSION_TYPE 255
#define URWIRE__VERSION_BODY 6u
#define URWIRE__VERSION_SUBTYPE_AT 5u
#define URWIRE__VERSION_SUBTYPE 0
#define URWIRE__VERSION_KIND URWIRE_KIND_UNKNOWN_SUBTYPE
#define URWIRE__VERSION_LAYOUT urwire_message  /* its struct: never decoded here */
#define URWIRE__VERSION_MAJOR(m) ((m)->version.major)
#define URWIRE__VERSION_MINOR(m) ((m)->version.minor)
#define URWIRE__VERSION_BUGFIX(m) 0
#define URWIRE__VERSION_TAIL 0u

/* ---- the tables ---- */

static const urwire__value_entry urwire__values_old[] = {
    {"NONE", URWIRE_VALUE_NONE, URWIRE__LAYOUT_EMPTY, URWIRE__ITEM_NONE, 0, 1},
    {"STRING", URWIRE_VALUE_STRING, URWIRE__LAYOUT_STRING, URWIRE__ITEM_NONE, 3, 1},
};

static const urwire__value_entry urwire__values_new[] = {
    {"NONE", URWIRE_VALUE_NONE, URWIRE__LAYOUT_EMPTY, URWIRE__ITEM_NONE, 0, 1},
    {"CONST_STRING", URWIRE_VALUE_STRING, URWIRE__LAYOUT_STRING, URWIRE__ITEM_NONE, 3, 1},
    {"POSE", URWIRE_VALUE_POSE, URWIRE__LAYOUT_ARRAY, URWIRE__ITEM_F32, 12, 6},
    {"BOOL", URWIRE_VALUE_BOOL, URWIRE__LAYOUT_SCALAR, URWIRE__ITEM_BOOL, 13, 1},
    {"NUM", URWIRE_VALUE_NUM, URWIRE__LAYOUT_SCALAR, URWIRE__ITEM_F32, 14, 1},
    {"INT", URWIRE_VALUE_INT, URWIRE__LAYOUT_SCALAR, URWIRE__ITEM_I32, 15, 1},
    {"LIST", URWIRE_VALUE_LIST, URWIRE__LAYOUT_LIST, URWIRE__ITEM_NONE, 17, 1},
    {"MATRIX", URWIRE_VALUE_MATRIX, URWIRE__LAYOUT_MATRIX, URWIRE__ITEM_NONE, 18, 1},
};

static const urwire__versions urwire__value_ranges[] = {
    {false, {0, 0, 0, false}, true, {3, 2, 999, false}},
    {true, {3, 3, 0, false}, false, {0, 0, 0, false}},
};

static const urwire__value_table urwire__value_tables[] = {
    {urwire__values_old, URWIRE__COUNT(urwire__values_old), 1},
    {urwire__values_new, URWIRE__COUNT(urwire__values_new), 1},
};

/* A layout of one scalar, as the generator writes layouts (struct as void *). */
#define URWIRE__ONE_SCALAR_LAYOUT(name, ctype, size, read, put)                                              \
    static inline bool urwire__decode_##name(const uint8_t *msg, size_t *at, size_t end,                       \
                                             const urwire__ver *ver, void *into, urwire_error *err)            \
    {                                                                                                          \
        urwire_##name *out = (urwire_##name *)into;                                                            \
        if (end - *at < size)                                                                                  \
            return urwire__short(err, "count", *at, size, end);                                                \
        out->count = read(msg + *at);                                                                          \
        out->version = ver->version;                                                                           \
        out->extra = urwire__view(msg + *at + size, end - *at - size);                                         \
        *at = end;                                                                                             \
        return true;                                                                                           \
    }                                                                                                          \
    static inline bool urwire__encode_##name(const void *from, const urwire__ver *ver, uint8_t *out,           \
                                             size_t cap, size_t *at, urwire_error *err)                        \
    {                                                                                                          \
        const urwire_##name *in = (const urwire_##name *)from;                                                 \
        (void)ver;                                                                                             \
        if (cap - *at < size)                                                                                  \
            return urwire__no_space(err, *at, size, cap);                                                      \
        put(out + *at, in->count);                                                                             \
        *at += size;                                                                                           \
        return urwire__put_view(out, cap, at, in->extra, err);                                                 \
    }                                                                                                          \
    static inline void urwire__visit_##name(const void *from, const urwire__ver *ver, const urwire_visitor *v) \
    {                                                                                                          \
        const urwire_##name *in = (const urwire_##name *)from;                                                 \
        (void)ver;                                                                                             \
        v->on_uint(v->ctx, "count", in->count);                                                                \
    }

URWIRE__ONE_SCALAR_LAYOUT(tally, uint16_t, 2u, urwire__u16, urwire__put_u16)
URWIRE__ONE_SCALAR_LAYOUT(counter, uint32_t, 4u, urwire__u32, urwire__put_u32)

static const urwire__package_kind urwire__package_kinds[] = {
    [URWIRE_LAYOUT_TALLY] = {"tally", urwire__encode_tally, urwire__visit_tally},
    [URWIRE_LAYOUT_COUNTER] = {"counter", urwire__encode_counter, urwire__visit_counter},
};

/* Forms: the version axis cut at 0.0.0, 3.2.1000 (after any 3.2.x) and 3.3.0, and past every
 * version, as the generator cuts it. */
static const uint64_t urwire__segment_bounds[] = {
    0u,
    URWIRE__V(0, 0, 0),
    URWIRE__V(3, 2, 1000),
    URWIRE__V(3, 3, 0),
    URWIRE__V(1048576, 0, 1),
};

/* Type 1: tally up to 3.2 (2 bytes), counter from 3.3 (4 bytes). */
static const urwire__form urwire__package_form_list[] = {
    {URWIRE_LAYOUT_TALLY, 1, {2, 0}, 2u, {3, 2, 999, false}},
    {URWIRE_LAYOUT_COUNTER, 1, {4, 0}, 4u, {5, 9, 0, false}},
};

/* Each size recognises one form. */
static const urwire__recognised urwire__package_by_length[] = {
    {2u, 0}, {4u, 1},
};

static const urwire__forms urwire__package_forms[] = {
    [1] = {&urwire__package_form_list[0], urwire__package_by_length, 2, 2},
};

static const uint8_t urwire__package_mine[] = {
    0, 0,  /* below 0.0.0 */
    0, 1,  /* from 0.0.0 */
    0, 1 | URWIRE__NEAREST,  /* from 3.2.1000: no form is sent; the nearest below */
    0, 2,  /* from 3.3.0 */
    0, 2 | URWIRE__NEAREST,  /* past every version */
};

static const urwire__form_table urwire__package_form_table = {
    urwire__package_form_list, urwire__package_forms, 2, urwire__package_mine,
};

static const uint32_t urwire__package_first_sizes[] = {
    URWIRE__NONE, URWIRE__NONE,  /* below 0.0.0 */
    URWIRE__NONE, 2u,            /* from 0.0.0 */
    URWIRE__NONE, URWIRE__NONE,  /* from 3.2.1000 */
    URWIRE__NONE, 4u,            /* from 3.3.0 */
    URWIRE__NONE, URWIRE__NONE,  /* past every version */
};

/* Type 1 in the form `form` (its number in urwire__package_form_list plus one). */
static inline bool urwire__decode_package(uint8_t form, const uint8_t *msg, size_t *at, size_t end,
                                          const urwire__ver *ver, void *into, urwire_error *err)
{
    if (urwire__package_form_list[form - 1].layout == URWIRE_LAYOUT_TALLY)
        return urwire__decode_tally(msg, at, end, ver, into, err);
    return urwire__decode_counter(msg, at, end, ver, into, err);
}

/* Type 1 in the form `form` (its number in urwire__package_form_list plus one). */
static inline bool urwire__decode_member(uint8_t type, uint8_t form, const uint8_t *msg, size_t *at, size_t end,
                                         const urwire__ver *ver, urwire_robot_state *out, urwire_error *err)
{
    (void)type;
    if (urwire__package_form_list[form - 1].layout == URWIRE_LAYOUT_TALLY) {
        out->layouts |= (uint32_t)URWIRE_BIT(URWIRE_LAYOUT_TALLY);
        return urwire__decode_tally(msg, at, end, ver, &out->tally, err);
    }
    out->layouts |= (uint32_t)URWIRE_BIT(URWIRE_LAYOUT_COUNTER);
    return urwire__decode_counter(msg, at, end, ver, &out->counter, err);
}

/* One fast path: the row from 3.3.0, where type 1 is a counter of 4 bytes; 5.9, the default
 * version, is in that segment. */
#define URWIRE__DEFAULT_SEGMENT 3u
#define URWIRE__ONE_FORM_A_CODE 0  /* several forms a code: the runtime chooses */
#define URWIRE__FAST_PATHS(X) X(1)
static const uint8_t urwire__package_fast_paths[] = {0, 0, 0, 1, 0};

static inline bool urwire__fast_member(int path, uint8_t type, size_t body_size, const uint8_t *msg, size_t *at,
                                       size_t end, const urwire__ver *ver, urwire_robot_state *out,
                                       urwire__fast_bits *bits, urwire_error *err)
{
    if (path != 1 || type != 1 || body_size != 4u)
        return false;
    bits->layouts |= (uint32_t)URWIRE_BIT(URWIRE_LAYOUT_COUNTER);
    if (urwire__decode_counter(msg, at, end, ver, &out->counter, err))
        bits->present |= (uint32_t)URWIRE_BIT(1);
    else
        bits->malformed |= (uint32_t)URWIRE_BIT(1);
    return true;
}

/* No Version message here: one skip of nothing. */
static const urwire__version_skip urwire__version_skips[] = {
    {0, 0, false},
};

static const urwire__message_type urwire__message_types[] = {
    {URWIRE__PACKAGES_TYPE, true, URWIRE_HEADER_SIZE, NULL, NULL, NULL},
};

static const urwire__message_header urwire__message_headers[] = {
    {NULL, NULL},
};

static const urwire__message_kind urwire__message_kinds[] = {
    [URWIRE_KIND_UNKNOWN_MESSAGE] = {"unknown", NULL, NULL, NULL},
    [URWIRE_KIND_STATE] = {"state", &urwire__message_types[0], NULL, NULL},
    [URWIRE_KIND_UNKNOWN_SUBTYPE] = {"unknown", NULL, NULL, NULL},
};

static const urwire__decode_fn urwire__message_decoders[] = {
    [URWIRE_KIND_UNKNOWN_MESSAGE] = NULL,
    [URWIRE_KIND_STATE] = NULL,
    [URWIRE_KIND_UNKNOWN_SUBTYPE] = NULL,
};

/* Types 16 (URWIRE__PACKAGES_TYPE) and 20, a bit each. */
static const uint8_t urwire__known_message_types[32] = {[2] = 0x11};

#endif
