/* Finds the float32 values whose canonical text depends on how a decimal is read back: a
 * decimal of at most 9 significant digits that lies within half a double ulp of the midpoint
 * between two neighbouring float32 values (but not on it) reads as that midpoint when read as
 * a double, and the midpoint then rounds to the even neighbour, though the decimal itself is
 * nearer the other. Prints both neighbours' bit patterns, one pair a line; their texts are
 * where a float32 formatter that ignores the double read differs from Python's.
 *
 *     cc -O2 -o near_midpoints tests/c/near_midpoints.c -lm
 *     ./near_midpoints | sort -u > tests/c/float32_near_midpoints.txt   (a minute or so)
 *
 * Needs unsigned __int128 (gcc, clang). For each binade and each decimal scale 10^s that
 * brings its midpoints M to 9 integer digits, it walks M * 10^s mod 1 as a 128-bit fixed-point
 * fraction; a fraction this close to 0 or 1 (but not 0) is such a decimal. A few more pairs
 * than needed are printed (twice the distance), which only adds test values. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>

__extension__ typedef unsigned __int128 u128;

/* frac(2^k * 10^s) as a 128-bit fixed-point fraction. */
static u128 scale_fraction(int k, int s)
{
    u128 p5 = 1, r = 1, q = 0;
    int i, a = s < 0 ? -s : s;
    for (i = 0; i < a; i++)
        p5 *= 5;
    if (s >= 0) {  /* 5^s / 2^t: exact */
        int t = -(k + s);
        if (t <= 0)
            return 0;
        return t >= 128 ? p5 >> (t - 128) : (p5 & (((u128)1 << t) - 1)) << (128 - t);
    }
    /* 2^(k - a) / 5^a with k >= a: ((2^(k - a) mod 5^a) * 2^128) / 5^a, bit by bit */
    for (i = 0; i < k - a; i++) {
        r <<= 1;
        if (r >= p5)
            r -= p5;
    }
    for (i = 0; i < 128; i++) {
        r <<= 1;
        q <<= 1;
        if (r >= p5) {
            r -= p5;
            q |= 1;
        }
    }
    return q;
}

int main(void)
{
    int e;
    puts("# float32 bit patterns, two neighbours a line, with a decimal of at most 9 digits within");
    puts("# half a double ulp of their midpoint: written by tests/c/near_midpoints.c");
    for (e = 0; e < 255; e++) {  /* the float32 biased exponent; 0: the subnormals */
        /* x = m * 2^(k+1) for m in [lo, hi]; M = (2m + 1) * 2^k, up to the next x. */
        uint32_t lo = e ? 1u << 23 : 0, hi = (1u << 24) - 1, m;
        int k = (e ? e : 1) - 151, s;
        double top = ldexp(1.0, k + 25), bottom = ldexp(e ? 1.0 : 0.5, e ? k + 24 : k + 1);
        for (s = (int)floor(8 - log10(top)) - 1; s <= (int)ceil(9 - log10(bottom)) + 1; s++) {
            u128 f = scale_fraction(k, s);
            double p10 = pow(10, s);
            if (s < 0 && k < -s)
                continue;  /* M * 10^s < 1: not a scale of this binade */
            for (m = lo; m <= hi; m++) {
                double mid = ldexp(2.0 * m + 1, k), scaled = mid * p10, dist, half_ulp;
                u128 frac, near;
                int exp2;
                if (scaled < 1e8 * (1 - 1e-12) || scaled >= 1e9 * (1 + 1e-12))
                    continue;
                frac = (u128)(2 * (u128)m + 1) * f;
                near = frac < ((u128)1 << 127) ? frac : -frac;
                if (near < ((u128)1 << 30))
                    continue;  /* M is itself such a decimal: both readings agree */
                dist = ldexp((double)near, -128);
                frexp(mid, &exp2);
                half_ulp = ldexp(1.0, exp2 - 54) * p10;
                if (dist <= 2 * half_ulp) {
                    uint32_t bits = e ? ((uint32_t)(e - 1) << 23) + m : m;  /* m holds the hidden bit */
                    printf("%08lx %08lx\n", (unsigned long)bits, (unsigned long)bits + 1);
                }
            }
        }
    }
    return 0;
}
