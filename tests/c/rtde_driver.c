/* Test driver for the RTDE C library and its JSON writer: reads on stdin a list of pieces, each
 * a direction byte ('r' from the robot, 'c' from the client), a 4-byte big-endian length and the
 * bytes, feeds them to one connection in order and prints its JSON lines, then closes it.
 * An argument sets the protocol version in force before any version exchange. */
#include <stdio.h>
#include <stdlib.h>

#include "rtde_json.h"

static rtde_json_stream stream;     /* large: static, as a firmware would keep it */

int main(int argc, char **argv)
{
    static uint8_t piece[1 << 20];
    int direction;
    rtde_json_stream_init(&stream);
    if (argc > 1)
        stream.conversation.protocol = (uint8_t)atoi(argv[1]);
    while ((direction = getchar()) != EOF) {
        unsigned char len[4];
        size_t n;
        if (fread(len, 1, 4, stdin) != 4)
            return 2;
        n = (size_t)len[0] << 24 | (size_t)len[1] << 16 | (size_t)len[2] << 8 | (size_t)len[3];
        if (n > sizeof piece || fread(piece, 1, n, stdin) != n)
            return 2;
        rtde_json_feed(&stream, piece, n, direction == 'r', stdout);
    }
    rtde_json_close(&stream, stdout);
    return 0;
}
