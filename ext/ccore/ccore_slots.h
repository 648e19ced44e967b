/* The slots of the generated record classes, as records.c, runs.c and flat.c fill them past
 * __init__ (slots.c). */
#ifndef URWIRE_CCORE_SLOTS_H
#define URWIRE_CCORE_SLOTS_H
#include <Python.h>

/* The slot offset of attribute `name` of cls; 0 (never a slot's offset) when it is not a slot,
 * -1 with an exception set. */
Py_ssize_t ccore_slot_of(PyTypeObject *cls, PyObject *name);

/* Whether descr, found in the dict of cls or of one of its bases, is what cls.name gives: a
 * slot that a subclass declares again hides its base's, which instances then leave empty
 * (dataclass(slots=True) on Python 3.10 declares every base field again). */
int ccore_slot_is_visible(PyTypeObject *cls, PyObject *name, PyObject *descr);

/* How many attributes an instance of cls holds: its slots and its bases' that no subclass hides, when that is all it
 * holds (no __dict__) and its __init__ only sets them (no __post_init__: made past __init__,
 * its records would miss what that adds); -1 otherwise. */
Py_ssize_t ccore_slot_count(PyTypeObject *cls);

#endif
