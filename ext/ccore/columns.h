/* urwire._ccore.PrimaryColumns and PrimaryStream (columns.c): the dataset's column buffers of a
 * primary/secondary stream, raw or a capture's. */
#ifndef URWIRE_CCORE_COLUMNS_H
#define URWIRE_CCORE_COLUMNS_H

#include <Python.h>

/* Adds PrimaryColumns and PrimaryStream to the module; -1 with an exception set. */
int columns_add_types(PyObject *module);

#endif
