"""Hostile global-variable values, C against Python: nesting at and past the bound
(protocol.max_value_depth), counts far beyond the bytes, negative counts, and a matrix with
zero columns but many rows. Both must agree, and the C build runs under the sanitizers; what
they print stays in proportion to the bytes."""
from __future__ import annotations

import struct

import pytest

from tests.c.harness_c import CommandPeer, parse_lines, python_records
from tests.tools import amplify

LIST, MATRIX, INT, NONE = 17, 18, 15, 0  # the 5.9 codes


def update(values: bytes) -> bytes:
    body = struct.pack(">QBH", 1000, 1, 0) + values
    return struct.pack(">iB", 5 + len(body), 25) + body


def nested(depth: int) -> bytes:
    """A LIST holding a LIST ... `depth` levels in all, the innermost holding one INT."""
    inner = bytes([INT]) + struct.pack(">i", 7)
    for _ in range(depth):
        inner = bytes([LIST]) + struct.pack(">h", 1) + inner
    return inner + b"\n"


CASES = {
    "depth_7": update(nested(7)),          # 8 levels of values: allowed
    "depth_8": update(nested(8)),          # 9: one too deep
    "depth_40": update(nested(40)),
    "list_count_32767_no_items": update(bytes([LIST]) + struct.pack(">h", 32767) + b"\n"),
    "list_count_negative": update(bytes([LIST]) + struct.pack(">h", -1) + b"\n"),
    "matrix_huge": update(bytes([MATRIX]) + struct.pack(">hh", 32767, 32767) + bytes([NONE]) * 50),
    "matrix_zero_columns": update(bytes([MATRIX]) + struct.pack(">hh", 30000, 0) + b"\n"),
    "matrix_negative_columns": update(bytes([MATRIX]) + struct.pack(">hh", 2, -3) + b"\n"),
    "string_negative_length": update(bytes([3]) + struct.pack(">h", -2) + b"\n"),
    "many_nones": update((bytes([NONE]) + b"\n") * 5000),
}


@pytest.fixture(scope="module")
def answers(asan) -> dict[str, tuple[list[str], int]]:
    with CommandPeer(asan.driver) as peer:
        return {name: peer.decode(data) for name, data in CASES.items()}


@pytest.mark.parametrize("name", list(CASES))
def test_hostile_values_agree_with_python(answers, name):
    lines, code = answers[name]
    expected, expected_code = python_records(CASES[name], None)
    assert parse_lines("\n".join(lines).encode()) == expected
    assert code == expected_code


def test_the_depth_bound_is_the_specs():
    import yaml
    from tests.c.harness_c import ROOT
    spec = yaml.safe_load((ROOT / "spec" / "ur_primary.yaml").read_text())
    bound = spec["protocol"]["max_value_depth"]
    assert (ROOT / "generated" / "c" / "urwire.h").read_text().count(f"#define URWIRE_MAX_VALUE_DEPTH {bound} ") == 1
    ok, _ = python_records(update(nested(bound - 1)), None)
    deep, _ = python_records(update(nested(bound)), None)
    assert "error" not in ok[0] and f"nesting deeper than {bound}" in deep[0]["error"]


def test_counts_past_their_bytes_print_in_proportion_to_them(fast):
    """Matrices of 32767 empty rows, five bytes each: errors, not millions of rows."""
    data = amplify.hostile_stream()
    cap = amplify.OUTPUT_PER_INPUT * len(data)
    hostile = amplify.run([str(fast.cli), "-"], data, cap=cap)
    assert hostile.printed <= cap
    assert hostile.code == 1
