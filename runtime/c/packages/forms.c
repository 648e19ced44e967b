/* <standalone> */
#include "runtime_support.h"
/* </standalone> */
/* ---- forms: the layout a type code is read in, by software version and by length ---------- */
/* The generated part cuts the version axis where any form of any type code starts or ends
 * (urwire__segment_bounds) and gives, for each type byte (the sub-package types, the subtypes
 * of each message), an urwire__form_table: the forms of each code and the form each segment
 * sends. The rule (docs/contract.md#choosing-a-layout), for every sub-package and subtype:
 * the version's form when it fits the body; else the one form whose exact size the body has,
 * read in that form's version; else the version's form, whose short or extra bytes are then
 * reported. */

/* The segment of the version axis that holds a version (its urwire__version_key): the last
 * bound at or below it. The default version's segment is tried first (a stream read before its
 * Version message, and most e-Series; the generator never makes it the last segment, so a
 * bound follows it), then the bounds from the newest, which streams run most; bound 0 stops
 * the search. */
URWIRE__PRIVATE size_t urwire__segment(uint64_t key)
{
    size_t k = URWIRE__COUNT(urwire__segment_bounds) - 1;
    if (key >= urwire__segment_bounds[URWIRE__DEFAULT_SEGMENT] &&
        key < urwire__segment_bounds[URWIRE__DEFAULT_SEGMENT + 1])
        return URWIRE__DEFAULT_SEGMENT;
    while (key < urwire__segment_bounds[k])
        k--;
    return k;
}

/* The form that the versions of a segment send for a code of t (which has a layout), or NULL.
 * In a segment that no form of the code is sent in (between series, or newer than the spec
 * knows), the form of the nearest version below, marked URWIRE__NEAREST: it is read as the
 * version it stands for. */
URWIRE__PRIVATE const urwire__form *urwire__mine(const urwire__form_table *t, size_t segment, size_t code,
                                                bool *nearest)
{
    uint8_t k = t->mine[segment * t->ncodes + code];
    *nearest = (k & URWIRE__NEAREST) != 0;
    k = (uint8_t)(k & ~URWIRE__NEAREST);
    return k ? &t->all[k - 1] : NULL;
}

/* The form of a body of `size` bytes, for a code of t (which has a layout) in a stream of
 * *version (in `segment`). A form chosen by its length alone sets *version to the version it
 * stands for and *by_length. */
URWIRE__PRIVATE const urwire__form *urwire__choose(const urwire__form_table *t, size_t code, size_t segment,
                                                  size_t size, urwire_sw_version *version, bool *by_length)
{
    const urwire__forms *fs = &t->codes[code];
    bool nearest;
    const urwire__form *mine = urwire__mine(t, segment, code, &nearest), *fit;
    uint8_t k;
    *by_length = false;
    if (nearest)
        *version = mine->rep;
    /* The one form of a code that has one (the generator saw that every version reads it) is
     * chosen whatever the size: no size can recognise another. */
    if (URWIRE__ONE_FORM_A_CODE || (mine != NULL && urwire__fits(mine, size)))
        return mine;
    /* The sizes the generator found in exactly one fixed-size form (an open-ended one fits too
     * much to be recognised by its length). */
    for (k = 0; k < fs->nby_length; k++)
        if (fs->by_length[k].size == size)
            break;
    if (k == fs->nby_length)
        return mine != NULL ? mine : &fs->forms[fs->count - 1];
    fit = &fs->forms[fs->by_length[k].form];
    version->major = fit->rep.major;
    version->minor = fit->rep.minor;
    version->bugfix = fit->rep.bugfix;  /* whether it was assumed stays as it was */
    *by_length = true;
    return fit;
}

/* A length prefix of size bytes, big-endian, signed or not. */
static int64_t urwire__prefix(const uint8_t *p, size_t size, bool is_signed)
{
    uint64_t raw = 0;
    size_t k;
    for (k = 0; k < size; k++)
        raw = raw << 8 | p[k];
    if (is_signed && size && (raw >> (size * 8 - 1)) & 1u)
        return (int64_t)(raw | ~(uint64_t)0 << (size * 8 - 1));
    return (int64_t)raw;
}

/* The major and minor numbers of a Version message (bugfix 0), read from its bytes before its
 * layout is chosen, so that it is read in the form of the version it carries; false when the
 * message is too short to hold them (as Python's peek_version). */
URWIRE__PRIVATE bool urwire__peek_version(const uint8_t *msg, size_t len, urwire_sw_version *out)
{
    uint64_t pos = URWIRE__VERSION_BODY;
    int64_t n;
    size_t k;
    for (k = 0; k < URWIRE__COUNT(urwire__version_skips); k++) {
        const urwire__version_skip *s = &urwire__version_skips[k];
        pos += s->fixed;
        if (pos + s->prefix > len)
            return false;
        n = urwire__prefix(msg + pos, s->prefix, s->is_signed);
        pos += s->prefix + (uint64_t)(n > 0 ? n : 0);
    }
    pos += URWIRE__VERSION_TAIL;
    if (pos + 2 > len)
        return false;
    out->major = msg[pos];
    out->minor = msg[pos + 1];
    out->bugfix = 0;
    return true;
}
