"""`urwire plot`: one field of a capture over time, a line per joint (or per value).

The x axis is the robot state's own clock (robot_mode_data's timestamp) when the message has
one, else the message's position; the y axis shows the field's label and unit from the
spec (the generated classes keep them in their fields' metadata). matplotlib is an optional
extra (`pip install urwire[plot]`).
"""
from __future__ import annotations

import argparse
import sys

from typing import Callable

from .canonical import has_error, to_json_line
from .generated import messages as _m
from .reading import decode_file


def add_parser(sub, version_arg) -> None:
    p = sub.add_parser("plot", help="plot one field of a capture over time",
                       description="Plot a field such as joint_data.q_actual: a line per joint or per value.")
    p.add_argument("file", help="a raw stream, a .pcap or a .pcapng file")
    p.add_argument("--field", required=True, metavar="KIND.FIELD",
                   help="e.g. joint_data.q_actual or tool_data.tool_current")
    p.add_argument("--out", default="plot.png", metavar="FILE", help="image to write (default: plot.png)")
    p.add_argument("--version-hint", type=version_arg, metavar="X.Y[.Z]",
                   help="software version to assume until a Version message is seen")
    p.set_defaults(run=plot_command)


def kind_class(kind: str):
    """The generated class whose TYPE is `kind`, or None."""
    for name in _m.__all__ if hasattr(_m, "__all__") else dir(_m):
        cls = getattr(_m, name, None)
        if isinstance(cls, type) and getattr(cls, "TYPE", None) == kind:
            return cls
    return None


def field_metadata(cls, name: str) -> dict:
    """{'label', 'unit'} of a field: the spec's label and unit, which every generated class
    keeps in its fields' metadata; the field's name when the class has no such field."""
    field = getattr(cls, "__dataclass_fields__", {}).get(name)
    meta = field.metadata if field is not None else {}
    return {"label": meta.get("label") or name, "unit": meta.get("unit")}


def axis_title(cls, name: str) -> str:
    meta = field_metadata(cls, name)
    return f"{meta['label']} ({meta['unit']})" if meta["unit"] else meta["label"]


def series(path: str, kind: str, name: str, hint=None,
           on_error: Callable[[object], None] = lambda record: None) -> tuple[list, list[list], str, object]:
    """(x values, one list of y values per line, x axis title, the class that holds the field);
    each record with an error goes to `on_error`."""
    xs: list = []
    lines: list[list] = []
    holder = None
    clock = "message position"
    for position, record in enumerate(decode_file(path, hint)):
        if has_error(record):
            on_error(record)
        parts = getattr(record, "packages", None)
        parts = parts if parts is not None else [record]
        x = position
        for part in parts:
            if getattr(part, "TYPE", None) == "robot_mode_data" and part.timestamp is not None:
                x, clock = part.timestamp, "robot_mode_data timestamp"
        for part in parts:
            if getattr(part, "TYPE", None) != kind:
                continue
            values = _values(part, name)
            if values is None:
                continue
            holder = holder or _holder(part, name)
            while len(lines) < len(values):
                lines.append([None] * len(xs))
            xs.append(x)
            for i, line in enumerate(lines):
                line.append(values[i] if i < len(values) else None)
    return xs, lines, clock, holder


def _values(part, name: str):
    if hasattr(part, name):
        value = getattr(part, name)
        if value is None:
            return None
        return [float(v) for v in value] if isinstance(value, list) else [float(value)]
    for group, kind, _ in part.JSON:   # a field of a group's items: one value per item (joint)
        if kind == "items" and getattr(part, group) and hasattr(getattr(part, group)[0], name):
            return [float(getattr(item, name)) for item in getattr(part, group)]
    return None


def _holder(part, name: str):
    if hasattr(part, name):
        return type(part)
    for group, kind, _ in part.JSON:
        if kind == "items" and getattr(part, group):
            return type(getattr(part, group)[0])
    return type(part)


def plot_command(args: argparse.Namespace) -> int:
    kind, _, name = args.field.partition(".")
    if not name or kind_class(kind) is None:
        print(f"urwire plot: --field is KIND.FIELD with a known kind, e.g. joint_data.q_actual; got {args.field}",
              file=sys.stderr)
        return 2
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("urwire plot: plotting needs matplotlib: pip install urwire[plot]", file=sys.stderr)
        return 2
    errors: list = []
    try:
        xs, lines, clock, holder = series(args.file, kind, name, args.version_hint, errors.append)
    except OSError as exc:
        print(f"urwire plot: cannot read {args.file}: {exc.strerror or exc}", file=sys.stderr)
        return 2
    if not xs:
        print(f"urwire plot: no {args.field} in {args.file}", file=sys.stderr)
        return 1
    fig, ax = plt.subplots(figsize=(10, 5))
    for i, line in enumerate(lines):
        ax.plot(xs, line, label=f"joint {i}" if len(lines) == 6 else f"{name}[{i}]" if len(lines) > 1 else name)
    ax.set_xlabel(clock)
    ax.set_ylabel(axis_title(holder, name))
    ax.set_title(args.field)
    if len(lines) > 1:
        ax.legend(loc="upper right", fontsize="small")
    try:
        fig.savefig(args.out, dpi=100)
    except OSError as exc:
        print(f"urwire plot: cannot write {args.out}: {exc.strerror or exc}", file=sys.stderr)
        return 2
    print(f"urwire plot: {len(xs)} points, {len(lines)} lines -> {args.out}", file=sys.stderr)
    if errors:  # as for decode: the plot shows what was read, the status says not all was
        print(f"urwire plot: {len(errors)} error record(s) in {args.file}, the first: {to_json_line(errors[0])}",
              file=sys.stderr)
        return 1
    return 0
