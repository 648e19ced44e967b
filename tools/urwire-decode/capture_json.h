/* A .pcap or .pcapng capture's conversations as canonical JSON Lines, each record in its
 * conversation's envelope, as `urwire decode CAPTURE` writes them: read and reassembled by the C
 * capture reader (runtime/c/capture), each TCP conversation read by the interface of its port
 * (cell_interface.h), with a state of its own. Here too: the primary interface's conversation,
 * a framer and a JSON writer. Part of the CLI. */
#ifndef URWIRE_CAPTURE_JSON_H
#define URWIRE_CAPTURE_JSON_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "cell_interface.h"
#include "urwire.h"

/* Whether a file that starts with `head` (n bytes of it) is a capture: a whole pcap file header
 * (one of its four magics, then major version 2 in the magic's byte order) or the start of a
 * pcapng section header block (its type, a length, the byte-order magic), as capture.is_capture. */
bool capture_json_is_capture(const uint8_t *head, size_t n);

/* `head` (n bytes, already read) and the rest of `in`: the conversations of every interface, or
 * of `only` when not NULL; `hinted`: the version was given. 0 when all decoded, 1 when the output
 * holds error records, 2 on a read error or when memory runs out. */
int capture_json_print(const uint8_t *head, size_t n, FILE *in, FILE *out, const cell_interface *only,
                       urwire_sw_version version, bool hinted);

#endif
