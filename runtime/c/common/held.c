/* <standalone> */
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include "macros.h"
#include "held.h"
/* </standalone> */
/* ---- the bytes a stream framer holds between feeds ---------------------------------------- */

/* The n bytes held after head moved to the front, in pieces no longer than head, the gap they
 * close: no piece overlaps where it goes, so memcpy moves them and a firmware links no memmove.
 * One piece when fewer bytes are held than were framed, as in a stream's steady state (the
 * part of one message after whole ones); more only while a message much longer than those
 * framed before it is still arriving, once. */
static void urwire__to_front(uint8_t *buf, size_t head, size_t n)
{
    size_t done, piece;
    if (n <= head) {  /* the steady state's one piece, without the loop */
        memcpy(buf, buf + head, n);
        return;
    }
    for (done = 0; done < n; done += piece) {
        piece = n - done < head ? n - done : head;
        memcpy(buf + done, buf + head + done, piece);
    }
}

/* The one way the stream framers (RTDE's, the real-time interface's) take bytes in: buf holds
 * `length` bytes, of which those before `head` are framed already; `base` is the stream offset
 * of buf[0]. The framed bytes are dropped (base moves past them), then as many of data's n bytes
 * as fit in the buffer's capacity are appended. Returns how many it took: fewer than n when the
 * buffer is full, and the caller frames what is held before it feeds the rest. */
URWIRE__PRIVATE size_t urwire__hold(uint8_t *buf, size_t capacity, size_t *head, size_t *length, uint64_t *base,
                                    const uint8_t *data, size_t n)
{
    size_t take;
    if (*head) {
        urwire__to_front(buf, *head, *length - *head);
        *length -= *head;
        *base += *head;
        *head = 0;
    }
    take = n < capacity - *length ? n : capacity - *length;
    if (take)
        memcpy(buf + *length, data, take);
    *length += take;
    return take;
}
