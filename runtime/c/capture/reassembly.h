#ifndef URWIRE_CAPTURE_REASSEMBLY_H
#define URWIRE_CAPTURE_REASSEMBLY_H
/* One direction of a TCP conversation: segments in, its stream out as pieces, in order, by the
 * rules of python/urwire/capture.py's _Reassembly: bytes; a gap where bytes are given up as
 * missing; a "differs" where a retransmission disagrees with the bytes it repeats (identical
 * retransmissions are dropped without a word). Out-of-order segments are held until the gap
 * closes or the capture shows it final. */
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define URWIRE_CAPTURE_SEGMENT_COST 200u        /* what holding a segment costs beyond its bytes */
#define URWIRE_CAPTURE_HISTORY_KEPT (256u << 10) /* bytes kept after delivery, to compare retransmissions with */

typedef enum urwire_capture_piece_kind {
    URWIRE_PIECE_BYTES, URWIRE_PIECE_GAP, URWIRE_PIECE_DIFFERS
} urwire_capture_piece_kind;

typedef struct urwire_capture_piece {
    urwire_capture_piece_kind kind;
    int64_t offset, length, differing;  /* gap, differs; bytes: `length` bytes at `offset` of the output's bytes */
} urwire_capture_piece;

/* What a step gives out: pieces in order, the bytes of all of them in one buffer. */
typedef struct urwire_capture_pieces {
    urwire_capture_piece *pieces;
    size_t n, capacity;
    uint8_t *bytes;
    size_t n_bytes, bytes_capacity;
    bool no_memory;
} urwire_capture_pieces;

typedef struct urwire_capture_held {
    int64_t at;             /* stream position */
    size_t length;
    uint8_t *data;
} urwire_capture_held;

typedef struct urwire_capture_reassembly {
    bool started;           /* next_seq known */
    uint32_t next_seq;
    int64_t position;       /* where next_seq is in the stream: the bytes delivered so far */
    urwire_capture_held *held;      /* ahead of next_seq, by position */
    size_t n_held, held_capacity;
    int64_t held_bytes;     /* the memory they take: their bytes and SEGMENT_COST each */
    uint64_t window;        /* the peer's largest window, in bytes (0: none seen yet) */
    int64_t furthest;       /* the stream position where the bytes held end */
    uint8_t *history;       /* the last bytes delivered, up to `position` */
    size_t history_length, history_capacity;
} urwire_capture_reassembly;

void urwire_capture_reassembly_init(urwire_capture_reassembly *r, bool started, uint32_t next_seq);
void urwire_capture_reassembly_free(urwire_capture_reassembly *r);
void urwire_capture_add(urwire_capture_reassembly *r, uint32_t seq, const uint8_t *data, size_t n,
                        urwire_capture_pieces *out);
void urwire_capture_ack(urwire_capture_reassembly *r, uint32_t seq, uint64_t window, urwire_capture_pieces *out);
void urwire_capture_skip_gap(urwire_capture_reassembly *r, urwire_capture_pieces *out);
void urwire_capture_flush(urwire_capture_reassembly *r, urwire_capture_pieces *out);
/* A TCP keep-alive probe: one byte (of any value) just before the next expected one. */
bool urwire_capture_keep_alive(const urwire_capture_reassembly *r, uint32_t seq, size_t n);

void urwire_capture_pieces_clear(urwire_capture_pieces *out);
void urwire_capture_pieces_free(urwire_capture_pieces *out);
#endif
