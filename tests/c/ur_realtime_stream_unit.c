/* Real-time stream framing on its own (runtime/c/sized_packets/ur_realtime_stream.c): each stream
 * below is framed whole, a byte at a time and cut at every point (or at a spread of points for the
 * long ones), and must give the frames it lists, with their offsets, lengths and bytes: whole
 * packets (of a layout's size or of none), a garbage prefix as one fault however it was cut, the
 * scan passing over sizes no layout has, a fault after each of two garbage runs, the largest
 * packet a size may declare, a stream of several buffers fed in one call, and tails: cut in a
 * packet, in the size field, and a scan that finds no packet before the end. Prints "all
 * ur_realtime stream checks passed". */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ur_realtime_stream.h"

static int failures;
static ur_realtime_stream stream;           /* about 90 KiB: static, as the command keeps it */

#define MAX_FRAMES 64
#define MAX_STREAM 400000

/* What a frame said, with a checksum of its bytes. */
typedef struct seen {
    ur_realtime_frame_kind kind;
    uint64_t offset;
    size_t length;
    long size;                              /* bad sizes: the size and the error */
    int error;
    size_t needed;                          /* truncated tails */
    unsigned long sum;
} seen;

typedef struct frames {
    size_t count;
    seen f[MAX_FRAMES];
} frames;

static unsigned long checksum(const uint8_t *p, size_t n)
{
    unsigned long sum = 0;
    size_t i;
    for (i = 0; i < n; i++)
        sum = sum * 31u + p[i];
    return sum;
}

static void drain(frames *out)
{
    ur_realtime_stream_frame f;
    ur_realtime_frame_kind kind;
    while ((kind = ur_realtime_stream_next(&stream, &f)) != UR_REALTIME_FRAME_NEED_MORE &&
           kind != UR_REALTIME_FRAME_END) {
        seen *s = &out->f[out->count < MAX_FRAMES ? out->count : MAX_FRAMES - 1];
        memset(s, 0, sizeof *s);
        s->kind = kind;
        s->offset = f.offset;
        s->length = f.length;
        s->sum = checksum(f.bytes, f.length);
        if (kind == UR_REALTIME_FRAME_BAD_SIZE) {
            s->size = f.size;
            s->error = (int)f.error;
        }
        if (kind == UR_REALTIME_FRAME_TRUNCATED)
            s->needed = f.needed;
        out->count++;
    }
}

/* The stream fed in pieces that end at the given cuts (ascending), then finished. */
static void frame_cut(const uint8_t *data, size_t n, const size_t *cuts, size_t count, frames *out)
{
    size_t at = 0, k;
    ur_realtime_stream_frame last;
    out->count = 0;
    ur_realtime_stream_init(&stream);
    for (k = 0; k <= count; k++) {
        size_t end = k < count ? cuts[k] : n;
        while (at < end) {
            at += ur_realtime_stream_feed(&stream, data + at, end - at);
            drain(out);
        }
    }
    ur_realtime_stream_finish(&stream);
    drain(out);
    if (ur_realtime_stream_next(&stream, &last) != UR_REALTIME_FRAME_END) {
        printf("the finished stream did not end\n");
        failures++;
    }
}

static bool same(const frames *a, const frames *b)
{
    return a->count == b->count && memcmp(a->f, b->f, a->count * sizeof a->f[0]) == 0;
}

static void show(const char *what, const char *name, const frames *fs)
{
    size_t i;
    printf("%s: %s:\n", name, what);
    for (i = 0; i < fs->count && i < MAX_FRAMES; i++)
        printf("  kind %d offset %llu length %lu size %ld error %d needed %lu\n", (int)fs->f[i].kind,
               (unsigned long long)fs->f[i].offset, (unsigned long)fs->f[i].length, fs->f[i].size, fs->f[i].error,
               (unsigned long)fs->f[i].needed);
}

/* want: the frames, as kind, offset, length (a bad size: its size and error; a tail: needed). */
typedef struct want {
    ur_realtime_frame_kind kind;
    uint64_t offset;
    size_t length;
    long size;
    int error;
    size_t needed;
} want;

static void check(const char *name, const uint8_t *data, size_t n, const want *w, size_t count)
{
    static frames whole, cut;
    static size_t cuts[MAX_STREAM];
    size_t i, step = n > 2000 ? n / 997 : 1;
    frame_cut(data, n, NULL, 0, &whole);
    for (i = 0; i < count; i++) {
        const seen *s = &whole.f[i];
        if (i >= whole.count || s->kind != w[i].kind || s->offset != w[i].offset || s->length != w[i].length ||
            s->size != w[i].size || s->error != w[i].error || s->needed != w[i].needed ||
            s->sum != checksum(data + w[i].offset, w[i].length))
            break;
    }
    if (i < count || whole.count != count) {
        show("fed whole, not the frames listed", name, &whole);
        failures++;
        return;
    }
    /* A byte at a time, for the short streams. */
    if (n <= 2000) {
        for (i = 0; i + 1 < n; i++)
            cuts[i] = i + 1;
        frame_cut(data, n, cuts, n ? n - 1 : 0, &cut);
        if (!same(&whole, &cut)) {
            show("fed a byte at a time, other frames", name, &cut);
            failures++;
        }
    }
    /* Cut once, at every point (or at a spread of them). */
    for (i = 1; i < n; i += step) {
        cuts[0] = i;
        frame_cut(data, n, cuts, 1, &cut);
        if (!same(&whole, &cut)) {
            printf("cut at %lu: ", (unsigned long)i);
            show("other frames", name, &cut);
            failures++;
            return;
        }
    }
}

static uint8_t data[MAX_STREAM];

/* A packet of the given size at p, its doubles' bytes odd and counting up: no four of them make a
 * size that frames a packet, so a scan never stops inside one. */
static size_t packet(uint8_t *p, size_t size)
{
    size_t i;
    p[0] = (uint8_t)(size >> 24);
    p[1] = (uint8_t)(size >> 16);
    p[2] = (uint8_t)(size >> 8);
    p[3] = (uint8_t)size;
    for (i = 4; i < size; i++)
        p[i] = (uint8_t)(i * 2u + 1u);
    return size;
}

static size_t bytes(uint8_t *p, const char *text, size_t n)
{
    memcpy(p, text, n);
    return n;
}

enum { BELOW = UR_REALTIME_E_SIZE_BELOW, ABOVE = UR_REALTIME_E_SIZE_ABOVE };
#define PACKET UR_REALTIME_FRAME_PACKET
#define BAD_SIZE UR_REALTIME_FRAME_BAD_SIZE
#define TRUNCATED UR_REALTIME_FRAME_TRUNCATED

int main(void)
{
    size_t n, k;

    /* Whole packets: the e-Series layout (1220), a CB3 one (1108), and a size in bounds that no
     * layout has (20): framed whole, for the decoder to call unknown, with no scan after it. */
    n = packet(data, 1220);
    n += packet(data + n, 1108);
    n += packet(data + n, 20);
    n += packet(data + n, 540);
    {
        const want w[] = {{PACKET, 0, 1220, 0, 0, 0}, {PACKET, 1220, 1108, 0, 0, 0}, {PACKET, 2328, 20, 0, 0, 0},
                          {PACKET, 2348, 540, 0, 0, 0}};
        check("whole packets", data, n, w, 4);
    }

    /* Garbage first: a size below the smallest, then a size in bounds that no layout has (20) and
     * bytes no size starts with: one fault, at the first byte, with what it said; the scan passes
     * the size of no layout and stops at the packet. */
    n = bytes(data, "\x00\x00\x00\x05\x00\x00\x00\x14\xff\xff", 10);
    n += packet(data + n, 1220);
    {
        const want w[] = {{BAD_SIZE, 0, 4, 5, BELOW, 0}, {PACKET, 10, 1220, 0, 0, 0}};
        check("garbage prefix", data, n, w, 2);
    }

    /* A fault whose size field runs into a packet: the scan goes on from the byte after the
     * fault's first, not after its size field. */
    n = bytes(data, "\x00\x00", 2);
    n += packet(data + n, 1220);
    {
        const want w[] = {{BAD_SIZE, 0, 4, 0, BELOW, 0}, {PACKET, 2, 1220, 0, 0, 0}};
        check("a fault overlapping a packet", data, n, w, 2);
    }

    /* Sizes above the largest and negative ones. Two garbage runs, a packet between them: two
     * faults. */
    n = bytes(data, "\x7f\xff\xff\xff\xee", 5);
    n += packet(data + n, 1116);
    n += bytes(data + n, "\x80\x00\x00\x00", 4);
    n += packet(data + n, 764);
    {
        const want w[] = {{BAD_SIZE, 0, 4, 2147483647L, ABOVE, 0}, {PACKET, 5, 1116, 0, 0, 0},
                          {BAD_SIZE, 1121, 4, -2147483647L - 1, BELOW, 0}, {PACKET, 1125, 764, 0, 0, 0}};
        check("two garbage runs", data, n, w, 4);
    }

    /* The bounds: the largest size a packet may declare (no layout has it: framed whole), then one
     * byte more (a fault), then the smallest. */
    n = packet(data, UR_REALTIME_MAX_MESSAGE_SIZE);
    n += bytes(data + n, "\x00\x00\x2f\xa9", 4);
    n += packet(data + n, 692);
    n += packet(data + n, UR_REALTIME_MIN_MESSAGE_SIZE);
    {
        const want w[] = {{PACKET, 0, UR_REALTIME_MAX_MESSAGE_SIZE, 0, 0, 0},
                          {BAD_SIZE, UR_REALTIME_MAX_MESSAGE_SIZE, 4, UR_REALTIME_MAX_MESSAGE_SIZE + 1, ABOVE, 0},
                          {PACKET, UR_REALTIME_MAX_MESSAGE_SIZE + 4, 692, 0, 0, 0},
                          {PACKET, UR_REALTIME_MAX_MESSAGE_SIZE + 696, UR_REALTIME_MIN_MESSAGE_SIZE, 0, 0, 0}};
        check("the largest packet", data, n, w, 4);
    }

    /* Several buffers' worth of the largest packets in one feed: each feed takes what fits. */
    {
        want w[30];
        for (n = 0, k = 0; k < 30; k++) {
            memset(&w[k], 0, sizeof w[k]);
            w[k].kind = PACKET;
            w[k].offset = n;
            w[k].length = UR_REALTIME_MAX_MESSAGE_SIZE - k;
            n += packet(data + n, UR_REALTIME_MAX_MESSAGE_SIZE - k);
        }
        if (n <= UR_REALTIME_STREAM_BUFFER * 3) {
            printf("the long stream is not longer than three buffers\n");
            failures++;
        }
        check("streams longer than the buffer", data, n, w, 30);
    }

    /* Tails: a packet cut short, and a size field cut short. */
    n = packet(data, 1044);
    n += packet(data + n, 1060) - 1000;
    {
        const want w[] = {{PACKET, 0, 1044, 0, 0, 0}, {TRUNCATED, 1044, 60, 0, 0, 1060}};
        check("a cut packet", data, n, w, 2);
    }
    n = packet(data, 812);
    n += bytes(data + n, "\x00\x00\x04", 3);
    {
        const want w[] = {{PACKET, 0, 812, 0, 0, 0}, {TRUNCATED, 812, 3, 0, 0, UR_REALTIME_SIZE_FIELD_BYTES}};
        check("a cut size", data, n, w, 2);
    }
    /* After a fault: a scan that finds no packet before the end takes the rest with it; one that
     * finds a packet cut short leaves it a tail. */
    n = bytes(data, "\x00\x00\x00\x00\x00\x00\x00\x14\x01\x02\x03", 11);
    {
        const want w[] = {{BAD_SIZE, 0, 4, 0, BELOW, 0}};
        check("a scan to the end", data, n, w, 1);
    }
    n = bytes(data, "\x00\x00\x00\x00\x01", 5);
    n += packet(data + n, 1108) - 8;
    {
        const want w[] = {{BAD_SIZE, 0, 4, 0, BELOW, 0}, {TRUNCATED, 5, 1100, 0, 0, 1108}};
        check("a scan to a cut packet", data, n, w, 2);
    }
    check("nothing", data, 0, NULL, 0);

    if (failures)
        return 1;
    printf("all ur_realtime stream checks passed\n");
    return 0;
}
