/* A primary stream's framer as PrimaryJsonLines and PrimaryStream open and restart it (ccore_framer.h). */
#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include "ccore_framer.h"

int ccore_framer_open(urwire_framer *framer, uint8_t **buffer, PyObject *args, PyObject *kwargs)
{
    static char *names[] = {"version_hint", NULL};
    const char *hint = NULL;
    urwire_sw_version version = URWIRE_DEFAULT_VERSION;
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "|z", names, &hint))
        return -1;
    if (hint && !urwire_parse_version(hint, &version)) {
        PyErr_Format(PyExc_ValueError, "not a software version: %s", hint);
        return -1;
    }
    PyMem_Free(*buffer);
    if (!(*buffer = PyMem_Malloc(URWIRE_FRAMER_MIN_BUFFER))) {
        PyErr_NoMemory();
        return -1;
    }
    urwire_framer_init(framer, *buffer, URWIRE_FRAMER_MIN_BUFFER, version);
    return 0;
}

void ccore_framer_restart(urwire_framer *f, uint64_t offset)
{
    urwire_framer_restart(f, offset);
}
