/* RTDE records as canonical JSON lines. See rtde_json.h. */
#include "rtde_json.h"

#include <string.h>

#include "json.h"

static void put_text(FILE *out, const uint8_t *p, size_t n)
{
    json_write_text(out, p, n);
}

/* Names joined by commas as a JSON list; no bytes are no names. */
static void put_names(FILE *out, rtde_text t)
{
    size_t at = 0, i;
    fputc('[', out);
    if (t.length) {
        for (i = 0; i <= t.length; i++) {
            if (i == t.length || t.data[i] == ',') {
                if (at)
                    fputs(", ", out);
                put_text(out, t.data + at, i - at);
                at = i + 1;
            }
        }
    }
    fputc(']', out);
}

/* An item of a value: its type in the generated table (rtde_value_type) says which member of the
 * item holds it; a type added to the spec and not here fails the build (-Wswitch). */
static void put_item(FILE *out, const rtde_value *v, size_t k)
{
    switch ((rtde_value_type)v->type) {
    case RTDE_VT_BOOL:
        fputs(v->item[k].u64 ? "true" : "false", out);
        break;
    case RTDE_VT_DOUBLE:
    case RTDE_VT_VECTOR3D:
    case RTDE_VT_VECTOR6D:
        json_write_f64(out, v->item[k].f64);
        break;
    case RTDE_VT_INT32:
    case RTDE_VT_VECTOR6INT32:
        fprintf(out, "%lld", (long long)v->item[k].i64);
        break;
    case RTDE_VT_UINT8:
    case RTDE_VT_UINT32:
    case RTDE_VT_UINT64:
    case RTDE_VT_VECTOR6UINT32:
    case RTDE_VT_COUNT:
        fprintf(out, "%llu", (unsigned long long)v->item[k].u64);
        break;
    }
}

static void put_values(FILE *out, const rtde_data *d, bool *first)
{
    size_t i, k;
    for (i = 0; i < rtde_data_count(d); i++) {
        rtde_text name = rtde_data_name(d, i);
        rtde_value v;
        rtde_data_value(d, i, &v);
        fputs(*first ? "" : ", ", out);
        *first = false;
        put_text(out, name.data, name.length);
        fputs(": ", out);
        if (v.count > 1)
            fputc('[', out);
        for (k = 0; k < v.count; k++) {
            if (k)
                fputs(", ", out);
            put_item(out, &v, k);
        }
        if (v.count > 1)
            fputc(']', out);
    }
}

static void put_member(FILE *out, const rtde_member *mb, const uint8_t *base, bool *first)
{
    const uint8_t *p = base + mb->offset;
    if (mb->kind == RTDE_MEMBER_VALUES) {
        rtde_data d;
        memcpy(&d, p, sizeof d);
        put_values(out, &d, first);
        return;
    }
    fputs(*first ? "\"" : ", \"", out);
    *first = false;
    fputs(mb->name, out);
    fputs("\": ", out);
    if (mb->kind == RTDE_MEMBER_TEXT || mb->kind == RTDE_MEMBER_NAMES) {
        rtde_text t;
        memcpy(&t, p, sizeof t);
        if (mb->kind == RTDE_MEMBER_TEXT)
            put_text(out, t.data, t.length);
        else
            put_names(out, t);
    } else if (mb->kind == RTDE_MEMBER_F64) {
        double d;
        memcpy(&d, p, sizeof d);
        json_write_f64(out, d);
    } else {
        /* Integers of their own width in the struct (uint8_t to uint64_t, int32_t). */
        uint64_t u = 0;
        uint8_t u8;
        uint16_t u16;
        uint32_t u32;
        int32_t i32;
        if (mb->kind == RTDE_MEMBER_INT) {
            memcpy(&i32, p, sizeof i32);
            fprintf(out, "%ld", (long)i32);
            return;
        }
        if (mb->size == 1) {
            memcpy(&u8, p, 1);
            u = u8;
        } else if (mb->size == 2) {
            memcpy(&u16, p, 2);
            u = u16;
        } else if (mb->size == 4) {
            memcpy(&u32, p, 4);
            u = u32;
        } else {
            memcpy(&u, p, 8);
        }
        if (mb->kind == RTDE_MEMBER_BOOL)
            fputs(u ? "true" : "false", out);
        else
            fprintf(out, "%llu", (unsigned long long)u);
    }
}

/* The next comma-separated item of t from *at; false at the end. */
static bool next_item(rtde_text t, size_t *at, size_t *start, size_t *n)
{
    size_t i;
    if (*at > t.length || t.length == 0)
        return false;
    for (i = *at; i < t.length && t.data[i] != ','; i++)
        ;
    *start = *at;
    *n = i - *at;
    *at = i + 1;
    return true;
}

/* A refused setup: {"name": "WORD", ...} for each name whose answer is no value type (empty
 * names name no variable and have no answer). */
static void put_refused(FILE *out, rtde_text names, rtde_text types)
{
    size_t an = 0, at = 0, s1, n1, s2, n2;
    bool first = true;
    fputs(", \"refused\": {", out);
    for (;;) {
        bool more = next_item(names, &an, &s1, &n1);
        while (more && n1 == 0)
            more = next_item(names, &an, &s1, &n1);
        if (!more || !next_item(types, &at, &s2, &n2))
            break;
        if (rtde_value_type_of(types.data + s2, n2) < 0) {
            fputs(first ? "" : ", ", out);
            first = false;
            put_text(out, names.data + s1, n1);
            fputs(": ", out);
            put_text(out, types.data + s2, n2);
        }
    }
    fputc('}', out);
}

static rtde_text reply_types(const rtde_message *m)
{
    rtde_text none = {NULL, 0};
    if (m->layout == RTDE_LAYOUT_SETUP_OUTPUTS_REPLY) return m->u.setup_outputs_reply.types;
    if (m->layout == RTDE_LAYOUT_SETUP_OUTPUTS_REPLY_V1) return m->u.setup_outputs_reply_v1.types;
    if (m->layout == RTDE_LAYOUT_SETUP_INPUTS_REPLY) return m->u.setup_inputs_reply.types;
    return none;
}

int rtde_json_record(FILE *out, const envelope *env, const rtde_message *m, rtde_error e, size_t at,
                     const uint8_t *msg, size_t size)
{
    const rtde_layout_info *info = rtde_layout_of(m->layout);
    bool first = false;
    size_t i;
    if (e != RTDE_OK) {
        envelope_open(out, env);
        fputs("\"type\": \"", out);
        fputs(m->layout == RTDE_LAYOUT_NONE ? rtde_unlaid_name(m->code) : info->name, out);
        fprintf(out, "\", \"message_type\": %u", (unsigned)m->code);
        if (e == RTDE_UNKNOWN_RECIPE) {
            if (info->count > 1 && strcmp(info->members[0].name, "recipe_id") == 0 && size > RTDE_HEADER_SIZE)
                fprintf(out, ", \"recipe_id\": %u", (unsigned)msg[RTDE_HEADER_SIZE]);
            fputs(", \"error\": \"data package of a recipe this connection did not set up\"", out);
        } else if (e == RTDE_SHORT) {
            fprintf(out, ", \"error\": \"%s at offset %lu: needs %lu bytes, %lu left\"", m->error_field,
                    (unsigned long)at, (unsigned long)m->error_need, (unsigned long)(size - at));
        } else if (e == RTDE_EXTRA) {
            fprintf(out, ", \"error\": \"extra at offset %lu: %lu bytes after the layout\"", (unsigned long)at,
                    (unsigned long)m->error_need);
        } else if (e != RTDE_UNKNOWN_TYPE) {
            fprintf(out, ", \"error\": \"%s\"", rtde_error_text(e));
        }
        fputs(", \"raw\": ", out);
        json_write_hex(out, msg, size);
        fputs("}\n", out);
        return e != RTDE_UNKNOWN_TYPE;   /* a code no layout has is kept whole without an error */
    }
    envelope_open(out, env);
    fprintf(out, "\"type\": \"%s\"", info->name);
    for (i = 0; i < info->count; i++)
        put_member(out, &info->members[i], (const uint8_t *)&m->u, &first);
    if (m->refused)
        put_refused(out, m->request_names, reply_types(m));
    if (m->warning) {
        fputs(", \"warning\": ", out);
        put_text(out, (const uint8_t *)m->warning, strlen(m->warning));
    }
    if (m->error) {
        fputs(", \"error\": ", out);
        put_text(out, (const uint8_t *)m->error, strlen(m->error));
    }
    fputs("}\n", out);
    return m->error != NULL;   /* a record the conversation could not follow (a queue, a version) */
}

/* The protocol's own limits: the command keeps every recipe a connection can make, as the Python
 * decoder does. */
static const rtde_limits protocol_limits = {RTDE_JSON_RECIPES, RTDE_JSON_VARIABLES, RTDE_JSON_NAMES};

void rtde_json_stream_init(rtde_json_stream *s)
{
    rtde_conversation_init_in(&s->conversation, &protocol_limits, s->storage.bytes, sizeof s->storage.bytes);
    rtde_stream_init(&s->direction[0]);
    rtde_stream_init(&s->direction[1]);
    s->envelope[0] = s->envelope[1] = NULL;
}

/* Every record the direction's framed bytes make, in the direction's envelope; the number of
 * error records. */
static int drain(rtde_json_stream *s, bool from_robot, FILE *out)
{
    rtde_stream *d = &s->direction[from_robot ? 1 : 0];
    const envelope *env = s->envelope[from_robot ? 1 : 0];
    rtde_frame f;
    rtde_message m;
    rtde_error e;
    size_t at;
    int errors = 0;
    for (;;) {
        switch (rtde_stream_next(d, &f)) {
        case RTDE_FRAME_NEED_MORE:
        case RTDE_FRAME_END:
            return errors;
        case RTDE_FRAME_MESSAGE:
            e = rtde_decode(&s->conversation, f.bytes, f.length, from_robot, &m, &at);
            errors += rtde_json_record(out, env, &m, e, at, f.bytes, f.length);
            break;
        case RTDE_FRAME_BAD_HEADER:
            envelope_open(out, env);
            fprintf(out, "\"type\": \"error\", \"offset\": %llu, \"error\": \"bad message header: size %lu, "
                    "type %u\"}\n", (unsigned long long)f.offset, (unsigned long)f.size, (unsigned)f.code);
            errors++;
            break;
        case RTDE_FRAME_TRUNCATED:
            envelope_open(out, env);
            fprintf(out, "\"type\": \"error\", \"offset\": %llu, \"error\": \"truncated message: %lu bytes at "
                    "the end of the stream\"}\n", (unsigned long long)f.offset, (unsigned long)f.length);
            errors++;
            break;
        }
    }
}

int rtde_json_feed(rtde_json_stream *s, const uint8_t *data, size_t length, bool from_robot, FILE *out)
{
    int errors = 0;
    while (length) {
        size_t n = rtde_stream_feed(&s->direction[from_robot ? 1 : 0], data, length);
        data += n;
        length -= n;
        errors += drain(s, from_robot, out);
    }
    return errors;
}

int rtde_json_close_direction(rtde_json_stream *s, bool from_robot, FILE *out)
{
    rtde_stream_finish(&s->direction[from_robot ? 1 : 0]);
    return drain(s, from_robot, out);
}

int rtde_json_close(rtde_json_stream *s, FILE *out)
{
    /* the client's tail first, each in its own direction's envelope */
    int errors = rtde_json_close_direction(s, false, out);
    return errors + rtde_json_close_direction(s, true, out);
}

/* ---- a conversation of cell_interface.h ------------------------------------------------------ */

/* The output's envelopes are the connection's. */
static rtde_json_stream *enveloped(void *state, const cell_output *out)
{
    rtde_json_stream *s = state;
    s->envelope[0] = out->envelope[0];
    s->envelope[1] = out->envelope[1];
    return s;
}

static void init(void *state, urwire_sw_version version, bool hinted)
{
    (void)version;          /* RTDE negotiates its protocol: no software version chooses a layout */
    (void)hinted;
    rtde_json_stream_init(state);
}

static int feed(void *state, const uint8_t *data, size_t n, bool from_robot, cell_output *out)
{
    out->errors |= rtde_json_feed(enveloped(state, out), data, n, from_robot, out->out) > 0;
    return 0;
}

static int close_way(void *state, bool from_robot, cell_output *out)
{
    out->errors |= rtde_json_close_direction(enveloped(state, out), from_robot, out->out) > 0;
    return 0;
}

/* The message the lost bytes cut short given up, and the direction framed afresh after them, the
 * protocol and the recipes kept, the pairing of replies unknown (rtde.py's Conversation.lost). */
static int lost(void *state, bool from_robot, uint64_t offset, cell_output *out)
{
    rtde_json_stream *s = state;
    (void)close_way(state, from_robot, out);
    rtde_conversation_lost(&s->conversation, from_robot);
    rtde_stream_init(&s->direction[from_robot ? 1 : 0]);
    s->direction[from_robot ? 1 : 0].base = offset;
    return 0;
}

static const uint16_t ports[] = {30004};       /* as python/urwire/interfaces.py: the spec's */
const cell_interface cell_rtde = {"rtde", ports, 1, true, false, sizeof(rtde_json_stream), init, feed, close_way,
                                  lost, NULL, NULL, NULL};
