/* <standalone> */
#ifndef URWIRE_RUNTIME_VERSION_H
#define URWIRE_RUNTIME_VERSION_H
#include <stdbool.h>
/* </standalone> */
/* ---- software versions -------------------------------------------------------------------- */

/* Software version ("major.minor") that chooses the global-variable value-type table. */
typedef struct urwire_sw_version {
    int major;
    int minor;
} urwire_sw_version;

/* Assumed when a stream has shown no Version message and no hint was given (see
 * URWIRE_DEFAULT_VERSION_INIT). */
extern const urwire_sw_version URWIRE_DEFAULT_VERSION;

/* "5.9", "5.10.1" -> {5, 9}, {5, 10}; false (and *out untouched) for anything else. */
bool urwire_parse_version(const char *text, urwire_sw_version *out);
/* <standalone> */
#endif
/* </standalone> */
