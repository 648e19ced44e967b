#ifndef URWIRE_CAPTURE_H
#define URWIRE_CAPTURE_H
/* A .pcap or .pcapng capture in, in chunks of any size; the TCP streams of the ports asked for
 * out, each direction reassembled: the C twin of python/urwire/capture.py's timed_streams, by the
 * same rules and with the same texts (capture_file.h reads the records, capture_packet.h the
 * layers, reassembly.h each direction).
 *
 * Items come out through a callback, in the order timed_streams yields them: a stream's bytes
 * (joined between faults; the last of a segment's items says whether the stream ended), a gap,
 * a retransmission that differs, or a fault of the capture file. Memory: the bytes held out of
 * order by all streams are bounded by URWIRE_CAPTURE_MAX_PENDING (the stream holding the most then
 * gives up its gap); each stream keeps at most 2 * URWIRE_CAPTURE_HISTORY_KEPT bytes it delivered;
 * the rest grows with what the capture holds, never beyond it. Hand-written for hosts (malloc). */
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "capture_packet.h"

#define URWIRE_CAPTURE_MAX_PENDING (16 << 20)

typedef struct urwire_capture urwire_capture;

/* A TCP conversation: the robot's side is the one on a port asked for. */
typedef struct urwire_capture_conversation {
    char robot[URWIRE_CAPTURE_ADDRESS_TEXT], client[URWIRE_CAPTURE_ADDRESS_TEXT];
    uint16_t robot_port, client_port;
    void *user;                         /* the caller's own, NULL until it sets it */
} urwire_capture_conversation;

typedef enum urwire_capture_item_kind {
    URWIRE_ITEM_BYTES, URWIRE_ITEM_GAP, URWIRE_ITEM_DIFFERS, URWIRE_ITEM_FAULT
} urwire_capture_item_kind;

typedef struct urwire_capture_item {
    urwire_capture_item_kind kind;
    urwire_capture_conversation *conversation;   /* NULL for a fault */
    bool from_robot, ended;
    double time;                        /* of the frame that brought it (the last frame's at the end) */
    const uint8_t *data;                /* bytes: valid during the callback */
    size_t length;
    int64_t offset, missing, differing; /* gap: offset, missing; differs: offset, missing (the bytes at
                                           stake), differing; fault: offset in the file */
    const char *error;                  /* fault */
} urwire_capture_item;

/* Nonzero stops the reading: urwire_capture_feed and _finish return it. */
typedef int (*urwire_capture_emit)(void *context, const urwire_capture_item *item);

/* A TCP conversation on none of the ports: server and client as python/urwire/capture.py's
 * OtherConversations tells them, with the bytes it carried. */
typedef struct urwire_capture_other {
    char server[URWIRE_CAPTURE_ADDRESS_TEXT], client[URWIRE_CAPTURE_ADDRESS_TEXT];
    uint16_t server_port, client_port;
    uint64_t bytes;
} urwire_capture_other;

#define URWIRE_CAPTURE_NO_MEMORY (-1)

/* `ports`: the robot sides read; `both_ways`: those whose client->robot bytes are read too;
 * `others`: whether to count the conversations on no port. NULL when out of memory. */
urwire_capture *urwire_capture_new(const uint16_t *ports, size_t n_ports, const uint16_t *both_ways,
                                   size_t n_both_ways, bool others);
int urwire_capture_feed(urwire_capture *c, const uint8_t *data, size_t n, urwire_capture_emit emit,
                        void *context);
/* The end of the file: what it leaves unread is a fault, then every stream ends. */
int urwire_capture_finish(urwire_capture *c, urwire_capture_emit emit, void *context);
size_t urwire_capture_others(const urwire_capture *c, const urwire_capture_other **others);
/* Each conversation once, for the caller to release what it set in `user`. */
void urwire_capture_each_conversation(urwire_capture *c, void (*visit)(urwire_capture_conversation *));
void urwire_capture_free(urwire_capture *c);
#endif
