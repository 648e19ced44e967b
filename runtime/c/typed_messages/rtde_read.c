/* ---- reading a message: big-endian loads, each after a bounds check ------------------------- */

typedef struct rtde__reader {
    const uint8_t *buf;
    size_t pos, end;
    const char *field;          /* the field that did not fit, and the bytes it needed */
    size_t need;
} rtde__reader;

static bool rtde__need(rtde__reader *r, size_t n, const char *field)
{
    if (r->end - r->pos < n) {
        r->field = field;
        r->need = n;
        return false;
    }
    return true;
}

static uint64_t rtde__take(rtde__reader *r, size_t n)
{
    uint64_t v = urwire__uint(r->buf + r->pos, n);
    r->pos += n;
    return v;
}

/* Two's complement of the low 32 bits, without implementation-defined conversions. */
static int32_t rtde__as_i32(uint64_t u)
{
    uint32_t v = (uint32_t)u;
    return v >= 0x80000000u ? -(int32_t)(0xffffffffu - v) - 1 : (int32_t)v;
}

static bool rtde__prefixed_text(rtde__reader *r, size_t prefix, rtde_text *out, const char *field)
{
    size_t n;
    if (!rtde__need(r, prefix, field))
        return false;
    n = (size_t)rtde__take(r, prefix);
    if (!rtde__need(r, n, field))
        return false;
    out->data = r->buf + r->pos;
    out->length = n;
    r->pos += n;
    return true;
}

static void rtde__rest(rtde__reader *r, rtde_text *out)
{
    out->data = r->buf + r->pos;
    out->length = r->end - r->pos;
    r->pos = r->end;
}

static bool rtde__values(rtde__reader *r, rtde_data *out);

static rtde_error rtde__end(rtde__reader *r)
{
    if (r->pos < r->end) {
        r->field = "extra";
        r->need = r->end - r->pos;
        return RTDE_EXTRA;
    }
    return RTDE_OK;
}
