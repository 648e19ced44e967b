/* <standalone> */
#include "runtime_support.h"
/* </standalone> */
/* ---- the framer --------------------------------------------------------------------------- */

/* A header the spec could have sent: a length from the header's size to the maximum, and a
 * type it names (a bit of urwire__known_message_types). */
static urwire_status urwire__header_fault(int64_t length, uint8_t type)
{
    /* The type's bit, looked up first: so urwire_framer_next keeps Cortex-M0+'s frame at -O2. */
    unsigned known = (unsigned)urwire__known_message_types[type >> 3] >> (type & 7);
    if (length < (int64_t)URWIRE_HEADER_SIZE)
        return URWIRE_E_LENGTH_LOW;
    if (length > (int64_t)URWIRE_MAX_MESSAGE_LENGTH)
        return URWIRE_E_LENGTH_HIGH;
    return (known & 1u) != 0 ? URWIRE_OK : URWIRE_E_MESSAGE_TYPE;
}

void urwire_framer_init(urwire_framer *f, uint8_t *buf, size_t cap, urwire_sw_version hint)
{
    f->buf = buf;
    f->cap = cap;
    f->head = 0;
    f->len = 0;
    f->base = 0;
    f->skip = 0;
    f->resyncing = false;
    f->finished = false;
    f->ended_inside = false;
    f->version_seen = false;
    f->version_out_of_range = false;
    f->version = hint;
    f->unlearnt = 0;
}

/* The robot state handed out last, which ends at head, when the caller did not hand it back
 * decoded: the version its layout sizes show, from a walk over its sub-package headers. */
static void urwire__learn_unlearnt(urwire_framer *f)
{
    if (f->unlearnt) {
        urwire__implied_version(f->buf + f->head - f->unlearnt, f->unlearnt, &f->version);
        f->unlearnt = 0;
    }
}

void urwire_framer_learn(urwire_framer *f, const urwire_message *m)
{
    const urwire_sw_version *v = &f->version;
    /* Only that robot state, decoded in the version it was handed out with, tells the same. */
    if (f->unlearnt == 0 || m->bytes != f->buf + f->head - f->unlearnt || m->length != f->unlearnt ||
        m->kind != URWIRE__PACKAGES_KIND || m->version.major != v->major || m->version.minor != v->minor ||
        m->version.bugfix != v->bugfix || m->version.assumed != v->assumed)
        return;
    if (m->implied)
        f->version = m->implied_version;
    f->unlearnt = 0;
}

size_t urwire_framer_feed(urwire_framer *f, const uint8_t *data, size_t n)
{
    urwire__learn_unlearnt(f);  /* before its bytes move */
    return urwire__hold(f->buf, f->cap, &f->head, &f->len, &f->base, data, n);
}

void urwire_framer_finish(urwire_framer *f)
{
    f->finished = true;
}

void urwire_framer_restart(urwire_framer *f, uint64_t offset)
{
    urwire__learn_unlearnt(f);  /* before its bytes are dropped */
    f->head = f->len = 0;
    f->base = offset;
    f->skip = 0;
    f->resyncing = f->finished = f->ended_inside = false;
}

/* A fault at head; out of line, so that urwire_framer_next keeps one copy for its four. */
URWIRE__NOINLINE static urwire_frame_kind urwire__fault(urwire_framer *f, urwire_frame *out, urwire_status status,
                                                        int64_t value, int64_t left)
{
    out->kind = URWIRE_FRAME_FAULT;
    out->bytes = NULL;
    out->length = 0;
    out->offset = f->base + f->head;
    out->version = f->version;
    urwire__fail(&out->fault, status, (size_t)out->offset, "", value, left);
    return URWIRE_FRAME_FAULT;
}

/* Nothing whole to hand out: the end once the stream has finished (the bytes left, if any,
 * belong to a fault already reported), else a wait for more bytes. */
static urwire_frame_kind urwire__wait(urwire_framer *f, urwire_frame *out)
{
    if (f->finished)
        f->head = f->len;
    out->kind = f->finished ? URWIRE_FRAME_END : URWIRE_FRAME_NEED_MORE;
    return out->kind;
}

/* Where a rescan stops: a plausible header, and once the stream has ended inside a message,
 * one whose whole message is in the buffer (the headers passed belong to that fault). */
static bool urwire__rescan_stops_at(const urwire_framer *f, size_t at)
{
    int64_t length = URWIRE__LENGTH(f->buf + at);
    return urwire__header_fault(length, f->buf[at + URWIRE__TYPE_AT]) == URWIRE_OK &&
           (!f->ended_inside || (uint64_t)length <= f->len - at);
}

/* What a Version message announces (see urwire__learn_version). Its layout alone is decoded,
 * as urwire_decode_message would read it: a whole urwire_message here would cost the stack
 * of urwire_framer_next 500 bytes more. Every form of its subtype is that layout. */
static void urwire__learn_announced(urwire_framer *f, const uint8_t *bytes, size_t len)
{
    URWIRE__VERSION_LAYOUT announced;
    urwire_sw_version version = f->version;
    if (bytes[URWIRE__TYPE_AT] != URWIRE__VERSION_TYPE || len < URWIRE__VERSION_BODY ||
        bytes[URWIRE__VERSION_SUBTYPE_AT] != URWIRE__VERSION_SUBTYPE)
        return;
    if (urwire__decode_announced(bytes, len, &version, &announced)) {
        int bugfix = URWIRE__VERSION_BUGFIX(&announced);
        /* A bugfix out of range is set aside, as in every target: the stream goes on as
         * major.minor.0, flagged. */
        f->version_out_of_range = bugfix < 0 || bugfix > URWIRE_BUGFIX_ANY;
        f->version.major = URWIRE__VERSION_MAJOR(&announced);
        f->version.minor = URWIRE__VERSION_MINOR(&announced);
        f->version.bugfix = f->version_out_of_range ? 0 : bugfix;
        f->version.assumed = false;
        f->version_seen = true;
    }
}

/* What a message tells of the stream's software version, for the messages after it: the
 * layout that announces it (URWIRE__VERSION_*) sets it, bugfix included where its form has one
 * (their type and subtype bytes are looked at before anything is decoded); while the version
 * is only assumed, the layout sizes of a robot state may show it, learnt later: from the
 * caller's decoding (urwire_framer_learn), else by urwire__learn_unlearnt. The robot state,
 * nine messages in ten, is told apart inline; any other message costs a call. */
URWIRE__INLINE void urwire__learn_version(urwire_framer *f, const uint8_t *bytes, size_t len)
{
    if (URWIRE__LIKELY(bytes[URWIRE__TYPE_AT] == URWIRE__PACKAGES_TYPE)) {
        if (f->version.assumed)
            f->unlearnt = len;
        return;
    }
    urwire__learn_announced(f, bytes, len);
}

/* One straight pass: the rest of a message too big for the buffer is dropped, or the bytes after
 * a fault are scanned for a header (never both: a message is skipped only after a good header),
 * then the header at head is checked and its message handed out. */
urwire_frame_kind urwire_framer_next(urwire_framer *f, urwire_frame *out)
{
    size_t left, drop;
    int64_t length;
    urwire_status status;
    urwire__learn_unlearnt(f);
    if (f->skip) {
        left = f->len - f->head;
        drop = f->skip < left ? f->skip : left;
        f->head += drop;
        f->skip -= drop;
        if (f->skip)
            return urwire__wait(f, out);
    }
    if (f->resyncing) {
        while (f->len - f->head >= URWIRE_HEADER_SIZE && !urwire__rescan_stops_at(f, f->head))
            f->head++;
        if (f->len - f->head < URWIRE_HEADER_SIZE)
            return urwire__wait(f, out);
        f->resyncing = false;
    }
    left = f->len - f->head;
    if (left < URWIRE_HEADER_SIZE) {
        if (f->finished && left) {
            urwire__fault(f, out, URWIRE_E_TRUNCATED_HEADER, 0, (int64_t)left);
            f->head = f->len;
            return URWIRE_FRAME_FAULT;
        }
        return urwire__wait(f, out);
    }
    length = URWIRE__LENGTH(f->buf + f->head);
    status = urwire__header_fault(length, f->buf[f->head + URWIRE__TYPE_AT]);
    if (status != URWIRE_OK) {
        urwire__fault(f, out, status, status == URWIRE_E_MESSAGE_TYPE ? f->buf[f->head + URWIRE__TYPE_AT] : length, 0);
        f->resyncing = true;
        f->head++;
        return URWIRE_FRAME_FAULT;
    }
    if ((size_t)length > f->cap) {
        f->skip = (size_t)length;
        return urwire__fault(f, out, URWIRE_E_TOO_BIG_FOR_BUFFER, length, (int64_t)f->cap);
    }
    if ((size_t)length > left) {
        if (!f->finished)
            return urwire__wait(f, out);
        /* Every byte of the stream is here: the rest of the span is rescanned for the whole
         * messages it holds, one check per byte however the lengths nest. */
        urwire__fault(f, out, URWIRE_E_TRUNCATED_MESSAGE, length, (int64_t)left);
        f->ended_inside = f->resyncing = true;
        f->head++;
        return URWIRE_FRAME_FAULT;
    }
    out->kind = URWIRE_FRAME_MESSAGE;
    out->bytes = f->buf + f->head;
    out->length = (size_t)length;
    out->offset = f->base + f->head;
    out->version = f->version;
    urwire__learn_version(f, out->bytes, out->length);
    f->head += (size_t)length;
    return URWIRE_FRAME_MESSAGE;
}
