"""The native dissectors of the text-line interfaces (generated/epan/packet-ur-dashboard.c and
packet-ur-script-sender.c) against their Lua twins (generated/lua/ur_dashboard.lua,
ur_script_sender.lua), each loaded alone in real tshark: the same fields registered, and on the
same captures the same `-T json` layers, Info column and expert infos.

The captures: every golden vector of the interface as a TCP session, whole and again cut into 1-7
byte segments, in one capture per software-version preference; the dashboard fuzzer's kept
corpus (tests/fuzz/corpus/ur_dashboard), each input a session of its segments; the dashboard and
script-sender conversations of the cell sample; hostile conversations (junk, long lines, more
commands in flight than a conversation keeps), with TCP reassembly on and off; a session on
another port under Decode As. The same captures go through the plugin built with ASan and UBSan,
where any report fails the run. Also: the packet list with no tree, text that is not UTF-8, and
the dissector's runtime compiled alone (the matcher it joins, runtime/c/lines/match.c, is the C
library's, tested in tests/c/test_c_kind_runtimes.py)."""
from __future__ import annotations

import functools
import hashlib
import json
import random
import re
import subprocess
from pathlib import Path

import pytest

from tests.interface_vectors import Segment, conversation_cases
from tests.native import harness
from tests.native.lua_twin import native_report
from tests.tools import capture

ROOT = Path(__file__).resolve().parents[2]
CORPUS = ROOT / "tests" / "fuzz" / "corpus" / "ur_dashboard"
CELL = ROOT / "dissector" / "samples" / "cell_session.pcapng"
RUNTIME = ROOT / "runtime" / "epan" / "lines"
MATCH = ROOT / "runtime" / "c" / "lines"         # the matcher, the C library's, which the dissector joins
INTERFACES = ("ur_dashboard", "ur_script_sender", "ur_interpreter", "robotiq_gripper")
PORTS = {"ur_dashboard": 29999, "ur_script_sender": 50002, "ur_interpreter": 30020, "robotiq_gripper": 63352}
# The script sender's port is the control PC's, and the robot connects to it: in the capture
# writer's terms (the side on the port sends "from_robot") its vectors' directions are swapped.
PC_LISTENS = {"ur_dashboard": False, "ur_script_sender": True, "ur_interpreter": False, "robotiq_gripper": False}
CLIENT_PORTS = 41000           # the client side of the n-th session: 41000 + n, no interface's port
# The versions the dashboard fuzzer starts a conversation with, by its first byte's two low bits
# (tests/c/fuzz_ur_dashboard.c).
FUZZ_VERSIONS = (None, "3.15", "5.4", "5.11")


def in_pieces(segments: tuple[Segment, ...], rng: random.Random, most: int) -> tuple[Segment, ...]:
    """The same conversation cut into segments of 1 to `most` bytes."""
    out = []
    for s in segments:
        at = 0
        while at < len(s.data):
            n = rng.randint(1, most)
            out.append(Segment(s.from_robot, s.data[at:at + n]))
            at += n
    return tuple(out)


def sessions(tmp_path: Path, interface: str, conversations: list[tuple[Segment, ...]], port: int = 0) -> Path:
    """One capture holding each conversation as a TCP session of its own."""
    frames = []
    for i, segments in enumerate(conversations):
        tcp = [capture.Segment(s.from_robot != PC_LISTENS[interface], s.data) for s in segments]
        frames += capture.session_frames(tcp, port=port or PORTS[interface], client_port=CLIENT_PORTS + i)
    return capture.write(tmp_path / f"{interface}.pcap", frames)


def preference(interface: str, version) -> tuple[str, ...]:
    return ("-o", f"{interface}.version:{version}") if version else ()


def lua_run(interfaces):
    return functools.partial(harness.run_lua, lua=[harness.lua_plugin(name) for name in interfaces])


def native_run(variant: str):
    if variant == "asan":
        return functools.partial(harness.run_native, variant="asan", env=asan_environment())
    return functools.partial(harness.run_native, variant=variant)


def asan_environment() -> dict:
    """tshark under the sanitizers the asan plugin is built with: libasan preloaded (tshark itself
    is not instrumented), leaks not counted (Wireshark keeps its tables to the end)."""
    libasan = subprocess.run(["gcc", "-print-file-name=libasan.so"], capture_output=True, text=True,
                             check=True).stdout.strip()
    return {"LD_PRELOAD": libasan, "ASAN_OPTIONS": "detect_leaks=0:abort_on_error=1",
            "UBSAN_OPTIONS": "print_stacktrace=1:halt_on_error=1"}


@functools.lru_cache(maxsize=None)
def _lua_shown(digest: str, pcap: Path, interfaces: tuple[str, ...], args: tuple[str, ...]) -> harness.Shown:
    return harness.shown(lua_run(interfaces), pcap, interfaces, *args)


def lua_shown(pcap: Path, interfaces, *args: str) -> harness.Shown:
    """What the Lua dissectors show, once per capture's content (each build is compared with it)."""
    digest = hashlib.sha256(Path(pcap).read_bytes()).hexdigest()
    return _lua_shown(digest, Path(pcap), tuple(interfaces), args)


def assert_same(pcap: Path, interfaces, *args: str, variant: str = "gcc") -> harness.Shown:
    """Native and Lua show the capture alike: layers, Info column, expert infos. Under the asan
    build, any sanitizer report on stderr fails the run (harness.checked)."""
    native = harness.shown(native_run(variant), pcap, interfaces, *args)
    lua = lua_shown(pcap, interfaces, *args)
    assert len(native.layers) == len(lua.layers)
    for number, (mine, theirs) in enumerate(zip(native.layers, lua.layers), start=1):
        assert mine == theirs, f"frame {number}"
    assert native.info == lua.info
    assert native.experts == lua.experts
    return native


def vector_captures(tmp_path: Path, interface: str) -> list[tuple[Path, tuple[str, ...]]]:
    """Per version preference, one capture of its vectors, each whole and in 1-7 byte segments."""
    groups: dict = {}
    for case in conversation_cases(interface):
        groups.setdefault(case.version, []).append(case)
    out = []
    for version, cases in sorted(groups.items(), key=lambda g: g[0] or ""):
        rng = random.Random(f"{interface} {version}")
        conversations = [c.segments for c in cases] + [in_pieces(c.segments, rng, 7) for c in cases]
        folder = tmp_path / (version or "none")
        folder.mkdir()
        out.append((sessions(folder, interface, conversations), preference(interface, version)))
    return out


def corpus_conversation(raw: bytes) -> tuple[Segment, ...]:
    """A dashboard fuzz input as the harness reads it: after the version byte, segments, each a
    control byte (bit 0: from the robot; bits 1-7: its length) and up to that many bytes."""
    out, at = [], 1
    while at < len(raw):
        from_robot, n = bool(raw[at] & 1), raw[at] >> 1
        data = raw[at + 1:at + 1 + n]
        at += 1 + n
        if data:
            out.append(Segment(from_robot, data))
    return tuple(out)


def corpus_captures(tmp_path: Path) -> list[tuple[Path, tuple[str, ...]]]:
    groups: dict = {}
    for path in sorted(CORPUS.iterdir()):
        raw = path.read_bytes()
        if raw and corpus_conversation(raw):
            groups.setdefault(FUZZ_VERSIONS[raw[0] & 3], []).append(corpus_conversation(raw))
    out = []
    for version, conversations in sorted(groups.items(), key=lambda g: g[0] or ""):
        folder = tmp_path / f"corpus-{version or 'none'}"
        folder.mkdir()
        out.append((sessions(folder, "ur_dashboard", conversations), preference("ur_dashboard", version)))
    return out


# ---- the dashboard server and the script sender, native against Lua ----

def test_the_plugin_builds_with_gcc_and_clang():
    for variant in ("gcc", "clang"):
        assert harness.plugin(variant).library.is_file()


@pytest.mark.parametrize("interface", INTERFACES)
def test_the_same_fields_experts_and_ports_are_registered(interface):
    lua = harness.lua_plugin(interface)
    empty = {"HOME": str(harness._empty_home()), "PATH": "/usr/bin:/bin"}
    for report in ("fields", "protocols", "decodes"):
        mine = sorted(line for line in native_report(report) if f"\t{interface}" in line)
        theirs = subprocess.run(["tshark", "-G", report, "-X", f"lua_script:{lua}"], capture_output=True,
                                env=empty, timeout=120).stdout.decode().splitlines()
        theirs = sorted(line for line in theirs if f"\t{interface}" in line
                        # a Lua error caught while dissecting: the native dissector has none to report
                        and f"\t{interface}.internal_error\t" not in line)
        assert mine and mine == theirs, report


# Each capture through the plain build and the one built with ASan and UBSan.
VARIANTS = ("gcc", "asan")


@pytest.mark.parametrize("variant", VARIANTS)
@pytest.mark.parametrize("interface", INTERFACES)
def test_every_golden_vector_whole_and_in_1_to_7_byte_segments(tmp_path, interface, variant):
    for pcap, prefs in vector_captures(tmp_path, interface):
        shown = assert_same(pcap, [interface], *prefs, variant=variant)
        assert any(shown.layers), "the dissector showed nothing"


@pytest.mark.parametrize("variant", [v if v != "asan" else pytest.param(v, marks=pytest.mark.deep) for v in VARIANTS])
def test_the_dashboard_fuzz_corpus(tmp_path, variant):
    captures = corpus_captures(tmp_path)
    assert len(captures) == len(FUZZ_VERSIONS)
    for pcap, prefs in captures:
        assert_same(pcap, ["ur_dashboard"], *prefs, variant=variant)


@pytest.mark.parametrize("variant", VARIANTS)
def test_the_cell_sample(variant):
    # Only the frames of these interfaces: the other interfaces' frames show what other dissectors,
    # native or not, make of them.
    ports = " || ".join(f"tcp.port == {PORTS[name]}" for name in INTERFACES)
    shown = assert_same(CELL, list(INTERFACES), "-Y", ports, variant=variant)
    assert {name for layer in shown.layers for name in layer} == set(INTERFACES)


@pytest.mark.parametrize("interface", INTERFACES)
def test_decode_as_on_another_port(tmp_path, interface):
    case = conversation_cases(interface)[0]
    pcap = sessions(tmp_path, interface, [case.segments], port=40000)
    shown = assert_same(pcap, [interface], "-d", f"tcp.port==40000,{interface}")
    assert any(shown.layers)


@pytest.mark.parametrize("interface", INTERFACES)
def test_the_port_preference_moves_the_dissector(tmp_path, interface):
    """<name>.tcp.port (dissector_add_uint_range_with_preference; the Lua twin's Pref.range of the
    same name), set to another port, decodes a session there. (Set with -o, tshark 4.0 adds the
    new ports to a native dissector without taking the spec's away, as for its own Gopher; the
    Lua twin gives them up: docs/wireshark.md.)"""
    case = conversation_cases(interface)[0]
    shown = assert_same(sessions(tmp_path, interface, [case.segments], port=40000), [interface],
                        "-o", f"{interface}.tcp.port:40000")
    assert any(shown.layers)


def test_the_asan_build_is_instrumented():
    """The sanitizers are in the plugin the asan runs load (else those runs would prove nothing)."""
    symbols = subprocess.run(["nm", "-D", str(harness.plugin("asan").library)], capture_output=True, text=True,
                             check=True).stdout
    assert "__asan_report" in symbols and "__ubsan_handle" in symbols


# ---- the runtime alone (the matcher's own test: tests/c/test_c_kind_runtimes.py) ----


def test_the_dissector_runtime_compiles_alone():
    flags = subprocess.run(["pkg-config", "--cflags", "wireshark"], capture_output=True, text=True, check=True)
    result = subprocess.run(["gcc", "-std=c11", "-Wall", "-Wextra", "-Werror", "-Wno-unused-function", "-fsyntax-only",
                             *flags.stdout.split(), f"-I{RUNTIME}", f"-I{MATCH}", str(RUNTIME / "lines_dissect.c")],
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stderr


def test_text_that_is_not_utf8_shows_as_replacement_characters(tmp_path):
    """A line's bytes are shown as UTF-8 with U+FFFD for each ill-formed part, in the tree and the
    Info column, so that tshark's output is valid UTF-8 (Lua's is compared above)."""
    case = next(c for c in conversation_cases("ur_dashboard") if c.name == "text_not_utf8")
    pcap = sessions(tmp_path, "ur_dashboard", [case.segments + (Segment(False, b"popup a\0b\nplay\n"),)])
    out = harness.checked(harness.run_native(pcap, "-2", "-T", "fields", "-e", "ur_dashboard.command",
                                             "-e", "ur_dashboard.argument", "-e", "_ws.col.Info"))
    raw = harness.run_native(pcap, "-2", "-T", "json").stdout
    raw.decode("utf-8")            # strict: raises on any ill-formed byte
    assert "popup caf\ufffd \ufffd\tcaf\ufffd \ufffd\tCommand: popup caf\ufffd \ufffd" in out
    # A NUL ends a line's text, as C strings end, and the lines after it are shown all the same.
    assert "popup a,play\ta\tCommand: popup a; Command: play" in out


@pytest.mark.parametrize("interface", INTERFACES)
def test_without_a_tree_the_same_packet_list(tmp_path, interface):
    """One pass and no detail asked (tshark's packet list): the dissector runs with no tree, doing
    only the framing, the pairing and the Info column, and shows what Lua shows."""
    for pcap, prefs in vector_captures(tmp_path, interface):
        native = harness.checked(harness.run_native(pcap, *prefs)).splitlines()
        lua = harness.checked(lua_run([interface])(pcap, *prefs)).splitlines()
        assert native == lua
        assert any(("Command: " in line or "Reply: " in line) for line in native)


def hostile_conversations() -> list[tuple[Segment, ...]]:
    """What the vectors do not reach: binary junk, lines longer than the limit, empty lines and
    bare carriage returns, replies before any command, more commands in flight than a
    conversation keeps, version replies that tell no version, and a version learnt
    mid-conversation that makes later commands unavailable. The short ones are cut into 1-7
    byte segments too; the long lines cross segments of up to 700 bytes (reassembling a 9000-byte
    line a few bytes at a time is slow in Lua, and the short ones cross every state)."""
    junk = bytes(range(256)) * 2
    many = b"".join(b"play\n" for _ in range(300))
    short = [
        (Segment(True, junk), Segment(False, junk), Segment(True, b"\n" * 3), Segment(False, b"\r\n\r\r\nplay\r")),
        (Segment(False, b"PolyscopeVersion\nPolyscopeVersion\nPolyscopeVersion\n"),
         Segment(True, b"URSoftware 5.\nURSoftware 1234.5.6 (x)\nURSoftware 3.15.7.1 (Nov 2021)\n"),
         Segment(False, b"safetystatus\nget serial number\nload \n"),
         Segment(True, b"could not understand: 'safetystatus'\n20165500123\nFile not found: \n")),
    ]
    long = [
        (Segment(False, b"x" * 5000 + b"\nstop\n"), Segment(True, b"y" * 4097 + b"\r\nStopped\r\n"),
         Segment(False, b"\r\n" + b"p" * 9000), Segment(False, b"\nplay\n")),
        (Segment(True, b"Starting program\n"), Segment(False, many), Segment(True, b"Starting program\n" * 301)),
        (Segment(False, b"robotmode\n" * 256 + b"play\n"), Segment(True, b"Robotmode: IDLE\n" * 200),
         Segment(False, b"stop\n"), Segment(True, b"Robotmode: IDLE\n" * 56 + b"Starting program\nStopped\n"),
         Segment(False, b"stop\n"), Segment(True, b"Stopped\n")),
    ]
    rng = random.Random("hostile")
    return (short + long + [in_pieces(c, rng, 7) for c in short] + [in_pieces(c, rng, 700) for c in long])


@pytest.mark.parametrize("variant", VARIANTS)
def test_hostile_conversations(tmp_path, variant):
    pcap = sessions(tmp_path, "ur_dashboard", hostile_conversations())
    shown = assert_same(pcap, ["ur_dashboard"], variant=variant)
    messages = {e["_ws.expert.message"] for e in shown.experts}
    assert {"Line longer than 4096 bytes", "Unknown command", "The software version lacks this command",
            "Command not kept: more than 256 commands awaited replies",
            "Reply to a command that was not kept: more than 256 commands awaited replies"} <= messages
    # The same with TCP reassembly off: a line cut by a segment shows as a part of a line.
    shown = assert_same(pcap, ["ur_dashboard"], "-o", "tcp.desegment_tcp_streams:FALSE", variant=variant)
    assert "Part of a line (reassembly is off)" in json.dumps(shown.layers)


def test_the_expert_tap_lists_the_same_experts_as_the_lua_twin(tmp_path):
    """`tshark -q -z expert` builds no tree: the experts a line's items carry (a command or reply
    not kept past 256 awaited replies, an unknown or unavailable command, a reply that says an
    error) are listed by the native dissector as by the Lua one, not only under a tree."""
    pcap = sessions(tmp_path, "ur_dashboard", hostile_conversations())
    lua = harness.checked(lua_run(["ur_dashboard"])(pcap, "-q", "-z", "expert"))
    native = harness.checked(harness.run_native(pcap, "-q", "-z", "expert"))
    for summary in ("Command not kept: more than 256 commands awaited replies",
                    "Reply to a command that was not kept: more than 256 commands awaited replies",
                    "The reply says an error", "Unknown command", "The software version lacks this command"):
        assert summary in lua
    assert native == lua


@pytest.mark.parametrize("interface", INTERFACES)
def test_every_handle_is_declared_registered_and_used(interface):
    """What Wireshark's tools/checkhf.pl checks, for hf_, ett_ and ei_ handles alike: each static
    handle of the generated file is in its registration array and used outside it."""
    text = (ROOT / "generated" / "epan" / f"packet-{interface.replace('_', '-')}.c").read_text()
    code = re.sub(r"/\*.*?\*/", "", text, flags=re.S)
    code = re.sub(r'"(?:\\.|[^"\\])*"', '""', code)
    declared = re.findall(r"^static (?:int|expert_field) ((?:hf|ett|ei)_\w+) = (?:-1|EI_INIT);", code, re.M)
    assert len(declared) == 7 + 3 + 1 + 6     # the fields, the exchange links, ett, experts
    registration = code[code.index(f"void proto_register_{interface}(void)\n{{"):]
    registration = registration[:registration.index("\n}\n")]
    elsewhere = code.replace(registration, "")
    for handle in declared:
        assert f"&{handle}" in registration, f"{handle} is not registered"
        assert len(re.findall(rf"\b{handle}\b", elsewhere)) >= 2, f"{handle} is declared but not used"


def test_a_new_connection_on_the_same_ports_pairs_nothing_with_the_last_ones_commands(tmp_path):
    """Commands with no reply on one connection, then a new connection from the same client port
    whose replies come: Wireshark's TCP starts a new conversation at the SYN, and neither
    dissector pairs those replies with the last connection's commands (Lua labelled "Starting
    program" a reply to robotmode). -Y: Lua sees the TCP conversation on a first pass with a tree
    only (dissector/README.md)."""
    frames = capture.session_frames([capture.Segment(False, b"robotmode\n"), capture.Segment(False, b"play\n")],
                                    port=29999, client_port=41000)
    frames += capture.session_frames([capture.Segment(True, b"Connected: Universal Robots Dashboard Server\n"),
                                      capture.Segment(True, b"Starting program\n")], port=29999,
                                     client_port=41000, robot_isn=90000, client_isn=70000)
    pcap = capture.write(tmp_path / "reused.pcap", frames)
    shown = assert_same(pcap, ["ur_dashboard"], "-Y", "ur_dashboard")
    reply = shown.layers[-1]["ur_dashboard"]
    assert reply["ur_dashboard.reply"] == "Starting program" and "ur_dashboard.command_name" not in reply
