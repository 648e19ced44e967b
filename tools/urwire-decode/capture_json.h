/* A .pcap or .pcapng capture's primary/secondary conversations as canonical JSON Lines, each record
 * in its conversation's envelope, as `urwire decode --protocol ur CAPTURE` writes them: read and
 * reassembled by the C capture reader (runtime/c/capture), a framer per conversation. Part of the
 * CLI. */
#ifndef URWIRE_CAPTURE_JSON_H
#define URWIRE_CAPTURE_JSON_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "urwire.h"

/* Whether a file that starts with `head` (n bytes of it) is a capture: a whole pcap file header
 * (one of its four magics, then major version 2 in the magic's byte order) or the start of a
 * pcapng section header block (its type, a length, the byte-order magic), as capture.is_capture. */
bool capture_json_is_capture(const uint8_t *head, size_t n);

/* `head` (n bytes, already read) and the rest of `in`; 0 when all decoded, 1 when the output
 * holds error records, 2 on a read error or when memory runs out. */
int capture_json_print(const uint8_t *head, size_t n, FILE *in, FILE *out, urwire_sw_version hint);

#endif
