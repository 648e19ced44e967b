"""Write pow5_table.h: the 125-bit powers of five that shortest.c multiplies by (Ryū's tables).

    python3 runtime/c/json/pow5_table.py          rewrite pow5_table.h beside this file
    python3 runtime/c/json/pow5_table.py --check  fail if pow5_table.h is not what it writes

POW5[i]     = 5^i scaled by a power of two to exactly 125 bits (rounded down), i < 326:
              doubles below 1 are multiplied by 5^i
POW5_INV[q] = 2^(bitlength(5^q) - 1 + 125) / 5^q, rounded down, plus one, q < 342:
              doubles of 1 and above are divided by 5^q
Each entry is two uint64_t words, low word first. The sizes cover every double's exponent.
"""
from __future__ import annotations

import sys
from pathlib import Path

BITS = 125
POW5_SIZE = 326
POW5_INV_SIZE = 342
HERE = Path(__file__).resolve().parent
OUT = HERE / "pow5_table.h"


def pow5_bits(e: int) -> int:
    """shortest.c's bit length of 5^e (a multiply and a shift); checked against the exact one below."""
    return ((e * 1217359) >> 19) + 1


def pow5(i: int) -> int:
    n = 5**i
    shift = n.bit_length() - BITS
    return n >> shift if shift >= 0 else n << -shift


def pow5_inv(q: int) -> int:
    n = 5**q
    return (1 << (n.bit_length() - 1 + BITS)) // n + 1


def render() -> str:
    for e in range(max(POW5_SIZE, POW5_INV_SIZE)):
        assert pow5_bits(e) == (5**e).bit_length(), e

    def rows(values: list[int]) -> str:
        mask = (1 << 64) - 1
        return "\n".join(f"    {{0x{v & mask:016x}u, 0x{v >> 64:016x}u}}, /* {i} */" for i, v in enumerate(values))

    return f"""/* Powers of five for shortest.c, 125 bits each as {{low, high}} words. Written by
 * pow5_table.py (python3 runtime/c/json/pow5_table.py); do not edit by hand.
 * POW5[i] = 5^i scaled to 125 bits; POW5_INV[q] = floor(2^(bitlength(5^q) - 1 + 125) / 5^q) + 1. */
#ifndef URWIRE_POW5_TABLE_H
#define URWIRE_POW5_TABLE_H

#include <stdint.h>

#define POW5_BITS {BITS}

static const uint64_t POW5[{POW5_SIZE}][2] = {{
{rows([pow5(i) for i in range(POW5_SIZE)])}
}};

static const uint64_t POW5_INV[{POW5_INV_SIZE}][2] = {{
{rows([pow5_inv(q) for q in range(POW5_INV_SIZE)])}
}};

#endif
"""


def main(argv: list[str]) -> int:
    text = render()
    if argv == ["--check"]:
        if OUT.read_text() != text:
            print(f"{OUT.name} is stale: run python3 runtime/c/json/pow5_table.py")
            return 1
        return 0
    OUT.write_text(text)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
