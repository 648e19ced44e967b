/* <standalone> */
#ifndef URWIRE_RUNTIME_FRAMER_H
#define URWIRE_RUNTIME_FRAMER_H
#include "runtime_spec.h"
/* </standalone> */
/* ---- framing a stream --------------------------------------------------------------------- */

/* A framer buffer this large frames every legal message; smaller ones skip bigger messages. */
#define URWIRE_FRAMER_MIN_BUFFER (URWIRE_MAX_MESSAGE_LENGTH + 4096u)

typedef enum urwire_frame_kind {
    URWIRE_FRAME_NEED_MORE,         /* feed more bytes (or finish) */
    URWIRE_FRAME_MESSAGE,           /* bytes, length, offset and version are set */
    URWIRE_FRAME_FAULT,             /* fault is set; the framer resynchronises by itself */
    URWIRE_FRAME_END                /* finished and drained */
} urwire_frame_kind;

typedef struct urwire_frame {
    urwire_frame_kind kind;
    const uint8_t *bytes;           /* inside the framer's buffer: valid until the next feed */
    size_t length;
    uint64_t offset;                /* of the message or fault, from the stream's first byte */
    urwire_sw_version version;      /* to decode this message with (assumed: see its doc) */
    urwire_error fault;
} urwire_frame;

/* Frames a byte stream in a caller-provided buffer. Tracks the software version from the
 * stream's Version messages (else the hint; with URWIRE_DEFAULT_VERSION as the hint, which is
 * only assumed, from the layout sizes of robot states where they show it: learnt from the
 * robot state you decoded when you hand it back with urwire_framer_learn, else by a walk over
 * its sub-package headers when the framer next moves on). After a bad length or type it scans
 * forward byte by byte to the next plausible header; the skipped bytes belong to that one
 * fault. When the stream ends inside a message, the rest is scanned the same way for whole
 * messages. */
typedef struct urwire_framer {
    uint8_t *buf;
    size_t cap;
    size_t head;                    /* first byte not yet framed */
    size_t len;                     /* bytes held */
    uint64_t base;                  /* stream offset of buf[0] */
    size_t skip;                    /* bytes still to drop of a message bigger than buf (at most
                                       URWIRE_MAX_MESSAGE_LENGTH) */
    bool resyncing;
    bool finished;
    bool ended_inside;              /* the stream ended inside a message: rescans stop only at
                                       whole messages */
    bool version_seen;              /* a Version message set the version */
    bool version_out_of_range;      /* the last Version message's bugfix was below 0 or above
                                       URWIRE_BUGFIX_ANY, where it cannot compare with the spec's
                                       bounds: version is its major.minor.0 (the message itself
                                       keeps the number) */
    urwire_sw_version version;      /* in force: the last Version message's, else the hint, else
                                       what a robot state's layout sizes showed (assumed), else
                                       URWIRE_DEFAULT_VERSION (assumed) */
    size_t unlearnt;                /* the length of the robot state just handed out whose layout
                                       sizes may still show the version (0: none) */
} urwire_framer;

void urwire_framer_init(urwire_framer *f, uint8_t *buf, size_t cap, urwire_sw_version hint);
/* Copies up to n bytes in; returns how many it took (fewer when the buffer is full: call
 * urwire_framer_next until URWIRE_FRAME_NEED_MORE, then feed the rest). */
size_t urwire_framer_feed(urwire_framer *f, const uint8_t *data, size_t n);
/* The stream has ended: what is left becomes a truncated-message or truncated-header fault,
 * and the whole messages inside a truncated message's span are framed after it. */
void urwire_framer_finish(urwire_framer *f);
urwire_frame_kind urwire_framer_next(urwire_framer *f, urwire_frame *out);
/* The stream lost bytes (a capture's gap, a reconnection): what is held is dropped and framing
 * starts afresh, its next byte at stream offset `offset`, the version in force kept. Drain the
 * framer first (urwire_framer_finish, then urwire_framer_next until URWIRE_FRAME_END) for the
 * faults and messages it still holds. */
void urwire_framer_restart(urwire_framer *f, uint64_t offset);
/* Optional, after decoding the message of the last frame with its frame.version: takes the
 * version its layout sizes show from your decoding (m->implied, m->implied_version), so that
 * the framer does not walk a robot state's sub-packages a second time. The versions it tracks
 * are the same either way; any other message is ignored. */
void urwire_framer_learn(urwire_framer *f, const urwire_message *m);
/* <standalone> */
#endif
/* </standalone> */
