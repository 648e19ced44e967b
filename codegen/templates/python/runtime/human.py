"""A readable one-line view of each record: enum names, text in quotes.

Hand-written; copied into generated/python/urwire/ by `make generate`.
"""
from __future__ import annotations

from enum import IntEnum
from typing import Any

from ._runtime import (GlobalValue, MalformedPackage, MalformedSubtype, StreamError, UnknownMessage,
                       UnknownPackage, UnknownSubtype)


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
    if isinstance(v, list):
        if len(v) > 6 and not isinstance(v[0], (int, float, str)):
            return f"[{len(v)} items]"
        return "[" + ", ".join(_show(x) for x in v) + "]"
    if hasattr(v, "JSON"):
        return "{" + " ".join(f"{n}={_show(getattr(v, n))}" for n, _, _ in v.JSON) + "}"
    return str(v)


def _package(p: Any) -> str:
    if isinstance(p, UnknownPackage):
        return f"unknown package {p.package_type} ({len(p.raw)} bytes)"
    if isinstance(p, MalformedPackage):
        return f"{p.name} ! {p.error}"
    shown = " ".join(f"{n}={_show(getattr(p, n))}" for n in p.SUMMARY)
    extra = f" +{len(p.extra)} extra bytes" if p.extra else ""
    return f"{p.TYPE}" + (f" {shown}" if shown else "") + extra


def line(record: Any) -> str:
    if isinstance(record, StreamError):
        return f"{'! stream fault':<24} at offset {record.offset}: {record.error}"
    if isinstance(record, UnknownMessage):
        why = f" ! {record.error}" if record.error else ""
        return f"{'unknown':<24} message type {record.message_type} ({len(record.raw)} bytes){why}"
    if isinstance(record, UnknownSubtype):
        return (f"{'unknown':<24} message type {record.message_type} subtype {record.subtype} "
                f"({len(record.raw)} bytes)")
    if isinstance(record, MalformedSubtype):
        return f"{record.name:<24} ! {record.error}"
    if hasattr(record, "packages"):
        parts = [_package(p) for p in record.packages if not hasattr(p, "SUMMARY") or p.SUMMARY
                 or isinstance(p, (UnknownPackage, MalformedPackage)) or p.extra]
        tail = f" ! {record.error}" if record.error else ""
        return f"{record.TYPE:<24} [{len(record.packages)} packages] " + " | ".join(parts) + tail
    fields = " ".join(f"{n}={_show(getattr(record, n))}" for n, _, _ in record.JSON)
    extra = f" +{len(record.extra)} extra bytes" if record.extra else ""
    return f"{record.TYPE:<24} {fields}{extra}"
