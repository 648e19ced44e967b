/* <standalone> */
#ifndef LINES_RUNTIME_LINES_H
#define LINES_RUNTIME_LINES_H
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#define LINES_MAX_LINE 4096
/* </standalone> */
/* ---- lines, commands and replies ----------------------------------------------------------- */

#define LINES_PENDING 256     /* commands awaiting a reply that a conversation keeps */
/* What a reader of raw files keeps in a queue of its own (lines_keep_pending): the client's whole
 * file comes before the server's, so every command of a session awaits its reply at once. */
#define LINES_PENDING_RAW (1u << 20)
#define LINES_NONE (-1)       /* no command: an unknown one, or a reply with none pending */

/* Bytes of the caller's buffer: never copied, valid while the buffer is. */
typedef struct lines_view {
    const uint8_t *ptr;
    size_t len;
} lines_view;

/* A reply pattern: literal pieces, each placeholder between two of them taking any text. */
typedef struct lines_reply_spec {
    const char *name;
    const char *const *pieces;
    size_t piece_count;
    bool error;               /* the reply says that the command failed */
} lines_reply_spec;

typedef struct lines_command_spec {
    const char *name;
    const char *text;         /* the words that open the line */
    bool takes_argument;
    uint32_t since_cb;        /* lines_version(...) of the first CB version; 0: none */
    uint32_t since_e_series;  /* the same for the e-Series (5.x and later); 0: none */
    const lines_reply_spec *replies;
    size_t reply_count;
} lines_command_spec;

typedef enum lines_record_type {
    LINES_COMMAND,     /* a line from the client */
    LINES_REPLY,       /* a line from the server, the banner too */
    LINES_FAULT        /* a line too long, or bytes without a newline at the end */
} lines_record_type;

typedef enum lines_fault {
    LINES_LINE_TOO_LONG,        /* line longer than LINES_MAX_LINE bytes */
    LINES_NO_NEWLINE_AT_END     /* <bytes> bytes without a newline at the end of the stream */
} lines_fault;

typedef struct lines_record {
    lines_record_type type;
    lines_view text;            /* the line without its "\n" (or "\r\n") */
    int command_name;                  /* the command (lines_commands index) or LINES_NONE */
    bool has_argument;
    lines_view argument;
    int available;                     /* commands: 1 or 0 when the version is known, else -1 */
    const lines_reply_spec *reply_name;   /* replies: the one matched, or NULL */
    bool error;                        /* replies: reply_name says an error */
    bool not_kept;                     /* commands: not kept to pair; replies: answers such a
                                          command ("more than <kept> commands awaited replies") */
    size_t kept;                       /* the conversation's bound, when not_kept */
    lines_fault fault;          /* faults: what, where (the direction's offset) and how many bytes */
    uint64_t offset;
    size_t bytes;
} lines_record;

typedef struct lines_direction {
    uint64_t offset;                   /* of the next byte to decode */
    bool skipping;                     /* inside a line too long, dropped up to its newline */
} lines_direction;

/* One TCP connection: both directions and the commands awaiting their replies. Caller-owned.
 * A command that comes when LINES_PENDING await is not kept but counted lost, and so is every
 * command behind a lost one (replies come in order); a reply with none kept answers a lost one. */
typedef struct lines_conversation {
    lines_direction commands, replies;
    int16_t pending[LINES_PENDING];
    int16_t *more;                     /* the caller's longer queue (lines_keep_pending), or NULL */
    size_t head, count, lost, kept;
    uint32_t version;                  /* lines_version(...), 0 while unknown */
    bool greeted;
} lines_conversation;

/* major.minor.bugfix as one number that compares in version order. */
uint32_t lines_version(uint32_t major, uint32_t minor, uint32_t bugfix);
/* A conversation with nothing read; version 0 when not known (the version reply teaches it). */
void lines_init(lines_conversation *c, uint32_t version);
/* Before any line: keep up to n commands awaiting replies in queue (n entries, the caller's, as
 * long as the conversation) instead of LINES_PENDING; raw files take LINES_PENDING_RAW. */
void lines_keep_pending(lines_conversation *c, int16_t *queue, size_t n);
/* Read one record from the front of buf, the next bytes of one direction. Returns the bytes
 * used, and sets *got when rec holds a record. 0 with *got false: a line is not whole yet;
 * call again with more bytes (at most LINES_MAX_LINE + 2 are ever needed). */
size_t lines_decode(lines_conversation *c, bool from_robot, const uint8_t *buf, size_t n,
                           lines_record *rec, bool *got);
/* At the end of a direction: the n bytes left without a newline, as a fault record (true), or
 * nothing to report (false). */
bool lines_finish(lines_conversation *c, bool from_robot, size_t n, lines_record *rec);
/* The command a line is (an index, or LINES_NONE), and its argument. */
int lines_find_command(lines_view line, lines_view *argument, bool *has_argument);
/* The reply a line is: a common reply, else one of the command's (command may be LINES_NONE). */
const lines_reply_spec *lines_classify(int command, lines_view line);
bool lines_matches(const lines_reply_spec *reply, lines_view line);
bool lines_available(int command, uint32_t version);
/* The record as a line of canonical JSON (no newline) in out, NUL-terminated when cap > 0.
 * Returns its length; when that is cap or more, out holds its first cap - 1 bytes. */
size_t lines_json(const lines_record *rec, char *out, size_t cap);
/* <standalone> */
#endif
/* </standalone> */
