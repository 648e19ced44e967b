/* libFuzzer harness: the real-time decoder (generated/c/ur_realtime.c), its stream framing
 * (runtime/c/sized_packets/ur_realtime_stream.c) and its JSON writer
 * (tools/urwire-decode/ur_realtime_json.c) over any bytes.
 *
 * Input: one control byte, then the stream. The control byte's low two bits pick the software
 * version the decoder is told (unknown, 3.12, 5.2, 5.10); its other six bits where the stream is cut
 * in two feeds (0: fed whole; else at that many sixty-fourths of it). Checked on every input, frame
 * by frame as urwire-decode frames them:
 *   - framing: a packet's size frames one and is whole; a bad size is below the smallest or above
 *     the largest, and a scan follows it: never two faults without a packet between them; frames
 *     come in stream order, and only a finished stream ends with a truncated tail;
 *   - a decoded packet's layout has the declared size, and every slot lies inside it;
 *   - a packet of unknown size keeps exactly its bytes after the size field;
 *   - every field the layout has reads back through ur_realtime_values, and an enum name, when
 *     there is one, belongs to a field with an enum;
 *   - the JSON writer writes one line per packet, opening with {"type": .
 *
 *     make fuzz-ur-realtime FUZZ_SECONDS=10
 */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ur_realtime.h"
#include "ur_realtime_json.h"
#include "ur_realtime_stream.h"

static ur_realtime_stream stream;        /* about 90 KiB: static, as the command keeps it */

static void check(int ok, const char *what)
{
    if (!ok) {
        fprintf(stderr, "fuzz_ur_realtime: %s\n", what);
        abort();
    }
}

static void check_packet(const uint8_t *p, size_t len, int32_t size, const ur_realtime_packet *pkt,
                         ur_realtime_error e)
{
    const ur_realtime_slot *slots;
    size_t i, n;
    check(pkt->message_size == size, "message_size is the declared size");
    if (e == UR_REALTIME_E_UNKNOWN_SIZE) {
        check(pkt->layout == UR_REALTIME_UNKNOWN && pkt->raw == p + UR_REALTIME_SIZE_FIELD_BYTES, "raw view");
        check(pkt->raw_length == (size_t)size - UR_REALTIME_SIZE_FIELD_BYTES, "raw length");
        return;
    }
    check(e == UR_REALTIME_OK && pkt->layout >= 0 && pkt->layout < UR_REALTIME_LAYOUT_COUNT, "a known layout");
    n = ur_realtime_layout_fields(pkt->layout, &slots);
    check(n > 0, "a layout has fields");
    for (i = 0; i < n; i++) {
        const ur_realtime_field_info *info = ur_realtime_field_info_of(slots[i].field);
        const double *v = ur_realtime_values(pkt, slots[i].field);
        uint64_t bits, want;
        check(info != NULL && info->count == slots[i].count, "slot and field agree");
        check((size_t)slots[i].offset + 8u * slots[i].count <= (size_t)size, "slot inside the packet");
        check(ur_realtime_has(pkt, slots[i].field), "has what the layout has");
        memcpy(&bits, &v[0], sizeof bits);
        want = 0;
        {
            size_t k;
            for (k = 0; k < 8; k++)
                want = want << 8 | p[slots[i].offset + k];
        }
        check(bits == want, "the first value is the packet's bytes");
        if (ur_realtime_enum_name(pkt, slots[i].field, v[0]) != NULL)
            check(info->enum_id >= 0, "an enum name belongs to an enum field");
    }
    (void)len;
}

/* Every frame the stream has ready: packets checked and written, faults checked. */
static void drain(uint32_t version, FILE *out, size_t *packets, bool *after_fault, uint64_t *next_offset)
{
    ur_realtime_stream_frame f;
    ur_realtime_frame_kind kind;
    while ((kind = ur_realtime_stream_next(&stream, &f)) != UR_REALTIME_FRAME_NEED_MORE &&
           kind != UR_REALTIME_FRAME_END) {
        int32_t declared = 0;
        check(f.offset >= *next_offset, "frames in stream order");
        if (kind == UR_REALTIME_FRAME_BAD_SIZE) {
            check(!*after_fault, "one fault a garbage run");
            check(ur_realtime_frame(f.bytes, f.length, &declared) == f.error && declared == f.size, "a bad size");
            check(f.size < UR_REALTIME_MIN_MESSAGE_SIZE || f.size > UR_REALTIME_MAX_MESSAGE_SIZE, "out of bounds");
            *after_fault = true;
            *next_offset = f.offset + 1;
        } else if (kind == UR_REALTIME_FRAME_TRUNCATED) {
            check(f.length > 0 && f.length < f.needed, "a tail short of what it needs");
            *next_offset = f.offset + f.length;
        } else {
            ur_realtime_packet pkt;
            ur_realtime_error e;
            check(ur_realtime_frame(f.bytes, f.length, &declared) == UR_REALTIME_OK, "a packet's size frames it");
            check(declared >= UR_REALTIME_MIN_MESSAGE_SIZE && declared <= UR_REALTIME_MAX_MESSAGE_SIZE, "bounds");
            check((size_t)declared == f.length, "a packet is whole");
            e = ur_realtime_decode(f.bytes, f.length, version, &pkt);
            check_packet(f.bytes, f.length, declared, &pkt, e);
            ur_realtime_write_json(out, &pkt, (size_t)f.offset);
            (*packets)++;
            *after_fault = false;
            *next_offset = f.offset + f.length;
        }
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const unsigned versions[4][3] = {{0, 0, 0}, {3, 12, 0}, {5, 2, 0}, {5, 10, 0}};
    uint32_t version;
    char *text = NULL;
    size_t text_size = 0, lines = 0, packets = 0, k, n, at = 0, cut;
    bool after_fault = false;
    uint64_t next_offset = 0;
    FILE *out;
    if (size < 1)
        return 0;
    version = data[0] & 3u ? ur_realtime_version(versions[data[0] & 3u][0], versions[data[0] & 3u][1],
                                                 versions[data[0] & 3u][2]) : 0u;
    n = size - 1;
    cut = (data[0] >> 2) ? n / 64 * (size_t)(data[0] >> 2) : n;
    out = open_memstream(&text, &text_size);
    check(out != NULL, "open_memstream");
    ur_realtime_stream_init(&stream);
    while (at < n) {
        size_t end = at < cut ? cut : n;
        while (at < end) {
            at += ur_realtime_stream_feed(&stream, data + 1 + at, end - at);
            drain(version, out, &packets, &after_fault, &next_offset);
        }
    }
    ur_realtime_stream_finish(&stream);
    drain(version, out, &packets, &after_fault, &next_offset);
    fclose(out);
    for (k = 0; k < text_size; k++)
        if (text[k] == '\n')
            lines++;
    check(lines == packets, "one line per packet");
    check(packets == 0 || strncmp(text, "{\"type\": ", 9) == 0, "a line opens with its type");
    free(text);
    return 0;
}
