/* Test driver for generated/c/ur_dashboard.{h,c}: reads segments of both directions from stdin,
 * each as one byte (1: from the robot, 0: from the client), a 4-byte big-endian length and the
 * bytes, and prints one canonical JSON line per record, as urwire.text_lines does in Python. At
 * the end of the input, what each direction holds without a newline is a fault record.
 * Usage: ur_dashboard_driver [VERSION]   (major.minor[.bugfix], the version known at the start) */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ur_dashboard.h"

#define HELD (UR_DASHBOARD_MAX_LINE * 4)

typedef struct held {
    unsigned char bytes[HELD];
    size_t len;
} held;

static char line[4 * HELD + 256];

static void emit(const ur_dashboard_record *rec)
{
    size_t len = ur_dashboard_json(rec, line, sizeof line);
    if (len >= sizeof line) {
        fprintf(stderr, "record too long for the driver\n");
        exit(2);
    }
    puts(line);
}

/* Decode what the direction holds; keep the bytes of a line not yet whole. */
static void drain(ur_dashboard_conversation *c, int from_robot, held *h)
{
    size_t at = 0, used;
    ur_dashboard_record rec;
    bool got;
    while ((used = ur_dashboard_decode(c, from_robot != 0, h->bytes + at, h->len - at, &rec, &got)) > 0 || got) {
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
    return ur_dashboard_version(major, minor, bugfix);
}

int main(int argc, char **argv)
{
    static held directions[2];
    ur_dashboard_conversation c;
    ur_dashboard_record rec;
    unsigned char head[5];
    int d;
    ur_dashboard_init(&c, argc > 1 ? parse_version(argv[1]) : 0);
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
        if (ur_dashboard_finish(&c, d == 1, directions[d].len, &rec))
            emit(&rec);
    return 0;
}
