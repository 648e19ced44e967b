"""The RTDE dissector (generated/lua/rtde.lua) in real tshark: every golden exchange, against the
vectors' records and the Python Conversation's, in whole and byte-by-byte segments; recipes kept
per conversation; experts; filters by variable name."""
from __future__ import annotations

import json
import math
import subprocess
from pathlib import Path

import pytest

from tests.lua.harness import ROOT, _checked
from tests.rtde_vectors import python_records, rtde_cases, shown_as
from tests.tools import capture
from tests.tools.capture import Segment

import urwire

PLUGIN = ROOT / "generated" / "lua" / "rtde.lua"
CASES = rtde_cases()
PORT = 30004


def tshark(pcap: Path, *args: str) -> str:
    cmd = ["tshark", "-r", str(pcap), "-X", f"lua_script:{PLUGIN}", *args]
    return _checked(subprocess.run(cmd, capture_output=True, text=True, timeout=300))


def frames_of(case, client_port: int, bytewise: bool = False) -> list[bytes]:
    segments = []
    for from_robot, data in case.messages:
        pieces = [data[i:i + 1] for i in range(len(data))] if bytewise else [data]
        segments += [Segment(from_robot, p) for p in pieces]
    return capture.session_frames(segments, port=PORT, client_port=client_port)


def messages_by_stream(pcap: Path) -> dict[int, list[dict]]:
    """Each TCP stream's rtde items in order: {field: text or [texts]}, experts under "experts"."""
    out: dict[int, list[dict]] = {}
    for frame in json.loads(tshark(pcap, "-Y", "rtde", "-T", "json", "--no-duplicate-keys")):
        layers = frame["_source"]["layers"]
        items = layers["rtde"] if isinstance(layers["rtde"], list) else [layers["rtde"]]
        stream = int(layers["tcp"]["tcp.stream"])
        for item in items:
            flat = {k: v for k, v in item.items() if k.startswith("rtde.")}
            # A vector with named items: its values under a subtree of text, keyed by the vector.
            texts = item.get("_ws.lua.text", [])
            for text in texts if isinstance(texts, list) else [texts]:
                flat.update({k: v for k, v in text.items() if k.startswith("rtde.")} if isinstance(text, dict) else {})
            flat["experts"] = _experts(item)
            out.setdefault(stream, []).append(flat)
    return out


def _experts(obj) -> list[str]:
    found = []
    if isinstance(obj, dict):
        for k, v in obj.items():
            if k == "_ws.expert.message":
                found += v if isinstance(v, list) else [v]
            else:
                found += _experts(v)
    elif isinstance(obj, list):
        for v in obj:
            found += _experts(v)
    return found


def same(expected, shown) -> bool:
    """A canonical JSON value against tshark's text of it."""
    if isinstance(expected, list):
        shown = shown if isinstance(shown, list) else [shown]
        if all(isinstance(x, str) for x in expected):   # a list of names: one comma-joined string
            return ",".join(expected) == (shown[0] if len(shown) == 1 else ",".join(shown))
        return len(expected) == len(shown) and all(same(e, s) for e, s in zip(expected, shown))
    if isinstance(expected, bool):
        return shown in (("1", "True", "true") if expected else ("0", "False", "false"))
    if isinstance(expected, float):
        return math.isclose(expected, float(shown), rel_tol=1e-13, abs_tol=1e-300)
    if isinstance(expected, int):
        return int(shown) == expected
    return expected == shown


def compare(record: dict, item: dict) -> list[str]:
    """Where the dissector's item disagrees with a record of the canonical JSON."""
    if record["type"] == "error":
        return [] if any("Bad message header" in e or "size" in e for e in item["experts"]) or not item.get(
            "rtde.kind") else [f"no fault shown for {record}"]
    problems = []
    if item.get("rtde.kind") != record["type"]:
        return [f"kind {item.get('rtde.kind')} for {record['type']}"]
    for key, value in record.items():
        if key in ("type", "message_type", "raw"):
            continue
        if key == "error":
            if not item["experts"]:
                problems.append(f"{record['type']}: no expert for {value!r}")
            continue
        if key == "refused":
            for name, word in value.items():
                if f"{name}: {word}" not in item["experts"]:
                    problems.append(f"no expert '{name}: {word}' in {item['experts']}")
            continue
        if key == "warning":
            if value not in item["experts"]:
                problems.append(f"no expert {value!r} in {item['experts']}")
            continue
        if f"rtde.{key}" not in item and any(e.startswith(f"{key}: ") and "by the setup reply" in e
                                               for e in item["experts"]):
            # A variable the setup reply types otherwise: under the field of the reply's type.
            if not any(same(value, v) for k, v in item.items() if k.startswith("rtde.value_")):
                problems.append(f"{record['type']}.{key}: {value!r} under no rtde.value_* field of {item}")
            continue
        if f"rtde.{key}" not in item or not same(value, item[f"rtde.{key}"]):
            problems.append(f"{record['type']}.{key}: {value!r} against {item.get('rtde.' + key)!r}")
    return problems


@pytest.fixture(scope="module")
def dissected(tmp_path_factory):
    """Every case as one TCP session of its own port, whole then byte by byte (two pcaps)."""
    folder = tmp_path_factory.mktemp("rtde")
    out = {}
    for bytewise in (False, True):
        frames = []
        for i, case in enumerate(CASES):
            frames += frames_of(case, 51000 + i, bytewise)
        pcap = folder / f"cases_{int(bytewise)}.pcap"
        capture.write(pcap, frames)
        out[bytewise] = messages_by_stream(pcap)
    return out


@pytest.mark.parametrize("bytewise", [False, True], ids=["whole", "bytewise"])
@pytest.mark.parametrize("index", range(len(CASES)), ids=[c.name for c in CASES])
def test_dissector_shows_every_vector(dissected, index, bytewise):
    """Each record of the vector, and of the Python decoder (the same here), is one rtde item with
    the same values: the golden expectations and the differential check in one."""
    case = CASES[index]
    items = dissected[bytewise].get(index, [])
    python = [shown_as(urwire.to_json_line(r)) for r in python_records(case)]
    # A stream fault reports as an item where the scan started; a truncated tail is not an item.
    expected = [r for r in case.expect if not (r["type"] == "error" and r["error"].startswith("truncated"))]
    assert [r for r in python if not (r["type"] == "error" and r["error"].startswith("truncated"))] == expected
    assert len(items) == len(expected), [i.get("rtde.kind") for i in items]
    problems = [p for record, item in zip(expected, items) for p in compare(record, item)]
    assert not problems, "\n".join(problems)


def test_two_clients_never_share_a_recipe(tmp_path):
    """Two clients of one robot in one capture, their frames interleaved, each with its own recipe 1."""
    first, second = [c for c in CASES if c.name == "data_during_setup"][0], None
    one = frames_of(first, 51001)
    # The second client sets up recipe 1 as a DOUBLE only, then gets a data package of it.
    names = b"timestamp"
    other = [Segment(False, bytes([0, 3 + 8 + len(names), 0x4F]) + bytes.fromhex("405f400000000000") + names),
             Segment(True, bytes([0, 3 + 1 + 6, 0x4F, 1]) + b"DOUBLE"),
             Segment(True, bytes([0, 12, 0x55, 1]) + bytes.fromhex("4000000000000000"))]
    two = capture.session_frames(other, port=PORT, client_port=51002)
    frames = [f for pair in zip(one, two) for f in pair] + one[len(two):] + two[len(one):]
    pcap = tmp_path / "two.pcap"
    capture.write(pcap, frames)
    streams = messages_by_stream(pcap)
    data = {s: [i for i in items if i.get("rtde.kind") == "data_package"] for s, items in streams.items()}
    firsts, seconds = data[0], data[1]
    assert firsts[0]["rtde.actual_q"] == ["1", "2", "3", "0.5", "0.25", "0"]
    assert "rtde.actual_q" not in seconds[0] and seconds[0]["rtde.timestamp"] == "2"


def test_filters_and_experts(dissected, tmp_path):
    pcap = tmp_path / "p2.pcap"
    capture.write(pcap, frames_of([c for c in CASES if c.name == "protocol2_session"][0], 51000))
    out = tshark(pcap, "-Y", "rtde.actual_q > 2.5 && rtde.recipe_id == 2", "-T", "fields", "-e", "rtde.recipe_frame")
    assert out.split() == ["18"]                 # the data package, linked to the setup reply's frame
    experts = tshark(pcap, "-q", "-z", "expert")
    assert "not_a_variable: NOT_FOUND" in experts and "input_int_register_24: IN_USE" in experts


def test_without_a_visible_tree_values_still_filter_and_experts_still_show(dissected, tmp_path):
    """A data package's values become items only where someone looks (a visible tree, or a filter
    naming rtde): a filter on a value with no tree printed finds the package, and a retyped
    variable's expert is counted without a tree, as with one."""
    pcap = tmp_path / "p2.pcap"
    capture.write(pcap, frames_of([c for c in CASES if c.name == "protocol2_session"][0], 51000))
    assert len(tshark(pcap, "-Y", "rtde.actual_q > 2.5 && rtde.recipe_id == 2").splitlines()) == 1
    assert tshark(pcap, "-Y", "rtde.actual_q > 2.5", "-T", "fields", "-e", "frame.number").split() == ["32"]
    retyped = tmp_path / "retyped.pcap"
    capture.write(retyped, frames_of([c for c in CASES if c.name == "retyped_variable"][0], 51000))
    summary = "timestamp: UINT8 by the setup reply, DOUBLE in the variable table"
    counted = [line for line in tshark(retyped, "-q", "-z", "expert").splitlines() if summary in line]
    assert [line.split()[0] for line in counted] == ["2"]      # the setup reply's and the data package's
    shown = tshark(retyped, "-T", "fields", "-e", "_ws.expert.message").split("\n")
    assert sum(line.count(summary) for line in shown) == 2


def test_hostile_bytes_raise_no_lua_error(tmp_path):
    """Flipped, cut and random bytes and huge sizes in both directions, whole and in small
    segments: tshark finishes with no Lua error (run_tshark's checks) and shows rtde items."""
    import random
    import struct as st
    rng = random.Random(5)
    session = [c for c in CASES if c.name == "protocol2_session"][0].messages
    segments = []
    for _ in range(400):
        from_robot, data = rng.choice(session)
        data = bytearray(data)
        roll = rng.random()
        if roll < 0.3 and data:
            data[rng.randrange(len(data))] ^= 1 << rng.randrange(8)
        elif roll < 0.5:
            data = data[:rng.randrange(len(data) + 1)]
        elif roll < 0.6:
            data = bytearray(st.pack(">HB", rng.choice([0xFFFF, 2, 3, 4]), rng.choice(b"UOIVMR")))
        elif roll < 0.7:
            data = bytearray(rng.getrandbits(8) for _ in range(rng.randrange(1, 80)))
        cut = rng.choice([len(data) or 1, 1, 3])
        segments += [Segment(from_robot, bytes(data[i:i + cut])) for i in range(0, len(data), cut)]
    pcap = tmp_path / "hostile.pcap"
    capture.write(pcap, capture.session_frames(segments, port=PORT, client_port=51009))
    out = tshark(pcap, "-Y", "rtde", "-T", "fields", "-e", "rtde.kind")
    assert len(out.splitlines()) > 50 and "setup_outputs" in out
    assert not tshark(pcap, "-Y", "rtde.internal_error").strip(), "a Lua error caught by the guard"


def test_decode_as_on_another_port(tmp_path):
    """A robot behind a port forward: `-d tcp.port==40004,rtde` (Decode As) reads it the same."""
    case = [c for c in CASES if c.name == "protocol2_session"][0]
    pcap = tmp_path / "moved.pcap"
    segments = [Segment(fr, d) for fr, d in case.messages]
    capture.write(pcap, capture.session_frames(segments, port=40004, client_port=51000))
    assert tshark(pcap, "-Y", "rtde").strip() == ""
    out = tshark(pcap, "-d", "tcp.port==40004,rtde", "-Y", "rtde.kind == \"data_package\"", "-T", "fields",
                 "-e", "rtde.actual_q")
    assert out.split() == ["0,-1.5,1.5,-0.5,0.25,3"]


def test_two_passes_show_what_one_shows(tmp_path):
    """tshark -2 dissects every frame again after the first pass, as the GUI does: each message keeps
    the recipe, protocol and refusals the first pass saw (the state is not re-run)."""
    pcap = tmp_path / "p2.pcap"
    capture.write(pcap, frames_of([c for c in CASES if c.name == "protocol2_session"][0], 51000))
    fields = ["-Y", "rtde", "-T", "fields", "-e", "rtde.kind", "-e", "rtde.actual_q", "-e", "rtde.recipe_frame",
              "-e", "rtde.protocol", "-e", "_ws.expert.message"]
    one = tshark(pcap, *fields)
    assert "not_a_variable: NOT_FOUND" in one
    assert tshark(pcap, "-2", *fields) == one
