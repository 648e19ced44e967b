/* <standalone> */
#include "runtime_spec.h"       /* first: URWIRE_MAX_VALUE_DEPTH, before this file's guard */
#ifndef URWIRE_RUNTIME_ERRORS_H
#define URWIRE_RUNTIME_ERRORS_H
#include <stddef.h>
#include <stdint.h>
/* </standalone> */
/* ---- errors ------------------------------------------------------------------------------- */

#define URWIRE_PATH_MAX 192                /* an error's field path in its text: cut to one less */
/* The elements an error's path can pass through: the item of a global variable's value in each
 * LIST or MATRIX it is nested in, and the value's own place in its message. */
#define URWIRE_PATH_STEPS (URWIRE_MAX_VALUE_DEPTH + 1)

typedef enum urwire_status {
    URWIRE_OK = 0,
    /* inside a message */
    URWIRE_E_SHORT,               /* <path> at offset <o>: needs <value> bytes, <left> left */
    URWIRE_E_NEGATIVE_LENGTH,     /* <path> at offset <o>: negative length <value> */
    URWIRE_E_VALUE_TYPE,          /* <path> at offset <o>: unknown value type <value> */
    URWIRE_E_TERMINATOR,          /* <path> at offset <o>: expected terminator 0x<left>, found 0x<value> */
    URWIRE_E_TOO_DEEP,            /* <path> at offset <o>: nesting deeper than <value> */
    URWIRE_E_TOO_MANY_ITEMS,      /* <path> at offset <o>: <value> items need more than the <left> bytes left */
    URWIRE_E_EMPTY_ROWS,          /* <path> at offset <o>: <value> rows of 0 columns */
    URWIRE_E_PACKAGE_HEADER_CUT,  /* package at offset <o>: needs <value> bytes, <left> left */
    URWIRE_E_PACKAGE_LENGTH_LOW,  /* package at offset <o>: length <value> is below URWIRE_PACKAGE_HEADER_SIZE */
    URWIRE_E_PACKAGE_LENGTH_HIGH, /* package at offset <o>: length <value> exceeds the <left> bytes left */
    /* stream faults (offset from the stream's first byte) */
    URWIRE_E_LENGTH_LOW,          /* length <value> is below URWIRE_HEADER_SIZE */
    URWIRE_E_LENGTH_HIGH,         /* length <value> is above URWIRE_MAX_MESSAGE_LENGTH */
    URWIRE_E_MESSAGE_TYPE,        /* unknown message type <value> */
    URWIRE_E_TRUNCATED_MESSAGE,   /* truncated message: length <value>, <left> bytes left */
    URWIRE_E_TRUNCATED_HEADER,    /* truncated header: <left> bytes left */
    URWIRE_E_TOO_BIG_FOR_BUFFER,  /* message of length <value> exceeds the framer's buffer of <left> bytes */
    /* encoding */
    URWIRE_E_NO_SPACE,            /* <path> at offset <o>: needs <value> bytes, <left> left in the output */
    URWIRE_E_TOO_LONG             /* <path>: <value> bytes do not fit the length prefix (max <left>) */
} urwire_status;

/* One element on an error's path: name[index], or name[index][index2 - 1] (a MATRIX item). */
typedef struct urwire_path_step {
    const char *name;         /* name_len characters, not NUL-terminated; may be empty */
    uint32_t index;
    uint16_t name_len;
    uint16_t index2;          /* 0: none */
} urwire_path_step;

/* The field path (joints[5].joint_mode, variables[2][0].type) is kept as its parts, in the
 * parser's own text and numbers, and written only by urwire_error_text: a decoder that fails
 * formats nothing, and the error is small. */
typedef struct urwire_error {
    urwire_status status;
    size_t offset;            /* from the message's first byte; stream faults: the stream's */
    int64_t value;            /* the number in the text: bytes needed, the bad length or type... */
    int64_t left;             /* the second number, where there is one */
    const char *field;        /* the path after its last element: ".joint_mode", "label_name" */
    uint8_t steps;            /* the elements before it, innermost first in step[] */
    urwire_path_step step[URWIRE_PATH_STEPS];
} urwire_error;

/* The status as an identifier: "URWIRE_E_SHORT". */
const char *urwire_status_name(urwire_status status);
/* The canonical text of an error, NUL-terminated, cut to fit; returns its full length. Its
 * path is cut to URWIRE_PATH_MAX - 1 characters. */
size_t urwire_error_text(const urwire_error *e, char *out, size_t cap);
/* <standalone> */
#endif
/* </standalone> */
