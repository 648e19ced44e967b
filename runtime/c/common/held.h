/* <standalone> */
#ifndef URWIRE_RUNTIME_HELD_H
#define URWIRE_RUNTIME_HELD_H
#include <stddef.h>
#include <stdint.h>
#include "macros.h"
/* </standalone> */
/* ---- the bytes a stream framer holds between feeds (held.c) ------------------------------- */

URWIRE__PRIVATE size_t urwire__hold(uint8_t *buf, size_t capacity, size_t *head, size_t *length, uint64_t *base,
                                    const uint8_t *data, size_t n);
/* <standalone> */
#endif
/* </standalone> */
