"""One framed message to a record and back: decode_message, encode_message, and package_classes,
over the table of message types that urwire.generated.messages makes (MESSAGES).

Under the C backend (extension.py) robot states are framed in C (urwire._ccore.PackageStates),
each sub-package a copy of the record the same bytes gave last, else read by the version's form
as PackageList.decode reads it: in C for the forms of one fixed run (RUN_RECIPES), else by the
form's Python decoder; what that common case does not cover is read here in Python."""
from __future__ import annotations

from typing import Optional

from . import _runtime as _rt
from ._runtime import MalformedSubtype, UnknownMessage, UnknownSubtype
from .arguments import bytes_of, version_of
from .extension import CCORE
from .generated.messages import ITEM_RUNS, MESSAGES, RUN_RECIPES
from .generated.spec import DEFAULT_VERSION, HEADER, MESSAGE_TYPE_OFFSET
from .message_kinds import PackageList

# The message of sub-packages (the robot state): the one whose sub-package classes are asked for.
(_PACKAGE_LIST,) = (kind for kind in MESSAGES.values() if isinstance(kind, PackageList))
_PACKAGE_LIST_TYPE = next(code for code, kind in MESSAGES.items() if kind is _PACKAGE_LIST)
# Its records from C under the C backend; None under pure Python.
_C_STATES = None if CCORE is None else CCORE.PackageStates(
    _PACKAGE_LIST.cls, _PACKAGE_LIST.forms, _PACKAGE_LIST.body_offset, RUN_RECIPES, ITEM_RUNS,
    message_type=_PACKAGE_LIST_TYPE, type_offset=MESSAGE_TYPE_OFFSET, default_version=DEFAULT_VERSION)


def package_classes(version) -> dict:
    """The class each sub-package type code is read into in a stream of `version` ((major,
    minor, bugfix) or a text such as '3.2'), in code order: the layout of that version's form
    (a part of another length may still be read in another form)."""
    return _PACKAGE_LIST.package_classes(version_of(version))


def decode_message(buf, version: Optional[tuple] = None, known: Optional[bool] = None):
    """Decode one framed message (its declared length is len(buf)); never raises on bad bytes.

    `buf` is any bytes-like object. `version` ((major, minor, bugfix), or a text such as
    '5.25.1') is the stream's software version: it chooses the layout of each part and the
    meaning of version-dependent codes. Without it, DEFAULT_VERSION is assumed and a robot
    state's layout sizes may overrule it (`implied_version`). `known` says whether `version` is
    known (announced or hinted) rather than assumed.
    """
    if _C_STATES is not None:
        # First the common case at C speed: a robot state's bytes, the version a tuple or None.
        msg = _C_STATES.decode(buf, version)
        if msg is not None:
            return msg
    given = buf, version
    if type(buf) is not bytes:
        buf = bytes_of(buf, "decode_message")
    if len(buf) < HEADER.size:
        return UnknownMessage(0, buf, _rt.short("length", 0, HEADER.size, len(buf)).text)
    if version is not None:
        version = version_of(version)
    if _C_STATES is not None and (buf is not given[0] or version is not given[1]):
        msg = _C_STATES.decode(buf, version)      # the same, once the arguments are as it takes them
        if msg is not None:
            return msg
    return decode_in_python(buf, version, known)


def decode_in_python(buf: bytes, version: Optional[tuple], known: Optional[bool]):
    """decode_message in pure Python, whatever the backend: buf is bytes of at least a header,
    version a tuple or None."""
    kind = MESSAGES.get(buf[MESSAGE_TYPE_OFFSET])
    if kind is None:
        return UnknownMessage(buf[MESSAGE_TYPE_OFFSET], bytes(buf[HEADER.size:]))
    if version is None:
        return kind.decode(buf, DEFAULT_VERSION, bool(known))
    return kind.decode(buf, version, known is not False)


def encode_message(msg, version: Optional[tuple] = None) -> bytes:
    """The bytes of a decoded or hand-built message; lengths are computed, never taken."""
    if isinstance(msg, UnknownMessage):
        return HEADER.pack(HEADER.size + len(msg.raw), msg.message_type) + msg.raw
    if isinstance(msg, (UnknownSubtype, MalformedSubtype)):
        return MESSAGES[msg.message_type].encode(msg, version or DEFAULT_VERSION)
    return msg.encode(version)
