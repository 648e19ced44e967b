/* The real-time interface as canonical JSON Lines (ur_realtime_json.h). */
#include "ur_realtime_json.h"

#include "cell_interface.h"
#include "json.h"

void ur_realtime_write_json(FILE *out, const ur_realtime_packet *p, size_t stream_offset)
{
    ur_realtime_write_record(out, NULL, p, stream_offset);
}

void ur_realtime_write_record(FILE *out, const envelope *e, const ur_realtime_packet *p, size_t stream_offset)
{
    const ur_realtime_slot *slots;
    size_t i, j, n;
    envelope_open(out, e);
    if (p->layout == UR_REALTIME_UNKNOWN) {
        fprintf(out, "\"type\": \"unknown\", \"message_size\": %ld, \"error\": \"packet at offset %lu: size %ld "
                     "matches no layout\", \"raw\": ", (long)p->message_size, (unsigned long)stream_offset,
                (long)p->message_size);
        json_write_hex(out, p->raw, p->raw_length);
        fputs("}\n", out);
        return;
    }
    fprintf(out, "\"type\": \"%s\", \"message_size\": %ld", ur_realtime_layout_name(p->layout), (long)p->message_size);
    n = ur_realtime_layout_fields(p->layout, &slots);
    for (i = 0; i < n; i++) {
        const ur_realtime_field_info *info = ur_realtime_field_info_of(slots[i].field);
        const double *values = ur_realtime_values(p, slots[i].field);
        fprintf(out, ", \"%s\": ", info->name);
        if (slots[i].count == 1) {
            json_write_f64(out, values[0]);
            continue;
        }
        fputc('[', out);
        for (j = 0; j < slots[i].count; j++) {
            if (j)
                fputs(", ", out);
            json_write_f64(out, values[j]);
        }
        fputc(']', out);
    }
    fputs("}\n", out);
}

static void write_error(FILE *out, const envelope *e, uint64_t offset, const char *what)
{
    char error[160];
    (void)snprintf(error, sizeof error, "packet at offset %lu: %s", (unsigned long)offset, what);
    envelope_error(out, e, (int64_t)offset, error);
}

/* Every frame the stream's bytes make, as JSON lines. */
static void drain(ur_realtime_conversation *c, cell_output *out)
{
    const envelope *e = out->envelope[1];
    ur_realtime_stream_frame f;
    ur_realtime_packet p;
    char what[96];
    for (;;) {
        switch (ur_realtime_stream_next(&c->stream, &f)) {
        case UR_REALTIME_FRAME_NEED_MORE:
        case UR_REALTIME_FRAME_END:
            return;
        case UR_REALTIME_FRAME_PACKET:
            if (ur_realtime_decode(f.bytes, f.length, c->version, &p) != UR_REALTIME_OK)
                out->errors = true;
            ur_realtime_write_record(out->out, e, &p, (size_t)f.offset);
            break;
        case UR_REALTIME_FRAME_BAD_SIZE:
            (void)snprintf(what, sizeof what, "size %ld is %s %d", (long)f.size,
                           f.error == UR_REALTIME_E_SIZE_BELOW ? "below" : "above",
                           f.error == UR_REALTIME_E_SIZE_BELOW ? UR_REALTIME_MIN_MESSAGE_SIZE : UR_REALTIME_MAX_MESSAGE_SIZE);
            write_error(out->out, e, f.offset, what);
            out->errors = true;
            break;
        case UR_REALTIME_FRAME_TRUNCATED:
            (void)snprintf(what, sizeof what, "needs %ld bytes, %lu left", (long)f.needed, (unsigned long)f.length);
            write_error(out->out, e, f.offset, what);
            out->errors = true;
            break;
        }
    }
}

static void init(void *state, urwire_sw_version v, bool hinted)
{
    ur_realtime_conversation *c = state;
    ur_realtime_stream_init(&c->stream);
    c->hinted = hinted;
    c->version = hinted ? ur_realtime_version((unsigned)v.major, (unsigned)v.minor, (unsigned)v.bugfix) : 0u;
}

/* What a client sends to the port is URScript, which is not decoded. */
static int feed(void *state, const uint8_t *data, size_t n, bool from_robot, cell_output *out)
{
    ur_realtime_conversation *c = state;
    size_t off = 0;
    while (from_robot && off < n) {
        off += ur_realtime_stream_feed(&c->stream, data + off, n - off);
        drain(c, out);
    }
    return 0;
}

static int close_way(void *state, bool from_robot, cell_output *out)
{
    ur_realtime_conversation *c = state;
    if (from_robot) {
        ur_realtime_stream_finish(&c->stream);
        drain(c, out);
    }
    return 0;
}

/* The packet the lost bytes cut short reported, and the stream framed afresh after them
 * (realtime.py's RealtimeFramer.restart). */
static int lost(void *state, bool from_robot, uint64_t offset, cell_output *out)
{
    ur_realtime_conversation *c = state;
    if (from_robot) {
        (void)close_way(state, true, out);
        ur_realtime_stream_init(&c->stream);
        c->stream.base = offset;
    }
    return 0;
}

/* The version the robot's primary stream announced chooses among layouts of one size, unless one
 * was given (spec framing.same_size). */
static void learn(void *state, urwire_sw_version v)
{
    ur_realtime_conversation *c = state;
    if (!c->hinted)
        c->version = ur_realtime_version((unsigned)v.major, (unsigned)v.minor, (unsigned)v.bugfix);
}

static const uint16_t ports[] = {30003, 30013};     /* as python/urwire/interfaces.py: the spec's */
const cell_interface cell_ur_realtime = {"ur_realtime", ports, 2, false, false, sizeof(ur_realtime_conversation),
                                         init, feed, close_way, lost, NULL, learn, NULL};
