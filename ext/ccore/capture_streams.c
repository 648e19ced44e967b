/* urwire._ccore.CaptureStreams: the items of python/urwire/capture.py's timed_streams, made by
 * the C capture reader (runtime/c/capture/capture.h). capture.py gives the classes of its faults
 * (Gap, Differs, CaptureFault), so that both readers hand out the same objects.
 *
 * On the `joined` ports, the bytes of one direction that come in a row within one feed (no other
 * item between them) are one item, a Segments (ccore_segments.h) that keeps each segment's end
 * and time: a reader of a large capture then takes a Python step per run, not per segment. */
#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <string.h>

#include "capture.h"
#include "capture_streams.h"
#include "ccore_segments.h"
#include "growing.h"

/* The bytes being joined: one direction of one conversation. */
typedef struct {
    urwire_capture_conversation *conversation;  /* NULL: none */
    bool from_robot, ended;
    double time;                                /* the last segment's */
    uint8_t *data;
    size_t length, capacity;
    ccore_segment_stamp *stamps;
    size_t n_stamps, stamps_capacity;
} run;

typedef struct {
    PyObject_HEAD
    urwire_capture *capture;
    PyObject *gap, *differs, *fault, *segments;     /* the classes */
    uint8_t joined[65536 / 8];          /* a bit per robot port whose bytes are joined */
    run run;
    PyObject *items;                    /* the list being filled by a feed or finish */
} CaptureStreams;

static void release_key(urwire_capture_conversation *conversation)
{
    Py_CLEAR(conversation->user);
}

static void streams_dealloc(CaptureStreams *self)
{
    if (self->capture != NULL) {
        urwire_capture_each_conversation(self->capture, release_key);
        urwire_capture_free(self->capture);
    }
    Py_XDECREF(self->gap);
    Py_XDECREF(self->differs);
    Py_XDECREF(self->fault);
    Py_XDECREF(self->segments);
    Py_XDECREF(self->items);
    free(self->run.data);
    free(self->run.stamps);
    Py_TYPE(self)->tp_free((PyObject *)self);
}

/* The ports of an iterable of ints into `ports` (at most 65536); -1 with an exception set. */
static Py_ssize_t ports_of(PyObject *iterable, uint16_t *ports)
{
    PyObject *iterator = PyObject_GetIter(iterable), *item;
    Py_ssize_t n = 0;
    if (iterator == NULL)
        return -1;
    while ((item = PyIter_Next(iterator)) != NULL) {
        long port = PyLong_AsLong(item);
        Py_DECREF(item);
        if (port == -1 && PyErr_Occurred())
            break;
        if (port < 0 || port > 65535) {
            PyErr_Format(PyExc_ValueError, "not a TCP port: %ld", port);
            break;
        }
        if (n < 65536)
            ports[n++] = (uint16_t)port;
    }
    Py_DECREF(iterator);
    return PyErr_Occurred() ? -1 : n;
}

/* CaptureStreams(ports, both_ways, others, Gap, Differs, CaptureFault, joined=(), Segments=None) */
static int streams_init(CaptureStreams *self, PyObject *args, PyObject *kwargs)
{
    static char *names[] = {"ports", "both_ways", "others", "gap", "differs", "fault", "joined", "segments", NULL};
    PyObject *ports, *both_ways, *gap, *differs, *fault, *joined = NULL, *segments = Py_None;
    int others;
    uint16_t *read = NULL, *both = NULL;
    Py_ssize_t n_read, n_both, n_joined = 0, i;
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "OOpOOO|OO", names, &ports, &both_ways, &others, &gap, &differs,
                                     &fault, &joined, &segments))
        return -1;
    if (self->capture != NULL) {
        PyErr_SetString(PyExc_RuntimeError, "CaptureStreams is made once");
        return -1;
    }
    read = PyMem_Malloc(65536 * sizeof *read);
    both = PyMem_Malloc(65536 * sizeof *both);
    if (read == NULL || both == NULL) {
        PyMem_Free(read);
        PyMem_Free(both);
        PyErr_NoMemory();
        return -1;
    }
    if (joined != NULL) {       /* read into `both` first, which is free until both_ways is read */
        n_joined = ports_of(joined, both);
        if (n_joined > 0 && segments == Py_None) {
            PyErr_SetString(PyExc_TypeError, "CaptureStreams: joined ports need the Segments class");
            n_joined = -1;
        }
        for (i = 0; i < n_joined; i++)
            self->joined[both[i] >> 3] |= (uint8_t)(1u << (both[i] & 7));
    }
    n_read = n_joined < 0 ? -1 : ports_of(ports, read);
    n_both = n_read < 0 ? -1 : ports_of(both_ways, both);
    if (n_both >= 0 && (self->capture = urwire_capture_new(read, (size_t)n_read, both, (size_t)n_both,
                                                           others != 0)) == NULL)
        PyErr_NoMemory();
    PyMem_Free(read);
    PyMem_Free(both);
    if (self->capture == NULL)
        return -1;
    Py_INCREF(gap);
    Py_INCREF(differs);
    Py_INCREF(fault);
    self->gap = gap;
    self->differs = differs;
    self->fault = fault;
    Py_INCREF(segments);
    self->segments = segments;
    return 0;
}

/* The conversation's key tuple (robot address, robot port, client address, client port), made once. */
static PyObject *key_of(urwire_capture_conversation *conversation)
{
    if (conversation->user == NULL)
        conversation->user = Py_BuildValue("(sIsI)", conversation->robot, (unsigned)conversation->robot_port,
                                           conversation->client, (unsigned)conversation->client_port);
    return conversation->user;
}

/* Appends the item (key, from robot, piece, ended, time) to the list; -2 with an exception set. */
static int append(CaptureStreams *self, urwire_capture_conversation *conversation, bool from_robot, PyObject *piece,
                  bool ended, double time)
{
    PyObject *key = key_of(conversation), *entry;
    int rc;
    if (key == NULL) {
        Py_DECREF(piece);
        return -2;
    }
    entry = Py_BuildValue("(OONOd)", key, from_robot ? Py_True : Py_False, piece, ended ? Py_True : Py_False, time);
    if (entry == NULL)
        return -2;
    rc = PyList_Append(self->items, entry);
    Py_DECREF(entry);
    return rc < 0 ? -2 : 0;
}

/* The run, if any, as one item: Segments(data, stamps). 0, or -2 with an exception set. */
static int close_run(CaptureStreams *self)
{
    run *r = &self->run;
    urwire_capture_conversation *conversation = r->conversation;
    PyObject *piece;
    if (conversation == NULL)
        return 0;
    piece = PyObject_CallFunction(self->segments, "y#y#", (const char *)r->data, (Py_ssize_t)r->length,
                                  (const char *)r->stamps, (Py_ssize_t)(r->n_stamps * sizeof *r->stamps));
    r->conversation = NULL;
    r->length = r->n_stamps = 0;
    return piece == NULL ? -2 : append(self, conversation, r->from_robot, piece, r->ended, r->time);
}

static bool joins(const CaptureStreams *self, const urwire_capture_item *item)
{
    uint16_t port = item->conversation->robot_port;
    const run *r = &self->run;
    if (item->kind != URWIRE_ITEM_BYTES || !(self->joined[port >> 3] & (1u << (port & 7))))
        return false;
    /* The empty item that ends a stream closes the run it ends, else it goes as it is. */
    return item->length > 0 || (r->conversation == item->conversation && r->from_robot == item->from_robot);
}

/* The item's bytes added to the run (a run of another direction closed first). 0, -2 with an
 * exception set, or URWIRE_CAPTURE_NO_MEMORY. */
static int join(CaptureStreams *self, const urwire_capture_item *item)
{
    run *r = &self->run;
    if ((r->conversation != item->conversation || r->from_robot != item->from_robot) && close_run(self) < 0)
        return -2;
    if (item->length > 0) {
        if (item->length > SIZE_MAX - r->length
            || !urwire_capture_grow((void **)&r->data, &r->capacity, r->length + item->length, 1)
            || !urwire_capture_grow((void **)&r->stamps, &r->stamps_capacity, r->n_stamps + 1, sizeof *r->stamps))
            return URWIRE_CAPTURE_NO_MEMORY;
        memcpy(r->data + r->length, item->data, item->length);
        r->length += item->length;
        r->stamps[r->n_stamps].end = (int64_t)r->length;
        r->stamps[r->n_stamps++].time = item->time;
    }
    r->conversation = item->conversation;
    r->from_robot = item->from_robot;
    r->ended = item->ended;
    r->time = item->time;
    return item->ended ? close_run(self) : 0;
}

static int collect(void *context, const urwire_capture_item *item)
{
    CaptureStreams *self = context;
    PyObject *piece;
    if (item->kind != URWIRE_ITEM_FAULT && joins(self, item))
        return join(self, item);
    if (close_run(self) < 0)
        return -2;
    switch (item->kind) {
    case URWIRE_ITEM_FAULT:
        piece = PyObject_CallFunction(self->fault, "Ls", (long long)item->offset, item->error);
        if (piece == NULL)
            return -2;
        if (PyList_Append(self->items, piece) < 0) {
            Py_DECREF(piece);
            return -2;
        }
        Py_DECREF(piece);
        return 0;
    case URWIRE_ITEM_GAP:
        piece = PyObject_CallFunction(self->gap, "LL", (long long)item->offset, (long long)item->missing);
        break;
    case URWIRE_ITEM_DIFFERS:
        piece = PyObject_CallFunction(self->differs, "LLL", (long long)item->offset, (long long)item->missing,
                                      (long long)item->differing);
        break;
    default:
        piece = PyBytes_FromStringAndSize((const char *)item->data, (Py_ssize_t)item->length);
    }
    return piece == NULL ? -2 : append(self, item->conversation, item->from_robot, piece, item->ended, item->time);
}

/* The list of items, or NULL with an exception set, from a feed or finish that returned `stop`. */
static PyObject *items_after(CaptureStreams *self, int stop)
{
    PyObject *items;
    if (stop == 0 && close_run(self) < 0)    /* a run ends with the feed: its items are all out */
        stop = -2;
    self->run.conversation = NULL;
    self->run.length = self->run.n_stamps = 0;
    items = self->items;
    self->items = NULL;
    if (stop == URWIRE_CAPTURE_NO_MEMORY)
        PyErr_NoMemory();
    if (stop != 0) {
        Py_DECREF(items);
        return NULL;
    }
    return items;
}

static PyObject *streams_feed(CaptureStreams *self, PyObject *arg)
{
    Py_buffer view;
    int stop;
    if (PyObject_GetBuffer(arg, &view, PyBUF_SIMPLE) < 0)
        return NULL;
    if ((self->items = PyList_New(0)) == NULL) {
        PyBuffer_Release(&view);
        return NULL;
    }
    stop = urwire_capture_feed(self->capture, view.buf, (size_t)view.len, collect, self);
    PyBuffer_Release(&view);
    return items_after(self, stop);
}

static PyObject *streams_finish(CaptureStreams *self, PyObject *Py_UNUSED(ignored))
{
    if ((self->items = PyList_New(0)) == NULL)
        return NULL;
    return items_after(self, urwire_capture_finish(self->capture, collect, self));
}

static PyObject *streams_others(CaptureStreams *self, PyObject *Py_UNUSED(ignored))
{
    const urwire_capture_other *others;
    size_t n = urwire_capture_others(self->capture, &others), i;
    PyObject *list = PyList_New((Py_ssize_t)n);
    for (i = 0; list != NULL && i < n; i++) {
        PyObject *entry = Py_BuildValue("(sIsIK)", others[i].server, (unsigned)others[i].server_port,
                                        others[i].client, (unsigned)others[i].client_port,
                                        (unsigned long long)others[i].bytes);
        if (entry == NULL) {
            Py_CLEAR(list);
            break;
        }
        PyList_SET_ITEM(list, (Py_ssize_t)i, entry);
    }
    return list;
}

static PyMethodDef streams_methods[] = {
    {"feed", (PyCFunction)streams_feed, METH_O,
     "feed(chunk): the next bytes of the capture file; the items they complete, as a list"},
    {"finish", (PyCFunction)streams_finish, METH_NOARGS,
     "finish(): the end of the file; the last items (every stream ends)"},
    {"others", (PyCFunction)streams_others, METH_NOARGS,
     "others(): the conversations on no port read so far, first seen first: (server address, "
     "server port, client address, client port, bytes)"},
    {NULL, NULL, 0, NULL},
};

static PyTypeObject CaptureStreamsType = {
    PyVarObject_HEAD_INIT(NULL, 0)
    .tp_name = "urwire._ccore.CaptureStreams",
    .tp_doc = "A .pcap or .pcapng in, in chunks; its TCP streams out, reassembled (capture.timed_streams' items).",
    .tp_basicsize = sizeof(CaptureStreams),
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_new = PyType_GenericNew,
    .tp_init = (initproc)streams_init,
    .tp_dealloc = (destructor)streams_dealloc,
    .tp_methods = streams_methods,
};

int capture_streams_add_types(PyObject *module)
{
    if (PyType_Ready(&CaptureStreamsType) < 0)
        return -1;
    Py_INCREF(&CaptureStreamsType);
    if (PyModule_AddObject(module, "CaptureStreams", (PyObject *)&CaptureStreamsType) < 0) {
        Py_DECREF(&CaptureStreamsType);
        return -1;
    }
    return 0;
}
