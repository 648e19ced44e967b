/* Canonical JSON writer for urwire records. See json.h. */
#include "json.h"

#include <math.h>
#include <stdbool.h>
#include <string.h>

#include "shortest.h"
#include "../common/utf8.h"

/* Float texts are at most 25 bytes ("-2.2250738585072014e-308"). The layouts below copy a
 * fixed DIGIT_COPY bytes of digits, more than any float has, out of a buffer of twice that with
 * the digits ending in its middle, into a text with TEXT_ROOM bytes of room: fixed-size copies
 * compile to a few moves, where copies of the exact length would be calls. */
#define DIGIT_COPY 24
#define TEXT_ROOM 48

static const char digit_pairs[] =
    "00010203040506070809101112131415161718192021222324252627282930313233343536373839"
    "40414243444546474849505152535455565758596061626364656667686970717273747576777879"
    "8081828384858687888990919293949596979899";

/* The two digits of v (0 to 99). */
static const char *digit_pair(uint32_t v)
{
    return digit_pairs + (size_t)v * 2;
}

static void four_digits(char *at, uint32_t v)
{
    memcpy(at, digit_pair(v / 100), 2);
    memcpy(at + 2, digit_pair(v % 100), 2);
}

/* The decimal digits of n written to end just before end; returns where they start. */
static char *digits_before(char *end, uint64_t n)
{
    uint32_t m;
    while (n >= 100000000) {  /* eight at a time, in 32-bit arithmetic */
        uint64_t high = n / 100000000;
        uint32_t low = (uint32_t)(n - high * 100000000);
        end -= 8;
        four_digits(end, low / 10000);
        four_digits(end + 4, low % 10000);
        n = high;
    }
    for (m = (uint32_t)n; m >= 100; m /= 100) {
        end -= 2;
        memcpy(end, digit_pair(m % 100), 2);
    }
    if (m >= 10) {
        end -= 2;
        memcpy(end, digit_pair(m), 2);
    } else {
        *--end = (char)('0' + m);
    }
    return end;
}

/* A float's digits, ending in the middle of buf (see DIGIT_COPY). */
typedef struct digits {
    char buf[2 * DIGIT_COPY];
    const char *d;
    size_t n;
} digits;

static void set_digits(digits *g, uint64_t value)
{
    g->d = digits_before(g->buf + DIGIT_COPY, value);
    g->n = (size_t)(g->buf + DIGIT_COPY - g->d);
}

/* d[.ddd]e+XX, the exponent of at least two digits, as repr() and %g write it. */
static size_t scientific(char *out, const digits *g, int exp10)
{
    size_t at = g->n > 1 ? g->n + 1 : 1;
    unsigned e = (unsigned)(exp10 < 0 ? -exp10 : exp10);
    out[0] = g->d[0];
    out[1] = '.';
    memcpy(out + 2, g->d + 1, DIGIT_COPY);
    out[at++] = 'e';
    out[at++] = exp10 < 0 ? '-' : '+';
    if (e >= 100)
        out[at++] = (char)('0' + e / 100);
    memcpy(out + at, digit_pair(e % 100), 2);
    return at + 2;
}

/* The digits with the decimal point after the first `point` of them: point from -3 to 0 puts
 * "0." and -point zeros first; point > n, zeros up to it (16 at most), then ".0". */
static size_t fixed(char *out, const digits *g, int point)
{
    size_t at, n = g->n;
    if (point <= 0) {
        at = 2 + (size_t)-point;
        memcpy(out, "0.000", 5);
        memcpy(out + at, g->d, DIGIT_COPY);
        return at + n;
    }
    at = (size_t)point;
    memcpy(out, g->d, DIGIT_COPY);
    if (at < n) {
        out[at] = '.';
        memcpy(out + at + 1, g->d + at, DIGIT_COPY);
        return n + 1;
    }
    memcpy(out + n, "0000000000000000", 16);
    out[at++] = '.';
    out[at++] = '0';
    return at;
}

/* NaN and the infinities as canonical JSON names them, and a zero as `zero`, signed: the
 * texts that need no digits. */
static size_t wordy_text(double x, const char *zero, char *out)
{
    const char *t = isnan(x) ? "NaN" : isinf(x) ? (x > 0 ? "Infinity" : "-Infinity") : zero;
    size_t sign = !isnan(x) && !isinf(x) && signbit(x), n = strlen(t);
    out[0] = '-';
    memcpy(out + sign, t, n);
    return sign + n;
}

/* |x| = dec laid out as Python's repr() lays out a double: fixed from 1e-4 up to 1e16, with at
 * least one decimal, else scientific. Float32 texts too: only their digits are their own. */
static size_t decimal_text(double x, shortest_decimal dec, char *out)
{
    digits g;
    size_t sign = signbit(x) ? 1 : 0;
    int point;
    set_digits(&g, dec.digits);
    point = (int)g.n + dec.exponent;
    out[0] = '-';
    if (point <= -4 || point > 16)
        return sign + scientific(out + sign, &g, point - 1);
    return sign + fixed(out + sign, &g, point);
}

/* The canonical texts; out has TEXT_ROOM bytes. */
static size_t f64_text(double x, char *out)
{
    if (!isfinite(x) || x == 0)
        return wordy_text(x, "0.0", out);
    return decimal_text(x, shortest_f64(x), out);
}

static size_t f32_text(float x, char *out)
{
    if (!isfinite(x) || x == 0)
        return wordy_text(x, "0.0", out);
    return decimal_text(x, shortest_f32(x), out);
}

static void cut(const char *text, size_t n, char *buf, size_t cap)
{
    if (cap == 0)
        return;
    if (n >= cap)
        n = cap - 1;
    memcpy(buf, text, n);
    buf[n] = '\0';
}

void json_f32_text(float x, char *buf, size_t cap)
{
    char text[TEXT_ROOM];
    cut(text, f32_text(x, text), buf, cap);
}

void json_f64_text(double x, char *buf, size_t cap)
{
    char text[TEXT_ROOM];
    cut(text, f64_text(x, text), buf, cap);
}

/* The writer's buffer: bytes go to out in one fwrite per record, not one call per token. */
static void flush(json_writer *w)
{
    if (w->len > 0)
        fwrite(w->buf, 1, w->len, w->out);
    w->len = 0;
    w->flushes++;
}

/* Room for n more bytes (n <= JSON_WRITER_BUFFER); the caller adds what it wrote to w->len. */
static char *reserve(json_writer *w, size_t n)
{
    if (sizeof w->buf - w->len < n)
        flush(w);
    return w->buf + w->len;
}

static void put(json_writer *w, const char *p, size_t n)
{
    if (sizeof w->buf - w->len < n) {
        flush(w);
        if (n > sizeof w->buf) {
            fwrite(p, 1, n, w->out);
            return;
        }
    }
    memcpy(w->buf + w->len, p, n);
    w->len += n;
}

static void put_char(json_writer *w, char c)
{
    if (w->len == sizeof w->buf)
        flush(w);
    w->buf[w->len++] = c;
}

/* Bytes as a JSON string into w's buffer (see json_write_text). */
static void write_text(json_writer *w, const unsigned char *p, size_t n)
{
    static const char hex[] = "0123456789abcdef";
    size_t i = 0, run, len, bad;
    put_char(w, '"');
    while (i < n) {
        unsigned char c = p[i];
        for (run = i; run < n && p[run] >= 0x20 && p[run] < 0x80 && p[run] != '"' && p[run] != '\\'; run++)
            ;
        if (run > i) {
            put(w, (const char *)p + i, run - i);
            i = run;
            continue;
        }
        if (c < 0x80) {
            switch (c) {
            case '"': put(w, "\\\"", 2); break;
            case '\\': put(w, "\\\\", 2); break;
            case '\n': put(w, "\\n", 2); break;
            case '\r': put(w, "\\r", 2); break;
            case '\t': put(w, "\\t", 2); break;
            case '\b': put(w, "\\b", 2); break;
            case '\f': put(w, "\\f", 2); break;
            default: {
                char u[6] = {'\\', 'u', '0', '0', hex[c >> 4], hex[c & 15]};
                put(w, u, sizeof u);
            }
            }
            i++;
            continue;
        }
        bad = 0;
        len = urwire__utf8_sequence(p + i, n - i, &bad);
        if (len) {
            put(w, (const char *)p + i, len);
            i += len;
        } else {
            put(w, "\xEF\xBF\xBD", 3);
            i += bad;
        }
    }
    put_char(w, '"');
}

/* Bytes as a JSON string of hex digits into w's buffer (see json_write_hex). */
static void write_hex(json_writer *w, const unsigned char *p, size_t n)
{
    static const char hex[] = "0123456789abcdef";
    size_t i = 0, k;
    char *at;
    put_char(w, '"');
    while (i < n) {
        size_t chunk = n - i < sizeof w->buf / 2 ? n - i : sizeof w->buf / 2;
        at = reserve(w, 2 * chunk);
        /* cppcheck-suppress knownConditionTrueFalse ; cppcheck 2.10 takes sizeof w->buf for 0 */
        for (k = 0; k < chunk; k++, i++) {
            *at++ = hex[p[i] >> 4];
            *at++ = hex[p[i] & 15];
        }
        w->len += 2 * chunk;
    }
    put_char(w, '"');
}

/* Bytes written alone, straight to out, by a writer of their own. */
static void write_alone(FILE *out, void (*write)(json_writer *, const unsigned char *, size_t),
                        const unsigned char *p, size_t n)
{
    json_writer w;
    w.out = out;
    w.len = 0;
    w.flushes = 0;
    write(&w, p, n);
    flush(&w);
}

void json_write_text(FILE *out, const unsigned char *p, size_t n)
{
    write_alone(out, write_text, p, n);
}

void json_write_hex(FILE *out, const unsigned char *p, size_t n)
{
    write_alone(out, write_hex, p, n);
}

void json_write_f64(FILE *out, double x)
{
    char text[TEXT_ROOM];
    size_t n = f64_text(x, text);
    fwrite(text, 1, n, out);
}

/* A record is written: hand it to out. */
static void record_end(json_writer *w)
{
    if (w->depth <= 0)
        flush(w);
}

/* Writes the separator and key of the next value and returns where the value goes, with
 * `room` bytes of room there; the caller sets w->len past what it writes. */
static char *field(json_writer *w, const char *key, size_t room)
{
    size_t n = key ? strlen(key) : 0;
    bool comma = false;
    char *at;
    /* The protocol nests values 8 deep at most; past `first` the writer would misplace commas
     * but never write out of bounds. */
    if (w->depth > 0 && w->depth <= (int)sizeof w->first) {
        comma = !w->first[w->depth - 1];
        w->first[w->depth - 1] = 0;
    }
    if (n + room + 5 > sizeof w->buf) {  /* no key is this long; written in pieces if one were */
        if (comma)
            put(w, ", ", 2);
        if (key) {
            put_char(w, '"');
            put(w, key, n);
            put(w, "\": ", 3);
        }
        return reserve(w, room);
    }
    at = reserve(w, n + room + 5);
    if (comma) {
        *at++ = ',';
        *at++ = ' ';
    }
    if (key) {
        *at++ = '"';
        memcpy(at, key, n);
        at += n;
        memcpy(at, "\": ", 3);
        at += 3;
    }
    return at;
}

static void open_(json_writer *w, const char *key, char c)
{
    char *at = field(w, key, 1);
    *at++ = c;
    w->len = (size_t)(at - w->buf);
    if (w->depth < (int)sizeof w->first)
        w->first[w->depth] = 1;
    w->depth++;
}

/* The package being kept has ended: its text goes to its slot, without the separator before
 * it, when it is all still in buf and fits. */
static void keep(json_writer *w)
{
    json_kept_package *k = w->keeping;
    const char *text = w->buf + w->keeping_from;
    size_t n = w->len - w->keeping_from;
    w->keeping = NULL;
    if (w->flushes != w->keeping_flushes)
        return;
    if (n >= 2 && text[0] == ',') {
        text += 2;
        n -= 2;
    }
    if (n <= sizeof k->text) {
        memcpy(k->text, text, n);
        k->text_length = n;
    }
}

static void close_(json_writer *w, char c)
{
    put_char(w, c);
    w->depth--;
    if (w->keeping != NULL && w->depth < w->keeping_depth)
        keep(w);
    record_end(w);
}

static void begin_object(void *ctx, const char *key) { open_((json_writer *)ctx, key, '{'); }
static void end_object(void *ctx) { close_((json_writer *)ctx, '}'); }
static void begin_array(void *ctx, const char *key) { open_((json_writer *)ctx, key, '['); }
static void end_array(void *ctx) { close_((json_writer *)ctx, ']'); }

/* An integer's text at at: v, after a minus sign when negative. */
static size_t integer_text(char *at, uint64_t v, bool negative)
{
    /* cppcheck-suppress unassignedVariable ; digits_before writes buf, from its middle back */
    char buf[2 * DIGIT_COPY], *d = digits_before(buf + DIGIT_COPY, v);
    at[0] = '-';
    memcpy(at + negative, d, DIGIT_COPY);
    return (size_t)(buf + DIGIT_COPY - d) + negative;
}

static void on_int(void *ctx, const char *key, int64_t v)
{
    json_writer *w = (json_writer *)ctx;
    char *at = field(w, key, TEXT_ROOM);
    w->len = (size_t)(at - w->buf) + integer_text(at, v < 0 ? 0 - (uint64_t)v : (uint64_t)v, v < 0);
    record_end(w);
}

static void on_uint(void *ctx, const char *key, uint64_t v)
{
    json_writer *w = (json_writer *)ctx;
    char *at = field(w, key, TEXT_ROOM);
    w->len = (size_t)(at - w->buf) + integer_text(at, v, false);
    record_end(w);
}

static void on_bool(void *ctx, const char *key, bool v)
{
    json_writer *w = (json_writer *)ctx;
    char *at = field(w, key, 5);
    memcpy(at, v ? "true" : "false", 5);
    w->len = (size_t)(at - w->buf) + (v ? 4 : 5);
    record_end(w);
}

static void on_f32(void *ctx, const char *key, float v)
{
    json_writer *w = (json_writer *)ctx;
    char *at = field(w, key, TEXT_ROOM);
    w->len = (size_t)(at - w->buf) + f32_text(v, at);
    record_end(w);
}

static void on_f64(void *ctx, const char *key, double v)
{
    json_writer *w = (json_writer *)ctx;
    char *at = field(w, key, TEXT_ROOM);
    w->len = (size_t)(at - w->buf) + f64_text(v, at);
    record_end(w);
}

static void on_text(void *ctx, const char *key, urwire_bytes t)
{
    json_writer *w = (json_writer *)ctx;
    w->len = (size_t)(field(w, key, 0) - w->buf);
    write_text(w, t.ptr, t.len);
    record_end(w);
}

static void on_hex(void *ctx, const char *key, urwire_bytes b)
{
    json_writer *w = (json_writer *)ctx;
    w->len = (size_t)(field(w, key, 0) - w->buf);
    write_hex(w, b.ptr, b.len);
    record_end(w);
}

static void on_null(void *ctx, const char *key)
{
    json_writer *w = (json_writer *)ctx;
    char *at = field(w, key, 4);
    memcpy(at, "null", 4);
    w->len = (size_t)(at - w->buf) + 4;
    record_end(w);
}

static bool same_version(urwire_sw_version a, urwire_sw_version b)
{
    return a.major == b.major && a.minor == b.minor && a.bugfix == b.bugfix && a.assumed == b.assumed;
}

/* Before a sub-package: its kept text, when its type, version and body are those it was made
 * from; otherwise the walk writes it, and its text is kept when it ends. A malformed package
 * is never kept: its error names offsets in the message. */
static bool on_package(void *ctx, const urwire_package *pkg)
{
    json_writer *w = (json_writer *)ctx;
    json_kept_package *k;
    char *at;
    if (pkg->type >= JSON_KEPT_TYPES || pkg->raw.len > JSON_KEPT_BODY || pkg->failed)
        return false;
    k = &w->kept[pkg->type];
    if (k->text_length > 0 && k->body_length == pkg->raw.len && same_version(k->version, pkg->version) &&
        memcmp(k->body, pkg->raw.ptr, pkg->raw.len) == 0) {
        at = field(w, NULL, k->text_length);
        memcpy(at, k->text, k->text_length);
        w->len = (size_t)(at - w->buf) + k->text_length;
        return true;
    }
    k->text_length = 0;
    k->version = pkg->version;
    k->body_length = pkg->raw.len;
    if (pkg->raw.len > 0)
        memcpy(k->body, pkg->raw.ptr, pkg->raw.len);
    w->keeping = k;
    w->keeping_depth = w->depth + 1;  /* the package's object, opened next */
    w->keeping_from = w->len;
    w->keeping_flushes = w->flushes;
    return false;
}

urwire_visitor json_visitor(json_writer *w)
{
    urwire_visitor v;
    size_t i;
    w->len = 0;
    w->flushes = 0;
    w->keeping = NULL;
    for (i = 0; i < JSON_KEPT_TYPES; i++)
        w->kept[i].text_length = 0;
    v.ctx = w;
    v.begin_object = begin_object;
    v.end_object = end_object;
    v.begin_array = begin_array;
    v.end_array = end_array;
    v.on_int = on_int;
    v.on_uint = on_uint;
    v.on_bool = on_bool;
    v.on_f32 = on_f32;
    v.on_f64 = on_f64;
    v.on_text = on_text;
    v.on_hex = on_hex;
    v.on_null = on_null;
    v.package = on_package;
    return v;
}
