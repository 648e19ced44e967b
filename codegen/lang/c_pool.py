"""Texts in one C object, a pool: each text once, NUL-terminated, found by its offset. A table row
then holds a 2-byte offset instead of a pointer (4 or 8 bytes), and the texts are one object that
the linker keeps or drops whole, with the table that reads it (string literals of a file share one
section, kept whole as soon as any of them is used).

C99 promises string literals of 4095 bytes only (gcc -pedantic warns past them), so the pool is a
struct of char arrays laid end to end, each initialised by one literal of at most PART bytes."""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Iterable

from . import c
from ..wrap import LIMIT, columns

PART = 4000
MAX_OFFSET = 0xffff             # offsets are uint16_t


@dataclass
class Part:
    size: int = 0               # its texts' bytes, NULs included, and the literal's own NUL
    lines: list[str] = field(default_factory=list)     # its initializer: adjacent literals (a column
                                                        # left for the comma after them)


class Pool:
    """The texts in their first order, each once; `parts` as the C struct declares and initialises
    them, `offset` where a text starts from the struct's first byte."""

    def __init__(self, texts: Iterable[str], indent: str = "    ", width: int = LIMIT - 1):
        self.offsets: dict[str, int] = {}
        self.parts: list[Part] = [Part(size=1)]
        at = 0
        for text in texts:
            if text in self.offsets:
                continue
            size = len(text.encode("utf-8")) + 1
            if size + 1 > PART:
                raise ValueError(f"a text of {size - 1} bytes is longer than a part of the pool: {text[:40]!r}")
            if self.parts[-1].size + size > PART:
                at += self.parts[-1].size
                self.parts.append(Part(size=1))
            part = self.parts[-1]
            self.offsets[text] = at + part.size - 1
            if self.offsets[text] > MAX_OFFSET:
                raise ValueError(f"the pool's texts pass {MAX_OFFSET} bytes: offsets would not fit a uint16_t")
            part.size += size
            _append(part.lines, c.string(text)[:-1] + '\\0"', indent, width)

    def offset(self, text: str) -> int:
        return self.offsets[text]


def _append(lines: list[str], literal: str, indent: str, width: int) -> None:
    """A literal after the last line's when both fit in `width`, else on a line of its own."""
    if lines and columns(lines[-1]) + 1 + columns(literal) <= width:
        lines[-1] += " " + literal
    else:
        lines.append(indent + literal)
