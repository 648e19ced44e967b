/* Everything a runtime .c file of codegen/templates/c/runtime/ sees when it is joined into
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
#define URWIRE__VERSION_MAJOR(m) ((m)->version.major)
#define URWIRE__VERSION_MINOR(m) ((m)->version.minor)

/* ---- the tables ---- */

static const urwire__value_entry urwire__values_old[] = {
    {0, URWIRE_VALUE_NONE, "NONE", URWIRE__LAYOUT_EMPTY, URWIRE__ITEM_NONE, 1},
    {3, URWIRE_VALUE_STRING, "STRING", URWIRE__LAYOUT_STRING, URWIRE__ITEM_NONE, 1},
};

static const urwire__value_entry urwire__values_new[] = {
    {0, URWIRE_VALUE_NONE, "NONE", URWIRE__LAYOUT_EMPTY, URWIRE__ITEM_NONE, 1},
    {3, URWIRE_VALUE_STRING, "CONST_STRING", URWIRE__LAYOUT_STRING, URWIRE__ITEM_NONE, 1},
    {12, URWIRE_VALUE_POSE, "POSE", URWIRE__LAYOUT_ARRAY, URWIRE__ITEM_F32, 6},
    {13, URWIRE_VALUE_BOOL, "BOOL", URWIRE__LAYOUT_SCALAR, URWIRE__ITEM_BOOL, 1},
    {14, URWIRE_VALUE_NUM, "NUM", URWIRE__LAYOUT_SCALAR, URWIRE__ITEM_F32, 1},
    {15, URWIRE_VALUE_INT, "INT", URWIRE__LAYOUT_SCALAR, URWIRE__ITEM_I32, 1},
    {17, URWIRE_VALUE_LIST, "LIST", URWIRE__LAYOUT_LIST, URWIRE__ITEM_NONE, 1},
    {18, URWIRE_VALUE_MATRIX, "MATRIX", URWIRE__LAYOUT_MATRIX, URWIRE__ITEM_NONE, 1},
};

static const urwire__value_table urwire__value_tables[] = {
    {{false, {0, 0}, true, {3, 2}}, urwire__values_old, URWIRE__COUNT(urwire__values_old)},
    {{true, {3, 3}, false, {0, 0}}, urwire__values_new, URWIRE__COUNT(urwire__values_new)},
};

static inline bool urwire__decode_counter(const uint8_t *msg, size_t *at, size_t end, urwire_sw_version version,
                                          void *into, urwire_error *err)
{
    urwire_counter *out = (urwire_counter *)into;
    (void)version;
    if (end - *at < 4u)
        return urwire__short(err, "count", *at, 4u, end);
    out->count = urwire__u32(msg + *at);
    out->extra = urwire__view(msg + *at + 4, end - *at - 4);
    *at = end;
    return true;
}

static inline bool urwire__encode_counter(const void *from, urwire_sw_version version, uint8_t *out, size_t cap,
                                          size_t *at, urwire_error *err)
{
    const urwire_counter *in = (const urwire_counter *)from;
    (void)version;
    if (cap - *at < 4u)
        return urwire__no_space(err, *at, 4u, cap);
    urwire__put_u32(out + *at, in->count);
    *at += 4u;
    return urwire__put_view(out, cap, at, in->extra, err);
}

static inline void urwire__visit_counter(const void *from, urwire_sw_version version, const urwire_visitor *v)
{
    const urwire_counter *in = (const urwire_counter *)from;
    (void)version;
    v->on_uint(v->ctx, "count", in->count);
}

static const urwire__package_kind urwire__package_kinds[] = {
    [1] = {"counter", urwire__encode_counter, urwire__visit_counter},
};

static inline bool urwire__decode_package(uint8_t type, const uint8_t *msg, size_t *at, size_t end,
                                          urwire_sw_version version, void *into, urwire_error *err)
{
    return type == 1 && urwire__decode_counter(msg, at, end, version, into, err);
}

static inline bool urwire__decode_member(uint8_t type, const uint8_t *msg, size_t *at, size_t end,
                                         urwire_sw_version version, urwire_robot_state *out, urwire_error *err)
{
    return type == 1 && urwire__decode_counter(msg, at, end, version, &out->counter, err);
}

static const urwire__message_type urwire__message_types[] = {
    {URWIRE__PACKAGES_TYPE, true, URWIRE_HEADER_SIZE, NULL, NULL, NULL, NULL},
};

static const urwire__message_kind urwire__message_kinds[] = {
    [URWIRE_KIND_UNKNOWN_MESSAGE] = {"unknown", NULL, 0, NULL, NULL, NULL},
    [URWIRE_KIND_STATE] = {"state", &urwire__message_types[0], 0, NULL, NULL, NULL},
    [URWIRE_KIND_UNKNOWN_SUBTYPE] = {"unknown", NULL, 0, NULL, NULL, NULL},
};

static const bool urwire__known_message_types[256] = {
    [URWIRE__PACKAGES_TYPE] = true,
    [20] = true,
};

#endif
