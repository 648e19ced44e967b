/* The real-time interface (30003) as canonical JSON Lines: a raw stream framed packet by packet
 * (runtime/c/sized_packets/ur_realtime_stream.c), each packet and fault written as the Python
 * decoder writes it (docs/canonical-json.md). Part of the CLI. */
#ifndef URWIRE_UR_REALTIME_JSON_H
#define URWIRE_UR_REALTIME_JSON_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

#include "ur_realtime.h"

/* One decoded packet (or one of unknown size) as a JSON line on out, newline included. */
void ur_realtime_write_json(FILE *out, const ur_realtime_packet *p, size_t stream_offset);

/* Every packet of the stream in `in`, one line each; `version` chooses among layouts of one
 * size (0: unknown). Returns 0 when all decoded, 1 when the output holds error records, 2 on a
 * read error. */
int ur_realtime_print_stream(FILE *in, FILE *out, uint32_t version);

#endif
