/* <standalone> */
#ifndef URWIRE_RUNTIME_BUFFER_H
#define URWIRE_RUNTIME_BUFFER_H
#include <stddef.h>
#include "macros.h"
/* </standalone> */
/* ---- a text written into the caller's bounded buffer (buffer.c) --------------------------- */

typedef struct urwire__text {
    char *out;
    size_t cap;
    size_t n;                 /* the text's length, what did not fit too */
} urwire__text;

URWIRE__PRIVATE void urwire__bytes(urwire__text *t, const char *p, size_t n);
URWIRE__PRIVATE void urwire__str(urwire__text *t, const char *s);
URWIRE__PRIVATE size_t urwire__end(urwire__text *t);
/* <standalone> */
#endif
/* </standalone> */
