/* What the firmwares of examples/embedded take from their board: the bytes the network stack
 * received, a way to send, and somewhere to put what they read. board_target.c is a device's
 * (no stdio: the bytes are in a buffer that the network or a debugger fills); board_host.c
 * reads standard input and prints, so that the tests run the same firmwares on the build
 * machine (tests/c/test_embedded.py). */
#ifndef BOARD_H
#define BOARD_H

#include <stddef.h>
#include <stdint.h>

/* Up to cap received bytes into out; 0 when the stream has ended. */
size_t board_receive(uint8_t *out, size_t cap);
/* Bytes for the robot (an RTDE client's requests). */
void board_send(const uint8_t *bytes, size_t n);
/* One value the firmware read, by name, in the type the parser gives it: a firmware converts
 * nothing, so that a single-precision FPU pays for no double arithmetic the parser does not do. */
void board_report_double(const char *name, double value);
void board_report_float(const char *name, float value);
void board_report_int(const char *name, int64_t value);

#endif
