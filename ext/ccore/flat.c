/* Records made from one struct's unpacked values, for the interfaces whose layouts are a single
 * run of plain values: real-time packets (30003) and RTDE data packages.
 *
 * FlatRecords(layouts) takes the generated FLAT_LAYOUTS of a sized-packets interface ({class:
 * (struct, ((name, first, stop or None), ...))}) and makes a packet's record as its decoder does,
 * cls(v[0], v[1], v[2:8], ...) with v = struct.unpack_from(packet, offset), past __init__:
 * the same values, tuples for the slices, `extra` b"". */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <structmember.h>

#include "ccore_flat.h"
#include "ccore_slots.h"

#define MAX_FIELDS 256

/* A class's layout, compiled: its struct, and each attribute's slot and values. */
typedef struct {
    PyObject *st;              /* the struct.Struct */
    Py_ssize_t count;
    Py_ssize_t slot[MAX_FIELDS];
    Py_ssize_t first[MAX_FIELDS], stop[MAX_FIELDS];   /* stop -1: one value */
    Py_ssize_t slot_extra;
} flat_layout;

typedef struct {
    PyObject_HEAD
    PyObject *layouts;         /* FLAT_LAYOUTS */
    PyObject *compiled;        /* {class: PyCapsule of flat_layout, or None} */
    PyObject *unpack_from;     /* the name, interned */
} FlatRecords;

static void free_layout(PyObject *capsule)
{
    flat_layout *l = PyCapsule_GetPointer(capsule, NULL);
    if (l != NULL)
        Py_XDECREF(l->st);
    PyMem_Free(l);
}

/* A layout from (struct, fields); 0 when this cannot make the class's records, -1 with an
 * exception set. */
static int compile_layout(PyObject *cls, PyObject *spec, flat_layout *l)
{
    PyObject *fields, *extra;
    Py_ssize_t i;
    if (!PyType_Check(cls) || !PyTuple_Check(spec) || PyTuple_GET_SIZE(spec) != 2
        || !PyTuple_Check(PyTuple_GET_ITEM(spec, 1)))
        return 0;
    fields = PyTuple_GET_ITEM(spec, 1);
    l->count = PyTuple_GET_SIZE(fields);
    if (l->count > MAX_FIELDS)
        return 0;
    l->st = Py_NewRef(PyTuple_GET_ITEM(spec, 0));
    for (i = 0; i < l->count; i++) {
        PyObject *f = PyTuple_GET_ITEM(fields, i);
        if (!PyTuple_Check(f) || PyTuple_GET_SIZE(f) != 3 || !PyLong_Check(PyTuple_GET_ITEM(f, 1)))
            return 0;
        if ((l->slot[i] = ccore_slot_of((PyTypeObject *)cls, PyTuple_GET_ITEM(f, 0))) <= 0)
            return (int)l->slot[i];
        l->first[i] = PyLong_AsSsize_t(PyTuple_GET_ITEM(f, 1));
        l->stop[i] = PyTuple_GET_ITEM(f, 2) == Py_None ? -1 : PyLong_AsSsize_t(PyTuple_GET_ITEM(f, 2));
        if (PyErr_Occurred())
            return -1;
        if (l->first[i] < 0 || (l->stop[i] != -1 && l->stop[i] < l->first[i]))
            return 0;
    }
    if ((extra = PyUnicode_InternFromString("extra")) == NULL)
        return -1;
    l->slot_extra = ccore_slot_of((PyTypeObject *)cls, extra);
    Py_DECREF(extra);
    if (l->slot_extra <= 0)
        return (int)l->slot_extra;
    return ccore_slot_count((PyTypeObject *)cls) == l->count + 1;   /* every attribute set: the fields, extra */
}

/* The compiled layout of a class, or NULL with no exception set when it has none. */
static const flat_layout *layout_for(FlatRecords *self, PyObject *cls)
{
    PyObject *found = PyDict_GetItemWithError(self->compiled, cls), *spec, *capsule;
    flat_layout *l;
    int ok;
    if (found != NULL)
        return found == Py_None ? NULL : PyCapsule_GetPointer(found, NULL);
    if (PyErr_Occurred())
        return NULL;
    spec = PyDict_GetItemWithError(self->layouts, cls);
    if (spec == NULL) {
        if (!PyErr_Occurred())
            PyDict_SetItem(self->compiled, cls, Py_None);
        return NULL;
    }
    l = PyMem_Calloc(1, sizeof *l);
    if (l == NULL) {
        PyErr_NoMemory();
        return NULL;
    }
    capsule = PyCapsule_New(l, NULL, free_layout);
    if (capsule == NULL) {
        PyMem_Free(l);
        return NULL;
    }
    Py_INCREF(spec);
    ok = compile_layout(cls, spec, l);
    Py_DECREF(spec);
    if (ok < 0 || PyDict_SetItem(self->compiled, cls, ok ? capsule : Py_None) < 0) {
        Py_DECREF(capsule);
        return NULL;
    }
    Py_DECREF(capsule);
    return ok ? l : NULL;
}

static int flat_init(FlatRecords *self, PyObject *args, PyObject *kwargs)
{
    static char *names[] = {"layouts", NULL};
    PyObject *layouts;
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "O!", names, &PyDict_Type, &layouts))
        return -1;
    Py_INCREF(layouts);
    Py_XSETREF(self->layouts, layouts);
    Py_XSETREF(self->compiled, PyDict_New());
    Py_XSETREF(self->unpack_from, PyUnicode_InternFromString("unpack_from"));
    return self->compiled != NULL && self->unpack_from != NULL ? 0 : -1;
}

static void flat_dealloc(FlatRecords *self)
{
    Py_CLEAR(self->layouts);
    Py_CLEAR(self->compiled);
    Py_CLEAR(self->unpack_from);
    Py_TYPE(self)->tp_free((PyObject *)self);
}

/* decode(cls, packet, offset): what cls.decode(packet, offset) returns, or None when cls has no
 * layout here (its decoder then reads it). struct's errors (a packet too short) are raised as
 * the decoder raises them. */
static PyObject *flat_decode(FlatRecords *self, PyObject *const *args, Py_ssize_t nargs)
{
    const flat_layout *l;
    PyObject *call[3], *flat, *record;
    Py_ssize_t i, n;
    if (nargs != 3) {
        PyErr_SetString(PyExc_TypeError, "decode(cls, packet, offset)");
        return NULL;
    }
    if (self->compiled == NULL) {
        PyErr_SetString(PyExc_RuntimeError, "FlatRecords was not initialised");
        return NULL;
    }
    if ((l = layout_for(self, args[0])) == NULL) {
        if (PyErr_Occurred())
            return NULL;
        Py_RETURN_NONE;
    }
    call[0] = l->st;
    call[1] = args[1];
    call[2] = args[2];
    flat = PyObject_VectorcallMethod(self->unpack_from, call, 3, NULL);   /* struct.unpack_from(packet, offset) */
    if (flat == NULL)
        return NULL;
    n = PyTuple_Check(flat) ? PyTuple_GET_SIZE(flat) : -1;
    record = ((PyTypeObject *)args[0])->tp_alloc((PyTypeObject *)args[0], 0);
    if (record == NULL) {
        Py_DECREF(flat);
        return NULL;
    }
    for (i = 0; i < l->count; i++) {
        PyObject *value;
        if (l->first[i] >= n || l->stop[i] > n) {
            PyErr_SetString(PyExc_ValueError, "a layout's field lies past its struct's values");
            value = NULL;
        } else if (l->stop[i] < 0) {
            value = Py_NewRef(PyTuple_GET_ITEM(flat, l->first[i]));
        } else {
            value = PyTuple_GetSlice(flat, l->first[i], l->stop[i]);
        }
        if (value == NULL) {
            Py_DECREF(flat);
            Py_DECREF(record);
            return NULL;
        }
        *(PyObject **)((char *)record + l->slot[i]) = value;
    }
    Py_DECREF(flat);
    *(PyObject **)((char *)record + l->slot_extra) = PyBytes_FromStringAndSize(NULL, 0);
    if (*(PyObject **)((char *)record + l->slot_extra) == NULL) {
        Py_DECREF(record);
        return NULL;
    }
    return record;
}

static PyMethodDef flat_methods[] = {
    {"decode", (PyCFunction)(void (*)(void))flat_decode, METH_FASTCALL,
     "decode(cls, packet, offset) -> record or None: cls.decode(packet, offset), made in C"},
    {NULL, NULL, 0, NULL},
};

static PyTypeObject FlatRecordsType = {
    PyVarObject_HEAD_INIT(NULL, 0)
    .tp_name = "urwire._ccore.FlatRecords",
    .tp_doc = "Records of layouts that are one run of plain values (FLAT_LAYOUTS), made in C.",
    .tp_basicsize = sizeof(FlatRecords),
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_new = PyType_GenericNew,
    .tp_init = (initproc)flat_init,
    .tp_dealloc = (destructor)flat_dealloc,
    .tp_methods = flat_methods,
};

int flat_add_types(PyObject *module)
{
    if (PyType_Ready(&FlatRecordsType) < 0)
        return -1;
    Py_INCREF(&FlatRecordsType);
    if (PyModule_AddObject(module, "FlatRecords", (PyObject *)&FlatRecordsType) < 0) {
        Py_DECREF(&FlatRecordsType);
        return -1;
    }
    return 0;
}
