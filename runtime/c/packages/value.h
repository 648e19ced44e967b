/* <standalone> */
#ifndef URWIRE_RUNTIME_VALUE_H
#define URWIRE_RUNTIME_VALUE_H
#include "runtime_spec.h"
/* </standalone> */
/* ---- global-variable values --------------------------------------------------------------- */

/* One value: a type byte and its data. LIST and MATRIX hold their items as a seq to walk with
 * urwire_next_value(), so no fixed capacity ever truncates them. */
typedef struct urwire_value {
    uint8_t code;             /* the type byte on the wire */
    urwire_value_kind kind;
    const char *type_name;    /* the name in the version's table: "CONST_STRING", "STRING" up to 3.2 */
    union {
        uint8_t boolean;      /* BOOL: the wire byte, nonzero is true */
        int32_t integer;      /* INT */
        float number;         /* NUM and FLOAT */
        float pose[URWIRE_VALUE_ARRAY_MAX]; /* POSE: X, Y, Z, Rx, Ry, Rz */
        urwire_bytes text;    /* STRING, CONST_STRING, VAR_STRING */
    } as;
    int16_t rows;             /* LIST: its length; MATRIX: nRows */
    int16_t cols;             /* MATRIX: nColumns */
    urwire_seq items;         /* LIST and MATRIX: the items, row by row */
} urwire_value;

/* The next name of a names seq (without its terminator); false at the end. */
bool urwire_next_text(urwire_seq *seq, urwire_bytes *out);
/* The next value of a value seq (a message's values, or a LIST/MATRIX's items); false at the end. */
bool urwire_next_value(urwire_seq *seq, urwire_value *out);
/* <standalone> */
#endif
/* </standalone> */
