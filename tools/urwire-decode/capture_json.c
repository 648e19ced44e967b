/* A capture's primary/secondary conversations as JSON Lines. See capture_json.h. */
#define _POSIX_C_SOURCE 200809L     /* open_memstream: a record is written, then enveloped */
#include "capture_json.h"

#include <stdlib.h>
#include <string.h>

#include "capture.h"
#include "envelope.h"
#include "json.h"
#include "records.h"

#define CAPTURE_HEAD 12u

static const uint16_t primary_ports[] = {30001, 30002, 30011, 30012};   /* as python/urwire/interfaces.py */

/* One conversation: its framer, its writer (whose kept package texts are the conversation's), and
 * its name in the envelope. */
typedef struct conversation {
    urwire_framer framer;
    uint8_t *buffer;
    json_writer writer;
    urwire_visitor visitor;
    char name[2 * URWIRE_CAPTURE_ADDRESS_TEXT + 16];
    envelope from_robot;
} conversation;

typedef struct printer {
    FILE *out;
    urwire_sw_version hint;
    char *text;             /* the memory stream's */
    size_t size;
    bool errors;
} printer;

bool capture_json_is_capture(const uint8_t *head, size_t n)
{
    static const uint8_t pcap[4][4] = {{0xA1, 0xB2, 0xC3, 0xD4}, {0xD4, 0xC3, 0xB2, 0xA1},
                                       {0xA1, 0xB2, 0x3C, 0x4D}, {0x4D, 0x3C, 0xB2, 0xA1}};
    size_t i;
    if (n < CAPTURE_HEAD)
        return false;
    for (i = 0; i < 4; i++)
        if (memcmp(head, pcap[i], 4) == 0)
            return head[0] == 0xA1 ? head[4] == 0 && head[5] == 2 : head[4] == 2 && head[5] == 0;
    return memcmp(head, "\x0A\x0D\x0D\x0A", 4) == 0 &&
           (memcmp(head + 8, "\x1A\x2B\x3C\x4D", 4) == 0 || memcmp(head + 8, "\x4D\x3C\x2B\x1A", 4) == 0);
}

static void at(char *text, size_t size, const char *address, unsigned port)
{
    (void)snprintf(text, size, strchr(address, ':') ? "[%s]:%u" : "%s:%u", address, port);
}

static conversation *conversation_of(urwire_capture_conversation *c, urwire_sw_version hint)
{
    conversation *conv = c->user;
    char robot[URWIRE_CAPTURE_ADDRESS_TEXT + 8], client[URWIRE_CAPTURE_ADDRESS_TEXT + 8];
    if (conv != NULL)
        return conv;
    conv = calloc(1, sizeof *conv);
    if (conv == NULL || (conv->buffer = malloc(URWIRE_FRAMER_MIN_BUFFER)) == NULL) {
        free(conv);
        return NULL;
    }
    urwire_framer_init(&conv->framer, conv->buffer, URWIRE_FRAMER_MIN_BUFFER, hint);
    conv->visitor = json_visitor(&conv->writer);
    at(robot, sizeof robot, c->robot, c->robot_port);
    at(client, sizeof client, c->client, c->client_port);
    (void)snprintf(conv->name, sizeof conv->name, "%s-%s", robot, client);
    conv->from_robot.interface = "ur";
    conv->from_robot.direction = "from_robot";
    conv->from_robot.conversation = conv->name;
    c->user = conv;
    return conv;
}

static void forget(urwire_capture_conversation *c)
{
    conversation *conv = c->user;
    if (conv != NULL) {
        free(conv->buffer);
        free(conv);
        c->user = NULL;
    }
}

/* The conversation's ready records, each in its envelope. */
static int print_ready(printer *p, conversation *conv)
{
    FILE *lines = open_memstream(&p->text, &p->size);
    char *line, *end;
    if (lines == NULL)
        return URWIRE_CAPTURE_NO_MEMORY;
    conv->writer.out = lines;
    p->errors |= print_ready_records(&conv->framer, &conv->visitor, &conv->writer);
    if (fclose(lines) != 0)
        return URWIRE_CAPTURE_NO_MEMORY;
    for (line = p->text; (end = strchr(line, '\n')) != NULL; line = end + 1) {
        *end = '\0';
        envelope_line(p->out, &conv->from_robot, line);
    }
    free(p->text);
    p->text = NULL;
    return 0;
}

static void print_error(printer *p, const envelope *e, int64_t offset, const char *error)
{
    envelope_open(p->out, e);
    fprintf(p->out, "\"type\": \"error\", \"offset\": %lld, \"error\": ", (long long)offset);
    json_write_text(p->out, (const unsigned char *)error, strlen(error));
    fputs("}\n", p->out);
    p->errors = true;
}

/* The framer's tail given up, and framing afresh from stream offset `offset` (framer.py's
 * Framer.restart). */
static int restart(printer *p, conversation *conv, uint64_t offset)
{
    urwire_framer *f = &conv->framer;
    int stop;
    urwire_framer_finish(f);
    if ((stop = print_ready(p, conv)) != 0)
        return stop;
    urwire_framer_restart(f, offset);
    return 0;
}

static int feed(printer *p, conversation *conv, const uint8_t *data, size_t n)
{
    size_t used = 0;
    int stop;
    while (used < n) {
        used += urwire_framer_feed(&conv->framer, data + used, n - used);
        if ((stop = print_ready(p, conv)) != 0)
            return stop;
    }
    return 0;
}

/* An item of the capture reader, as cell.py's conversation_records takes it for the primary
 * interface: only the robot's streams are read. */
static int on_item(void *context, const urwire_capture_item *item)
{
    printer *p = context;
    conversation *conv;
    char error[160];
    int stop;
    if (item->kind == URWIRE_ITEM_FAULT) {
        print_error(p, NULL, item->offset, item->error);
        return 0;
    }
    if (item->conversation->user == NULL && item->kind == URWIRE_ITEM_BYTES && item->length == 0)
        return 0;   /* the end of a conversation already closed */
    if ((conv = conversation_of(item->conversation, p->hint)) == NULL)
        return URWIRE_CAPTURE_NO_MEMORY;
    switch (item->kind) {
    case URWIRE_ITEM_GAP:
        (void)snprintf(error, sizeof error, "%lld bytes missing from the capture at offset %lld",
                       (long long)item->missing, (long long)item->offset);
        print_error(p, &conv->from_robot, item->offset, error);
        return restart(p, conv, (uint64_t)(item->offset + item->missing));
    case URWIRE_ITEM_DIFFERS:
        if (item->differing == 0)
            (void)snprintf(error, sizeof error, "%lld retransmitted bytes at offset %lld could not be compared: the "
                           "bytes they repeat are no longer kept", (long long)item->missing, (long long)item->offset);
        else
            (void)snprintf(error, sizeof error, "retransmitted bytes at offset %lld differ from those delivered first "
                           "(%lld of %lld); the first kept", (long long)item->offset, (long long)item->differing,
                           (long long)item->missing);
        print_error(p, &conv->from_robot, item->offset, error);
        return 0;
    default:
        if ((stop = feed(p, conv, item->data, item->length)) != 0)
            return stop;
        if (item->ended) {
            urwire_framer_finish(&conv->framer);
            stop = print_ready(p, conv);
            forget(item->conversation);
            return stop;
        }
        return 0;
    }
}

static void forget_at_end(urwire_capture_conversation *c)
{
    forget(c);
}

int capture_json_print(const uint8_t *head, size_t n, FILE *in, FILE *out, urwire_sw_version hint)
{
    static uint8_t chunk[1 << 16];
    printer p;
    urwire_capture *capture = urwire_capture_new(primary_ports, 4, NULL, 0, false);
    int stop = 0, status;
    memset(&p, 0, sizeof p);
    p.out = out;
    p.hint = hint;
    if (capture == NULL)
        return 2;
    stop = urwire_capture_feed(capture, head, n, on_item, &p);
    while (stop == 0) {
        size_t got = fread(chunk, 1, sizeof chunk, in);
        if (got == 0)
            break;
        stop = urwire_capture_feed(capture, chunk, got, on_item, &p);
    }
    if (stop == 0 && !ferror(in))
        stop = urwire_capture_finish(capture, on_item, &p);
    status = stop != 0 || ferror(in) ? 2 : p.errors ? 1 : 0;
    urwire_capture_each_conversation(capture, forget_at_end);
    urwire_capture_free(capture);
    return status;
}
