/* Test driver for a text-line interface's generated C (ur_dashboard, ur_script_sender), built
 * with -DPREFIX=ur_dashboard_ -DUPPER=UR_DASHBOARD_ -DHEADER='"ur_dashboard.h"'. Reads segments
 * of both directions from stdin, each as one byte (1: from the robot, 0: from the client), a 4-byte big-endian length and the
 * bytes, and prints one canonical JSON line per record, as urwire.text_lines does in Python. At
 * the end of the input, what each direction holds without a newline is a fault record.
 * Usage: lines_driver [VERSION]   (major.minor[.bugfix], the version known at the start) */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include HEADER

#define CAT2(a, b) a##b
#define CAT(a, b) CAT2(a, b)
#define FN(name) CAT(PREFIX, name)
#define T(name) CAT(PREFIX, name)
#define C(name) CAT(UPPER, name)

#define HELD (C(MAX_LINE) * 4)

typedef struct held {
    unsigned char bytes[HELD];
    size_t len;
} held;

static char line[4 * HELD + 256];

static void emit(const T(record) *rec)
{
    size_t len = FN(json)(rec, line, sizeof line);
    if (len >= sizeof line) {
        fprintf(stderr, "record too long for the driver\n");
        exit(2);
    }
    puts(line);
}

/* Decode what the direction holds; keep the bytes of a line not yet whole. */
static void drain(T(conversation) *c, int from_robot, held *h)
{
    size_t at = 0, used;
    T(record) rec;
    bool got;
    while ((used = FN(decode)(c, from_robot != 0, h->bytes + at, h->len - at, &rec, &got)) > 0 || got) {
        if (got)
            emit(&rec);
        at += used;
    }
    memmove(h->bytes, h->bytes + at, h->len - at);
    h->len -= at;
}

static uint32_t parse_version(const char *text)
{
    unsigned major = 0, minor = 0, bugfix = 0;
    if (sscanf(text, "%u.%u.%u", &major, &minor, &bugfix) < 2)
        return 0;
    return FN(version)(major, minor, bugfix);
}

int main(int argc, char **argv)
{
    static held directions[2];
    T(conversation) c;
    T(record) rec;
    unsigned char head[5];
    int d;
    FN(init)(&c, argc > 1 ? parse_version(argv[1]) : 0);
    while (fread(head, 1, sizeof head, stdin) == sizeof head) {
        size_t n = (size_t)head[1] << 24 | (size_t)head[2] << 16 | (size_t)head[3] << 8 | (size_t)head[4];
        held *h = &directions[head[0] ? 1 : 0];
        while (n > 0) {
            size_t take = HELD - h->len < n ? HELD - h->len : n;
            if (fread(h->bytes + h->len, 1, take, stdin) != take) {
                fprintf(stderr, "truncated input\n");
                return 2;
            }
            h->len += take;
            n -= take;
            drain(&c, head[0], h);
        }
    }
    for (d = 0; d < 2; d++)
        if (FN(finish)(&c, d == 1, directions[d].len, &rec))
            emit(&rec);
    return 0;
}
