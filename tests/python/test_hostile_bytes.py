"""Random and mutated bytes never raise anything, never hang, never allocate without bound."""
from __future__ import annotations

import os
import struct
import sys
from pathlib import Path

import pytest
import urwire
from hypothesis import given, settings, strategies as st

from tests.tools import amplify
from tests.tools.streams import mutate
from tests.vectors import all_cases

CLI_ENV = dict(os.environ, PYTHONPATH=os.pathsep.join(str(Path(__file__).resolve().parents[2] / part) for part in ("python", "generated/python")))

MESSAGES = [c.data for c in all_cases()]
KNOWN = (urwire.StreamError, urwire.UnknownMessage, urwire.UnknownSubtype, urwire.MalformedSubtype)


def decode_all(data: bytes, hint=None) -> list:
    records = list(urwire.decode_stream(data, hint))
    for r in records:
        urwire.to_json_line(r)  # printing must not fail either
    return records


@settings(max_examples=500, deadline=2000)
@given(data=st.binary(max_size=2000))
def test_random_bytes_decode_without_raising(data):
    decode_all(data)


@settings(max_examples=500, deadline=2000)
@given(index=st.integers(0, len(MESSAGES) - 1), seed=st.randoms(use_true_random=False),
       rounds=st.integers(1, 4), hint=st.sampled_from([None, "3.2", "5.0", "5.9"]))
def test_mutated_messages_decode_without_raising(index, seed, rounds, hint):
    data = MESSAGES[index]
    for _ in range(rounds):
        data = mutate(data, seed)
    decode_all(data, hint)


def update_message(values: bytes) -> bytes:
    body = bytes(8) + b"\x01" + b"\x00\x00" + values
    return struct.pack(">iB", len(body) + 5, 25) + body


def test_nesting_is_bounded():
    list_of = lambda inner: b"\x11\x00\x01" + inner  # LIST (5.9 code 17) of one item
    within = list_of(list_of(list_of(list_of(list_of(list_of(list_of(b"\x0f\x00\x00\x00\x07")))))))
    (ok,) = decode_all(update_message(within + b"\x0a"))
    assert not urwire.canonical.has_error(ok)
    too_deep = list_of(within)
    (bad,) = decode_all(update_message(too_deep + b"\x0a"))
    assert "nesting deeper than 8" in bad.error


def test_huge_counts_fail_fast_instead_of_allocating():
    huge_list = b"\x11\x7f\xff"              # LIST of 32767 items, none present
    huge_matrix = b"\x12\x7f\xff\x7f\xff"    # MATRIX 32767 x 32767, none present
    for values, items in ((huge_list, 32767), (huge_matrix, 32767 * 32767)):
        (msg,) = decode_all(update_message(values + b"\x0a"))
        assert isinstance(msg, urwire.MalformedSubtype)
        assert msg.error == f"variables[0] at offset 17: {items} items need more than the 1 bytes left"


@pytest.mark.parametrize("fmt", ["json", "text"])
def test_counts_past_their_bytes_print_and_cost_no_more_than_legal_values(fmt):
    """Matrices of 32767 empty rows, five bytes each: errors, not millions of rows."""
    command = [sys.executable, "-m", "urwire", "decode", "--format", fmt, "-"]
    data = amplify.hostile_stream()
    cap = amplify.OUTPUT_PER_INPUT * len(data)
    hostile = amplify.run(command, data, cap=cap, env=CLI_ENV)
    legal = amplify.run(command, amplify.legal_stream(), env=CLI_ENV)
    assert hostile.printed <= cap
    assert hostile.code == 1 and legal.code == 0
    assert hostile.peak <= 2 * legal.peak


def test_errors_name_the_field_and_offset():
    joint_data = struct.pack(">iB", 5 + 100, 1) + bytes(100)
    state = struct.pack(">iB", 5 + len(joint_data), 16) + joint_data
    (record,) = decode_all(state)
    (pkg,) = record.packages
    assert pkg.error == "joints[2].qd_actual at offset 108: needs 8 bytes, 2 left"
    assert pkg.raw == bytes(100)
