#ifndef URWIRE_CAPTURE_PACKET_H
#define URWIRE_CAPTURE_PACKET_H
/* A frame's TCP segment, through its link and IP layers, as python/urwire/capture.py reads them
 * with dpkt: Ethernet (802.1Q and QinQ tags), Linux cooked (SLL, SLL2), loopback/null, raw IP;
 * IPv4 (its total length trims the frame; a fragment other than the first holds no TCP header)
 * and IPv6 (its payload length, its extension headers). */
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define URWIRE_CAPTURE_ADDRESS_TEXT 46   /* INET6_ADDRSTRLEN */
#define URWIRE_TCP_FIN 0x01u
#define URWIRE_TCP_SYN 0x02u
#define URWIRE_TCP_RST 0x04u
#define URWIRE_TCP_ACK 0x10u
#define URWIRE_TCP_WSCALE_UNKNOWN 14u    /* a window's scale when the handshake is not in the capture */

typedef struct urwire_capture_segment {
    uint8_t family;                      /* 4 or 6 */
    const uint8_t *src, *dst;            /* 4 or 16 bytes */
    uint16_t sport, dport, window;
    uint32_t seq, ack;
    uint8_t flags;
    const uint8_t *options, *data;
    size_t options_length, length;
} urwire_capture_segment;

bool urwire_capture_segment_of(uint32_t linktype, const uint8_t *frame, size_t n, urwire_capture_segment *out);
/* The window scale a SYN segment asks for (RFC 7323: at most 14), 0 without the option. */
unsigned urwire_capture_window_shift(const urwire_capture_segment *segment);
/* An address as the C library's inet_ntop writes it (glibc's forms for IPv6). */
void urwire_capture_address_text(uint8_t family, const uint8_t *address, char text[URWIRE_CAPTURE_ADDRESS_TEXT]);
#endif
