/* <standalone> */
#include "runtime_support.h"
/* </standalone> */
/* ---- visiting ----------------------------------------------------------------------------- */

static void urwire__name(const urwire_visitor *v, const char *key, const char *name)
{
    v->on_text(v->ctx, key, urwire__view((const uint8_t *)name, strlen(name)));
}

static void urwire__visit_error(const urwire_error *e, const urwire_visitor *v)
{
    char text[URWIRE_PATH_MAX + 128];
    size_t n = urwire_error_text(e, text, sizeof text);
    v->on_text(v->ctx, "error", urwire__view((const uint8_t *)text, n < sizeof text ? n : sizeof text - 1));
}

/* A part that could not be read: why, and its bytes. */
static void urwire__visit_failed(const urwire_error *e, urwire_bytes raw, const urwire_visitor *v)
{
    urwire__visit_error(e, v);
    v->on_hex(v->ctx, "raw", raw);
}

URWIRE__PRIVATE void urwire__visit_texts(const urwire_seq *names, const char *key, const urwire_visitor *v)
{
    urwire_seq seq = *names;
    urwire_bytes text;
    v->begin_array(v->ctx, key);
    while (urwire_next_text(&seq, &text))
        v->on_text(v->ctx, NULL, text);
    v->end_array(v->ctx);
}

static void urwire__visit_value(const urwire_value *val, const char *key, const urwire_visitor *v)
{
    const urwire__value_entry *e = urwire__value_entry_of(urwire__values_of(val->items.version), val->code);
    urwire_seq items = val->items;
    urwire_value item;
    size_t k, r, c;
    v->begin_object(v->ctx, key);
    urwire__name(v, "type", val->type_name);
    switch (e ? e->layout : URWIRE__LAYOUT_EMPTY) {
    case URWIRE__LAYOUT_EMPTY:
        v->on_null(v->ctx, "value");
        break;
    case URWIRE__LAYOUT_SCALAR:
        if (e->item == URWIRE__ITEM_BOOL)
            v->on_bool(v->ctx, "value", val->as.boolean != 0);
        else if (e->item == URWIRE__ITEM_I32)
            v->on_int(v->ctx, "value", val->as.integer);
        else
            v->on_f32(v->ctx, "value", val->as.number);
        break;
    case URWIRE__LAYOUT_ARRAY:
        v->begin_array(v->ctx, "value");
        for (k = 0; k < e->count; k++)
            v->on_f32(v->ctx, NULL, val->as.pose[k]);
        v->end_array(v->ctx);
        break;
    case URWIRE__LAYOUT_STRING:
        v->on_text(v->ctx, "value", val->as.text);
        break;
    case URWIRE__LAYOUT_LIST:
        v->begin_array(v->ctx, "value");
        while (urwire_next_value(&items, &item))
            urwire__visit_value(&item, NULL, v);
        v->end_array(v->ctx);
        break;
    case URWIRE__LAYOUT_MATRIX:
        v->begin_array(v->ctx, "value");
        for (r = 0; r < (size_t)val->rows; r++) {
            v->begin_array(v->ctx, NULL);
            for (c = 0; c < (size_t)val->cols && urwire_next_value(&items, &item); c++)
                urwire__visit_value(&item, NULL, v);
            v->end_array(v->ctx);
        }
        v->end_array(v->ctx);
        break;
    }
    v->end_object(v->ctx);
}

URWIRE__PRIVATE void urwire__visit_values(const urwire_seq *values, const char *key, const urwire_visitor *v)
{
    urwire_seq seq = *values;
    urwire_value value;
    v->begin_array(v->ctx, key);
    while (urwire_next_value(&seq, &value))
        urwire__visit_value(&value, NULL, v);
    v->end_array(v->ctx);
}

static void urwire__visit_package(const urwire_package *pkg, const urwire_visitor *v)
{
    const urwire__package_kind *k = pkg->known ? urwire__package_kind_of(pkg->layout) : NULL;
    urwire__ver ver = urwire__ver_of(pkg->version);
    if (v->package != NULL && v->package(v->ctx, pkg))
        return;
    v->begin_object(v->ctx, NULL);
    if (k == NULL) {
        urwire__name(v, "type", "unknown");
        v->on_uint(v->ctx, "package_type", pkg->type);
        v->on_hex(v->ctx, "raw", pkg->raw);
    } else {
        urwire__name(v, "type", k->name);
        if (pkg->failed)
            urwire__visit_failed(&pkg->error, pkg->raw, v);
        else
            k->visit(&pkg->as, &ver, v);
    }
    v->end_object(v->ctx);
}

/* A robot state's sub-packages in wire order, then what could not be framed. */
static void urwire__visit_packages(const urwire_message *m, const urwire_visitor *v)
{
    urwire_seq seq = m->packages;
    urwire_package pkg;
    v->begin_array(v->ctx, "packages");
    while (urwire_next_package(&seq, &pkg))
        urwire__visit_package(&pkg, v);
    v->end_array(v->ctx);
    if (m->failed)
        urwire__visit_failed(&m->error, m->raw, v);
}

void urwire_visit_message(const urwire_message *m, const urwire_visitor *v)
{
    const urwire__message_kind *k = urwire__message_kind_of(m->kind);
    const urwire__message_type *t = urwire__header_type(m);
    urwire__ver ver = urwire__ver_of(m->version);
    v->begin_object(v->ctx, NULL);
    if (m->kind == URWIRE_KIND_UNKNOWN_MESSAGE || m->kind == URWIRE_KIND_UNKNOWN_SUBTYPE) {
        urwire__name(v, "type", "unknown");
        v->on_uint(v->ctx, "message_type", m->message_type);
        if (t != NULL && urwire__header_of(t)->visit != NULL)
            urwire__header_of(t)->visit(m, true, v);  /* an unknown subtype: its code, then the header */
        else if (m->failed && m->kind == URWIRE_KIND_UNKNOWN_MESSAGE)
            urwire__visit_error(&m->error, v);
        v->on_hex(v->ctx, "raw", m->raw);
    } else if (k != NULL) {
        urwire__name(v, "type", k->name);
        if (k->type->packages) {
            urwire__visit_packages(m, v);
        } else {
            if (urwire__header_of(t)->visit != NULL)
                urwire__header_of(t)->visit(m, false, v);
            if (m->failed)
                urwire__visit_failed(&m->error, m->raw, v);
            else
                k->visit(&m->as, &ver, v);
        }
    }
    v->end_object(v->ctx);
}

void urwire_visit_fault(const urwire_error *fault, const urwire_visitor *v)
{
    v->begin_object(v->ctx, NULL);
    urwire__name(v, "type", "error");
    v->on_uint(v->ctx, "offset", fault->offset);
    urwire__visit_error(fault, v);
    v->end_object(v->ctx);
}
