/* urwire._ccore's records of one-run layouts (flat.c): real-time packets, RTDE data packages. */
#ifndef URWIRE_CCORE_FLAT_H
#define URWIRE_CCORE_FLAT_H
#include <Python.h>

/* Adds FlatRecords to the module; -1 with an exception set. */
int flat_add_types(PyObject *module);

#endif
