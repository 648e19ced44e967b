/* <standalone> */
#ifndef URWIRE_RUNTIME_LOADS_H
#define URWIRE_RUNTIME_LOADS_H
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include "macros.h"
/* </standalone> */
/* ---- big-endian loads and stores ---------------------------------------------------------- */

/* The one set of big-endian loads of the C runtime: every kind's generated C joins it, and the C
 * command includes it. Every field is read with memcpy into an integer (one unaligned load) and
 * a byte swap built of shifts, which compilers fold into one instruction. They must be inlined to
 * be fast (see URWIRE__INLINE in macros.h). The caller has checked that the bytes are there. */

/* The host's byte order, a constant once optimised: 1 on a big-endian machine. */
URWIRE__INLINE int urwire__host_is_big_endian(void)
{
    const uint16_t one = 1u;
    uint8_t first;
    memcpy(&first, &one, 1);
    return first == 0;
}

URWIRE__INLINE uint16_t urwire__swap16(uint16_t v)
{
    return (uint16_t)((unsigned)v << 8 | (unsigned)v >> 8);
}

URWIRE__INLINE uint32_t urwire__swap32(uint32_t v)
{
    return (v & 0x000000ffu) << 24 | (v & 0x0000ff00u) << 8 | (v & 0x00ff0000u) >> 8 | (v & 0xff000000u) >> 24;
}

URWIRE__INLINE uint64_t urwire__swap64(uint64_t v)
{
    return (uint64_t)urwire__swap32((uint32_t)v) << 32 | urwire__swap32((uint32_t)(v >> 32));
}

/* Big-endian bytes at p as a host integer, and back. */
URWIRE__INLINE uint16_t urwire__from_be16(uint16_t v) { return urwire__host_is_big_endian() ? v : urwire__swap16(v); }
URWIRE__INLINE uint32_t urwire__from_be32(uint32_t v) { return urwire__host_is_big_endian() ? v : urwire__swap32(v); }
URWIRE__INLINE uint64_t urwire__from_be64(uint64_t v) { return urwire__host_is_big_endian() ? v : urwire__swap64(v); }

URWIRE__INLINE uint8_t urwire__u8(const uint8_t *p) { return p[0]; }
URWIRE__INLINE int8_t urwire__i8(const uint8_t *p) { return (int8_t)p[0]; }

URWIRE__INLINE uint16_t urwire__u16(const uint8_t *p)
{
    uint16_t v;
    memcpy(&v, p, sizeof v);
    return urwire__from_be16(v);
}

URWIRE__INLINE uint32_t urwire__u32(const uint8_t *p)
{
    uint32_t v;
    memcpy(&v, p, sizeof v);
    return urwire__from_be32(v);
}

URWIRE__INLINE uint64_t urwire__u64(const uint8_t *p)
{
    uint64_t v;
    memcpy(&v, p, sizeof v);
    return urwire__from_be64(v);
}

/* n bytes (1 to 8, known when inlined) as an unsigned integer: a length prefix or a value of a
 * width read from a table. */
URWIRE__INLINE uint64_t urwire__uint(const uint8_t *p, size_t n)
{
    uint64_t v = 0;
    size_t i;
    for (i = 0; i < n; i++)
        v = v << 8 | p[i];
    return v;
}

URWIRE__INLINE int16_t urwire__i16(const uint8_t *p) { return (int16_t)urwire__u16(p); }
URWIRE__INLINE int32_t urwire__i32(const uint8_t *p) { return (int32_t)urwire__u32(p); }
URWIRE__INLINE int64_t urwire__i64(const uint8_t *p) { return (int64_t)urwire__u64(p); }

/* Floats are read as their bit pattern, never byte-swapped as numbers. */
URWIRE__INLINE float urwire__f32(const uint8_t *p)
{
    uint32_t bits = urwire__u32(p);
    float f;
    memcpy(&f, &bits, sizeof f);
    return f;
}

/* A double from its bit pattern, NaN payloads included. */
URWIRE__INLINE double urwire__f64_of(uint64_t bits)
{
    double d;
    memcpy(&d, &bits, sizeof d);
    return d;
}

URWIRE__INLINE double urwire__f64(const uint8_t *p)
{
    return urwire__f64_of(urwire__u64(p));
}

/* count doubles in a row into out. */
URWIRE__INLINE void urwire__f64s(double *out, const uint8_t *p, size_t count)
{
    size_t i;
    for (i = 0; i < count; i++)
        out[i] = urwire__f64(p + 8 * i);
}

URWIRE__INLINE void urwire__put_u8(uint8_t *p, uint8_t v) { p[0] = v; }
URWIRE__INLINE void urwire__put_i8(uint8_t *p, int8_t v) { p[0] = (uint8_t)v; }

URWIRE__INLINE void urwire__put_u16(uint8_t *p, uint16_t v)
{
    v = urwire__from_be16(v);
    memcpy(p, &v, sizeof v);
}

URWIRE__INLINE void urwire__put_u32(uint8_t *p, uint32_t v)
{
    v = urwire__from_be32(v);
    memcpy(p, &v, sizeof v);
}

URWIRE__INLINE void urwire__put_u64(uint8_t *p, uint64_t v)
{
    v = urwire__from_be64(v);
    memcpy(p, &v, sizeof v);
}

URWIRE__INLINE void urwire__put_i16(uint8_t *p, int16_t v) { urwire__put_u16(p, (uint16_t)v); }
URWIRE__INLINE void urwire__put_i32(uint8_t *p, int32_t v) { urwire__put_u32(p, (uint32_t)v); }
URWIRE__INLINE void urwire__put_i64(uint8_t *p, int64_t v) { urwire__put_u64(p, (uint64_t)v); }

URWIRE__INLINE void urwire__put_f32(uint8_t *p, float v)
{
    uint32_t bits;
    memcpy(&bits, &v, sizeof bits);
    urwire__put_u32(p, bits);
}

URWIRE__INLINE void urwire__put_f64(uint8_t *p, double v)
{
    uint64_t bits;
    memcpy(&bits, &v, sizeof bits);
    urwire__put_u64(p, bits);
}
/* <standalone> */
#endif
/* </standalone> */
