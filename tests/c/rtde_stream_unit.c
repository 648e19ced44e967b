/* RTDE stream framing on its own (runtime/c/typed_messages/rtde_stream.c): each stream below is framed whole, a
 * byte at a time and cut at every point (or at a spread of points for the long ones), and must give
 * the frames it lists, with their offsets, sizes and bytes: whole messages, a garbage prefix as one
 * fault however it was cut, a fault after each of two garbage runs, the largest message a uint16
 * size allows, a stream of several buffers fed in one call, and tails cut in a message or in a
 * header. Prints "all rtde stream checks passed". */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rtde_stream.h"

static int failures;
static rtde_stream stream;                  /* 64 KiB: static, as the command keeps it */

#define MAX_FRAMES 64
#define MAX_STREAM 300000

/* What a frame said, with a checksum of its bytes. */
typedef struct seen {
    rtde_frame_kind kind;
    uint64_t offset;
    size_t length;
    size_t size;                            /* bad headers: the size field and the type code */
    unsigned code;
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
    rtde_frame f;
    rtde_frame_kind kind;
    while ((kind = rtde_stream_next(&stream, &f)) != RTDE_FRAME_NEED_MORE && kind != RTDE_FRAME_END) {
        seen *s = &out->f[out->count < MAX_FRAMES ? out->count : MAX_FRAMES - 1];
        memset(s, 0, sizeof *s);
        s->kind = kind;
        s->offset = f.offset;
        s->length = f.length;
        if (kind == RTDE_FRAME_BAD_HEADER) {
            s->size = f.size;
            s->code = f.code;
        } else {
            s->sum = checksum(f.bytes, f.length);
        }
        out->count++;
    }
}

/* The stream fed in pieces that end at the given cuts (ascending), then finished. */
static void frame_cut(const uint8_t *data, size_t n, const size_t *cuts, size_t count, frames *out)
{
    size_t at = 0, k;
    rtde_frame last;
    out->count = 0;
    rtde_stream_init(&stream);
    for (k = 0; k <= count; k++) {
        size_t end = k < count ? cuts[k] : n;
        while (at < end) {
            at += rtde_stream_feed(&stream, data + at, end - at);
            drain(out);
        }
    }
    rtde_stream_finish(&stream);
    drain(out);
    if (rtde_stream_next(&stream, &last) != RTDE_FRAME_END) {
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
        printf("  kind %d offset %llu length %lu size %lu code %u\n", (int)fs->f[i].kind,
               (unsigned long long)fs->f[i].offset, (unsigned long)fs->f[i].length, (unsigned long)fs->f[i].size,
               fs->f[i].code);
}

/* want: the frames, as kind, offset, length (and for a bad header its size and code). */
typedef struct want {
    rtde_frame_kind kind;
    uint64_t offset;
    size_t length;
    size_t size;
    unsigned code;
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
            s->size != w[i].size || s->code != w[i].code ||
            (s->kind != RTDE_FRAME_BAD_HEADER && s->sum != checksum(data + w[i].offset, w[i].length)))
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

/* A message of the given size and type code at p, its body bytes counting up. */
static size_t message(uint8_t *p, size_t size, uint8_t code)
{
    size_t i;
    p[0] = (uint8_t)(size >> 8);
    p[1] = (uint8_t)size;
    p[2] = code;
    for (i = 3; i < size; i++)
        p[i] = (uint8_t)(i * 7u);
    return size;
}

int main(void)
{
    size_t n, k;

    /* Whole messages: a protocol version request ('V', 5 bytes) and a text message ('M'). */
    n = message(data, 5, 'V');
    n += message(data + n, 12, 'M');
    {
        const want w[] = {{RTDE_FRAME_MESSAGE, 0, 5, 0, 0}, {RTDE_FRAME_MESSAGE, 5, 12, 0, 0}};
        check("two messages", data, n, w, 2);
    }

    /* Garbage first: a size below the header's, then bytes no header starts with: one fault, at
     * the first byte, with what its header said; the message after it is whole. */
    memcpy(data, "\x00\x01V\xff\xff\xff\x00\x00", 8);
    n = 8 + message(data + 8, 5, 'V');
    {
        const want w[] = {{RTDE_FRAME_BAD_HEADER, 0, 3, 1, 'V'}, {RTDE_FRAME_MESSAGE, 8, 5, 0, 0}};
        check("garbage prefix", data, n, w, 2);
    }

    /* A type code no layout has: a fault of its own size and code. Two garbage runs, a message
     * between them: two faults. */
    memcpy(data, "\x00\x09\x01\x01", 4);
    n = 4 + message(data + 4, 5, 'V');
    memcpy(data + n, "\x00\x02V", 3);
    n += 3;
    n += message(data + n, 4, 'V');
    {
        const want w[] = {{RTDE_FRAME_BAD_HEADER, 0, 3, 9, 1}, {RTDE_FRAME_MESSAGE, 4, 5, 0, 0},
                          {RTDE_FRAME_BAD_HEADER, 9, 3, 2, 'V'}, {RTDE_FRAME_MESSAGE, 12, 4, 0, 0}};
        check("two garbage runs", data, n, w, 4);
    }

    /* The largest message a uint16 size allows, between two small ones. */
    n = message(data, 4, 'V');
    n += message(data + n, 65535, 'U');
    n += message(data + n, 4, 'V');
    {
        const want w[] = {{RTDE_FRAME_MESSAGE, 0, 4, 0, 0}, {RTDE_FRAME_MESSAGE, 4, 65535, 0, 0},
                          {RTDE_FRAME_MESSAGE, 65539, 4, 0, 0}};
        check("the largest message", data, n, w, 3);
    }

    /* Four buffers' worth of large messages in one feed: each feed takes what fits. */
    {
        want w[5];
        for (n = 0, k = 0; k < 5; k++) {
            w[k].kind = RTDE_FRAME_MESSAGE;
            w[k].offset = n;
            w[k].length = 60000 - k;
            w[k].size = 0;
            w[k].code = 0;
            n += message(data + n, 60000 - k, 'U');
        }
        check("streams longer than the buffer", data, n, w, 5);
    }

    /* Tails: a message cut short, and two bytes left after a fault's scan. */
    n = message(data, 5, 'V');
    n += message(data + n, 40, 'M') - 30;
    {
        const want w[] = {{RTDE_FRAME_MESSAGE, 0, 5, 0, 0}, {RTDE_FRAME_TRUNCATED, 5, 10, 0, 0}};
        check("a cut message", data, n, w, 2);
    }
    memcpy(data, "\x00\x00V\x00\x00", 5);
    {
        const want w[] = {{RTDE_FRAME_BAD_HEADER, 0, 3, 0, 'V'}, {RTDE_FRAME_TRUNCATED, 3, 2, 0, 0}};
        check("a scan to the end", data, 5, w, 2);
    }
    {
        const want w[] = {{RTDE_FRAME_TRUNCATED, 0, 2, 0, 0}};
        check("a cut header", data, 2, w, 1);
    }
    check("nothing", data, 0, NULL, 0);

    if (failures)
        return 1;
    printf("all rtde stream checks passed\n");
    return 0;
}
