/* Firmware (1) and (2) of `make bench-embedded`: frame a robot's primary/secondary stream and
 * read every robot-state sub-package, in every software version (generated/c/urwire.c) or in the
 * one of a pinned build (`make pinned-c PIN=5.11`, the same source against build/pinned/c).
 *
 * RAM: the framer's buffer holds the largest message a real robot sends. A robot state is
 * 0.7 to 1.5 KiB (the captures of tests/conformance: 682, 1,386 and 1,471 bytes; the others
 * are smaller), global-variable and program-thread messages grow with the program: 4 KiB holds
 * them for programs of a few hundred variables, and a bigger one is reported
 * (URWIRE_E_TOO_BIG_FOR_BUFFER) and skipped. The structs are static, so that the RAM a build
 * reports is all there is beside the stack. */
#include "board.h"
#include "urwire.h"

#define FRAMER_BUFFER 4096u
#define CHUNK 256u

static uint8_t framer_buffer[FRAMER_BUFFER];
static urwire_framer framer;
static urwire_message message;
static urwire_robot_state state;

static void read_state(const urwire_robot_state *s)
{
    /* Every sub-package the robot sent is decoded into s; the bits say which, and a few of
     * their values stand for what a firmware would use. */
    board_report("present", (double)s->present);
    board_report("malformed", (double)s->malformed);
    if (s->present & URWIRE_BIT(URWIRE_PACKAGE_TYPE_ROBOT_MODE_DATA))
        board_report("robot_mode", (double)s->robot_mode_data.robot_mode);
    if (s->present & URWIRE_BIT(URWIRE_PACKAGE_TYPE_JOINT_DATA))
        board_report("q_actual0", s->joint_data.joints[0].q_actual);
    if (s->present & URWIRE_BIT(URWIRE_PACKAGE_TYPE_CARTESIAN_INFO))
        board_report("tcp_x", s->cartesian_info.x);
    if (s->present & URWIRE_BIT(URWIRE_PACKAGE_TYPE_TOOL_DATA))
        board_report("tool_voltage", (double)s->tool_data.tool_voltage_48v);
}

static void on_frame(const urwire_frame *frame)
{
    urwire_decode_robot_state_message(frame->bytes, frame->length, frame->version, &message, &state);
    urwire_framer_learn(&framer, &message);
    if (message.kind == URWIRE_KIND_ROBOT_STATE)
        read_state(&state);
    else if (message.kind == URWIRE_KIND_VERSION && !message.failed) {
        board_report("major_version", message.as.version.major_version);
        board_report("minor_version", message.as.version.minor_version);
    }
}

/* The received chunk and the frame in static RAM too: the stack keeps only the parser's calls. */
static uint8_t chunk[CHUNK];
static urwire_frame frame;

int main(void)
{
    urwire_frame_kind kind;
    size_t n, used;

    urwire_framer_init(&framer, framer_buffer, sizeof framer_buffer, URWIRE_DEFAULT_VERSION);
    do {
        n = board_receive(chunk, sizeof chunk);
        if (n == 0)
            urwire_framer_finish(&framer);
        used = 0;
        do {
            used += urwire_framer_feed(&framer, chunk + used, n - used);
            while ((kind = urwire_framer_next(&framer, &frame)) == URWIRE_FRAME_MESSAGE ||
                   kind == URWIRE_FRAME_FAULT) {
                if (kind == URWIRE_FRAME_MESSAGE)
                    on_frame(&frame);
                else
                    board_report("fault", (double)frame.fault.status);
            }
        } while (used < n);
    } while (kind != URWIRE_FRAME_END);
    return 0;
}
