#ifndef URWIRE_CAPTURE_FILE_H
#define URWIRE_CAPTURE_FILE_H
/* The records of a .pcap or .pcapng file, one at a time, with the rules of
 * python/urwire/capture_records.py: a record that cannot be read is a fault at its file offset;
 * a pcapng packet block of a sound length whose body is bad is skipped, any other fault stops the
 * reading. Each pcapng section has its own byte order, and each interface its own link type and
 * timestamp resolution. The caller holds the bytes; the walker says how many it took. */
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define URWIRE_CAPTURE_PCAP_RECORD_MAX 262144u   /* Wireshark's largest record for Ethernet */
#define URWIRE_CAPTURE_MAX_INTERFACES 1024u      /* interfaces kept per pcapng section */
#define URWIRE_CAPTURE_FAULT_TEXT 160

typedef struct urwire_capture_interface {
    uint32_t linktype;
    double divisor;         /* timestamp units per second */
    int64_t offset;         /* if_tsoffset, seconds */
} urwire_capture_interface;

typedef struct urwire_capture_file {
    enum { URWIRE_CAPTURE_HEADER, URWIRE_CAPTURE_PCAP, URWIRE_CAPTURE_PCAPNG, URWIRE_CAPTURE_DONE } state;
    bool little;            /* the byte order of the file (pcap) or of the current section */
    bool nano;              /* pcap: nanosecond timestamps */
    uint32_t snaplen, linktype;
    uint64_t offset;        /* in the file, of the next byte the walker takes */
    urwire_capture_interface *interfaces;
    size_t n_interfaces, capacity;
} urwire_capture_file;

typedef enum urwire_capture_step {
    URWIRE_CAPTURE_MORE,    /* a whole record needs more bytes than given (none taken) */
    URWIRE_CAPTURE_FRAME,   /* a frame: `frame` */
    URWIRE_CAPTURE_SKIP,    /* a block that holds no frame, taken */
    URWIRE_CAPTURE_FAULTED, /* `fault`: a record that cannot be read; reading goes on unless `state` is DONE */
    URWIRE_CAPTURE_END,     /* nothing more: the end of the file, or reading stopped */
    URWIRE_CAPTURE_OUT_OF_MEMORY
} urwire_capture_step;

typedef struct urwire_capture_record {
    const uint8_t *data;
    size_t length;
    uint32_t linktype;
    double time;            /* seconds since the epoch */
    uint64_t fault_offset;
    char fault[URWIRE_CAPTURE_FAULT_TEXT];
} urwire_capture_record;

void urwire_capture_file_init(urwire_capture_file *file);
void urwire_capture_file_free(urwire_capture_file *file);
/* One step over `buf` (the file's bytes from file->offset on, `n` of them; `at_end`: there are no
 * more). `*taken` is how many bytes the step used. */
urwire_capture_step urwire_capture_file_next(urwire_capture_file *file, const uint8_t *buf, size_t n, bool at_end,
                                             size_t *taken, urwire_capture_record *record);
#endif
