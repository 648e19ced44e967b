/* <standalone> */
#ifndef URWIRE_RUNTIME_UTF8_H
#define URWIRE_RUNTIME_UTF8_H
#include <stddef.h>
#include <stdint.h>
#include "macros.h"
/* </standalone> */
/* ---- UTF-8 read as Python reads it, each invalid part replaced (utf8.c) ------------------- */

URWIRE__PRIVATE size_t urwire__utf8_sequence(const uint8_t *p, size_t n, size_t *bad);
/* <standalone> */
#endif
/* </standalone> */
