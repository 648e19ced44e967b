/* The test driver of a subset build that keeps joint data and tool data
 * (python -m codegen --select ur:robot_state.joint_data,robot_state.tool_data):
 *
 *   subset_driver [V] < STREAM   frames a raw primary stream (V: the version hint, e.g. 5.11) and
 *                                checks that every message and every robot-state sub-package
 *                                encodes back to its exact bytes, that a sub-package is decoded
 *                                only when it was picked, and that the one-pass robot-state
 *                                decoder finds the picked parts the iterator finds; prints
 *                                "messages N packages P raw R" (R: kept raw) or the first
 *                                mismatch (exit 1).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "urwire.h"

static uint8_t framer_buffer[URWIRE_FRAMER_MIN_BUFFER];
static uint8_t encoded[URWIRE_MAX_MESSAGE_LENGTH + 64];
static uint8_t stream[1 << 22];

typedef struct counts {
    unsigned long messages, packages, raw;
} counts;

static int mismatch(const char *what, const urwire_frame *frame)
{
    printf("MISMATCH %s at stream offset %lu\n", what, (unsigned long)frame->offset);
    return 1;
}

static bool picked(uint8_t type)
{
    return type == URWIRE_PACKAGE_TYPE_JOINT_DATA || type == URWIRE_PACKAGE_TYPE_TOOL_DATA;
}

static int check(const urwire_frame *frame, counts *c)
{
    urwire_message m, m2;
    urwire_robot_state state;
    urwire_package pkg;
    urwire_seq seq;
    urwire_error err;
    uint32_t found = 0;
    size_t n;
    urwire_decode_message(frame->bytes, frame->length, frame->version, &m);
    n = urwire_encode_message(&m, encoded, sizeof encoded, &err);
    if (n != frame->length || memcmp(encoded, frame->bytes, n) != 0)
        return mismatch("message", frame);
    c->messages++;
    if (m.kind != URWIRE_KIND_ROBOT_STATE)
        return 0;
    seq = m.packages;
    while (urwire_next_package(&seq, &pkg)) {
        n = urwire_encode_package(&pkg, encoded, sizeof encoded, &err);
        if (n != pkg.raw.len + 5 || memcmp(encoded, frame->bytes + pkg.offset, n) != 0)
            return mismatch("package", frame);
        if (pkg.known != picked(pkg.type))
            return mismatch(pkg.known ? "a package decoded that was not picked" : "a picked package kept raw", frame);
        if (pkg.known && !pkg.failed)
            found |= URWIRE_BIT(pkg.type);
        c->packages++;
        c->raw += !pkg.known;
    }
    urwire_decode_robot_state_message(frame->bytes, frame->length, frame->version, &m2, &state);
    if (state.present != found)
        return mismatch("the one-pass decoder and the iterator differ", frame);
    return 0;
}

int main(int argc, char **argv)
{
    urwire_sw_version hint = URWIRE_DEFAULT_VERSION;
    urwire_framer fr;
    urwire_frame frame;
    urwire_frame_kind kind;
    counts c = {0, 0, 0};
    size_t len = fread(stream, 1, sizeof stream, stdin), off = 0;
    int rc = 0;
    if (argc == 2 && !urwire_parse_version(argv[1], &hint))
        return 2;
    urwire_framer_init(&fr, framer_buffer, sizeof framer_buffer, hint);
    for (;;) {
        if (off < len)
            off += urwire_framer_feed(&fr, stream + off, len - off);
        else
            urwire_framer_finish(&fr);
        while ((kind = urwire_framer_next(&fr, &frame)) == URWIRE_FRAME_MESSAGE || kind == URWIRE_FRAME_FAULT)
            if (kind == URWIRE_FRAME_MESSAGE && !rc)
                rc = check(&frame, &c);
        if (kind == URWIRE_FRAME_END)
            break;
    }
    if (!rc)
        printf("messages %lu packages %lu raw %lu\n", c.messages, c.packages, c.raw);
    return rc;
}
