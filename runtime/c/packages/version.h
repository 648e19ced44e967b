/* <standalone> */
#ifndef URWIRE_RUNTIME_VERSION_H
#define URWIRE_RUNTIME_VERSION_H
#include <stdbool.h>
/* </standalone> */
/* ---- software versions -------------------------------------------------------------------- */

/* A controller software version, major.minor.bugfix: it chooses the layout of each part of a
 * stream, the meaning of version-dependent codes and the global-variable value-type table.
 * Versions compare part by part (5.8.2 < 5.9.0 < 5.25.1). {5, 9} means 5.9.0, given by you. */
typedef struct urwire_sw_version {
    int major;
    int minor;
    int bugfix;
    /* Neither announced by the stream nor given by you, but assumed (URWIRE_DEFAULT_VERSION):
     * the layout sizes of a robot state may then tell the version
     * (docs/contract.md#where-the-version-comes-from). */
    bool assumed;
} urwire_sw_version;

/* Assumed when a stream has shown no Version message and no hint was given (see
 * URWIRE_DEFAULT_VERSION_INIT); its `assumed` is true. */
extern const urwire_sw_version URWIRE_DEFAULT_VERSION;

/* "5.9" -> {5, 9, 0}, "5.25.1" -> {5, 25, 1}, not assumed; false (and *out untouched) for
 * anything else. */
bool urwire_parse_version(const char *text, urwire_sw_version *out);
/* <standalone> */
#endif
/* </standalone> */
