"""C spelled once: string literals, literals of plain values, identifier parts and comment text,
for the C parser and the Wireshark (epan) dissectors alike."""
from __future__ import annotations

import re
import textwrap
from typing import Optional

from .. import wrap


def string(text: str) -> str:
    """A C string literal; bytes outside printable ASCII as octal escapes, so the file is
    ASCII-clean and the compiled bytes are the text's UTF-8."""
    out = []
    for b in text.encode("utf-8"):
        ch = chr(b)
        if ch == "\\":
            out.append("\\\\")
        elif ch == '"':
            out.append('\\"')
        elif ch == "\n":
            out.append("\\n")
        elif b < 32 or b > 126:
            out.append(f"\\{b:03o}")
        else:
            out.append(ch)
    return '"' + "".join(out) + '"'


def string_or_null(text: Optional[str]) -> str:
    """A C string literal, or NULL for no text."""
    return "NULL" if text is None else string(text)


def prose(text: str, indent: str) -> str:
    """A long C string literal as adjacent literals, one per line, at most wrap.PROSE wide; C joins
    them into one string."""
    pieces = wrap.lines(text, "", "", wrap.PROSE - len(indent) - 4)
    words = [p + (" " if i < len(pieces) - 1 else "") for i, p in enumerate(pieces)]
    return ("\n" + indent).join(string(w) for w in words)


def literal(value) -> str:
    """A Python value as a C initializer in Wireshark's dialect (None NULL, bools TRUE/FALSE)."""
    if value is None:
        return "NULL"
    if isinstance(value, bool):
        return "TRUE" if value else "FALSE"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, str):
        return string(value)
    raise TypeError(f"no C literal for {value!r}")


def value_key(value: int) -> str:
    """A value_string's value: a guint32, a negative code as its two's complement (-1 is 0xffffffff),
    which is what a signed field's value is looked up as."""
    return str(value) if value >= 0 else f"(guint32){value}"


def identifier(text: str) -> str:
    """An identifier part from any name: runs of other characters as one underscore, lower case."""
    return re.sub(r"[^0-9A-Za-z]+", "_", text).strip("_").lower()


def comment(*texts: str, width: int = 92) -> list[str]:
    """Doc strings as the lines of a C comment body (no delimiters), wrapped."""
    text = inline(*texts)
    return textwrap.wrap(text, width) if text else []


def inline(*texts: str) -> str:
    """Doc strings as one line safe inside a C comment."""
    return " ".join(t.strip() for t in texts if t and t.strip()).replace("*/", "* /")
