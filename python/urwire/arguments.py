"""What the public functions and the commands take: bytes-like input, software versions, ports
and numbers, checked once at the door so that a wrong type is a TypeError saying what is wanted
(a command's: argparse's one-line error, exit 2), not a failure deep inside.
"""
from __future__ import annotations

import argparse
import math
from typing import Optional, Union

VersionLike = Union[str, tuple, None]

_VERSION_TYPES = "a str such as '5.9' or '5.25.1' or a tuple such as (5, 25, 1)"

# A version text is read as the C command reads it: ASCII blanks around it (str.strip() alone
# would also take Unicode ones), and parts of one to six ASCII digits (str.isdigit() alone would
# also take "５" and "²"). A tuple's parts have the same range.
_BLANKS = " \t\n\r\v\f"
_PART_DIGITS = 6


def _is_part(text: str) -> bool:
    return 1 <= len(text) <= _PART_DIGITS and text.isascii() and text.isdigit()


def _is_number(x) -> bool:
    return isinstance(x, int) and not isinstance(x, bool) and 0 <= x < 10 ** _PART_DIGITS


def bytes_of(data, who: str) -> bytes:
    """The bytes of any object with the buffer protocol (an array.array of ints gives its memory,
    as memoryview(data).cast('B') would); anything else is a TypeError naming `who`."""
    if type(data) is bytes:
        return data
    try:
        view = memoryview(data)
    except TypeError:
        raise TypeError(f"{who}: expected a bytes-like object (bytes, bytearray, memoryview or another "
                        f"buffer), got {type(data).__name__}") from None
    return view.tobytes()


def parse_version(version: VersionLike) -> Optional[tuple[int, int, int]]:
    """'5.9', '5.25.1', (5, 9), (5, 25, 1) or None -> (major, minor, bugfix) or None."""
    if version is None:
        return None
    if isinstance(version, str):
        parts = version.strip(_BLANKS).split(".")
        if not 2 <= len(parts) <= 3 or not all(_is_part(p) for p in parts):
            raise ValueError(f"not a software version: {version!r} (expected e.g. 5.9 or 5.25.1)")
        numbers = [int(p) for p in parts]
    elif isinstance(version, (tuple, list)):
        if not 2 <= len(version) <= 3 or not all(_is_number(x) for x in version):
            raise ValueError(f"not a software version: {version!r} (expected e.g. (5, 9) or (5, 25, 1))")
        numbers = [int(x) for x in version]
    else:
        raise TypeError(f"a software version is {_VERSION_TYPES}, not {type(version).__name__}")
    major, minor, bugfix = (numbers + [0])[:3]
    return major, minor, bugfix


def software_version(text: str) -> tuple[int, int, int]:
    """A command-line software version (X.Y or X.Y.Z), else refused (argparse: exit 2)."""
    try:
        return parse_version(text)  # type: ignore[return-value]
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def finite_number(text: str) -> float:
    """A command-line number that is one: "nan" and "inf" are refused (argparse: exit 2) as a
    robot refuses them, where float() alone would take them and the live tools spin on them."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"not a finite number: {text!r}")
    return value


HIGHEST_PORT = 65535


def port_of(text: str, lowest: int = 0) -> int:
    """A TCP port number written in ASCII digits, from `lowest` to 65535, else ValueError. int()
    alone would take "-1", " 7" and "٧", and a socket call then fails on the number, or wraps it."""
    if not (text.isascii() and text.isdigit()) or not lowest <= int(text) <= HIGHEST_PORT:
        raise ValueError(f"not a TCP port: {text!r} ({lowest} to {HIGHEST_PORT})")
    return int(text)


def port_number(text: str) -> int:
    """A command-line port to listen on: 0 (a free one) to 65535, else refused (argparse: exit 2)."""
    try:
        return port_of(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def version_of(version) -> Optional[tuple[int, int, int]]:
    """A version argument as (major, minor, bugfix): the framer's own tuples pass untouched."""
    if type(version) is tuple and len(version) == 3 and type(version[0]) is int and type(version[1]) is int \
            and type(version[2]) is int:
        return version
    return parse_version(version)
