/* <standalone> */
#ifndef UR_DASHBOARD_RUNTIME_LINES_H
#define UR_DASHBOARD_RUNTIME_LINES_H
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#define UR_DASHBOARD_MAX_LINE 4096
/* </standalone> */
/* ---- lines, commands and replies ----------------------------------------------------------- */

#define UR_DASHBOARD_PENDING 256     /* commands awaiting a reply that a conversation keeps */
#define UR_DASHBOARD_NONE (-1)       /* no command: an unknown one, or a reply with none pending */

/* Bytes of the caller's buffer: never copied, valid while the buffer is. */
typedef struct ur_dashboard_view {
    const uint8_t *ptr;
    size_t len;
} ur_dashboard_view;

/* A reply pattern: literal pieces, each placeholder between two of them taking any text. */
typedef struct ur_dashboard_reply_spec {
    const char *name;
    const char *const *pieces;
    size_t piece_count;
    bool error;               /* the reply says that the command failed */
} ur_dashboard_reply_spec;

typedef struct ur_dashboard_command_spec {
    const char *name;
    const char *text;         /* the words that open the line */
    bool takes_argument;
    uint32_t since_cb;        /* ur_dashboard_version(...) of the first CB version; 0: none */
    uint32_t since_e_series;  /* the same for the e-Series (5.x and later); 0: none */
    const ur_dashboard_reply_spec *replies;
    size_t reply_count;
} ur_dashboard_command_spec;

typedef enum ur_dashboard_record_type {
    UR_DASHBOARD_COMMAND,     /* a line from the client */
    UR_DASHBOARD_REPLY,       /* a line from the server, the banner too */
    UR_DASHBOARD_FAULT        /* a line too long, or bytes without a newline at the end */
} ur_dashboard_record_type;

typedef enum ur_dashboard_fault {
    UR_DASHBOARD_LINE_TOO_LONG,        /* line longer than UR_DASHBOARD_MAX_LINE bytes */
    UR_DASHBOARD_NO_NEWLINE_AT_END     /* <bytes> bytes without a newline at the end of the stream */
} ur_dashboard_fault;

typedef struct ur_dashboard_record {
    ur_dashboard_record_type type;
    ur_dashboard_view text;            /* the line without its "\n" (or "\r\n") */
    int command_name;                  /* the command (ur_dashboard_commands index) or UR_DASHBOARD_NONE */
    bool has_argument;
    ur_dashboard_view argument;
    int available;                     /* commands: 1 or 0 when the version is known, else -1 */
    const ur_dashboard_reply_spec *reply_name;   /* replies: the one matched, or NULL */
    bool error;                        /* replies: reply_name says an error */
    ur_dashboard_fault fault;          /* faults: what, where (the direction's offset) and how many bytes */
    uint64_t offset;
    size_t bytes;
} ur_dashboard_record;

typedef struct ur_dashboard_direction {
    uint64_t offset;                   /* of the next byte to decode */
    bool skipping;                     /* inside a line too long, dropped up to its newline */
} ur_dashboard_direction;

/* One TCP connection: both directions and the commands awaiting their replies. Caller-owned. */
typedef struct ur_dashboard_conversation {
    ur_dashboard_direction commands, replies;
    int16_t pending[UR_DASHBOARD_PENDING];
    size_t head, count;
    uint32_t version;                  /* ur_dashboard_version(...), 0 while unknown */
    bool greeted;
} ur_dashboard_conversation;

/* major.minor.bugfix as one number that compares in version order. */
uint32_t ur_dashboard_version(uint32_t major, uint32_t minor, uint32_t bugfix);
/* A conversation with nothing read; version 0 when not known (the version reply teaches it). */
void ur_dashboard_init(ur_dashboard_conversation *c, uint32_t version);
/* Read one record from the front of buf, the next bytes of one direction. Returns the bytes
 * used, and sets *got when rec holds a record. 0 with *got false: a line is not whole yet;
 * call again with more bytes (at most UR_DASHBOARD_MAX_LINE + 2 are ever needed). */
size_t ur_dashboard_decode(ur_dashboard_conversation *c, bool from_robot, const uint8_t *buf, size_t n,
                           ur_dashboard_record *rec, bool *got);
/* At the end of a direction: the n bytes left without a newline, as a fault record (true), or
 * nothing to report (false). */
bool ur_dashboard_finish(ur_dashboard_conversation *c, bool from_robot, size_t n, ur_dashboard_record *rec);
/* The command a line is (an index, or UR_DASHBOARD_NONE), and its argument. */
int ur_dashboard_find_command(ur_dashboard_view line, ur_dashboard_view *argument, bool *has_argument);
/* The reply a line is: a common reply, else one of the command's (command may be UR_DASHBOARD_NONE). */
const ur_dashboard_reply_spec *ur_dashboard_classify(int command, ur_dashboard_view line);
bool ur_dashboard_matches(const ur_dashboard_reply_spec *reply, ur_dashboard_view line);
bool ur_dashboard_available(int command, uint32_t version);
/* The record as a line of canonical JSON (no newline) in out, NUL-terminated when cap > 0.
 * Returns its length; when that is cap or more, out holds its first cap - 1 bytes. */
size_t ur_dashboard_json(const ur_dashboard_record *rec, char *out, size_t cap);
/* <standalone> */
#endif
/* </standalone> */
