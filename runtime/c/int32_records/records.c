/* <standalone> */
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include "../common/macros.h"
#include "../common/buffer.h"
#include "../common/loads.h"
/* </standalone> */
/* ---- int32 records: the JSON writer, scaled numbers as Python's repr writes them ------------ */
/* Every function is private: each interface of this kind joins its own copy, after
 * runtime/c/common/ (loads, the output buffer). */

/* The decimal digits of u, most significant first, in digits[]; returns their count. */
URWIRE__PRIVATE size_t i32r_digits(uint64_t u, char digits[21])
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

URWIRE__PRIVATE void i32r_int(urwire__text *o, int64_t v)
{
    char digits[21];
    uint64_t u = v < 0 ? (uint64_t)(-(v + 1)) + 1u : (uint64_t)v;
    if (v < 0)
        urwire__bytes(o, "-", 1);
    urwire__bytes(o, digits, i32r_digits(u, digits));
}

/* raw / 10^decimals as Python's repr() writes the double nearest it: the exact decimal is the
 * shortest text that reads back (values of 10 digits at most are 1e-6 apart, far more than an
 * ulp), in fixed notation with at least one decimal, or as 1.5e-05 below 1e-4. */
URWIRE__PRIVATE void i32r_scaled(urwire__text *o, int32_t raw, unsigned decimals)
{
    char digits[21], text[48];
    uint64_t u = raw < 0 ? (uint64_t)(-(int64_t)raw) : (uint64_t)raw;
    size_t n, sig, at = 0, i;
    long exponent;
    if (raw == 0) {
        urwire__str(o, "0.0");
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
            text[at++] = (char)(i < n ? digits[i] : '0');
    }
    urwire__bytes(o, text, at);
}

URWIRE__PRIVATE size_t i32r_fault(uint64_t offset, size_t left, size_t size, bool from_robot, char *out,
                                size_t cap)
{
    urwire__text o;
    o.out = out;
    o.cap = cap;
    o.n = 0;
    urwire__str(&o, "{\"type\": \"error\", \"offset\": ");
    i32r_int(&o, (int64_t)offset);
    urwire__str(&o, ", \"error\": \"");
    i32r_int(&o, (int64_t)left);
    if (size == 0) {
        urwire__str(&o, from_robot ? " bytes from the robot, where none are specified\"}"
                                 : " bytes to the robot, where none are specified\"}");
    } else {
        urwire__str(&o, " bytes left, short of a ");
        i32r_int(&o, (int64_t)size);
        urwire__str(&o, "-byte record\"}");
    }
    return urwire__end(&o);
}
