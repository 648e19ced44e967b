/* urwire._ccore.PrimaryColumns (columns.c): the dataset's column buffers of a raw primary stream. */
#ifndef URWIRE_CCORE_COLUMNS_H
#define URWIRE_CCORE_COLUMNS_H

#include <Python.h>

extern PyTypeObject PrimaryColumnsType;

#endif
