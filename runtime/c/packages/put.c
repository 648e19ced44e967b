/* <standalone> */
#include "runtime_support.h"
/* </standalone> */
/* ---- encoding helpers: bytes and length-prefixed text ------------------------------------- */

/* Bytes as they are, at *pos. */
URWIRE__PRIVATE bool urwire__put_view(uint8_t *out, size_t cap, size_t *pos, urwire_bytes b, urwire_error *err)
{
    if (cap - *pos < b.len)
        return urwire__no_space(err, *pos, b.len, cap);
    if (b.len)
        memcpy(out + *pos, b.ptr, b.len);
    *pos += b.len;
    return true;
}

/* A length prefix of size bytes (big-endian), then the bytes; max is the prefix's largest length. */
URWIRE__PRIVATE bool urwire__put_prefixed(uint8_t *out, size_t cap, size_t *pos, size_t size, uint64_t max,
                                          urwire_bytes b, const char *path, urwire_error *err)
{
    size_t k;
    if ((uint64_t)b.len > max)
        return urwire__fail(err, URWIRE_E_TOO_LONG, *pos, path, (int64_t)b.len, (int64_t)max);
    if (cap - *pos < size)
        return urwire__no_space(err, *pos, size, cap);
    for (k = 0; k < size; k++)
        out[*pos + k] = (uint8_t)((uint64_t)b.len >> (8 * (size - 1 - k)));
    *pos += size;
    return urwire__put_view(out, cap, pos, b, err);
}
