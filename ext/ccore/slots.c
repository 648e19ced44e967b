/* The slots of the generated record classes (ccore_slots.h). */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <structmember.h>

#include "ccore_slots.h"

static int is_object_slot(PyObject *descr)
{
    return Py_IS_TYPE(descr, &PyMemberDescr_Type) && ((PyMemberDescrObject *)descr)->d_member->type == T_OBJECT_EX;
}

Py_ssize_t ccore_slot_of(PyTypeObject *cls, PyObject *name)
{
    PyObject *descr = PyObject_GetAttr((PyObject *)cls, name);
    Py_ssize_t offset = 0;
    if (descr == NULL) {
        if (!PyErr_ExceptionMatches(PyExc_AttributeError))
            return -1;
        PyErr_Clear();
        return 0;
    }
    if (is_object_slot(descr))
        offset = ((PyMemberDescrObject *)descr)->d_member->offset;
    Py_DECREF(descr);
    return offset;
}

int ccore_slot_is_visible(PyTypeObject *cls, PyObject *name, PyObject *descr)
{
    PyObject *found = PyObject_GetAttr((PyObject *)cls, name);
    if (found == NULL) {
        PyErr_Clear();
        return 0;
    }
    Py_DECREF(found);
    return found == descr;
}

Py_ssize_t ccore_slot_count(PyTypeObject *cls)
{
    PyObject *mro = cls->tp_mro;
    Py_ssize_t i, count = 0;
    if (cls->tp_dictoffset != 0 || cls->tp_itemsize != 0 || mro == NULL
        || PyObject_HasAttrString((PyObject *)cls, "__post_init__"))
        return -1;
    for (i = 0; i < PyTuple_GET_SIZE(mro); i++) {
        PyObject *key, *value;
        Py_ssize_t at = 0;
        PyTypeObject *base = (PyTypeObject *)PyTuple_GET_ITEM(mro, i);
        if (base == &PyBaseObject_Type)
            continue;
        while (PyDict_Next(base->tp_dict, &at, &key, &value))
            if (is_object_slot(value) && ccore_slot_is_visible(cls, key, value))
                count++;
    }
    return count;
}
