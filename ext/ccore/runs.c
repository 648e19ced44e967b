/* Sub-package forms read by fixed runs alone, made into the generated record objects in C.
 *
 * The generator writes, beside each such form's Python decoder, what it reads as data
 * (RUN_RECIPES in urwire.generated.messages): its runs in order, each with its struct, the field
 * whose nonzero value it needs (the Euromap67 block) and, for each member, its attribute, its
 * conversion (plain, bool, f32, enum, venum, item_enum), its enum table and where its values are
 * among the struct's; fixed group items have theirs in ITEM_RUNS. A recipe is
 * compiled here on first use (struct codes to byte offsets, attribute names to slot offsets) and
 * then read with no Python call: each value becomes what the decoder makes of it (an int, a float,
 * True/False or the byte, the enum member or the int), the record is made past __init__, and the
 * attributes the form does not send are None, `extra` b"" and `decoded_version` the version.
 * A float32 NaN keeps its bits through urwire._runtime.f32_nan, as the decoder does. */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <structmember.h>

#include <math.h>
#include <stdint.h>
#include <string.h>

#include "ccore_runs.h"
#include "ccore_slots.h"

#ifndef Py_ALWAYS_INLINE            /* Python 3.11 and later define it */
#define Py_ALWAYS_INLINE
#endif

enum member_kind { KIND_SCALAR, KIND_ARRAY, KIND_GROUP };
enum member_conv { CONV_PLAIN, CONV_BOOL, CONV_F32, CONV_ENUM, CONV_VENUM, CONV_ITEM_ENUM };

typedef struct {
    char code;                 /* struct's: b B h H i I q Q f d */
    Py_ssize_t offset;         /* from the start of the run */
} run_leaf;

typedef struct run_member {
    Py_ssize_t slot;           /* offset of its attribute in the instance */
    enum member_kind kind;
    enum member_conv conv;
    PyObject *table;           /* enum: a dict; venum: a table per version (ByVersion) */
    Py_ssize_t lookup;         /* item_enum: index among the item enums its parent passes */
    Py_ssize_t first, count;   /* its first value among the run's (the item's); values or items */
    Py_ssize_t width, size;    /* groups: values and bytes per item */
    PyTypeObject *item;        /* groups: the item class */
    struct run_member *item_members;
    Py_ssize_t item_count;
    PyObject *item_enums;      /* groups: a tuple of the versioned tables its items look up */
    /* The table (venum) or the tuple of item tables (groups) last looked up, and the version it is
     * for: a stream keeps its version, and looking one up hashes the version per value. */
    PyObject *seen_version, *seen_tables;
    int plain_scalar;          /* one value kept as read (no conversion): read inline */
} run_member;

typedef struct {
    Py_ssize_t size;           /* bytes of the run */
    Py_ssize_t leaf_count;
    run_leaf *leaves;
    Py_ssize_t member_count;
    run_member *members;
    Py_ssize_t flag;           /* the slot whose truth it needs; 0: read always */
    Py_ssize_t skipped_count;
    Py_ssize_t *skipped;       /* the slots left None when it is not read */
} fixed_run;

struct run_recipe {
    PyTypeObject *cls;
    Py_ssize_t run_count;
    fixed_run *runs;
    Py_ssize_t absent_count;
    Py_ssize_t *absent;        /* slots left None */
    Py_ssize_t slot_extra, slot_version;
    PyObject *owned;           /* a list of the objects the members point at, held */
    PyObject *f32_nan;         /* its run_recipes' (which outlives it) */
};

struct run_recipes {
    PyObject *recipes, *item_runs;
    PyObject *compiled;        /* {decoder: PyCapsule of run_recipe, or None} */
    PyObject *f32_nan;         /* urwire._runtime.f32_nan(buf, at) */
};

/* ---- compiling ----------------------------------------------------------------------------- */

static void free_members(run_member *members, Py_ssize_t count)
{
    Py_ssize_t i;
    if (members == NULL)
        return;
    for (i = 0; i < count; i++) {
        free_members(members[i].item_members, members[i].item_count);
        Py_XDECREF(members[i].seen_version);
        Py_XDECREF(members[i].seen_tables);
    }
    PyMem_Free(members);
}

static void free_recipe(PyObject *capsule)
{
    run_recipe *r = PyCapsule_GetPointer(capsule, NULL);
    Py_ssize_t i;
    if (r == NULL)
        return;
    for (i = 0; r->runs != NULL && i < r->run_count; i++) {
        PyMem_Free(r->runs[i].leaves);
        free_members(r->runs[i].members, r->runs[i].member_count);
        PyMem_Free(r->runs[i].skipped);
    }
    PyMem_Free(r->runs);
    PyMem_Free(r->absent);
    Py_XDECREF(r->owned);
    Py_XDECREF((PyObject *)r->cls);
    PyMem_Free(r);
}

/* The leaves of a struct format such as ">QBBd" (big-endian, no padding); 0 when the format
 * holds anything else, -1 with an exception set. */
static int parse_format(PyObject *st, fixed_run *r)
{
    PyObject *format = PyObject_GetAttrString(st, "format"), *size_obj;
    const char *f;
    Py_ssize_t n = 0, offset = 0, repeat;
    int ok = 1;
    if (format == NULL)
        return -1;
    f = PyUnicode_Check(format) ? PyUnicode_AsUTF8(format) : NULL;
    if (f == NULL || *f != '>') {
        Py_DECREF(format);
        return PyErr_Occurred() ? -1 : 0;
    }
    r->leaves = PyMem_Malloc(sizeof(run_leaf) * (strlen(f) + 1));
    if (r->leaves == NULL) {
        Py_DECREF(format);
        PyErr_NoMemory();
        return -1;
    }
    for (f++; *f && ok; f++) {
        Py_ssize_t width;
        repeat = 0;
        while (*f >= '0' && *f <= '9')
            repeat = repeat * 10 + (*f++ - '0');
        if (repeat != 0) {
            ok = 0;                       /* the generator writes each code once */
            break;
        }
        switch (*f) {
        case 'b': case 'B': width = 1; break;
        case 'h': case 'H': width = 2; break;
        case 'i': case 'I': case 'f': width = 4; break;
        case 'q': case 'Q': case 'd': width = 8; break;
        default: ok = 0; width = 0; break;
        }
        if (!ok)
            break;
        r->leaves[n].code = *f;
        r->leaves[n].offset = offset;
        offset += width;
        n++;
    }
    Py_DECREF(format);
    r->leaf_count = n;
    r->size = offset;
    size_obj = PyObject_GetAttrString(st, "size");
    if (size_obj == NULL)
        return -1;
    ok = ok && PyLong_Check(size_obj) && PyLong_AsSsize_t(size_obj) == offset;
    Py_DECREF(size_obj);
    return ok;
}

static int compile_members(PyObject *spec, PyTypeObject *cls, const fixed_run *r, PyObject *item_runs,
                           PyObject *owned, run_member **out, Py_ssize_t *count, int depth, Py_ssize_t base,
                           Py_ssize_t limit);

static const char *const CONVERSIONS[] = {"plain", "bool", "f32", "enum", "venum", "item_enum"};

/* One member from (name, kind, conversion, table, first, count, item, width, size, enums), its
 * values among the `limit` from the run's value `base` (the run's, or its group's first item's);
 * 0 when it is one this does not read, -1 with an exception set. */
static int compile_member(PyObject *entry, PyTypeObject *cls, const fixed_run *r, PyObject *item_runs,
                          PyObject *owned, run_member *m, int depth, Py_ssize_t base, Py_ssize_t limit)
{
    PyObject *name, *kind, *conv, *item;
    Py_ssize_t k, last;
    const char *text;
    if (!PyTuple_Check(entry) || PyTuple_GET_SIZE(entry) != 10)
        return 0;
    name = PyTuple_GET_ITEM(entry, 0);
    kind = PyTuple_GET_ITEM(entry, 1);
    conv = PyTuple_GET_ITEM(entry, 2);
    item = PyTuple_GET_ITEM(entry, 6);
    if (!PyUnicode_Check(name) || !PyUnicode_Check(kind) || !PyUnicode_Check(conv))
        return 0;
    if ((m->slot = ccore_slot_of(cls, name)) <= 0)
        return (int)m->slot;
    text = PyUnicode_AsUTF8(kind);
    if (text == NULL)
        return -1;
    m->kind = strcmp(text, "scalar") == 0 ? KIND_SCALAR : strcmp(text, "array") == 0 ? KIND_ARRAY : KIND_GROUP;
    if (m->kind == KIND_GROUP && strcmp(text, "group") != 0)
        return 0;
    if ((text = PyUnicode_AsUTF8(conv)) == NULL)
        return -1;
    for (k = 0; k < (Py_ssize_t)(sizeof CONVERSIONS / sizeof *CONVERSIONS); k++)
        if (strcmp(text, CONVERSIONS[k]) == 0)
            break;
    if (k == (Py_ssize_t)(sizeof CONVERSIONS / sizeof *CONVERSIONS))
        return 0;
    m->conv = (enum member_conv)k;
    m->table = PyTuple_GET_ITEM(entry, 3);
    if (m->conv == CONV_ITEM_ENUM) {
        if (!PyLong_Check(m->table))
            return 0;
        m->lookup = PyLong_AsSsize_t(m->table);
        m->table = NULL;
    } else if (m->conv == CONV_ENUM && !PyDict_Check(m->table)) {
        return 0;
    } else if (m->conv != CONV_ENUM && m->conv != CONV_VENUM) {
        m->table = NULL;
    }
    m->first = PyLong_AsSsize_t(PyTuple_GET_ITEM(entry, 4));
    m->count = PyLong_AsSsize_t(PyTuple_GET_ITEM(entry, 5));
    m->width = PyLong_AsSsize_t(PyTuple_GET_ITEM(entry, 7));
    m->size = PyLong_AsSsize_t(PyTuple_GET_ITEM(entry, 8));
    m->item_enums = PyTuple_GET_ITEM(entry, 9);
    if (PyErr_Occurred())
        return -1;
    if (m->first < 0 || m->count < 0 || m->width < 0 || !PyTuple_Check(m->item_enums))
        return 0;
    if (m->kind != KIND_GROUP) {
        last = m->first + m->count;
        if (last > limit || (m->kind == KIND_SCALAR && m->count != 1))
            return 0;
        m->plain_scalar = m->kind == KIND_SCALAR && (m->conv == CONV_PLAIN || m->conv == CONV_F32);
        for (k = m->first; k < last; k++) {
            char code = r->leaves[base + k].code;   /* an item's: those of its group's first */
            if (m->conv == CONV_F32 ? code != 'f' : code == 'f' || (code == 'd' && m->conv != CONV_PLAIN))
                return 0;
            if (m->conv == CONV_BOOL && code != 'B')
                return 0;
        }
        return 1;
    }
    if (depth > 0 || !PyType_Check(item) || m->width <= 0 || m->first + m->count * m->width > limit)
        return 0;              /* items inside items: the spec has none */
    m->item = (PyTypeObject *)item;
    {
        PyObject *item_spec = PyDict_GetItemWithError(item_runs, item);
        if (item_spec == NULL)
            return PyErr_Occurred() ? -1 : 0;
        if (PyList_Append(owned, item) < 0)
            return -1;
        return compile_members(item_spec, m->item, r, item_runs, owned, &m->item_members, &m->item_count, depth + 1,
                               base + m->first, m->width);
    }
}

/* The members of a recipe, or of an item (depth 1: their values count from the item's first). */
static int compile_members(PyObject *spec, PyTypeObject *cls, const fixed_run *r, PyObject *item_runs,
                           PyObject *owned, run_member **out, Py_ssize_t *count, int depth, Py_ssize_t base,
                           Py_ssize_t limit)
{
    Py_ssize_t i, n;
    int ok;
    if (!PyTuple_Check(spec))
        return 0;
    n = PyTuple_GET_SIZE(spec);
    *out = PyMem_Calloc((size_t)n + 1, sizeof(run_member));
    if (*out == NULL) {
        PyErr_NoMemory();
        return -1;
    }
    *count = n;
    for (i = 0; i < n; i++) {
        ok = compile_member(PyTuple_GET_ITEM(spec, i), cls, r, item_runs, owned, &(*out)[i], depth, base, limit);
        if (ok <= 0)
            return ok;
        if ((*out)[i].table != NULL && PyList_Append(owned, (*out)[i].table) < 0)
            return -1;
        if (PyList_Append(owned, (*out)[i].item_enums) < 0)
            return -1;
    }
    if (depth > 0 && ccore_slot_count(cls) != n)
        return 0;              /* an item must be its members and nothing else */
    return 1;
}

/* The slots of a tuple of attribute names; 0 when one is not a slot, -1 with an exception set. */
static int slots_of(PyTypeObject *cls, PyObject *names, Py_ssize_t **slots, Py_ssize_t *count)
{
    Py_ssize_t i;
    if (!PyTuple_Check(names))
        return 0;
    *count = PyTuple_GET_SIZE(names);
    *slots = PyMem_Calloc((size_t)*count + 1, sizeof(Py_ssize_t));
    if (*slots == NULL) {
        PyErr_NoMemory();
        return -1;
    }
    for (i = 0; i < *count; i++)
        if (((*slots)[i] = ccore_slot_of(cls, PyTuple_GET_ITEM(names, i))) <= 0)
            return (int)(*slots)[i];
    return 1;
}

static int has_slot(const Py_ssize_t *slots, Py_ssize_t count, Py_ssize_t slot)
{
    Py_ssize_t i;
    for (i = 0; i < count; i++)
        if (slots[i] == slot)
            return 1;
    return 0;
}

/* One run from (struct, members, flag name or None, names left None when skipped); `read` holds
 * the slots the runs before it set (its flag must be one), and gets its own. */
static int compile_run(PyObject *spec, run_recipe *r, fixed_run *run, PyObject *item_runs, Py_ssize_t *read,
                       Py_ssize_t *read_count)
{
    PyObject *flag;
    Py_ssize_t i;
    int ok;
    if (!PyTuple_Check(spec) || PyTuple_GET_SIZE(spec) != 4)
        return 0;
    if ((ok = parse_format(PyTuple_GET_ITEM(spec, 0), run)) <= 0)
        return ok;
    ok = compile_members(PyTuple_GET_ITEM(spec, 1), r->cls, run, item_runs, r->owned, &run->members,
                         &run->member_count, 0, 0, run->leaf_count);
    if (ok <= 0)
        return ok;
    flag = PyTuple_GET_ITEM(spec, 2);
    if (flag != Py_None) {
        if ((run->flag = ccore_slot_of(r->cls, flag)) <= 0)
            return (int)run->flag;
        if (!has_slot(read, *read_count, run->flag))
            return 0;               /* a flag the runs before have not read */
    }
    if ((ok = slots_of(r->cls, PyTuple_GET_ITEM(spec, 3), &run->skipped, &run->skipped_count)) <= 0)
        return ok;
    for (i = 0; i < run->member_count; i++) {
        /* Skipped, a conditional run's attributes must still be set: each is among its names. */
        if (run->flag && !has_slot(run->skipped, run->skipped_count, run->members[i].slot))
            return 0;
        read[(*read_count)++] = run->members[i].slot;
    }
    return 1;
}

/* A recipe from (runs, absent names) for the decoder's class; 0 when it cannot be read here,
 * -1 with an exception set. */
static int compile_recipe(PyObject *spec, PyObject *decode, PyObject *item_runs, run_recipe *r)
{
    PyObject *runs, *extra, *version;
    Py_ssize_t i, slots, *read, read_count = 0;
    int ok;
    if (!PyMethod_Check(decode) || !PyType_Check(PyMethod_GET_SELF(decode)))
        return 0;
    r->cls = (PyTypeObject *)Py_NewRef(PyMethod_GET_SELF(decode));
    if ((r->owned = PyList_New(0)) == NULL)
        return -1;
    if (!PyTuple_Check(spec) || PyTuple_GET_SIZE(spec) != 2 || !PyTuple_Check(PyTuple_GET_ITEM(spec, 0)))
        return 0;
    if ((slots = ccore_slot_count(r->cls)) <= 0)
        return 0;
    runs = PyTuple_GET_ITEM(spec, 0);
    r->run_count = PyTuple_GET_SIZE(runs);
    r->runs = PyMem_Calloc((size_t)r->run_count + 1, sizeof(fixed_run));
    read = PyMem_Calloc((size_t)slots + 1, sizeof(Py_ssize_t));
    if (r->runs == NULL || read == NULL) {
        PyMem_Free(read);
        PyErr_NoMemory();
        return -1;
    }
    ok = 1;
    for (i = 0; i < r->run_count && ok > 0; i++) {
        PyObject *run = PyTuple_GET_ITEM(runs, i);
        if (PyTuple_Check(run) && PyTuple_GET_SIZE(run) == 4 && PyTuple_Check(PyTuple_GET_ITEM(run, 1))
            && read_count + PyTuple_GET_SIZE(PyTuple_GET_ITEM(run, 1)) <= slots)
            ok = compile_run(run, r, &r->runs[i], item_runs, read, &read_count);
        else
            ok = 0;
    }
    PyMem_Free(read);
    if (ok <= 0)
        return ok;
    if ((ok = slots_of(r->cls, PyTuple_GET_ITEM(spec, 1), &r->absent, &r->absent_count)) <= 0)
        return ok;
    if ((extra = PyUnicode_InternFromString("extra")) == NULL)
        return -1;
    r->slot_extra = ccore_slot_of(r->cls, extra);
    Py_DECREF(extra);
    if ((version = PyUnicode_InternFromString("decoded_version")) == NULL)
        return -1;
    r->slot_version = ccore_slot_of(r->cls, version);
    Py_DECREF(version);
    if (r->slot_extra <= 0 || r->slot_version <= 0)
        return r->slot_extra < 0 || r->slot_version < 0 ? -1 : 0;
    /* Every attribute is set once: the runs' members, the absent ones, extra and decoded_version. */
    return slots == read_count + r->absent_count + 2;
}

run_recipes *run_recipes_new(PyObject *recipes, PyObject *item_runs)
{
    run_recipes *all;
    PyObject *runtime;
    if (!PyDict_Check(recipes) || !PyDict_Check(item_runs)) {
        PyErr_SetString(PyExc_TypeError, "recipes and item_runs must be dicts");
        return NULL;
    }
    all = PyMem_Calloc(1, sizeof *all);
    if (all == NULL) {
        PyErr_NoMemory();
        return NULL;
    }
    all->recipes = Py_NewRef(recipes);
    all->item_runs = Py_NewRef(item_runs);
    all->compiled = PyDict_New();
    runtime = PyImport_ImportModule("urwire._runtime");
    if (runtime != NULL) {
        all->f32_nan = PyObject_GetAttrString(runtime, "f32_nan");
        Py_DECREF(runtime);
    }
    if (all->compiled == NULL || all->f32_nan == NULL) {
        run_recipes_free(all);
        return NULL;
    }
    return all;
}

void run_recipes_free(run_recipes *all)
{
    if (all == NULL)
        return;
    Py_XDECREF(all->recipes);
    Py_XDECREF(all->item_runs);
    Py_XDECREF(all->compiled);
    Py_XDECREF(all->f32_nan);
    PyMem_Free(all);
}

int run_recipe_of(run_recipes *all, PyObject *decode, const run_recipe **recipe)
{
    PyObject *found = PyDict_GetItemWithError(all->compiled, decode), *spec, *capsule;
    run_recipe *r;
    int ok;
    *recipe = NULL;
    if (found != NULL) {
        if (found != Py_None)
            *recipe = PyCapsule_GetPointer(found, NULL);
        return 0;
    }
    if (PyErr_Occurred())
        return -1;
    spec = PyDict_GetItemWithError(all->recipes, decode);
    if (spec == NULL)
        return PyErr_Occurred() ? -1 : PyDict_SetItem(all->compiled, decode, Py_None);
    r = PyMem_Calloc(1, sizeof *r);
    if (r == NULL) {
        PyErr_NoMemory();
        return -1;
    }
    capsule = PyCapsule_New(r, NULL, free_recipe);
    if (capsule == NULL) {
        PyMem_Free(r);
        return -1;
    }
    r->f32_nan = all->f32_nan;
    Py_INCREF(spec);
    ok = compile_recipe(spec, decode, all->item_runs, r);
    Py_DECREF(spec);
    if (ok < 0 || PyDict_SetItem(all->compiled, decode, ok ? capsule : Py_None) < 0) {
        Py_DECREF(capsule);
        return -1;
    }
    Py_DECREF(capsule);            /* the dict holds it */
    *recipe = ok ? r : NULL;
    return 0;
}

/* ---- reading ------------------------------------------------------------------------------- */

/* Big-endian loads, written out so that compilers make each one load and byte swap. */
static uint16_t load16(const unsigned char *p)
{
    return (uint16_t)(p[0] << 8 | p[1]);
}

static uint32_t load32(const unsigned char *p)
{
    return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | (uint32_t)p[3];
}

static uint64_t load64(const unsigned char *p)
{
    return (uint64_t)load32(p) << 32 | load32(p + 4);
}

/* Where a run is read: its leaves start at byte `start` of buf. */
typedef struct {
    const fixed_run *run;
    PyObject *buf;
    Py_ssize_t start;
    PyObject *version;
    PyObject *f32_nan;
} reading;

/* The value of leaf k as struct unpacks it (a float32 NaN with its bits, as f32_nan keeps them). */
static inline Py_ALWAYS_INLINE PyObject *leaf_value(const reading *at, Py_ssize_t k)
{
    const run_leaf *leaf = &at->run->leaves[k];
    const unsigned char *p = (const unsigned char *)PyBytes_AS_STRING(at->buf) + at->start + leaf->offset;
    switch (leaf->code) {
    case 'd': {
        uint64_t bits = load64(p);
        double d;
        memcpy(&d, &bits, sizeof d);
        return PyFloat_FromDouble(d);
    }
    case 'f': {
        uint32_t bits = load32(p);
        float f;
        memcpy(&f, &bits, sizeof f);
        if (isnan(f))
            return PyObject_CallFunction(at->f32_nan, "On", at->buf, at->start + leaf->offset);
        return PyFloat_FromDouble((double)f);
    }
    case 'b': return PyLong_FromLong((int8_t)p[0]);
    case 'B': return PyLong_FromLong(p[0]);
    case 'h': return PyLong_FromLong((int16_t)load16(p));
    case 'H': return PyLong_FromLong(load16(p));
    case 'i': return PyLong_FromLong((int32_t)load32(p));
    case 'I': return PyLong_FromUnsignedLong(load32(p));
    case 'q': return PyLong_FromLongLong((long long)(int64_t)load64(p));
    default:  return PyLong_FromUnsignedLongLong(load64(p));      /* 'Q' */
    }
}

/* A value as the member's conversion makes it: True/False or the byte, the enum member or the int. */
static PyObject *tables_for(run_member *m, PyObject *version);

static PyObject *converted(run_member *m, PyObject *value, PyObject *version, PyObject *item_enums)
{
    PyObject *table = NULL, *member;
    switch (m->conv) {
    case CONV_PLAIN:
    case CONV_F32:
        return value;
    case CONV_BOOL:
        if (value == NULL)
            return NULL;
        if (PyLong_AsLong(value) == 0 || PyLong_AsLong(value) == 1) {
            member = PyBool_FromLong(PyLong_AsLong(value));
            Py_DECREF(value);
            return member;
        }
        return value;
    case CONV_ENUM:
        table = Py_NewRef(m->table);
        break;
    case CONV_VENUM:
        table = Py_XNewRef(tables_for(m, version));
        break;
    case CONV_ITEM_ENUM:
        table = item_enums != NULL && m->lookup < PyTuple_GET_SIZE(item_enums)
            ? Py_NewRef(PyTuple_GET_ITEM(item_enums, m->lookup)) : NULL;
        if (table == NULL)
            PyErr_SetString(PyExc_IndexError, "item enum table");
        break;
    }
    if (value == NULL || table == NULL) {
        Py_XDECREF(table);
        Py_XDECREF(value);
        return NULL;
    }
    member = PyDict_Check(table) ? PyDict_GetItemWithError(table, value) : NULL;
    if (member == NULL && !PyErr_Occurred() && !PyDict_Check(table)) {
        /* a table that is not a dict: what .get(value, value) gives */
        member = PyObject_CallMethod(table, "get", "OO", value, value);
        Py_DECREF(table);
        Py_DECREF(value);
        return member;
    }
    if (member == NULL) {
        Py_DECREF(table);
        if (PyErr_Occurred()) {
            Py_DECREF(value);
            return NULL;
        }
        return value;               /* a code the table does not name: the int, as .get gives */
    }
    Py_INCREF(member);              /* borrowed from the table: held before the table is let go */
    Py_DECREF(table);
    Py_DECREF(value);
    return member;
}

/* An attribute slot of a record being made: set, or set again (a name the form left None). */
static void set_slot(PyObject *record, Py_ssize_t slot, PyObject *value)
{
    Py_XSETREF(*(PyObject **)((char *)record + slot), value);
}

/* What member m looks up for this version (a venum's table, a group's tuple of item tables),
 * borrowed: the last one found is kept with its version (held, so that its address is not another
 * version's); NULL with an exception set. */
static PyObject *tables_for(run_member *m, PyObject *version)
{
    PyObject *found;
    Py_ssize_t i, n;
    if (m->seen_version == version)
        return m->seen_tables;
    if (m->kind != KIND_GROUP) {
        found = PyObject_GetItem(m->table, version);
    } else {
        n = PyTuple_GET_SIZE(m->item_enums);
        found = PyTuple_New(n);
        for (i = 0; found != NULL && i < n; i++) {
            PyObject *table = PyObject_GetItem(PyTuple_GET_ITEM(m->item_enums, i), version);
            if (table == NULL)
                Py_CLEAR(found);
            else
                PyTuple_SET_ITEM(found, i, table);
        }
    }
    if (found == NULL)
        return NULL;
    Py_XSETREF(m->seen_tables, found);
    Py_INCREF(version);
    Py_XSETREF(m->seen_version, version);
    return found;
}

static PyObject *member_value(const reading *at, run_member *m, Py_ssize_t base, PyObject *item_enums);

/* A group's items: each a new instance of the item class, its members read from its values. */
static PyObject *group_value(const reading *at, run_member *m, Py_ssize_t base)
{
    PyObject *items, *enums = tables_for(m, at->version);  /* the items' versioned tables */
    Py_ssize_t j, i;
    if (enums == NULL)
        return NULL;
    items = PyList_New(m->count);
    if (items == NULL)
        return NULL;
    Py_INCREF(enums);                  /* held while reading: a collection may run other code */
    for (j = 0; j < m->count; j++) {
        PyObject *item = m->item->tp_alloc(m->item, 0);
        if (item == NULL)
            goto failed;
        PyList_SET_ITEM(items, j, item);
        for (i = 0; i < m->item_count; i++) {
            run_member *im = &m->item_members[i];
            Py_ssize_t first = base + m->first + j * m->width;
            PyObject *value = im->plain_scalar ? leaf_value(at, first + im->first) : member_value(at, im, first, enums);
            if (value == NULL)
                goto failed;
            set_slot(item, im->slot, value);
        }
    }
    Py_DECREF(enums);
    return items;
failed:
    Py_DECREF(enums);
    Py_DECREF(items);
    return NULL;
}

/* One member's attribute; `base` is the index its first value counts from (an item's first). */
static PyObject *member_value(const reading *at, run_member *m, Py_ssize_t base, PyObject *item_enums)
{
    PyObject *list;
    Py_ssize_t k;
    int plain = m->conv == CONV_PLAIN || m->conv == CONV_F32;    /* the value as it is read */
    if (m->kind == KIND_SCALAR) {
        PyObject *value = leaf_value(at, base + m->first);
        return plain ? value : converted(m, value, at->version, item_enums);
    }
    if (m->kind == KIND_GROUP)
        return group_value(at, m, base);
    list = PyList_New(m->count);
    if (list == NULL)
        return NULL;
    for (k = 0; k < m->count; k++) {
        PyObject *value = leaf_value(at, base + m->first + k);
        if (!plain)
            value = converted(m, value, at->version, item_enums);
        if (value == NULL) {
            Py_DECREF(list);
            return NULL;
        }
        PyList_SET_ITEM(list, k, value);
    }
    return list;
}

/* Reads one run into the record, or, when its flag is not set, leaves its names None; the
 * bytes it took, or -1 with an exception set, or -2 when it does not fit in the bytes left. */
static Py_ssize_t read_run(const fixed_run *run, PyObject *record, PyObject *buf, Py_ssize_t start,
                           Py_ssize_t stop, PyObject *version, PyObject *f32_nan)
{
    reading at = {run, buf, start, version, f32_nan};
    Py_ssize_t i;
    if (run->flag) {
        int set = PyObject_IsTrue(*(PyObject **)((char *)record + run->flag));
        if (set < 0)
            return -1;
        if (!set) {
            for (i = 0; i < run->skipped_count; i++)
                set_slot(record, run->skipped[i], Py_NewRef(Py_None));
            return 0;
        }
    }
    if (run->size > stop - start)
        return -2;
    for (i = 0; i < run->member_count; i++) {
        run_member *m = &run->members[i];
        PyObject *value = m->plain_scalar ? leaf_value(&at, m->first) : member_value(&at, m, 0, NULL);
        if (value == NULL)
            return -1;
        set_slot(record, m->slot, value);
    }
    return run->size;
}

PyObject *run_read(const run_recipe *r, PyObject *buf, Py_ssize_t body, Py_ssize_t stop, PyObject *version)
{
    PyObject *record;
    Py_ssize_t i, pos = body;
    if (stop > PyBytes_GET_SIZE(buf) || body > stop)
        return NULL;
    record = r->cls->tp_alloc(r->cls, 0);
    if (record == NULL)
        return NULL;
    for (i = 0; i < r->absent_count; i++)
        set_slot(record, r->absent[i], Py_NewRef(Py_None));
    for (i = 0; i < r->run_count; i++) {
        Py_ssize_t took = read_run(&r->runs[i], record, buf, pos, stop, version, r->f32_nan);
        if (took < 0) {
            Py_DECREF(record);
            return NULL;               /* -2, short: the Python decoder's case (no exception) */
        }
        pos += took;
    }
    if (pos != stop) {
        Py_DECREF(record);             /* extra bytes: the Python decoder's case */
        return NULL;
    }
    set_slot(record, r->slot_extra, PyBytes_FromStringAndSize(NULL, 0));
    set_slot(record, r->slot_version, Py_NewRef(version));
    if (*(PyObject **)((char *)record + r->slot_extra) == NULL) {
        Py_DECREF(record);
        return NULL;
    }
    return record;
}
