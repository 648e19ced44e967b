/* <standalone> */
#include "runtime_support.h"
/* </standalone> */
/* ---- global-variable values --------------------------------------------------------------- */
/* The value types of each software version are the generated urwire__value_tables, each for
 * the versions of its urwire__value_ranges. String
 * lengths and LIST/MATRIX counts are int16 (the generator refuses any other). */

/* The value types of a software version: the first table whose range holds it, else the newest. */
URWIRE__PRIVATE const urwire__value_table *urwire__values_of(urwire_sw_version v)
{
    return &urwire__value_tables[urwire__table_index(v, urwire__value_ranges, URWIRE__COUNT(urwire__value_ranges))];
}

URWIRE__PRIVATE const urwire__value_entry *urwire__value_entry_of(const urwire__value_table *t, uint8_t code)
{
    size_t k;
    for (k = 0; k < t->count; k++)
        if (t->entries[k].code == code)
            return &t->entries[k];
    return NULL;
}

/* Items that cannot fit in the bytes from pos (each takes at least t->min_size) are refused
 * before any is read; at is the offset of their count. */
static bool urwire__count_fits(const urwire__value_table *t, uint64_t items, size_t at, size_t pos, size_t end,
                               urwire_error *err)
{
    if (items * t->min_size > end - pos)
        return urwire__fail(err, URWIRE_E_TOO_MANY_ITEMS, at, "", (int64_t)items, (int64_t)(end - pos));
    return true;
}

/* A value whose items are being checked, LIST or MATRIX: its rows and columns (int16 counts:
 * at most 32767 * 32767 items), how many items are done. 8 bytes: the stack holds nine. */
typedef struct urwire__open_value {
    uint32_t done;
    uint16_t rows;
    uint16_t cols;                  /* a MATRIX's columns (its items go row by row), else 0 */
} urwire__open_value;

URWIRE__INLINE uint32_t urwire__items_of(const urwire__open_value *v)
{
    return v->cols ? (uint32_t)v->rows * v->cols : v->rows;
}

/* One value at *at, `depth` deep: its type byte and data, and of a LIST or MATRIX its counts
 * (into *open, done 0), checked against the bytes left, but not its items. Into *out as well
 * when it is not NULL (out->items: where the items start, and their count).
 * Error paths are relative ("", ".type") and prefixed by the callers. */
URWIRE__INLINE bool urwire__read_head(const uint8_t *msg, size_t *at, size_t end, const urwire_sw_version *version,
                                      const urwire__value_table *t, size_t depth, urwire__open_value *open,
                                      urwire_value *out, urwire_error *err)
{
    size_t pos = *at, k;
    const urwire__value_entry *e;
    int16_t rows = 0, cols = 0;
    urwire_bytes text;
    /* false said outright, not as the error setters' result: a file analysed on its own (the
     * runtime's standalone build) cannot see that they return false, and out is unset here */
    if (pos >= end) {
        urwire__short(err, URWIRE__NAME(".type"), pos, 1, end);
        return false;
    }
    if (depth > URWIRE_MAX_VALUE_DEPTH) {
        urwire__fail(err, URWIRE_E_TOO_DEEP, pos, "", URWIRE_MAX_VALUE_DEPTH, 0);
        return false;
    }
    /* *open (within open[] now that depth is) set before the returns below, for the same
     * reason */
    open->done = 0;
    open->rows = 0;
    open->cols = 0;
    e = urwire__value_entry_of(t, msg[pos]);
    if (e == NULL) {
        urwire__fail(err, URWIRE_E_VALUE_TYPE, pos, URWIRE__NAME(".type"), msg[pos], 0);
        return false;
    }
    if (out != NULL) {
        out->code = e->code;
        out->kind = e->kind;
        out->type_name = e->name;
        urwire__init_seq(&out->items, msg, pos + 1, version, -1);
    }
    pos++;
    switch (e->layout) {
    case URWIRE__LAYOUT_EMPTY:
        break;
    case URWIRE__LAYOUT_SCALAR:
        if (end - pos < (e->item == URWIRE__ITEM_BOOL ? 1u : 4u))
            return urwire__short(err, "", pos, e->item == URWIRE__ITEM_BOOL ? 1u : 4u, end);
        if (out == NULL)
            pos += e->item == URWIRE__ITEM_BOOL ? 1u : 4u;
        else if (e->item == URWIRE__ITEM_BOOL)
            out->as.boolean = msg[pos++];
        else if (e->item == URWIRE__ITEM_I32)
            out->as.integer = urwire__i32(msg + pos), pos += 4;
        else
            out->as.number = urwire__f32(msg + pos), pos += 4;
        break;
    case URWIRE__LAYOUT_ARRAY:
        if (end - pos < (size_t)e->count * 4u)
            return urwire__short(err, "", pos, (size_t)e->count * 4u, end);
        for (k = 0; out != NULL && k < e->count; k++)
            out->as.pose[k] = urwire__f32(msg + pos + 4 * k);
        pos += (size_t)e->count * 4u;
        break;
    case URWIRE__LAYOUT_STRING:
        if (!urwire__read_prefixed(msg, &pos, end, 2, true, "", &text, err))
            return false;
        if (out != NULL)
            out->as.text = text;
        break;
    case URWIRE__LAYOUT_LIST:
        if (end - pos < 2)
            return urwire__short(err, "", pos, 2, end);
        rows = urwire__i16(msg + pos);
        if (rows < 0)
            return urwire__fail(err, URWIRE_E_NEGATIVE_LENGTH, pos, "", rows, 0);
        if (!urwire__count_fits(t, (uint64_t)rows, pos, pos + 2, end, err))
            return false;
        pos += 2;
        break;
    case URWIRE__LAYOUT_MATRIX:
        if (end - pos < 4)
            return urwire__short(err, "", pos, 4, end);
        rows = urwire__i16(msg + pos);
        cols = urwire__i16(msg + pos + 2);
        if (rows < 0)
            return urwire__fail(err, URWIRE_E_NEGATIVE_LENGTH, pos, "", rows, 0);
        if (cols < 0)
            return urwire__fail(err, URWIRE_E_NEGATIVE_LENGTH, pos + 2, "", cols, 0);
        /* Rows of no items would take no bytes at all: any number of them fits in none. */
        if (rows > 0 && cols == 0)
            return urwire__fail(err, URWIRE_E_EMPTY_ROWS, pos, "", rows, 0);
        if (!urwire__count_fits(t, (uint64_t)rows * (uint64_t)cols, pos, pos + 4, end, err))
            return false;
        pos += 4;
        break;
    }
    open->rows = (uint16_t)rows;
    open->cols = (uint16_t)cols;
    if (out != NULL) {
        out->rows = rows;
        out->cols = cols;
        if (e->layout == URWIRE__LAYOUT_LIST || e->layout == URWIRE__LAYOUT_MATRIX) {
            out->items.pos = out->items.end = pos;
            out->items.count = urwire__items_of(open);
        }
    }
    *at = pos;
    return true;
}

/* One value at *at: its type byte and data, into *out unless it is NULL (the caller keeps
 * nothing of it). The items of a LIST or MATRIX are checked (and skipped) here, so that
 * iterating them later cannot fail, in a loop over a stack of the values still open (the
 * first is the value itself, as the one item of none), at most URWIRE_MAX_VALUE_DEPTH deep,
 * rather than by recursion, so that the stack this takes is known and small. Error paths are
 * relative ("", ".type", "[2][0]") and prefixed by the callers. */
static bool urwire__read_value(const uint8_t *msg, size_t *at, size_t end, const urwire_sw_version *version,
                               const urwire__value_table *t, urwire_value *out, urwire_error *err)
{
    urwire__open_value open[URWIRE_MAX_VALUE_DEPTH + 1];
    urwire__open_value *top;
    size_t pos = *at, n = 1, first = 0;
    open[0].done = 0;
    open[0].rows = 1;
    open[0].cols = 0;
    while (n) {
        top = &open[n - 1];
        if (top->done == urwire__items_of(top)) {
            if (--n)
                open[n - 1].done++;
            continue;
        }
        /* read_head refuses a value deeper than URWIRE_MAX_VALUE_DEPTH, and this one is n
         * deep: the value it opens goes to open[n], within open[] */
        if (!urwire__read_head(msg, &pos, end, version, t, n, &open[n], n == 1 ? out : NULL, err)) {
            for (; n > 1; n--) {  /* the item's path within each value open, innermost first */
                top = &open[n - 1];
                if (top->cols)
                    urwire__within2(err, "", top->done / top->cols, top->done % top->cols, true);
                else
                    urwire__within(err, "", top->done);
            }
            return false;
        }
        if (n == 1)
            first = pos;
        if (urwire__items_of(&open[n]))
            n++;
        else
            top->done++;
    }
    if (out != NULL && pos != first)  /* its items, read */
        out->items.end = pos;
    *at = pos;
    return true;
}

/* Top-level values: each a value and the terminator, until the end of the layout. */
URWIRE__PRIVATE bool urwire__read_values(const uint8_t *msg, size_t *at, size_t end, const urwire_sw_version *version,
                                         uint8_t terminator, const char *path, urwire_seq *out, urwire_error *err)
{
    const urwire__value_table *t = urwire__values_of(*version);
    size_t pos = *at;
    urwire__init_seq(out, msg, pos, version, terminator);
    while (pos < end) {
        if (!urwire__read_value(msg, &pos, end, version, t, NULL, err))
            return urwire__within(err, path, out->count);
        if (pos >= end) {
            urwire__short(err, "", pos, 1, end);
            return urwire__within(err, path, out->count);
        }
        if (msg[pos] != terminator) {
            urwire__fail(err, URWIRE_E_TERMINATOR, pos, "", msg[pos], terminator);
            return urwire__within(err, path, out->count);
        }
        pos++;
        out->count++;
    }
    out->end = pos;
    *at = pos;
    return true;
}

bool urwire_next_value(urwire_seq *seq, urwire_value *out)
{
    if (seq->count == 0)
        return false;
    if (!urwire__read_value(seq->msg, &seq->pos, seq->end, &seq->version, urwire__values_of(seq->version), out,
                            NULL)) {
        seq->count = 0;  /* not reached for a seq from a decoded message: it was checked whole */
        return false;
    }
    if (seq->terminator >= 0)
        seq->pos++;
    seq->count--;
    return true;
}
