/* <standalone> */
#include "runtime_support.h"
/* </standalone> */
/* ---- decoding messages -------------------------------------------------------------------- */
/* The one sub-package list is URWIRE__PACKAGES_TYPE, decoded as URWIRE__PACKAGES_KIND; its
 * sub-packages go through the generated switches urwire__decode_package and, on the robot-state
 * fast path, urwire__decode_member. */

/* The kind of a subtype of type t. */
static urwire_message_kind urwire__subtype_kind(const urwire__message_type *t, int64_t subtype)
{
    int k;
    for (k = 0; k < (int)URWIRE__COUNT(urwire__message_kinds); k++)
        if (urwire__message_kinds[k].type == t && urwire__message_kinds[k].subtype == subtype)
            return (urwire_message_kind)k;
    return URWIRE_KIND_UNKNOWN_SUBTYPE;
}

static void urwire__init_message(urwire_message *out, const uint8_t *bytes, size_t len, urwire_sw_version version)
{
    out->bytes = bytes;
    out->length = len;
    out->message_type = len > URWIRE__TYPE_AT ? bytes[URWIRE__TYPE_AT] : 0;
    out->failed = false;
    out->error.status = URWIRE_OK;
    out->error.path[0] = '\0';
    out->raw = urwire__view(bytes, 0);
    out->packages = urwire__seq(bytes, len, version, -1);
    out->version = version;
}

static void urwire__fail_message(urwire_message *out, size_t raw_from)
{
    out->failed = true;
    out->raw = urwire__view(out->bytes + raw_from, out->length - raw_from);
}

/* Checks the sub-package header at pos; false (and *err set) when it cannot be framed. */
static bool urwire__frame_package(const uint8_t *msg, size_t pos, size_t end, size_t *size, urwire_error *err)
{
    size_t left = end - pos;
    int64_t declared;
    if (left < URWIRE_PACKAGE_HEADER_SIZE)
        return urwire__fail(err, URWIRE_E_PACKAGE_HEADER_CUT, pos, "package", URWIRE_PACKAGE_HEADER_SIZE,
                            (int64_t)left);
    declared = URWIRE__PACKAGE_LENGTH(msg + pos);
    if (declared < (int64_t)URWIRE_PACKAGE_HEADER_SIZE)
        return urwire__fail(err, URWIRE_E_PACKAGE_LENGTH_LOW, pos, "package", declared, 0);
    if ((uint64_t)declared > left)
        return urwire__fail(err, URWIRE_E_PACKAGE_LENGTH_HIGH, pos, "package", declared, (int64_t)left);
    *size = (size_t)declared;
    return true;
}

/* A robot state: frames the sub-packages by their lengths; each is decoded when iterated. */
static bool urwire__decode_packages(urwire_message *out, urwire_sw_version version)
{
    const uint8_t *msg = out->bytes;
    size_t pos = URWIRE_HEADER_SIZE, end = out->length, size = 0;
    out->kind = URWIRE__PACKAGES_KIND;
    out->packages = urwire__seq(msg, pos, version, -1);
    while (pos < end && urwire__frame_package(msg, pos, end, &size, &out->error)) {
        pos += size;
        out->packages.count++;
    }
    out->packages.end = pos;
    if (pos < end) {
        urwire__fail_message(out, pos);
        return false;
    }
    return true;
}

/* A message with a common header and a subtype: the header, then the subtype's layout. */
static bool urwire__decode_subtype(urwire_message *out, const urwire__message_type *t, urwire_sw_version version)
{
    const urwire__message_kind *k;
    size_t pos = t->body;
    if (out->length < t->body) {
        out->kind = URWIRE_KIND_UNKNOWN_MESSAGE;
        urwire__short_in_run(&out->error, t->header, 0, out->length);
        urwire__fail_message(out, URWIRE_HEADER_SIZE);
        return false;
    }
    out->kind = urwire__subtype_kind(t, t->read_header(out));
    k = &urwire__message_kinds[out->kind];
    if (k->decode == NULL) {
        out->raw = urwire__view(out->bytes + t->body, out->length - t->body);
        return true;
    }
    if (!k->decode(out->bytes, &pos, out->length, version, &out->as, &out->error)) {
        urwire__fail_message(out, t->body);
        return false;
    }
    return true;
}

bool urwire_decode_message(const uint8_t *bytes, size_t len, urwire_sw_version version, urwire_message *out)
{
    const urwire__message_type *t;
    urwire__init_message(out, bytes, len, version);
    if (len < URWIRE_HEADER_SIZE) {
        /* The framer never hands out such a message; a direct caller may. */
        out->kind = URWIRE_KIND_UNKNOWN_MESSAGE;
        out->message_type = 0;
        out->failed = true;
        out->raw = urwire__view(bytes, len);
        return urwire__short(&out->error, "length", 0, URWIRE_HEADER_SIZE, len);
    }
    out->message_type = bytes[URWIRE__TYPE_AT];
    t = urwire__message_type_of(out->message_type);
    if (t == NULL) {
        out->kind = URWIRE_KIND_UNKNOWN_MESSAGE;
        out->raw = urwire__view(bytes + URWIRE_HEADER_SIZE, len - URWIRE_HEADER_SIZE);
        return true;
    }
    return t->packages ? urwire__decode_packages(out, version) : urwire__decode_subtype(out, t, version);
}

/* One framed sub-package straight into its member of a robot state. */
static void urwire__decode_into_state(const uint8_t *msg, size_t pos, size_t stop, urwire_sw_version version,
                                      urwire_robot_state *out)
{
    uint8_t type = msg[pos + URWIRE__PACKAGE_TYPE_AT];
    urwire_error err;
    size_t body = pos + URWIRE_PACKAGE_HEADER_SIZE;
    /* urwire__package_kind_of(type) == NULL, spelt out: gcc -Os calls it, and the call made
     * the whole fast path a third slower there. */
    if (type >= URWIRE__COUNT(urwire__package_kinds) || urwire__package_kinds[type].name == NULL)
        out->unknown++;
    else if (urwire__decode_member(type, msg, &body, stop, version, out, &err))
        out->present |= (uint32_t)URWIRE_BIT(type);
    else
        out->malformed |= (uint32_t)URWIRE_BIT(type);
}

bool urwire_next_package(urwire_seq *seq, urwire_package *out)
{
    const uint8_t *msg = seq->msg;
    const urwire__package_kind *k;
    size_t pos = seq->pos, body, stop;
    int64_t size;
    if (seq->count == 0 || seq->end - pos < URWIRE_PACKAGE_HEADER_SIZE)
        return false;
    size = URWIRE__PACKAGE_LENGTH(msg + pos);
    if (size < (int64_t)URWIRE_PACKAGE_HEADER_SIZE || (uint64_t)size > seq->end - pos)
        return false;  /* not reached for a seq from urwire_decode_message */
    body = pos + URWIRE_PACKAGE_HEADER_SIZE;
    stop = pos + (size_t)size;
    out->type = msg[pos + URWIRE__PACKAGE_TYPE_AT];
    out->version = seq->version;
    out->offset = pos;
    out->raw = urwire__view(msg + body, stop - body);
    out->error.status = URWIRE_OK;
    k = urwire__package_kind_of(out->type);
    out->known = k != NULL;
    out->failed = k != NULL && !urwire__decode_package(out->type, msg, &body, stop, seq->version, &out->as,
                                                        &out->error);
    seq->pos = stop;
    seq->count--;
    return true;
}

bool urwire_decode_robot_state(const urwire_message *m, urwire_robot_state *out)
{
    const urwire_seq *seq = &m->packages;
    size_t pos, count;
    out->present = 0;
    out->malformed = 0;
    out->unknown = 0;
    if (m->kind != URWIRE__PACKAGES_KIND)
        return false;
    /* The frames were checked by urwire_decode_message. */
    for (pos = seq->pos, count = seq->count; count > 0; count--) {
        size_t stop = pos + (size_t)URWIRE__PACKAGE_LENGTH(seq->msg + pos);
        urwire__decode_into_state(seq->msg, pos, stop, seq->version, out);
        pos = stop;
    }
    return !m->failed && out->malformed == 0;
}

bool urwire_decode_robot_state_message(const uint8_t *bytes, size_t len, urwire_sw_version version,
                                       urwire_message *m, urwire_robot_state *out)
{
    size_t pos = URWIRE_HEADER_SIZE, size = 0, count = 0;
    out->present = 0;
    out->malformed = 0;
    out->unknown = 0;
    if (len < URWIRE_HEADER_SIZE || bytes[URWIRE__TYPE_AT] != URWIRE__PACKAGES_TYPE) {
        urwire_decode_message(bytes, len, version, m);
        return false;
    }
    urwire__init_message(m, bytes, len, version);
    m->kind = URWIRE__PACKAGES_KIND;
    m->packages = urwire__seq(bytes, pos, version, -1);
    /* One pass: framing each sub-package and decoding it overlap in the CPU. */
    while (pos < len && urwire__frame_package(bytes, pos, len, &size, &m->error)) {
        urwire__decode_into_state(bytes, pos, pos + size, version, out);
        pos += size;
        count++;
    }
    m->packages.count = count;
    m->packages.end = pos;
    if (pos < len)
        urwire__fail_message(m, pos);
    return !m->failed && out->malformed == 0;
}

bool urwire_message_has_error(const urwire_message *m)
{
    urwire_seq seq;
    urwire_package pkg;
    if (m->failed)
        return true;
    if (m->kind != URWIRE__PACKAGES_KIND)
        return false;
    seq = m->packages;
    while (urwire_next_package(&seq, &pkg))
        if (pkg.failed)
            return true;
    return false;
}
