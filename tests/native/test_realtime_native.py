"""The native real-time dissector (generated/epan/packet-ur-realtime.c, in the plugin) against its
Lua twin (generated/lua/ur_realtime.lua): the same fields registered, and on every golden vector
(whole and in 1-7-byte segments, with and without the version preference), the fuzz corpus and
the real-time conversation of the cell sample, the same -T json layers, Info column and expert
infos."""
from __future__ import annotations

import struct
from pathlib import Path

import pytest

from tests.native import harness
from tests.native.lua_twin import compare, cuts, readable, registered, run_lua, run_native, run_sanitized, sessions
from tests.vectors import interface_cases

PROTOCOL = "ur_realtime"
PORT = 30003
CASES = interface_cases(PROTOCOL)
VERSIONS = sorted({c.version for c in CASES if c.version}) + [None]
CORPUS = sorted((harness.ROOT / "tests" / "fuzz" / "corpus" / PROTOCOL).iterdir())
CELL = harness.ROOT / "dissector" / "samples" / "cell_session.pcapng"


@pytest.fixture(scope="module", autouse=True)
def built():
    return harness.plugin("gcc")


def _preference(version) -> list[str]:
    return ["-o", f"{PROTOCOL}.version:{version}"] if version else []


def _vectors(version):
    """Every vector that names this version, or every vector when None: each whole and cut in
    1-7-byte segments, one session each."""
    chosen = [c for c in CASES if c.version == version or version is None]
    streams = [[c.data] for c in chosen] + [cuts(c.data, seed=i) for i, c in enumerate(chosen)]
    return sessions(streams, PORT, f"rt-vectors-{version}")


def _corpus():
    streams = [[p.read_bytes()] for p in CORPUS] + [cuts(p.read_bytes(), seed=i) for i, p in enumerate(CORPUS)]
    return sessions(streams, PORT, "rt-corpus")


def test_the_same_fields_are_registered():
    native = registered(PROTOCOL, lua=False)
    assert any("\tur_realtime.q_actual\tFT_DOUBLE" in line for line in native)
    assert "defaultprefs: #ur_realtime.ports: 30003,30013" in native
    assert "defaultprefs: #ur_realtime.version: " in native
    assert "protocols: Universal Robots real-time client interface\tUR_REALTIME\tur_realtime" in native
    assert native == registered(PROTOCOL, lua=True)


@pytest.mark.parametrize("version", VERSIONS, ids=lambda v: f"version={v}")
def test_every_vector_whole_and_in_small_segments(version):
    """Every vector under the version preference, and the vectors that name no version under none:
    one session whole and one cut in 1-7-byte segments each."""
    chosen = [c for c in CASES if c.version == version or version is None]
    shown = compare(_vectors(version), PROTOCOL, *_preference(version))
    layouts = [v for layer in shown.layers for v in _all(layer, "ur_realtime.layout")]
    assert len(layouts) >= 2 * len(chosen)
    if version is None:
        assert any("Packet size 28 matches no layout" in str(e) for e in shown.experts)


def test_without_tcp_reassembly():
    """With TCP reassembly off a packet split over segments is not shown, as the Lua twin shows none."""
    compare(_vectors(None), PROTOCOL, "-o", "tcp.desegment_tcp_streams:FALSE")


@pytest.mark.parametrize("text", ["3.6.5000", " 3.6. ", "3.6x", "5.1"])
def test_the_version_preference_reads_as_lua_reads_it(text):
    """A 1108-byte packet is CB3 3.5-3.9 or e-Series 5.0-5.3: joint mode 248 has a name in CB3's
    table only. Texts the pattern takes (a bugfix over 999, blanks, a trailing dot) and one it
    does not choose the same form in both dissectors."""
    n = (1108 - 4) // 8
    doubles = [0.0] * n
    doubles[95:101] = [248.0] * 6
    packet = struct.pack(f">i{n}d", 1108, *doubles)
    path, preference = sessions([[packet]], PORT, "rt-1108"), ["-o", f"{PROTOCOL}.version:{text}"]
    compare(path, PROTOCOL, *preference)
    tree = harness.checked(run_native(path, "-V", *preference))
    assert ("Wrist 3: 248 (PART_D_CALIBRATION_ERROR)" in tree) == text.strip().startswith("3.6.")


def test_the_client_side_is_urscript():
    compare(sessions([[CASES[0].data]], PORT, "rt-client", client_says=b"movej([0,0,0,0,0,0])\n"), PROTOCOL)


@pytest.mark.parametrize("port, args", [(30013, []), (40123, ["-d", "tcp.port==40123,ur_realtime"]),
                                         (40124, ["-o", "ur_realtime.ports:40124"])],
                         ids=["read-only-port", "decode-as", "ports-preference"])
def test_other_ports(port, args):
    shown = compare(sessions([[c.data] for c in CASES], port, f"rt-port-{port}"), PROTOCOL, *args)
    assert any(shown.layers), f"nothing dissected on {port}"


def test_the_fuzz_corpus():
    shown = compare(_corpus(), PROTOCOL)
    assert shown.experts, "the corpus holds packets of sizes no layout has"


def test_the_cell_sample():
    shown = compare(readable(CELL), PROTOCOL)
    assert any(layer for layer in shown.layers), "the sample has a real-time conversation"


def _all(node, key: str) -> list:
    if isinstance(node, dict):
        return [v for k, value in node.items() for v in ([value] if k == key else _all(value, key))]
    if isinstance(node, list):
        return [v for item in node for v in _all(item, key)]
    return []


def test_without_a_tree_the_summary_is_the_same():
    """tshark's one line per frame builds no tree: the native dissector then only frames and
    words the Info column, and its lines must still be Lua's."""
    streams = [[c.data] for c in CASES] + [cuts(c.data, seed=i) for i, c in enumerate(CASES)]
    path = sessions(streams, PORT, "rt-summary")
    native = harness.checked(run_native(path, alone=PROTOCOL))
    assert "UR real-time" in native and "rt_1_8, RUNNING (+2)" in native
    assert native == harness.checked(run_lua(path, protocol=PROTOCOL))


def test_the_tree_reads_in_words_with_units_and_names():
    case = next(c for c in CASES if c.name.endswith("cb3_3_2"))
    text = harness.checked(run_native(sessions([[case.data]], PORT, "rt-words"), "-V"))
    assert "Actual joint position (rad)\n        Base: 0.501953125 rad" in text
    assert "Motor temperature (°C)\n        Base: 30.5 °C" in text                 # the unit as the Lua dissector shows it
    assert "Robot mode: 7 (RUNNING)" in text and "Program state: 2 (PLAYING)" in text
    assert "UR_REALTIME, rt_3_2" in text or "client interface, rt_3_2" in text


@pytest.mark.parametrize("name", ["sized_packets/ur_realtime_types.h", "sized_packets/ur_realtime_dissect.c"])
def test_each_runtime_file_compiles_alone(name):
    """runtime/epan/<kind>/<file> with the lines it needs alone (its <standalone> part), strict."""
    import shlex
    import subprocess

    flags = subprocess.run(["pkg-config", "--cflags", "wireshark"], capture_output=True, text=True, check=True)
    folder = harness.ROOT / "runtime" / "epan"
    result = subprocess.run(["gcc", "-fsyntax-only", "-Wall", "-Wextra", "-Werror", "-Wno-unused-function", "-x", "c",
                             *shlex.split(flags.stdout), f"-I{folder}", str(folder / name)],
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stderr


def test_under_asan_and_ubsan_no_report():
    """The plugin built with -fsanitize=address,undefined over every capture above, with and
    without a tree: tshark ends well, with nothing on stderr."""
    captures = [(_vectors(v), _preference(v)) for v in VERSIONS] + [(_corpus(), []), (readable(CELL), [])]
    captures.append((_vectors(None), ["-o", "tcp.desegment_tcp_streams:FALSE"]))
    captures.append((sessions([[CASES[0].data]], PORT, "rt-client", client_says=b"movej([0,0,0,0,0,0])\n"), []))
    for path, args in captures:
        for view in (["-V"], []):
            out = harness.checked(run_sanitized(path, "-2", *view, *args))
            assert "UR real-time" in out or "ur_realtime" in out, (path, view)


def test_the_tree_reads_as_lua_word_for_word():
    """Each double's label shows its unit as the Lua dissector appends it (" s", " °C"), so the
    two trees print alike; only TCP's "[PDU Size: N]" is the native one's own, which
    tcp_dissect_pdus adds."""
    path = sessions([[c.data] for c in CASES], PORT, "rt-verbose")

    def lines(text: str) -> list[str]:
        return [line for line in text.splitlines() if not line.strip().startswith("[PDU Size: ")]

    native = harness.checked(run_native(path, "-V", alone=PROTOCOL))
    assert " °C" in native and " rad/s" in native
    assert lines(native) == lines(harness.checked(run_lua(path, "-V", protocol=PROTOCOL)))
