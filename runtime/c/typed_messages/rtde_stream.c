/* RTDE stream framing. See rtde_stream.h. */
#include "rtde_stream.h"

#include "../common/held.h"

void rtde_stream_init(rtde_stream *s)
{
    s->head = 0;
    s->length = 0;
    s->base = 0;
    s->scanning = false;
    s->finished = false;
}

size_t rtde_stream_feed(rtde_stream *s, const uint8_t *data, size_t n)
{
    return urwire__hold(s->buf, sizeof s->buf, &s->head, &s->length, &s->base, data, n);
}

void rtde_stream_finish(rtde_stream *s)
{
    s->finished = true;
}

/* A header some message could have: the library's own test (rtde_message_size). */
static bool plausible(const uint8_t *p)
{
    size_t size;
    return rtde_message_size(p, RTDE_HEADER_SIZE, &size) != RTDE_BAD_HEADER;
}

rtde_frame_kind rtde_stream_next(rtde_stream *s, rtde_frame *out)
{
    while (s->length - s->head >= RTDE_HEADER_SIZE) {
        const uint8_t *p = s->buf + s->head;
        size_t size = 0;
        rtde_error e = rtde_message_size(p, s->length - s->head, &size);
        if (e == RTDE_BAD_HEADER) {
            /* One fault per scan, however the bytes were cut: a scan that ran out of bytes goes
             * on silently when more come. */
            bool report = !s->scanning;
            if (report) {
                out->bytes = p;
                out->length = RTDE_HEADER_SIZE;
                out->offset = s->base + s->head;
                out->size = size;       /* rtde_message_size reads it before it judges it */
                out->code = p[2];
            }
            s->scanning = true;
            s->head++;
            while (s->length - s->head >= RTDE_HEADER_SIZE && !plausible(s->buf + s->head))
                s->head++;
            if (report)
                return RTDE_FRAME_BAD_HEADER;
            continue;
        }
        s->scanning = false;
        if (e == RTDE_NEED_MORE)
            break;
        out->bytes = p;
        out->length = size;
        out->offset = s->base + s->head;
        s->head += size;
        return RTDE_FRAME_MESSAGE;
    }
    if (!s->finished)
        return RTDE_FRAME_NEED_MORE;
    if (s->length > s->head) {
        out->bytes = s->buf + s->head;
        out->length = s->length - s->head;
        out->offset = s->base + s->head;
        s->head = s->length;
        return RTDE_FRAME_TRUNCATED;
    }
    return RTDE_FRAME_END;
}
