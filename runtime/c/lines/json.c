/* <standalone> */
#include <string.h>
#include "../common/macros.h"
#include "../common/buffer.h"
#include "../common/utf8.h"
#include "match.h"
#include "lines.h"
/* </standalone> */
/* ---- canonical JSON of a record (docs/canonical-json.md) ---------------------------------- */

/* Bytes as a JSON string, escaped as Python's json module does with ensure_ascii=False, invalid
 * UTF-8 replaced as bytes.decode("utf-8", "replace") does (runtime/c/common/utf8.c). */
static void out_string(urwire__text *o, lines_view v)
{
    static const char hex[] = "0123456789abcdef";
    size_t i = 0, len, bad;
    urwire__bytes(o, "\"", 1);
    while (i < v.len) {
        uint8_t ch = v.ptr[i];
        if (ch >= 0x80) {
            bad = 0;
            len = urwire__utf8_sequence(v.ptr + i, v.len - i, &bad);
            if (len) {
                urwire__bytes(o, (const char *)v.ptr + i, len);
                i += len;
            } else {
                urwire__bytes(o, "\xEF\xBF\xBD", 3);
                i += bad;
            }
            continue;
        }
        switch (ch) {
        case '"': urwire__bytes(o, "\\\"", 2); break;
        case '\\': urwire__bytes(o, "\\\\", 2); break;
        case '\n': urwire__bytes(o, "\\n", 2); break;
        case '\r': urwire__bytes(o, "\\r", 2); break;
        case '\t': urwire__bytes(o, "\\t", 2); break;
        case '\b': urwire__bytes(o, "\\b", 2); break;
        case '\f': urwire__bytes(o, "\\f", 2); break;
        default:
            if (ch < 0x20) {
                char u[6] = {'\\', 'u', '0', '0', hex[ch >> 4], hex[ch & 15]};
                urwire__bytes(o, u, sizeof u);
            } else {
                urwire__bytes(o, (const char *)&ch, 1);
            }
        }
        i++;
    }
    urwire__bytes(o, "\"", 1);
}

static void out_name(urwire__text *o, const char *key, const char *name)
{
    lines_view v;
    v.ptr = (const uint8_t *)name;
    v.len = strlen(name);
    urwire__str(o, key);
    out_string(o, v);
}

static void out_number(urwire__text *o, uint64_t n)
{
    char digits[21];
    size_t at = sizeof digits;
    do {
        digits[--at] = (char)('0' + (int)(n % 10u));
        n /= 10u;
    } while (n);
    urwire__bytes(o, digits + at, sizeof digits - at);
}

/* The first line after bytes lost in its direction, and a reply whose command they leave unknown:
 * each text once in the object code, where `"error": "` opens it. */
#define LINES__AFTER_GAP "line after bytes lost from the capture: its start may be lost"
#define LINES__UNKNOWN "reply after bytes lost from the capture: its command is unknown"

static void out_error(urwire__text *o, const char *text)
{
    urwire__str(o, ", \"error\": \"");
    urwire__str(o, text);
    urwire__str(o, "\"");
}

/* Whether the record's JSON carries an error text (a fault, or a line the conversation could not
 * pair or take whole): what makes a command exit 1. A reply that says an error is the robot's word. */
URWIRE__PRIVATE bool lines_failed(const lines_record *rec)
{
    return rec->type == LINES_FAULT || rec->not_kept || rec->cut || rec->unknown;
}

/* The record as a line of canonical JSON (no newline) in out, NUL-terminated when cap > 0.
 * Returns its length; when that is cap or more, out holds its first cap - 1 bytes. */
URWIRE__PRIVATE size_t lines_json(const lines_spec_t *spec, const lines_record *rec, char *out, size_t cap)
{
    urwire__text o;
    o.out = out;
    o.cap = cap;
    o.n = 0;
    if (rec->type == LINES_FAULT) {
        urwire__str(&o, "{\"type\": \"error\", \"offset\": ");
        out_number(&o, rec->offset);
        if (rec->fault == LINES_LINE_TOO_LONG) {
            urwire__str(&o, ", \"error\": \"line longer than ");
            out_number(&o, spec->max_line);
            urwire__str(&o, " bytes\"}");
        } else {
            urwire__str(&o, ", \"error\": \"");
            out_number(&o, rec->bytes);
            urwire__str(&o, " bytes without a newline at the end of the stream\"}");
        }
    } else if (rec->type == LINES_COMMAND) {
        urwire__str(&o, "{\"type\": \"command\", \"command\": ");
        out_string(&o, rec->text);
        if (rec->command_name != LINES_NONE)
            out_name(&o, ", \"command_name\": ", spec->commands[rec->command_name].name);
        if (rec->has_argument) {
            urwire__str(&o, ", \"argument\": ");
            out_string(&o, rec->argument);
        }
        if (rec->available >= 0)
            urwire__str(&o, rec->available ? ", \"available\": true" : ", \"available\": false");
        if (rec->cut) {
            out_error(&o, LINES__AFTER_GAP);
        } else if (rec->not_kept) {
            urwire__str(&o, ", \"error\": \"command not kept: more than ");
            out_number(&o, rec->kept);
            urwire__str(&o, " commands awaited replies\"");
        }
        urwire__str(&o, "}");
    } else {
        urwire__str(&o, "{\"type\": \"reply\", \"reply\": ");
        out_string(&o, rec->text);
        if (rec->command_name != LINES_NONE)
            out_name(&o, ", \"command_name\": ", spec->commands[rec->command_name].name);
        if (rec->reply_name != NULL)
            out_name(&o, ", \"reply_name\": ", rec->reply_name->name);
        if (rec->not_kept) {
            urwire__str(&o, ", \"error\": \"reply to a command that was not kept: more than ");
            out_number(&o, rec->kept);
            urwire__str(&o, " commands awaited replies\"}");
        } else if (rec->unknown || rec->cut) {
            out_error(&o, rec->unknown ? LINES__UNKNOWN : LINES__AFTER_GAP);
            urwire__str(&o, "}");
        } else {
            urwire__str(&o, rec->error ? ", \"error\": true}" : ", \"error\": false}");
        }
    }
    return urwire__end(&o);
}
