/* libFuzzer harness: urwire-decode's side of the stream, from the version hint to the JSON Lines
 * (runtime/c/json: records.c, json.c; the library's urwire_parse_version).
 *
 * Input: one control byte, then the stream. The control byte's low bits pick a version hint
 * ("", 3.2, 5.0, 5.12); with bit 2 set, the hint is the text that follows, up to a NUL. Bits 3-7
 * pick the size of the chunks fed to the framer. Checked on every input:
 *   - urwire_parse_version agrees with a plain reading of its documented grammar, and what it
 *     accepts prints and parses back to the same version;
 *   - every output line is one JSON object (a strict parser, which also takes NaN and
 *     +-Infinity as Python's json module writes them), whose first key is "type", in valid UTF-8;
 *   - every float text reads back as the same float, and a float64 text looks like Python's
 *     repr (a "." or an exponent);
 *   - the lines are the same, byte for byte, when the whole stream is fed at once;
 *   - json_write_text keeps valid UTF-8 as it is, and turns any bytes into a JSON string.
 *
 *     make fuzz-json FUZZ_SECONDS=600     # longer runs; crashes land in build/fuzz/crashes-json/
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "json.h"
#include "records.h"
#include "urwire.h"

#define HINT_MAX 32

static uint8_t framer_buffer[URWIRE_FRAMER_MIN_BUFFER];

/* ---- a plain reading of the grammar json.h and urwire.h document --------------------------- */

/* Length of the well-formed UTF-8 sequence at p (RFC 3629), or 0. */
static size_t utf8_length(const unsigned char *p, size_t n)
{
    size_t need, k;
    unsigned long cp;
    if (p[0] < 0x80)
        return 1;
    if ((p[0] & 0xE0) == 0xC0)
        need = 1, cp = p[0] & 0x1Fu;
    else if ((p[0] & 0xF0) == 0xE0)
        need = 2, cp = p[0] & 0x0Fu;
    else if ((p[0] & 0xF8) == 0xF0)
        need = 3, cp = p[0] & 0x07u;
    else
        return 0;
    if (need >= n)
        return 0;
    for (k = 1; k <= need; k++) {
        if ((p[k] & 0xC0) != 0x80)
            return 0;
        cp = cp << 6 | (p[k] & 0x3Fu);
    }
    if ((need == 1 && cp < 0x80) || (need == 2 && cp < 0x800) || (need == 3 && cp < 0x10000) || cp > 0x10FFFF ||
        (cp >= 0xD800 && cp <= 0xDFFF))
        return 0;
    return need + 1;
}

static int is_utf8(const unsigned char *p, size_t n)
{
    size_t i = 0, k;
    while (i < n) {
        if ((k = utf8_length(p + i, n - i)) == 0)
            return 0;
        i += k;
    }
    return 1;
}

static int is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f'; }

/* "major.minor" or "major.minor.bugfix" between ASCII blanks, each part 1 to 6 digits. */
static int reference_version(const char *text, int parts[3])
{
    size_t start = 0, end = strlen(text), i, digits = 0;
    int n = 0;
    parts[0] = parts[1] = parts[2] = 0;
    while (start < end && is_space(text[start]))
        start++;
    while (end > start && is_space(text[end - 1]))
        end--;
    for (i = start; i < end; i++) {
        if (text[i] == '.') {
            if (digits == 0 || ++n > 2)
                return 0;
            digits = 0;
        } else if (text[i] >= '0' && text[i] <= '9' && ++digits <= 6) {
            parts[n] = parts[n] * 10 + (text[i] - '0');
        } else {
            return 0;
        }
    }
    return digits > 0 && n >= 1;
}

static void check_version(const char *text)
{
    urwire_sw_version v = {-1, -1, -1, true}, again;
    char printed[40];
    int parts[3], ok = urwire_parse_version(text, &v), expected = reference_version(text, parts);
    if (ok != expected)
        abort();
    if (!ok) {
        if (v.major != -1 || v.minor != -1 || v.bugfix != -1 || !v.assumed)
            abort();  /* refused: *out untouched */
        return;
    }
    if (v.major != parts[0] || v.minor != parts[1] || v.bugfix != parts[2] || v.assumed)
        abort();
    snprintf(printed, sizeof printed, "%d.%d.%d", v.major, v.minor, v.bugfix);
    if (!urwire_parse_version(printed, &again) || again.major != v.major || again.minor != v.minor ||
        again.bugfix != v.bugfix)
        abort();
}

/* ---- a strict JSON parser for one line ------------------------------------------------------ */

typedef struct cursor {
    const char *p, *end;
} cursor;

static int json_value(cursor *c, int depth);

static int take(cursor *c, const char *word)
{
    size_t n = strlen(word);
    if ((size_t)(c->end - c->p) < n || memcmp(c->p, word, n) != 0)
        return 0;
    c->p += n;
    return 1;
}

static void blanks(cursor *c)
{
    while (c->p < c->end && *c->p == ' ')
        c->p++;
}

static int digits(cursor *c)
{
    const char *start = c->p;
    while (c->p < c->end && *c->p >= '0' && *c->p <= '9')
        c->p++;
    return c->p > start;
}

static int json_number(cursor *c)
{
    if (take(c, "NaN") || take(c, "Infinity") || take(c, "-Infinity"))
        return 1;
    take(c, "-");
    if (take(c, "0")) {
        if (c->p < c->end && *c->p >= '0' && *c->p <= '9')
            return 0;  /* no leading zeros */
    } else if (!digits(c)) {
        return 0;
    }
    if (take(c, ".") && !digits(c))
        return 0;
    if (c->p < c->end && (*c->p == 'e' || *c->p == 'E')) {
        c->p++;
        if (!take(c, "+"))
            take(c, "-");
        return digits(c);
    }
    return 1;
}

static int json_string(cursor *c)
{
    if (!take(c, "\""))
        return 0;
    while (c->p < c->end && *c->p != '"') {
        unsigned char ch = (unsigned char)*c->p;
        size_t k;
        if (ch < 0x20)
            return 0;
        if (ch == '\\') {
            if (++c->p >= c->end)
                return 0;
            if (*c->p == 'u') {
                for (k = 1; k <= 4; k++)
                    if (c->p + k >= c->end || !strchr("0123456789abcdefABCDEF", c->p[k]) || c->p[k] == '\0')
                        return 0;
                c->p += 5;
            } else if (strchr("\"\\/bfnrt", *c->p) && *c->p != '\0') {
                c->p++;
            } else {
                return 0;
            }
            continue;
        }
        if ((k = utf8_length((const unsigned char *)c->p, (size_t)(c->end - c->p))) == 0)
            return 0;
        c->p += k;
    }
    return take(c, "\"");
}

/* A member list or element list up to the closing bracket; first_key gets the first key. */
static int json_members(cursor *c, int depth, char close, int keyed, const char **first_key)
{
    blanks(c);
    if (take(c, close == '}' ? "}" : "]"))
        return 1;
    for (;;) {
        blanks(c);
        if (keyed) {
            const char *key = c->p;
            if (!json_string(c))
                return 0;
            if (first_key && !*first_key)
                *first_key = key;
            blanks(c);
            if (!take(c, ":"))
                return 0;
            blanks(c);
        }
        if (!json_value(c, depth + 1))
            return 0;
        blanks(c);
        if (take(c, close == '}' ? "}" : "]"))
            return 1;
        if (!take(c, ","))
            return 0;
    }
}

static int json_value(cursor *c, int depth)
{
    if (depth > 64 || c->p >= c->end)
        return 0;
    switch (*c->p) {
    case '{': c->p++; return json_members(c, depth, '}', 1, NULL);
    case '[': c->p++; return json_members(c, depth, ']', 0, NULL);
    case '"': return json_string(c);
    case 't': return take(c, "true");
    case 'f': return take(c, "false");
    case 'n': return take(c, "null");
    default: return json_number(c);
    }
}

/* Every line: one JSON object whose first key is "type". */
static void check_lines(const char *out, size_t len)
{
    const char *line = out, *nl;
    if (len > 0 && out[len - 1] != '\n')
        abort();
    while (line < out + len) {
        cursor c;
        const char *first = NULL;
        nl = memchr(line, '\n', (size_t)(out + len - line));
        c.p = line;
        c.end = nl;
        if (!take(&c, "{") || !json_members(&c, 0, '}', 1, &first) || c.p != nl)
            abort();
        if (!first || strncmp(first, "\"type\"", 6) != 0)
            abort();
        line = nl + 1;
    }
}

/* ---- the JSON writer's visitor, with each float text checked on the way ------------------- */

typedef struct checked {
    urwire_visitor json;
} checked;

static void check_number_text(const char *text, size_t cap)
{
    cursor c;
    c.p = text;
    c.end = text + strlen(text);
    if ((size_t)(c.end - c.p) >= cap - 1 || !json_number(&c) || c.p != c.end)
        abort();
}

static void f32_checked(void *ctx, const char *key, float v)
{
    checked *k = (checked *)ctx;
    char text[48];
    json_f32_text(v, text, sizeof text);
    check_number_text(text, sizeof text);
    if (!isnan(v) && (strtof(text, NULL) != v || signbit(strtof(text, NULL)) != signbit(v)))
        abort();
    if (!isnan(v) && !isinf(v) && !strpbrk(text, ".e"))
        abort();  /* laid out as float64: always a decimal point or an exponent */
    k->json.on_f32(k->json.ctx, key, v);
}

static void f64_checked(void *ctx, const char *key, double v)
{
    checked *k = (checked *)ctx;
    char text[48];
    json_f64_text(v, text, sizeof text);
    check_number_text(text, sizeof text);
    if (!isnan(v) && !isinf(v) && !strpbrk(text, ".e"))
        abort();  /* repr() always shows a decimal point or an exponent */
    if (!isnan(v) && (strtod(text, NULL) != v || signbit(strtod(text, NULL)) != signbit(v)))
        abort();
    k->json.on_f64(k->json.ctx, key, v);
}

static void begin_object(void *ctx, const char *key) { checked *k = ctx; k->json.begin_object(k->json.ctx, key); }
static void end_object(void *ctx) { checked *k = ctx; k->json.end_object(k->json.ctx); }
static void begin_array(void *ctx, const char *key) { checked *k = ctx; k->json.begin_array(k->json.ctx, key); }
static void end_array(void *ctx) { checked *k = ctx; k->json.end_array(k->json.ctx); }
static void on_int(void *ctx, const char *key, int64_t v) { checked *k = ctx; k->json.on_int(k->json.ctx, key, v); }
static void on_uint(void *ctx, const char *key, uint64_t v) { checked *k = ctx; k->json.on_uint(k->json.ctx, key, v); }
static void on_bool(void *ctx, const char *key, bool v) { checked *k = ctx; k->json.on_bool(k->json.ctx, key, v); }
static void on_text(void *ctx, const char *key, urwire_bytes t) { checked *k = ctx; k->json.on_text(k->json.ctx, key, t); }
static void on_hex(void *ctx, const char *key, urwire_bytes b) { checked *k = ctx; k->json.on_hex(k->json.ctx, key, b); }
static void on_null(void *ctx, const char *key) { checked *k = ctx; k->json.on_null(k->json.ctx, key); }
static bool on_package(void *ctx, const urwire_package *pkg) { checked *k = ctx; return k->json.package(k->json.ctx, pkg); }

static urwire_visitor checked_visitor(checked *k)
{
    urwire_visitor v = {NULL, begin_object, end_object, begin_array, end_array, on_int, on_uint, on_bool,
                        f32_checked, f64_checked, on_text, on_hex, on_null, on_package};
    v.ctx = k;
    return v;
}

/* ---- the command's loop, into memory --------------------------------------------------------- */

typedef struct output {
    char *text;
    size_t len;
    bool errors;
} output;

static output decode(const uint8_t *data, size_t size, urwire_sw_version version, size_t chunk)
{
    output o = {NULL, 0, false};
    urwire_framer fr;
    json_writer w;
    checked k;
    urwire_visitor v;
    size_t off = 0;
    memset(&w, 0, sizeof w);
    w.out = open_memstream(&o.text, &o.len);
    if (!w.out)
        abort();
    k.json = json_visitor(&w);
    v = checked_visitor(&k);
    urwire_framer_init(&fr, framer_buffer, sizeof framer_buffer, version);
    while (off < size) {
        size_t n = chunk < size - off ? chunk : size - off, fed = 0;
        while (fed < n) {
            fed += urwire_framer_feed(&fr, data + off + fed, n - fed);
            o.errors |= print_ready_records(&fr, &v, &w);
        }
        off += n;
    }
    urwire_framer_finish(&fr);
    o.errors |= print_ready_records(&fr, &v, &w);
    if (fclose(w.out) != 0)
        abort();
    return o;
}

/* json_write_text: always a JSON string in UTF-8; valid UTF-8 comes out as it went in. */
static void check_text(const uint8_t *data, size_t size)
{
    char *text = NULL, *unescaped;
    size_t len = 0, i, n = 0;
    cursor c;
    FILE *out = open_memstream(&text, &len);
    if (!out)
        abort();
    json_write_text(out, data, size);
    if (fclose(out) != 0)
        abort();
    c.p = text;
    c.end = text + len;
    if (!json_string(&c) || c.p != c.end)
        abort();
    if (is_utf8(data, size)) {
        unescaped = malloc(len + 1);
        for (i = 1; i + 1 < len; i++) {
            char ch = text[i];
            if (ch == '\\') {
                ch = text[++i];
                if (ch == 'u') {
                    ch = (char)strtol((char[]){text[i + 1], text[i + 2], text[i + 3], text[i + 4], 0}, NULL, 16);
                    i += 4;
                } else {
                    ch = ch == 'n' ? '\n' : ch == 'r' ? '\r' : ch == 't' ? '\t' : ch == 'b' ? '\b' : ch == 'f' ? '\f' : ch;
                }
            }
            unescaped[n++] = ch;
        }
        if (n != size || memcmp(unescaped, data, n) != 0)
            abort();
        free(unescaped);
    }
    free(text);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const char *const hints[4] = {"", "3.2", "5.0", "5.12"};
    char hint[HINT_MAX + 1];
    urwire_sw_version version = URWIRE_DEFAULT_VERSION;
    output chunked, whole;
    uint8_t control;
    size_t n = 0, chunk;
    if (size == 0)
        return 0;
    control = data[0];
    data++;
    size--;
    /* 1 byte to 63 KiB, times one more for every 16 KiB of input (as fuzz_urwire.c) */
    chunk = (1 + (size_t)(control >> 3) * (control >> 3) * 67) * (1 + size / 16384);
    if (control & 4) {
        while (n < size && n < HINT_MAX && data[n] != 0)
            n++;
        memcpy(hint, data, n);
        hint[n] = '\0';
        data += n < size ? n + 1 : n;
        size -= n < size ? n + 1 : n;
    } else {
        strcpy(hint, hints[control & 3]);
    }
    check_version(hint);
    if (hint[0] && !urwire_parse_version(hint, &version))
        return 0;  /* the command stops: not a software version */
    check_text(data, size < 4096 ? size : 4096);

    chunked = decode(data, size, version, chunk);
    check_lines(chunked.text, chunked.len);
    if (!is_utf8((const unsigned char *)chunked.text, chunked.len))
        abort();
    whole = decode(data, size, version, size ? size : 1);
    if (whole.len != chunked.len || memcmp(whole.text, chunked.text, whole.len) != 0 || whole.errors != chunked.errors)
        abort();  /* how the bytes arrive never changes the lines */
    free(chunked.text);
    free(whole.text);
    return 0;
}
