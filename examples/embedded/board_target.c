/* A device's board: the received bytes are in a buffer that the network (or a debugger, or an
 * emulator's loader) fills, what the firmware reads goes to memory a debugger can watch. */
#include <string.h>

#include "board.h"

const uint8_t *volatile board_rx;           /* the bytes received so far, and how many */
volatile size_t board_rx_length;
const uint8_t *volatile board_tx;           /* the last request sent */
volatile size_t board_tx_length;
const char *volatile board_name;            /* the last value read, in its own type */
volatile double board_double;
volatile float board_float;
volatile int64_t board_int;

size_t board_receive(uint8_t *out, size_t cap)
{
    size_t n = board_rx_length < cap ? board_rx_length : cap;

    if (n != 0) {
        memcpy(out, (const uint8_t *)board_rx, n);
        board_rx += n;
        board_rx_length -= n;
    }
    return n;
}

void board_send(const uint8_t *bytes, size_t n)
{
    board_tx = bytes;
    board_tx_length = n;
}

void board_report_double(const char *name, double value)
{
    board_name = name;
    board_double = value;
}

void board_report_float(const char *name, float value)
{
    board_name = name;
    board_float = value;
}

void board_report_int(const char *name, int64_t value)
{
    board_name = name;
    board_int = value;
}
