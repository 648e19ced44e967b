/* The real-time interface (30003) as canonical JSON Lines: the robot's stream framed packet by
 * packet (runtime/c/sized_packets/ur_realtime_stream.c), each packet and fault written as the
 * Python decoder writes it (docs/canonical-json.md); a conversation of cell_interface.h. Part of
 * the CLI. */
#ifndef URWIRE_UR_REALTIME_JSON_H
#define URWIRE_UR_REALTIME_JSON_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

#include "envelope.h"
#include "ur_realtime.h"
#include "ur_realtime_stream.h"

/* One decoded packet (or one of unknown size) as a JSON line on out, newline included, in its
 * envelope when e is not NULL. */
void ur_realtime_write_record(FILE *out, const envelope *e, const ur_realtime_packet *p, size_t stream_offset);
void ur_realtime_write_json(FILE *out, const ur_realtime_packet *p, size_t stream_offset);

/* A connection: the robot's stream, and the version that chooses among layouts of one size (0:
 * unknown), given or learnt from the robot's primary stream. */
typedef struct ur_realtime_conversation {
    ur_realtime_stream stream;
    uint32_t version;
    bool hinted;
} ur_realtime_conversation;

#endif
