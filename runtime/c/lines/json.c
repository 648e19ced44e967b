/* <standalone> */
#include <string.h>
#include "lines.h"
extern const lines_command_spec lines_commands[];
/* </standalone> */
/* ---- canonical JSON of a record (docs/canonical-json.md) ---------------------------------- */

typedef struct lines_out {
    char *buf;
    size_t cap, len;          /* len counts what did not fit too */
} lines_out;

static void out_bytes(lines_out *o, const char *p, size_t n)
{
    size_t room = o->cap > o->len + 1 ? o->cap - o->len - 1 : 0;
    if (room > 0)
        memcpy(o->buf + o->len, p, n < room ? n : room);
    o->len += n;
}

static void out_text(lines_out *o, const char *p)
{
    out_bytes(o, p, strlen(p));
}

/* Length of the valid UTF-8 sequence at p (1..4), or 0 with *bad set to the length of the
 * maximal subpart that one U+FFFD replaces, as Python's bytes.decode("utf-8", "replace"). */
static size_t utf8_sequence(const uint8_t *p, size_t n, size_t *bad)
{
    uint8_t b = p[0], lo = 0x80, hi = 0xBF;
    size_t need, k;
    if (b < 0x80)
        return 1;
    if (b >= 0xC2 && b <= 0xDF) {
        need = 1;
    } else if (b >= 0xE0 && b <= 0xEF) {
        need = 2;
        lo = b == 0xE0 ? 0xA0 : 0x80;
        hi = b == 0xED ? 0x9F : 0xBF;
    } else if (b >= 0xF0 && b <= 0xF4) {
        need = 3;
        lo = b == 0xF0 ? 0x90 : 0x80;
        hi = b == 0xF4 ? 0x8F : 0xBF;
    } else {
        *bad = 1;
        return 0;
    }
    for (k = 1; k <= need; k++) {
        if (k >= n || p[k] < (k == 1 ? lo : 0x80) || p[k] > (k == 1 ? hi : 0xBF)) {
            *bad = k;
            return 0;
        }
    }
    return need + 1;
}

/* Bytes as a JSON string, escaped as Python's json module does with ensure_ascii=False. */
static void out_string(lines_out *o, lines_view v)
{
    static const char hex[] = "0123456789abcdef";
    size_t i = 0, len, bad;
    out_bytes(o, "\"", 1);
    while (i < v.len) {
        uint8_t ch = v.ptr[i];
        if (ch >= 0x80) {
            bad = 0;
            len = utf8_sequence(v.ptr + i, v.len - i, &bad);
            if (len) {
                out_bytes(o, (const char *)v.ptr + i, len);
                i += len;
            } else {
                out_bytes(o, "\xEF\xBF\xBD", 3);
                i += bad;
            }
            continue;
        }
        switch (ch) {
        case '"': out_bytes(o, "\\\"", 2); break;
        case '\\': out_bytes(o, "\\\\", 2); break;
        case '\n': out_bytes(o, "\\n", 2); break;
        case '\r': out_bytes(o, "\\r", 2); break;
        case '\t': out_bytes(o, "\\t", 2); break;
        case '\b': out_bytes(o, "\\b", 2); break;
        case '\f': out_bytes(o, "\\f", 2); break;
        default:
            if (ch < 0x20) {
                char u[6] = {'\\', 'u', '0', '0', hex[ch >> 4], hex[ch & 15]};
                out_bytes(o, u, sizeof u);
            } else {
                out_bytes(o, (const char *)&ch, 1);
            }
        }
        i++;
    }
    out_bytes(o, "\"", 1);
}

static void out_name(lines_out *o, const char *key, const char *name)
{
    lines_view v;
    v.ptr = (const uint8_t *)name;
    v.len = strlen(name);
    out_text(o, key);
    out_string(o, v);
}

static void out_number(lines_out *o, uint64_t n)
{
    char digits[21];
    size_t at = sizeof digits;
    do {
        digits[--at] = (char)('0' + (int)(n % 10u));
        n /= 10u;
    } while (n);
    out_bytes(o, digits + at, sizeof digits - at);
}

size_t lines_json(const lines_record *rec, char *out, size_t cap)
{
    lines_out o;
    o.buf = out;
    o.cap = cap;
    o.len = 0;
    if (rec->type == LINES_FAULT) {
        out_text(&o, "{\"type\": \"error\", \"offset\": ");
        out_number(&o, rec->offset);
        if (rec->fault == LINES_LINE_TOO_LONG) {
            out_text(&o, ", \"error\": \"line longer than ");
            out_number(&o, LINES_MAX_LINE);
            out_text(&o, " bytes\"}");
        } else {
            out_text(&o, ", \"error\": \"");
            out_number(&o, rec->bytes);
            out_text(&o, " bytes without a newline at the end of the stream\"}");
        }
    } else if (rec->type == LINES_COMMAND) {
        out_text(&o, "{\"type\": \"command\", \"command\": ");
        out_string(&o, rec->text);
        if (rec->command_name != LINES_NONE)
            out_name(&o, ", \"command_name\": ", lines_commands[rec->command_name].name);
        if (rec->has_argument) {
            out_text(&o, ", \"argument\": ");
            out_string(&o, rec->argument);
        }
        if (rec->available >= 0)
            out_text(&o, rec->available ? ", \"available\": true" : ", \"available\": false");
        if (rec->not_kept) {
            out_text(&o, ", \"error\": \"command not kept: more than ");
            out_number(&o, rec->kept);
            out_text(&o, " commands awaited replies\"");
        }
        out_text(&o, "}");
    } else {
        out_text(&o, "{\"type\": \"reply\", \"reply\": ");
        out_string(&o, rec->text);
        if (rec->command_name != LINES_NONE)
            out_name(&o, ", \"command_name\": ", lines_commands[rec->command_name].name);
        if (rec->reply_name != NULL)
            out_name(&o, ", \"reply_name\": ", rec->reply_name->name);
        if (rec->not_kept) {
            out_text(&o, ", \"error\": \"reply to a command that was not kept: more than ");
            out_number(&o, rec->kept);
            out_text(&o, " commands awaited replies\"}");
        } else
            out_text(&o, rec->error ? ", \"error\": true}" : ", \"error\": false}");
    }
    if (cap > 0)
        out[o.len < cap ? o.len : cap - 1] = '\0';
    return o.len;
}
