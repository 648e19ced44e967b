"""Loader for urwire's language-neutral test vectors.

Two sets live beside this file:

- ``golden/*.yaml``: hand-made cases, one per file. ``hex`` is the whole input stream and
  ``expect`` the complete canonical JSON records (full match, exact floats).
- ``conformance/<origin>/<name>.hex`` with ``<name>.yaml`` beside it: real or published bytes
  from other projects, with a partial expectation (only the keys listed are checked, floats
  within a relative tolerance).

Every decoder (Python, C, Lua) runs every case; ``mismatches`` compares its output, parsed with
Python's ``json`` module, with the expectation. Only the standard library and PyYAML are used.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path

import yaml

HERE = Path(__file__).resolve().parent
GOLDEN_DIR = HERE / "golden"
CONFORMANCE_DIR = HERE / "conformance"


@dataclass(frozen=True)
class Case:
    name: str            # file stem, e.g. "robot_state_joint_data" or "python-urx/packet"
    path: Path           # the YAML file
    data: bytes          # the input stream
    version: str | None  # version hint, or None for the decoder's default
    expect: list         # expected records, in stream order
    partial: bool        # False for golden (full match), True for conformance
    tolerance: float     # relative float tolerance; 0.0 for golden


class VectorError(ValueError):
    """A vector file that cannot be loaded."""


# What scripts/new_vector.py writes into a vector it copied from an older version: the file is
# refused until a person has checked its values and deleted every line that says it.
UNCHECKED = "TODO: check"


_COMMENT = re.compile(r"#.*")
_WHITESPACE = re.compile(r"\s+")


def parse_hex(text: str, where: Path | str) -> bytes:
    """Hex text to bytes: drop ``#`` comments per line, then all whitespace."""
    digits = "".join(_WHITESPACE.sub("", _COMMENT.sub("", line)) for line in text.splitlines())
    try:
        return bytes.fromhex(digits)
    except ValueError as exc:
        raise VectorError(f"{where}: bad hex: {exc}") from None


def _load_yaml(path: Path) -> dict:
    text = path.read_text(encoding="utf-8")
    if UNCHECKED in text:
        line = text[:text.index(UNCHECKED)].count("\n") + 1
        raise VectorError(f"{path}:{line}: {UNCHECKED!r}: a scaffold whose values nobody has checked yet")
    doc = yaml.safe_load(text)
    if not isinstance(doc, dict):
        raise VectorError(f"{path}: expected a mapping at the top")
    return doc


def _version(doc: dict, path: Path) -> str | None:
    v = doc.get("version")
    if v is not None and not isinstance(v, str):
        # 5.10 written unquoted would read as 5.1: insist on a string.
        raise VectorError(f"{path}: version must be a quoted string, got {v!r}")
    return v


def _expect(doc: dict, path: Path) -> list:
    exp = doc.get("expect")
    if not isinstance(exp, list):
        raise VectorError(f"{path}: 'expect' must be a list of records")
    return exp


def golden_cases() -> list[Case]:
    cases = []
    for path in sorted(GOLDEN_DIR.glob("*.yaml")):
        doc = _load_yaml(path)
        if "hex" not in doc:
            raise VectorError(f"{path}: no 'hex'")
        case = Case(name=path.stem, path=path, data=parse_hex(doc["hex"], path),
                    version=_version(doc, path), expect=_expect(doc, path), partial=False, tolerance=0.0)
        cases.append(case)
        if doc.get("also_without_version_message"):
            cases.append(_without_version_message(case))
    return cases


def interface_cases(interface: str) -> list[Case]:
    """The golden cases of another interface of the cell: golden/<interface>/*.yaml, in the same
    form (hex, expect, an optional version)."""
    cases = []
    for path in sorted((GOLDEN_DIR / interface).glob("*.yaml")):
        doc = _load_yaml(path)
        if "hex" not in doc:
            raise VectorError(f"{path}: no 'hex'")
        cases.append(Case(name=f"{interface}/{path.stem}", path=path, data=parse_hex(doc["hex"], path),
                          version=_version(doc, path), expect=_expect(doc, path), partial=False, tolerance=0.0))
    return cases


def _without_version_message(case: Case) -> Case:
    """The same stream with its first message, a Version message, cut off: what a capture that
    starts mid-stream holds. The layout sizes must then tell the version, and the canonical JSON
    of what follows (integers, not names) must not change."""
    if not case.expect or case.expect[0].get("type") != "version" or case.version is not None:
        raise VectorError(f"{case.path}: also_without_version_message needs a Version message first and no hint")
    length = int.from_bytes(case.data[:4], "big")
    return Case(name=f"{case.name}~no_version_message", path=case.path, data=case.data[length:], version=None,
                expect=case.expect[1:], partial=False, tolerance=0.0)


def conformance_cases() -> list[Case]:
    cases = []
    for path in sorted(CONFORMANCE_DIR.glob("*/*.yaml")):
        doc = _load_yaml(path)
        hex_path = path.with_suffix(".hex")
        if not hex_path.is_file():
            raise VectorError(f"{path}: no {hex_path.name} beside it")
        tolerance = float(doc.get("tolerance", 0.0))
        cases.append(Case(name=f"{path.parent.name}/{path.stem}", path=path,
                          data=parse_hex(hex_path.read_text(encoding="ascii"), hex_path),
                          version=_version(doc, path), expect=_expect(doc, path),
                          partial=True, tolerance=tolerance))
    return cases


def all_cases() -> list[Case]:
    return golden_cases() + conformance_cases()


def _is_number(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _numbers_equal(expected, actual, tolerance: float) -> bool:
    if expected == actual:  # exact; Python compares an int with a float exactly
        return True
    if isinstance(expected, int) and isinstance(actual, int):
        return False
    e, a = float(expected), float(actual)
    if math.isnan(e) or math.isnan(a):
        return math.isnan(e) and math.isnan(a)
    if math.isinf(e) or math.isinf(a) or tolerance == 0.0:
        return False
    return abs(a - e) <= tolerance * max(1.0, abs(e))


def _where(path: str) -> str:
    return path or "<top>"


def mismatches(expected, actual, *, partial: bool, tolerance: float, path: str = "") -> list[str]:
    """Differences between an expected and an actual JSON-like value; [] when they match.

    Dicts: with ``partial`` only the expected keys are checked, otherwise the key sets must be
    equal. Lists must have equal length in both modes. Numbers compare numerically (an int
    matches an equal float), within ``tolerance`` relative to max(1, |expected|); NaN matches
    NaN. A bool never matches a number.
    """
    out: list[str] = []
    if isinstance(expected, dict):
        if not isinstance(actual, dict):
            return [f"{_where(path)}: expected an object, got {actual!r}"]
        for key, value in expected.items():
            sub = f"{path}.{key}" if path else str(key)
            if key not in actual:
                out.append(f"{sub}: missing (expected {value!r})")
            else:
                out += mismatches(value, actual[key], partial=partial, tolerance=tolerance, path=sub)
        if not partial:
            for key in actual:
                if key not in expected:
                    sub = f"{path}.{key}" if path else str(key)
                    out.append(f"{sub}: unexpected key (value {actual[key]!r})")
        return out
    if isinstance(expected, list):
        if not isinstance(actual, list):
            return [f"{_where(path)}: expected a list, got {actual!r}"]
        if len(expected) != len(actual):
            out.append(f"{_where(path)}: expected {len(expected)} items, got {len(actual)}")
        for i, (e, a) in enumerate(zip(expected, actual)):
            out += mismatches(e, a, partial=partial, tolerance=tolerance, path=f"{path}[{i}]")
        return out
    if isinstance(expected, bool) or isinstance(actual, bool):
        if not (isinstance(expected, bool) and isinstance(actual, bool) and expected == actual):
            out.append(f"{_where(path)}: expected {expected!r}, got {actual!r}")
        return out
    if _is_number(expected):
        if not _is_number(actual) or not _numbers_equal(expected, actual, tolerance):
            out.append(f"{_where(path)}: expected {expected!r}, got {actual!r}")
        return out
    if expected != actual or type(expected) is not type(actual):
        out.append(f"{_where(path)}: expected {expected!r}, got {actual!r}")
    return out


if __name__ == "__main__":
    golden, conformance = golden_cases(), conformance_cases()
    print(f"{len(golden)} golden cases, {len(conformance)} conformance cases")
