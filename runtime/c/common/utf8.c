/* <standalone> */
#include <stddef.h>
#include <stdint.h>
#include "macros.h"
#include "utf8.h"
/* </standalone> */
/* ---- UTF-8 read as Python reads it, each invalid part replaced ---------------------------- */

/* The one UTF-8 decoder of the C runtime: the canonical JSON of text (runtime/c/json/json.c, and
 * each text-line interface's JSON) writes what Python's bytes.decode("utf-8", "replace") gives.
 * Length of the valid sequence at p, of the n bytes there are (n >= 1): 1 to 4; or 0, with *bad
 * set to the length of the maximal subpart that one U+FFFD replaces (1 to 3). Valid is what
 * Table 3-7 of the Unicode Standard allows: no overlong forms, no surrogates, nothing past
 * U+10FFFF; a subpart is the longest start of a valid sequence, cut by a byte or by the end. */
URWIRE__PRIVATE size_t urwire__utf8_sequence(const uint8_t *p, size_t n, size_t *bad)
{
    uint8_t b = p[0], lo = 0x80, hi = 0xBF;
    size_t need, k;
    if (b < 0x80)
        return 1;
    if (b >= 0xC2 && b <= 0xDF) {
        need = 1;
    } else if (b >= 0xE0 && b <= 0xEF) {
        need = 2;
        lo = b == 0xE0 ? 0xA0 : 0x80;   /* E0 80..9F would be overlong */
        hi = b == 0xED ? 0x9F : 0xBF;   /* ED A0..BF would be a surrogate */
    } else if (b >= 0xF0 && b <= 0xF4) {
        need = 3;
        lo = b == 0xF0 ? 0x90 : 0x80;   /* F0 80..8F would be overlong */
        hi = b == 0xF4 ? 0x8F : 0xBF;   /* F4 90..BF would be past U+10FFFF */
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
