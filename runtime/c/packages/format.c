/* <standalone> */
#include "runtime_support.h"
/* </standalone> */
/* ---- number formatting -------------------------------------------------------------------- */

/* u / 10 by shifts and adds (Hacker's Delight, divu10), and its remainder: a 32-bit CPU has
 * no 64-bit divide, and the library's would cost a firmware 700 bytes of flash for an error's
 * digits. */
static uint64_t urwire__div10(uint64_t u, unsigned *rem)
{
    uint64_t q = (u >> 1) + (u >> 2), r;
    q += q >> 4;
    q += q >> 8;
    q += q >> 16;
    q += q >> 32;
    q >>= 3;
    r = u - ((q << 2) + q) * 2u;  /* 0..19: q is low by at most one */
    if (r > 9u) {
        q++;
        r -= 10u;
    }
    *rem = (unsigned)r;
    return q;
}

/* Digits of v into buf (at least 24 bytes, not NUL-terminated); returns their count. */
URWIRE__PRIVATE size_t urwire__digits(char *buf, int64_t v)
{
    size_t n = 0, lo, hi;
    unsigned digit;
    char c;
    uint64_t u = v < 0 ? (uint64_t)0 - (uint64_t)v : (uint64_t)v;
    if (v < 0)
        buf[n++] = '-';
    lo = n;
    do {  /* lowest digit first, then turned round in place */
        u = urwire__div10(u, &digit);
        buf[n++] = (char)('0' + digit);
    } while (u);
    for (hi = n - 1; lo < hi; lo++, hi--) {
        c = buf[lo];
        buf[lo] = buf[hi];
        buf[hi] = c;
    }
    return n;
}

URWIRE__PRIVATE void urwire__num(urwire__text *t, int64_t v)
{
    char buf[24];
    size_t n = urwire__digits(buf, v);
    buf[n] = '\0';
    urwire__str(t, buf);
}

/* The low byte of v as two lowercase hex digits. */
URWIRE__PRIVATE void urwire__hex2(urwire__text *t, int64_t v)
{
    static const char hex[] = "0123456789abcdef";
    char buf[3];
    buf[0] = hex[(v >> 4) & 15];
    buf[1] = hex[v & 15];
    buf[2] = '\0';
    urwire__str(t, buf);
}
