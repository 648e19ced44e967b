/* A capture's conversations of every interface as JSON Lines, and the primary interface's
 * conversation. See capture_json.h. */
#define _POSIX_C_SOURCE 200809L     /* open_memstream: a record is written, then enveloped */
#include "capture_json.h"

#include <stdlib.h>
#include <string.h>

#include "capture.h"
#include "envelope.h"
#include "growing.h"
#include "json.h"
#include "records.h"

#define CAPTURE_HEAD 12u

/* ---- the primary interface's conversation (interfaces.py's PrimaryConversation) ----------- */

/* Its framer, and its writer, whose kept package texts are the conversation's. */
typedef struct conversation {
    urwire_framer framer;
    json_writer writer;
    urwire_visitor visitor;
    uint8_t buffer[URWIRE_FRAMER_MIN_BUFFER];
} conversation;

typedef cell_output printer;

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
        envelope_line(p->out, p->envelope[1], line);
    }
    free(p->text);
    p->text = NULL;
    return 0;
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

static void primary_init(void *state, urwire_sw_version version, bool hinted)
{
    conversation *conv = state;
    (void)hinted;
    urwire_framer_init(&conv->framer, conv->buffer, sizeof conv->buffer, version);
    conv->visitor = json_visitor(&conv->writer);
}

/* What a client sends to the port is URScript, which is not decoded. */
static int primary_feed(void *state, const uint8_t *data, size_t n, bool from_robot, cell_output *out)
{
    return from_robot ? feed(out, state, data, n) : 0;
}

static int primary_close(void *state, bool from_robot, cell_output *out)
{
    conversation *conv = state;
    if (!from_robot)
        return 0;
    urwire_framer_finish(&conv->framer);
    return print_ready(out, conv);
}

static int primary_lost(void *state, bool from_robot, uint64_t offset, cell_output *out)
{
    return from_robot ? restart(out, state, offset) : 0;
}

/* The version the robot's last Version message announced, which its other conversations learn. */
static bool primary_announced(const void *state, urwire_sw_version *version)
{
    const conversation *conv = state;
    *version = conv->framer.version;
    return conv->framer.version_seen;
}

static const uint16_t primary_ports[] = {30001, 30002, 30011, 30012};   /* as python/urwire/interfaces.py */
const cell_interface cell_primary = {"ur", primary_ports, 4, false, false, sizeof(conversation), primary_init,
                                     primary_feed, primary_close, primary_lost, primary_announced, NULL, NULL};

/* ---- a capture: each TCP conversation read by the interface of its port (cell.py) ----------- */

/* The version a robot's primary conversation announced, by the address on the port's side. */
typedef struct robot {
    char address[URWIRE_CAPTURE_ADDRESS_TEXT];
    bool known;
    urwire_sw_version version;
} robot;

/* An open conversation: its interface and its state, its robot, its envelopes. */
typedef struct open_conversation {
    const cell_interface *kind;
    void *state;
    size_t robot;
    char name[2 * URWIRE_CAPTURE_ADDRESS_TEXT + 16];
    envelope envelope[2];
} open_conversation;

typedef struct reader {
    cell_output output;
    urwire_sw_version version;
    bool hinted;
    const cell_interface *by_port[65536];
    robot *robots;
    size_t n_robots, robots_capacity;
} reader;

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

/* The robot of this address: found, or added as one whose version is not known yet. */
static bool robot_of(reader *r, const char *address, size_t *index)
{
    size_t i;
    for (i = 0; i < r->n_robots; i++)
        if (strcmp(r->robots[i].address, address) == 0)
            break;
    if (i == r->n_robots) {
        if (!urwire_capture_grow((void **)&r->robots, &r->robots_capacity, i + 1, sizeof *r->robots))
            return false;
        memset(&r->robots[i], 0, sizeof r->robots[i]);
        memcpy(r->robots[i].address, address, sizeof r->robots[i].address);
        r->n_robots++;
    }
    *index = i;
    return true;
}

/* The conversation's state, made when new, with its name in the envelope
 * ("<server>:<port>-<client>:<port>", the server being the side on the port). */
static open_conversation *conversation_of(reader *r, urwire_capture_conversation *c)
{
    open_conversation *conv = c->user;
    const cell_interface *kind = r->by_port[c->robot_port];
    char server[URWIRE_CAPTURE_ADDRESS_TEXT + 8], client[URWIRE_CAPTURE_ADDRESS_TEXT + 8];
    int k;
    if (conv != NULL)
        return conv;
    conv = calloc(1, sizeof *conv);
    if (conv == NULL || (conv->state = calloc(1, kind->size)) == NULL || !robot_of(r, c->robot, &conv->robot)) {
        if (conv != NULL)
            free(conv->state);
        free(conv);
        return NULL;
    }
    conv->kind = kind;
    at(server, sizeof server, c->robot, c->robot_port);
    at(client, sizeof client, c->client, c->client_port);
    (void)snprintf(conv->name, sizeof conv->name, "%s-%s", server, client);
    for (k = 0; k < 2; k++) {
        conv->envelope[k].interface = kind->name;
        conv->envelope[k].direction = k ? "from_robot" : "to_robot";
        conv->envelope[k].conversation = conv->name;
    }
    kind->init(conv->state, r->version, r->hinted);
    c->user = conv;
    return conv;
}

static void forget(urwire_capture_conversation *c)
{
    open_conversation *conv = c->user;
    if (conv != NULL) {
        free(conv->state);
        free(conv);
        c->user = NULL;
    }
}

static void print_error(reader *r, const envelope *e, int64_t offset, const char *error)
{
    envelope_error(r->output.out, e, offset, error);
    r->output.errors = true;
}

/* One piece of a conversation's stream for its interface: a gap, bytes that differ, or bytes. */
static int take(reader *r, open_conversation *conv, const urwire_capture_item *item, bool from_robot)
{
    const envelope *e = &conv->envelope[from_robot ? 1 : 0];
    char error[160];
    switch (item->kind) {
    case URWIRE_ITEM_GAP:
        (void)snprintf(error, sizeof error, "%lld bytes missing from the capture at offset %lld",
                       (long long)item->missing, (long long)item->offset);
        print_error(r, e, item->offset, error);
        return conv->kind->lost(conv->state, from_robot, (uint64_t)(item->offset + item->missing), &r->output);
    case URWIRE_ITEM_DIFFERS:
        if (item->differing == 0)
            (void)snprintf(error, sizeof error, "%lld retransmitted bytes at offset %lld could not be compared: the "
                           "bytes they repeat are no longer kept", (long long)item->missing, (long long)item->offset);
        else
            (void)snprintf(error, sizeof error, "retransmitted bytes at offset %lld differ from those delivered first "
                           "(%lld of %lld); the first kept", (long long)item->offset, (long long)item->differing,
                           (long long)item->missing);
        print_error(r, e, item->offset, error);
        return 0;
    default:
        return item->length ? conv->kind->feed(conv->state, item->data, item->length, from_robot, &r->output) : 0;
    }
}

/* An item of the capture reader, as cell.py's conversation_records takes it: the robot is the
 * side on the port but on the driver's sockets; the version a robot's primary conversation
 * announced is passed on to its others; a conversation closes when the side on the port ends,
 * each direction's tail reported, the client's first. */
static int on_item(void *context, const urwire_capture_item *item)
{
    reader *r = context;
    open_conversation *conv;
    robot *rb;
    bool from_robot;
    int stop;
    if (item->kind == URWIRE_ITEM_FAULT) {
        print_error(r, NULL, item->offset, item->error);
        return 0;
    }
    if (item->conversation->user == NULL && item->kind == URWIRE_ITEM_BYTES && item->length == 0)
        return 0;   /* the end of a conversation already closed */
    if ((conv = conversation_of(r, item->conversation)) == NULL)
        return URWIRE_CAPTURE_NO_MEMORY;
    from_robot = item->from_robot != conv->kind->robot_is_client;
    r->output.envelope[0] = &conv->envelope[0];
    r->output.envelope[1] = &conv->envelope[1];
    rb = &r->robots[conv->robot];
    if (conv->kind->learn != NULL && rb->known)
        conv->kind->learn(conv->state, rb->version);
    if ((stop = take(r, conv, item, from_robot)) != 0)
        return stop;
    if (conv->kind->announced != NULL && conv->kind->announced(conv->state, &rb->version))
        rb->known = true;
    if (item->ended && item->from_robot) {
        if ((stop = conv->kind->close(conv->state, false, &r->output)) == 0)
            stop = conv->kind->close(conv->state, true, &r->output);
        forget(item->conversation);
    }
    return stop;
}

int capture_json_print(const uint8_t *head, size_t n, FILE *in, FILE *out, const cell_interface *only,
                       urwire_sw_version version, bool hinted)
{
    static uint8_t chunk[1 << 16];
    uint16_t ports[64], both_ways[64];        /* every interface's, a few each */
    size_t n_ports = 0, n_both = 0, i, k;
    reader *r = calloc(1, sizeof *r);
    urwire_capture *capture = NULL;
    int stop = 0, status;
    if (r == NULL)
        return 2;
    r->output.out = out;
    r->version = version;
    r->hinted = hinted;
    for (i = 0; i < cell_interface_count; i++) {
        const cell_interface *kind = cell_interfaces[i];
        if (only != NULL && kind != only)
            continue;
        for (k = 0; k < kind->n_ports; k++) {
            r->by_port[kind->ports[k]] = kind;
            ports[n_ports++] = kind->ports[k];
            if (kind->both_directions)
                both_ways[n_both++] = kind->ports[k];
        }
    }
    capture = urwire_capture_new(ports, n_ports, both_ways, n_both, false);
    if (capture == NULL) {
        free(r);
        return 2;
    }
    stop = urwire_capture_feed(capture, head, n, on_item, r);
    while (stop == 0) {
        size_t got = fread(chunk, 1, sizeof chunk, in);
        if (got == 0)
            break;
        stop = urwire_capture_feed(capture, chunk, got, on_item, r);
    }
    if (stop == 0 && !ferror(in))
        stop = urwire_capture_finish(capture, on_item, r);
    status = stop != 0 || ferror(in) ? 2 : r->output.errors ? 1 : 0;
    urwire_capture_each_conversation(capture, forget);
    urwire_capture_free(capture);
    free(r->robots);
    free(r);
    return status;
}
