/* The envelope of a record of a capture or read with --to-robot: the interface, the direction and
 * the conversation (its TCP endpoints, or the file the record came from), written before the
 * record's own keys, as `urwire decode` writes them
 * (docs/canonical-json.md#records-of-the-other-interfaces). Part of the CLI. */
#ifndef URWIRE_ENVELOPE_H
#define URWIRE_ENVELOPE_H

#include <stdint.h>
#include <stdio.h>

typedef struct envelope {
    const char *interface;              /* "rtde" */
    const char *direction;              /* "from_robot" or "to_robot" */
    const char *conversation;           /* the endpoints, or the file's name as given */
} envelope;

/* Writes "{" and, with an envelope, its three keys: the record's own keys follow. */
void envelope_open(FILE *out, const envelope *e);

/* A record's JSON object (`{...}`, no newline) as one line, enveloped when e is not NULL. */
void envelope_line(FILE *out, const envelope *e, const char *record);

/* An error record, {"type": "error", "offset": N, "error": TEXT}, as one line in its envelope:
 * what the Python decoder's StreamError writes (a gap, the end of a record whose start is lost). */
void envelope_error(FILE *out, const envelope *e, int64_t offset, const char *error);

#endif
