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

/* An empty seq at pos; its decoder moves end and count on. */
URWIRE__PRIVATE urwire_seq urwire__seq(const uint8_t *msg, size_t pos, urwire_sw_version version, int terminator)
{
    urwire_seq s;
    s.msg = msg;
    s.pos = pos;
    s.end = pos;
    s.count = 0;
    s.version = version;
    s.terminator = terminator;
    return s;
}

/* The bytes of a seq's items, as they are encoded back. */
URWIRE__PRIVATE urwire_bytes urwire__seq_bytes(const urwire_seq *s)
{
    return urwire__view(s->msg + s->pos, s->end - s->pos);
}
