/* <standalone> */
#ifndef URWIRE_RUNTIME_VERSION_TEXT_H
#define URWIRE_RUNTIME_VERSION_TEXT_H
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include "macros.h"
/* </standalone> */
/* ---- a software version's text (version_text.c) ----------------------------------------- */

/* A part stops growing at its first thirteen digits: far past every version a table names, and
 * never an overflow. */
#define URWIRE__VERSION_PART_BIG 1000000000000u

typedef struct urwire__version_text {
    uint64_t part[3];           /* major, minor, bugfix; a missing bugfix 0 */
    size_t parts;               /* the numbers read: 2 or 3 */
    size_t longest;             /* the digits of the longest number */
    bool dot_after;             /* whole: a dot with no number after it ("5.9.") */
    const char *end;            /* past what was read */
} urwire__version_text;

URWIRE__PRIVATE bool urwire__read_version(const char *text, const char *end, bool whole, bool vt_blank,
                                          urwire__version_text *out);
/* <standalone> */
#endif
/* </standalone> */
