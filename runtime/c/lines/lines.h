/* <standalone> */
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include "match.h"
/* </standalone> */
/* ---- lines, commands and replies ----------------------------------------------------------- */
/* The types of the C library's records and conversations, which every interface of the kind
 * shares: its generated header names them after the interface (ur_dashboard_record, ...) and
 * declares its functions. Guarded: two interfaces' headers may meet in one file. */
#ifndef URWIRE_LINES_H
#define URWIRE_LINES_H

#define LINES_PENDING 256     /* commands awaiting a reply that a conversation keeps */
/* What a reader of raw files keeps in a queue of its own (lines_keep_pending): the client's whole
 * file comes before the server's, so every command of a session awaits its reply at once. */
#define LINES_PENDING_RAW (1u << 20)

/* Bytes of the caller's buffer: never copied, valid while the buffer is. */
typedef struct lines_view {
    const uint8_t *ptr;
    size_t len;
} lines_view;

typedef enum lines_record_type {
    LINES_COMMAND,     /* a line from the client */
    LINES_REPLY,       /* a line from the server, the banner too */
    LINES_FAULT        /* a line too long, or bytes without a newline at the end */
} lines_record_type;

typedef enum lines_fault {
    LINES_LINE_TOO_LONG,        /* line longer than the interface's longest (lines_spec_t.max_line) */
    LINES_NO_NEWLINE_AT_END     /* <bytes> bytes without a newline at the end of the stream */
} lines_fault;

typedef struct lines_record {
    lines_record_type type;
    lines_view text;                   /* the line without its "\n" (or "\r\n") */
    int command_name;                  /* the command (the spec's index) or LINES_NONE */
    bool has_argument;
    lines_view argument;
    int available;                     /* commands: 1 or 0 when the version is known, else -1 */
    const lines_reply_t *reply_name;   /* replies: the one matched, or NULL */
    bool error;                        /* replies: reply_name says an error */
    bool not_kept;                     /* commands: not kept to pair; replies: answers such a
                                          command ("more than <kept> commands awaited replies") */
    bool cut;                          /* the first line after bytes lost in its direction: its
                                          start may be lost (a reply so pairs with none) */
    bool unknown;                      /* replies: after bytes lost, the command it answers is unknown */
    size_t kept;                       /* the conversation's bound, when not_kept */
    lines_fault fault;                 /* faults: what, where (the direction's offset), how many bytes */
    uint64_t offset;
    size_t bytes;
} lines_record;

typedef struct lines_direction {
    uint64_t offset;                   /* of the next byte to decode */
    bool skipping;                     /* inside a line too long, dropped up to its newline */
    bool cut;                          /* bytes were lost before the next line (lines_lost) */
} lines_direction;

/* One TCP connection: both directions and the commands awaiting their replies. Caller-owned.
 * A command that comes when LINES_PENDING await is not kept but counted lost, and so is every
 * command behind a lost one (replies come in order); a reply with none kept answers a lost one.
 * Bytes lost from a capture (lines_lost) may have held commands or answered them: from then on,
 * a reply with none kept answers one unknown (`unknown`; one reply per request: for good, as no
 * later byte tells how many the gap held; else until the next command). */
typedef struct lines_conversation {
    lines_direction commands, replies;
    int16_t pending[LINES_PENDING];
    int16_t *more;                     /* the caller's longer queue (lines_keep_pending), or NULL */
    size_t head, count, lost, kept;
    uint32_t version;                  /* lines_version(...), 0 while unknown */
    bool greeted;
    bool unknown;
} lines_conversation;

#endif
