/* Shortest decimals of binary floats (see shortest.h), after Ryū (Adams, PLDI 2018).
 *
 * A finite float is v * 2^e2 for an integer v, and the decimals that read back as it fill an
 * interval [lo, hi] * 2^e2 around it, its ends in or out as the reader rounds ties. Ryū
 * multiplies v, lo and hi by 2^e2 / 10^e10 with 125-bit powers of five (pow5_table.h), precise
 * enough that the products' floors are exact for every v < 2^55, at a scale 10^e10 finer than
 * the interval; it then drops decimal digits while a shorter decimal still lies in the
 * interval, and rounds. Here the interval is an argument rather than derived from v, so that a
 * float32's can be widened or narrowed by half a double ulp (shortest_f32). */
#include "shortest.h"

#include <stdbool.h>
#include <string.h>

#include "pow5_table.h"

/* floor(log10(2^e)) for 0 <= e <= 1650; floor(log10(5^e)) for 0 <= e <= 2620; the bit length
 * of 5^e for 0 <= e <= 3528 (pow5_table.py checks it over the tables). */
static uint32_t log10_pow2(int32_t e) { return ((uint32_t)e * 78913u) >> 18; }
static uint32_t log10_pow5(int32_t e) { return ((uint32_t)e * 732923u) >> 20; }
static int32_t pow5_bits(int32_t e) { return (int32_t)(((uint32_t)e * 1217359u) >> 19) + 1; }

#if defined(__SIZEOF_INT128__) && !defined(SHORTEST_PORTABLE)
__extension__ typedef unsigned __int128 uint128;

/* floor(m * mul / 2^j) for m < 2^55, a 125-bit mul (low word first) and 64 < j < 128. */
static uint64_t mul_shift(uint64_t m, const uint64_t mul[2], int32_t j)
{
    uint128 low = (uint128)m * mul[0], high = (uint128)m * mul[1];
    return (uint64_t)(((low >> 64) + high) >> (j - 64));
}
#else
/* a * b: the low word, and the high word in *high. */
static uint64_t mul_64(uint64_t a, uint64_t b, uint64_t *high)
{
    uint64_t a0 = a & 0xffffffffu, a1 = a >> 32, b0 = b & 0xffffffffu, b1 = b >> 32;
    uint64_t p00 = a0 * b0, p01 = a0 * b1, p10 = a1 * b0, p11 = a1 * b1;
    uint64_t mid = (p00 >> 32) + (p01 & 0xffffffffu) + (p10 & 0xffffffffu);
    *high = p11 + (p01 >> 32) + (p10 >> 32) + (mid >> 32);
    return (mid << 32) | (p00 & 0xffffffffu);
}

static uint64_t mul_shift(uint64_t m, const uint64_t mul[2], int32_t j)
{
    uint64_t high0, high1, sum;
    uint64_t low1 = mul_64(m, mul[1], &high1);
    (void)mul_64(m, mul[0], &high0);
    sum = high0 + low1;
    high1 += sum < high0;
    return (high1 << (128 - j)) | (sum >> (j - 64));
}
#endif

static bool multiple_of_pow5(uint64_t n, uint32_t p)
{
    for (; p > 0; p--, n /= 5)
        if (n % 5 != 0)
            return false;
    return true;
}

static bool multiple_of_pow2(uint64_t n, uint32_t p)
{
    return p < 64 && (n & ((UINT64_C(1) << p) - 1)) == 0;
}

/* v, lo and hi at the decimal scale 10^e10, with what rounding them down lost. */
typedef struct scaled {
    uint64_t vr, vp, vm;  /* v, hi and lo * 2^e2 / 10^e10, rounded down; vp less one when hi is
                           * exact but out: vm < d <= vp holds every d * 10^e10 inside */
    int32_t e10;
    uint8_t last;         /* the digit of v last dropped from vr */
    bool vr_exact;        /* the digits of v below `last` are all zero */
    bool vm_exact;        /* lo is exactly vm * 10^e10, and inside: d == vm is inside too */
} scaled;

static scaled scale(uint64_t v, uint64_t lo, uint64_t hi, int32_t e2, bool ends_inside)
{
    scaled s;
    bool hi_exact = false;
    s.last = 0;
    s.vr_exact = s.vm_exact = false;
    if (e2 >= 0) {
        /* A decimal finer than 2^e2 (10^(q+1) <= 2^e2), so that a digit is always dropped. */
        uint32_t q = log10_pow2(e2) - (e2 > 3);
        int32_t j = -e2 + (int32_t)q + POW5_BITS + pow5_bits((int32_t)q) - 1;
        s.e10 = (int32_t)q;
        s.vr = mul_shift(v, POW5_INV[q], j);
        s.vp = mul_shift(hi, POW5_INV[q], j);
        s.vm = mul_shift(lo, POW5_INV[q], j);
        /* n * 2^e2 / 10^q is whole when 5^q divides n (q <= e2); 5^24 > 2^55 > n. */
        if (q <= 23) {
            s.vr_exact = multiple_of_pow5(v, q);
            s.vm_exact = multiple_of_pow5(lo, q);
            hi_exact = multiple_of_pow5(hi, q);
        }
    } else {
        uint32_t q = log10_pow5(-e2) - (-e2 > 1);
        int32_t i = -e2 - (int32_t)q;
        int32_t j = (int32_t)q - pow5_bits(i) + POW5_BITS;
        s.e10 = (int32_t)q + e2;
        s.vr = mul_shift(v, POW5[i], j);
        s.vp = mul_shift(hi, POW5[i], j);
        s.vm = mul_shift(lo, POW5[i], j);
        /* n * 2^e2 / 10^e10 = n * 5^i / 2^q is whole when 2^q divides n. */
        s.vr_exact = multiple_of_pow2(v, q);
        s.vm_exact = multiple_of_pow2(lo, q);
        hi_exact = multiple_of_pow2(hi, q);
    }
    s.vm_exact = s.vm_exact && ends_inside;
    if (hi_exact && !ends_inside)
        s.vp--;
    return s;
}

/* Drop the last k digits at once: p = 10^k, below = 10^(k - 1) (constants, for the compiler). */
static void drop_digits(scaled *s, uint64_t p, uint64_t below, int32_t k)
{
    uint64_t rest = s->vr % p;
    s->vm_exact = s->vm_exact && s->vm % p == 0;
    s->vr_exact = s->vr_exact && s->last == 0 && rest % below == 0;
    s->last = (uint8_t)(rest / below);
    s->vr /= p;
    s->vp /= p;
    s->vm /= p;
    s->e10 += k;
}

static void drop_digit(scaled *s) { drop_digits(s, 10, 1, 1); }

/* Does v rounded to vr's digits go up? Ties go to the even digit, as printf rounds. */
static bool rounds_up(const scaled *s)
{
    return s->last > 5 || (s->last == 5 && !(s->vr_exact && s->vr % 2 == 0));
}

static bool inside(const scaled *s, uint64_t d)
{
    return (d > s->vm || (d == s->vm && s->vm_exact)) && d <= s->vp;
}

/* Drop digits while a shorter decimal lies inside: then vr has the fewest digits that any
 * decimal inside has, and vr or vr + 1 is inside. */
static void shorten(scaled *s)
{
    while (s->vp / 10000 > s->vm / 10000)  /* four at a time first: a float32 drops about nine */
        drop_digits(s, 10000, 1000, 4);
    while (s->vp / 10 > s->vm / 10)
        drop_digit(s);
    if (s->vm_exact)  /* lo itself is inside: its trailing zeros can go too */
        while (s->vm % 10 == 0)
            drop_digit(s);
}

static shortest_decimal decimal(uint64_t digits, int32_t exponent)
{
    shortest_decimal d;
    d.digits = digits;
    d.exponent = exponent;
    return d;
}

shortest_decimal shortest_f64(double x)
{
    uint64_t bits, m2, v;
    uint32_t exponent;
    bool lopsided = false;
    scaled s;
    memcpy(&bits, &x, sizeof bits);
    m2 = bits & ((UINT64_C(1) << 52) - 1);
    exponent = (uint32_t)(bits >> 52) & 0x7ffu;
    if (exponent != 0) {
        lopsided = m2 == 0 && exponent > 1;  /* a power of two: the double below is nearer */
        m2 |= UINT64_C(1) << 52;
    }
    /* x = m2 * 2^(exponent - 1075), counted in quarters of its ulp: v * 2^e2. */
    v = 4 * m2;
    s = scale(v, v - (lopsided ? 1 : 2), v + 2, (int32_t)(exponent ? exponent : 1) - 1077, m2 % 2 == 0);
    shorten(&s);
    /* The nearest of the fewest digits: vr rounded, or vr + 1 when vr is outside. */
    return decimal(s.vr + (rounds_up(&s) || !inside(&s, s.vr)), s.e10);
}

shortest_decimal shortest_f32(float x)
{
    uint32_t fbits, fexp;
    uint64_t dbits, v, gap, mid_lo, mid_hi, lo, hi, near;
    double d = x;
    int32_t dexp, drops, r;
    bool even;
    scaled s, first;
    memcpy(&fbits, &x, sizeof fbits);
    memcpy(&dbits, &d, sizeof dbits);
    fexp = (fbits >> 23) & 0xffu;
    dexp = (int32_t)(dbits >> 52) & 0x7ff;
    even = fbits % 2 == 0;
    /* x as a double (never subnormal), counted in quarters of the double's ulp: v * 2^e2.
     * gap: the float32 spacing above x in double ulps (2^29, more for a subnormal float32). */
    v = 4 * ((dbits & ((UINT64_C(1) << 52) - 1)) | (UINT64_C(1) << 52));
    gap = UINT64_C(1) << ((int32_t)(fexp ? fexp : 1) - 150 - (dexp - 1075));
    mid_hi = v + 2 * gap;
    mid_lo = v - ((fbits & 0x7fffffu) == 0 && fexp > 1 ? gap : 2 * gap);  /* below a power of two: half */
    /* A decimal within half a double ulp of a midpoint reads as the midpoint, and the midpoint
     * rounds to the even float32: the interval grows by that half ulp when x is even and shrinks
     * by it when x is odd. Half an ulp is 2 quarters, 1 below a double power of two. */
    if (even) {
        lo = mid_lo - ((dbits & ((UINT64_C(1) << 52) - 1)) == 0 ? 1 : 2);
        hi = mid_hi + 2;
    } else {
        lo = mid_lo + ((dbits & ((UINT64_C(1) << 52) - 1)) == 0 ? 1 : 2);
        hi = mid_hi - 2;
    }
    first = s = scale(v, lo, hi, dexp - 1077, even);
    shorten(&s);
    /* The canonical text is the correctly rounded one of the fewest digits that is inside:
     * mostly the shortest; near a power of two, where the interval is lopsided, maybe longer. */
    near = s.vr + rounds_up(&s);
    for (drops = s.e10 - first.e10, r = drops - 1; !inside(&s, near) && r > 0; r--) {
        s = first;
        while (s.e10 - first.e10 < r)
            drop_digit(&s);
        near = s.vr + rounds_up(&s);
    }
    return decimal(near, s.e10);
}
