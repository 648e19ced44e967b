"""The native RTDE dissector (generated/epan/packet-rtde.c, in the plugin of dissector/native) against
its Lua twin (generated/lua/rtde.lua), each loaded alone in real tshark: the same fields, and on every
golden exchange (whole and in 1-7-byte segments), the RTDE conversations of the cell sample and the
fuzz corpus as TCP sessions, the same -T json layers, Info column and expert infos; then the same
captures through the plugin built with ASan and UBSan, with no sanitizer report.

The comparisons run tshark -2, which keeps the recipes of a first pass for the second as the GUI
does, and the -V text on one pass."""
from __future__ import annotations

import os
import random
import re
import subprocess
import tempfile
from functools import lru_cache
from pathlib import Path

import pytest

from tests.native import harness
from tests.native.lua_twin import as_lua_writes
from tests.rtde_vectors import rtde_cases
from tests.tools import capture
from tests.tools.capture import Segment

PORT = 30004
PROTOCOLS = ["rtde"]
CORPUS = harness.ROOT / "tests" / "fuzz" / "corpus" / "rtde"
CELL_SAMPLE = harness.ROOT / "dissector" / "samples" / "cell_session.pcapng"


def native(capture_: harness.Capture, *args: str) -> subprocess.CompletedProcess:
    return harness.run_native(capture_, *args)


def native_asan(capture_: harness.Capture, *args: str) -> subprocess.CompletedProcess:
    """The ASan/UBSan build; the sanitizer runtime preloaded into tshark, which is not built with it."""
    libasan = subprocess.run(["gcc", "-print-file-name=libasan.so"], capture_output=True, text=True).stdout.strip()
    env = {"LD_PRELOAD": libasan, "ASAN_OPTIONS": "detect_leaks=0:abort_on_error=0",
           "UBSAN_OPTIONS": "print_stacktrace=1:halt_on_error=1"}
    return harness.run_native(capture_, *args, variant="asan", env=env)


def lua(capture_: harness.Capture, *args: str) -> subprocess.CompletedProcess:
    return harness.run_lua(capture_, *args, lua=[harness.lua_plugin("rtde")])


# ---- the captures: one TCP session per case, each on its own client port ----

def _cut(data: bytes, rng: random.Random) -> list[bytes]:
    out, at = [], 0
    while at < len(data):
        n = rng.randint(1, 7)
        out.append(data[at:at + n])
        at += n
    return out


@lru_cache(maxsize=None)
def golden_capture(segmented: bool) -> bytes:
    """Every golden exchange, its messages whole or cut into 1-7-byte segments (the same seed)."""
    rng = random.Random(24)
    frames = []
    for i, case in enumerate(rtde_cases()):
        pieces = ([Segment(fr, p) for fr, data in case.messages for p in _cut(data, rng)] if segmented
                  else [Segment(fr, data) for fr, data in case.messages])
        frames += capture.session_frames(pieces, port=PORT, client_port=51000 + i)
    return _pcap(frames)


def corpus_sessions() -> list[list[Segment]]:
    """Each input of the RTDE fuzz corpus as a TCP session: after its protocol byte, pieces of a
    direction bit and a 7-bit length (tests/c/fuzz_rtde.c), one segment each."""
    sessions = []
    for path in sorted(CORPUS.iterdir()):
        data, at, pieces = path.read_bytes(), 1, []
        while at < len(data):
            n, from_robot = data[at] & 0x7F, bool(data[at] & 0x80)
            piece = data[at + 1:at + 1 + n]
            at += 1 + n
            if piece:
                pieces.append(Segment(from_robot, piece))
        sessions.append(pieces)
    return sessions


@lru_cache(maxsize=None)
def corpus_capture() -> bytes:
    frames = []
    for i, pieces in enumerate(corpus_sessions()):
        frames += capture.session_frames(pieces, port=PORT, client_port=40000 + i)
    return _pcap(frames)


def _pcap(frames: list[bytes]) -> bytes:
    with tempfile.TemporaryDirectory() as folder:
        return capture.write(Path(folder) / "sessions.pcap", frames).read_bytes()


def assert_same(capture_: harness.Capture, *args: str) -> harness.Shown:
    want = harness.shown(lua, capture_, PROTOCOLS, *args)
    got = harness.shown(native, capture_, PROTOCOLS, *args)
    got.layers = [as_lua_writes(layer) for layer in got.layers]   # a subtree's text, as Lua keys it
    for frame, (w, g) in enumerate(zip(want.layers, got.layers), start=1):
        assert g == w, f"frame {frame}: native {g} against Lua {w}"
    assert len(got.layers) == len(want.layers)
    assert got.info == want.info
    assert got.experts == want.experts
    # The tree's text too (labels, units after values, vector indices, generated items), on one pass
    # this time: the state followed while the tree is built, where -2 builds it from the kept state.
    detail = ["-O", "rtde", "-V", *args]
    assert harness.checked(native(capture_, *detail)) == harness.checked(lua(capture_, *detail))
    return got


# ---- 1: the same fields ----

def _fields(result: subprocess.CompletedProcess) -> list[str]:
    """The rtde lines of tshark -G fields (not harness.checked: the list names _ws.lua.error itself)."""
    assert result.returncode == 0, result.stderr[-2000:]
    lines = result.stdout.decode().splitlines()
    return sorted(line for line in lines if line.split("\t")[:1] == ["P"] and line.endswith("\trtde")
                  or len(line.split("\t")) > 4 and line.split("\t")[4] == "rtde")


def test_fields_are_the_lua_dissectors():
    """tshark -G fields lists the same protocol and fields, line for line (names, abbrevs, types,
    bases), with the experts' names; the Lua one lists them in its table's order, hence sorted."""
    environment = {**os.environ, "HOME": str(harness._empty_home())}
    lua_fields = subprocess.run(["tshark", "-G", "fields", "-X", f"lua_script:{harness.lua_plugin('rtde')}"],
                                capture_output=True, env=environment, timeout=300)
    native_fields = _fields(harness.native_tshark(["-G", "fields"]))
    assert len(native_fields) > 400          # the variable table is in
    assert native_fields == _fields(lua_fields)


# ---- 2: golden exchanges, in segments, the cell sample ----

def test_golden_exchanges_show_as_in_lua():
    shown = assert_same(golden_capture(False))
    assert any("rtde.actual_q" in str(layer) for layer in shown.layers)
    assert any("NOT_FOUND" in str(e) for e in shown.experts)


def test_golden_exchanges_in_small_segments_show_as_in_lua():
    shown = assert_same(golden_capture(True))
    assert any("rtde.recipe_frame" in str(layer) for layer in shown.layers)


def test_cell_sample_rtde_conversations_show_as_in_lua():
    shown = assert_same(CELL_SAMPLE, "-Y", f"tcp.port == {PORT}")
    assert any("rtde.actual_q" in str(layer) for layer in shown.layers)


@pytest.mark.parametrize("segmented", [False, True], ids=["whole", "segments"])
def test_the_expert_tap_lists_the_same_experts_as_lua(segmented):
    """`tshark -q -z expert` builds no tree: the expert a retyped variable's value carries in each
    data package is listed by the plugin as by Lua, not only under a tree."""
    capture_ = golden_capture(segmented)
    want = harness.checked(lua(capture_, "-q", "-z", "expert"))
    retyped = "timestamp: UINT8 by the setup reply, DOUBLE in the variable table"
    # once on the setup reply, once on the data package's value
    assert re.search(r"\n +2 +Protocol +RTDE +" + re.escape(retyped), want), want
    assert harness.checked(native(capture_, "-q", "-z", "expert")) == want


@pytest.mark.parametrize("args", [
    ("-e", "rtde.actual_q", "-e", "rtde.timestamp", "-e", "rtde.protocol_version"),
    ("-e", "rtde", "-e", "_ws.col.Info", "-e", "rtde.recipe_id", "-e", "rtde.target_q"),
], ids=["values", "protocol item and Info"])
def test_tshark_fields_prints_what_lua_prints(args):
    """tshark -T fields, where the plugin appends no unit or index to its items (no label is
    printed there): the same lines as Lua, which appends them."""
    fields = ("-T", "fields", *args)
    for capture_ in (golden_capture(False), CELL_SAMPLE):
        out = harness.checked(native(capture_, "-Y", "rtde", *fields))
        assert out.strip() and out == harness.checked(lua(capture_, "-Y", "rtde", *fields))


# ---- 3: the fuzz corpus ----

def test_fuzz_corpus_as_streams_shows_as_in_lua():
    """Each kept input of the RTDE fuzzer as a TCP session of its own: bad headers, resynchronising,
    cut messages, refused and unknown recipes, in either direction."""
    shown = assert_same(corpus_capture())
    assert len(corpus_sessions()) >= 100
    assert any("Bad message header" in str(e) or "size " in str(e) for e in shown.experts)


# ---- 4: the same captures under ASan and UBSan ----

@pytest.mark.parametrize("name", ["golden", "golden_segmented", "corpus", "cell_sample"])
def test_sanitized_build_reports_nothing(name):
    """The plugin built with -fsanitize=address,undefined reads every capture above, with and
    without a tree, on one pass and on two: exit 0, nothing on stderr, and the same Info column as
    the plain build."""
    symbols = subprocess.run(["nm", "-D", str(harness.plugin("asan").library)], capture_output=True, text=True).stdout
    assert "__asan_" in symbols and "__ubsan_" in symbols      # the build under test is instrumented
    captured = {"golden": lambda: golden_capture(False), "golden_segmented": lambda: golden_capture(True),
                "corpus": corpus_capture, "cell_sample": lambda: CELL_SAMPLE.read_bytes()}[name]()
    for args in (["-2", "-V"], ["-T", "fields", "-e", "_ws.col.Info"]):
        result = native_asan(captured, *args)
        err = result.stderr.decode(errors="replace")
        assert "Sanitizer" not in err and "runtime error" not in err, err[:4000]
        out = harness.checked(result)
        if args[0] == "-T":
            assert out == harness.checked(native(captured, *args))
        else:
            assert "Real-Time Data Exchange (RTDE)" in out


def test_a_message_reassembled_and_one_after_it_in_a_frame_keep_their_own_views():
    """A data package completed by a segment that also holds a whole start reply: the frame is
    dissected in two calls (the reassembled package, then the rest), and on the second pass each
    message still finds its own recipe and notes (both dissectors key them by the message's place
    in the frame's bytes, not by its rank within a call)."""
    names = b"timestamp"
    data = bytes([0, 12, 0x55, 1]) + bytes.fromhex("4000000000000000")
    pieces = [Segment(False, bytes([0, 3 + 8 + len(names), 0x4F]) + bytes(8) + names),
              Segment(True, bytes([0, 3 + 1 + 6, 0x4F, 1]) + b"DOUBLE"),
              Segment(True, data[:5]), Segment(True, data[5:] + bytes([0, 4, 0x53, 0]))]
    captured = _pcap(capture.session_frames(pieces, port=PORT, client_port=50000))
    shown = assert_same(captured)
    last = shown.layers[9]["rtde"]            # frame 10: the last segment
    assert last[0]["rtde.timestamp"] == "2" and "_ws.expert" not in last[0]
    assert last[1]["_ws.expert"]["_ws.expert.message"] == "the robot refused to start"


def _recipe_session(names: bytes, types: bytes, values: bytes, port: int = PORT) -> bytes:
    pieces = [Segment(False, bytes([0, 3 + 8 + len(names), 0x4F]) + bytes.fromhex("405f400000000000") + names),
              Segment(True, bytes([0, 3 + 1 + len(types), 0x4F, 1]) + types),
              Segment(True, bytes([0, 3 + 1 + len(values), 0x55, 1]) + values)]
    return _pcap(capture.session_frames(pieces, port=port, client_port=50000))


def test_a_variable_the_table_lacks_shows_its_bytes_and_name():
    """A newer controller's variable, accepted by the robot: its value's bytes under
    rtde.unknown_variable with its name, and the next value still under its own field."""
    captured = _recipe_session(b"a_newer_variable,timestamp", b"VECTOR3D,DOUBLE",
                               bytes(24) + bytes.fromhex("4029000000000000"))
    shown = assert_same(captured)
    package = shown.layers[7]["rtde"]
    assert package["rtde.unknown_variable"] == ":".join(["00"] * 24) and package["rtde.timestamp"] == "12.5"
    text = harness.checked(native(captured, "-O", "rtde", "-V"))
    assert "Variable not in the table: " + "00" * 24 + " (a_newer_variable)" in text


def test_decode_as_and_the_ports_preference():
    """A robot behind a port forward: Decode As (-d) and the ports preference read it as on 30004."""
    captured = _recipe_session(b"timestamp", b"DOUBLE", bytes.fromhex("4029000000000000"), port=40004)
    assert "rtde" not in harness.checked(native(captured, "-T", "fields", "-e", "frame.protocols"))
    for args in (["-d", "tcp.port==40004,rtde"], ["-o", "rtde.ports:40004"]):
        shown = assert_same(captured, *args)
        assert shown.layers[7]["rtde"]["rtde.timestamp"] == "12.5"


def test_a_variable_the_reply_types_otherwise_is_read_by_the_replys_type():
    """timestamp typed UINT8 by the setup reply (the table's DOUBLE): its byte under
    rtde.value_uint8 with an expert, and the values after it under their own fields; no exception,
    no malformed packet (both dissectors threw on fetching 8 bytes from 1)."""
    captured = _recipe_session(b"timestamp,actual_q,robot_mode", b"UINT8,VECTOR6D,INT32",
                               bytes([7]) + bytes(48) + bytes.fromhex("00000009"))
    shown = assert_same(captured)
    reply, package = shown.layers[5]["rtde"], shown.layers[7]["rtde"]
    said = "timestamp: UINT8 by the setup reply, DOUBLE in the variable table"
    assert reply["_ws.expert"]["_ws.expert.message"] == said
    assert package["rtde.value_uint8"] == "7" and "rtde.timestamp" not in package
    assert package["_ws.lua.text"]["rtde.actual_q"] == ["0"] * 6 and package["rtde.robot_mode"] == "9"
    text = harness.checked(native(captured, "-O", "rtde", "-V"))
    assert "Malformed" not in text and said in text
    assert "Value of the setup reply's type (uint8): 7 (timestamp)" in text


def test_queues_and_protocol_versions_say_what_they_could_not_follow():
    """The golden exchanges of requests not kept and of protocol versions with no layouts: the
    native dissector's experts say so, as the records' errors do."""
    cases = {c.name: i for i, c in enumerate(rtde_cases())}
    text = harness.checked(native(golden_capture(False), "-O", "rtde", "-V"))
    for said in ("setup not kept: more than 8 setups awaited replies",
                 "reply to a setup that was not kept: more than 8 setups awaited replies",
                 "protocol version request not kept: more than 8 protocol version requests awaited replies",
                 "reply to a protocol version request that was not kept: more than 8 protocol version requests "
                 "awaited replies",
                 "protocol version 300 accepted, which has no layouts: protocol 1 stays in force"):
        assert said in text, said
    assert {"pending_setups_overflow", "pending_version_requests_overflow",
            "protocol_version_without_layouts"} <= set(cases)


def test_a_new_connection_on_the_same_ports_keeps_no_recipe():
    """A recipe set up on one connection, then a new connection from the same client port that
    sends a data package of that recipe id without a setup: Wireshark's TCP starts a new
    conversation at the SYN, and the package's recipe is unknown there, in both dissectors (Lua
    read it with the last connection's recipe). -Y: Lua sees the TCP conversation on a first
    pass with a tree only (dissector/README.md)."""
    names, value = b"timestamp", bytes.fromhex("4029000000000000")
    setup = [Segment(False, bytes([0, 3 + 8 + len(names), 0x4F]) + bytes.fromhex("405f400000000000") + names),
             Segment(True, bytes([0, 3 + 1 + 6, 0x4F, 1]) + b"DOUBLE")]
    frames = capture.session_frames(setup, port=PORT, client_port=50000)
    frames += capture.session_frames([Segment(True, bytes([0, 3 + 1 + 8, 0x55, 1]) + value)], port=PORT,
                                     client_port=50000, robot_isn=90000, client_isn=70000)
    shown = assert_same(_pcap(frames), "-Y", "rtde")
    package = shown.layers[-1]["rtde"]
    assert "rtde.timestamp" not in package and "_ws.expert" in package
