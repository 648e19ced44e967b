/* <standalone> */
#ifndef UR_REALTIME_RUNTIME_LOADS_H
#define UR_REALTIME_RUNTIME_LOADS_H
#include <stddef.h>
#include <stdint.h>
#include <string.h>
/* </standalone> */
/* Big-endian loads of the real-time packet: its int32 size and its doubles, assembled from bytes
 * with shifts, so that they are right on any host and never read out of bounds (the caller has
 * checked the packet's length once). */

/* Unused ones never warn: clang warns on an unused static inline function unless told `unused`. */
#if defined(__GNUC__)
#define UR_REALTIME__INLINE static inline __attribute__((unused))
#else
#define UR_REALTIME__INLINE static inline
#endif

UR_REALTIME__INLINE uint64_t ur_realtime__u64(const uint8_t *p)
{
    return (uint64_t)p[0] << 56 | (uint64_t)p[1] << 48 | (uint64_t)p[2] << 40 | (uint64_t)p[3] << 32 |
           (uint64_t)p[4] << 24 | (uint64_t)p[5] << 16 | (uint64_t)p[6] << 8 | (uint64_t)p[7];
}

UR_REALTIME__INLINE int32_t ur_realtime__i32(const uint8_t *p)
{
    uint32_t u = (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | (uint32_t)p[3];
    int32_t v;
    memcpy(&v, &u, sizeof v);   /* two's complement, without an implementation-defined cast */
    return v;
}

/* A double is read as its bit pattern, NaN payloads included. */
UR_REALTIME__INLINE double ur_realtime__f64(const uint8_t *p)
{
    uint64_t bits = ur_realtime__u64(p);
    double d;
    memcpy(&d, &bits, sizeof d);
    return d;
}

UR_REALTIME__INLINE void ur_realtime__f64s(double *out, const uint8_t *p, size_t count)
{
    size_t i;
    for (i = 0; i < count; i++)
        out[i] = ur_realtime__f64(p + 8 * i);
}
/* <standalone> */
#endif
/* </standalone> */
