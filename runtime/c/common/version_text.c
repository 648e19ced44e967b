/* <standalone> */
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include "macros.h"
#include "version_text.h"
/* </standalone> */
/* ---- a software version's text ---------------------------------------------------------- */
/* The one reader of a version's text in C: the C library's urwire_parse_version, the version a
 * dashboard reply tells ("URSoftware 5.11.1.108318 (...)"), and every Wireshark dissector's
 * version preference ("5.9", " 3.15.2 "). Each caller's rules that differ are its parameters and
 * its checks of what was read (how many digits, what follows). */

/* Blanks as Wireshark's g_ascii_isspace sees them; vt_blank: a vertical tab too, as C's isspace
 * and Lua's %s see it. */
static bool urwire__version_blank(char c, bool vt_blank)
{
    return c == ' ' || c == '\t' || c == '\n' || c == '\f' || c == '\r' || (vt_blank && c == '\v');
}

static bool urwire__version_digit(const char *at, const char *end)
{
    return at < end && *at >= '0' && *at <= '9';
}

/* major.minor or major.minor.bugfix in [text, end), after blanks. whole: nothing but blanks may
 * follow (a dot with no number after it too); else anything may, and a third number needs its
 * digit right after the dot. False for text that is not a version. */
URWIRE__PRIVATE bool urwire__read_version(const char *text, const char *end, bool whole, bool vt_blank,
                                          urwire__version_text *out)
{
    const char *p = text;
    size_t i;
    out->parts = 0;
    out->longest = 0;
    out->dot_after = false;
    while (p < end && urwire__version_blank(*p, vt_blank))
        p++;
    for (i = 0; i < 3; i++) {
        size_t digits = 0;
        out->part[i] = 0;
        if (i == 1 && (p == end || *p++ != '.'))
            return false;
        if (i == 2 && !(p < end && *p == '.' && urwire__version_digit(p + 1, end))) {
            if (whole && p < end && *p == '.') {
                out->dot_after = true;
                p++;
            }
            break;
        }
        if (i == 2)
            p++;
        if (!urwire__version_digit(p, end))
            return false;
        for (; urwire__version_digit(p, end); p++, digits++) {
            if (out->part[i] < URWIRE__VERSION_PART_BIG)
                out->part[i] = out->part[i] * 10u + (uint64_t)(*p - '0');
        }
        out->parts = i + 1;
        out->longest = digits > out->longest ? digits : out->longest;
    }
    if (whole) {
        while (p < end && urwire__version_blank(*p, vt_blank))
            p++;
        if (p != end)
            return false;
    }
    out->end = p;
    return true;
}
