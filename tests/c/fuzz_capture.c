/* libFuzzer harness: the C capture reader (runtime/c/capture) over any bytes, under ASan and
 * UBSan. The input is read whole and again in chunks whose sizes its first byte sets (down to
 * one byte at a time): both readings must give the same items, as a reader that holds the tail
 * of a record between feeds must. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "capture.h"

typedef struct {
    uint64_t hash, items;
} digest;

static void mix(digest *d, const void *data, size_t n)
{
    const uint8_t *p = data;
    size_t i;
    for (i = 0; i < n; i++)
        d->hash = (d->hash ^ p[i]) * 1099511628211u;
}

static int note(void *context, const urwire_capture_item *item)
{
    digest *d = context;
    mix(d, &item->kind, sizeof item->kind);
    mix(d, &item->from_robot, sizeof item->from_robot);
    mix(d, &item->ended, sizeof item->ended);
    mix(d, &item->time, sizeof item->time);
    mix(d, &item->offset, sizeof item->offset);
    mix(d, &item->missing, sizeof item->missing);
    mix(d, &item->differing, sizeof item->differing);
    mix(d, item->data, item->length);
    if (item->error != NULL)
        mix(d, item->error, strlen(item->error));
    if (item->conversation != NULL) {
        mix(d, item->conversation->robot, strlen(item->conversation->robot));
        mix(d, item->conversation->client, strlen(item->conversation->client));
    }
    d->items++;
    return 0;
}

static digest read_in_chunks(const uint8_t *data, size_t size, size_t chunk)
{
    static const uint16_t ports[] = {30001, 30002, 30003, 30004, 29999, 50001};
    static const uint16_t both_ways[] = {30004, 29999, 50001};
    digest d = {1469598103934665603u, 0};
    urwire_capture *capture = urwire_capture_new(ports, 6, both_ways, 3, true);
    const urwire_capture_other *others;
    size_t at, n, i;
    if (capture == NULL)
        abort();
    for (at = 0; at < size; at += n) {
        n = size - at < chunk ? size - at : chunk;
        if (urwire_capture_feed(capture, data + at, n, note, &d) != 0)
            abort();
    }
    if (urwire_capture_finish(capture, note, &d) != 0)
        abort();
    n = urwire_capture_others(capture, &others);
    for (i = 0; i < n; i++)
        mix(&d, &others[i], sizeof others[i]);
    urwire_capture_free(capture);
    return d;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    size_t chunk = size ? (size_t)data[0] % 64u + 1u : 1u;
    digest whole = read_in_chunks(data, size, size ? size : 1), chunked;
    if (size > 1u << 16)
        chunk *= 1024u;    /* byte by byte is for small inputs */
    chunked = read_in_chunks(data, size, chunk);
    if (whole.hash != chunked.hash || whole.items != chunked.items)
        abort();
    return 0;
}
