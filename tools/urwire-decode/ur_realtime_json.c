/* The real-time interface as canonical JSON Lines (ur_realtime_json.h). */
#include "ur_realtime_json.h"

#include <string.h>

#include "json.h"

static void write_double(FILE *out, double x)
{
    char text[40];
    json_f64_text(x, text, sizeof text);
    fputs(text, out);
}

void ur_realtime_write_json(FILE *out, const ur_realtime_packet *p, size_t stream_offset)
{
    const ur_realtime_slot *slots;
    size_t i, j, n;
    if (p->layout == UR_REALTIME_UNKNOWN) {
        fprintf(out, "{\"type\": \"unknown\", \"message_size\": %ld, \"error\": \"packet at offset %lu: size %ld "
                     "matches no layout\", \"raw\": \"", (long)p->message_size, (unsigned long)stream_offset,
                (long)p->message_size);
        for (i = 0; i < p->raw_length; i++)
            fprintf(out, "%02x", p->raw[i]);
        fputs("\"}\n", out);
        return;
    }
    fprintf(out, "{\"type\": \"%s\", \"message_size\": %ld", ur_realtime_layout_name(p->layout), (long)p->message_size);
    n = ur_realtime_layout_fields(p->layout, &slots);
    for (i = 0; i < n; i++) {
        const ur_realtime_field_info *info = ur_realtime_field_info_of(slots[i].field);
        const double *values = ur_realtime_values(p, slots[i].field);
        fprintf(out, ", \"%s\": ", info->name);
        if (slots[i].count == 1) {
            write_double(out, values[0]);
            continue;
        }
        fputc('[', out);
        for (j = 0; j < slots[i].count; j++) {
            if (j)
                fputs(", ", out);
            write_double(out, values[j]);
        }
        fputc(']', out);
    }
    fputs("}\n", out);
}

static void write_error(FILE *out, size_t offset, const char *what)
{
    fprintf(out, "{\"type\": \"error\", \"offset\": %lu, \"error\": \"packet at offset %lu: %s\"}\n",
            (unsigned long)offset, (unsigned long)offset, what);
}

int ur_realtime_print_stream(FILE *in, FILE *out, uint32_t version)
{
    static uint8_t buf[UR_REALTIME_MAX_MESSAGE_SIZE + (1 << 16)];
    size_t have = 0, offset = 0;   /* bytes in buf; stream offset of buf[0] */
    bool errors = false, eof = false;
    while (!eof) {
        size_t pos = 0, got = fread(buf + have, 1, sizeof buf - have, in);
        if (got < sizeof buf - have) {
            if (ferror(in))
                return 2;
            eof = true;
        }
        have += got;
        for (;;) {
            ur_realtime_packet p;
            char what[96];
            int32_t size = 0;
            ur_realtime_error e = ur_realtime_frame(buf + pos, have - pos, &size);
            if (e == UR_REALTIME_E_SIZE_BELOW || e == UR_REALTIME_E_SIZE_ABOVE) {
                /* Nothing after it can be framed: say so and read no further. */
                sprintf(what, "size %ld is %s %d", (long)size, e == UR_REALTIME_E_SIZE_BELOW ? "below" : "above",
                        e == UR_REALTIME_E_SIZE_BELOW ? UR_REALTIME_MIN_MESSAGE_SIZE : UR_REALTIME_MAX_MESSAGE_SIZE);
                write_error(out, offset + pos, what);
                return 1;
            }
            if (e == UR_REALTIME_E_SHORT || (size_t)size > have - pos) {
                if (eof && have > pos) {
                    long needed = e == UR_REALTIME_E_SHORT ? (long)UR_REALTIME_SIZE_FIELD_BYTES : (long)size;
                    sprintf(what, "needs %ld bytes, %lu left", needed, (unsigned long)(have - pos));
                    write_error(out, offset + pos, what);
                    errors = true;
                }
                break;
            }
            if (ur_realtime_decode(buf + pos, have - pos, version, &p) != UR_REALTIME_OK)
                errors = true;
            ur_realtime_write_json(out, &p, offset + pos);
            pos += (size_t)size;
        }
        memmove(buf, buf + pos, have - pos);
        have -= pos;
        offset += pos;
    }
    return errors ? 1 : 0;
}
