"""Canonical JSON keeps texts between lines: of floats, and the last text of every message and
sub-package kind with the values it was made from. A line must never depend on what was written
before it: each text here is compared with the same record written with nothing kept."""
from __future__ import annotations

import dataclasses
import math
import random

import pytest
import urwire
from urwire import canonical
from urwire.generated import messages

from tests.tools import valid
from tests.vectors import all_cases


def fresh(record) -> str:
    canonical.forget_texts()
    return urwire.to_json_line(record)


def records() -> list:
    """Records of every vector and of random valid messages of every generation: every layout,
    NaNs and infinities included (the random floats are random bits)."""
    out = [r for case in all_cases() for r in urwire.decode_stream(case.data, case.version)]
    rng = random.Random(7)
    for version in valid.versions():
        data = b"".join(valid.message(rng, version) for _ in range(40))
        out += list(urwire.decode_stream(data, version))
    return out


RECORDS = records()


def parts(record) -> list:
    """The record and its sub-packages."""
    return [record, *getattr(record, "packages", [])]


def test_texts_do_not_depend_on_what_came_before():
    expected = [fresh(r) for r in RECORDS]
    canonical.forget_texts()
    for order in (range(len(RECORDS)), reversed(range(len(RECORDS))), random.Random(1).sample(range(len(RECORDS)), len(RECORDS))):
        for i in order:
            assert urwire.to_json_line(RECORDS[i]) == expected[i]


def changed(value):
    """A value of the same kind that differs from it, in the ways that equality overlooks: a
    zero's sign, an integer for a float of the same value."""
    if isinstance(value, bool):
        return not value
    if isinstance(value, float):
        if value == 0.0:
            return -value if math.copysign(1.0, value) > 0 else 0.0
        return math.nextafter(value, math.inf) if value == value else 1.5
    if isinstance(value, int):
        return int(value) + 1
    if isinstance(value, str):
        return value + "x"
    if isinstance(value, bytes):
        return value + b"\x01"
    return value


def variants(obj) -> list:
    """Ways to change one value of obj in place: (what, change). Lists and the items of groups
    are changed in place, as a user editing a record would."""
    out = []
    for f in dataclasses.fields(obj):
        value = getattr(obj, f.name)
        if isinstance(value, list) and value and not dataclasses.is_dataclass(value[0]):
            out.append((f"{f.name}[0]", lambda v=value: v.__setitem__(0, changed(v[0]))))
        elif isinstance(value, list) and value and dataclasses.is_dataclass(value[0]):
            out += [(f"{f.name}[0].{what}", change) for what, change in variants(value[0])]
        elif value is not None and changed(value) is not value:
            out.append((f.name, lambda n=f.name, v=value: setattr(obj, n, changed(v))))
    return out


@pytest.mark.parametrize("kind", sorted({type(p).__name__ for r in RECORDS for p in parts(r) if hasattr(p, "JSON")}))
def test_a_value_changed_in_place_changes_the_text(kind):
    found = [p for r in RECORDS for p in parts(r) if type(p).__name__ == kind][:3]
    for part in found:
        for what, _ in variants(part):
            obj = _copy(part)
            urwire.to_json_line(obj)             # the writer keeps this text...
            dict(variants(obj))[what]()          # ...then one value changes in place
            assert urwire.to_json_line(obj) == fresh(obj), f"{kind}.{what}"


def _copy(obj):
    """A deep copy of a record: lists and items of its own."""
    values = {}
    for f in dataclasses.fields(obj):
        value = getattr(obj, f.name)
        if isinstance(value, list):
            value = [_copy(v) if dataclasses.is_dataclass(v) else v for v in value]
        values[f.name] = value
    return type(obj)(**values)


def test_signed_zeros_have_their_own_texts():
    cal = messages.CalibrationData(0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    assert '"fx": 0.0' in urwire.to_json_line(cal)
    cal.fx = -0.0
    assert '"fx": -0.0' in urwire.to_json_line(cal)
    cal.fx = 0.0
    assert '"fx": 0.0' in urwire.to_json_line(cal)


def test_an_integer_and_the_float_of_its_value_have_their_own_texts():
    """report_data holds an int32 or a float32, by report_data_type: 1e6 prints as 1000000.0 as a
    float32 and as 1000000 as an integer, though 1000000 == 1e6."""
    msg = next(r for r in RECORDS if hasattr(r, "report_data") and r.report_data is not None)
    msg = _copy(msg)
    msg.report_data = 1e6
    assert '"report_data": 1000000.0' in urwire.to_json_line(msg)
    msg.report_data = 1000000
    assert '"report_data": 1000000' in urwire.to_json_line(msg)
