/* The TCP streams of a capture (capture.h): timed_streams of python/urwire/capture.py in C. */
#include "capture.h"

#include <stdlib.h>
#include <string.h>

#include "capture_file.h"
#include "growing.h"
#include "reassembly.h"

/* Two endpoints, and a flag (the direction, for a way): the key of every table here. */
typedef struct endpoints {
    uint8_t family, flag;
    uint16_t port_a, port_b;
    uint8_t a[16], b[16];
} endpoints;

typedef struct table {
    uint32_t *slots;        /* 0: empty; else the record's index + 1 */
    size_t mask, count;
} table;

/* One direction of a conversation: its SYN's window scale, and its stream while it has one. */
typedef struct way {
    endpoints key;
    urwire_capture_conversation *conversation;
    bool has_shift;
    uint8_t shift;
    urwire_capture_reassembly *stream;
    uint32_t prev, next;    /* the streams in the order timed_streams' dict holds them; NONE ends */
} way;

#define NONE UINT32_MAX

struct urwire_capture {
    urwire_capture_file file;
    uint8_t *input;
    size_t input_length, input_capacity;
    bool ports[65536], both_ways[65536], count_others;
    way *ways;
    size_t n_ways, ways_capacity;
    table way_table, other_table;
    struct { endpoints key; uint32_t other; } *other_keys;   /* either end first -> its conversation */
    size_t n_other_keys, other_keys_capacity;
    urwire_capture_conversation **conversations;
    size_t n_conversations, conversations_capacity;
    uint32_t first, last;   /* the ways with a stream, in order */
    int64_t held;           /* bytes held out of order by all the streams, as held_bytes counts them */
    double time;
    urwire_capture_pieces pieces;
    urwire_capture_other *others;
    size_t n_others, others_capacity;
    bool finished;
};

static size_t hash(const endpoints *k)
{
    const uint8_t *p = (const uint8_t *)k;
    uint64_t h = 1469598103934665603u;
    size_t i;
    for (i = 0; i < sizeof *k; i++)
        h = (h ^ p[i]) * 1099511628211u;
    return (size_t)(h ^ h >> 29);
}

/* The slot of `key` in `t`, whose records' keys `key_of` gives: where it is, or an empty one. */
static uint32_t *slot_of(table *t, const endpoints *key, const endpoints *(*key_of)(const urwire_capture *, uint32_t),
                         const urwire_capture *c)
{
    size_t i = hash(key) & t->mask;
    for (;; i = (i + 1) & t->mask) {
        uint32_t *s = &t->slots[i];
        if (*s == 0 || memcmp(key_of(c, *s - 1), key, sizeof *key) == 0)
            return s;
    }
}

static bool table_room(table *t, const endpoints *(*key_of)(const urwire_capture *, uint32_t),
                       const urwire_capture *c)
{
    table bigger;
    size_t i;
    if (t->slots != NULL && 2 * (t->count + 1) <= t->mask + 1)
        return true;
    bigger.mask = t->slots == NULL ? 63 : 2 * t->mask + 1;
    bigger.count = t->count;
    bigger.slots = calloc(bigger.mask + 1, sizeof *bigger.slots);
    if (bigger.slots == NULL)
        return false;
    for (i = 0; t->slots != NULL && i <= t->mask; i++)
        if (t->slots[i])
            *slot_of(&bigger, key_of(c, t->slots[i] - 1), key_of, c) = t->slots[i];
    free(t->slots);
    *t = bigger;
    return true;
}

static const endpoints *way_key(const urwire_capture *c, uint32_t i)
{
    return &c->ways[i].key;
}

static const endpoints *other_key(const urwire_capture *c, uint32_t i)
{
    return &c->other_keys[i].key;
}

/* The key of a segment's way: robot side first, flagged with the direction. */
static endpoints key_of(const urwire_capture_segment *s, bool from_robot)
{
    endpoints k;
    size_t size = s->family == 4 ? 4 : 16;
    memset(&k, 0, sizeof k);
    k.family = s->family;
    k.flag = from_robot;
    k.port_a = from_robot ? s->sport : s->dport;
    k.port_b = from_robot ? s->dport : s->sport;
    memcpy(k.a, from_robot ? s->src : s->dst, size);
    memcpy(k.b, from_robot ? s->dst : s->src, size);
    return k;
}

static way *find_way(urwire_capture *c, const endpoints *key)
{
    uint32_t *s;
    if (c->way_table.slots == NULL)
        return NULL;
    s = slot_of(&c->way_table, key, way_key, c);
    return *s ? &c->ways[*s - 1] : NULL;
}

/* The way of `key`, made when new (with its conversation, shared with the other way's). */
static way *way_of(urwire_capture *c, const endpoints *key)
{
    way *w = find_way(c, key), *other;
    endpoints back = *key;
    urwire_capture_conversation *conversation;
    if (w != NULL)
        return w;
    back.flag = !key->flag;
    other = find_way(c, &back);
    if (other != NULL) {
        conversation = other->conversation;
    } else {
        conversation = calloc(1, sizeof *conversation);
        if (conversation == NULL || !urwire_capture_grow((void **)&c->conversations, &c->conversations_capacity,
                                          c->n_conversations + 1, sizeof(urwire_capture_conversation *))) {
            free(conversation);
            return NULL;
        }
        c->conversations[c->n_conversations++] = conversation;
        urwire_capture_address_text(key->family, key->a, conversation->robot);
        urwire_capture_address_text(key->family, key->b, conversation->client);
        conversation->robot_port = key->port_a;
        conversation->client_port = key->port_b;
    }
    if (!table_room(&c->way_table, way_key, c) ||
        !urwire_capture_grow((void **)&c->ways, &c->ways_capacity, c->n_ways + 1, sizeof *c->ways))
        return NULL;
    w = &c->ways[c->n_ways];
    memset(w, 0, sizeof *w);
    w->key = *key;
    w->conversation = conversation;
    w->prev = w->next = NONE;
    *slot_of(&c->way_table, key, way_key, c) = (uint32_t)++c->n_ways;
    c->way_table.count++;
    return w;
}

static uint32_t index_of(const urwire_capture *c, const way *w)
{
    return (uint32_t)(w - c->ways);
}

/* A stream for the way, at the end of the order (or, replacing one, in its place). */
static bool start_stream(urwire_capture *c, way *w, bool started, uint32_t next_seq)
{
    if (w->stream == NULL) {
        w->stream = malloc(sizeof *w->stream);
        if (w->stream == NULL)
            return false;
        w->prev = c->last;
        w->next = NONE;
        if (c->last == NONE)
            c->first = index_of(c, w);
        else
            c->ways[c->last].next = index_of(c, w);
        c->last = index_of(c, w);
    } else {
        urwire_capture_reassembly_free(w->stream);
    }
    urwire_capture_reassembly_init(w->stream, started, next_seq);
    return true;
}

static void end_stream(urwire_capture *c, way *w)
{
    if (w->prev == NONE)
        c->first = w->next;
    else
        c->ways[w->prev].next = w->next;
    if (w->next == NONE)
        c->last = w->prev;
    else
        c->ways[w->next].prev = w->prev;
    urwire_capture_reassembly_free(w->stream);
    free(w->stream);
    w->stream = NULL;
    w->prev = w->next = NONE;
}

/* The items of one step's pieces: the bytes between faults joined; the last item says whether the
 * stream ended (an empty one when it ended with nothing more). */
static int emit_pieces(urwire_capture *c, const way *w, bool ended, urwire_capture_emit emit, void *context)
{
    urwire_capture_pieces *out = &c->pieces;
    urwire_capture_item item;
    size_t i, run_start = 0, run_end = 0;
    bool run = false;
    int stop;
    if (out->no_memory)
        return URWIRE_CAPTURE_NO_MEMORY;
    memset(&item, 0, sizeof item);
    item.conversation = w->conversation;
    item.from_robot = w->key.flag;
    item.time = c->time;
    for (i = 0; i < out->n; i++) {
        const urwire_capture_piece *p = &out->pieces[i];
        if (p->kind == URWIRE_PIECE_BYTES) {
            if (!run)
                run_start = (size_t)p->offset;
            run_end = (size_t)(p->offset + p->length);
            run = true;
            continue;
        }
        if (run) {
            item.kind = URWIRE_ITEM_BYTES;
            item.data = out->bytes + run_start;
            item.length = run_end - run_start;
            if ((stop = emit(context, &item)) != 0)
                return stop;
            run = false;
        }
        item.kind = p->kind == URWIRE_PIECE_GAP ? URWIRE_ITEM_GAP : URWIRE_ITEM_DIFFERS;
        item.offset = p->offset;
        item.missing = p->length;
        item.differing = p->differing;
        if ((stop = emit(context, &item)) != 0)
            return stop;
    }
    urwire_capture_pieces_clear(out);
    if (!run && !ended)
        return 0;
    item.kind = URWIRE_ITEM_BYTES;
    item.data = run ? out->bytes + run_start : (const uint8_t *)"";
    item.length = run ? run_end - run_start : 0;
    item.ended = ended;
    return emit(context, &item);
}

static int count_other(urwire_capture *c, const urwire_capture_segment *s)
{
    endpoints key = key_of(s, true), back = key_of(s, false);
    uint32_t *slot;
    urwire_capture_other *o;
    bool src_is_client;
    if (!table_room(&c->other_table, other_key, c))
        return URWIRE_CAPTURE_NO_MEMORY;
    key.flag = back.flag = 0;
    slot = slot_of(&c->other_table, &key, other_key, c);
    if (*slot) {
        c->others[c->other_keys[*slot - 1].other].bytes += s->length;
        return 0;
    }
    if (!urwire_capture_grow((void **)&c->others, &c->others_capacity, c->n_others + 1, sizeof *c->others) ||
        !urwire_capture_grow((void **)&c->other_keys, &c->other_keys_capacity, c->n_other_keys + 2, sizeof *c->other_keys) ||
        !table_room(&c->other_table, other_key, c))
        return URWIRE_CAPTURE_NO_MEMORY;
    /* The client sent the first SYN, when the capture holds it; else it is on the higher port. */
    src_is_client = s->flags & URWIRE_TCP_SYN ? !(s->flags & URWIRE_TCP_ACK) : s->sport > s->dport;
    o = &c->others[c->n_others];
    urwire_capture_address_text(s->family, src_is_client ? s->dst : s->src, o->server);
    urwire_capture_address_text(s->family, src_is_client ? s->src : s->dst, o->client);
    o->server_port = src_is_client ? s->dport : s->sport;
    o->client_port = src_is_client ? s->sport : s->dport;
    o->bytes = s->length;
    c->other_keys[c->n_other_keys].key = key;
    c->other_keys[c->n_other_keys].other = (uint32_t)c->n_others;
    *slot_of(&c->other_table, &key, other_key, c) = (uint32_t)++c->n_other_keys;
    c->other_table.count++;
    if (!table_room(&c->other_table, other_key, c))
        return URWIRE_CAPTURE_NO_MEMORY;
    c->other_keys[c->n_other_keys].key = back;
    c->other_keys[c->n_other_keys].other = (uint32_t)c->n_others;
    slot = slot_of(&c->other_table, &back, other_key, c);
    if (*slot == 0) {       /* a conversation of a host with itself, on one port, has one key */
        *slot = (uint32_t)++c->n_other_keys;
        c->other_table.count++;
    }
    c->n_others++;
    return 0;
}

/* One TCP segment, as timed_streams takes it. */
static int on_segment(urwire_capture *c, const urwire_capture_segment *s, urwire_capture_emit emit, void *context)
{
    bool from_robot, ended;
    endpoints key;
    way *w, *peer;
    int stop;
    if (c->ports[s->sport])
        from_robot = true;
    else if (c->ports[s->dport])
        from_robot = false;     /* read for its acknowledgements, and for its bytes where asked */
    else
        return c->count_others ? count_other(c, s) : 0;
    key = key_of(s, from_robot);
    if (s->flags & URWIRE_TCP_SYN) {
        if ((w = way_of(c, &key)) == NULL)
            return URWIRE_CAPTURE_NO_MEMORY;
        w->has_shift = true;
        w->shift = (uint8_t)urwire_capture_window_shift(s);
    } else if (s->flags & URWIRE_TCP_ACK) {
        endpoints back = key;
        back.flag = !from_robot;
        peer = find_way(c, &back);
        if (peer != NULL && peer->stream != NULL) {    /* its gaps this acknowledgement decides came first */
            const way *self = find_way(c, &key);
            unsigned shift = self != NULL && self->has_shift ? self->shift : URWIRE_TCP_WSCALE_UNKNOWN;
            c->held -= peer->stream->held_bytes;
            urwire_capture_ack(peer->stream, s->ack, (uint64_t)s->window << shift, &c->pieces);
            if ((stop = emit_pieces(c, peer, false, emit, context)) != 0)
                return stop;
            c->held += peer->stream->held_bytes;
        }
    }
    if (!from_robot && !c->both_ways[s->dport])
        return 0;
    if ((w = way_of(c, &key)) == NULL)
        return URWIRE_CAPTURE_NO_MEMORY;
    if (w->stream != NULL)
        c->held -= w->stream->held_bytes;   /* added back below, as the segment leaves it */
    if (s->flags & URWIRE_TCP_SYN) {
        if (w->stream != NULL && w->stream->n_held) {   /* a new connection on the same ports */
            urwire_capture_flush(w->stream, &c->pieces);
            if ((stop = emit_pieces(c, w, true, emit, context)) != 0)
                return stop;
        }
        return start_stream(c, w, true, s->seq + 1u) ? 0 : URWIRE_CAPTURE_NO_MEMORY;
    }
    if (w->stream == NULL && !start_stream(c, w, false, 0))
        return URWIRE_CAPTURE_NO_MEMORY;
    if (s->length && !urwire_capture_keep_alive(w->stream, s->seq, s->length))
        urwire_capture_add(w->stream, s->seq, s->data, s->length, &c->pieces);
    ended = (s->flags & (URWIRE_TCP_FIN | URWIRE_TCP_RST)) != 0;
    if (ended)
        urwire_capture_flush(w->stream, &c->pieces);
    else
        c->held += w->stream->held_bytes;
    stop = emit_pieces(c, w, ended, emit, context);
    if (ended)
        end_stream(c, w);
    if (stop)
        return stop;
    while (c->held > URWIRE_CAPTURE_MAX_PENDING) {     /* the stream holding the most gives up its gap */
        uint32_t i, most = c->first;
        for (i = c->first; i != NONE; i = c->ways[i].next)
            if (c->ways[i].stream->held_bytes > c->ways[most].stream->held_bytes)
                most = i;
        w = &c->ways[most];
        c->held -= w->stream->held_bytes;
        urwire_capture_skip_gap(w->stream, &c->pieces);
        if ((stop = emit_pieces(c, w, false, emit, context)) != 0)
            return stop;
        c->held += w->stream->held_bytes;
    }
    return 0;
}

static int emit_fault(const urwire_capture_record *record, urwire_capture_emit emit, void *context)
{
    urwire_capture_item item;
    memset(&item, 0, sizeof item);
    item.kind = URWIRE_ITEM_FAULT;
    item.offset = (int64_t)record->fault_offset;
    item.error = record->fault;
    return emit(context, &item);
}

/* Every whole record of the input held; what is left of it waits for more. */
static int walk(urwire_capture *c, bool at_end, urwire_capture_emit emit, void *context)
{
    size_t at = 0, taken;
    int stop = 0;
    urwire_capture_record record;
    urwire_capture_segment segment;
    while (stop == 0) {
        urwire_capture_step step = urwire_capture_file_next(&c->file, c->input + at, c->input_length - at, at_end,
                                                            &taken, &record);
        at += taken;
        if (step == URWIRE_CAPTURE_MORE || step == URWIRE_CAPTURE_END)
            break;
        if (step == URWIRE_CAPTURE_OUT_OF_MEMORY)
            stop = URWIRE_CAPTURE_NO_MEMORY;
        else if (step == URWIRE_CAPTURE_FAULTED)
            stop = emit_fault(&record, emit, context);
        else if (step == URWIRE_CAPTURE_FRAME) {
            c->time = record.time;
            if (urwire_capture_segment_of(record.linktype, record.data, record.length, &segment))
                stop = on_segment(c, &segment, emit, context);
        }
    }
    memmove(c->input, c->input + at, c->input_length - at);
    c->input_length -= at;
    if (c->file.state == URWIRE_CAPTURE_DONE)
        c->input_length = 0;    /* reading stopped: the rest is not read */
    return stop;
}

urwire_capture *urwire_capture_new(const uint16_t *ports, size_t n_ports, const uint16_t *both_ways,
                                   size_t n_both_ways, bool others)
{
    urwire_capture *c = calloc(1, sizeof *c);
    size_t i;
    if (c == NULL)
        return NULL;
    urwire_capture_file_init(&c->file);
    for (i = 0; i < n_ports; i++)
        c->ports[ports[i]] = true;
    for (i = 0; i < n_both_ways; i++)
        c->both_ways[both_ways[i]] = true;
    c->count_others = others;
    c->first = c->last = NONE;
    if (!urwire_capture_grow((void **)&c->input, &c->input_capacity, 1, 1)) {     /* never NULL, though nothing is fed */
        free(c);
        return NULL;
    }
    return c;
}

int urwire_capture_feed(urwire_capture *c, const uint8_t *data, size_t n, urwire_capture_emit emit, void *context)
{
    if (c->file.state == URWIRE_CAPTURE_DONE || c->finished)
        return 0;
    if (!urwire_capture_grow((void **)&c->input, &c->input_capacity, c->input_length + n, 1))
        return URWIRE_CAPTURE_NO_MEMORY;
    memcpy(c->input + c->input_length, data, n);
    c->input_length += n;
    return walk(c, false, emit, context);
}

int urwire_capture_finish(urwire_capture *c, urwire_capture_emit emit, void *context)
{
    int stop;
    if (c->finished)
        return 0;
    if ((stop = walk(c, true, emit, context)) != 0)
        return stop;
    c->finished = true;
    while (c->first != NONE) {
        way *w = &c->ways[c->first];
        urwire_capture_flush(w->stream, &c->pieces);
        stop = emit_pieces(c, w, true, emit, context);
        end_stream(c, w);
        if (stop)
            return stop;
    }
    return 0;
}

size_t urwire_capture_others(const urwire_capture *c, const urwire_capture_other **others)
{
    *others = c->others;
    return c->n_others;
}

void urwire_capture_each_conversation(urwire_capture *c, void (*visit)(urwire_capture_conversation *))
{
    size_t i;
    for (i = 0; i < c->n_conversations; i++)
        visit(c->conversations[i]);
}

void urwire_capture_free(urwire_capture *c)
{
    size_t i;
    if (c == NULL)
        return;
    for (i = 0; i < c->n_ways; i++)
        if (c->ways[i].stream != NULL) {
            urwire_capture_reassembly_free(c->ways[i].stream);
            free(c->ways[i].stream);
        }
    for (i = 0; i < c->n_conversations; i++)
        free(c->conversations[i]);
    urwire_capture_file_free(&c->file);
    urwire_capture_pieces_free(&c->pieces);
    free(c->conversations);
    free(c->ways);
    free(c->way_table.slots);
    free(c->other_table.slots);
    free(c->other_keys);
    free(c->others);
    free(c->input);
    free(c);
}
