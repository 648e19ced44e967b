/* The generated part of urwire.h in miniature: what the hand-written runtime headers and files
 * (runtime/c/) take from it, for a made-up protocol, so that each runtime
 * file compiles, and is unit-tested, on its own (tests/c/test_c_runtime.py).
 *
 * The made-up protocol: a message is an int32 length and a uint8 type, as in the real one.
 * Type 16 ("state") is a list of sub-packages, each an int32 length and a uint8 type; type 1
 * has two layouts: "tally" (one uint16) up to 3.2, "counter" (one uint32) from 3.3.
 * Global-variable values have two tables: up to 3.2, and 3.3 on.
 * runtime_support.h gives the private part (the tables of urwire.c). */
#ifndef URWIRE_RUNTIME_SPEC_H
#define URWIRE_RUNTIME_SPEC_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define URWIRE_MAX_VALUE_DEPTH 3         /* before errors.h, which sizes a path by it */

#include "version.h"
#include "views.h"
#include "errors.h"

#define URWIRE_MAX_MESSAGE_LENGTH 1048576u
#define URWIRE_HEADER_SIZE 5u
#define URWIRE_PACKAGE_HEADER_SIZE 5u
#define URWIRE_DEFAULT_VERSION_INIT {5, 9, 0, true}
#define URWIRE_BUGFIX_ANY 999
#define URWIRE_VALUE_ARRAY_MAX 6
/* A private number that the generated urwire.c defines before the runtime: the most exact
 * sizes a form has (private.h sizes urwire__form with it). */
#define URWIRE__FORM_SIZES 2

typedef enum urwire_value_kind {
    URWIRE_VALUE_NONE,
    URWIRE_VALUE_STRING,
    URWIRE_VALUE_BOOL,
    URWIRE_VALUE_INT,
    URWIRE_VALUE_NUM,
    URWIRE_VALUE_POSE,
    URWIRE_VALUE_LIST,
    URWIRE_VALUE_MATRIX,
    URWIRE_VALUE_KIND_COUNT
} urwire_value_kind;

typedef enum urwire_message_kind {
    URWIRE_KIND_UNKNOWN_MESSAGE,
    URWIRE_KIND_STATE,
    URWIRE_KIND_UNKNOWN_SUBTYPE
} urwire_message_kind;

typedef enum urwire_package_layout {
    URWIRE_LAYOUT_TALLY,
    URWIRE_LAYOUT_COUNTER,
    URWIRE_LAYOUT_COUNT
} urwire_package_layout;

typedef struct urwire_tally {
    uint16_t count;
    urwire_sw_version version;
    urwire_bytes extra;
} urwire_tally;

typedef struct urwire_counter {
    uint32_t count;
    urwire_sw_version version;
    urwire_bytes extra;
} urwire_counter;

typedef struct urwire_message {
    const uint8_t *bytes;
    size_t length;
    uint8_t message_type;
    urwire_message_kind kind;
    urwire_sw_version version;
    bool implied;
    urwire_sw_version implied_version;
    bool failed;
    urwire_error error;
    urwire_bytes raw;
    urwire_seq packages;
    union {
        uint8_t none;
    } header;
    union {
        uint8_t none;
    } as;
} urwire_message;

typedef struct urwire_package {
    uint8_t type;
    urwire_sw_version version;
    bool known;
    urwire_package_layout layout;
    bool failed;
    urwire_error error;
    size_t offset;
    urwire_bytes raw;
    union {
        urwire_tally tally;
        urwire_counter counter;
    } as;
} urwire_package;

typedef struct urwire_robot_state {
    uint32_t present;
    uint32_t malformed;
    uint32_t layouts;
    size_t unknown;
    urwire_tally tally;
    urwire_counter counter;
} urwire_robot_state;

#endif
