"""The types no UR document lays out, as a Python user meets them: named records with the
spec's labels and marks in the text and tree views, their bytes kept, encoded back exactly."""
from __future__ import annotations

import struct
from pathlib import Path

import urwire
from urwire import human

from tests.vectors import golden_cases

ROOT = Path(__file__).resolve().parents[2]
CASES = {c.name: c for c in golden_cases()}


def decoded(name: str) -> list:
    case = CASES[name]
    return list(urwire.decode_stream(case.data, urwire.parse_version(case.version)))


def test_the_cb3_stream_reads_as_named_records_with_their_marks():
    version, message_12, tolerances = decoded("safety_compliance_tolerances_cb3_3_10")
    assert type(message_12).__name__ == "RobotMessage12Message"
    assert message_12.LABEL == "Robot message 12 (undocumented)"
    assert tolerances.LABEL == "Safety compliance tolerances (undocumented, inferred)"
    assert len(tolerances.tolerances) == 22
    lines = [human.line(r) for r in (message_12, tolerances)]
    assert lines[0].startswith("Robot message 12 (undocumented) Timestamp: ")
    assert lines[0].endswith("Robot message 12 data: <9 bytes>")
    assert lines[1].startswith("Safety compliance tolerances (undocumented, inferred) Tolerances: [0.15, 25, 0, 3,")
    assert not any("Unknown" in line for line in lines)


def test_the_tree_shows_the_payload_with_its_units():
    (state,) = decoded("robot_state_payload_info")
    text = human.tree(state)
    assert "  Payload info (undocumented, inferred)\n    Payload mass: 1 kg\n" in text
    assert "    Payload inertia: [0.001539, 0.001539, 0.001539, 0, 0, 0] kg·m²" in text


def test_the_raw_layouts_keep_every_byte():
    modbus, hmc, broadcast, disconnect, _ = decoded("undocumented_message_types")
    assert (modbus.raw, hmc.raw, broadcast.raw) == (b"\0\0\0\0", b"\xff" * 6, bytes(range(20)))
    assert human.line(modbus) == f"{'Modbus info (undocumented)':<24} Modbus info data: <4 bytes>"
    assert isinstance(disconnect, urwire.UnknownMessage)


def test_a_longer_type_24_keeps_its_extra_bytes_and_encodes_back():
    body = struct.pack(">22d", *range(22)) + b"\x01\x02"
    data = struct.pack(">iB", len(body) + 5, 24) + body
    (record,) = urwire.decode_stream(data)
    assert record.tolerances == [float(i) for i in range(22)] and record.extra == b"\x01\x02"
    assert not urwire.canonical.has_error(record)
    assert urwire.encode_message(record) == data


def test_the_demo_capture_no_longer_shows_an_unknown_package_14():
    capture = ROOT / "dissector" / "samples" / "primary_session.pcapng"
    lines = [human.line(r) for _, r in zip(range(12), urwire.decode_file(capture))]
    assert not any("Unknown package" in line for line in lines)
    state = next(r for r in urwire.decode_file(capture) if hasattr(r, "packages"))
    (payload,) = [p for p in state.packages if type(p).__name__ == "PayloadInfo"]
    assert (payload.mass, payload.center_of_gravity) == (1.0, [0.0, 0.0, 0.0])
