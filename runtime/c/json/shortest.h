/* The decimal digits that canonical JSON prints for a float64 or a float32
 * (docs/canonical-json.md), found with Ryū: Ulf Adams, "Ryū: fast float-to-string
 * conversion", PLDI 2018, https://doi.org/10.1145/3192366.3192369. C runtime beside the
 * parser (not joined into it): json.c prints with it, for urwire-decode and urwire._ccore. */
#ifndef URWIRE_SHORTEST_H
#define URWIRE_SHORTEST_H

#include <stdint.h>

/* digits * 10^exponent; digits has no trailing zero. */
typedef struct shortest_decimal {
    uint64_t digits;
    int32_t exponent;
} shortest_decimal;

/* |x| for a finite, nonzero x: the fewest digits that read back as x, and of those the
 * nearest to x (the digits of Python's repr(x)). */
shortest_decimal shortest_f64(double x);

/* |x| for a finite, nonzero x: the correctly rounded p-digit decimal with the fewest digits p
 * that reads back as x when read as a double and then rounded to float32, as Python reads a
 * JSON number into a float32 (the digits of the canonical "%.{p}g"). */
shortest_decimal shortest_f32(float x);

#endif
