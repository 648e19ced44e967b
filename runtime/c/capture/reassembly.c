/* One direction of a TCP conversation reassembled (reassembly.h). The held segments are an array
 * sorted by falling position, so that the earliest, the next to deliver, is popped off its end. */
#include "reassembly.h"

#include <stdlib.h>
#include <string.h>

#include "growing.h"

static int64_t delta(uint32_t seq, uint32_t ref)
{
    uint32_t d = seq - ref;
    return d >= 0x80000000u ? (int64_t)d - ((int64_t)1 << 32) : (int64_t)d;
}

static void put(urwire_capture_pieces *out, urwire_capture_piece_kind kind, int64_t offset, int64_t length,
                int64_t differing)
{
    urwire_capture_piece *p;
    if (!urwire_capture_grow((void **)&out->pieces, &out->capacity, out->n + 1, sizeof *out->pieces)) {
        out->no_memory = true;
        return;
    }
    p = &out->pieces[out->n++];
    p->kind = kind;
    p->offset = offset;
    p->length = length;
    p->differing = differing;
}

static void put_bytes(urwire_capture_pieces *out, const uint8_t *data, size_t n)
{
    if (!urwire_capture_grow((void **)&out->bytes, &out->bytes_capacity, out->n_bytes + n, 1)) {
        out->no_memory = true;
        return;
    }
    memcpy(out->bytes + out->n_bytes, data, n);
    put(out, URWIRE_PIECE_BYTES, (int64_t)out->n_bytes, (int64_t)n, 0);
    out->n_bytes += n;
}

void urwire_capture_pieces_clear(urwire_capture_pieces *out)
{
    out->n = out->n_bytes = 0;
    out->no_memory = false;
}

void urwire_capture_pieces_free(urwire_capture_pieces *out)
{
    free(out->pieces);
    free(out->bytes);
    memset(out, 0, sizeof *out);
}

void urwire_capture_reassembly_init(urwire_capture_reassembly *r, bool started, uint32_t next_seq)
{
    memset(r, 0, sizeof *r);
    r->started = started;
    r->next_seq = next_seq;
}

void urwire_capture_reassembly_free(urwire_capture_reassembly *r)
{
    size_t i;
    for (i = 0; i < r->n_held; i++)
        free(r->held[i].data);
    free(r->held);
    free(r->history);
    memset(r, 0, sizeof *r);
}

/* Two copies of the stream's bytes from `at` on: a "differs" when their common part differs. */
static void same(int64_t at, const uint8_t *first, size_t n_first, const uint8_t *second, size_t n_second,
                 urwire_capture_pieces *out)
{
    size_t n = n_first < n_second ? n_first : n_second, i, differing = 0;
    for (i = 0; i < n; i++)
        differing += first[i] != second[i];
    if (differing)
        put(out, URWIRE_PIECE_DIFFERS, at, (int64_t)n, (int64_t)differing);
}

/* Bytes of the stream from `at` on, delivered before: said when they differ. */
static void compare(urwire_capture_reassembly *r, int64_t at, const uint8_t *data, size_t n,
                    urwire_capture_pieces *out)
{
    int64_t kept_from = r->position - (int64_t)r->history_length;
    size_t start, kept;
    if (at < kept_from) {
        put(out, URWIRE_PIECE_DIFFERS, at, (int64_t)n, 0);
        return;
    }
    start = (size_t)(at - kept_from);
    kept = start < r->history_length ? r->history_length - start : 0;
    same(at, r->history + start, kept < n ? kept : n, data, n, out);
}

static void advance(urwire_capture_reassembly *r, int64_t n)
{
    r->position += n;
    r->next_seq = (uint32_t)(r->next_seq + (uint64_t)n);
}

static void deliver(urwire_capture_reassembly *r, const uint8_t *piece, size_t n, urwire_capture_pieces *out)
{
    const size_t kept = URWIRE_CAPTURE_HISTORY_KEPT;
    put_bytes(out, piece, n);
    advance(r, (int64_t)n);
    if (r->history_length + n <= 2 * kept) {
        if (!urwire_capture_grow((void **)&r->history, &r->history_capacity, r->history_length + n, 1)) {
            out->no_memory = true;
            return;
        }
        memcpy(r->history + r->history_length, piece, n);
        r->history_length += n;
        return;
    }
    if (!urwire_capture_grow((void **)&r->history, &r->history_capacity, kept, 1)) {
        out->no_memory = true;
        return;
    }
    if (n >= kept) {
        memcpy(r->history, piece + n - kept, kept);
    } else {
        memmove(r->history, r->history + r->history_length - (kept - n), kept - n);
        memcpy(r->history + kept - n, piece, n);
    }
    r->history_length = kept;
}

/* Where a segment at `at` is, or goes, in the array sorted by falling position. */
static size_t place_of(const urwire_capture_reassembly *r, int64_t at)
{
    size_t lo = 0, hi = r->n_held;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (r->held[mid].at > at)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

static void hold(urwire_capture_reassembly *r, int64_t at, const uint8_t *data, size_t n, urwire_capture_pieces *out)
{
    size_t i = place_of(r, at);
    if (i < r->n_held && r->held[i].at == at) {
        urwire_capture_held *kept = &r->held[i];
        uint8_t *longer;
        same(at, kept->data, kept->length, data, n, out);
        if (kept->length >= n)
            return;  /* a retransmission of bytes already held */
        longer = realloc(kept->data, n);    /* the first copy stands, the longer one adds to it */
        if (longer == NULL) {
            out->no_memory = true;
            return;
        }
        memcpy(longer + kept->length, data + kept->length, n - kept->length);
        r->held_bytes += (int64_t)(n - kept->length);
        kept->data = longer;
        kept->length = n;
    } else {
        uint8_t *copy = malloc(n);
        if (copy == NULL || !urwire_capture_grow((void **)&r->held, &r->held_capacity, r->n_held + 1, sizeof *r->held)) {
            free(copy);
            out->no_memory = true;
            return;
        }
        memcpy(copy, data, n);
        memmove(&r->held[i + 1], &r->held[i], (r->n_held - i) * sizeof *r->held);
        r->held[i].at = at;
        r->held[i].length = n;
        r->held[i].data = copy;
        r->n_held++;
        r->held_bytes += (int64_t)(n + URWIRE_CAPTURE_SEGMENT_COST);
    }
    if (at + (int64_t)n > r->furthest)
        r->furthest = at + (int64_t)n;
}

#define EARLIEST(r) ((r)->held[(r)->n_held - 1])

/* Deliver the held bytes the stream has reached, earliest first, each segment once. */
static void drain(urwire_capture_reassembly *r, urwire_capture_pieces *out)
{
    while (r->n_held && EARLIEST(r).at <= r->position) {
        urwire_capture_held segment = EARLIEST(r);
        size_t seen = (size_t)(r->position - segment.at);
        r->n_held--;
        r->held_bytes -= (int64_t)(segment.length + URWIRE_CAPTURE_SEGMENT_COST);
        if (seen)
            compare(r, segment.at, segment.data, seen < segment.length ? seen : segment.length, out);
        if (seen < segment.length)
            deliver(r, segment.data + seen, segment.length - seen, out);
        free(segment.data);
    }
}

void urwire_capture_skip_gap(urwire_capture_reassembly *r, urwire_capture_pieces *out)
{
    int64_t length = EARLIEST(r).at - r->position;
    put(out, URWIRE_PIECE_GAP, r->position, length, 0);
    advance(r, length);
    r->history_length = 0;  /* what came before the gap is not what a retransmission repeats */
    drain(r, out);
}

/* Give up the gaps behind held bytes that reach further than the peer's largest window. */
static void beyond_window(urwire_capture_reassembly *r, urwire_capture_pieces *out)
{
    while (r->n_held && r->window > 0 && r->furthest - r->position > 0 &&
           r->window < (uint64_t)(r->furthest - r->position))
        urwire_capture_skip_gap(r, out);
}

void urwire_capture_add(urwire_capture_reassembly *r, uint32_t seq, const uint8_t *data, size_t n,
                        urwire_capture_pieces *out)
{
    int64_t ahead;
    if (!r->started) {
        r->started = true;
        r->next_seq = seq;  /* the capture starts mid-stream */
    }
    ahead = delta(seq, r->next_seq);
    if (ahead > 0) {
        hold(r, r->position + ahead, data, n, out);
        beyond_window(r, out);
        return;
    }
    if ((uint64_t)-ahead >= n) {
        compare(r, r->position + ahead, data, n, out);  /* a retransmission of bytes delivered */
        return;
    }
    if (ahead < 0)
        compare(r, r->position + ahead, data, (size_t)-ahead, out);
    deliver(r, data + (size_t)-ahead, n - (size_t)-ahead, out);
    if (r->n_held)
        drain(r, out);
}

void urwire_capture_ack(urwire_capture_reassembly *r, uint32_t seq, uint64_t window, urwire_capture_pieces *out)
{
    if (window > r->window)
        r->window = window;
    while (r->n_held && delta(seq, r->next_seq) > EARLIEST(r).at - r->position)
        urwire_capture_skip_gap(r, out);
    beyond_window(r, out);
}

void urwire_capture_flush(urwire_capture_reassembly *r, urwire_capture_pieces *out)
{
    while (r->n_held)
        urwire_capture_skip_gap(r, out);
}

bool urwire_capture_keep_alive(const urwire_capture_reassembly *r, uint32_t seq, size_t n)
{
    return n == 1 && r->started && delta(seq, r->next_seq) == -1;
}
