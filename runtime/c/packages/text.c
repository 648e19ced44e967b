/* <standalone> */
#include "runtime_support.h"
/* </standalone> */
/* ---- text: length-prefixed strings and terminated names ----------------------------------- */

/* A length prefix of size bytes (big-endian, signed or not), then that many bytes. */
URWIRE__PRIVATE bool urwire__read_prefixed(const uint8_t *msg, size_t *at, size_t end, size_t size, bool is_signed,
                                           const char *path, urwire_bytes *out, urwire_error *err)
{
    size_t pos = *at;
    uint64_t raw;
    int64_t n;
    if (end - pos < size)
        return urwire__short(err, path, pos, size, end);
    raw = urwire__uint(msg + pos, size);
    n = (int64_t)raw;
    /* size is a prefix's width, 1 to 8 bytes, at every call: the shifts stay below 64. */
    /* NOLINTNEXTLINE(clang-analyzer-core.UndefinedBinaryOperatorResult) */
    if (is_signed && (raw >> (size * 8 - 1)) & 1u)
        n = (int64_t)(raw | ~(uint64_t)0 << (size * 8 - 1));
    if (n < 0)
        return urwire__fail(err, URWIRE_E_NEGATIVE_LENGTH, pos, path, n, 0);
    pos += size;
    if ((uint64_t)n > end - pos)
        return urwire__short(err, path, pos, (size_t)n, end);
    *out = urwire__view(msg + pos, (size_t)n);
    *at = pos + (size_t)n;
    return true;
}

/* Names each ended by terminator; bytes after the last terminator are not a name (extra). */
URWIRE__PRIVATE void urwire__read_texts(const uint8_t *msg, size_t *at, size_t end, uint8_t terminator,
                                        urwire_seq *out)
{
    size_t pos = *at, k, last = end;
    urwire__init_seq(out, msg, pos, &URWIRE_DEFAULT_VERSION, terminator);
    for (k = end; k > pos; k--)
        if (msg[k - 1] == terminator) {
            last = k - 1;
            break;
        }
    if (last == end)
        return;
    for (k = pos; k <= last; k++)
        out->count += msg[k] == terminator;
    out->end = last + 1;
    *at = last + 1;
}

bool urwire_next_text(urwire_seq *seq, urwire_bytes *out)
{
    const uint8_t *start, *stop;
    if (seq->count == 0 || seq->pos >= seq->end)
        return false;
    start = seq->msg + seq->pos;
    stop = (const uint8_t *)memchr(start, seq->terminator, seq->end - seq->pos);
    if (stop == NULL)
        return false;
    *out = urwire__view(start, (size_t)(stop - start));
    seq->pos += (size_t)(stop - start) + 1;
    seq->count--;
    return true;
}
