/* <standalone> */
#include "runtime_support.h"
/* </standalone> */
/* ---- visiting ----------------------------------------------------------------------------- */

static void urwire__name(const urwire_visitor *v, const char *key, const char *name)
{
    v->on_text(v->ctx, key, urwire__view((const uint8_t *)name, strlen(name)));
}

#define URWIRE__ERROR_TEXT (URWIRE_PATH_MAX + 128)  /* an error's text, cut to this */

/* The error's text, written into text[0..URWIRE__ERROR_TEXT), given to the visitor. */
static void urwire__visit_error_in(const urwire_error *e, char *text, const urwire_visitor *v)
{
    size_t n = urwire_error_text(e, text, URWIRE__ERROR_TEXT);
    if (n >= URWIRE__ERROR_TEXT)
        n = URWIRE__ERROR_TEXT - 1;  /* cut */
    v->on_text(v->ctx, "error", urwire__view((const uint8_t *)text, n));
}

/* Out of line: its buffer is on the stack only while it runs. */
URWIRE__NOINLINE static void urwire__visit_error(const urwire_error *e, const urwire_visitor *v)
{
    char text[URWIRE__ERROR_TEXT];
    urwire__visit_error_in(e, text, v);
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

/* A value's object up to its items: its type and, but for a LIST or MATRIX, its value, closed.
 * True when it is a LIST or MATRIX, its "value" array open for its items. */
static bool urwire__visit_head(const urwire_value *val, const char *key, const urwire_visitor *v)
{
    const urwire__value_entry *e = urwire__value_entry_of(urwire__values_of(val->items.version), val->code);
    size_t k;
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
    case URWIRE__LAYOUT_MATRIX:
        v->begin_array(v->ctx, "value");
        return true;
    }
    v->end_object(v->ctx);
    return false;
}

/* A LIST or MATRIX whose items are being visited: where its items seq stands, and in a MATRIX
 * (cols > 0) the row and column of the next item, each row an array of its own. */
typedef struct urwire__open_items {
    size_t pos;
    size_t end;
    size_t count;
    int16_t rows;
    int16_t cols;
    int16_t r;
    int16_t c;
    bool row_open;
} urwire__open_items;

/* One value, its items visited in a loop over a stack of the values still open (at most
 * URWIRE_MAX_VALUE_DEPTH deep, as decoding checked) rather than by recursion, so that the
 * stack this takes is known. */
static void urwire__visit_value(const urwire_value *val, const char *key, const urwire_visitor *v)
{
    urwire__open_items open[URWIRE_MAX_VALUE_DEPTH];
    urwire__open_items *top;
    urwire_seq items = val->items;  /* every level's: the same message, version and terminator */
    urwire_value item;
    const urwire_value *next = val;
    size_t n = 0;
    bool more;
    for (;;) {
        if (next != NULL && urwire__visit_head(next, key, v)) {
            if (n == URWIRE_MAX_VALUE_DEPTH) {  /* not reached for a decoded value */
                v->end_array(v->ctx);
                v->end_object(v->ctx);
            } else {
                top = &open[n++];
                top->pos = next->items.pos;
                top->end = next->items.end;
                top->count = next->items.count;
                top->rows = next->rows;
                top->cols = 0;                      /* a LIST's items are one run */
                if (next->kind == URWIRE_VALUE_MATRIX)
                    top->cols = next->cols;
                top->r = 0;
                top->c = 0;
                top->row_open = false;
            }
        }
        next = NULL;
        key = NULL;
        if (n == 0)
            return;
        top = &open[n - 1];
        items.pos = top->pos;
        items.end = top->end;
        items.count = top->count;
        if (top->cols == 0) {  /* a LIST */
            more = urwire_next_value(&items, &item);
        } else if (top->r >= top->rows) {
            more = false;
        } else {
            if (!top->row_open) {
                v->begin_array(v->ctx, NULL);
                top->row_open = true;
            }
            more = top->c < top->cols && urwire_next_value(&items, &item);
            if (!more) {  /* the row ends; the next one starts */
                v->end_array(v->ctx);
                top->row_open = false;
                top->r++;
                top->c = 0;
                continue;
            }
            top->c++;
        }
        if (more) {
            top->pos = items.pos;
            top->end = items.end;
            top->count = items.count;
            next = &item;
            continue;
        }
        v->end_array(v->ctx);   /* the "value" array */
        v->end_object(v->ctx);
        n--;
    }
}

URWIRE__PRIVATE void urwire__visit_values(const urwire_seq *values, const char *key, const urwire_visitor *v)
{
    urwire_seq seq = *values;
    urwire_value value = {0};
    v->begin_array(v->ctx, key);
    while (urwire_next_value(&seq, &value))
        urwire__visit_value(&value, NULL, v);
    v->end_array(v->ctx);
}

static void urwire__visit_package(urwire_package *pkg, const urwire_visitor *v)
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
        if (pkg->failed && sizeof pkg->as >= URWIRE__ERROR_TEXT) {
            /* a failed package's layout holds nothing: its storage takes the error's text, which
             * is then not on the stack beside the package (where the layouts are that large) */
            urwire__visit_error_in(&pkg->error, (char *)&pkg->as, v);
            v->on_hex(v->ctx, "raw", pkg->raw);
        } else if (pkg->failed) {
            urwire__visit_failed(&pkg->error, pkg->raw, v);
        } else {
            k->visit(&pkg->as, &ver, v);
        }
    }
    v->end_object(v->ctx);
}

/* A robot state's sub-packages in wire order; out of line, so that its package is not on the
 * stack beside the error of what could not be framed. */
URWIRE__NOINLINE static void urwire__visit_packages(const urwire_message *m, const urwire_visitor *v)
{
    urwire_seq seq = m->packages;
    urwire_package pkg;
    v->begin_array(v->ctx, "packages");
    while (urwire_next_package(&seq, &pkg))
        urwire__visit_package(&pkg, v);
    v->end_array(v->ctx);
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
            if (m->failed)  /* what could not be framed */
                urwire__visit_failed(&m->error, m->raw, v);
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
