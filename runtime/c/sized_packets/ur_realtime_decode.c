/* <standalone> */
#include "ur_realtime_runtime_spec.h"
#include "../common/loads.h"
/* </standalone> */
/* Framing and decoding of one real-time packet: the size field checked, the layout chosen by the
 * spec's same_size rule over the generated forms table, then the layout's generated decoder. */

const char *ur_realtime_error_name(ur_realtime_error e)
{
    switch (e) {
    case UR_REALTIME_OK: return "ok";
    case UR_REALTIME_E_SHORT: return "short";
    case UR_REALTIME_E_SIZE_BELOW: return "size below the smallest packet";
    case UR_REALTIME_E_SIZE_ABOVE: return "size above the largest packet";
    case UR_REALTIME_E_UNKNOWN_SIZE: return "size matches no layout";
    }
    return "unknown error";
}

uint32_t ur_realtime_version(unsigned major, unsigned minor, unsigned bugfix)
{
    if (bugfix > 999u)
        bugfix = 999u;
    return ((uint32_t)major * 1000u + (uint32_t)minor) * 1000u + (uint32_t)bugfix;
}

ur_realtime_error ur_realtime_frame(const uint8_t *buf, size_t len, int32_t *size)
{
    int32_t declared;
    if (len < UR_REALTIME_SIZE_FIELD_BYTES)
        return UR_REALTIME_E_SHORT;
    declared = urwire__i32(buf);
    *size = declared;
    if (declared < UR_REALTIME_MIN_MESSAGE_SIZE)
        return UR_REALTIME_E_SIZE_BELOW;
    if (declared > UR_REALTIME_MAX_MESSAGE_SIZE)
        return UR_REALTIME_E_SIZE_ABOVE;
    return UR_REALTIME_OK;
}

/* The same_size rule: the first form of this size whose versions hold `version`, else the last
 * (the newest); -1 when no layout has the size. Forms are in size order, then the spec's. */
static int ur_realtime__form_of(int32_t size, uint32_t version)
{
    int i, last = -1;
    for (i = 0; i < UR_REALTIME__FORM_COUNT; i++) {
        const ur_realtime__form *f = &ur_realtime__forms[i];
        if (f->size != size)
            continue;
        if (version != 0 && f->low <= version && version <= f->high)
            return i;
        last = i;
    }
    return last;
}

ur_realtime_error ur_realtime_decode(const uint8_t *buf, size_t len, uint32_t version, ur_realtime_packet *out)
{
    int32_t size = 0;
    int form;
    ur_realtime_error e = ur_realtime_frame(buf, len, &size);
    out->message_size = size;
    out->layout = UR_REALTIME_UNKNOWN;
    out->form = -1;
    out->raw = NULL;
    out->raw_length = 0;
    if (e != UR_REALTIME_OK)
        return e;
    if ((size_t)size > len)
        return UR_REALTIME_E_SHORT;
    form = ur_realtime__form_of(size, version);
    if (form < 0) {
        out->raw = buf + UR_REALTIME_SIZE_FIELD_BYTES;
        out->raw_length = (size_t)size - UR_REALTIME_SIZE_FIELD_BYTES;
        return UR_REALTIME_E_UNKNOWN_SIZE;
    }
    out->form = form;
    out->layout = ur_realtime__forms[form].layout;
    ur_realtime__decoders[out->layout](buf, out);
    return UR_REALTIME_OK;
}

const char *ur_realtime_layout_name(ur_realtime_layout layout)
{
    return layout >= 0 && layout < UR_REALTIME_LAYOUT_COUNT ? ur_realtime__layouts[layout].name : "unknown";
}

size_t ur_realtime_layout_fields(ur_realtime_layout layout, const ur_realtime_slot **slots)
{
    if (layout < 0 || layout >= UR_REALTIME_LAYOUT_COUNT) {
        *slots = NULL;
        return 0;
    }
    *slots = ur_realtime__layouts[layout].slots;
    return ur_realtime__layouts[layout].count;
}

const ur_realtime_field_info *ur_realtime_field_info_of(ur_realtime_field field)
{
    return (unsigned)field < UR_REALTIME_FIELD_COUNT ? &ur_realtime__fields[field] : NULL;
}

bool ur_realtime_has(const ur_realtime_packet *p, ur_realtime_field field)
{
    const ur_realtime_slot *slots;
    size_t i, n = ur_realtime_layout_fields(p->layout, &slots);
    for (i = 0; i < n; i++)
        if (slots[i].field == field)
            return true;
    return false;
}

const double *ur_realtime_values(const ur_realtime_packet *p, ur_realtime_field field)
{
    if ((unsigned)field >= UR_REALTIME_FIELD_COUNT)
        return NULL;
    return (const double *)(const void *)((const unsigned char *)p + ur_realtime__fields[field].member);
}

const char *ur_realtime_enum_name(const ur_realtime_packet *p, ur_realtime_field field, double value)
{
    const ur_realtime__names *table;
    size_t i;
    int which;
    if (p->form < 0 || (unsigned)field >= UR_REALTIME_FIELD_COUNT)
        return NULL;
    which = ur_realtime__fields[field].enum_id;
    if (which < 0)
        return NULL;
    table = &ur_realtime__forms[p->form].names[which];
    for (i = 0; i < table->count; i++)
        if ((double)table->entries[i].value == value)
            return table->entries[i].name;
    return NULL;
}
