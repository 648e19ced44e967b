/* libFuzzer harness: the framer and every decoder, encoder and visitor of urwire.c.
 *
 * Input: one control byte, then a stream. The control byte picks the software version
 * (value-type table), the chunk size fed to the framer, and now and then a small framer
 * buffer (so that the too-big-for-buffer path runs). Every framed message must re-encode to
 * its exact bytes; a twin framer, handed back every message it frames decoded
 * (urwire_framer_learn), must frame the same messages in the same versions; every view handed out must lie inside the input (ASan checks each byte
 * we touch); the JSON text writer of the CLI runs on every string.
 *
 *     make fuzz FUZZ_SECONDS=600          # longer runs; crashes land in build/fuzz/crashes/
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "json.h"
#include "urwire.h"

static uint8_t framer_buffer[URWIRE_FRAMER_MIN_BUFFER];
static uint8_t twin_buffer[URWIRE_FRAMER_MIN_BUFFER];
static uint8_t encoded[URWIRE_MAX_MESSAGE_LENGTH + 64];
static FILE *sink;
static volatile unsigned touched;

static void touch(urwire_bytes b)
{
    size_t i;
    for (i = 0; i < b.len; i++)
        touched += b.ptr[i];
}

static void v_begin(void *ctx, const char *key) { (void)ctx; (void)key; }
static void v_end(void *ctx) { (void)ctx; }
static void v_int(void *ctx, const char *key, int64_t v) { (void)ctx; (void)key; touched += (unsigned)v; }
static void v_uint(void *ctx, const char *key, uint64_t v) { (void)ctx; (void)key; touched += (unsigned)v; }
static void v_bool(void *ctx, const char *key, bool v) { (void)ctx; (void)key; touched += v; }
static void v_f32(void *ctx, const char *key, float v) { (void)ctx; (void)key; touched += v > 0; }
static void v_f64(void *ctx, const char *key, double v) { (void)ctx; (void)key; touched += v > 0; }
static void v_null(void *ctx, const char *key) { (void)ctx; (void)key; }
static void v_text(void *ctx, const char *key, urwire_bytes t)
{
    (void)ctx;
    (void)key;
    touch(t);
    json_write_text(sink, t.ptr, t.len);
}
static void v_hex(void *ctx, const char *key, urwire_bytes b) { (void)ctx; (void)key; touch(b); }

static const urwire_visitor visitor = {NULL, v_begin, v_end, v_begin, v_end, v_int, v_uint, v_bool,
                                       v_f32, v_f64, v_text, v_hex, v_null, NULL};

static void check_error_text(const urwire_error *e)
{
    char small[8], big[URWIRE_PATH_MAX + 128];
    size_t n = urwire_error_text(e, big, sizeof big);
    if (urwire_error_text(e, small, sizeof small) != n || strlen(small) >= sizeof small)
        abort();
    if (urwire_status_name(e->status) == NULL)
        abort();
}

static bool same_version(urwire_sw_version a, urwire_sw_version b)
{
    return a.major == b.major && a.minor == b.minor && a.bugfix == b.bugfix && a.assumed == b.assumed;
}

/* The twin framer takes each message it frames, decoded one way or the other, back. */
static void hand_back(urwire_framer *twin, const urwire_frame *frame, size_t nth)
{
    urwire_message m;
    urwire_robot_state state;
    if (nth % 2)
        urwire_decode_robot_state_message(frame->bytes, frame->length, frame->version, &m, &state);
    else
        urwire_decode_message(frame->bytes, frame->length, frame->version, &m);
    urwire_framer_learn(twin, &m);
}

/* Decode, visit, re-encode; `framed` when the length field is the true length. */
static void check_message(const uint8_t *bytes, size_t len, urwire_sw_version version, bool framed)
{
    urwire_message m;
    urwire_robot_state state;
    urwire_package pkg;
    urwire_seq seq;
    urwire_error err;
    size_t n;
    urwire_decode_message(bytes, len, version, &m);
    urwire_visit_message(&m, &visitor);
    if (m.failed)
        check_error_text(&m.error);
    if (urwire_message_has_error(&m) != !urwire_decode_robot_state(&m, &state) && m.kind == URWIRE_KIND_ROBOT_STATE)
        abort();
    if (m.kind == URWIRE_KIND_ROBOT_STATE) {
        urwire_message m2;
        urwire_robot_state state2;
        bool ok2 = urwire_decode_robot_state_message(bytes, len, version, &m2, &state2);
        if (ok2 != !urwire_message_has_error(&m) || state2.present != state.present ||
            state2.malformed != state.malformed || m2.failed != m.failed || m2.packages.count != m.packages.count)
            abort();
        if (m2.implied != m.implied || !same_version(m2.implied_version, m.implied_version))
            abort();  /* either decoding tells the framer the same (urwire_framer_learn) */
        seq = m.packages;
        while (urwire_next_package(&seq, &pkg)) {
            if (pkg.failed)
                check_error_text(&pkg.error);
            n = urwire_encode_package(&pkg, encoded, sizeof encoded, &err);
            if (n != pkg.raw.len + 5 || memcmp(encoded, bytes + pkg.offset, n) != 0)
                abort();
        }
    }
    if (len < URWIRE_HEADER_SIZE || len > URWIRE_MAX_MESSAGE_LENGTH)
        return;  /* (an unframed input longer than any message only decodes) */
    n = urwire_encode_message(&m, encoded, sizeof encoded, &err);
    if (n != len || memcmp(encoded + 4, bytes + 4, len - 4) != 0)
        abort();  /* lossless: every byte after the length field comes back */
    if (framed && memcmp(encoded, bytes, 4) != 0)
        abort();  /* and the computed length is the declared one */
    if (urwire_encode_message(&m, encoded, len - 1, &err) != 0)
        abort();  /* one byte short must fail, not overrun */
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const urwire_sw_version versions[4] = {URWIRE_DEFAULT_VERSION_INIT, {3, 2, 0, false}, {5, 0, 0, false},
                                                  {5, 12, 0, false}};
    urwire_framer fr, twin;
    urwire_frame frame, twin_frame;
    urwire_frame_kind kind = URWIRE_FRAME_NEED_MORE;
    uint8_t control;
    size_t chunk, off = 0, cap, took, nth = 0;
    if (!sink)
        sink = fopen("/dev/null", "w");
    if (size == 0)
        return 0;
    control = data[0];
    data++;
    size--;
    /* Long inputs go in proportionally longer chunks: a byte at a time through 1 MiB only
     * repeats what a short input shows, a million times over. */
    chunk = (1 + (size_t)((control >> 2) & 31) * 13) * (1 + size / 16384);
    cap = (control & 0x80) ? 64 + (size_t)(control & 0x7c) : sizeof framer_buffer;
    urwire_framer_init(&fr, framer_buffer, cap, versions[control & 3]);
    urwire_framer_init(&twin, twin_buffer, cap, versions[control & 3]);
    while (kind != URWIRE_FRAME_END) {
        if (off < size) {
            took = urwire_framer_feed(&fr, data + off, chunk < size - off ? chunk : size - off);
            if (urwire_framer_feed(&twin, data + off, chunk < size - off ? chunk : size - off) != took)
                abort();
            off += took;
        } else {
            urwire_framer_finish(&fr);
            urwire_framer_finish(&twin);
        }
        for (;;) {
            kind = urwire_framer_next(&fr, &frame);
            if (urwire_framer_next(&twin, &twin_frame) != kind)
                abort();
            if (kind != URWIRE_FRAME_MESSAGE && kind != URWIRE_FRAME_FAULT)
                break;
            if (twin_frame.offset != frame.offset || !same_version(twin_frame.version, frame.version))
                abort();
            if (kind == URWIRE_FRAME_MESSAGE)
                hand_back(&twin, &twin_frame, nth++);
            if (kind == URWIRE_FRAME_FAULT) {
                check_error_text(&frame.fault);
                urwire_visit_fault(&frame.fault, &visitor);
            } else {
                if (frame.bytes < fr.buf || frame.bytes + frame.length > fr.buf + fr.len)
                    abort();
                check_message(frame.bytes, frame.length, frame.version, true);
            }
        }
    }
    /* The same bytes as one message whatever its length field says: every decoder, unframed. */
    check_message(data, size, versions[control & 3], false);
    return 0;
}
