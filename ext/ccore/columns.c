/* urwire._ccore.PrimaryColumns and PrimaryStream: the dataset's columns of the primary/secondary
 * interface, made in C (python/urwire/data/dataset_c.py and dataset_c_capture.py turn them into Arrow
 * tables; docs/tables.md).
 *
 * The C parser frames and decodes a raw stream (feed, close), or the streams of a capture's
 * connections, each framed by its PrimaryStream (feed_stream, close_stream: their records numbered
 * and dated by the caller); a visitor appends each record's values straight into the column
 * buffers of its kind, in the layout Python decided from the dataset's schema
 * (dataset_columns.dataset_schema): per kind, one column per field path ("joints/0/q_actual",
 * "dh_a/3", "timestamp") with its Arrow type, after the record's position and capture time.
 * A kind fills a batch of rows at a time; a full batch is handed over as bytes (validity bitmap,
 * values, offsets), ready for pyarrow.Array.from_buffers, with no Python object per value.
 *
 * Routing follows dataset.PartBuilder: a record with an error goes whole to `errors` and an
 * unknown message to `unknown`, each as its canonical JSON line (the C command's writer); a robot
 * state gives a `robot_state` row (its package count) and a row per sub-package, an unknown
 * sub-package going to `unknown`. A kind given without columns (one that holds JSON text, which
 * Python writes) has its messages handed back as bytes, to be decoded in Python. */
#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ccore_framer.h"
#include "ccore_segments.h"
#include "columns.h"
#include "json.h"
#include "urwire.h"

/* The column types, as dataset_c.py numbers them. */
enum { COL_INT64, COL_UINT64, COL_BOOL, COL_F32, COL_F64, COL_STRING, COL_BINARY, COL_TYPES };
static const size_t col_width[COL_TYPES] = {8, 8, 0, 4, 8, 0, 0};

/* A batch's text of a kind may reach this before its rows do: Arrow's string offsets are 32-bit. */
#define TEXT_FLUSH_BYTES ((size_t)64 << 20)
#define MAX_DEPTH 32
#define PATH_MAX_TEXT 512
#define LEAD_COLUMNS 2          /* every kind's first columns: the position and the capture time */

typedef struct {
    char *path;
    int type;
    Py_ssize_t cap;         /* rows the buffers hold */
    Py_ssize_t filled;      /* rows of the batch that have a value or a null here */
    Py_ssize_t nulls;
    uint8_t *data;          /* values; COL_BOOL: a bitmap */
    uint8_t *valid;         /* validity bitmap */
    int32_t *offsets;       /* COL_STRING, COL_BINARY: cap + 1 */
    char *text;             /* COL_STRING, COL_BINARY: the bytes */
    size_t text_len, text_cap;
} column;

/* A record's events, as the kind's last row gave them: while a row repeats them (same event,
 * same key pointer), each value's column is known without building its path. */
enum { EV_BEGIN_OBJECT = 1, EV_END_OBJECT, EV_BEGIN_ARRAY, EV_END_ARRAY, EV_VALUE };
typedef struct {
    unsigned char event;
    const char *key;
    int column;             /* -1: none (a container, or a path without a column) */
} trace_step;

typedef struct {
    char *name;
    int fallback;           /* no columns here: the kind's messages go back to Python */
    int ncolumns;
    column *columns;
    Py_ssize_t rows;
    size_t text_bytes;
    trace_step *trace;
    size_t trace_len, trace_cap;
} table;

typedef struct {
    const char *key;
    int index;              /* an array: items so far */
    int item;               /* an object or array inside an array: its index there */
    int array;
} frame;

/* A primary stream's framing state: one per connection of a capture (PrimaryStream), or the
 * raw stream's own. */
typedef struct {
    PyObject_HEAD
    urwire_framer framer;
    uint8_t *buffer;
    int finished;
} PrimaryStream;

typedef struct {
    PyObject_HEAD
    urwire_framer own;      /* a raw stream's (feed, close) */
    uint8_t *framer_buffer;
    urwire_framer *framer;  /* the stream being read */
    json_writer *writer;
    urwire_visitor json;
    table *tables;
    int ntables;
    int robot_state, errors, unknown;   /* table indexes */
    Py_ssize_t batch_rows;
    long long position;
    long long time_us;      /* the capture time of the bytes being read (UTC, microseconds) */
    int has_time;           /* 0: none (a raw stream) */
    PyObject *batches;      /* full batches not yet taken */
    PyObject *messages;     /* messages for Python not yet taken */
    int failed;             /* a Python error is set */
    int finished;
    /* the walk over one record */
    int depth;              /* containers open in the record */
    int row_depth;          /* the depth of the row's object; 0: none */
    int awaiting_type;      /* an object whose "type" names its kind has just opened */
    int in_robot_state;
    int packages;
    int fallback_table;     /* the record's kind goes back to Python: its table, else -1 */
    table *row;             /* the table of the row being filled, NULL: values are skipped */
    size_t step;
    int matching;
    frame stack[MAX_DEPTH];
    int nframes;
    int too_deep;           /* containers open beyond MAX_DEPTH: their values are skipped */
    /* kind names seen -> tables: the visitor's names are the parser's constants */
    const uint8_t *name_ptr[64];
    int name_table[64];
    int names;
} PrimaryColumns;

/* ---- column buffers ------------------------------------------------------------------------ */

static int column_grow(column *c)
{
    Py_ssize_t cap = c->cap ? c->cap * 2 : 1024;
    size_t width = col_width[c->type];
    uint8_t *data, *valid;
    size_t data_bytes = width ? (size_t)cap * width : (size_t)(cap + 7) / 8;
    size_t old_data = width ? (size_t)c->cap * width : (size_t)(c->cap + 7) / 8;
    data = PyMem_Realloc(c->data, data_bytes ? data_bytes : 1);
    if (!data)
        return -1;
    c->data = data;
    valid = PyMem_Realloc(c->valid, (size_t)(cap + 7) / 8);
    if (!valid)
        return -1;
    c->valid = valid;
    memset(c->data + old_data, 0, data_bytes - old_data);
    memset(c->valid + (c->cap + 7) / 8, 0, (size_t)(cap + 7) / 8 - (size_t)(c->cap + 7) / 8);
    if (c->type == COL_STRING || c->type == COL_BINARY) {
        int32_t *offsets = PyMem_Realloc(c->offsets, sizeof *offsets * (size_t)(cap + 1));
        if (!offsets)
            return -1;
        if (!c->offsets)
            offsets[0] = 0;
        c->offsets = offsets;
    }
    c->cap = cap;
    return 0;
}

/* Marks the column's next row valid, making room for it; -1 with MemoryError set. */
static int column_slot(column *c)
{
    if (c->filled == c->cap && column_grow(c) < 0) {
        PyErr_NoMemory();
        return -1;
    }
    c->valid[c->filled >> 3] |= (uint8_t)(1u << (c->filled & 7));
    return 0;
}

static int put_null(column *c)
{
    if (c->filled == c->cap && column_grow(c) < 0) {
        PyErr_NoMemory();
        return -1;
    }
    if (c->offsets)
        c->offsets[c->filled + 1] = c->offsets[c->filled];
    c->nulls++;
    c->filled++;
    return 0;
}

static int put_i64(column *c, int64_t v)
{
    if (column_slot(c) < 0)
        return -1;
    memcpy(c->data + 8 * c->filled++, &v, 8);
    return 0;
}

static int put_u64(column *c, uint64_t v)
{
    if (column_slot(c) < 0)
        return -1;
    memcpy(c->data + 8 * c->filled++, &v, 8);
    return 0;
}

static int put_f64(column *c, double v)
{
    if (column_slot(c) < 0)
        return -1;
    memcpy(c->data + 8 * c->filled++, &v, 8);
    return 0;
}

static int put_f32(column *c, float v)
{
    if (column_slot(c) < 0)
        return -1;
    memcpy(c->data + 4 * c->filled++, &v, 4);
    return 0;
}

static int put_bool(column *c, int v)
{
    if (column_slot(c) < 0)
        return -1;
    if (v)
        c->data[c->filled >> 3] |= (uint8_t)(1u << (c->filled & 7));
    c->filled++;
    return 0;
}

static int put_bytes(column *c, const void *p, size_t n, size_t *text_bytes)
{
    if (column_slot(c) < 0)
        return -1;
    if (c->text_len + n > c->text_cap) {
        size_t cap = c->text_cap ? c->text_cap : 4096;
        char *text;
        while (cap < c->text_len + n)
            cap *= 2;
        text = PyMem_Realloc(c->text, cap);
        if (!text) {
            PyErr_NoMemory();
            return -1;
        }
        c->text = text;
        c->text_cap = cap;
    }
    if (n)
        memcpy(c->text + c->text_len, p, n);
    c->text_len += n;
    *text_bytes += n;
    c->offsets[c->filled + 1] = (int32_t)c->text_len;
    c->filled++;
    return 0;
}

static int utf8_valid(const uint8_t *p, size_t n)
{
    size_t i = 0;
    while (i < n) {
        uint8_t b = p[i];
        size_t more, k;
        uint32_t cp;
        if (b < 0x80) {
            i++;
            continue;
        }
        if (b >= 0xC2 && b <= 0xDF) {
            more = 1;
            cp = b & 0x1F;
        } else if (b >= 0xE0 && b <= 0xEF) {
            more = 2;
            cp = b & 0x0F;
        } else if (b >= 0xF0 && b <= 0xF4) {
            more = 3;
            cp = b & 0x07;
        } else {
            return 0;
        }
        if (n - i <= more)
            return 0;
        for (k = 1; k <= more; k++) {
            if ((p[i + k] & 0xC0) != 0x80)
                return 0;
            cp = (cp << 6) | (p[i + k] & 0x3F);
        }
        if ((more == 2 && (cp < 0x800 || (cp >= 0xD800 && cp <= 0xDFFF)))   /* overlong, a surrogate */
            || (more == 3 && (cp < 0x10000 || cp > 0x10FFFF)))
            return 0;
        i += more + 1;
    }
    return 1;
}

/* Text as the dataset shows it: invalid UTF-8 replaced as bytes.decode("utf-8", "replace") does. */
static int put_text(column *c, urwire_bytes s, size_t *text_bytes)
{
    PyObject *decoded;
    const char *utf8;
    Py_ssize_t n;
    int rc;
    if (utf8_valid(s.ptr, s.len))
        return put_bytes(c, s.ptr, s.len, text_bytes);
    decoded = PyUnicode_DecodeUTF8((const char *)s.ptr, (Py_ssize_t)s.len, "replace");
    if (!decoded)
        return -1;
    utf8 = PyUnicode_AsUTF8AndSize(decoded, &n);
    rc = utf8 ? put_bytes(c, utf8, (size_t)n, text_bytes) : -1;
    Py_DECREF(decoded);
    return rc;
}

static void column_free(column *c)
{
    PyMem_Free(c->path);
    PyMem_Free(c->data);
    PyMem_Free(c->valid);
    PyMem_Free(c->offsets);
    PyMem_Free(c->text);
}

/* The batch's buffers as (validity or None, values, offsets or None), and the column emptied. */
static PyObject *column_take(column *c)
{
    size_t width = col_width[c->type];
    size_t data_bytes = width ? (size_t)c->filled * width : (size_t)(c->filled + 7) / 8;
    size_t bitmap_bytes = (size_t)(c->filled + 7) / 8;
    PyObject *valid = NULL, *data = NULL, *offsets = NULL, *out;
    if (c->nulls) {
        valid = PyBytes_FromStringAndSize((const char *)c->valid, (Py_ssize_t)bitmap_bytes);
    } else {
        valid = Py_None;
        Py_INCREF(valid);
    }
    if (c->offsets) {
        offsets = PyBytes_FromStringAndSize((const char *)c->offsets,
                                            (Py_ssize_t)(sizeof(int32_t) * (size_t)(c->filled + 1)));
        data = PyBytes_FromStringAndSize(c->text ? c->text : "", (Py_ssize_t)c->text_len);
    } else {
        offsets = Py_None;
        Py_INCREF(offsets);
        data = PyBytes_FromStringAndSize((const char *)c->data, (Py_ssize_t)data_bytes);
    }
    out = (valid && data && offsets) ? PyTuple_Pack(3, valid, data, offsets) : NULL;
    Py_XDECREF(valid);
    Py_XDECREF(data);
    Py_XDECREF(offsets);
    if (c->data)
        memset(c->data, 0, width ? data_bytes : bitmap_bytes);
    if (c->valid)
        memset(c->valid, 0, bitmap_bytes);
    c->filled = c->nulls = 0;
    c->text_len = 0;
    return out;
}

/* ---- tables: a kind's batch ---------------------------------------------------------------- */

/* The kind's rows so far as (table index, rows, [column buffers]) on self->batches. */
static int table_flush(PrimaryColumns *self, int index)
{
    table *t = &self->tables[index];
    PyObject *columns, *batch;
    int i;
    if (t->rows == 0)
        return 0;
    columns = PyList_New(t->ncolumns);
    if (!columns)
        return -1;
    for (i = 0; i < t->ncolumns; i++) {
        PyObject *buffers = column_take(&t->columns[i]);
        if (!buffers) {
            Py_DECREF(columns);
            return -1;
        }
        PyList_SET_ITEM(columns, i, buffers);
    }
    batch = Py_BuildValue("(inN)", index, t->rows, columns);
    if (!batch)
        return -1;
    t->rows = 0;
    t->text_bytes = 0;
    i = PyList_Append(self->batches, batch);
    Py_DECREF(batch);
    return i;
}

/* A row of t begins: its position and capture time first. */
static int row_begin(PrimaryColumns *self, table *t)
{
    self->row = t;
    self->step = 0;
    self->matching = 1;
    self->nframes = 0;
    self->too_deep = 0;
    if (put_i64(&t->columns[0], self->position) < 0)
        return -1;
    return self->has_time ? put_i64(&t->columns[1], self->time_us) : put_null(&t->columns[1]);
}

/* The row ends: the columns it gave no value are null; a full batch is handed over. */
static int row_end(PrimaryColumns *self, table *t)
{
    int i;
    self->row = NULL;
    for (i = LEAD_COLUMNS; i < t->ncolumns; i++)
        if (t->columns[i].filled == t->rows && put_null(&t->columns[i]) < 0)
            return -1;
    t->rows++;
    if (t->rows >= self->batch_rows || t->text_bytes >= TEXT_FLUSH_BYTES)
        return table_flush(self, (int)(t - self->tables));
    return 0;
}

/* ---- the walk: which column a visitor event's value goes to -------------------------------- */

/* The path of a value (key, or the next item of the array on top) inside the row's object:
 * keys and array indexes joined by '/', as dataset_columns.Column.path spells them. */
static void value_path(const PrimaryColumns *self, const char *key, char *out, size_t cap)
{
    size_t n = 0;
    int i;
    out[0] = '\0';
    for (i = 0; i < self->nframes; i++) {
        const frame *f = &self->stack[i];
        if (f->key)
            n += (size_t)snprintf(out + n, n < cap ? cap - n : 0, "%s/", f->key);
        if (f->array)
            n += (size_t)snprintf(out + n, n < cap ? cap - n : 0, "%d/",
                                  i + 1 < self->nframes ? self->stack[i + 1].item : f->index);
    }
    if (key)
        n += (size_t)snprintf(out + n, n < cap ? cap - n : 0, "%s", key);
    else if (n > 0 && n < cap)
        out[n - 1] = '\0';      /* an array's item: its path ends at its index */
}

static int find_column(const table *t, const char *path)
{
    int i;
    for (i = LEAD_COLUMNS; i < t->ncolumns; i++)
        if (strcmp(t->columns[i].path, path) == 0)
            return i;
    return -1;
}

/* The column of this event of the row (-1: none), from the kind's trace while the row repeats
 * its last one, else from the value's path (and the trace learns it). */
static int locate(PrimaryColumns *self, unsigned char event, const char *key)
{
    table *t = self->row;
    size_t s = self->step++;
    int col = -1;
    if (self->matching && s < t->trace_len && t->trace[s].event == event && t->trace[s].key == key)
        return t->trace[s].column;
    self->matching = 0;
    if (event == EV_VALUE) {
        char path[PATH_MAX_TEXT];
        value_path(self, key, path, sizeof path);
        col = find_column(t, path);
    }
    if (s >= t->trace_cap) {
        size_t cap = t->trace_cap ? t->trace_cap * 2 : 256;
        trace_step *trace = PyMem_Realloc(t->trace, cap * sizeof *trace);
        if (!trace) {
            t->trace_len = 0;   /* no trace: every row finds its columns by path */
            return col;
        }
        t->trace = trace;
        t->trace_cap = cap;
    }
    t->trace[s].event = event;
    t->trace[s].key = key;
    t->trace[s].column = col;
    t->trace_len = s + 1;
    return col;
}

/* A value's column in the row being filled, or NULL: outside a row, no column, or given already. */
static column *value_column(PrimaryColumns *self, const char *key)
{
    int col;
    column *c;
    if (!self->row || self->depth != self->row_depth + self->nframes || self->failed)
        return NULL;
    col = locate(self, EV_VALUE, key);
    if (self->nframes && self->stack[self->nframes - 1].array)
        self->stack[self->nframes - 1].index++;
    if (col < 0)
        return NULL;
    c = &self->row->columns[col];
    return c->filled > self->row->rows ? NULL : c;
}

static void check(PrimaryColumns *self, int rc)
{
    if (rc < 0)
        self->failed = 1;
}

/* The table of a kind's name, -1 for none. The names a record's "type" gives are the parser's
 * constants, so each is looked up once and then known by its address. */
static int table_named(PrimaryColumns *self, urwire_bytes name)
{
    int i;
    for (i = 0; i < self->names; i++)
        if (self->name_ptr[i] == name.ptr)
            return self->name_table[i];
    for (i = 0; i < self->ntables; i++)
        if (strlen(self->tables[i].name) == name.len && memcmp(self->tables[i].name, name.ptr, name.len) == 0)
            break;
    if (i == self->ntables)
        i = -1;
    if (self->names < 64) {
        self->name_ptr[self->names] = name.ptr;
        self->name_table[self->names++] = i;
    }
    return i;
}

static void walk_begin(void *ctx, const char *key, unsigned char event)
{
    PrimaryColumns *self = ctx;
    int parent_array;
    self->depth++;
    if (self->depth == 1 || (self->in_robot_state && self->depth == 3 && event == EV_BEGIN_OBJECT)) {
        self->awaiting_type = 1;    /* a message, or a sub-package: its kind comes next */
        if (self->depth == 3)
            self->packages++;
        return;
    }
    if (!self->row || self->failed)
        return;
    if (self->too_deep || self->nframes == MAX_DEPTH) {
        self->too_deep++;   /* deeper than any layout: what it holds has no column */
        return;
    }
    locate(self, event, key);
    parent_array = self->nframes && self->stack[self->nframes - 1].array;
    self->stack[self->nframes].key = key;
    self->stack[self->nframes].index = 0;
    self->stack[self->nframes].item = parent_array ? self->stack[self->nframes - 1].index : 0;
    self->stack[self->nframes].array = event == EV_BEGIN_ARRAY;
    self->nframes++;
}

static void walk_end(void *ctx, unsigned char event)
{
    PrimaryColumns *self = ctx;
    self->depth--;
    if (self->row && self->depth == self->row_depth - 1) {
        check(self, row_end(self, self->row));
        return;
    }
    if (self->depth == 0 && self->in_robot_state && !self->failed) {
        table *t = &self->tables[self->robot_state];
        check(self, row_begin(self, t));
        if (!self->failed)
            check(self, put_i64(&t->columns[LEAD_COLUMNS], self->packages));
        if (!self->failed)
            check(self, row_end(self, t));
        return;
    }
    if (!self->row || self->failed || self->depth < self->row_depth)
        return;
    if (self->too_deep) {
        self->too_deep--;
        return;
    }
    locate(self, event, NULL);
    if (self->nframes) {
        self->nframes--;
        if (self->nframes && self->stack[self->nframes - 1].array)
            self->stack[self->nframes - 1].index++;
    }
}

static void on_begin_object(void *ctx, const char *key) { walk_begin(ctx, key, EV_BEGIN_OBJECT); }
static void on_begin_array(void *ctx, const char *key) { walk_begin(ctx, key, EV_BEGIN_ARRAY); }
static void on_end_object(void *ctx) { walk_end(ctx, EV_END_OBJECT); }
static void on_end_array(void *ctx) { walk_end(ctx, EV_END_ARRAY); }

static void on_int(void *ctx, const char *key, int64_t v)
{
    PrimaryColumns *self = ctx;
    column *c = value_column(self, key);
    if (!c)
        return;
    switch (c->type) {
    case COL_INT64: check(self, put_i64(c, v)); break;
    case COL_UINT64: check(self, put_u64(c, (uint64_t)v)); break;
    case COL_BOOL: check(self, put_bool(c, v != 0)); break;
    case COL_F32: check(self, put_f32(c, (float)v)); break;
    case COL_F64: check(self, put_f64(c, (double)v)); break;
    default: check(self, put_null(c));
    }
}

static void on_uint(void *ctx, const char *key, uint64_t v)
{
    PrimaryColumns *self = ctx;
    column *c = value_column(self, key);
    if (!c)
        return;
    switch (c->type) {
    case COL_INT64: check(self, put_i64(c, (int64_t)v)); break;
    case COL_UINT64: check(self, put_u64(c, v)); break;
    case COL_BOOL: check(self, put_bool(c, v != 0)); break;
    case COL_F32: check(self, put_f32(c, (float)v)); break;
    case COL_F64: check(self, put_f64(c, (double)v)); break;
    default: check(self, put_null(c));
    }
}

static void on_bool(void *ctx, const char *key, bool v)
{
    PrimaryColumns *self = ctx;
    column *c = value_column(self, key);
    if (!c)
        return;
    switch (c->type) {
    case COL_BOOL: check(self, put_bool(c, v)); break;
    case COL_INT64: check(self, put_i64(c, v)); break;
    default: check(self, put_null(c));
    }
}

static void on_f32(void *ctx, const char *key, float v)
{
    PrimaryColumns *self = ctx;
    column *c = value_column(self, key);
    if (!c)
        return;
    switch (c->type) {
    case COL_F32: check(self, put_f32(c, v)); break;
    case COL_F64: check(self, put_f64(c, (double)v)); break;
    default: check(self, put_null(c));
    }
}

static void on_f64(void *ctx, const char *key, double v)
{
    PrimaryColumns *self = ctx;
    column *c = value_column(self, key);
    if (!c)
        return;
    switch (c->type) {
    case COL_F64: check(self, put_f64(c, v)); break;
    case COL_F32: check(self, put_f32(c, (float)v)); break;
    default: check(self, put_null(c));
    }
}

static void on_text(void *ctx, const char *key, urwire_bytes s)
{
    PrimaryColumns *self = ctx;
    column *c;
    if (self->awaiting_type && (self->depth == 1 || self->depth == 3) && key && strcmp(key, "type") == 0) {
        int index = table_named(self, s);
        self->awaiting_type = 0;
        if (self->depth == 1 && index == self->robot_state) {
            self->in_robot_state = 1;
            return;
        }
        if (index >= 0 && self->tables[index].fallback) {
            self->fallback_table = index;
            return;
        }
        if (index >= 0 && index != self->errors && index != self->unknown) {
            self->row_depth = self->depth;
            check(self, row_begin(self, &self->tables[index]));
        }
        return;
    }
    c = value_column(self, key);
    if (!c)
        return;
    if (c->type == COL_STRING)
        check(self, put_text(c, s, &self->row->text_bytes));
    else
        check(self, put_null(c));
}

static void on_hex(void *ctx, const char *key, urwire_bytes b)
{
    PrimaryColumns *self = ctx;
    column *c = value_column(self, key);
    if (!c)
        return;
    if (c->type == COL_BINARY)
        check(self, put_bytes(c, b.ptr, b.len, &self->row->text_bytes));
    else
        check(self, put_null(c));
}

static void on_null(void *ctx, const char *key)
{
    PrimaryColumns *self = ctx;
    column *c = value_column(self, key);
    if (c)
        check(self, put_null(c));
}

/* ---- records as canonical JSON text (errors, unknown) ------------------------------------- */

/* One record's JSON line (without its newline) as a row of `errors` or `unknown`. Exactly one of
 * m, fault, pkg is given: a message, a stream fault, an unknown sub-package. */
static int json_row(PrimaryColumns *self, int index, const urwire_message *m, const urwire_error *fault,
                    const urwire_package *pkg)
{
    table *t = &self->tables[index];
    char *text = NULL;
    size_t size = 0;
    FILE *out = open_memstream(&text, &size);
    int rc;
    if (!out) {
        PyErr_SetFromErrno(PyExc_OSError);
        return -1;
    }
    self->writer->out = out;
    self->writer->depth = 0;
    if (m) {
        urwire_visit_message(m, &self->json);
    } else if (fault) {
        urwire_visit_fault(fault, &self->json);
    } else {
        static const char unknown[] = "unknown";
        urwire_bytes name = {(const uint8_t *)unknown, sizeof unknown - 1};
        self->json.begin_object(self->json.ctx, NULL);
        self->json.on_text(self->json.ctx, "type", name);
        self->json.on_uint(self->json.ctx, "package_type", pkg->type);
        self->json.on_hex(self->json.ctx, "raw", pkg->raw);
        self->json.end_object(self->json.ctx);
    }
    self->writer->out = NULL;
    if (fclose(out) != 0) {
        free(text);
        PyErr_SetFromErrno(PyExc_OSError);
        return -1;
    }
    rc = row_begin(self, t);
    if (rc == 0)
        rc = put_bytes(&t->columns[LEAD_COLUMNS], text ? text : "", size, &t->text_bytes);
    free(text);
    return rc == 0 ? row_end(self, t) : -1;
}

/* Before each sub-package of a robot state: an unknown one is a row of `unknown`, not walked. */
static bool on_package(void *ctx, const urwire_package *pkg)
{
    PrimaryColumns *self = ctx;
    if (pkg->known || self->failed)
        return false;
    self->packages++;
    check(self, json_row(self, self->unknown, NULL, NULL, pkg));
    return true;
}

/* ---- records -------------------------------------------------------------------------------- */

static int message_for_python(PrimaryColumns *self, int index, const urwire_frame *frame)
{
    PyObject *time = self->has_time ? PyLong_FromLongLong(self->time_us) : (Py_INCREF(Py_None), Py_None);
    PyObject *item = time ? Py_BuildValue("(iLNy#(iii)O)", index, self->position, time, (const char *)frame->bytes,
                                          (Py_ssize_t)frame->length, frame->version.major, frame->version.minor,
                                          frame->version.bugfix, frame->version.assumed ? Py_False : Py_True) : NULL;
    int rc;
    if (!item)
        return -1;
    rc = PyList_Append(self->messages, item);
    Py_DECREF(item);
    return rc;
}

static int add_message(PrimaryColumns *self, const urwire_frame *frame, const urwire_message *m)
{
    static const urwire_visitor walker = {
        NULL, on_begin_object, on_end_object, on_begin_array, on_end_array, on_int, on_uint, on_bool,
        on_f32, on_f64, on_text, on_hex, on_null, on_package,
    };
    urwire_visitor v = walker;
    if (urwire_message_has_error(m))
        return json_row(self, self->errors, m, NULL, NULL);
    if (m->kind == URWIRE_KIND_UNKNOWN_MESSAGE || m->kind == URWIRE_KIND_UNKNOWN_SUBTYPE)
        return json_row(self, self->unknown, m, NULL, NULL);
    v.ctx = self;
    self->depth = self->row_depth = self->awaiting_type = self->in_robot_state = self->packages = 0;
    self->fallback_table = -1;
    self->row = NULL;
    urwire_visit_message(m, &v);
    if (self->failed)
        return -1;
    if (self->fallback_table >= 0)
        return message_for_python(self, self->fallback_table, frame);
    return 0;
}

/* Every record the framer has ready, each into its kind's columns. */
static int add_ready(PrimaryColumns *self)
{
    urwire_frame frame;
    urwire_message m;
    for (;;) {
        urwire_frame_kind kind = urwire_framer_next(self->framer, &frame);
        int rc;
        if (kind == URWIRE_FRAME_NEED_MORE || kind == URWIRE_FRAME_END)
            return 0;
        if (kind == URWIRE_FRAME_FAULT) {
            rc = json_row(self, self->errors, NULL, &frame.fault, NULL);
        } else {
            urwire_decode_message(frame.bytes, frame.length, frame.version, &m);
            urwire_framer_learn(self->framer, &m);
            rc = add_message(self, &frame, &m);
        }
        self->position++;
        if (rc < 0) {
            self->failed = 1;
            return -1;
        }
    }
}

/* ---- the Python type ------------------------------------------------------------------------ */

static void tables_free(PrimaryColumns *self)
{
    int i, j;
    for (i = 0; i < self->ntables; i++) {
        table *t = &self->tables[i];
        for (j = 0; j < t->ncolumns; j++)
            column_free(&t->columns[j]);
        PyMem_Free(t->columns);
        PyMem_Free(t->name);
        PyMem_Free(t->trace);
    }
    PyMem_Free(self->tables);
    self->tables = NULL;
    self->ntables = 0;
}

static void columns_dealloc(PrimaryColumns *self)
{
    tables_free(self);
    PyMem_Free(self->framer_buffer);
    PyMem_Free(self->writer);
    Py_XDECREF(self->batches);
    Py_XDECREF(self->messages);
    Py_TYPE(self)->tp_free((PyObject *)self);
}

static char *copy_text(const char *s)
{
    size_t n = strlen(s) + 1;
    char *out = PyMem_Malloc(n);
    if (out)
        memcpy(out, s, n);
    return out;
}

/* One kind of the layout: (name, None) or (name, [(path, type), ...]). */
static int table_init(table *t, PyObject *spec)
{
    const char *name;
    PyObject *columns;
    Py_ssize_t i, n;
    if (!PyArg_ParseTuple(spec, "sO", &name, &columns))
        return -1;
    if (!(t->name = copy_text(name)))
        return PyErr_NoMemory(), -1;
    t->fallback = columns == Py_None;
    n = t->fallback ? 0 : PySequence_Size(columns);
    if (n < 0)
        return -1;
    t->columns = PyMem_Calloc((size_t)n + LEAD_COLUMNS, sizeof *t->columns);
    if (!t->columns)
        return PyErr_NoMemory(), -1;
    t->ncolumns = (int)n + LEAD_COLUMNS;
    t->columns[0].type = COL_INT64;         /* the position */
    t->columns[1].type = COL_INT64;         /* the capture time */
    if (!(t->columns[0].path = copy_text("")) || !(t->columns[1].path = copy_text("")))
        return PyErr_NoMemory(), -1;
    for (i = 0; i < n; i++) {
        PyObject *item = PySequence_GetItem(columns, i);
        const char *path;
        int type, ok;
        if (!item)
            return -1;
        ok = PyArg_ParseTuple(item, "si", &path, &type);
        Py_DECREF(item);
        if (!ok)
            return -1;
        if (type < 0 || type >= COL_TYPES) {
            PyErr_Format(PyExc_ValueError, "column %s of %s: no type %d", path, name, type);
            return -1;
        }
        t->columns[i + LEAD_COLUMNS].type = type;
        if (!(t->columns[i + LEAD_COLUMNS].path = copy_text(path)))
            return PyErr_NoMemory(), -1;
    }
    return 0;
}

static int kind_index(PrimaryColumns *self, const char *name)
{
    int i;
    for (i = 0; i < self->ntables; i++)
        if (strcmp(self->tables[i].name, name) == 0)
            return i;
    PyErr_Format(PyExc_ValueError, "the layout has no kind %s", name);
    return -1;
}

/* PrimaryColumns(version_hint, layout, batch_rows): layout is a list of (kind, columns), columns
 * None for a kind whose messages go back to Python; it has robot_state ([("packages", int64)]),
 * errors and unknown ([("record", string)]). */
static int columns_init(PrimaryColumns *self, PyObject *args, PyObject *kwargs)
{
    static char *names[] = {"version_hint", "layout", "batch_rows", NULL};
    const char *hint = NULL;
    PyObject *layout;
    Py_ssize_t batch_rows, i, n;
    urwire_sw_version version = URWIRE_DEFAULT_VERSION;
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "zOn", names, &hint, &layout, &batch_rows))
        return -1;
    if (hint && !urwire_parse_version(hint, &version)) {
        PyErr_Format(PyExc_ValueError, "not a software version: %s", hint);
        return -1;
    }
    if (batch_rows < 1) {
        PyErr_SetString(PyExc_ValueError, "batch_rows must be at least 1");
        return -1;
    }
    tables_free(self);
    PyMem_Free(self->framer_buffer);
    PyMem_Free(self->writer);
    Py_CLEAR(self->batches);
    Py_CLEAR(self->messages);
    self->framer_buffer = PyMem_Malloc(URWIRE_FRAMER_MIN_BUFFER);
    self->writer = PyMem_Calloc(1, sizeof *self->writer);
    self->batches = PyList_New(0);
    self->messages = PyList_New(0);
    if (!self->framer_buffer || !self->writer) {
        PyErr_NoMemory();
        return -1;
    }
    if (!self->batches || !self->messages)
        return -1;
    n = PySequence_Size(layout);
    if (n < 0)
        return -1;
    self->tables = PyMem_Calloc((size_t)n, sizeof *self->tables);
    if (!self->tables && n) {
        PyErr_NoMemory();
        return -1;
    }
    for (i = 0; i < n; i++) {
        PyObject *spec = PySequence_GetItem(layout, i);
        int rc;
        if (!spec)
            return -1;
        self->ntables = (int)i + 1;
        rc = table_init(&self->tables[i], spec);
        Py_DECREF(spec);
        if (rc < 0)
            return -1;
    }
    if ((self->robot_state = kind_index(self, "robot_state")) < 0 || (self->errors = kind_index(self, "errors")) < 0
        || (self->unknown = kind_index(self, "unknown")) < 0)
        return -1;
    urwire_framer_init(&self->own, self->framer_buffer, URWIRE_FRAMER_MIN_BUFFER, version);
    self->framer = &self->own;
    self->has_time = 0;
    self->json = json_visitor(self->writer);
    self->batch_rows = batch_rows;
    self->position = 0;
    self->failed = self->finished = 0;
    self->names = 0;
    return 0;
}

/* (batches, messages) taken so far: each batch (kind index, rows, [(validity, values, offsets)]),
 * each message (kind index, position, bytes, (major, minor, bugfix), version known). */
static PyObject *take_output(PrimaryColumns *self)
{
    PyObject *out = PyTuple_Pack(2, self->batches, self->messages);
    PyObject *batches = PyList_New(0), *messages = PyList_New(0);
    if (!out || !batches || !messages) {
        Py_XDECREF(out);
        Py_XDECREF(batches);
        Py_XDECREF(messages);
        return NULL;
    }
    Py_SETREF(self->batches, batches);
    Py_SETREF(self->messages, messages);
    return out;
}

static int usable(PrimaryColumns *self)
{
    if (!self->writer || !self->batches) {
        PyErr_SetString(PyExc_RuntimeError, "PrimaryColumns was not initialised");
        return 0;
    }
    if (self->failed) {
        PyErr_SetString(PyExc_RuntimeError, "PrimaryColumns failed earlier");
        return 0;
    }
    if (self->finished) {
        PyErr_SetString(PyExc_ValueError, "the stream has ended (close() was called)");
        return 0;
    }
    return 1;
}

/* Feeds data to the stream being read (self->framer) and adds every record it completes. */
static int feed_framer(PrimaryColumns *self, const uint8_t *data, size_t length)
{
    size_t off = 0;
    int rc = 0;
    while (off < length && rc == 0) {
        off += urwire_framer_feed(self->framer, data + off, length - off);
        rc = add_ready(self);
    }
    return rc;
}

static PyObject *columns_feed(PrimaryColumns *self, PyObject *arg)
{
    Py_buffer view;
    int rc;
    if (!usable(self))
        return NULL;
    if (PyObject_GetBuffer(arg, &view, PyBUF_SIMPLE) != 0)
        return NULL;
    self->framer = &self->own;
    self->has_time = 0;
    rc = feed_framer(self, view.buf, (size_t)view.len);
    PyBuffer_Release(&view);
    return rc == 0 ? take_output(self) : NULL;
}

static int flush_all(PrimaryColumns *self)
{
    int i;
    for (i = 0; i < self->ntables; i++)
        if (table_flush(self, i) < 0)
            return -1;
    return 0;
}

static PyObject *columns_close(PrimaryColumns *self, PyObject *Py_UNUSED(ignored))
{
    if (!usable(self))
        return NULL;
    self->framer = &self->own;
    self->has_time = 0;
    urwire_framer_finish(self->framer);
    self->finished = 1;
    if (add_ready(self) < 0 || flush_all(self) < 0)
        return NULL;
    return take_output(self);
}

/* The position and capture time (microseconds, or None) of what comes next. */
static int place(PrimaryColumns *self, long long position, PyObject *time)
{
    self->position = position;
    self->has_time = time != Py_None;
    self->time_us = self->has_time ? PyLong_AsLongLong(time) : 0;
    return self->has_time && self->time_us == -1 && PyErr_Occurred() ? -1 : 0;
}

static PyTypeObject PrimaryStreamType;

/* Whether a capture's stream can be fed; 0 with an exception set. */
static int stream_open(PrimaryColumns *self, PrimaryStream *stream)
{
    if (!usable(self))
        return 0;
    if (!stream->buffer || stream->finished) {
        PyErr_SetString(PyExc_ValueError, "the stream has ended, or was not initialised");
        return 0;
    }
    return 1;
}

/* feed_stream(stream, data, position, time) -> the records the bytes complete in that stream of a
 * capture, numbered from position, dated time (UTC microseconds); their rows wait for take(). */
static PyObject *columns_feed_stream(PrimaryColumns *self, PyObject *args)
{
    PrimaryStream *stream;
    Py_buffer view;
    long long position, start;
    PyObject *time;
    int rc;
    if (!PyArg_ParseTuple(args, "O!y*LO", &PrimaryStreamType, &stream, &view, &position, &time))
        return NULL;
    if (!stream_open(self, stream) || place(self, position, time) < 0) {
        PyBuffer_Release(&view);
        return NULL;
    }
    start = self->position;
    self->framer = &stream->framer;
    rc = feed_framer(self, view.buf, (size_t)view.len);
    self->framer = &self->own;
    PyBuffer_Release(&view);
    return rc == 0 ? PyLong_FromLongLong(self->position - start) : NULL;
}

/* A capture time in seconds as the dataset's column holds it: in microseconds, rounded half to
 * even (python/urwire/data/dataset_c.py's micros, Python's round). */
static long long micros(double time)
{
    return (long long)nearbyint(time * 1e6);
}

/* feed_segments(stream, data, stamps, position) -> records: feed_stream of a run of segments
 * joined (ccore_segments.h: capture.py's Segments), a segment at a time, so that each record is
 * dated by the segment that completes it, as if each had been fed alone. */
static PyObject *columns_feed_segments(PrimaryColumns *self, PyObject *args)
{
    PrimaryStream *stream;
    Py_buffer view, stamps;
    long long position;
    ccore_segment_stamp stamp;
    size_t n, i, from = 0;
    int rc = 0;
    if (!PyArg_ParseTuple(args, "O!y*y*L", &PrimaryStreamType, &stream, &view, &stamps, &position))
        return NULL;
    n = (size_t)stamps.len / sizeof stamp;
    for (i = 0; i < n && rc == 0; i++) {
        memcpy(&stamp, (const char *)stamps.buf + i * sizeof stamp, sizeof stamp);
        rc = stamp.end >= (int64_t)from && stamp.end <= (int64_t)view.len ? 0 : -1;
        from = (size_t)stamp.end;
    }
    if (rc < 0 || from != (size_t)view.len || (size_t)stamps.len % sizeof stamp) {
        PyErr_SetString(PyExc_ValueError, "feed_segments: the stamps do not cut the bytes in order");
    } else if (stream_open(self, stream)) {
        self->position = position;
        self->has_time = 1;
        self->framer = &stream->framer;
        for (i = 0, from = 0; i < n && rc == 0; i++) {
            memcpy(&stamp, (const char *)stamps.buf + i * sizeof stamp, sizeof stamp);
            self->time_us = micros(stamp.time);
            rc = feed_framer(self, (const uint8_t *)view.buf + from, (size_t)stamp.end - from);
            from = (size_t)stamp.end;
        }
        self->framer = &self->own;
    }
    PyBuffer_Release(&view);
    PyBuffer_Release(&stamps);
    return PyErr_Occurred() ? NULL : PyLong_FromLongLong(self->position - position);
}

/* close_stream(stream, position, time) -> the records the end of that stream completes. */
static PyObject *columns_close_stream(PrimaryColumns *self, PyObject *args)
{
    PrimaryStream *stream;
    long long position, start;
    PyObject *time;
    int rc;
    if (!PyArg_ParseTuple(args, "O!LO", &PrimaryStreamType, &stream, &position, &time))
        return NULL;
    if (!usable(self) || place(self, position, time) < 0)
        return NULL;
    if (!stream->buffer || stream->finished)
        return PyLong_FromLong(0);
    start = self->position;
    self->framer = &stream->framer;
    urwire_framer_finish(self->framer);
    stream->finished = 1;
    rc = add_ready(self);
    self->framer = &self->own;
    return rc == 0 ? PyLong_FromLongLong(self->position - start) : NULL;
}

/* restart_stream(stream, offset, position, time) -> records: the stream lost bytes before stream
 * offset `offset` (a gap in the capture): what it holds is given up as close_stream gives it, and
 * it is framed afresh from `offset`, the version it learnt kept (framer.py's Framer.restart). */
static PyObject *columns_restart_stream(PrimaryColumns *self, PyObject *args)
{
    PrimaryStream *stream;
    long long position, start, offset;
    PyObject *time;
    int rc = 0;
    urwire_framer *f;
    if (!PyArg_ParseTuple(args, "O!LLO", &PrimaryStreamType, &stream, &offset, &position, &time))
        return NULL;
    if (offset < 0) {
        PyErr_SetString(PyExc_ValueError, "restart_stream: a stream offset is not negative");
        return NULL;
    }
    if (!usable(self) || place(self, position, time) < 0)
        return NULL;
    if (!stream->buffer || stream->finished)
        return PyLong_FromLong(0);
    start = self->position;
    f = &stream->framer;
    self->framer = f;
    urwire_framer_finish(f);
    rc = add_ready(self);
    self->framer = &self->own;
    ccore_framer_restart(f, (uint64_t)offset);
    return rc == 0 ? PyLong_FromLongLong(self->position - start) : NULL;
}

/* add_record(kind, position, time, text): a row of `errors` or `unknown` that Python wrote (a
 * fault of the capture file), in its place among C's rows. */
static PyObject *columns_add_record(PrimaryColumns *self, PyObject *args)
{
    const char *kind, *text;
    Py_ssize_t size;
    long long position;
    PyObject *time;
    table *t;
    int index;
    if (!PyArg_ParseTuple(args, "sLOs#", &kind, &position, &time, &text, &size))
        return NULL;
    if (!usable(self) || place(self, position, time) < 0 || (index = kind_index(self, kind)) < 0)
        return NULL;
    t = &self->tables[index];
    if (t->fallback || t->ncolumns != LEAD_COLUMNS + 1 || t->columns[LEAD_COLUMNS].type != COL_STRING) {
        PyErr_Format(PyExc_ValueError, "%s is not a kind of records", kind);
        return NULL;
    }
    if (row_begin(self, t) < 0 || put_bytes(&t->columns[LEAD_COLUMNS], text, (size_t)size, &t->text_bytes) < 0
        || row_end(self, t) < 0)
        return NULL;
    Py_RETURN_NONE;
}

static PyObject *columns_take(PrimaryColumns *self, PyObject *Py_UNUSED(ignored))
{
    return usable(self) ? take_output(self) : NULL;
}

static PyObject *columns_flush(PrimaryColumns *self, PyObject *Py_UNUSED(ignored))
{
    return usable(self) && flush_all(self) == 0 ? take_output(self) : NULL;
}

static PyMethodDef columns_methods[] = {
    {"feed", (PyCFunction)columns_feed, METH_O,
     "feed(data) -> (batches, messages): the kinds' batches the bytes so far fill, and the messages "
     "of kinds without columns"},
    {"close", (PyCFunction)columns_close, METH_NOARGS,
     "close() -> (batches, messages): what the end of the stream completes, and every kind's last batch"},
    {"feed_stream", (PyCFunction)columns_feed_stream, METH_VARARGS,
     "feed_stream(stream, data, position, time) -> records: a capture's stream, its rows kept for take()"},
    {"feed_segments", (PyCFunction)columns_feed_segments, METH_VARARGS,
     "feed_segments(stream, data, stamps, position) -> records: feed_stream of segments joined, each dated "
     "by its own time (capture.Segments)"},
    {"close_stream", (PyCFunction)columns_close_stream, METH_VARARGS,
     "close_stream(stream, position, time) -> records: what the end of a capture's stream completes"},
    {"restart_stream", (PyCFunction)columns_restart_stream, METH_VARARGS,
     "restart_stream(stream, offset, position, time) -> records: a capture's stream that lost bytes "
     "before offset: its tail, then framed afresh from there"},
    {"add_record", (PyCFunction)columns_add_record, METH_VARARGS,
     "add_record(kind, position, time, text): a row of errors or unknown written in Python"},
    {"take", (PyCFunction)columns_take, METH_NOARGS, "take() -> (batches, messages) filled so far"},
    {"flush", (PyCFunction)columns_flush, METH_NOARGS, "flush() -> (batches, messages): every kind's rows so far"},
    {NULL, NULL, 0, NULL},
};

static PyTypeObject PrimaryColumnsType = {
    PyVarObject_HEAD_INIT(NULL, 0)
    .tp_name = "urwire._ccore.PrimaryColumns",
    .tp_doc = "A primary/secondary stream in, the dataset's column buffers of each kind out.",
    .tp_basicsize = sizeof(PrimaryColumns),
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_new = PyType_GenericNew,
    .tp_init = (initproc)columns_init,
    .tp_dealloc = (destructor)columns_dealloc,
    .tp_methods = columns_methods,
};

/* ---- a capture's primary stream ------------------------------------------------------------- */

static void stream_dealloc(PrimaryStream *self)
{
    PyMem_Free(self->buffer);
    Py_TYPE(self)->tp_free((PyObject *)self);
}

/* PrimaryStream(version_hint=None): as ccore_framer_open takes it. */
static int stream_init(PrimaryStream *self, PyObject *args, PyObject *kwargs)
{
    if (ccore_framer_open(&self->framer, &self->buffer, args, kwargs) < 0)
        return -1;
    self->finished = 0;
    return 0;
}

/* The version the stream's last Version message announced, else None. */
static PyObject *stream_software_version(PrimaryStream *self, void *Py_UNUSED(closure))
{
    if (!self->buffer || !self->framer.version_seen)
        Py_RETURN_NONE;
    return Py_BuildValue("(iii)", self->framer.version.major, self->framer.version.minor,
                         self->framer.version.bugfix);
}

static PyGetSetDef stream_getset[] = {
    {"software_version", (getter)stream_software_version, NULL,
     "the version the stream's last Version message announced, else None", NULL},
    {NULL, NULL, NULL, NULL, NULL},
};

static PyTypeObject PrimaryStreamType = {
    PyVarObject_HEAD_INIT(NULL, 0)
    .tp_name = "urwire._ccore.PrimaryStream",
    .tp_doc = "The framing state of one primary/secondary stream of a capture (PrimaryColumns.feed_stream).",
    .tp_basicsize = sizeof(PrimaryStream),
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_new = PyType_GenericNew,
    .tp_init = (initproc)stream_init,
    .tp_dealloc = (destructor)stream_dealloc,
    .tp_getset = stream_getset,
};

static int add_type(PyObject *module, const char *name, PyTypeObject *type)
{
    if (PyType_Ready(type) < 0)
        return -1;
    Py_INCREF(type);
    if (PyModule_AddObject(module, name, (PyObject *)type) < 0) {
        Py_DECREF(type);
        return -1;
    }
    return 0;
}

int columns_add_types(PyObject *module)
{
    if (add_type(module, "PrimaryColumns", &PrimaryColumnsType) < 0)
        return -1;
    return add_type(module, "PrimaryStream", &PrimaryStreamType);
}
