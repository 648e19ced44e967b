/* <standalone> */
#include <stddef.h>
#include <string.h>
#include "macros.h"
#include "buffer.h"
/* </standalone> */
/* ---- a text written into the caller's bounded buffer -------------------------------------- */

/* Appends n bytes; those past the buffer's end (cap - 1, room for the NUL) are counted only. */
URWIRE__PRIVATE void urwire__bytes(urwire__text *t, const char *p, size_t n)
{
    size_t room = t->cap > t->n + 1 ? t->cap - t->n - 1 : 0;
    if (room > 0)
        memcpy(t->out + t->n, p, n < room ? n : room);
    t->n += n;
}

URWIRE__PRIVATE void urwire__str(urwire__text *t, const char *s)
{
    urwire__bytes(t, s, strlen(s));
}

/* Ends the text with a NUL (when cap > 0) and returns the length it needed: when that is cap or
 * more, the buffer holds its first cap - 1 bytes. */
URWIRE__PRIVATE size_t urwire__end(urwire__text *t)
{
    if (t->cap > 0)
        t->out[t->n < t->cap ? t->n : t->cap - 1] = '\0';
    return t->n;
}
