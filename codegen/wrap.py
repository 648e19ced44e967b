"""Line width of generated files: prose wrapped at word boundaries and long lists of code
spread over aligned lines, the same way in every target (the templates use these as filters).

No generated line is longer than LIMIT columns; prose is wrapped at PROSE, as hand-written
comments are.
"""
from __future__ import annotations

import textwrap

LIMIT = 120
PROSE = 100


def columns(text: str) -> int:
    """How wide a line is: its UTF-8 bytes, as tools that read a file without a locale count its
    columns (a unit such as "m/s²" is one byte wider than it looks)."""
    return len(text.encode("utf-8"))


def lines(text: str, first: str, rest: str, width: int = PROSE) -> list[str]:
    """`text` wrapped at word boundaries: the first line starts with `first`, the others with
    `rest`. A word longer than a line (a URL) stays whole."""
    return textwrap.wrap(" ".join(text.split()), width=width, initial_indent=first, subsequent_indent=rest,
                         break_long_words=False, break_on_hyphens=False) or [first.rstrip()]


def c_comment(text: str, indent: str = "") -> str:
    """A C block comment, "/* ... */", its continuation lines starting with " * "."""
    out = lines(text, indent + "/* ", indent + " * ")
    out[-1] += " */"
    return "\n".join(out)


def line_comment(text: str, indent: str = "", mark: str = "--") -> str:
    """Comment lines that each start with `mark` ("--" in Lua, "#" in Python)."""
    return "\n".join(lines(text, f"{indent}{mark} ", f"{indent}{mark} "))


def docstring(text: str, indent: str = "") -> str:
    """A Python docstring: on one line when it fits, else wrapped with its closing quotes on a
    line of their own."""
    one = f'{indent}"""{text}"""'
    if columns(one) <= PROSE:
        return one
    return "\n".join(lines(text, f'{indent}"""', indent) + [f'{indent}"""'])


def trailing(code: str, comment: str, indent: str = "", syntax: str = "c") -> str:
    """`code` with its comment after it on the same line when both fit in LIMIT, else the
    comment wrapped on the lines above it; no comment when it is empty."""
    marks = {"c": ("/* ", " */"), "lua": ("-- ", ""), "python": ("# ", "")}
    opening, closing = marks[syntax]
    if not comment:
        return f"{indent}{code}"
    one = f"{indent}{code}  {opening}{comment}{closing}"
    if columns(one) <= LIMIT:
        return one
    above = c_comment(comment, indent) if syntax == "c" else line_comment(comment, indent, opening.strip())
    return f"{above}\n{indent}{code}"


def spread(items: list[str], open_: str, close: str = "", indent: str = "", width: int = LIMIT,
           hang: bool = False) -> str:
    """`open_` followed by `items` joined with ", " and then `close`: on one line when it fits,
    else as many items per line as fit, continuation lines aligned under the first item (or,
    when not even the first item fits after `open_`, or `hang` asks for it, indented by four
    under the line)."""
    one = f"{indent}{open_}{', '.join(items)}{close}"
    if columns(one) <= width or not items:
        return one
    first = indent + open_
    if hang or columns(first) + columns(items[0]) + 1 > width:
        out, hang, line = [first.rstrip()], indent + "    ", indent + "    "
    else:
        out, hang, line = [], " " * len(first), first
    empty = True                                   # nothing on `line` yet but its indentation
    for n, item in enumerate(items):
        piece = item + (close if n == len(items) - 1 else ",")
        if not empty and columns(line) + 1 + columns(piece) > width:
            out.append(line)
            line, empty = hang, True
        line += piece if empty else " " + piece
        empty = False
    return "\n".join(out + [line])


def chain(names: list[str], value: str, indent: str = "", width: int = LIMIT) -> str:
    """One chained assignment, `a = b = ... = value`: continued after a backslash under the
    first name when it is long."""
    out, line = [], indent
    for name in names:
        piece = f"{name} = "
        if line.strip() and columns(line) + columns(piece) + columns(value) + 2 > width:
            out.append(line + "\\")
            line = indent + "    "
        line += piece
    return "\n".join(out + [line + value])


def pack(entries: str, column: int = 0, hang: int = 2, width: int = LIMIT) -> str:
    """Entries that a template laid out one per line (the pieces of a table constructor), packed
    into as few lines as fit from `column` on: one line when the whole fits, else continuation
    lines indented `hang` more than the first (relative: the caller indents the block). One column
    is left for the separator that follows the block."""
    width -= 1
    items = [e.strip() for e in entries.strip().splitlines() if e.strip()]
    one = " ".join(items)
    if column + columns(one) <= width:
        return one
    out, line = [], ""
    for item in items:
        limit = width - column - (hang if out else 0)
        if line and columns(line) + 1 + columns(item) > limit:
            out.append(line)
            line = item
        else:
            line = f"{line} {item}" if line else item
    out.append(line)
    return ("\n" + " " * hang).join(out)


FILTERS = dict(c_comment=c_comment, line_comment=line_comment, docstring=docstring, trailing=trailing,
               spread=spread, chain=chain, pack=pack)
