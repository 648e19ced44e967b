/* A primary stream's framer as PrimaryJsonLines and PrimaryStream open and restart it (framer.c). */
#ifndef URWIRE_CCORE_FRAMER_H
#define URWIRE_CCORE_FRAMER_H
#include <Python.h>

#include "urwire.h"

/* Opens (or opens again) a framer from the arguments (version_hint=None): version_hint is a text
 * such as "5.25.1", checked by the caller (urwire.arguments.parse_version) and read again here by
 * the C parser. *buffer is freed and made anew, URWIRE_FRAMER_MIN_BUFFER bytes: it frames every
 * legal message. 0, or -1 with an exception set. */
int ccore_framer_open(urwire_framer *framer, uint8_t **buffer, PyObject *args, PyObject *kwargs);

/* After the stream lost bytes, and once the framer's tail was finished and its records taken:
 * framing starts afresh at stream offset `offset`, the version learnt kept (framer.py's
 * Framer.restart). */
void ccore_framer_restart(urwire_framer *framer, uint64_t offset);

#endif
