/* <standalone> */
#include "runtime_support.h"
/* </standalone> */
/* ---- versions ----------------------------------------------------------------------------- */

const urwire_sw_version URWIRE_DEFAULT_VERSION = URWIRE_DEFAULT_VERSION_INIT;

/* Below, equal to or above major.minor: -1, 0 or 1. */
URWIRE__PRIVATE int urwire__version_cmp(urwire_sw_version v, int major, int minor)
{
    if (v.major != major)
        return v.major < major ? -1 : 1;
    return v.minor < minor ? -1 : v.minor > minor;
}

URWIRE__PRIVATE bool urwire__in_versions(urwire_sw_version v, const urwire__versions *range)
{
    return (!range->has_low || urwire__version_cmp(v, range->low.major, range->low.minor) >= 0) &&
           (!range->has_high || urwire__version_cmp(v, range->high.major, range->high.minor) <= 0);
}

static bool urwire__is_space(char c)
{
    return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}

bool urwire_parse_version(const char *text, urwire_sw_version *out)
{
    /* As Python's urwire.parse_version: at least "major.minor", every part digits. */
    long parts[2] = {0, 0};
    size_t len = strlen(text), start = 0, i, nparts = 0, digits = 0;
    while (start < len && urwire__is_space(text[start]))
        start++;
    while (len > start && urwire__is_space(text[len - 1]))
        len--;
    for (i = start; i <= len; i++) {
        if (i == len || text[i] == '.') {
            if (digits == 0)
                return false;
            nparts++;
            digits = 0;
        } else if (text[i] >= '0' && text[i] <= '9') {
            if (++digits > 6)
                return false;  /* no real version has such parts; keeps the ints small */
            if (nparts < 2)
                parts[nparts] = parts[nparts] * 10 + (text[i] - '0');
        } else {
            return false;
        }
    }
    if (nparts < 2)
        return false;
    out->major = (int)parts[0];
    out->minor = (int)parts[1];
    return true;
}
