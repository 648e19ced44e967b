/* The real-time interface as canonical JSON Lines (ur_realtime_json.h). */
#include "ur_realtime_json.h"

#include <string.h>

#include "json.h"

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

static void write_error(FILE *out, size_t offset, const char *what)
{
    fprintf(out, "{\"type\": \"error\", \"offset\": %lu, \"error\": \"packet at offset %lu: %s\"}\n",
            (unsigned long)offset, (unsigned long)offset, what);
}

/* Whether some layout has this size: a packet of it, zeros after the size field, decodes. */
static bool has_layout(int32_t size)
{
    static uint8_t probe[UR_REALTIME_MAX_MESSAGE_SIZE];
    ur_realtime_packet p;
    probe[0] = (uint8_t)((uint32_t)size >> 24);
    probe[1] = (uint8_t)((uint32_t)size >> 16);
    probe[2] = (uint8_t)((uint32_t)size >> 8);
    probe[3] = (uint8_t)size;
    return ur_realtime_decode(probe, (size_t)size, 0, &p) == UR_REALTIME_OK;
}

/* After a size that cannot frame a packet: where the next plausible packet starts, from pos on
 * (the next size some layout has), as python/urwire/realtime.py finds it. False when none is found
 * yet; *pos is then where the scan goes on when more bytes come (have, at the end of the stream). */
static bool next_packet(const uint8_t *buf, size_t have, size_t *pos, bool eof)
{
    size_t p = *pos;
    for (; have - p >= UR_REALTIME_SIZE_FIELD_BYTES; p++) {
        int32_t size = 0;
        if (ur_realtime_frame(buf + p, have - p, &size) == UR_REALTIME_OK && has_layout(size)) {
            *pos = p;
            return true;
        }
    }
    *pos = eof ? have : p;
    return false;
}

int ur_realtime_print_stream(FILE *in, FILE *out, uint32_t version)
{
    static uint8_t buf[UR_REALTIME_MAX_MESSAGE_SIZE + (1 << 16)];
    size_t have = 0, offset = 0;   /* bytes in buf; stream offset of buf[0] */
    bool errors = false, eof = false, scanning = false;
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
            ur_realtime_error e;
            if (scanning) {
                if (!next_packet(buf, have, &pos, eof))
                    break;
                scanning = false;
            }
            e = ur_realtime_frame(buf + pos, have - pos, &size);
            if (e == UR_REALTIME_E_SIZE_BELOW || e == UR_REALTIME_E_SIZE_ABOVE) {
                /* Say so, and go on at the next plausible packet. */
                sprintf(what, "size %ld is %s %d", (long)size, e == UR_REALTIME_E_SIZE_BELOW ? "below" : "above",
                        e == UR_REALTIME_E_SIZE_BELOW ? UR_REALTIME_MIN_MESSAGE_SIZE : UR_REALTIME_MAX_MESSAGE_SIZE);
                write_error(out, offset + pos, what);
                errors = true;
                scanning = true;
                pos++;
                continue;
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
