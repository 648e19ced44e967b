#ifndef URWIRE_CAPTURE_GROWING_H
#define URWIRE_CAPTURE_GROWING_H
/* The capture reader's arrays grow by doubling: one rule for its conversations, its held segments
 * and its output pieces. */
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

/* Makes *buf (of *capacity elements of `size` bytes) hold at least `need`; false, with *buf as it
 * was, when memory is refused or the size would overflow. */
static inline bool urwire_capture_grow(void **buf, size_t *capacity, size_t need, size_t size)
{
    size_t c = *capacity ? *capacity : 16;
    void *grown;
    if (need <= *capacity)
        return true;
    while (c < need) {
        if (c > SIZE_MAX / 2)
            return false;
        c *= 2;
    }
    if (c > SIZE_MAX / size)
        return false;
    grown = realloc(*buf, c * size);
    if (grown == NULL)
        return false;
    *buf = grown;
    *capacity = c;
    return true;
}

#endif
