/* urwire._ccore.PackageStates: robot states (the primary interface's message of sub-packages) as
 * the generated record objects of urwire.generated.messages, the same objects pure Python makes.
 *
 * A robot sends most sub-packages again with the same bytes from one state to the next (its
 * configuration, kinematics and limits always; every package at rest), and a package's record
 * depends only on its type code, the software version and its bytes. So the state is framed here
 * and each sub-package whose bytes, code and version match one of the last few of its code
 * (MEMO_WAYS: a capture may interleave robots) is a copy of the record they gave: made in C,
 * past the classes' __init__, with the same slots (the immutable values shared, lists and nested
 * records copied, so no two states share what can change). A copy handed out is taken back when
 * the state it went in was dropped and nothing else references it or any part of it, untouched:
 * a caller that drops each state after reading it (or the one before, as a loop does) then costs
 * no copy and no free for a package that did not move.
 * A package with new bytes is read by the version's form (Forms.fast), as PackageList.decode
 * reads it: in C when the form is read by fixed runs (generated RUN_RECIPES: each run's struct
 * and what each member becomes, runs.c), else by the generated Python decoder. A record made in
 * C is kept for copying once the same bytes come again, so that a package that changes in every
 * state (a moving joint) costs no copy; the Python decoder's record is kept at once.
 *
 * Anything the common case does not cover (a framing fault, a package that the version's form
 * does not read to its last byte, a code with no form) returns None: the caller then decodes the
 * whole message in Python, which reports it as it always has. */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <structmember.h>

#include <stdint.h>
#include <string.h>

#include "ccore_records.h"
#include "ccore_runs.h"
#include "ccore_slots.h"

#define PACKAGE_HEADER_SIZE 5   /* int32 length (header included), uint8 type code */
#define MAX_CODES 256
#define MAX_SLOTS 64            /* more than any generated class has */
#define MAX_CLONE_DEPTH 8       /* records in lists in records: two levels in the spec */

/* ---- copying records ---------------------------------------------------------------------- */

/* Where a slotted class keeps its attributes: the offsets of its member descriptors. */
typedef struct {
    Py_ssize_t count;
    Py_ssize_t offsets[MAX_SLOTS];
} slot_layout;

/* The slot layouts of the classes seen so far: {type: PyCapsule of slot_layout, or None for a
 * class whose instances are not copied}. */
static PyObject *layouts;

static void free_layout(PyObject *capsule)
{
    PyMem_Free(PyCapsule_GetPointer(capsule, NULL));
}

/* The member descriptors of a class and its bases, when they hold every attribute an instance
 * has: no __dict__, no items, nothing in the layout but object slots. A slot that a subclass
 * hides is counted in the size but not copied: instances leave it empty. *layout = NULL when the
 * class keeps something else (its records are then not copied); -1 with an exception set. */
static int find_layout(PyTypeObject *type, slot_layout **layout)
{
    PyObject *mro = type->tp_mro, *capsule;
    slot_layout found;
    Py_ssize_t i, hidden = 0, base = (Py_ssize_t)sizeof(PyObject);
    *layout = NULL;
    if (type->tp_dictoffset != 0 || type->tp_itemsize != 0 || mro == NULL)
        return PyDict_SetItem(layouts, (PyObject *)type, Py_None);
    found.count = 0;
    for (i = 0; i < PyTuple_GET_SIZE(mro); i++) {
        PyTypeObject *cls = (PyTypeObject *)PyTuple_GET_ITEM(mro, i);
        PyObject *key, *value;
        Py_ssize_t at = 0;
        if (cls == &PyBaseObject_Type)
            continue;
        if (!(cls->tp_flags & Py_TPFLAGS_HEAPTYPE))   /* a built-in base: not plain slots */
            return PyDict_SetItem(layouts, (PyObject *)type, Py_None);
        while (PyDict_Next(cls->tp_dict, &at, &key, &value)) {
            PyMemberDef *member;
            if (!Py_IS_TYPE(value, &PyMemberDescr_Type))
                continue;
            member = ((PyMemberDescrObject *)value)->d_member;
            if (member->type != T_OBJECT_EX || (member->flags & READONLY))
                continue;
            if (!ccore_slot_is_visible(type, key, value)) {
                hidden++;
                continue;
            }
            if (found.count == MAX_SLOTS)
                return PyDict_SetItem(layouts, (PyObject *)type, Py_None);
            found.offsets[found.count++] = member->offset;
        }
    }
    if (type->tp_weaklistoffset != 0)
        base += (Py_ssize_t)sizeof(PyObject *);   /* left NULL in a copy, as in a new object */
    if (base + (found.count + hidden) * (Py_ssize_t)sizeof(PyObject *) != type->tp_basicsize)
        return PyDict_SetItem(layouts, (PyObject *)type, Py_None);
    *layout = PyMem_Malloc(sizeof found);
    if (*layout == NULL) {
        PyErr_NoMemory();
        return -1;
    }
    **layout = found;
    capsule = PyCapsule_New(*layout, NULL, free_layout);
    if (capsule == NULL) {
        PyMem_Free(*layout);
        *layout = NULL;
        return -1;
    }
    if (PyDict_SetItem(layouts, (PyObject *)type, capsule) < 0) {
        Py_DECREF(capsule);
        *layout = NULL;
        return -1;
    }
    Py_DECREF(capsule);
    return 0;
}

/* The layouts of the classes met last, by the class's address: a copy asks one per record,
 * and a dict look-up each time would cost a sixth of the copy. The classes are held as keys of
 * `layouts`, so an address is never another class's. */
#define RECENT_LAYOUTS 64
static struct {
    PyTypeObject *type;
    slot_layout *layout;
} recent_layouts[RECENT_LAYOUTS];

/* The slot layout of a class (NULL: its instances are not copied); -1 with an exception set. */
static int layout_of(PyTypeObject *type, slot_layout **layout)
{
    size_t at = ((uintptr_t)type >> 6) % RECENT_LAYOUTS;
    PyObject *capsule;
    if (recent_layouts[at].type == type) {
        *layout = recent_layouts[at].layout;
        return 0;
    }
    capsule = PyDict_GetItemWithError(layouts, (PyObject *)type);
    if (capsule == NULL) {
        if (PyErr_Occurred() || find_layout(type, layout) < 0)
            return -1;
        capsule = PyDict_GetItemWithError(layouts, (PyObject *)type);
        if (capsule == NULL)
            return PyErr_Occurred() ? -1 : 0;
    }
    *layout = capsule == Py_None ? NULL : PyCapsule_GetPointer(capsule, NULL);
    recent_layouts[at].type = type;
    recent_layouts[at].layout = *layout;
    return 0;
}

/* Values a copy may share with its original: nothing in them can change. The exact types that
 * most values have are asked first; int subclasses are the enum members, float ones keep a NaN's
 * bits. */
static int is_immutable(PyObject *value)
{
    PyTypeObject *type = Py_TYPE(value);
    Py_ssize_t i;
    if (type == &PyFloat_Type || type == &PyLong_Type || type == &PyBool_Type || value == Py_None)
        return 1;
    if (PyType_HasFeature(type, Py_TPFLAGS_LONG_SUBCLASS) || type == &PyUnicode_Type || type == &PyBytes_Type)
        return 1;
    if (type == &PyList_Type)
        return 0;
    if (type == &PyTuple_Type) {
        for (i = 0; i < PyTuple_GET_SIZE(value); i++)
            if (!is_immutable(PyTuple_GET_ITEM(value, i)))
                return 0;
        return 1;
    }
    return PyFloat_Check(value);
}

/* The values most slots hold, shared by a copy: a test the copy makes inline. */
static inline int is_plain_value(PyObject *value)
{
    PyTypeObject *type = Py_TYPE(value);
    return type == &PyFloat_Type || type == &PyLong_Type || type == &PyBool_Type || value == Py_None
        || PyType_HasFeature(type, Py_TPFLAGS_LONG_SUBCLASS) || type == &PyBytes_Type || type == &PyUnicode_Type;
}

static PyObject *copy_value(PyObject *value, int depth);

/* The last tuple a copy shared: a tuple cannot change, so it need not be looked through again. */
static PyObject *last_immutable_tuple;

/* A new instance of a slotted record with a copy of each slot; NULL with no exception set when
 * it holds something this does not copy, NULL with one set on failure. */
static PyObject *copy_record(PyObject *record, const slot_layout *layout, int depth)
{
    PyTypeObject *type = Py_TYPE(record);
    PyObject *copy = type->tp_alloc(type, 0);
    Py_ssize_t i;
    if (copy == NULL)
        return NULL;
    for (i = 0; i < layout->count; i++) {
        PyObject *value = *(PyObject **)((char *)record + layout->offsets[i]);
        PyObject *copied;
        if (value == NULL)
            continue;
        copied = is_plain_value(value) ? Py_NewRef(value) : copy_value(value, depth + 1);
        if (copied == NULL) {
            Py_DECREF(copy);
            return NULL;
        }
        *(PyObject **)((char *)copy + layout->offsets[i]) = copied;
    }
    return copy;
}

/* A value as a copied record holds it: the same object when immutable, else a copy (lists and
 * slotted records); NULL with no exception set when it cannot be copied. The exact types most
 * values have are asked first, then lists and records, then the rarer immutable kinds. */
static PyObject *copy_value(PyObject *value, int depth)
{
    PyTypeObject *type = Py_TYPE(value);
    slot_layout *layout;
    if (is_plain_value(value))
        return Py_NewRef(value);
    if (depth > MAX_CLONE_DEPTH)
        return NULL;
    if (type == &PyTuple_Type) {        /* a record's decoded_version: the same tuple in most */
        if (value != last_immutable_tuple) {
            if (!is_immutable(value))
                return NULL;
            Py_INCREF(value);           /* held, so that its address is no other tuple's */
            Py_XSETREF(last_immutable_tuple, value);
        }
        return Py_NewRef(value);
    }
    if (type == &PyList_Type) {
        Py_ssize_t i, n = PyList_GET_SIZE(value);
        PyObject *copy = PyList_New(n);
        if (copy == NULL)
            return NULL;
        for (i = 0; i < n; i++) {
            PyObject *item = PyList_GET_ITEM(value, i);
            item = is_plain_value(item) ? Py_NewRef(item) : copy_value(item, depth + 1);
            if (item == NULL) {
                Py_DECREF(copy);
                return NULL;
            }
            PyList_SET_ITEM(copy, i, item);
        }
        return copy;
    }
    /* A record's class is found in the recent layouts at once; is_immutable would first ask
     * PyFloat_Check, which walks the record class's MRO. A class with a layout has only slots
     * over object (find_layout), never an immutable built-in base. */
    if (layout_of(type, &layout) < 0)
        return NULL;
    if (layout != NULL)
        return copy_record(value, layout, depth);
    if (is_immutable(value)) {
        Py_INCREF(value);
        return value;
    }
    return NULL;
}

/* ---- the sub-packages seen last ------------------------------------------------------------ */

/* The bytes and version of the last package of one type code, and the record they gave: a copy
 * of its own, so that what a caller does to the records it gets never reaches it (NULL: none kept
 * yet, see the top of this file). */
#define LENT_COPIES 2
typedef struct {
    PyObject *record;
    char *body;            /* a copy of the package's bytes in a buffer of its own, reused: a */
    Py_ssize_t size;       /* moving package's bytes change in every state, and a bytes object */
    Py_ssize_t capacity;   /* made and freed for each would cost as much as a record */
    PyObject *version;     /* (major, minor, bugfix) */
    PyObject *lent[LENT_COPIES];   /* the copies of `record` handed out last (see take_back) */
    int next_lent;                 /* the one a new copy replaces */
} package_memo;

/* The last MEMO_WAYS packages of one type code with distinct bytes or versions, replaced in turn:
 * a capture may interleave robots (or a robot's forms), whose packages of a code differ. */
#define MEMO_WAYS 4
typedef struct {
    package_memo way[MEMO_WAYS];
    int next;                  /* the way a new package replaces */
} code_memo;

typedef struct {
    PyObject_HEAD
    PyObject *message_class;   /* the robot state's class (a PackageListMessage) */
    PyObject *forms;           /* its urwire._runtime.Forms */
    Py_ssize_t body_offset;    /* where its first sub-package starts */
    int message_type;          /* its type code, at type_offset */
    Py_ssize_t type_offset;
    PyObject *default_version; /* the version of a stream that has not said */
    Py_ssize_t slot_packages, slot_error, slot_raw, slot_implied;   /* the message's slot offsets */
    PyObject *fast_version;    /* the version whose Forms.fast table `fast` is */
    PyObject *fast;
    run_recipes *recipes;      /* the forms read by one fixed run, compiled on first use */
    /* Each code's recipe in `fast` once asked (NULL: none); asked[code] says it was. Forgotten
     * when `fast` is another version's: a moving package would otherwise cost two look-ups. */
    const run_recipe *recipe_of_code[MAX_CODES];
    char asked[MAX_CODES];
    code_memo memo[MAX_CODES];
} PackageStates;

/* Drops the copies lent out: they are copies of a record no longer kept. */
static void forget_lent(package_memo *memo)
{
    int i;
    for (i = 0; i < LENT_COPIES; i++)
        Py_CLEAR(memo->lent[i]);
    memo->next_lent = 0;
}

static void forget(package_memo *memo)
{
    forget_lent(memo);
    Py_CLEAR(memo->record);
    PyMem_Free(memo->body);
    memo->body = NULL;
    memo->size = memo->capacity = 0;
    Py_CLEAR(memo->version);
}

static void states_dealloc(PackageStates *self)
{
    int code, way;
    for (code = 0; code < MAX_CODES; code++)
        for (way = 0; way < MEMO_WAYS; way++)
            forget(&self->memo[code].way[way]);
    Py_CLEAR(self->message_class);
    Py_CLEAR(self->forms);
    Py_CLEAR(self->default_version);
    Py_CLEAR(self->fast_version);
    Py_CLEAR(self->fast);
    run_recipes_free(self->recipes);
    Py_TYPE(self)->tp_free((PyObject *)self);
}

/* The offset of the slot `name` that a class's instances keep; -1 with an exception set. */
static Py_ssize_t slot_offset(PyObject *cls, const char *name)
{
    PyObject *descr = PyObject_GetAttrString(cls, name);
    Py_ssize_t offset;
    if (descr == NULL)
        return -1;
    if (!Py_IS_TYPE(descr, &PyMemberDescr_Type)
        || ((PyMemberDescrObject *)descr)->d_member->type != T_OBJECT_EX) {
        PyErr_Format(PyExc_TypeError, "%R.%s is not a slot", cls, name);
        Py_DECREF(descr);
        return -1;
    }
    offset = ((PyMemberDescrObject *)descr)->d_member->offset;
    Py_DECREF(descr);
    return offset;
}

/* PackageStates(message_class, forms, body_offset, recipes=None, item_runs=None, *,
 *               message_type=16, type_offset=4, default_version=(5, 9, 0)):
 * message_class has exactly the slots packages, error, raw and implied_version
 * (urwire.message_kinds.PackageListMessage); recipes and item_runs are the generated RUN_RECIPES
 * and ITEM_RUNS (None: every new package is read by its Python decoder); the message is the one
 * whose type byte at type_offset is message_type. */
static int states_init(PackageStates *self, PyObject *args, PyObject *kwargs)
{
    static char *names[] = {"message_class", "forms", "body_offset", "recipes", "item_runs", "message_type",
                            "type_offset", "default_version", NULL};
    PyObject *cls, *forms, *recipes = Py_None, *item_runs = Py_None, *default_version = NULL;
    Py_ssize_t body_offset, type_offset = 4;
    int message_type = 16;
    slot_layout *layout;
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "O!On|OO$inO!", names, &PyType_Type, &cls, &forms, &body_offset,
                                     &recipes, &item_runs, &message_type, &type_offset, &PyTuple_Type,
                                     &default_version))
        return -1;
    if (type_offset < 0 || type_offset >= body_offset || message_type < 0 || message_type > 255) {
        PyErr_SetString(PyExc_ValueError, "the type byte must lie before the body, and be a byte");
        return -1;
    }
    self->message_type = message_type;
    self->type_offset = type_offset;
    if (default_version == NULL && (default_version = Py_BuildValue("(iii)", 5, 9, 0)) == NULL)
        return -1;
    else if (default_version != NULL)
        Py_INCREF(default_version);
    Py_XSETREF(self->default_version, default_version);
    if (body_offset < 0) {
        PyErr_SetString(PyExc_ValueError, "body_offset must not be negative");
        return -1;
    }
    if (layout_of((PyTypeObject *)cls, &layout) < 0)
        return -1;
    if (layout == NULL || layout->count != 4) {
        PyErr_Format(PyExc_TypeError, "%R: expected a slotted class of 4 attributes", cls);
        return -1;
    }
    if ((self->slot_packages = slot_offset(cls, "packages")) < 0 || (self->slot_error = slot_offset(cls, "error")) < 0
        || (self->slot_raw = slot_offset(cls, "raw")) < 0
        || (self->slot_implied = slot_offset(cls, "implied_version")) < 0)
        return -1;
    Py_INCREF(cls);
    Py_XSETREF(self->message_class, cls);
    Py_INCREF(forms);
    Py_XSETREF(self->forms, forms);
    self->body_offset = body_offset;
    Py_CLEAR(self->fast_version);
    Py_CLEAR(self->fast);
    run_recipes_free(self->recipes);
    self->recipes = NULL;
    if (recipes != Py_None && (self->recipes = run_recipes_new(recipes, item_runs)) == NULL)
        return -1;
    return 0;
}

static int same_version(PyObject *a, PyObject *b)
{
    return a == b ? 1 : PyObject_RichCompareBool(a, b, Py_EQ);
}

/* The version's {code: decoder} table (Forms.fast), kept while the version stays; a new
 * reference, NULL with an exception set. */
static PyObject *fast_table(PackageStates *self, PyObject *version)
{
    PyObject *table;
    if (self->fast_version != NULL) {
        int same = same_version(self->fast_version, version);
        if (same < 0)
            return NULL;
        if (same) {
            Py_INCREF(self->fast);
            return self->fast;
        }
    }
    PyObject *name = PyUnicode_InternFromString("fast");
    if (name == NULL)
        return NULL;
    table = PyObject_CallMethodOneArg(self->forms, name, version);
    Py_DECREF(name);
    if (table == NULL)
        return NULL;
    if (!PyDict_Check(table)) {
        PyErr_SetString(PyExc_TypeError, "Forms.fast() did not return a dict");
        Py_DECREF(table);
        return NULL;
    }
    Py_INCREF(version);
    Py_XSETREF(self->fast_version, version);
    Py_INCREF(table);
    Py_XSETREF(self->fast, table);
    memset(self->asked, 0, sizeof self->asked);
    return table;
}

/* Whether a package has the bytes and version a remembered one has: 1 or 0, -1 with an
 * exception set. */
static int same_package(const package_memo *memo, const char *body, Py_ssize_t size, PyObject *version)
{
    if (memo->body == NULL || memo->size != size || memcmp(memo->body, body, (size_t)size) != 0)
        return 0;
    return same_version(memo->version, version);
}

/* The remembered package of its code with these bytes and version, or NULL (with an exception
 * set when *failed). */
static package_memo *seen_before(code_memo *memo, const char *body, Py_ssize_t size, PyObject *version,
                                 int *failed)
{
    int way, same;
    *failed = 0;
    for (way = 0; way < MEMO_WAYS; way++) {
        if ((same = same_package(&memo->way[way], body, size, version)) < 0) {
            *failed = 1;
            return NULL;
        }
        if (same)
            return &memo->way[way];
    }
    return NULL;
}

/* The way a package not seen before is remembered in, in turn. */
static package_memo *new_way(code_memo *memo)
{
    package_memo *way = &memo->way[memo->next];
    memo->next = (memo->next + 1) % MEMO_WAYS;
    return way;
}

/* Whether a part of a copy lent out is still what a new copy of the kept part would be: the
 * very object (an immutable value shared), or a list or record that nothing else references
 * and that is untouched in turn. */
static int is_untouched(PyObject *copy, PyObject *kept, int depth);

static inline int same_part(PyObject *copy, PyObject *kept, int depth)
{
    if (copy == kept)
        return 1;
    if (copy == NULL || kept == NULL || Py_REFCNT(copy) != 1)
        return 0;
    return is_untouched(copy, kept, depth + 1);
}

static int is_untouched(PyObject *copy, PyObject *kept, int depth)
{
    PyTypeObject *type = Py_TYPE(kept);
    slot_layout *layout;
    Py_ssize_t i, n;
    if (Py_TYPE(copy) != type || depth > MAX_CLONE_DEPTH)
        return 0;
    if (type == &PyList_Type) {
        if ((n = PyList_GET_SIZE(kept)) != PyList_GET_SIZE(copy))
            return 0;
        for (i = 0; i < n; i++)
            if (!same_part(PyList_GET_ITEM(copy, i), PyList_GET_ITEM(kept, i), depth))
                return 0;
        return 1;
    }
    if (layout_of(type, &layout) < 0) {
        PyErr_Clear();               /* known since the copy was made: not reached */
        return 0;
    }
    if (layout == NULL)
        return 0;
    if (type->tp_weaklistoffset > 0 && *(PyObject **)((char *)copy + type->tp_weaklistoffset) != NULL)
        return 0;                    /* a weak reference could still reach it */
    for (i = 0; i < layout->count; i++) {
        Py_ssize_t at = layout->offsets[i];
        if (!same_part(*(PyObject **)((char *)copy + at), *(PyObject **)((char *)kept + at), depth))
            return 0;
    }
    return 1;
}

/* A copy lent out earlier that only this memo references now, untouched: the state it went out
 * in was dropped as it came. Handing it out again is a copy that costs neither making nor
 * freeing, and no one can tell it from a new one: nothing else reaches it or any part of it.
 * A borrowed reference, or NULL. */
static PyObject *take_back(package_memo *memo)
{
    int i;
    for (i = 0; i < LENT_COPIES; i++) {
        PyObject *lent = memo->lent[i];
        if (lent != NULL && Py_REFCNT(lent) == 1 && is_untouched(lent, memo->record, 0)) {
            memo->next_lent = (i + 1) % LENT_COPIES;
            return lent;
        }
    }
    return NULL;
}

/* A copy of the record kept for the last package of a code: one lent out before and taken back,
 * else a new one, lent in place of the oldest (a caller that reads a stream holds the state
 * before while the next is read, so two are lent). NULL with no exception set when none is kept
 * or it cannot be copied, NULL with one set on failure. */
static PyObject *copy_kept(package_memo *memo)
{
    PyObject *record, *copy;
    if (memo->record == NULL)
        return NULL;
    if ((copy = take_back(memo)) != NULL)
        return Py_NewRef(copy);
    record = Py_NewRef(memo->record);     /* held: a collection while copying may run other code */
    copy = copy_value(record, 0);
    Py_DECREF(record);
    if (copy != NULL) {
        Py_XSETREF(memo->lent[memo->next_lent], Py_NewRef(copy));
        memo->next_lent = (memo->next_lent + 1) % LENT_COPIES;
    }
    return copy;
}

/* Remembers a package's bytes and version, and a copy of its record unless `record` is NULL
 * (or it cannot be copied); -1 with an exception set on failure. */
static int remember(package_memo *memo, PyObject *record, const char *body, Py_ssize_t size, PyObject *version)
{
    PyObject *copy = NULL;
    if (record != NULL && (copy = copy_value(record, 0)) == NULL && PyErr_Occurred())
        return -1;
    if (memo->capacity < size || memo->body == NULL) {
        char *grown = PyMem_Malloc(size > 0 ? (size_t)size : 1);
        if (grown == NULL) {
            Py_XDECREF(copy);
            PyErr_NoMemory();
            return -1;
        }
        PyMem_Free(memo->body);
        memo->body = grown;
        memo->capacity = size;
    }
    if (memo->body != body)
        memcpy(memo->body, body, (size_t)size);
    memo->size = size;
    forget_lent(memo);
    Py_XSETREF(memo->record, copy);
    Py_INCREF(version);
    Py_XSETREF(memo->version, version);
    return 0;
}

/* The version's decoder of a type code in its Forms.fast table (borrowed), or NULL: none (an
 * exception set on failure). */
static PyObject *decoder_of(PyObject *fast, int code)
{
    PyObject *key = PyLong_FromLong(code), *decode;
    if (key == NULL)
        return NULL;
    decode = PyDict_GetItemWithError(fast, key);
    Py_DECREF(key);
    return decode;
}

/* The record of one sub-package read by the version's form, when it reads the package to its
 * last byte; NULL with no exception set otherwise (the caller decodes the message in Python). */
static PyObject *read_package(PyObject *fast, PyObject *buf, int code, Py_ssize_t body, Py_ssize_t stop,
                              PyObject *version)
{
    PyObject *decode = decoder_of(fast, code), *result, *record = NULL;
    Py_ssize_t used;
    if (decode == NULL)
        return NULL;
    Py_INCREF(decode);
    result = PyObject_CallFunction(decode, "OnnO", buf, body, stop, version);
    Py_DECREF(decode);
    if (result == NULL) {
        PyErr_Clear();             /* Python's decoder reports it: the message goes to Python */
        return NULL;
    }
    if (PyTuple_Check(result) && PyTuple_GET_SIZE(result) == 2) {
        used = PyLong_AsSsize_t(PyTuple_GET_ITEM(result, 1));
        if (used == -1 && PyErr_Occurred())
            PyErr_Clear();
        else if (used == stop)
            record = Py_NewRef(PyTuple_GET_ITEM(result, 0));
    }
    Py_DECREF(result);
    return record;
}

/* The record of a package whose version's form is one fixed run of exactly its size, read in C;
 * NULL with no exception set when the form is not such a run. */
static PyObject *read_run(PackageStates *self, PyObject *fast, PyObject *buf, int code, Py_ssize_t body,
                          Py_ssize_t stop, PyObject *version)
{
    PyObject *decode;
    const run_recipe *recipe;
    if (self->recipes == NULL)
        return NULL;
    if (!self->asked[code]) {
        if ((decode = decoder_of(fast, code)) == NULL)
            return NULL;
        if (run_recipe_of(self->recipes, decode, &recipe) < 0)
            return NULL;
        self->recipe_of_code[code] = recipe;
        self->asked[code] = 1;
    }
    recipe = self->recipe_of_code[code];
    return recipe == NULL ? NULL : run_read(recipe, buf, body, stop, version);
}

static int32_t load_i32(const unsigned char *p)
{
    return (int32_t)((uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | (uint32_t)p[3]);
}

/* A new message of the class with its packages and the other slots as PackageListMessage's
 * defaults: error None, raw b"", implied_version None. */
static PyObject *new_message(PackageStates *self, PyObject *packages)
{
    PyTypeObject *type = (PyTypeObject *)self->message_class;
    PyObject *msg = type->tp_alloc(type, 0), *empty;
    if (msg == NULL)
        return NULL;
    empty = PyBytes_FromStringAndSize(NULL, 0);
    if (empty == NULL) {
        Py_DECREF(msg);
        return NULL;
    }
    *(PyObject **)((char *)msg + self->slot_packages) = Py_NewRef(packages);
    *(PyObject **)((char *)msg + self->slot_error) = Py_NewRef(Py_None);
    *(PyObject **)((char *)msg + self->slot_raw) = empty;
    *(PyObject **)((char *)msg + self->slot_implied) = Py_NewRef(Py_None);
    return msg;
}

/* How many sub-packages a robot state's body frames into, or -1 when a length does not frame
 * one (the message is then Python's to report). */
static Py_ssize_t count_packages(const char *data, Py_ssize_t n, Py_ssize_t pos)
{
    Py_ssize_t count = 0, size;
    while (pos < n) {
        if (n - pos < PACKAGE_HEADER_SIZE)
            return -1;
        size = load_i32((const unsigned char *)data + pos);
        if (size < PACKAGE_HEADER_SIZE || size > n - pos)
            return -1;
        pos += size;
        count++;
    }
    return count;
}

/* A version as the decoders take it: (major, minor, bugfix) of ints, else NULL. */
static int is_version(PyObject *version)
{
    Py_ssize_t i;
    if (!PyTuple_CheckExact(version) || PyTuple_GET_SIZE(version) != 3)
        return 0;
    for (i = 0; i < 3; i++)
        if (!PyLong_CheckExact(PyTuple_GET_ITEM(version, i)))
            return 0;
    return 1;
}

/* decode(buf, version): the record of one framed message (buf: its bytes, its declared length
 * len(buf)) when it is a robot state read as `version` ((major, minor, bugfix), or None for
 * the default), or None when Python must read it: another message, other types of argument,
 * or what the top of this file says. */
static PyObject *states_decode(PackageStates *self, PyObject *const *args, Py_ssize_t nargs)
{
    PyObject *buf, *version, *fast, *packages, *msg = NULL;
    const char *data;
    Py_ssize_t n, pos, count, k;
    if (nargs != 2) {
        PyErr_SetString(PyExc_TypeError, "decode(buf, version)");
        return NULL;
    }
    if (self->forms == NULL) {
        PyErr_SetString(PyExc_RuntimeError, "PackageStates was not initialised");
        return NULL;
    }
    buf = args[0];
    version = args[1] == Py_None ? self->default_version : args[1];
    if (!PyBytes_CheckExact(buf) || PyBytes_GET_SIZE(buf) < self->body_offset || !is_version(version)
        || (unsigned char)PyBytes_AS_STRING(buf)[self->type_offset] != self->message_type)
        Py_RETURN_NONE;
    data = PyBytes_AS_STRING(buf);
    n = PyBytes_GET_SIZE(buf);
    if ((count = count_packages(data, n, self->body_offset)) < 0)
        Py_RETURN_NONE;
    fast = fast_table(self, version);
    if (fast == NULL)
        return NULL;
    packages = PyList_New(count);       /* filled in order; an unfilled slot is NULL until then */
    if (packages == NULL)
        goto done;
    for (pos = self->body_offset, k = 0; k < count; k++) {
        Py_ssize_t size, body, stop;
        int code, failed_look;
        package_memo *seen;
        PyObject *pkg;
        size = load_i32((const unsigned char *)data + pos);
        code = (unsigned char)data[pos + 4];
        body = pos + PACKAGE_HEADER_SIZE;
        stop = pos + size;
        seen = seen_before(&self->memo[code], data + body, stop - body, version, &failed_look);
        if (failed_look)
            goto failed;
        pkg = seen != NULL ? copy_kept(seen) : NULL;
        if (pkg == NULL) {
            PyObject *keep;
            if (PyErr_Occurred())
                goto failed;
            /* Made in C, a package is kept once its bytes come again: one that changes in every
             * state (a moving joint) then costs no copy. The Python decoder's, always. */
            pkg = read_run(self, fast, buf, code, body, stop, version);
            if (pkg == NULL && PyErr_Occurred())
                goto failed;
            keep = pkg != NULL && seen == NULL ? NULL : pkg;
            if (pkg == NULL)
                keep = pkg = read_package(fast, buf, code, body, stop, version);
            if (pkg == NULL) {
                if (PyErr_Occurred())
                    goto failed;
                goto to_python;
            }
            if (remember(seen != NULL ? seen : new_way(&self->memo[code]), keep, data + body, stop - body,
                         version) < 0) {
                Py_DECREF(pkg);
                goto failed;
            }
        }
        PyList_SET_ITEM(packages, k, pkg);
        pos = stop;
    }
    msg = new_message(self, packages);
    goto done;
to_python:
    msg = Py_NewRef(Py_None);
    goto done;
failed:
    msg = NULL;
done:
    Py_XDECREF(packages);
    Py_DECREF(fast);
    return msg;
}

static PyMethodDef states_methods[] = {
    {"decode", (PyCFunction)(void (*)(void))states_decode, METH_FASTCALL,
     "decode(buf, version) -> record or None: one framed robot state (bytes) as the record that "
     "pure Python makes, or None when pure Python must read it"},
    {NULL, NULL, 0, NULL},
};

static PyTypeObject PackageStatesType = {
    PyVarObject_HEAD_INIT(NULL, 0)
    .tp_name = "urwire._ccore.PackageStates",
    .tp_doc = "Robot states framed in C, each sub-package a copy of the record its bytes gave last.",
    .tp_basicsize = sizeof(PackageStates),
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_new = PyType_GenericNew,
    .tp_init = (initproc)states_init,
    .tp_dealloc = (destructor)states_dealloc,
    .tp_methods = states_methods,
};

int records_add_types(PyObject *module)
{
    if (layouts == NULL && (layouts = PyDict_New()) == NULL)
        return -1;
    if (PyType_Ready(&PackageStatesType) < 0)
        return -1;
    Py_INCREF(&PackageStatesType);
    if (PyModule_AddObject(module, "PackageStates", (PyObject *)&PackageStatesType) < 0) {
        Py_DECREF(&PackageStatesType);
        return -1;
    }
    return 0;
}
