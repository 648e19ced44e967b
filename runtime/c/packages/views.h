/* <standalone> */
#ifndef URWIRE_RUNTIME_VIEWS_H
#define URWIRE_RUNTIME_VIEWS_H
#include <stddef.h>
#include <stdint.h>
#include "version.h"
/* </standalone> */
/* ---- views -------------------------------------------------------------------------------- */

/* Bytes inside the caller's buffer: never copied, never owned. */
typedef struct urwire_bytes {
    const uint8_t *ptr;
    size_t len;
} urwire_bytes;

/* A run of repeated items inside a message, walked by an urwire_next_*() function. The
 * message was checked whole when decoded, so iteration meets no surprises; copy the seq
 * and iterate the copy to walk it again. */
typedef struct urwire_seq {
    const uint8_t *msg;      /* first byte of the message (offsets count from here) */
    size_t pos;              /* next item */
    size_t end;              /* end of the items */
    size_t count;            /* items left */
    urwire_sw_version version; /* the stream's software version when decoded */
    int terminator;          /* value lists and names: byte after each top-level item, else -1 */
} urwire_seq;
/* <standalone> */
#endif
/* </standalone> */
