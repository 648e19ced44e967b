/* <standalone> */
#include "runtime_support.h"
/* </standalone> */
/* ---- versions ----------------------------------------------------------------------------- */

const urwire_sw_version URWIRE_DEFAULT_VERSION = URWIRE_DEFAULT_VERSION_INIT;

/* Below, equal to or above major.minor.bugfix: -1, 0 or 1 (part by part, as the spec's
 * version tuples compare; an upper bound written "5.8" takes in every 5.8 bugfix release). */
URWIRE__PRIVATE int urwire__version_cmp(urwire_sw_version v, int major, int minor, int bugfix)
{
    if (v.major != major)
        return v.major < major ? -1 : 1;
    if (v.minor != minor)
        return v.minor < minor ? -1 : 1;
    return v.bugfix < bugfix ? -1 : v.bugfix > bugfix;
}

URWIRE__PRIVATE bool urwire__in_versions(urwire_sw_version v, const urwire__versions *range)
{
    return (!range->has_low || urwire__version_cmp(v, range->low.major, range->low.minor, range->low.bugfix) >= 0) &&
           (!range->has_high ||
            urwire__version_cmp(v, range->high.major, range->high.minor, range->high.bugfix) <= 0);
}

/* The first of count ranges that holds v, else the last: which table of a versioned enum (or
 * of value types) a version reads. */
URWIRE__PRIVATE size_t urwire__table_index(urwire_sw_version v, const urwire__versions *ranges, size_t count)
{
    size_t k;
    for (k = 0; k + 1 < count; k++)
        if (urwire__in_versions(v, &ranges[k]))
            return k;
    return count - 1;
}

bool urwire_parse_version(const char *text, urwire_sw_version *out)
{
    /* As Python's urwire.parse_version: "major.minor" or "major.minor.bugfix", blanks around it
     * (C's isspace), every part 1 to 6 digits (no real version has more; it keeps the ints small),
     * and no dot without a number after it. */
    urwire__version_text v;
    if (!urwire__read_version(text, text + strlen(text), true, true, &v) || v.dot_after || v.longest > 6)
        return false;
    out->major = (int)v.part[0];
    out->minor = (int)v.part[1];
    out->bugfix = (int)v.part[2];
    out->assumed = false;
    return true;
}
