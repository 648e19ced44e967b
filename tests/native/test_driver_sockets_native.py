"""The native dissectors of the ROS driver's reverse, trajectory and script command sockets
(generated/epan/packet-ur-reverse.c and its siblings, in the plugin) against their Lua twins: the
same fields registered, and on every golden vector (both directions, whole and in 1-7-byte
segments, under its release), each socket's fuzz corpus under two releases and the cell sample,
the same -T json layers, Info column and expert infos. The three sockets share each capture (each
on its port), so that a few tshark runs cover them all; the plugin built with ASan and UBSan
reads the same captures."""
from __future__ import annotations

import random
import shlex
import subprocess

import pytest

from tests.interface_vectors import conversation_cases
from tests.native import harness
from tests.native.lua_twin import compare, cuts, readable, registered, run_lua, run_native, run_sanitized, sessions
from tests.tools.capture import Segment

PORTS = {"ur_reverse": 50001, "ur_trajectory": 50003, "ur_script_command": 50004}
NAMES = tuple(PORTS)
CASES = {name: conversation_cases(name) for name in NAMES}
RELEASES = sorted({c.version for cases in CASES.values() for c in cases}, key=str)
CELL = harness.ROOT / "dissector" / "samples" / "cell_session.pcapng"
CORPUS = harness.ROOT / "tests" / "fuzz" / "corpus"
NO_REASSEMBLY = ["-o", "tcp.desegment_tcp_streams:FALSE"]


@pytest.fixture(scope="module", autouse=True)
def built():
    return harness.plugin("gcc")


def _release(release) -> list[str]:
    """The release preference of every socket."""
    return [a for name in NAMES for a in ("-o", f"{name}.release:{release}")] if release is not None else []


def _on_the_wire(segments) -> list[Segment]:
    """A vector's segments as the capture writer takes them: the control PC listens on the port,
    so the side on the port is the PC, not the robot."""
    return [Segment(not s.from_robot, s.data) for s in segments]


def _small(segments: list[Segment], seed: int) -> list[Segment]:
    rng = random.Random(seed)
    return [Segment(s.from_robot, piece) for s in segments for piece in cuts(s.payload, rng.randrange(1 << 30))]


def _capture(streams_by_name: dict, label: str):
    """One capture: each socket's streams on its port, one TCP session each."""
    paths = [sessions(streams, PORTS[name], f"{label}-{name}", first_client_port=41000 + 1000 * i)
             for i, (name, streams) in enumerate(streams_by_name.items()) if streams]
    return _merged(paths, label) if len(paths) > 1 else paths[0]


def _merged(paths, label: str):
    out = paths[0].with_name(f"{label}-all-{paths[0].stem.rsplit('-', 1)[-1]}.pcap")
    subprocess.run(["mergecap", "-a", "-F", "pcap", "-w", str(out), *map(str, paths)], check=True)
    for path in paths:
        path.unlink()
    return readable(out)


def _vectors() -> list:
    """(capture, tshark arguments) for each release the vectors name: the vectors of that release
    of every socket, each whole and in 1-7-byte segments."""
    out = []
    for release in RELEASES:
        streams = {}
        for name in NAMES:
            chosen = [c for c in CASES[name] if c.version == release]
            streams[name] = [_on_the_wire(c.segments) for c in chosen]
            streams[name] += [_small(_on_the_wire(c.segments), seed=i) for i, c in enumerate(chosen)]
        out.append((_capture(streams, f"sockets-{release}"), _release(release)))
    return out


def _corpus_streams(name: str) -> list[list[Segment]]:
    """Each kept fuzz input as the harness reads it (tests/c/fuzz_int32_records.c): a release byte,
    then chunks, each a byte (bit 0: from the robot; bits 1-7: the length) and its bytes."""
    streams = []
    for path in sorted((CORPUS / name).iterdir()):
        data, at, segments = path.read_bytes(), 1, []
        while at < len(data):
            head, at = data[at], at + 1
            chunk, at = data[at:at + (head >> 1)], at + (head >> 1)
            segments.append(Segment(not head & 1, chunk))      # on the wire: see _on_the_wire
        streams.append(segments)
    return streams


def _corpus():
    return _capture({name: _corpus_streams(name) for name in NAMES}, "sockets-corpus")


def test_the_same_fields_are_registered():
    for name in NAMES:
        native = registered(name, lua=False)
        assert any(f"\t{name}." in line for line in native), name
        assert f"defaultprefs: #{name}.release: " in native, name
        # The ports preference: Wireshark 4.0 keeps the native one among Decode As's preferences, which
        # -G defaultprefs does not print, and prints the Lua twin's Pref.range of the same name.
        ports = f"defaultprefs: #{name}.tcp.port: "
        lua = registered(name, lua=True, loaded=NAMES)
        assert any(line.startswith(ports) for line in lua), name
        assert native == [line for line in lua if not line.startswith(ports)], name


def test_every_vector_whole_and_in_small_segments():
    seen = set()
    for path, args in _vectors():
        shown = compare(path, NAMES, *args)
        seen |= {name for layer in shown.layers for name in layer}
    assert seen == set(NAMES)


def test_without_tcp_reassembly():
    """With TCP reassembly off the part of a record a segment holds is shown as such, as by Lua."""
    for path, args in _vectors():
        compare(path, NAMES, *NO_REASSEMBLY, *args)


@pytest.mark.parametrize("release", [None, "1.0.0", " 1.3.1 ", "not a release"])
def test_the_fuzz_corpus(release):
    shown = compare(_corpus(), NAMES, *_release(release))
    assert all(any(name in layer for layer in shown.layers) for name in NAMES)


def test_the_cell_sample():
    shown = compare(readable(CELL), NAMES)
    for name in NAMES:
        assert any(name in layer for layer in shown.layers), f"the sample has a {name} conversation"


def test_decode_as_on_another_port():
    case = next(c for c in CASES["ur_trajectory"] if c.name == "point_and_result_2_14")
    shown = compare(sessions([_on_the_wire(case.segments)], 40003, "trajectory-40003"), "ur_trajectory",
                    "-d", "tcp.port==40003,ur_trajectory")
    assert any(shown.layers)


def test_the_port_preference_moves_the_dissector():
    """ur_trajectory.tcp.port (dissector_add_uint_range_with_preference; the Lua twin's Pref.range
    of the same name), set to another port, decodes a session there as Decode As does."""
    case = next(c for c in CASES["ur_trajectory"] if c.name == "point_and_result_2_14")
    shown = compare(sessions([_on_the_wire(case.segments)], 40003, "trajectory-40003"), "ur_trajectory",
                    "-o", "ur_trajectory.tcp.port:40003")
    assert any(shown.layers)


def test_without_a_tree_the_summary_is_the_same():
    path, args = _vectors()[-1]
    native = harness.checked(run_native(path, *args, alone=NAMES))
    assert "UR reverse" in native and "UR trajectory" in native and "UR script command" in native
    assert native == harness.checked(run_lua(path, *args, protocol=NAMES))


def test_the_tree_shows_scaled_values_with_their_raw_int32_and_enum_names():
    case = next(c for c in CASES["ur_reverse"] if c.name == "servoj_and_idle")
    path = sessions([_on_the_wire(case.segments)], PORTS["ur_reverse"], "reverse-words")
    text = harness.checked(run_native(path, "-O", "ur_reverse"))
    assert "Control mode: SERVOJ (1)" in text and "(raw 500000, scaled by MULT_JOINTSTATE = 1000000)" in text
    fields = harness.checked(run_native(path, "-Y", "ur_reverse.control_mode == 1 && ur_reverse.target > 2000",
                                        "-T", "fields", "-e", "ur_reverse.target_raw"))
    assert fields.split() == ["500000,-1570796,0,3141593,-1,2147483647,0,0,0,0,0,-2147483648"]


def test_under_asan_and_ubsan_no_report():
    """The plugin built with -fsanitize=address,undefined over the captures above, with and without
    a tree and without TCP reassembly: tshark ends well, with nothing on stderr."""
    vectors = _vectors()
    captures = vectors + [(p, NO_REASSEMBLY + a) for p, a in vectors] + [(readable(CELL), [])]
    captures += [(_corpus(), _release(r)) for r in (None, "1.0.0")]
    for path, args in captures:
        for view in (["-V"], []):
            out = harness.checked(run_sanitized(path, "-2", *view, *args))
            # the plugin read it: a record's label in the tree, the Protocol column in the summary
            assert any(w in out for w in ("UR ", "Reverse interface command", "Trajectory point", "Script command")), \
                (path, view)


@pytest.mark.parametrize("name", ["int32_records/int32_records_types.h", "int32_records/int32_records.c"])
def test_each_runtime_file_compiles_alone(name):
    """runtime/epan/<kind>/<file> with the lines it needs alone (its <standalone> part), strict."""
    flags = subprocess.run(["pkg-config", "--cflags", "wireshark"], capture_output=True, text=True, check=True)
    folder = harness.ROOT / "runtime" / "epan"
    result = subprocess.run(["gcc", "-fsyntax-only", "-Wall", "-Wextra", "-Werror", "-Wno-unused-function", "-x", "c",
                             *shlex.split(flags.stdout), f"-I{folder}", str(folder / name)],
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
