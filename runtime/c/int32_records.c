/* <standalone> */
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
/* </standalone> */
/* ---- int32 records: loads, the JSON writer, scaled numbers as Python's repr writes them ------ */
/* Every function is static: each interface of this kind joins its own copy. */

static int32_t i32r_load(const uint8_t *p)
{
    uint32_t u = (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | (uint32_t)p[3];
    /* two's complement, without an implementation-defined cast */
    return u <= 0x7FFFFFFFu ? (int32_t)u : -(int32_t)(~u) - 1;
}

/* A JSON line in the caller's buffer; len counts what did not fit too. */
typedef struct i32r_out {
    char *buf;
    size_t cap, len;
} i32r_out;

static void i32r_bytes(i32r_out *o, const char *p, size_t n)
{
    size_t room = o->cap > o->len + 1 ? o->cap - o->len - 1 : 0;
    if (room > 0)
        memcpy(o->buf + o->len, p, n < room ? n : room);
    o->len += n;
}

static void i32r_text(i32r_out *o, const char *p)
{
    i32r_bytes(o, p, strlen(p));
}

static size_t i32r_end(i32r_out *o)
{
    if (o->cap > 0)
        o->buf[o->len < o->cap ? o->len : o->cap - 1] = '\0';
    return o->len;
}

/* The decimal digits of u, most significant first, in digits[]; returns their count. */
static size_t i32r_digits(uint64_t u, char digits[21])
{
    char rev[21];
    size_t n = 0, i;
    do {
        rev[n++] = (char)('0' + (int)(u % 10u));
        u /= 10u;
    } while (u);
    for (i = 0; i < n; i++)
        digits[i] = rev[n - 1 - i];
    return n;
}

static void i32r_int(i32r_out *o, int64_t v)
{
    char digits[21];
    uint64_t u = v < 0 ? (uint64_t)(-(v + 1)) + 1u : (uint64_t)v;
    if (v < 0)
        i32r_bytes(o, "-", 1);
    i32r_bytes(o, digits, i32r_digits(u, digits));
}

/* raw / 10^decimals as Python's repr() writes the double nearest it: the exact decimal is the
 * shortest text that reads back (values of 10 digits at most are 1e-6 apart, far more than an
 * ulp), in fixed notation with at least one decimal, or as 1.5e-05 below 1e-4. */
static void i32r_scaled(i32r_out *o, int32_t raw, unsigned decimals)
{
    char digits[21], text[48];
    uint64_t u = raw < 0 ? (uint64_t)(-(int64_t)raw) : (uint64_t)raw;
    size_t n, sig, at = 0, i;
    long exponent;
    if (raw == 0) {
        i32r_text(o, "0.0");
        return;
    }
    if (raw < 0)
        text[at++] = '-';
    n = i32r_digits(u, digits);
    for (sig = n; sig > 1 && digits[sig - 1] == '0'; sig--)
        ;
    exponent = (long)n - 1 - (long)decimals;
    if (exponent < -4) {
        text[at++] = digits[0];
        if (sig > 1) {
            text[at++] = '.';
            for (i = 1; i < sig; i++)
                text[at++] = digits[i];
        }
        text[at++] = 'e';
        text[at++] = '-';
        text[at++] = (char)('0' + (int)(-exponent / 10));
        text[at++] = (char)('0' + (int)(-exponent % 10));
    } else {
        size_t whole = n > decimals ? n - decimals : 0, end;
        if (whole == 0)
            text[at++] = '0';
        for (i = 0; i < whole; i++)
            text[at++] = digits[i];
        text[at++] = '.';
        for (i = n; i < decimals; i++)     /* zeros between the point and the first digit */
            text[at++] = '0';
        end = sig > whole ? sig : whole + 1;
        for (i = whole; i < end; i++)
            text[at++] = i < n ? digits[i] : '0';
    }
    i32r_bytes(o, text, at);
}

static size_t i32r_fault(uint64_t offset, size_t left, size_t size, bool from_robot, char *out, size_t cap)
{
    i32r_out o;
    o.buf = out;
    o.cap = cap;
    o.len = 0;
    i32r_text(&o, "{\"type\": \"error\", \"offset\": ");
    i32r_int(&o, (int64_t)offset);
    i32r_text(&o, ", \"error\": \"");
    i32r_int(&o, (int64_t)left);
    if (size == 0) {
        i32r_text(&o, from_robot ? " bytes from the robot, where none are specified\"}"
                                 : " bytes to the robot, where none are specified\"}");
    } else {
        i32r_text(&o, " bytes left, short of a ");
        i32r_int(&o, (int64_t)size);
        i32r_text(&o, "-byte record\"}");
    }
    return i32r_end(&o);
}
