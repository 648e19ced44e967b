"""What every generated message and sub-package class is built on, and the two kinds of message
the protocol has, as algorithms over the generated tables:

- a list of sub-packages (the robot state): each framed by its own length, read in the form
  that the stream's version or the part's length chooses (PackageList);
- a common header, then a subtype byte that chooses the layout (robot messages, program state
  messages: SubtypeMessage); with no header and no subtype byte, one layout right after the
  message header (a body message: a SubtypeMessage whose subtype is its message type).

urwire.generated.messages holds the classes and the tables (forms, header formats) and makes one
PackageList or SubtypeMessage per message type; nothing here names a message of the spec.
"""
from __future__ import annotations

import struct
from dataclasses import dataclass, field
from typing import Optional, TypeVar

from . import _runtime as _rt
from ._runtime import (DecodeError, EncodeError, MalformedPackage, MalformedSubtype, UnknownMessage, UnknownPackage,
                       UnknownSubtype)
from .generated.spec import DEFAULT_VERSION, HEADER, PACKAGE_HEADER

_P = TypeVar("_P")


class Layout:
    """What every generated class shares: a class of one form defines `_encode`; a class of
    several defines `_encode_0`, `_encode_1`..., `_ENCODERS` (those in order), `_SEGMENT_STARTS`
    (where each segment of the version axis starts) and `_ENCODER_BY_SEGMENT` (the index of its
    encoder in each segment), and is encoded here."""

    __slots__ = ()

    def _encode(self, out: bytearray, version: tuple) -> None:
        """Write the form of `version` (the one it was read in, for a decoded package)."""
        encoder = self._ENCODER_BY_SEGMENT[_rt.segment(self._SEGMENT_STARTS, version)]
        return self._ENCODERS[encoder](self, out, version)


class Package(Layout):
    """What every sub-package class shares."""

    __slots__ = ()

    def encode(self, version: Optional[tuple] = None) -> bytes:
        """The sub-package's bytes, header included; the length is computed. A decoded package
        is written in the form it was read in; a new one in the form of `version`."""
        out = bytearray(PACKAGE_HEADER.size)
        try:
            self._encode(out, self.decoded_version or version or DEFAULT_VERSION)
        except struct.error as exc:
            raise EncodeError(f"{self.TYPE}: {exc}") from None
        PACKAGE_HEADER.pack_into(out, 0, len(out), self.CODE)
        return bytes(out)


class Subtype(Layout):
    """What every robot-message and program-state class shares. Its SubtypeMessage sets
    `MESSAGE` (itself) and `MESSAGE_TYPE` (its code) on the class."""

    __slots__ = ()

    def encode(self, version: Optional[tuple] = None) -> bytes:
        """The whole message, header included; the length is computed."""
        return self.MESSAGE.encode(self, version or DEFAULT_VERSION)


class Item(Layout):
    """One entry of a repeated group."""

    __slots__ = ()


def encode_package(pkg, version: Optional[tuple] = None) -> bytes:
    """Bytes of one sub-package, known, unknown or malformed."""
    if isinstance(pkg, (UnknownPackage, MalformedPackage)):
        return PACKAGE_HEADER.pack(PACKAGE_HEADER.size + len(pkg.raw), pkg.package_type) + pkg.raw
    return pkg.encode(version)


@dataclass(slots=True)
class PackageListMessage:
    """What a message of sub-packages (the robot state) holds; the generated class names it."""

    packages: list
    """The sub-packages in wire order: known ones, UnknownPackage and MalformedPackage."""
    error: Optional[str] = None
    """Why the sub-packages after `packages` could not be framed, if they could not."""
    raw: bytes = b""
    """The bytes that could not be framed."""
    implied_version: Optional[tuple] = field(default=None, compare=False, repr=False)
    """The software version its layout sizes showed, when the version was not known."""

    def package(self, kind: type[_P]) -> Optional[_P]:
        """The first sub-package of the given class, e.g. `state.package(JointData)`, or None."""
        for pkg in self.packages:
            if type(pkg) is kind:
                return pkg
        return None

    def encode(self, version: Optional[tuple] = None) -> bytes:
        """The whole message, its length and every sub-package length computed."""
        out = bytearray(HEADER.size)
        for pkg in self.packages:
            out += encode_package(pkg, version)
        out += self.raw
        HEADER.pack_into(out, 0, len(out), self.CODE)
        return bytes(out)


class PackageList:
    """A message of length-framed sub-packages: `cls` (a PackageListMessage) and the forms of
    each sub-package type code."""

    __slots__ = ("cls", "forms", "body_offset")

    def __init__(self, cls: type, forms: _rt.Forms, body_offset: int):
        self.cls, self.forms, self.body_offset = cls, forms, body_offset

    def package_classes(self, version: tuple) -> dict:
        """The class each sub-package type code is read into in a stream of `version`, in code order."""
        return {code: form.cls for code, form in sorted(self.forms.sent(version).items())}

    def decode(self, buf, version: tuple, known: bool):
        cls, forms = self.cls, self.forms
        header = PACKAGE_HEADER.size
        unpack_header = PACKAGE_HEADER.unpack_from
        end = len(buf)
        implied = None
        pos = self.body_offset
        packages: list = []
        fast = forms.fast(version)
        while pos < end:
            left = end - pos
            if left < header:
                return cls(packages, f"package at offset {pos}: needs {header} bytes, {left} left", bytes(buf[pos:]))
            size, code = unpack_header(buf, pos)
            if size < header:
                return cls(packages, f"package at offset {pos}: length {size} is below {header}", bytes(buf[pos:]))
            if size > left:
                return cls(packages, f"package at offset {pos}: length {size} exceeds the {left} bytes left",
                           bytes(buf[pos:]))
            body, stop = pos + header, pos + size
            decode = fast.get(code)
            if decode is not None:
                # The version's form, when it reads the part to its last byte: the common case.
                try:
                    pkg, used = decode(buf, body, stop, version)
                except DecodeError:
                    used = -1
                if used == stop:
                    packages.append(pkg)
                    pos = stop
                    continue
            pkg, shown = forms.part(buf, body, stop, code, version, known)
            packages.append(pkg)
            if shown is not None:
                # The layout size tells the version: the rest of the message follows it.
                version = implied = shown
                fast = forms.fast(version)
            pos = stop
        if implied is None:
            return cls(packages)
        return cls(packages, implied_version=implied)


class SubtypeMessage:
    """A message with a common header (`header`: its fields, then the subtype byte; unpacked
    from `header_offset`, `run` names each for errors) and a layout per subtype code. With no
    `subtype` (a body message) there is no subtype byte: one layout, whose code is `code`.

    `converts` are (index in the header, enum lookup, by version?) of header fields that are
    enums. When `announces` is a subtype code, that subtype is the Version message: it is read
    in the form of the version it carries, found through `version_skips` and `version_tail`."""

    __slots__ = ("code", "header", "names", "run", "header_offset", "body_offset", "subtype", "converts", "forms",
                 "announces", "version_skips", "version_tail", "implied_subtype")

    def __init__(self, code: int, header: struct.Struct, names: tuple, run: tuple, header_offset: int,
                 body_offset: int, subtype: Optional[str], converts: tuple, forms: _rt.Forms, layouts: tuple,
                 announces: Optional[int] = None, version_skips: tuple = (), version_tail: int = 0):
        self.code, self.header, self.names, self.run = code, header, names, run
        self.header_offset, self.body_offset = header_offset, body_offset
        self.subtype, self.converts, self.forms = subtype, converts, forms
        self.announces, self.version_skips, self.version_tail = announces, version_skips, version_tail
        # The subtype code when no byte carries it: the message type's own.
        self.implied_subtype = () if subtype else (code,)
        for cls in layouts:
            cls.MESSAGE, cls.MESSAGE_TYPE = self, code

    def decode(self, buf, version: tuple, known: bool):
        end = len(buf)
        body = self.body_offset
        if end < body:
            return UnknownMessage(self.code, bytes(buf[HEADER.size:]), _rt.short_in_run(self.run, 0, end).text)
        *header, subtype = self.header.unpack_from(buf, self.header_offset) + self.implied_subtype
        for i, lookup, by_version in self.converts:
            header[i] = (lookup[version] if by_version else lookup).get(header[i], header[i])
        header = tuple(header)
        forms = self.forms.by_code.get(subtype)
        if forms is None:
            return UnknownSubtype(self.code, self.subtype, subtype, tuple(zip(self.names, header)), bytes(buf[body:]))
        if subtype == self.announces:
            # The Version message is read in the form of the version it carries.
            version = _rt.peek_version(buf, body, self.version_skips, self.version_tail) or version
        decode, use, _, form = (self.forms.at(version).get(end << 8 | subtype)
                                or self.forms.pick(version, subtype, end, body))
        try:
            msg, used = decode(buf, body, end, use, header)
        except DecodeError as exc:
            return MalformedSubtype(form.cls.TYPE, self.code, self.subtype, subtype, tuple(zip(self.names, header)),
                                    exc.text, bytes(buf[body:]))
        if used < end:
            msg.extra = bytes(buf[used:end])
        return msg

    def encode(self, msg, version: tuple) -> bytes:
        out = bytearray(HEADER.size)
        kept_raw = isinstance(msg, (UnknownSubtype, MalformedSubtype))
        subtype = msg.subtype if kept_raw else msg.CODE
        values = [getattr(msg, name) for name in self.names]
        if not self.implied_subtype:
            values.append(subtype)
        out += self.header.pack(*values)
        if kept_raw:
            out += msg.raw
        else:
            try:
                msg._encode(out, msg.decoded_version or version)
            except struct.error as exc:
                raise EncodeError(f"{msg.TYPE}: {exc}") from None
        HEADER.pack_into(out, 0, len(out), self.code)
        return bytes(out)
