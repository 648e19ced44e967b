/* urwire._ccore.CaptureStreams (capture_streams.c): a capture's TCP streams, read and
 * reassembled in C (runtime/c/capture). */
#ifndef URWIRE_CCORE_CAPTURE_STREAMS_H
#define URWIRE_CCORE_CAPTURE_STREAMS_H

#include <Python.h>

/* Adds CaptureStreams to the module; -1 with an exception set. */
int capture_streams_add_types(PyObject *module);

#endif
