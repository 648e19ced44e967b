/* <standalone> */
#include "runtime_support.h"
/* </standalone> */
/* ---- number formatting -------------------------------------------------------------------- */

/* Digits of v into buf (at least 24 bytes, not NUL-terminated); returns their count. */
URWIRE__PRIVATE size_t urwire__digits(char *buf, int64_t v)
{
    char tmp[24];
    size_t n = 0, k;
    uint64_t u = v < 0 ? (uint64_t)0 - (uint64_t)v : (uint64_t)v;
    do {
        tmp[n++] = (char)('0' + (int)(u % 10u));
        u /= 10u;
    } while (u);
    k = 0;
    if (v < 0)
        buf[k++] = '-';
    while (n)
        buf[k++] = tmp[--n];
    return k;
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
