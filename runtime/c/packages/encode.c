/* <standalone> */
#include "runtime_support.h"
/* </standalone> */
/* ---- encoding messages and sub-packages --------------------------------------------------- */

size_t urwire_encode_package(const urwire_package *pkg, uint8_t *out, size_t cap, urwire_error *err)
{
    const urwire__package_kind *k = pkg->known ? urwire__package_kind_of(pkg->layout) : NULL;
    size_t pos = URWIRE_PACKAGE_HEADER_SIZE;
    urwire__ver ver = urwire__ver_of(pkg->version);
    bool ok;
    if (cap < pos) {
        urwire__no_space(err, 0, pos, cap);
        return 0;
    }
    if (!pkg->known || pkg->failed || k == NULL)
        ok = urwire__put_view(out, cap, &pos, pkg->raw, err);
    else
        ok = k->encode(&pkg->as, &ver, out, cap, &pos, err);
    if (!ok)
        return 0;
    URWIRE__PUT_PACKAGE_LENGTH(out, pos);
    out[URWIRE__PACKAGE_TYPE_AT] = pkg->type;
    return pos;
}

/* A robot state's sub-packages from its seq, then its unframed tail. */
static bool urwire__put_packages(const urwire_message *m, uint8_t *out, size_t cap, size_t *pos, urwire_error *err)
{
    urwire_seq seq = m->packages;
    urwire_package pkg;
    size_t n;
    while (urwire_next_package(&seq, &pkg)) {
        n = urwire_encode_package(&pkg, out + *pos, cap - *pos, err);
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
