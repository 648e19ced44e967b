"""Lua spelled once: string literals (short, and long ones over several lines), literals of plain
values and the field-table entries of a dissector."""
from __future__ import annotations

from .. import wrap


def string(text: str) -> str:
    """A Lua double-quoted string literal."""
    out = []
    for ch in text:
        if ch == "\\":
            out.append("\\\\")
        elif ch == '"':
            out.append('\\"')
        elif ch == "\n":
            out.append("\\n")
        elif ord(ch) < 32:
            out.append(f"\\{ord(ch)}")
        else:
            out.append(ch)
    return '"' + "".join(out) + '"'


def text(value: str, indent: str = "", column: int = 0) -> str:
    """A long Lua string literal over several lines: each line but the last ends in a space and
    `\\z`, which makes Lua skip the line break and the next line's indentation, so the value is
    the text exactly. It breaks only before a word (never before a space the text keeps)."""
    words = value.split(" ")
    lines, line = [], []
    for word in words:
        width = (wrap.PROSE - column if not lines else wrap.PROSE - len(indent)) - 4
        if line and word and len(string(" ".join(line + [word]))) > width:
            lines.append(" ".join(line))
            line = [word]
        else:
            line.append(word)
    lines.append(" ".join(line))
    literals = [string(piece)[1:-1] for piece in lines]
    return '"' + (" \\z\n" + indent).join(literals) + '"'


def field(call: str, key: str, description: str, indent: str = "    ") -> str:
    """One entry of a field table, `[key] = ProtoField.x(..., description),` where `call` is the
    constructor up to its last argument, one argument a line: on one line when it fits, else the
    description (wrapped by `text`) on the lines under it, and the constructor under the key when
    even that is long."""
    args = "\n".join(a.strip() for a in call.splitlines() if a.strip())
    flat = args.replace("\n", " ")
    one = f"{indent}[{key}] = {flat}, {string(description)}),"
    if len(one) <= wrap.LIMIT:
        return one
    inner = indent + "    "
    head = f"{indent}[{key}] = {flat},"
    if len(head) <= wrap.LIMIT:
        lines = [head]
    else:
        lines = [f"{indent}[{key}] ="] + [inner + line for line in wrap.pack(args, len(inner), 4).split("\n")]
        lines[-1] += ","
    return "\n".join(lines + [inner + text(description, inner, len(inner)) + "),"])


def literal(value) -> str:
    """A Python value as a Lua literal (None is nil): the templates' `lua` filter."""
    if value is None:
        return "nil"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, str):
        return string(value)
    raise TypeError(f"no Lua literal for {value!r}")
