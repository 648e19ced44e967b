/* <standalone> */
#include "runtime_support.h"
/* </standalone> */
/* ---- encoding messages and sub-packages --------------------------------------------------- */

/* A sub-package's header and body: its layout's encoder's (k), else its raw bytes. */
static size_t urwire__encode_layout(uint8_t type, const urwire__package_kind *k, const void *as,
                                    urwire_sw_version version, urwire_bytes raw, uint8_t *out, size_t cap,
                                    urwire_error *err)
{
    size_t pos = URWIRE_PACKAGE_HEADER_SIZE;
    urwire__ver ver = urwire__ver_of(version);
    bool ok;
    if (cap < pos) {
        urwire__no_space(err, 0, pos, cap);
        return 0;
    }
    if (k == NULL)
        ok = urwire__put_view(out, cap, &pos, raw, err);
    else
        ok = k->encode(as, &ver, out, cap, &pos, err);
    if (!ok)
        return 0;
    URWIRE__PUT_PACKAGE_LENGTH(out, pos);
    out[URWIRE__PACKAGE_TYPE_AT] = type;
    return pos;
}

size_t urwire_encode_package(const urwire_package *pkg, uint8_t *out, size_t cap, urwire_error *err)
{
    const urwire__package_kind *k = pkg->known && !pkg->failed ? urwire__package_kind_of(pkg->layout) : NULL;
    return urwire__encode_layout(pkg->type, k, &pkg->as, pkg->version, pkg->raw, out, cap, err);
}

/* A robot state's sub-packages from its seq, each decoded into its layout alone (not a whole
 * urwire_package), then its unframed tail. Out of line: its layout is on the stack only here. */
URWIRE__NOINLINE static bool urwire__put_packages(const urwire_message *m, uint8_t *out, size_t cap, size_t *pos,
                                                  urwire_error *err)
{
    urwire_seq seq = m->packages;
    double as[URWIRE__LAYOUT_DOUBLES];
    const urwire__form *f;
    const urwire__package_kind *k;
    urwire__ver use;
    size_t at, n;
    bool failed;
    while (urwire__next_package_layout(&seq, &at, &f, &use, as, &failed)) {
        k = f != NULL && !failed ? urwire__package_kind_of((urwire_package_layout)f->layout) : NULL;
        n = urwire__encode_layout(seq.msg[at + URWIRE__PACKAGE_TYPE_AT], k, as, use.version,
                                  urwire__view(seq.msg + at + URWIRE_PACKAGE_HEADER_SIZE,
                                               seq.pos - at - URWIRE_PACKAGE_HEADER_SIZE),
                                  out + *pos, cap - *pos, err);
        if (n == 0)
            return false;
        *pos += n;
    }
    return !m->failed || urwire__put_view(out, cap, pos, m->raw, err);
}

size_t urwire_encode_message(const urwire_message *m, uint8_t *out, size_t cap, urwire_error *err)
{
    const urwire__message_kind *k = urwire__message_kind_of(m->kind);
    const urwire__message_type *t = urwire__header_type(m);
    size_t pos = URWIRE_HEADER_SIZE;
    urwire__ver ver = urwire__ver_of(m->version);
    bool ok = true;
    if (cap < pos) {
        urwire__no_space(err, 0, pos, cap);
        return 0;
    }
    if (t != NULL) {
        if (cap - pos < t->body - URWIRE_HEADER_SIZE) {
            urwire__no_space(err, pos, t->body - URWIRE_HEADER_SIZE, cap);
            return 0;
        }
        if (urwire__header_of(t)->put != NULL)
            urwire__header_of(t)->put(m, out);
        pos = t->body;
    }
    if (k == NULL)
        ok = true;  /* not a kind: the bare message header */
    else if (k->type != NULL && k->type->packages)
        ok = urwire__put_packages(m, out, cap, &pos, err);
    else if (m->failed || k->encode == NULL)
        ok = urwire__put_view(out, cap, &pos, m->raw, err);
    else
        ok = k->encode(&m->as, &ver, out, cap, &pos, err);
    if (!ok)
        return 0;
    URWIRE__PUT_LENGTH(out, pos);
    out[URWIRE__TYPE_AT] = m->message_type;
    return pos;
}
