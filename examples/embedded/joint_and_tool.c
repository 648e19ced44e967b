/* Firmware (4) of `make bench-embedded`: joint data and tool data alone, from a parser generated
 * with only those two sub-packages (a subset build: `python -m codegen --select`); every other
 * message and sub-package is still framed and skipped by its length. Memory as robot_states.c. */
#include "board.h"
#include "urwire.h"

#define FRAMER_BUFFER 4096u
#define CHUNK 256u

static uint8_t framer_buffer[FRAMER_BUFFER];
static urwire_framer framer;
static urwire_message message;
static urwire_robot_state state;

static void on_frame(const urwire_frame *frame)
{
    urwire_decode_robot_state_message(frame->bytes, frame->length, frame->version, &message, &state);
    urwire_framer_learn(&framer, &message);
    if (message.kind != URWIRE_KIND_ROBOT_STATE)
        return;
    if (state.present & URWIRE_BIT(URWIRE_PACKAGE_TYPE_JOINT_DATA))
        board_report("q_actual0", state.joint_data.joints[0].q_actual);
    if (state.present & URWIRE_BIT(URWIRE_PACKAGE_TYPE_TOOL_DATA))
        board_report("tool_voltage", (double)state.tool_data.tool_voltage_48v);
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
                   kind == URWIRE_FRAME_FAULT)
                if (kind == URWIRE_FRAME_MESSAGE)
                    on_frame(&frame);
        } while (used < n);
    } while (kind != URWIRE_FRAME_END);
    return 0;
}
