"""`urwire plot`: one field of a capture over time, a line per joint (or per value); or, given an
MCAP recording of urwire's, the robot's joints and TCP path as a viewer shows them (plot_mcap.py).

The x axis is the robot state's own clock (robot_mode_data's timestamp) when the message has
one, else the message's position; the y axis shows the field's label and unit from the
spec (the generated classes keep them in their fields' metadata). matplotlib is an optional
extra (`pip install urwire[plot]`).

Memory stays flat however long the input: the points go through min/max decimation (decimate.py),
which keeps each line's lowest and highest point in each of at most MAX_BUCKETS runs of
consecutive points; an image a thousand pixels wide looks as the full line would.
"""
from __future__ import annotations

import argparse
import sys

from typing import Callable

from ..arguments import software_version
from ..canonical import has_error, to_json_line
from ..generated import messages as _m
from ..mcap_recording import mcap_missing
from ..reading import decode_file
from . import plot_mcap
from .decimate import MAX_BUCKETS, MinMaxLines


def add_parser(sub) -> None:
    p = sub.add_parser("plot", help="plot one field of a capture over time, or the motion an MCAP recording holds",
                       description="Plot a numeric field such as joint_data.q_actual: a line per joint or per "
                                   "value; or, from an MCAP recording, its joints and its TCP path. Long inputs "
                                   "are decimated in flat memory: each line keeps its "
                                   f"lowest and highest point in each of at most {MAX_BUCKETS} runs of "
                                   "consecutive points, so every peak and dip is drawn.")
    p.add_argument("file", help="a raw stream, a .pcap or a .pcapng file; or an MCAP recording of urwire's, "
                                "drawn whole: its joints over time and its TCP path (docs/recording-view.md)")
    p.add_argument("--field", metavar="KIND.FIELD",
                   help="a numeric field, e.g. joint_data.q_actual or tool_data.tool_current (needed for a "
                        "capture or a stream)")
    p.add_argument("--out", default="plot.png", metavar="FILE", help="image to write (default: plot.png)")
    p.add_argument("--version-hint", type=software_version, metavar="X.Y[.Z]",
                   help="software version to assume until a Version message is seen")
    p.set_defaults(run=plot_command)


def field_metadata(cls, name: str) -> dict:
    """{'label', 'unit'} of a field: the spec's label and unit, which every generated class
    keeps in its fields' metadata; the field's name when the class has no such field."""
    field = getattr(cls, "__dataclass_fields__", {}).get(name)
    meta = field.metadata if field is not None else {}
    return {"label": meta.get("label") or name, "unit": meta.get("unit")}


def axis_title(cls, name: str) -> str:
    meta = field_metadata(cls, name)
    return f"{meta['label']} ({meta['unit']})" if meta["unit"] else meta["label"]


AGG_CHUNK_POINTS = 1000
NUMERIC_KINDS = {"int", "enum", "bool", "f32", "f64", "int|f32", "int|f64", "list:int", "list:f32", "list:f64",
                 "list:bool"}


def _numeric(cls) -> list[str]:
    return [name for name, kind, _ in cls.JSON if kind in NUMERIC_KINDS]


def plottable_fields(kind: str = "") -> list[str]:
    """KIND.FIELD of every numeric field of the spec (of one kind when `kind` is given): the
    fields of the generated classes whose canonical JSON kind is a number or a list of numbers;
    a group's item fields (a joint's q_actual) under the kind that holds the group."""
    out = []
    for name in sorted(dir(_m)):
        cls = getattr(_m, name)
        if not isinstance(cls, type) or not getattr(cls, "TYPE", None) or not hasattr(cls, "JSON"):
            continue
        if kind and cls.TYPE != kind:
            continue
        fields = _numeric(cls) + [f for item in getattr(cls, "ITEMS", {}).values() for f in _numeric(item)]
        out += [f"{cls.TYPE}.{f}" for f in fields]
    return sorted(set(out))


def series(path: str, kind: str, name: str, hint=None,
           on_error: Callable[[object], None] = lambda record: None) -> tuple[MinMaxLines, str, object]:
    """(the field's lines, decimated, x axis title, the class that holds the field); each record
    with an error goes to `on_error`."""
    lines = MinMaxLines()
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
            lines.add(x, values)
    return lines, clock, holder


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


def _pyplot():
    """matplotlib's pyplot drawing to files, or None (said on stderr) when it is not installed."""
    try:
        import matplotlib  # an optional extra: urwire[plot]
        matplotlib.use("Agg")
        # Agg rasterises a line at once, and one that doubles back (several sessions in a
        # capture: their clocks restart) covers the image again each time; in chunks of
        # points its memory stays bounded as well.
        matplotlib.rcParams["agg.path.chunksize"] = AGG_CHUNK_POINTS
        import matplotlib.pyplot as plt
    except ImportError:
        print("urwire plot: plotting needs matplotlib: pip install urwire[plot]", file=sys.stderr)
        return None
    return plt


def plot_command(args: argparse.Namespace) -> int:
    if plot_mcap.is_mcap(args.file):
        return plot_recording(args)
    if args.field is None:
        print("urwire plot: a capture or a stream needs --field KIND.FIELD (an MCAP recording is drawn whole)",
              file=sys.stderr)
        return 2
    kind, _, name = args.field.partition(".")
    if args.field not in plottable_fields():
        known = plottable_fields(kind) or plottable_fields()
        print(f"urwire plot: {args.field} is not a numeric field of the spec; fields it can plot: "
              f"{', '.join(known)}", file=sys.stderr)
        return 2
    plt = _pyplot()
    if plt is None:
        return 2
    errors: list = []
    try:
        lines, clock, holder = series(args.file, kind, name, args.version_hint, errors.append)
    except OSError as exc:
        print(f"urwire plot: cannot read {args.file}: {exc.strerror or exc}", file=sys.stderr)
        return 2
    if not lines.points:
        print(f"urwire plot: no {args.field} in {args.file}", file=sys.stderr)
        return 1
    fig, ax = plt.subplots(figsize=(10, 5))
    count = lines.lines
    for i in range(count):
        ax.plot(*lines.line(i), label=f"joint {i}" if count == 6 else f"{name}[{i}]" if count > 1 else name)
    ax.set_xlabel(clock)
    ax.set_ylabel(axis_title(holder, name))
    ax.set_title(args.field)
    if count > 1:
        ax.legend(loc="upper right", fontsize="small")
    try:
        fig.savefig(args.out, dpi=100)
    except OSError as exc:
        print(f"urwire plot: cannot write {args.out}: {exc.strerror or exc}", file=sys.stderr)
        return 2
    print(f"urwire plot: {lines.points} points, {count} lines -> {args.out}", file=sys.stderr)
    if errors:  # as for decode: the plot shows what was read, the status says not all was
        print(f"urwire plot: {len(errors)} error record(s) in {args.file}, the first: {to_json_line(errors[0])}",
              file=sys.stderr)
        return 1
    return 0


def plot_recording(args: argparse.Namespace) -> int:
    """`urwire plot RECORDING.mcap`: the joints and the TCP path of an MCAP recording (plot_mcap.py)."""
    if args.field is not None:
        print("urwire plot: an MCAP recording is drawn whole, its joints and TCP path: no --field", file=sys.stderr)
        return 2
    if mcap_missing():
        print(f"urwire plot: {mcap_missing()}", file=sys.stderr)
        return 2
    plt = _pyplot()
    if plt is None:
        return 2
    try:
        with open(args.file, "rb") as fh:
            motion = plot_mcap.RecordedMotion(fh)
    except (OSError, ValueError) as exc:   # ValueError: a file cut short, or not of urwire's shape
        print(f"urwire plot: cannot read {args.file}: {getattr(exc, 'strerror', None) or exc}", file=sys.stderr)
        return 2
    if not motion.joints.points or not motion.path.points:   # a source needs both topics
        print(f"urwire plot: no joint positions and TCP pose in {args.file} (docs/mcap.md)", file=sys.stderr)
        return 1
    try:
        plot_mcap.draw(motion, args.out, plt)
    except OSError as exc:
        print(f"urwire plot: cannot write {args.out}: {exc.strerror or exc}", file=sys.stderr)
        return 2
    print(f"urwire plot: {motion.source}: {motion.joints.points} joint positions, {motion.path.seen} TCP poses "
          f"-> {args.out}", file=sys.stderr)
    return 0
