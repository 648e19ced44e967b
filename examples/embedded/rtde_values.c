/* Firmware (3) of `make bench-embedded`: an RTDE client. It asks for protocol 2 and a recipe of
 * three outputs, starts, then decodes what the robot sends: the replies that make the recipe,
 * and data packages whose values it reads by index and by name.
 *
 * RAM: the connection keeps its recipes and the names of the requests awaiting replies; the
 * build sizes them for what this client asks (RTDE_MAX_RECIPES, RTDE_MAX_VARIABLES,
 * RTDE_MAX_NAMES, given to every file: mk/embedded.mk). A data package of this recipe is
 * 3 + 1 + 8 + 48 + 4 bytes; MESSAGE_BUFFER holds any message up to 1 KiB, a bigger one is
 * skipped. */
#include <string.h>

#include "board.h"
#include "rtde.h"

#define MESSAGE_BUFFER 1024u

static const char *const outputs[] = {"timestamp", "actual_q", "robot_mode"};
static rtde_conversation conversation;
static rtde_message message;
static uint8_t held[MESSAGE_BUFFER];

/* Sends a request the client built, after the connection has taken it in (a setup request
 * waits there for its reply). */
static void request(const uint8_t *bytes, size_t n)
{
    size_t at;

    if (n != 0 && rtde_decode(&conversation, bytes, n, false, &message, &at) == RTDE_OK)
        board_send(bytes, n);
}

static void read_data(const rtde_data *data)
{
    rtde_value value;
    size_t i;

    for (i = 0; i < rtde_data_count(data); i++)         /* by index, in the recipe's order */
        if (rtde_data_value(data, i, &value) && value.type == RTDE_VT_DOUBLE)
            board_report_double("double", value.item[0].f64);
    if (rtde_data_find(data, "actual_q", &value))       /* by name */
        board_report_double("actual_q0", value.item[0].f64);
    if (rtde_data_find(data, "robot_mode", &value))
        board_report_int("robot_mode", value.item[0].i64);
}

static void on_message(const uint8_t *bytes, size_t n)
{
    size_t at;
    rtde_error e = rtde_decode(&conversation, bytes, n, true, &message, &at);

    if (e != RTDE_OK)
        board_report_int("error", (int64_t)e);
    else if (message.layout == RTDE_LAYOUT_DATA_PACKAGE)
        read_data(&message.u.data_package.values);
}

int main(void)
{
    static uint8_t out[128];
    size_t length = 0, size, skip = 0, n;
    rtde_error e;

    rtde_conversation_init(&conversation);
    request(out, rtde_build_request_protocol_version(out, sizeof out, 2));
    request(out, rtde_build_setup_outputs(out, sizeof out, 2, 125.0, outputs, 3));
    request(out, rtde_build_start(out, sizeof out));
    while ((n = board_receive(held + length, sizeof held - length)) != 0) {
        length += n;
        if (skip != 0) {                                /* the rest of a message too big to hold */
            n = skip < length ? skip : length;
            memmove(held, held + n, length - n);
            length -= n;
            skip -= n;
        }
        while ((e = rtde_message_size(held, length, &size)) == RTDE_OK || e == RTDE_BAD_HEADER) {
            if (e == RTDE_BAD_HEADER)
                size = 1;                               /* not a message: look one byte on */
            else
                on_message(held, size);
            memmove(held, held + size, length - size);
            length -= size;
        }
        if (length == sizeof held) {                    /* a message bigger than the buffer */
            skip = size - length;
            length = 0;
            board_report_int("skipped", (int64_t)size);
        }
    }
    return 0;
}
