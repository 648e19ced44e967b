/* The build machine's board: received bytes from standard input, each value read printed as a
 * line "name value", requests sent counted on standard error. */
#include <stdio.h>

#include "board.h"

size_t board_receive(uint8_t *out, size_t cap)
{
    return fread(out, 1, cap, stdin);
}

void board_send(const uint8_t *bytes, size_t n)
{
    fprintf(stderr, "sent %lu bytes, type %u\n", (unsigned long)n, n > 2 ? (unsigned)bytes[2] : 0u);
}

void board_report_double(const char *name, double value)
{
    printf("%s %.17g\n", name, value);
}

void board_report_float(const char *name, float value)
{
    printf("%s %.17g\n", name, (double)value);
}

void board_report_int(const char *name, int64_t value)
{
    printf("%s %lld\n", name, (long long)value);
}
