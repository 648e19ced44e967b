/* RTDE stream framing: one direction of a connection, its bytes in as they arrive, whole messages
 * out, as the primary framer (runtime/c/framer.c) frames the primary interface. After a header no
 * message has, the framer scans byte by byte to the next plausible one; the bytes it skips belong
 * to that one fault, however the stream was cut. C runtime beside the RTDE parser
 * (generated/c/rtde.{h,c}), not joined into it: urwire-decode compiles it. */
#ifndef RTDE_STREAM_H
#define RTDE_STREAM_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "rtde.h"

/* The buffer holds the largest message a uint16 size allows, and one byte more, so that a feed
 * after the frames are drained always takes a byte. */
#define RTDE_STREAM_BUFFER 65536

typedef enum rtde_frame_kind {
    RTDE_FRAME_NEED_MORE,           /* feed more bytes (or finish) */
    RTDE_FRAME_MESSAGE,             /* bytes and length: one whole message, to rtde_decode */
    RTDE_FRAME_BAD_HEADER,          /* size and code: a header no message has (a scan follows) */
    RTDE_FRAME_TRUNCATED,           /* length: the bytes the finished stream ended with, short of
                                       a message or of a header */
    RTDE_FRAME_END                  /* finished and drained */
} rtde_frame_kind;

typedef struct rtde_frame {
    const uint8_t *bytes;           /* in the stream's buffer: valid until the next feed */
    size_t length;
    uint64_t offset;                /* of the message or fault, from the direction's first byte */
    size_t size;                    /* a bad header's size field */
    uint8_t code;                   /* a bad header's type code */
} rtde_frame;

/* One direction's framing state and bytes. 64 KiB: static or inside a static struct. */
typedef struct rtde_stream {
    uint8_t buf[RTDE_STREAM_BUFFER];
    size_t head;                    /* first byte not yet framed */
    size_t length;                  /* bytes held */
    uint64_t base;                  /* offset of buf[0] in the direction's stream */
    bool scanning;                  /* after a bad header: looking for the next plausible one */
    bool finished;
} rtde_stream;

void rtde_stream_init(rtde_stream *s);
/* Copies up to n bytes in; returns how many it took (fewer when the buffer is full: call
 * rtde_stream_next until RTDE_FRAME_NEED_MORE, then feed the rest). */
size_t rtde_stream_feed(rtde_stream *s, const uint8_t *data, size_t n);
/* The stream has ended: what is left comes out as one RTDE_FRAME_TRUNCATED. */
void rtde_stream_finish(rtde_stream *s);
rtde_frame_kind rtde_stream_next(rtde_stream *s, rtde_frame *out);

#endif
