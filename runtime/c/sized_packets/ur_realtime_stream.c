/* Real-time stream framing. See ur_realtime_stream.h. */
#include "ur_realtime_stream.h"

#include <string.h>

#include "../common/held.h"

void ur_realtime_stream_init(ur_realtime_stream *s)
{
    memset(s->probe, 0, sizeof s->probe);
    s->head = 0;
    s->length = 0;
    s->base = 0;
    s->scanning = false;
    s->finished = false;
}

size_t ur_realtime_stream_feed(ur_realtime_stream *s, const uint8_t *data, size_t n)
{
    return urwire__hold(s->buf, sizeof s->buf, &s->head, &s->length, &s->base, data, n);
}

void ur_realtime_stream_finish(ur_realtime_stream *s)
{
    s->finished = true;
}

/* A packet could start at p: its size frames one and some layout has it, the decoder's own test
 * (a packet of that size, zeros after the size field, decodes). */
static bool plausible(ur_realtime_stream *s, const uint8_t *p)
{
    ur_realtime_packet packet;
    int32_t size = 0;
    if (ur_realtime_frame(p, UR_REALTIME_SIZE_FIELD_BYTES, &size) != UR_REALTIME_OK)
        return false;
    memcpy(s->probe, p, UR_REALTIME_SIZE_FIELD_BYTES);
    return ur_realtime_decode(s->probe, (size_t)size, 0, &packet) == UR_REALTIME_OK;
}

ur_realtime_frame_kind ur_realtime_stream_next(ur_realtime_stream *s, ur_realtime_stream_frame *out)
{
    int32_t size = 0;
    ur_realtime_error e;
    if (s->scanning) {
        /* A scan that runs out of bytes goes on silently when more come; at the end of the
         * stream the bytes left are the fault's. */
        while (s->length - s->head >= UR_REALTIME_SIZE_FIELD_BYTES && !plausible(s, s->buf + s->head))
            s->head++;
        if (s->length - s->head < UR_REALTIME_SIZE_FIELD_BYTES) {
            if (!s->finished)
                return UR_REALTIME_FRAME_NEED_MORE;
            s->head = s->length;
            return UR_REALTIME_FRAME_END;
        }
        s->scanning = false;
    }
    e = ur_realtime_frame(s->buf + s->head, s->length - s->head, &size);
    out->bytes = s->buf + s->head;
    out->offset = s->base + s->head;
    if (e == UR_REALTIME_E_SIZE_BELOW || e == UR_REALTIME_E_SIZE_ABOVE) {
        out->length = UR_REALTIME_SIZE_FIELD_BYTES;
        out->size = size;
        out->error = e;
        s->scanning = true;
        s->head++;
        return UR_REALTIME_FRAME_BAD_SIZE;
    }
    if (e == UR_REALTIME_E_SHORT || (size_t)size > s->length - s->head) {
        if (!s->finished)
            return UR_REALTIME_FRAME_NEED_MORE;
        if (s->length == s->head)
            return UR_REALTIME_FRAME_END;
        out->length = s->length - s->head;
        out->needed = e == UR_REALTIME_E_SHORT ? UR_REALTIME_SIZE_FIELD_BYTES : (size_t)size;
        s->head = s->length;
        return UR_REALTIME_FRAME_TRUNCATED;
    }
    out->length = (size_t)size;
    s->head += (size_t)size;
    return UR_REALTIME_FRAME_PACKET;
}
