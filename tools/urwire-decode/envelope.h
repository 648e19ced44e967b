/* The envelope of a record read with --to-robot: the interface, the direction and the
 * conversation (the file the record came from), written before the record's own keys, as
 * `urwire decode --protocol NAME FILE --to-robot FILE2` writes them
 * (docs/canonical-json.md#records-of-the-other-interfaces). Part of the CLI. */
#ifndef URWIRE_ENVELOPE_H
#define URWIRE_ENVELOPE_H

#include <stdio.h>

typedef struct envelope {
    const char *interface;              /* "rtde" */
    const char *direction;              /* "from_robot" or "to_robot" */
    const char *conversation;           /* the file's name as given */
} envelope;

/* Writes "{" and, with an envelope, its three keys: the record's own keys follow. */
void envelope_open(FILE *out, const envelope *e);

/* A record's JSON object (`{...}`, no newline) as one line, enveloped when e is not NULL. */
void envelope_line(FILE *out, const envelope *e, const char *record);

#endif
