/* RTDE records as canonical JSON lines (docs/canonical-json.md), the same bytes as the Python
 * `urwire.rtde.Conversation` and `urwire.to_json_line` give: for `urwire-decode --protocol rtde`.
 * Hand-written; part of the command, not of the library (generated/c/rtde.{h,c}). */
#ifndef RTDE_JSON_H
#define RTDE_JSON_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "cell_interface.h"
#include "envelope.h"
#include "rtde.h"
#include "rtde_stream.h"

/* The storage of a connection's recipes and pending names at the protocol's own limits (82 MB):
 * every recipe a robot and a client can make is kept, as the Python decoder keeps them. A test
 * harness on a board with less RAM defines smaller limits (RTDE_JSON_RECIPES and the others). */
#ifndef RTDE_JSON_RECIPES
#define RTDE_JSON_RECIPES RTDE_PROTOCOL_RECIPES
#define RTDE_JSON_VARIABLES RTDE_PROTOCOL_VARIABLES
#define RTDE_JSON_NAMES RTDE_PROTOCOL_NAMES
#endif
#define RTDE_JSON_STORAGE RTDE_STORAGE_SIZE(RTDE_JSON_RECIPES, RTDE_JSON_VARIABLES, RTDE_JSON_NAMES)

/* One connection: its RTDE state and both directions' framing (runtime/c/typed_messages/rtde_stream.h). Large:
 * static, where only the pages a connection uses are ever touched. */
typedef struct rtde_json_stream {
    rtde_conversation conversation;
    union {
        unsigned char bytes[RTDE_JSON_STORAGE];
        uint64_t align_u;
        double align_d;
        void *align_p;
    } storage;                          /* the conversation's recipes and pending names */
    rtde_stream direction[2];           /* [1]: from the robot */
    /* Each direction's records' envelope ([1]: from the robot; NULL: records as they are), the
     * end of its stream included, as `urwire decode --to-robot` reports them. */
    const envelope *envelope[2];
} rtde_json_stream;

/* A connection with no envelopes; set s->envelope after this to have them. */
void rtde_json_stream_init(rtde_json_stream *s);

/* Bytes of one direction, as they arrive: each record they complete, one line each, on out.
 * Returns the number of error records written: stream faults (bad headers) and messages kept
 * whole with an "error" (short, long, of an unknown recipe), each of which makes the command
 * exit 1, as in the Python command. */
int rtde_json_feed(rtde_json_stream *s, const uint8_t *data, size_t length, bool from_robot, FILE *out);

/* The ends of both streams (the client's first): a truncated tail becomes an error record, in
 * its own direction's envelope. Returns how many it wrote. */
int rtde_json_close(rtde_json_stream *s, FILE *out);
/* The end of one direction's stream alone. */
int rtde_json_close_direction(rtde_json_stream *s, bool from_robot, FILE *out);

/* One decoded message (or what rtde_decode said of it, e) as one line, in envelope env if not
 * NULL. Returns 1 when the line carries an "error", else 0. */
int rtde_json_record(FILE *out, const envelope *env, const rtde_message *m, rtde_error e, size_t at,
                     const uint8_t *msg, size_t size);

#endif
