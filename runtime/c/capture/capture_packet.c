/* A frame's TCP segment (capture_packet.h). */
#include "capture_packet.h"

#include <stdio.h>

#define ETH_IP 0x0800u
#define ETH_IP6 0x86DDu
#define IP_TCP 6u

static uint16_t be16(const uint8_t *p)
{
    return (uint16_t)(p[0] << 8 | p[1]);
}

static uint32_t be32(const uint8_t *p)
{
    return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
}

static bool tcp(const uint8_t *p, size_t n, urwire_capture_segment *out)
{
    size_t offset;
    if (n < 20u)
        return false;
    offset = (size_t)(p[12] >> 4) * 4u;
    if (offset < 20u)
        return false;
    out->sport = be16(p);
    out->dport = be16(p + 2);
    out->seq = be32(p + 4);
    out->ack = be32(p + 8);
    out->flags = p[13];
    out->window = be16(p + 14);
    out->options = p + 20;
    out->options_length = (offset < n ? offset : n) - 20u;
    out->data = p + (offset < n ? offset : n);
    out->length = offset < n ? n - offset : 0;
    return true;
}

static bool ipv4(const uint8_t *p, size_t n, urwire_capture_segment *out)
{
    size_t header, total, start, end;
    if (n < 20u)
        return false;
    header = (size_t)(p[0] & 0x0Fu) * 4u;
    if (header < 20u)
        return false;
    total = be16(p + 2);
    start = header < n ? header : n;
    end = total && total < n ? total : n;
    if ((be16(p + 6) & 0x1FFFu) != 0 || p[9] != IP_TCP)
        return false;
    out->family = 4;
    out->src = p + 12;
    out->dst = p + 16;
    return tcp(p + start, end > start ? end - start : 0, out);
}

static bool ipv6(const uint8_t *p, size_t n, urwire_capture_segment *out)
{
    const uint8_t *buf = p + 40;
    size_t left, payload;
    unsigned next, first;
    bool fragment_later = false;
    if (n < 40u)
        return false;
    payload = be16(p + 4);
    left = payload && payload < n - 40u ? payload : n - 40u;
    first = next = p[6];
    for (;;) {
        size_t length;
        if (next == 0u || next == 60u || next == 43u) {          /* hop-by-hop, destination, routing */
            if (left < (next == 43u ? 8u : 2u))
                return false;
            length = ((size_t)buf[1] + 1u) * 8u;
        } else if (next == 44u) {                                 /* fragment */
            if (left < 8u)
                return false;
            length = 8u;
            fragment_later = (be16(buf + 2) >> 3) > 0;
        } else if (next == 51u) {                                 /* authentication */
            if (left < 12u)
                return false;
            length = ((size_t)buf[1] + 2u) * 4u;
        } else if (next == 50u) {                                 /* ESP: nothing after it is read */
            return false;
        } else {
            break;
        }
        next = buf[0];
        if (length > left)
            length = left;
        buf += length;
        left -= length;
    }
    if ((first == 44u && fragment_later) || next != IP_TCP)
        return false;
    out->family = 6;
    out->src = p + 8;
    out->dst = p + 24;
    return tcp(buf, left, out);
}

static bool by_ethertype(unsigned type, const uint8_t *p, size_t n, urwire_capture_segment *out)
{
    if (type == ETH_IP)
        return ipv4(p, n, out);
    if (type == ETH_IP6)
        return ipv6(p, n, out);
    return false;
}

static bool ethernet(const uint8_t *p, size_t n, urwire_capture_segment *out)
{
    unsigned type, tags;
    if (n < 14u)
        return false;
    type = be16(p + 12);
    if (type <= 1500u)
        return false;       /* 802.3 lengths (LLC, SNAP): not read */
    p += 14;
    n -= 14;
    if (type == 0x8100u || type == 0x88A8u || type == 0x9100u || type == 0x9200u) {
        for (tags = 0; tags < 2u; tags++) {     /* a VLAN tag, or two (QinQ) */
            if (n < 4u)
                return false;
            type = be16(p + 2);
            p += 4;
            n -= 4;
            if (type != 0x8100u)
                break;
        }
    }
    return by_ethertype(type, p, n, out);
}

static bool loopback(const uint8_t *p, size_t n, urwire_capture_segment *out)
{
    uint32_t family;
    if (n < 4u)
        return false;
    family = be32(p);      /* the writer's own byte order: the families are checked in both */
    if (family == 0x02u || family == 0x02000000u)
        return ipv4(p + 4, n - 4, out);
    if (family == 0x18u || family == 0x18000000u || family == 0x1Cu || family == 0x1C000000u ||
        family == 0x1Eu || family == 0x1E000000u)
        return ipv6(p + 4, n - 4, out);
    return ethernet(p + 4, n - 4, out);
}

bool urwire_capture_segment_of(uint32_t linktype, const uint8_t *frame, size_t n, urwire_capture_segment *out)
{
    switch (linktype) {
    case 1:             /* Ethernet */
        return ethernet(frame, n, out);
    case 113:           /* Linux cooked (SLL) */
        return n >= 16u && by_ethertype(be16(frame + 14), frame + 16, n - 16, out);
    case 276:           /* Linux cooked v2 (SLL2) */
        return n >= 20u && by_ethertype(be16(frame), frame + 20, n - 20, out);
    case 0:             /* BSD loopback/null */
        return loopback(frame, n, out);
    case 12: case 14: case 101: case 228: case 229:     /* raw IP */
        if (n >= 1u && frame[0] >> 4 == 4u)
            return ipv4(frame, n, out);
        return ipv6(frame, n, out);
    default:
        return false;
    }
}

unsigned urwire_capture_window_shift(const urwire_capture_segment *segment)
{
    const uint8_t *p = segment->options;
    size_t left = segment->options_length;
    while (left) {
        size_t length;
        if (p[0] <= 1u) {       /* end of options, no-op: one byte */
            p++;
            left--;
            continue;
        }
        if (left < 2u)
            return 0;
        length = p[1] < 2u ? 2u : p[1];
        if (p[0] == 3u && length == 3u && left >= 3u)
            return p[2] < 14u ? p[2] : 14u;
        if (length > left)
            length = left;
        p += length;
        left -= length;
    }
    return 0;
}

void urwire_capture_address_text(uint8_t family, const uint8_t *address, char text[URWIRE_CAPTURE_ADDRESS_TEXT])
{
    unsigned words[8], i, best = 8, best_length = 0, run = 0;
    char *o = text;
    if (family == 4) {
        (void)snprintf(text, URWIRE_CAPTURE_ADDRESS_TEXT, "%u.%u.%u.%u", address[0], address[1], address[2],
                       address[3]);
        return;
    }
    for (i = 0; i < 8u; i++) {
        words[i] = (unsigned)address[2 * (size_t)i] << 8 | address[2 * (size_t)i + 1];
        run = words[i] ? 0 : run + 1;
        if (run > best_length) {
            best_length = run;
            best = i + 1 - run;
        }
    }
    if (best_length < 2u)
        best = 8;
    for (i = 0; i < 8u; i++) {
        if (i == best) {
            *o++ = ':';
            i += best_length - 1;
            if (i == 7u)
                *o++ = ':';
            continue;
        }
        if (i)
            *o++ = ':';
        if (i == 6u && best == 0 && (best_length == 6u || (best_length == 7u && words[7] != 1u) ||
                                      (best_length == 5u && words[5] == 0xFFFFu))) {
            (void)snprintf(o, (size_t)(text + URWIRE_CAPTURE_ADDRESS_TEXT - o), "%u.%u.%u.%u", address[12],
                           address[13], address[14], address[15]);
            return;
        }
        o += snprintf(o, (size_t)(text + URWIRE_CAPTURE_ADDRESS_TEXT - o), "%x", words[i]);
    }
    *o = '\0';
}
