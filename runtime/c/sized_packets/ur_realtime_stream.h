/* Real-time stream framing: a raw 30003 stream, its bytes in as they arrive, whole packets out, as
 * runtime/c/typed_messages/rtde_stream.c frames RTDE. After a size that frames no packet (below the
 * smallest or above the largest), the framer scans byte by byte to the next plausible packet (the
 * next size some layout has), as python/urwire/realtime.py does; the bytes it skips belong to that
 * one fault, however the stream was cut, and a scan that reaches the end takes the rest with it.
 * C runtime beside the real-time parser (generated/c/ur_realtime.{h,c}), not joined into it:
 * urwire-decode compiles it. */
#ifndef UR_REALTIME_STREAM_H
#define UR_REALTIME_STREAM_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "ur_realtime.h"

/* The buffer holds the largest packet and 64 KiB more, so that a feed after the frames are
 * drained always takes a byte, and takes many packets at once. */
#define UR_REALTIME_STREAM_BUFFER (UR_REALTIME_MAX_MESSAGE_SIZE + 65536)

typedef enum ur_realtime_frame_kind {
    UR_REALTIME_FRAME_NEED_MORE,    /* feed more bytes (or finish) */
    UR_REALTIME_FRAME_PACKET,       /* bytes and length: one whole packet, to ur_realtime_decode (which
                                       says UR_REALTIME_E_UNKNOWN_SIZE when no layout has its size) */
    UR_REALTIME_FRAME_BAD_SIZE,     /* size and error: a size that frames no packet (a scan follows) */
    UR_REALTIME_FRAME_TRUNCATED,    /* length and needed: the bytes the finished stream ended with,
                                       short of a packet or of a size field */
    UR_REALTIME_FRAME_END           /* finished and drained */
} ur_realtime_frame_kind;

typedef struct ur_realtime_stream_frame {
    const uint8_t *bytes;           /* in the stream's buffer: valid until the next feed */
    size_t length;
    uint64_t offset;                /* of the packet or fault, from the stream's first byte */
    int32_t size;                   /* a bad size as declared */
    ur_realtime_error error;        /* a bad size: UR_REALTIME_E_SIZE_BELOW or UR_REALTIME_E_SIZE_ABOVE */
    size_t needed;                  /* a truncated tail: the size it declared, or the size field's bytes */
} ur_realtime_stream_frame;

/* The stream's framing state and bytes. About 90 KiB: static or inside a static struct. */
typedef struct ur_realtime_stream {
    uint8_t buf[UR_REALTIME_STREAM_BUFFER];
    uint8_t probe[UR_REALTIME_MAX_MESSAGE_SIZE];  /* a packet of a size to try: zeros after the size */
    size_t head;                    /* first byte not yet framed */
    size_t length;                  /* bytes held */
    uint64_t base;                  /* offset of buf[0] in the stream */
    bool scanning;                  /* after a bad size: looking for the next plausible packet */
    bool finished;
} ur_realtime_stream;

void ur_realtime_stream_init(ur_realtime_stream *s);
/* Copies up to n bytes in; returns how many it took (fewer when the buffer is full: call
 * ur_realtime_stream_next until UR_REALTIME_FRAME_NEED_MORE, then feed the rest). */
size_t ur_realtime_stream_feed(ur_realtime_stream *s, const uint8_t *data, size_t n);
/* The stream has ended: what is left comes out as one UR_REALTIME_FRAME_TRUNCATED (or, after a bad
 * size whose scan found no packet, goes with that fault). */
void ur_realtime_stream_finish(ur_realtime_stream *s);
ur_realtime_frame_kind ur_realtime_stream_next(ur_realtime_stream *s, ur_realtime_stream_frame *out);

#endif
