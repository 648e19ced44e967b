/* Test driver for an int32-record interface's generated C (ur_reverse, ur_trajectory,
 * ur_script_command): built with -DPREFIX=ur_reverse_ -DUPPER=UR_REVERSE_ -DHEADER='"ur_reverse.h"'.
 * Reads segments
 * of both directions from stdin (one byte, 1: from the robot; a 4-byte big-endian length; the
 * bytes) and prints one canonical JSON line per record, as urwire.int32_records does, then the
 * tail each direction ends with. Usage: int32_records_driver [RELEASE]  (major.minor[.patch]) */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include HEADER

#define CAT2(a, b) a##b
#define CAT(a, b) CAT2(a, b)
#define FN(name) CAT(PREFIX, name)

typedef struct held {
    unsigned char *bytes;
    size_t len, cap;
    unsigned long long offset;
} held;

static char line[1 << 16];

static void append(held *h, const unsigned char *p, size_t n)
{
    if (n == 0)
        return;
    if (h->len + n > h->cap) {
        h->cap = (h->len + n) * 2;
        h->bytes = realloc(h->bytes, h->cap);
        if (!h->bytes)
            exit(2);
    }
    memcpy(h->bytes + h->len, p, n);
    h->len += n;
}

int main(int argc, char **argv)
{
    static held directions[2];
    static unsigned char chunk[1 << 16];
    unsigned major = 0, minor = 0, patch = 0;
    uint32_t release = 0;
    unsigned char head[5];
    int d;
    if (argc > 1 && sscanf(argv[1], "%u.%u.%u", &major, &minor, &patch) >= 2)
        release = (major * 1000u + minor) * 1000u + patch;
    if (release == 0)
        release = CAT(UPPER, DEFAULT_RELEASE);
    while (fread(head, 1, sizeof head, stdin) == sizeof head) {
        size_t n = (size_t)head[1] << 24 | (size_t)head[2] << 16 | (size_t)head[3] << 8 | (size_t)head[4];
        bool from_robot = head[0] != 0;
        held *h = &directions[from_robot ? 1 : 0];
        size_t size = FN(record_size)(from_robot, release), at = 0;
        if (n > sizeof chunk || fread(chunk, 1, n, stdin) != n)
            return 2;
        append(h, chunk, n);
        while (size > 0 && h->len - at >= size) {
            FN(record_json)(from_robot, h->bytes + at, size, release, line, sizeof line);
            puts(line);
            at += size;
        }
        if (at > 0)
            memmove(h->bytes, h->bytes + at, h->len - at);
        h->len -= at;
        h->offset += at;
    }
    for (d = 0; d < 2; d++)
        if (directions[d].len > 0) {
            FN(tail_json)(d == 1, directions[d].offset, directions[d].len, release, line, sizeof line);
            puts(line);
        }
    return 0;
}
