/* urwire._ccore: the generated C parser (generated/c/urwire.c) and the C runtime's canonical JSON
 * writer (runtime/c/json/json.c), reachable from Python.
 *
 * PrimaryJsonLines frames a primary/secondary stream fed in chunks of any size and gives back the
 * canonical JSON Lines of its records, the same bytes as `urwire.to_json_line` of each record the
 * pure-Python Framer makes, with the C parser and writer doing the work. The Python side that
 * picks it over pure Python is urwire/backends.py; a capture's primary conversations take one each
 * (urwire/capture_json.py), which restart() and announced serve. */
#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "capture_streams.h"
#include "ccore_flat.h"
#include "ccore_framer.h"
#include "ccore_records.h"
#include "columns.h"
#include "json.h"
#include "records.h"
#include "urwire.h"

typedef struct {
    PyObject_HEAD
    urwire_framer framer;
    uint8_t *framer_buffer;         /* URWIRE_FRAMER_MIN_BUFFER bytes: frames every legal message */
    json_writer *writer;            /* large (its kept package texts): on the heap */
    urwire_visitor visitor;
    int errors;                     /* a record written so far held an error */
    int finished;
    PyObject *head;                 /* bytes each line starts with in place of its "{", else NULL */
} PrimaryJsonLines;

static void lines_dealloc(PrimaryJsonLines *self)
{
    PyMem_Free(self->framer_buffer);
    PyMem_Free(self->writer);
    Py_XDECREF(self->head);
    Py_TYPE(self)->tp_free((PyObject *)self);
}

/* PrimaryJsonLines(version_hint=None): as ccore_framer_open takes it. */
static int lines_init(PrimaryJsonLines *self, PyObject *args, PyObject *kwargs)
{
    PyMem_Free(self->writer);
    if (!(self->writer = PyMem_Calloc(1, sizeof *self->writer))) {
        PyErr_NoMemory();
        return -1;
    }
    if (ccore_framer_open(&self->framer, &self->framer_buffer, args, kwargs) < 0)
        return -1;
    self->visitor = json_visitor(self->writer);
    self->errors = 0;
    self->finished = 0;
    return 0;
}

/* The lines the writer printed into a memory stream, as bytes, each line's "{" replaced by `head`
 * when it is not NULL (copied as the bytes are made: no second pass); NULL with an exception set.
 * *text and *size are the stream's, final once it is closed. */
static PyObject *take_lines(FILE *out, char **text, size_t *size, PyObject *head)
{
    PyObject *lines;
    const char *from, *end, *eol;
    char *to;
    size_t n = 0, h;
    if (fclose(out) != 0) {
        free(*text);
        return PyErr_SetFromErrno(PyExc_OSError);
    }
    if (head == NULL || *size == 0) {
        lines = PyBytes_FromStringAndSize(*text ? *text : "", (Py_ssize_t)*size);
        free(*text);
        return lines;
    }
    h = (size_t)PyBytes_GET_SIZE(head);
    for (from = *text, end = *text + *size; (eol = memchr(from, '\n', (size_t)(end - from))) != NULL; from = eol + 1)
        n++;
    lines = PyBytes_FromStringAndSize(NULL, (Py_ssize_t)(*size + n * h - n));
    if (lines != NULL) {
        to = PyBytes_AS_STRING(lines);
        for (from = *text; (eol = memchr(from, '\n', (size_t)(end - from))) != NULL; from = eol + 1) {
            memcpy(to, PyBytes_AS_STRING(head), h);
            memcpy(to + h, from + 1, (size_t)(eol - from));     /* after the line's "{", its newline too */
            to += h + (size_t)(eol - from);
        }
    }
    free(*text);
    return lines;
}

/* Feeds data (NULL: the stream has ended) and prints every record that is then ready. The GIL
 * stays held: two threads feeding one object would otherwise share its framer and writer. */
static PyObject *print_records(PrimaryJsonLines *self, const uint8_t *data, size_t n)
{
    char *text = NULL;
    size_t size = 0, off = 0;
    FILE *out;
    if (!self->writer) {
        PyErr_SetString(PyExc_RuntimeError, "PrimaryJsonLines was not initialised");
        return NULL;
    }
    if (self->finished) {
        PyErr_SetString(PyExc_ValueError, "the stream has ended (close() was called)");
        return NULL;
    }
    out = open_memstream(&text, &size);
    if (!out)
        return PyErr_SetFromErrno(PyExc_OSError);
    self->writer->out = out;
    if (data) {
        while (off < n) {
            off += urwire_framer_feed(&self->framer, data + off, n - off);
            self->errors |= print_ready_records(&self->framer, &self->visitor, self->writer);
        }
    } else {
        urwire_framer_finish(&self->framer);
        self->errors |= print_ready_records(&self->framer, &self->visitor, self->writer);
        self->finished = 1;
    }
    self->writer->out = NULL;
    return take_lines(out, &text, &size, self->head);
}

static PyObject *lines_feed(PrimaryJsonLines *self, PyObject *arg)
{
    Py_buffer view;
    PyObject *lines;
    if (PyObject_GetBuffer(arg, &view, PyBUF_SIMPLE) != 0)
        return NULL;
    lines = print_records(self, view.buf, (size_t)view.len);
    PyBuffer_Release(&view);
    return lines;
}

static PyObject *lines_close(PrimaryJsonLines *self, PyObject *Py_UNUSED(ignored))
{
    return print_records(self, NULL, 0);
}

/* restart(offset): the stream lost bytes; what is held is given up (close()'s lines) and framing
 * starts afresh at stream offset `offset`, the version learnt kept (framer.py's Framer.restart,
 * tools/urwire-decode/capture_json.c's restart). */
static PyObject *lines_restart(PrimaryJsonLines *self, PyObject *arg)
{
    unsigned long long offset = PyLong_AsUnsignedLongLong(arg);
    PyObject *lines;
    if (offset == (unsigned long long)-1 && PyErr_Occurred())
        return NULL;
    if (!(lines = print_records(self, NULL, 0)))
        return NULL;
    ccore_framer_restart(&self->framer, offset);
    self->finished = 0;
    return lines;
}

/* set_head(head): each line from now on starts with the bytes `head` in place of its "{" (the
 * envelope of a capture's record: "{" and its keys, the record's own to follow). */
static PyObject *lines_set_head(PrimaryJsonLines *self, PyObject *head)
{
    if (!PyBytes_Check(head) || PyBytes_GET_SIZE(head) < 1) {
        PyErr_SetString(PyExc_TypeError, "set_head(head): bytes, not empty");
        return NULL;
    }
    Py_INCREF(head);
    Py_XSETREF(self->head, head);
    Py_RETURN_NONE;
}

/* The version the stream's last Version message set, as (major, minor, bugfix), else None
 * (framer.py's Framer.announced). */
static PyObject *lines_announced(PrimaryJsonLines *self, void *Py_UNUSED(closure))
{
    const urwire_sw_version *v = &self->framer.version;
    if (!self->writer || !self->framer.version_seen)
        Py_RETURN_NONE;
    return Py_BuildValue("(iii)", v->major, v->minor, v->bugfix);
}

static PyObject *lines_errors(PrimaryJsonLines *self, void *Py_UNUSED(closure))
{
    return PyBool_FromLong(self->errors);
}

static PyMethodDef lines_methods[] = {
    {"feed", (PyCFunction)lines_feed, METH_O,
     "feed(data) -> bytes: the JSON Lines of the records the bytes so far complete"},
    {"close", (PyCFunction)lines_close, METH_NOARGS,
     "close() -> bytes: the JSON Lines of what the end of the stream completes (a cut tail's fault)"},
    {"set_head", (PyCFunction)lines_set_head, METH_O,
     "set_head(head): each line from now on starts with the bytes head in place of its '{'"},
    {"restart", (PyCFunction)lines_restart, METH_O,
     "restart(offset) -> bytes: close()'s lines, then framing afresh at stream offset `offset`, the version kept"},
    {NULL, NULL, 0, NULL},
};

static PyGetSetDef lines_getset[] = {
    {"errors", (getter)lines_errors, NULL, "whether a record written so far held an error", NULL},
    {"announced", (getter)lines_announced, NULL,
     "the version the last Version message set, (major, minor, bugfix), else None", NULL},
    {NULL, NULL, NULL, NULL, NULL},
};

static PyTypeObject PrimaryJsonLinesType = {
    PyVarObject_HEAD_INIT(NULL, 0)
    .tp_name = "urwire._ccore.PrimaryJsonLines",
    .tp_doc = "A primary/secondary stream in, its canonical JSON Lines out (the C parser and writer).",
    .tp_basicsize = sizeof(PrimaryJsonLines),
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_new = PyType_GenericNew,
    .tp_init = (initproc)lines_init,
    .tp_dealloc = (destructor)lines_dealloc,
    .tp_methods = lines_methods,
    .tp_getset = lines_getset,
};

static struct PyModuleDef ccore_module = {
    PyModuleDef_HEAD_INIT,
    .m_name = "urwire._ccore",
    .m_doc = "The generated C parser of the primary/secondary interface, for urwire's Python package.",
    .m_size = -1,
};

PyMODINIT_FUNC PyInit__ccore(void)
{
    PyObject *module;
    if (PyType_Ready(&PrimaryJsonLinesType) < 0)
        return NULL;
    module = PyModule_Create(&ccore_module);
    if (!module)
        return NULL;
    Py_INCREF(&PrimaryJsonLinesType);
    if (PyModule_AddObject(module, "PrimaryJsonLines", (PyObject *)&PrimaryJsonLinesType) < 0) {
        Py_DECREF(&PrimaryJsonLinesType);
        Py_DECREF(module);
        return NULL;
    }
    if (records_add_types(module) < 0 || flat_add_types(module) < 0 || columns_add_types(module) < 0 ||
        capture_streams_add_types(module) < 0) {
        Py_DECREF(module);
        return NULL;
    }
    return module;
}
