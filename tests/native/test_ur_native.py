"""The native dissector of the primary/secondary interface (generated/epan/packet-ur.c, protocol
`ur`) against its Lua twin (generated/lua/urwire.lua): each loaded alone in real tshark, they
must register the same fields and show the same layers (-T json), Info column and expert infos
on every capture the Lua dissector is tested with. The captures are batched: many TCP sessions
per capture, so that a few tshark runs cover every vector."""
from __future__ import annotations

import difflib
import functools
import json
import os
import random
import re
import struct
import subprocess
import tempfile
from pathlib import Path
from typing import Optional

import pytest

from tests.native import harness
from tests.tools import capture, valid
from tests.lua import test_fuzz_corpus as fuzz_corpus
from tests.vectors import golden_cases

SAMPLES = harness.ROOT / "dissector" / "samples"
LUA = functools.partial(harness.run_lua, lua=[harness.lua_plugin("ur")])


def _fields(result) -> list[list[str]]:
    """The `ur` protocol line and field lines of `tshark -G fields`, split into columns."""
    err = result.stderr.decode(errors="replace")
    assert result.returncode == 0 and "Lua: Error" not in err, err[:3000]
    rows = [line.split("\t") for line in result.stdout.decode().splitlines()]
    return [r for r in rows if (r[0] == "P" and r[2:3] == ["ur"]) or (r[0] == "F" and r[4:5] == ["ur"])]


def test_both_register_the_same_fields_in_the_same_order():
    native = _fields(harness.native_tshark(["-G", "fields"]))
    lua = _fields(_lua_fields())
    assert len(native) > 300
    # Kind, name, abbreviation, type, protocol, base and bitmask, line for line.
    assert [r[:7] for r in native] == [r[:7] for r in lua]
    # Descriptions too, where Lua has one: Wireshark 4.0 drops the description of a Lua string field.
    differ = [(n[2], n[7], l[7]) for n, l in zip(native, lua) if len(l) > 7 and l[7] and n[7:8] != l[7:8]]
    assert not differ, differ[:5]


def _lua_fields() -> subprocess.CompletedProcess:
    """tshark -G fields with the Lua dissector alone (-G must come first, so not through run_lua)."""
    environment = {**os.environ, "HOME": str(harness._empty_home())}
    environment.pop("XDG_CONFIG_HOME", None)
    return subprocess.run(["tshark", "-G", "fields", "-X", f"lua_script:{harness.lua_plugin('ur')}"],
                          capture_output=True, env=environment, timeout=120)


# ---- captures: many sessions each, fed to both dissectors ----

def _sessions(streams: list[list[bytes]], handshakes: Optional[list[bool]] = None,
              retransmit: Optional[list[int]] = None) -> bytes:
    """One TCP session per stream (a list of robot segment payloads), as tests/lua writes them;
    per stream, whether it opens with a handshake and every how many segments one is sent twice."""
    frames = []
    for i, segments in enumerate(streams):
        every = retransmit[i] if retransmit else 0
        again = range(0, len(segments), every) if every else ()
        frames += capture.session_frames([capture.Segment(True, s) for s in segments], port=30001,
                                         client_port=20000 + i % 40000,
                                         handshake=handshakes[i] if handshakes else True, retransmit=again)
    with tempfile.TemporaryDirectory() as folder:
        return capture.write(Path(folder) / "sessions.pcap", frames).read_bytes()


def _first_difference(a, b, path="") -> str:
    """Where two JSON values first differ, for a readable failure."""
    if type(a) is not type(b):
        return f"{path}: {json.dumps(a)[:300]} != {json.dumps(b)[:300]}"
    if isinstance(a, dict):
        if list(a) != list(b):
            return f"{path}: keys {list(a)[:20]} != {list(b)[:20]}"
        for k in a:
            if a[k] != b[k]:
                return _first_difference(a[k], b[k], f"{path}.{k}")
    if isinstance(a, list):
        if len(a) != len(b):
            return f"{path}: {len(a)} items != {len(b)} items"
        for i, (x, y) in enumerate(zip(a, b)):
            if x != y:
                return _first_difference(x, y, f"{path}[{i}]")
    return f"{path}: {json.dumps(a)[:300]} != {json.dumps(b)[:300]}"


def assert_same(capture_bytes: bytes, *args: str) -> harness.Shown:
    """Both dissectors show the same layers, Info column and expert infos of the capture's frames
    that show `ur` (-Y ur: the frames that carry only part of a message show nothing of it, and
    a frame one of them shows and the other does not makes the counts differ)."""
    native = harness.shown(harness.run_native, capture_bytes, ["ur"], "-Y", "ur", *args)
    lua = harness.shown(LUA, capture_bytes, ["ur"], "-Y", "ur", *args)
    assert len(native.layers) == len(lua.layers)
    for frame, (n, l) in enumerate(zip(native.layers, lua.layers), start=1):
        assert n == l, f"frame {frame}: native {_first_difference(n, l)}"
    for frame, (n, l) in enumerate(zip(native.info, lua.info), start=1):
        assert n == l, f"frame {frame}: Info column\n native: {n}\n    lua: {l}"
    assert native.info == lua.info
    assert native.experts == lua.experts
    return native


def _ur_pdml(result) -> list[str]:
    """The `ur` protocol elements of tshark -T pdml: every item's label (showname), offset and size."""
    return re.findall(r'<proto name="ur".*?</proto>', harness.checked(result), re.S)


def assert_same_tree(capture_bytes: bytes, *args: str) -> None:
    """Both dissectors build the same tree, item texts, offsets and sizes included (-T pdml)."""
    native = _ur_pdml(harness.run_native(capture_bytes, "-2", "-T", "pdml", "-Y", "ur", *args))
    lua = _ur_pdml(LUA(capture_bytes, "-2", "-T", "pdml", "-Y", "ur", *args))
    assert len(native) == len(lua) and native
    for i, (n, l) in enumerate(zip(native, lua)):
        if n != l:
            diff = difflib.unified_diff(l.splitlines(), n.splitlines(), "lua", "native", lineterm="", n=0)
            raise AssertionError(f"ur item {i}:\n" + "\n".join(list(diff)[:20]))


def _split(data: bytes) -> list[bytes]:
    """A stream cut at its declared lengths where they are plausible (else kept whole)."""
    out, pos = [], 0
    while len(data) - pos >= 5:
        n = int.from_bytes(data[pos:pos + 4], "big", signed=True)
        if n < 5 or pos + n > len(data):
            break
        out.append(data[pos:pos + n])
        pos += n
    if pos < len(data):
        out.append(data[pos:])
    return out


GOLDEN = golden_cases()
HINTS = sorted({c.version or "" for c in GOLDEN})


# The tail of a real message: a capture that starts in the middle of the stream.
MID_STREAM = bytes.fromhex("3ff000000000000000000001")


def tiny(messages: list[bytes], seed: int = 0) -> list[bytes]:
    """The stream in segments of 1 to 7 bytes."""
    data, rng, out = b"".join(messages), random.Random(seed), []
    while data:
        n = rng.randint(1, 7)
        out.append(data[:n])
        data = data[n:]
    return out


# As tests/lua/test_vectors.py cuts them (segments, handshake, retransmit every k), and 1-7 bytes.
SEGMENTATIONS = {
    "whole": (capture.whole, True, 0),
    "bytewise": (capture.bytewise, True, 0),
    "1-7 bytes": (tiny, True, 0),
    "random_cuts": (lambda msgs: capture.random_cuts(msgs, seed=7, max_len=40), True, 0),
    "packed": (lambda msgs: capture.packed(msgs, per_segment=3), True, 0),
    "mid_stream": (lambda msgs: capture.random_cuts([MID_STREAM] + list(msgs), seed=3, max_len=300), False, 0),
    "retransmitted": (lambda msgs: capture.random_cuts(msgs, seed=5, max_len=200), True, 3),
}


def _golden_capture(hint: str, segmentations: tuple[str, ...] = tuple(SEGMENTATIONS)) -> bytes:
    """Every golden vector of this version hint, in these segmentations, one session each."""
    streams, handshakes, retransmit = [], [], []
    for cut, handshake, every in (SEGMENTATIONS[name] for name in segmentations):
        for case in GOLDEN:
            if (case.version or "") == hint:
                streams.append(cut(_split(case.data)))
                handshakes.append(handshake)
                retransmit.append(every)
    return _sessions(streams, handshakes, retransmit)


def _prefs(hint: str) -> tuple[str, ...]:
    return ("-o", f"ur.version:{hint}") if hint else ()


# `make test` cuts the vectors two ways; `make test-deep` (CI) every way.
QUICK = ("whole", "1-7 bytes")


@pytest.mark.parametrize("hint", HINTS, ids=lambda h: h or "no hint")
def test_golden_vectors_whole_and_in_1_to_7_byte_segments(hint):
    data = _golden_capture(hint, QUICK)
    shown = assert_same(data, *_prefs(hint))
    assert sum(1 for layer in shown.layers if layer) > len(QUICK)
    assert_same_tree(data, *_prefs(hint))


@pytest.mark.deep
@pytest.mark.parametrize("hint", HINTS, ids=lambda h: h or "no hint")
def test_golden_vectors_in_every_segmentation(hint):
    data = _golden_capture(hint)
    shown = assert_same(data, *_prefs(hint))
    assert sum(1 for layer in shown.layers if layer) > len(SEGMENTATIONS)
    assert_same_tree(data, *_prefs(hint))


def _generation_capture() -> bytes:
    """Sessions of random valid messages of every controller generation (tests/tools/valid.py),
    with and without their Version message, in 7- and 400-byte segments."""
    streams = []
    for max_len in (7, 400):
        rng = random.Random(max_len)
        for version in valid.versions():
            for _ in range(3):
                session = valid.session(rng, version, 10)
                for data in (session, session[int.from_bytes(session[:4], "big"):]):
                    streams.append(capture.random_cuts([data], seed=len(streams), max_len=max_len))
    return _sessions(streams)


@pytest.mark.deep
def test_generation_sessions():
    data = _generation_capture()
    assert_same(data)
    assert_same_tree(data)


@pytest.mark.parametrize("sample", ["primary_session.pcapng", "secondary_session.pcap"])
def test_bundled_samples(sample):
    shown = assert_same(SAMPLES / sample)
    assert any(shown.layers)
    assert_same_tree(SAMPLES / sample)


# ---- the fuzzers' kept corpora, as tests/lua/test_fuzz_corpus.py feeds them ----

def _corpus_capture(version: str) -> bytes:
    """Every kept input of this version hint, cut the three ways tests/lua cuts them."""
    streams = []
    for cut in fuzz_corpus.CUTS:
        rng = random.Random(f"{version} {cut}")
        for data in fuzz_corpus.GROUPS[version]:
            if cut != "1-7 bytes" or len(data) <= fuzz_corpus.SMALL_INPUT:
                streams.append(fuzz_corpus.CUTS[cut](data, rng))
    return _sessions(streams)


@pytest.mark.deep
@pytest.mark.parametrize("version", sorted(fuzz_corpus.GROUPS), ids=lambda v: v or "no hint")
def test_fuzz_corpus(version):
    """Faults, resynchronisation and their experts included."""
    data = _corpus_capture(version)
    shown = assert_same(data, *_prefs(version))
    assert shown.experts
    assert_same_tree(data, *_prefs(version))


# ---- the same captures through the plugin built with ASan and UBSan ----

def _sanitizer_env() -> dict:
    """tshark is not built with ASan: its runtime is preloaded (leaks are Wireshark's to keep)."""
    runtime = subprocess.run(["gcc", "-print-file-name=libasan.so"], capture_output=True, text=True).stdout.strip()
    assert os.path.isabs(runtime), f"no libasan.so: {runtime}"
    return {"LD_PRELOAD": runtime, "ASAN_OPTIONS": "detect_leaks=0:abort_on_error=0",
            "UBSAN_OPTIONS": "print_stacktrace=1:halt_on_error=1"}


def _captures(name: str) -> dict[str, tuple[bytes, tuple[str, ...]]]:
    """The captures the differential tests read, by group: each with its preferences."""
    if name == "golden":
        return {f"golden {h or 'no hint'}": (_golden_capture(h, QUICK), _prefs(h)) for h in HINTS}
    if name == "golden, every segmentation":
        return {f"golden {h or 'no hint'}": (_golden_capture(h), _prefs(h)) for h in HINTS}
    if name == "corpus":
        return {f"corpus {v or 'no hint'}": (_corpus_capture(v), _prefs(v)) for v in sorted(fuzz_corpus.GROUPS)}
    if name == "generations":
        return {"generation sessions": (_generation_capture(), ())}
    return {s: ((SAMPLES / s).read_bytes(), ()) for s in ("primary_session.pcapng", "secondary_session.pcap")}


@pytest.mark.parametrize("name", ["golden", "samples"] + [pytest.param(name, marks=pytest.mark.deep) for name in (
    "golden, every segmentation", "generations", "corpus")])
def test_no_sanitizer_report(name):
    """With a tree (-V; its first pass builds neither tree nor columns) and without one (the packet
    list: the Info column only)."""
    env = _sanitizer_env()
    for label, (data, prefs) in _captures(name).items():
        for args in (("-2", "-V"), ()):
            result = harness.run_native(data, *args, *prefs, variant="asan", env=env)
            err = result.stderr.decode(errors="replace")
            assert "Sanitizer" not in err and "runtime error" not in err, f"{label} {args}:\n{err[:4000]}"
            assert result.returncode == 0, f"{label} {args}: exit {result.returncode}\n{err[:2000]}"
            if "-V" in args:
                assert b"Universal Robots primary/secondary" in result.stdout, f"{label}: the plugin did not load"


# ---- the tree cap, the client's direction, two robots on the same ports ----

def _update(values: bytes) -> bytes:
    """A global variables update (timestamp, subtype 1, start index 0), then the values."""
    body = struct.pack(">QBH", 7, 1, 0) + values
    return struct.pack(">iB", 5 + len(body), 25) + body


def _int_list(n: int) -> bytes:
    """One value: a LIST (17 from 5.9) of n INTs (15), then the terminator."""
    return struct.pack(">Bh", 17, n) + b"".join(struct.pack(">Bi", 15, i) for i in range(n)) + b"\x0a"


def test_tree_cap_client_direction_and_two_robots():
    """As tests/lua/test_tree_cap.py, test_two_robots.py and the URScript a client sends."""
    cases = {c.name: c for c in GOLDEN}
    frames = capture.session_frames([capture.Segment(True, _update(_int_list(3000))),
                                     capture.Segment(True, _update(_int_list(3000) + bytes([99])))],
                                    client_port=50001)
    script = [b"def prog():\n  movej([0, -1.57, 0, -1.57, 0, 0])\nend\n", "textmsg(\"\u00e9t\u00e9\")\n".encode()]
    robot = _split(cases["key_message"].data)
    frames += capture.session_frames([capture.Segment(False, script[0]), capture.Segment(True, robot[0]),
                                      capture.Segment(False, script[1])], client_port=50002)
    sessions = [capture.session_frames([capture.Segment(True, m) for m in _split(cases[name].data)], port=30001,
                                       client_port=50123, robot=address)
                for address, name in (("192.168.56.101", "global_variables_update_3_2_version_message"),
                                      ("192.168.56.102", "global_variables_update_5_0_version_message"))]
    frames += [f for pair in zip(*sessions) for f in pair] + max(sessions, key=len)[min(map(len, sessions)):]
    with tempfile.TemporaryDirectory() as folder:
        data = capture.write(Path(folder) / "cap.pcap", frames).read_bytes()
    shown = assert_same(data)
    assert_same_tree(data)
    texts = [e.get("_ws.expert.message", "") for e in shown.experts]
    assert any(t.endswith("more items not shown (a message shows at most 10000)") for t in texts), texts[:5]
    assert any("unknown value type 99" in t for t in texts)
    assert any(i.startswith("URScript: def prog():") for i in shown.info)


def test_builds_with_clang_too():
    """-Wall -Wextra -Werror under clang as under gcc (the gcc build is every other test's)."""
    assert harness.plugin("clang").library.is_file()


@pytest.mark.parametrize("how", [("-d", "tcp.port==40000,ur"), ("-o", "ur.ports:40000")],
                         ids=["decode as", "ports preference"])
def test_decode_as_and_the_ports_preference(how):
    """A robot on another port: Decode As, or the ports preference, makes both read it."""
    frames = []
    for i, case in enumerate(c for c in GOLDEN if not c.version):
        frames += capture.session_frames([capture.Segment(True, m) for m in _split(case.data)], port=40000,
                                         client_port=21000 + i)
    with tempfile.TemporaryDirectory() as folder:
        data = capture.write(Path(folder) / "port.pcap", frames).read_bytes()
    shown = assert_same(data, *how)
    assert sum(1 for layer in shown.layers if layer) > 50
    assert_same_tree(data, *how)


@pytest.mark.parametrize("args", [
    ("-T", "fields", "-e", "ur.joint_data.q_actual", "-e", "ur.robot_mode_data.robot_mode", "-e", "_ws.col.Info"),
    ("-Y", 'ur.robot_mode_data.robot_mode == "RUNNING" && ur.joint_data.q_actual > 0', "-T", "fields",
     "-e", "frame.number"),
    ("-2", "-Y", "ur.key.title contains \"PROGRAM\" || ur.version", "-T", "fields", "-e", "frame.number"),
], ids=["fields", "filter", "filter two passes"])
def test_fields_and_filters_on_the_sample(args):
    """tshark -T fields and display filters, where only some fields are asked for."""
    sample = SAMPLES / "primary_session.pcapng"
    native, lua = harness.checked(harness.run_native(sample, *args)), harness.checked(LUA(sample, *args))
    assert native == lua
    assert native.strip()


@pytest.mark.parametrize("args", [
    ("-e", "ur.joint_data.q_actual", "-e", "ur.masterboard_data.robot_voltage_48v"),
    ("-Y", 'ur.robot_mode_data.robot_mode == "RUNNING"', "-e", "frame.number", "-e", "ur.tool_data.tool_mode"),
    ("-e", "ur.type", "-e", "ur.key.title", "-e", "ur.cartesian_info"),
    ("-e", "ur.joint_data.q_actual", "-e", "ur.raw"),                     # not a spec field: every package
    ("-e", "ur.joint_data.q_actual", "-e", "ur.package.type"),            # a package header: every package
    ("-e", "ur.joint_data.q_actual", "-e", "_ws.expert.message"),         # expert infos: every package
], ids=["two packages", "filter on another", "items", "own field", "package header", "experts"])
def test_tshark_fields_builds_the_named_packages_as_the_full_tree_and_lua_do(args):
    """tshark -T fields builds only the robot-state packages its command line names (ur_wanted.c,
    the Lua twin's runtime/lua/packages/wanted.lua): the same lines as the whole tree (ur.named_fields_only
    off) and as Lua."""
    sample = SAMPLES / "primary_session.pcapng"
    named = harness.checked(harness.run_native(sample, "-T", "fields", *args))
    assert named.strip()
    assert named == harness.checked(harness.run_native(sample, "-o", "ur.named_fields_only:FALSE", "-T", "fields", *args))
    assert named == harness.checked(LUA(sample, "-T", "fields", *args))


@pytest.mark.parametrize("group", ["golden", pytest.param("corpus", marks=pytest.mark.deep)])
def test_packet_list_without_a_tree(group):
    """tshark's packet list, one pass: no tree, only framing, the version state and the Info column."""
    captures = ({h: _golden_capture(h, QUICK) for h in HINTS} if group == "golden"
                else {v: _corpus_capture(v) for v in sorted(fuzz_corpus.GROUPS)})
    for hint, data in captures.items():
        native = harness.checked(harness.run_native(data, *_prefs(hint)))
        lua = harness.checked(LUA(data, *_prefs(hint)))
        assert native.splitlines() == lua.splitlines(), hint
        assert " UR " in native


def test_without_tcp_reassembly():
    """A message split over segments, with reassembly off: what each segment holds, as Lua shows it."""
    data = _golden_capture("", ("whole", "random_cuts", "1-7 bytes"))
    shown = assert_same(data, "-o", "tcp.desegment_tcp_streams:FALSE")
    assert any("Continuation" in line for line in shown.info)


@pytest.mark.parametrize("text", ["5.1500", "5.9.x", " 3.2", "3.2.", "abc", "10.7.5000"])
def test_odd_version_preferences(text):
    """The ur.version preference's text read as Lua reads it: blanks, a trailing dot or word, a
    bugfix over 999, a minor over 999 (carried into the major), no version at all."""
    assert_same(_golden_capture("", ("whole",)), "-o", f"ur.version:{text}")


def test_a_new_connection_on_the_same_ports_starts_over():
    """The robot's stream left carrying by hand a message that never ends (a bad header, then one
    declaring 100000 bytes), then a new connection from the same client port (its SYN makes
    Wireshark's TCP start a new conversation): the native plugin's state is the conversation's,
    and Lua's starts over with it, so both decode every message of the new connection."""
    stuck = b"\xff" * 5 + b"\x00\x01\x86\xa0\x10" + bytes(20)
    messages = _split(valid.session(random.Random(3), valid.versions()[-1], 4))
    frames = capture.session_frames([capture.Segment(True, stuck)], client_port=50124)
    frames += capture.session_frames([capture.Segment(True, m) for m in messages], client_port=50124,
                                     robot_isn=90000, client_isn=70000)
    with tempfile.TemporaryDirectory() as folder:
        data = capture.write(Path(folder) / "reused.pcap", frames).read_bytes()
    shown = assert_same(data)
    assert len(messages) == 5 and sum(1 for line in shown.info if "Bad header" not in line) == len(messages)
