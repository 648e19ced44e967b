"""Readable views of a record, with the spec's labels and units, enum names and text in quotes:
one line per record (line), or every field on a line of its own, indented as Wireshark shows
the tree (tree). Fields a record's software version does not send are left out.
"""
from __future__ import annotations

import dataclasses
from enum import IntEnum
from functools import lru_cache
from typing import Any, Optional

from .envelope import Enveloped
from ._runtime import (GlobalValue, MalformedPackage, MalformedSubtype, StreamError, UnknownMessage,
                       UnknownPackage, UnknownSubtype)

WIDTH = 24   # the first column: what the record is


@lru_cache(maxsize=None)
def _labels(cls: type) -> dict[str, tuple[str, Optional[str]]]:
    """Each attribute's label and unit, from its dataclass field metadata."""
    return {f.name: (f.metadata["label"], f.metadata["unit"]) for f in dataclasses.fields(cls) if "label" in f.metadata}


def _words(name: str) -> str:
    """robot_mode_data -> Robot mode data: the label of a part known only by its name."""
    text = name.replace("_", " ")
    return text[:1].upper() + text[1:]


def _show(v: Any) -> str:
    if isinstance(v, IntEnum):
        return v.name
    if isinstance(v, str):
        return repr(v)
    if isinstance(v, float):
        return f"{v:.6g}"
    if isinstance(v, bytes):
        return f"<{len(v)} bytes>"
    if isinstance(v, GlobalValue):
        return f"{v.type}:{_show(v.value)}"
    if isinstance(v, (list, tuple)):
        if len(v) > 6 and not isinstance(v[0], (int, float, str)):
            return f"[{len(v)} items]"
        return "[" + ", ".join(_show(x) for x in v) + "]"
    if hasattr(v, "JSON"):
        return "{" + _fields(v, [n for n, _, _ in v.JSON]) + "}"
    return str(v)


def _fields(obj: Any, names) -> str:
    """'Label: value unit' for each field that holds a value, in the order given."""
    labels = _labels(type(obj))
    out = []
    for name in names:
        value = getattr(obj, name)
        if value is None:
            continue
        label, unit = labels.get(name, (name, None))
        out.append(f"{label}: {_show(value)}" + (f" {unit}" if unit else ""))
    return ", ".join(out)


def _package(p: Any) -> str:
    if isinstance(p, UnknownPackage):
        return f"Unknown package {p.package_type} ({len(p.raw)} bytes)"
    if isinstance(p, MalformedPackage):
        return f"{_words(p.name)} ! {p.error}"
    shown = _fields(p, p.SUMMARY)
    extra = f" +{len(p.extra)} extra bytes" if p.extra else ""
    return p.LABEL + (f" ({shown})" if shown else "") + extra


def _where(record: Enveloped) -> str:
    """Where the record came from, as its JSON's envelope says (nothing for a fault of the capture file)."""
    if record.interface is None:
        return ""
    return f"[{record.interface} {record.direction} {record.conversation}] "


def line(record: Any) -> str:
    if isinstance(record, Enveloped):
        return _where(record) + line(record.record)
    if isinstance(record, StreamError):
        return f"{'! Stream fault':<{WIDTH}} at offset {record.offset}: {record.error}"
    if isinstance(record, UnknownMessage):
        why = f" ! {record.error}" if record.error else ""
        return f"{'Unknown':<{WIDTH}} message type {record.message_type} ({len(record.raw)} bytes){why}"
    if isinstance(record, UnknownSubtype):
        return (f"{'Unknown':<{WIDTH}} message type {record.message_type} subtype {record.subtype} "
                f"({len(record.raw)} bytes)")
    if isinstance(record, MalformedSubtype):
        return f"{_words(record.name):<{WIDTH}} ! {record.error}"
    if hasattr(record, "packages"):
        parts = [_package(p) for p in record.packages if not hasattr(p, "SUMMARY") or p.SUMMARY
                 or isinstance(p, (UnknownPackage, MalformedPackage)) or p.extra]
        tail = f" ! {record.error}" if record.error else ""
        return f"{record.LABEL:<{WIDTH}} [{len(record.packages)} packages] " + " | ".join(parts) + tail
    fields = _fields(record, [n for n, _, _ in record.JSON])
    extra = f" +{len(record.extra)} extra bytes" if record.extra else ""
    return f"{record.LABEL:<{WIDTH}} {fields}{extra}"


def _tree_lines(obj: Any, depth: int, out: list[str]) -> None:
    """Every field of a record, package or item, one per line; items and values nest."""
    pad = "  " * depth
    labels = _labels(type(obj))
    for name, _, _ in obj.JSON:
        value = getattr(obj, name)
        if value is None:
            continue
        label, unit = labels.get(name, (name, None))
        if isinstance(value, list) and value and hasattr(value[0], "JSON"):
            for i, item in enumerate(value):
                out.append(f"{pad}{item.LABEL} {i}")
                _tree_lines(item, depth + 1, out)
            continue
        out.append(f"{pad}{label}: {_show(value)}" + (f" {unit}" if unit else ""))
    if getattr(obj, "extra", b""):
        out.append(f"{pad}Extra bytes: {obj.extra.hex()}")


def tree(record: Any) -> str:
    """The record's heading, then each part and field on a line of its own."""
    if isinstance(record, Enveloped):
        return _where(record) + tree(record.record)
    if not hasattr(record, "JSON") and not hasattr(record, "packages"):
        return line(record)
    if not hasattr(record, "packages"):
        out = [record.LABEL]
        _tree_lines(record, 1, out)
        return "\n".join(out)
    out = [f"{record.LABEL} [{len(record.packages)} packages]"]
    for p in record.packages:
        if hasattr(p, "JSON"):
            out.append(f"  {p.LABEL}")
            _tree_lines(p, 2, out)
        else:
            out.append(f"  {_package(p)}")
    if record.error:
        out.append(f"  ! {record.error}")
    return "\n".join(out)
