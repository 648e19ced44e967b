/* urwire._ccore's record objects (records.c): the types it adds to the module. */
#ifndef URWIRE_CCORE_RECORDS_H
#define URWIRE_CCORE_RECORDS_H
#include <Python.h>

/* Adds PackageStates to the module; -1 with an exception set. */
int records_add_types(PyObject *module);

#endif
