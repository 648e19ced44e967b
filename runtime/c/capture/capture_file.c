/* The records of a .pcap or .pcapng file (capture_file.h). */
#include "capture_file.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PCAP_HEADER 24u
#define PCAP_RECORD_HEADER 16u
#define PCAPNG_SECTION_HEADER 28u   /* type, length, byte order, version, section length */
#define PCAPNG_BLOCK_MIN 12u        /* type, length, trailing length */
#define PCAPNG_PACKET_HEADER 32u    /* an (enhanced) packet block up to its data, and its trailer */
#define PCAPNG_INTERFACE_HEADER 20u
#define BT_SECTION 0x0A0D0D0Au
#define BT_INTERFACE 1u
#define BT_PACKET 2u                /* the obsolete packet block */
#define BT_ENHANCED_PACKET 6u
#define OPT_END 0u
#define OPT_TSRESOL 9u
#define OPT_TSOFFSET 14u

static uint32_t load32(const uint8_t *p, bool little)
{
    return little ? (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24
                  : (uint32_t)p[3] | (uint32_t)p[2] << 8 | (uint32_t)p[1] << 16 | (uint32_t)p[0] << 24;
}

static uint16_t load16(const uint8_t *p, bool little)
{
    return (uint16_t)(little ? p[0] | p[1] << 8 : p[1] | p[0] << 8);
}

void urwire_capture_file_init(urwire_capture_file *file)
{
    memset(file, 0, sizeof *file);
}

void urwire_capture_file_free(urwire_capture_file *file)
{
    free(file->interfaces);
    file->interfaces = NULL;
    file->n_interfaces = file->capacity = 0;
}

/* The fault whose text is in record->fault, at file offset `at`; `stop`: reading stops there. */
static urwire_capture_step faulted(urwire_capture_file *file, urwire_capture_record *record, uint64_t at, bool stop)
{
    record->fault_offset = at;
    if (stop)
        file->state = URWIRE_CAPTURE_DONE;
    return URWIRE_CAPTURE_FAULTED;
}

/* FAULT(file, record, at, stop, format, ...): the text written, then faulted. */
#define FAULT(file, record, at, stop, ...) \
    ((void)snprintf((record)->fault, sizeof (record)->fault, __VA_ARGS__), faulted(file, record, at, stop))

/* 10^n or 2^n units per second, as if_tsresol says (exact as far as a double holds them). */
static double resolution(uint8_t tsresol)
{
    double divisor = 1.0, base = tsresol & 0x80u ? 2.0 : 10.0;
    unsigned n = tsresol & 0x7Fu;
    while (n--)
        divisor *= base;
    return divisor;
}

/* An interface description block's link type and timestamp options. */
static urwire_capture_step describe_interface(urwire_capture_file *file, const uint8_t *block, uint32_t length,
                                              urwire_capture_record *record, uint64_t at, bool in_header)
{
    urwire_capture_interface face;
    uint32_t o = PCAPNG_INTERFACE_HEADER - 4u;
    if (length < PCAPNG_INTERFACE_HEADER)
        return in_header ? FAULT(file, record, 0, true, "capture header unreadable (got %u, %u needed at least): "
                                 "nothing decoded", (unsigned)length, PCAPNG_INTERFACE_HEADER)
                         : FAULT(file, record, at, false, "damaged pcapng interface block skipped (got %u, %u "
                                 "needed at least)", (unsigned)length, PCAPNG_INTERFACE_HEADER);
    face.linktype = load16(block + 8, file->little);
    face.divisor = 1e6;
    face.offset = 0;
    while (o + 4u <= length - 4u) {
        uint32_t code = load16(block + o, file->little), size = load16(block + o + 2, file->little);
        const uint8_t *value = block + o + 4;
        uint32_t room = length - 4u - (o + 4u);
        if (size > room)
            size = room;
        if (code == OPT_END)
            break;
        if (code == OPT_TSRESOL && size >= 1u)
            face.divisor = resolution(value[0]);
        else if (code == OPT_TSOFFSET && size >= 8u) {
            uint64_t hi = load32(value, file->little), lo = load32(value + 4, file->little);
            uint64_t u = file->little ? lo << 32 | hi : hi << 32 | lo;
            face.offset = (int64_t)u;
        }
        o += 4u + ((size + 3u) & ~3u);
    }
    if (file->n_interfaces == file->capacity) {
        size_t capacity = file->capacity ? 2 * file->capacity : 4;
        urwire_capture_interface *grown;
        if (file->n_interfaces >= URWIRE_CAPTURE_MAX_INTERFACES)
            return FAULT(file, record, at, false, "pcapng interface block skipped: more than %u interfaces",
                         URWIRE_CAPTURE_MAX_INTERFACES);
        grown = realloc(file->interfaces, capacity * sizeof *grown);
        if (grown == NULL)
            return URWIRE_CAPTURE_OUT_OF_MEMORY;
        file->interfaces = grown;
        file->capacity = capacity;
    }
    file->interfaces[file->n_interfaces++] = face;
    return URWIRE_CAPTURE_SKIP;
}

/* The pcapng section header and the blocks up to the first interface description: what the
 * Python reader's dpkt takes as the file header. */
static urwire_capture_step pcapng_header(urwire_capture_file *file, const uint8_t *buf, size_t n, bool at_end,
                                         size_t *taken, urwire_capture_record *record)
{
    size_t o;
    uint32_t length;
    if (n < PCAPNG_SECTION_HEADER)
        return at_end ? FAULT(file, record, 0, true, "capture header unreadable (invalid pcapng header): "
                              "nothing decoded")
                      : URWIRE_CAPTURE_MORE;
    if (load32(buf + 8, true) != 0x1A2B3C4Du && load32(buf + 8, false) != 0x1A2B3C4Du)
        return FAULT(file, record, 0, true, "capture header unreadable (unknown endianness): nothing decoded");
    file->little = load32(buf + 8, true) == 0x1A2B3C4Du;
    length = load32(buf + 4, file->little);
    if (length < PCAPNG_SECTION_HEADER || length % 4u)
        return FAULT(file, record, 0, true, "capture header unreadable (pcapng block length %u is not valid): "
                     "nothing decoded", (unsigned)length);
    if (n < length)     /* dpkt's text: its section header block wants more bytes than there are */
        return at_end ? FAULT(file, record, 0, true, "capture header unreadable (NeedData): nothing decoded")
                      : URWIRE_CAPTURE_MORE;
    if (load32(buf + length - 4u, file->little) != length)
        return FAULT(file, record, 0, true, "capture header unreadable (length fields do not match): nothing decoded");
    if (load16(buf + 12, file->little) != 1u)
        return FAULT(file, record, 0, true, "capture header unreadable (unknown pcapng version %u.%u): nothing decoded",
                     (unsigned)load16(buf + 12, file->little), (unsigned)load16(buf + 14, file->little));
    for (o = length;;) {
        uint32_t kind, size;
        if (n - o < 8u || n - o < (size = load32(buf + o + 4, file->little))) {
            if (!at_end)
                return URWIRE_CAPTURE_MORE;
            return FAULT(file, record, 0, true, "capture header unreadable (%s): nothing decoded",
                         n - o >= 8u && load32(buf + o, file->little) == BT_INTERFACE ? "NeedData" : "IDB not found");
        }
        kind = load32(buf + o, file->little);
        if (size < PCAPNG_BLOCK_MIN || size % 4u)
            return FAULT(file, record, 0, true, "capture header unreadable (pcapng block length %u is not valid): "
                         "nothing decoded", (unsigned)size);
        if (kind == BT_INTERFACE) {
            urwire_capture_step step;
            if (size >= PCAPNG_INTERFACE_HEADER && load32(buf + o + size - 4u, file->little) != size)
                return FAULT(file, record, 0, true, "capture header unreadable (length fields do not match): "
                             "nothing decoded");
            step = describe_interface(file, buf + o, size, record, 0, true);
            if (step != URWIRE_CAPTURE_SKIP)
                return step;
            *taken = o + size;
            file->state = URWIRE_CAPTURE_PCAPNG;
            return URWIRE_CAPTURE_SKIP;
        }
        o += size;
    }
}

static urwire_capture_step pcap_header(urwire_capture_file *file, const uint8_t *buf, size_t n, bool at_end,
                                       size_t *taken, urwire_capture_record *record)
{
    uint32_t magic;
    if (n < PCAP_HEADER)
        return at_end ? FAULT(file, record, 0, true, "capture header unreadable (got %u, %u needed at least): "
                              "nothing decoded", (unsigned)n, PCAP_HEADER)
                      : URWIRE_CAPTURE_MORE;
    magic = load32(buf, false);
    if (magic != 0xA1B2C3D4u && magic != 0xD4C3B2A1u && magic != 0xA1B23C4Du && magic != 0x4D3CB2A1u)
        return FAULT(file, record, 0, true, "capture header unreadable (invalid tcpdump header): nothing decoded");
    file->little = buf[0] != 0xA1;
    file->nano = magic == 0xA1B23C4Du || magic == 0x4D3CB2A1u;
    file->snaplen = load32(buf + 16, file->little);
    file->linktype = load32(buf + 20, file->little);
    file->state = URWIRE_CAPTURE_PCAP;
    *taken = PCAP_HEADER;
    return URWIRE_CAPTURE_SKIP;
}

static urwire_capture_step pcap_record(urwire_capture_file *file, const uint8_t *buf, size_t n, bool at_end,
                                       size_t *taken, urwire_capture_record *record)
{
    uint32_t caplen, limit = file->snaplen > URWIRE_CAPTURE_PCAP_RECORD_MAX ? file->snaplen
                                                                           : URWIRE_CAPTURE_PCAP_RECORD_MAX;
    if (n < PCAP_RECORD_HEADER) {
        if (!at_end)
            return URWIRE_CAPTURE_MORE;
        if (n == 0) {
            file->state = URWIRE_CAPTURE_DONE;
            return URWIRE_CAPTURE_END;
        }
        return FAULT(file, record, file->offset, true, "capture cut short in a record header: reading stopped");
    }
    caplen = load32(buf + 8, file->little);
    if (caplen > limit)
        return FAULT(file, record, file->offset, true, "pcap record length %u exceeds the snap length %u: "
                     "reading stopped", (unsigned)caplen, (unsigned)limit);
    if (n - PCAP_RECORD_HEADER < caplen)
        return at_end ? FAULT(file, record, file->offset, true, "capture cut short in a record of %u bytes: "
                              "reading stopped", (unsigned)caplen)
                      : URWIRE_CAPTURE_MORE;
    record->data = buf + PCAP_RECORD_HEADER;
    record->length = caplen;
    record->linktype = file->linktype;
    record->time = (double)load32(buf, file->little) +
                   (double)load32(buf + 4, file->little) / (file->nano ? 1e9 : 1e6);
    *taken = PCAP_RECORD_HEADER + caplen;
    return URWIRE_CAPTURE_FRAME;
}

static urwire_capture_step pcapng_packet(urwire_capture_file *file, const uint8_t *block, uint32_t length,
                                         uint32_t kind, urwire_capture_record *record)
{
    uint32_t face, caplen;
    uint64_t stamp;
    const urwire_capture_interface *described;
    if (length < PCAPNG_PACKET_HEADER)
        return FAULT(file, record, file->offset, false, "damaged pcapng packet block skipped (got %u, %u needed at "
                     "least)", (unsigned)length, PCAPNG_PACKET_HEADER);
    caplen = load32(block + 20, file->little);
    if (caplen > length - PCAPNG_PACKET_HEADER)
        return FAULT(file, record, file->offset, false, "damaged pcapng packet block skipped (captured length %u "
                     "exceeds the block)", (unsigned)caplen);
    face = kind == BT_PACKET ? load16(block + 8, file->little) : load32(block + 8, file->little);
    if (face >= file->n_interfaces)
        return FAULT(file, record, file->offset, false, "damaged pcapng packet block skipped (interface %u is not "
                     "described)", (unsigned)face);
    described = &file->interfaces[face];
    stamp = (uint64_t)load32(block + 12, file->little) << 32 | load32(block + 16, file->little);
    record->data = block + 28;
    record->length = caplen;
    record->linktype = described->linktype;
    record->time = (double)described->offset + (double)stamp / described->divisor;
    return URWIRE_CAPTURE_FRAME;
}

static urwire_capture_step pcapng_block(urwire_capture_file *file, const uint8_t *buf, size_t n, bool at_end,
                                        size_t *taken, urwire_capture_record *record)
{
    uint32_t kind, length, trailer;
    bool little = file->little;
    if (n < 8u) {
        if (!at_end)
            return URWIRE_CAPTURE_MORE;
        if (n == 0) {
            file->state = URWIRE_CAPTURE_DONE;
            return URWIRE_CAPTURE_END;
        }
        return FAULT(file, record, file->offset, true, "capture cut short in a block header: reading stopped");
    }
    kind = load32(buf, little);
    if (kind == BT_SECTION) {      /* a section of its own byte order; its length needs it */
        if (n < 12u)
            return at_end ? FAULT(file, record, file->offset, true, "capture cut short in a block header: "
                                  "reading stopped") : URWIRE_CAPTURE_MORE;
        if (load32(buf + 8, true) == 0x1A2B3C4Du || load32(buf + 8, false) == 0x1A2B3C4Du)
            little = load32(buf + 8, true) == 0x1A2B3C4Du;
    }
    length = load32(buf + 4, little);
    if (length < PCAPNG_BLOCK_MIN || length % 4u)
        return FAULT(file, record, file->offset, true, "pcapng block length %u is not valid: reading stopped",
                     (unsigned)length);
    if (n < length)
        return at_end ? FAULT(file, record, file->offset, true, "capture cut short in a block of %u bytes: "
                              "reading stopped", (unsigned)length)
                      : URWIRE_CAPTURE_MORE;
    *taken = length;
    trailer = load32(buf + length - 4u, little);
    if (trailer != length)
        return FAULT(file, record, file->offset, true, "pcapng block lengths disagree (%u, %u): reading stopped",
                     (unsigned)length, (unsigned)trailer);
    switch (kind) {
    case BT_SECTION:
        file->little = little;
        file->n_interfaces = 0;
        return URWIRE_CAPTURE_SKIP;
    case BT_INTERFACE:
        return describe_interface(file, buf, length, record, file->offset, false);
    case BT_PACKET:
    case BT_ENHANCED_PACKET:
        return pcapng_packet(file, buf, length, kind, record);
    default:
        return URWIRE_CAPTURE_SKIP;   /* statistics, name resolution ... */
    }
}

urwire_capture_step urwire_capture_file_next(urwire_capture_file *file, const uint8_t *buf, size_t n, bool at_end,
                                             size_t *taken, urwire_capture_record *record)
{
    urwire_capture_step step;
    *taken = 0;
    switch (file->state) {
    case URWIRE_CAPTURE_HEADER:
        step = n >= 4u && load32(buf, false) == BT_SECTION ? pcapng_header(file, buf, n, at_end, taken, record)
                                                           : pcap_header(file, buf, n, at_end, taken, record);
        break;
    case URWIRE_CAPTURE_PCAP:
        step = pcap_record(file, buf, n, at_end, taken, record);
        break;
    case URWIRE_CAPTURE_PCAPNG:
        step = pcapng_block(file, buf, n, at_end, taken, record);
        break;
    default:
        return URWIRE_CAPTURE_END;
    }
    file->offset += *taken;
    return step;
}
