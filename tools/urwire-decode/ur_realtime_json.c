/* The real-time interface as canonical JSON Lines (ur_realtime_json.h). */
#include "ur_realtime_json.h"

#include "json.h"
#include "ur_realtime_stream.h"

void ur_realtime_write_json(FILE *out, const ur_realtime_packet *p, size_t stream_offset)
{
    const ur_realtime_slot *slots;
    size_t i, j, n;
    if (p->layout == UR_REALTIME_UNKNOWN) {
        fprintf(out, "{\"type\": \"unknown\", \"message_size\": %ld, \"error\": \"packet at offset %lu: size %ld "
                     "matches no layout\", \"raw\": ", (long)p->message_size, (unsigned long)stream_offset,
                (long)p->message_size);
        json_write_hex(out, p->raw, p->raw_length);
        fputs("}\n", out);
        return;
    }
    fprintf(out, "{\"type\": \"%s\", \"message_size\": %ld", ur_realtime_layout_name(p->layout), (long)p->message_size);
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

static void write_error(FILE *out, uint64_t offset, const char *what)
{
    fprintf(out, "{\"type\": \"error\", \"offset\": %lu, \"error\": \"packet at offset %lu: %s\"}\n",
            (unsigned long)offset, (unsigned long)offset, what);
}

/* Every frame the stream's bytes make, as JSON lines; whether one was an error. */
static bool drain(ur_realtime_stream *s, FILE *out, uint32_t version)
{
    ur_realtime_stream_frame f;
    ur_realtime_packet p;
    char what[96];
    bool errors = false;
    for (;;) {
        switch (ur_realtime_stream_next(s, &f)) {
        case UR_REALTIME_FRAME_NEED_MORE:
        case UR_REALTIME_FRAME_END:
            return errors;
        case UR_REALTIME_FRAME_PACKET:
            if (ur_realtime_decode(f.bytes, f.length, version, &p) != UR_REALTIME_OK)
                errors = true;
            ur_realtime_write_json(out, &p, (size_t)f.offset);
            break;
        case UR_REALTIME_FRAME_BAD_SIZE:
            (void)snprintf(what, sizeof what, "size %ld is %s %d", (long)f.size,
                           f.error == UR_REALTIME_E_SIZE_BELOW ? "below" : "above",
                           f.error == UR_REALTIME_E_SIZE_BELOW ? UR_REALTIME_MIN_MESSAGE_SIZE : UR_REALTIME_MAX_MESSAGE_SIZE);
            write_error(out, f.offset, what);
            errors = true;
            break;
        case UR_REALTIME_FRAME_TRUNCATED:
            (void)snprintf(what, sizeof what, "needs %ld bytes, %lu left", (long)f.needed, (unsigned long)f.length);
            write_error(out, f.offset, what);
            errors = true;
            break;
        }
    }
}

int ur_realtime_print_stream(FILE *in, FILE *out, uint32_t version)
{
    static ur_realtime_stream stream;
    static uint8_t chunk[1 << 16];
    bool errors = false;
    ur_realtime_stream_init(&stream);
    for (;;) {
        size_t n = fread(chunk, 1, sizeof chunk, in), off = 0;
        if (n < sizeof chunk && ferror(in))
            return 2;
        while (off < n) {
            off += ur_realtime_stream_feed(&stream, chunk + off, n - off);
            errors |= drain(&stream, out, version);
        }
        if (n < sizeof chunk)
            break;
    }
    ur_realtime_stream_finish(&stream);
    errors |= drain(&stream, out, version);
    return errors ? 1 : 0;
}
