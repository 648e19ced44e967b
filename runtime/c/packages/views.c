/* <standalone> */
#include "runtime_support.h"
/* </standalone> */
/* ---- views -------------------------------------------------------------------------------- */

URWIRE__PRIVATE urwire_bytes urwire__view(const uint8_t *ptr, size_t len)
{
    urwire_bytes b;
    b.ptr = ptr;
    b.len = len;
    return b;
}

/* *s, an empty seq at pos; its decoder moves end and count on. Set in place, field by field:
 * a seq returned by value is built on the stack and copied, 36 bytes of a firmware's stack. */
URWIRE__PRIVATE void urwire__init_seq(urwire_seq *s, const uint8_t *msg, size_t pos, const urwire_sw_version *version,
                                      int terminator)
{
    s->msg = msg;
    s->pos = pos;
    s->end = pos;
    s->count = 0;
    s->version = *version;
    s->terminator = terminator;
}

/* The bytes of a seq's items, as they are encoded back. */
URWIRE__PRIVATE urwire_bytes urwire__seq_bytes(const urwire_seq *s)
{
    return urwire__view(s->msg + s->pos, s->end - s->pos);
}
