/* The main() of the primary stream's firmwares (primary_stream.h): the loop over what the
 * board receives.
 *
 * RAM: the framer's buffer holds the largest message a real robot sends. A robot state is
 * 0.7 to 1.5 KiB (the captures of tests/conformance: 682, 1,386 and 1,471 bytes; the others
 * are smaller), global-variable and program-thread messages grow with the program: 4 KiB holds
 * them for programs of a few hundred variables, and a bigger one is reported
 * (URWIRE_E_TOO_BIG_FOR_BUFFER) and skipped. The structs, the received chunk and the frame are
 * static, so that the RAM a build reports is all there is beside the stack, and the stack keeps
 * only the parser's calls (main's own frame, with no call between it and the parser's). */
#include "board.h"
#include "primary_stream.h"

#define FRAMER_BUFFER 4096u
#define CHUNK 256u

static uint8_t framer_buffer[FRAMER_BUFFER];
static urwire_framer framer;
static urwire_message message;
static urwire_robot_state state;
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
                if (kind == URWIRE_FRAME_MESSAGE) {
                    urwire_decode_robot_state_message(frame.bytes, frame.length, frame.version, &message, &state);
                    urwire_framer_learn(&framer, &message);
                    primary_read(&message, &state);
                } else
                    board_report_int("fault", (int64_t)frame.fault.status);
            }
        } while (used < n);
    } while (kind != URWIRE_FRAME_END);
    return 0;
}
