/* A minimal urwire program to copy into firmware: frame a primary/secondary stream, decode
 * each robot state into one struct, and use a few values. Here the bytes come from stdin;
 * on a device they come from your TCP socket, in chunks of any size.
 *
 *     cc -std=c99 -I generated/c examples/robot_state_monitor.c generated/c/urwire.c
 *     ./a.out < capture.bin
 *
 * Memory: one framer buffer (static, 1 MiB + 4 KiB frames every legal message; a smaller
 * buffer works and reports bigger messages as URWIRE_E_TOO_BIG_FOR_BUFFER), plus the structs
 * on the stack. No allocation anywhere. */
#include <stdio.h>

#include "urwire.h"

static uint8_t framer_buffer[URWIRE_FRAMER_MIN_BUFFER];

static void on_message(const urwire_frame *frame)
{
    urwire_message msg;
    urwire_robot_state state;
    char why[URWIRE_PATH_MAX + 128];
    const char *mode;

    urwire_decode_message(frame->bytes, frame->length, frame->version, &msg);
    if (msg.kind == URWIRE_KIND_VERSION && !msg.failed) {
        printf("controller %d.%d\n", msg.as.version.major_version, msg.as.version.minor_version);
        return;
    }
    if (msg.kind != URWIRE_KIND_ROBOT_STATE)
        return;
    if (!urwire_decode_robot_state(&msg, &state) && msg.failed) {
        urwire_error_text(&msg.error, why, sizeof why);
        printf("robot state cut short: %s\n", why);
    }
    if (state.present & URWIRE_BIT(URWIRE_PACKAGE_TYPE_ROBOT_MODE_DATA)) {
        /* Robot modes meant other things on CB2: the name follows the version it was read in. */
        mode = urwire_robot_mode_name(state.robot_mode_data.version, state.robot_mode_data.robot_mode);
        printf("robot mode %s\n", mode ? mode : "(unknown)");
    }
    if (state.present & URWIRE_BIT(URWIRE_PACKAGE_TYPE_JOINT_DATA))
        printf("base joint q_actual %.4f rad\n", state.joint_data.joints[0].q_actual);
}

int main(void)
{
    urwire_framer framer;
    urwire_frame frame;
    urwire_frame_kind kind;
    uint8_t chunk[512];
    size_t n, used;
    char why[URWIRE_PATH_MAX + 128];

    urwire_framer_init(&framer, framer_buffer, sizeof framer_buffer, URWIRE_DEFAULT_VERSION);
    do {
        n = fread(chunk, 1, sizeof chunk, stdin);
        if (n == 0)
            urwire_framer_finish(&framer);  /* end of stream: a cut tail becomes a fault */
        used = 0;
        do {
            used += urwire_framer_feed(&framer, chunk + used, n - used);
            while ((kind = urwire_framer_next(&framer, &frame)) == URWIRE_FRAME_MESSAGE ||
                   kind == URWIRE_FRAME_FAULT) {
                if (kind == URWIRE_FRAME_MESSAGE) {
                    on_message(&frame);
                } else {
                    urwire_error_text(&frame.fault, why, sizeof why);
                    printf("stream fault at %lu: %s\n", (unsigned long)frame.offset, why);
                }
            }
        } while (used < n);
    } while (kind != URWIRE_FRAME_END);
    return 0;
}
