/* Canonical JSON writer for urwire records. See json.h. */
#include "json.h"

#include <inttypes.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

void json_f32_text(float x, char *buf, size_t cap)
{
    int p;
    if (isnan(x)) {
        snprintf(buf, cap, "NaN");
        return;
    }
    if (isinf(x)) {
        snprintf(buf, cap, x > 0 ? "Infinity" : "-Infinity");
        return;
    }
    for (p = 1; p <= 9; p++) {
        snprintf(buf, cap, "%.*g", p, (double)x);
        if (strtof(buf, NULL) == x)
            return;
    }
    snprintf(buf, cap, "%.9g", (double)x);
}

/* Does the decimal 0.digits * 10^(exp10 + 1), with this sign, read back as x? */
static int f64_reads_back(double x, const char *digits, int exp10)
{
    char text[48];
    snprintf(text, sizeof text, "%s%c.%se%d", x < 0 || (x == 0 && signbit(x)) ? "-" : "", digits[0], digits + 1,
             exp10);
    return strtod(text, NULL) == x;
}

/* The shortest digits that read back as x, laid out as Python's repr() lays them out: fixed
 * notation with at least one decimal when the decimal exponent is from -4 to 15 ("1.0",
 * "0.0001", "1e+16", "1e-05"), so that the CLI's lines are the Python CLI's byte for byte.
 * For each length p = 1..17: the correctly rounded %.{p-1}e, else its neighbour towards x
 * (at a power of two the rounding interval is lopsided, and only the neighbour may fit). */
void json_f64_text(double x, char *buf, size_t cap)
{
    char sci[40], digits[24], near[24];
    const char *e;
    int p, exp10 = 0, n = 0, decpt, k, found = 0;
    size_t at = 0;
    if (isnan(x) || isinf(x)) {
        snprintf(buf, cap, isnan(x) ? "NaN" : x > 0 ? "Infinity" : "-Infinity");
        return;
    }
    for (p = 1; p <= 17 && !found; p++) {
        snprintf(sci, sizeof sci, "%.*e", p - 1, x);
        for (n = 0, e = sci; *e && *e != 'e'; e++)
            if (*e >= '0' && *e <= '9')
                digits[n++] = *e;
        digits[n] = '\0';
        exp10 = atoi(e + 1);
        found = strtod(sci, NULL) == x;
        if (!found && p > 1) {
            /* The neighbour on x's side: up when the rounded text lies below |x|. */
            int up = fabs(strtod(sci, NULL)) < fabs(x);
            memcpy(near, digits, (size_t)n + 1);
            if (up ? near[n - 1] < '9' : near[n - 1] > '0') {
                near[n - 1] = (char)(near[n - 1] + (up ? 1 : -1));
                if (f64_reads_back(x, near, exp10)) {
                    memcpy(digits, near, (size_t)n + 1);
                    found = 1;
                }
            }
        }
    }
    while (n > 1 && digits[n - 1] == '0')
        digits[--n] = '\0';
    decpt = exp10 + 1;  /* x = 0.digits * 10^decpt */
    if (sci[0] == '-' && at + 1 < cap)
        buf[at++] = '-';
    if (decpt > -4 && decpt <= 16) {
        if (decpt <= 0) {
            at += (size_t)snprintf(buf + at, cap - at, "0.");
            for (k = 0; k < -decpt; k++)
                at += (size_t)snprintf(buf + at, cap - at, "0");
            snprintf(buf + at, cap - at, "%s", digits);
        } else {
            for (k = 0; k < decpt || k < n; k++) {
                if (k == decpt)
                    at += (size_t)snprintf(buf + at, cap - at, ".");
                at += (size_t)snprintf(buf + at, cap - at, "%c", k < n ? digits[k] : '0');
            }
            if (decpt >= n)
                snprintf(buf + at, cap - at, ".0");
        }
    } else {
        at += (size_t)snprintf(buf + at, cap - at, "%c", digits[0]);
        if (n > 1)
            at += (size_t)snprintf(buf + at, cap - at, ".%s", digits + 1);
        snprintf(buf + at, cap - at, "e%c%02d", exp10 < 0 ? '-' : '+', exp10 < 0 ? -exp10 : exp10);
    }
}

/* Length of the valid UTF-8 sequence at p (1..4), or 0 with *bad set to the length of the
 * maximal subpart to replace by one U+FFFD (Unicode 3-7, as CPython's decoder). */
static size_t utf8_sequence(const unsigned char *p, size_t n, size_t *bad)
{
    unsigned char b = p[0], lo = 0x80, hi = 0xBF;
    size_t need, k;
    if (b < 0x80)
        return 1;
    if (b >= 0xC2 && b <= 0xDF)
        need = 1;
    else if (b >= 0xE0 && b <= 0xEF) {
        need = 2;
        if (b == 0xE0)
            lo = 0xA0;
        if (b == 0xED)
            hi = 0x9F;
    } else if (b >= 0xF0 && b <= 0xF4) {
        need = 3;
        if (b == 0xF0)
            lo = 0x90;
        if (b == 0xF4)
            hi = 0x8F;
    } else {
        *bad = 1;
        return 0;
    }
    for (k = 1; k <= need; k++) {
        unsigned char c;
        if (k >= n) {
            *bad = k;
            return 0;
        }
        c = p[k];
        if (c < (k == 1 ? lo : 0x80) || c > (k == 1 ? hi : 0xBF)) {
            *bad = k;
            return 0;
        }
    }
    return need + 1;
}

void json_write_text(FILE *out, const unsigned char *p, size_t n)
{
    size_t i = 0, len, bad;
    putc('"', out);
    while (i < n) {
        unsigned char c = p[i];
        if (c < 0x80) {
            switch (c) {
            case '"': fputs("\\\"", out); break;
            case '\\': fputs("\\\\", out); break;
            case '\n': fputs("\\n", out); break;
            case '\r': fputs("\\r", out); break;
            case '\t': fputs("\\t", out); break;
            case '\b': fputs("\\b", out); break;
            case '\f': fputs("\\f", out); break;
            default:
                if (c < 0x20)
                    fprintf(out, "\\u%04x", c);
                else
                    putc(c, out);
            }
            i++;
            continue;
        }
        bad = 0;
        len = utf8_sequence(p + i, n - i, &bad);
        if (len) {
            fwrite(p + i, 1, len, out);
            i += len;
        } else {
            fputs("\xEF\xBF\xBD", out);
            i += bad;
        }
    }
    putc('"', out);
}

static void sep(json_writer *w, const char *key)
{
    if (w->depth > 0) {
        if (!w->first[w->depth - 1])
            fputs(", ", w->out);
        w->first[w->depth - 1] = 0;
    }
    if (key)
        fprintf(w->out, "\"%s\": ", key);
}

static void open_(json_writer *w, const char *key, char c)
{
    sep(w, key);
    putc(c, w->out);
    if (w->depth < (int)sizeof w->first)
        w->first[w->depth] = 1;
    w->depth++;
}

static void close_(json_writer *w, char c)
{
    putc(c, w->out);
    w->depth--;
}

static void begin_object(void *ctx, const char *key) { open_((json_writer *)ctx, key, '{'); }
static void end_object(void *ctx) { close_((json_writer *)ctx, '}'); }
static void begin_array(void *ctx, const char *key) { open_((json_writer *)ctx, key, '['); }
static void end_array(void *ctx) { close_((json_writer *)ctx, ']'); }

static void on_int(void *ctx, const char *key, int64_t v)
{
    json_writer *w = (json_writer *)ctx;
    sep(w, key);
    fprintf(w->out, "%" PRId64, v);
}

static void on_uint(void *ctx, const char *key, uint64_t v)
{
    json_writer *w = (json_writer *)ctx;
    sep(w, key);
    fprintf(w->out, "%" PRIu64, v);
}

static void on_bool(void *ctx, const char *key, bool v)
{
    json_writer *w = (json_writer *)ctx;
    sep(w, key);
    fputs(v ? "true" : "false", w->out);
}

static void on_f32(void *ctx, const char *key, float v)
{
    json_writer *w = (json_writer *)ctx;
    char buf[48];
    sep(w, key);
    json_f32_text(v, buf, sizeof buf);
    fputs(buf, w->out);
}

static void on_f64(void *ctx, const char *key, double v)
{
    json_writer *w = (json_writer *)ctx;
    char buf[48];
    sep(w, key);
    json_f64_text(v, buf, sizeof buf);
    fputs(buf, w->out);
}

static void on_text(void *ctx, const char *key, urwire_bytes t)
{
    json_writer *w = (json_writer *)ctx;
    sep(w, key);
    json_write_text(w->out, t.ptr, t.len);
}

static void on_hex(void *ctx, const char *key, urwire_bytes b)
{
    static const char digits[] = "0123456789abcdef";
    json_writer *w = (json_writer *)ctx;
    size_t i;
    sep(w, key);
    putc('"', w->out);
    for (i = 0; i < b.len; i++) {
        putc(digits[b.ptr[i] >> 4], w->out);
        putc(digits[b.ptr[i] & 15], w->out);
    }
    putc('"', w->out);
}

static void on_null(void *ctx, const char *key)
{
    json_writer *w = (json_writer *)ctx;
    sep(w, key);
    fputs("null", w->out);
}

urwire_visitor json_visitor(json_writer *w)
{
    urwire_visitor v;
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
    return v;
}
