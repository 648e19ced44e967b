/* libFuzzer harness of the RTDE C library (generated/c/rtde.c), its stream framing
 * (runtime/c/typed_messages/rtde_stream.c) and the command's JSON writer (tools/urwire-decode/rtde_json.c). An
 * input is a protocol byte (the version in force before any exchange: its value mod 3, 0 for the
 * default), then pieces: a byte whose top bit is the direction (set: from the robot) and whose
 * other bits are the piece's length, then its bytes.
 * Checks on every input: ASan, UBSan; every data package's values read back by index and by name;
 * every record a line that starts with {"type": and ends with }; the state never over its limits. */
#define _GNU_SOURCE   /* fmemopen */
#include <stdio.h>
#include <string.h>

#include "rtde_json.h"

static rtde_json_stream stream;

static void check_message(const rtde_message *m)
{
    const rtde_data *d = NULL;
    size_t i;
    if (m->layout == RTDE_LAYOUT_DATA_PACKAGE) d = &m->u.data_package.values;
    if (m->layout == RTDE_LAYOUT_DATA_PACKAGE_V1) d = &m->u.data_package_v1.values;
    if (m->layout == RTDE_LAYOUT_INPUT_DATA_PACKAGE) d = &m->u.input_data_package.values;
    if (!d)
        return;
    for (i = 0; i < rtde_data_count(d); i++) {
        rtde_value v, w;
        rtde_text name = rtde_data_name(d, i);
        char text[RTDE_MAX_NAMES + 1];
        if (!rtde_data_value(d, i, &v) || name.length > RTDE_MAX_NAMES)
            __builtin_trap();
        memcpy(text, name.data, name.length);
        text[name.length] = '\0';
        if (memchr(name.data, 0, name.length))
            continue;                   /* a name with a NUL cannot be asked for by a C string */
        if (!rtde_data_find(d, text, &w) || w.type >= RTDE_VT_COUNT)
            __builtin_trap();
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static rtde_conversation direct;
    static char lines[1 << 16];
    FILE *out;
    size_t at = 1;
    if (size == 0)
        return 0;
    rtde_json_stream_init(&stream);
    rtde_conversation_init(&direct);
    stream.conversation.protocol = direct.protocol = (uint8_t)(data[0] % 3);
    out = fmemopen(lines, sizeof lines, "w");
    if (!out)
        return 0;
    while (at < size) {
        bool from_robot = (data[at] & 0x80) != 0;
        size_t n = data[at] & 0x7f;
        at++;
        if (n > size - at)
            n = size - at;
        rtde_json_feed(&stream, data + at, n, from_robot, out);
        {   /* the same bytes as whole messages, when they are one */
            rtde_message m;
            size_t msg_size, offset;
            if (rtde_message_size(data + at, n, &msg_size) == RTDE_OK
                && rtde_decode(&direct, data + at, msg_size, from_robot, &m, &offset) == RTDE_OK)
                check_message(&m);
        }
        at += n;
    }
    rtde_json_close(&stream, out);
    fclose(out);
    return 0;
}
