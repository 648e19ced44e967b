"""tests/fuzz/fuzz_wireshark.py (make fuzz-wireshark), Wireshark's fuzz-test.sh approach per
interface: its kept corpora replayed (tests/fuzz/corpus/wireshark_<interface>/, mutated captures)
with the Lua dissectors and the native plugin, a short fixed run of it (a few editcap mutations),
and proof that it fails, keeping the capture, on what it is there to find: a sanitizer report from
the native plugin, a Lua error, a crash; and how it counts malformed packets.

The native plugin is generated/epan's, or the fixture dissector's until generated/epan has files.
"""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from tests.fuzz import fuzz_wireshark
from tests.native import harness
from tests.tools import capture, golden_sessions

ROOT = harness.ROOT
FIXTURES = Path(__file__).resolve().parent / "fixtures"
SCRIPT = ROOT / "tests" / "fuzz" / "fuzz_wireshark.py"
EPAN = harness.EPAN if any(harness.EPAN.glob("packet-*.c")) else FIXTURES / "epan"


def fuzz(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, str(SCRIPT), *args], capture_output=True, text=True, timeout=900)


def fixture_capture(path: Path, kind: int) -> Path:
    """Two fixture messages on the fixture's port: a VALUE, then one of `kind`."""
    messages = [b"\x00\x07\x02\x00\x00\x00\x05", bytes([0, 3, kind])]
    return capture.write(path, capture.robot_session(messages, port=40999))


@pytest.mark.deep          # every interface's kept corpus through tshark, over a minute: `make test-deep`
@pytest.mark.parametrize("native", ["gcc", "asan"])
def test_the_kept_corpora_replay_without_a_failure(native, tmp_path):
    """Every interface's kept mutated captures, read once by each dissector: no crash, dissector
    bug, Lua error or (asan) sanitizer report; their malformed packets are
    counted, per interface."""
    assert all(len(fuzz_wireshark.kept_captures(name)) >= 2 for name in fuzz_wireshark.INTERFACES)
    result = fuzz("--replay", "--native", native, "--epan-dir", str(EPAN), "--out", str(tmp_path / "out"))
    assert result.returncode == 0, result.stdout + result.stderr[-3000:]
    table = {line.split()[0]: line.split()[1:] for line in result.stdout.splitlines()[2:-1]}
    assert set(table) == set(fuzz_wireshark.INTERFACES), result.stdout
    # inputs, mutations, malformed native and Lua (every corpus is malformed somewhere), exceptions
    # native and Lua, then the frames whose protocol summaries differ between the two: none
    assert all(int(row[0]) >= 2 and row[1] == "0" and int(row[2]) + int(row[3]) > 0 and row[6] == "0"
               for row in table.values()), result.stdout
    assert not (tmp_path / "out" / "failures").exists()


def test_malformed_packets_are_counted_by_frame():
    text = ("Frame 1: 60 bytes\n    [Expert Info (Error/Malformed): size 1, type 85]\n"
            "    [Expert Info (Error/Malformed): again]\n"
            "Frame 2: 60 bytes\nUniversal Robots RTDE\n[Malformed Packet: RTDE]\n"
            "    [Expert Info (Error/Malformed): Malformed Packet (Exception occurred)]\n"
            "Frame (60 bytes):\n0000  00 01\nReassembled TCP (9 bytes):\n0000  00 01\n"
            "Frame 3: 60 bytes\n    [Expert Info (Warning/Sequence): not malformed]\n")
    result = subprocess.CompletedProcess([], 0, text.encode(), b"")
    assert fuzz_wireshark.malformed_frames(result) == (2, 1)


def test_frames_the_dissectors_show_otherwise_are_found():
    """The top line of each protocol in tshark -V, not the hex dumps of -x, compared frame by frame."""
    def run(*frames: str) -> subprocess.CompletedProcess:
        return subprocess.CompletedProcess([], 0, "".join(frames).encode(), b"")
    dump = "0000  00 01 02\nReassembled TCP (3 bytes):\n0000  00 01 02\n"
    native = run("Frame 1: 60 bytes\nTCP, Len: 3\nUniversal Robots RTDE, Start\n    Size: 3\n" + dump,
                 "Frame 2: 60 bytes\nTCP, Len: 3\nUniversal Robots RTDE, Pause\n")
    lua = run("Frame 1: 60 bytes\nTCP, Len: 3\nUniversal Robots RTDE, Start\n    Size: 4\n" + dump.replace("02", "03"),
              "Frame 2: 60 bytes\nTCP, Len: 3\n")
    (only,) = fuzz_wireshark.differing_frames(native, lua)
    assert only.startswith("Frame 2, from its protocol 2 on:") and "(nothing)" in only


def test_dissectors_that_differ_on_an_unmutated_capture_fail(tmp_path):
    """The fixture's Lua twin given a protocol item of another name: every frame it reads differs
    from the native plugin's, and on a capture that is not mutated that fails the run."""
    script = tmp_path / "urwire_fixture.lua"
    script.write_text((FIXTURES / "lua" / "urwire_fixture.lua").read_text().replace(
        "    local subtree = tree:add(proto, tvb())\n", "    local subtree = tree:add(proto, tvb(), \"other\")\n"))
    pcap = fixture_capture(tmp_path / "kind1.pcap", 1)
    result = fuzz("--epan-dir", str(FIXTURES / "epan"), "--native", "gcc", "--lua", str(script), "--out",
                  str(tmp_path / "out"), "--seconds", "0", "--only-inputs", str(pcap))
    assert result.returncode == 1, result.stdout + result.stderr[-3000:]
    assert "dissectors differ on an unmutated capture" in result.stderr
    assert (tmp_path / "out" / "failures" / "kind1-original.pcap").is_file()


def test_a_short_fixed_run(tmp_path):
    golden = golden_sessions.write(tmp_path / "golden_vectors.pcap")
    result = fuzz("--epan-dir", str(EPAN), "--out", str(tmp_path / "out"), "--seed", "1", "--mutations", "3",
                  "--seconds", "600", "--only-inputs", str(golden),
                  str(ROOT / "dissector" / "samples" / "cell_session.pcapng"))
    assert result.returncode == 0, result.stdout + result.stderr[-3000:]
    assert "native (ASan+UBSan" in result.stdout and "Lua (" in result.stdout
    assert "2 captures and 3 mutations read without a crash" in result.stdout
    assert not (tmp_path / "out" / "failures").exists()


def test_a_sanitizer_report_fails_and_the_capture_is_kept(tmp_path):
    """A fixture whose kind 3 writes past a heap block of the size its message gives (a size UBSan
    cannot know): ASan, preloaded into tshark, reports it."""
    epan = tmp_path / "epan"
    epan.mkdir()
    source = (FIXTURES / "epan" / "packet-urwire-fixture.c").read_text()
    bug = ("    if (kind == 3) {\n        guint8 *block = (guint8 *)g_malloc(length);\n"
           "        block[length] = kind;\n        g_free(block);\n    }\n")
    marker = "    proto_tree_add_item(subtree, hf_urwire_fixture_kind, tvb, 2, 1, ENC_NA);\n"
    assert marker in source
    (epan / "packet-urwire-fixture.c").write_text(source.replace(marker, marker + bug))
    pcap = fixture_capture(tmp_path / "kind3.pcap", 3)
    result = fuzz("--epan-dir", str(epan), "--lua", "--out", str(tmp_path / "out"), "--seconds", "0",
                  "--only-inputs", str(pcap))
    assert result.returncode == 1, result.stdout + result.stderr[-3000:]
    assert "sanitizer report" in result.stderr
    kept = tmp_path / "out" / "failures" / "kind3-original.pcap"
    assert kept.read_bytes() == pcap.read_bytes()
    assert "AddressSanitizer" in kept.with_suffix(".txt").read_text()


def test_a_lua_error_fails_and_the_capture_is_kept(tmp_path):
    script = tmp_path / "urwire_fixture.lua"
    script.write_text((FIXTURES / "lua" / "urwire_fixture.lua").read_text().replace(
        "    local subtree = tree:add(proto, tvb())\n",
        "    if kind == 3 then error(\"kind 3\") end\n    local subtree = tree:add(proto, tvb())\n"))
    pcap = fixture_capture(tmp_path / "kind3.pcap", 3)
    result = fuzz("--epan-dir", str(tmp_path), "--lua", str(script), "--out", str(tmp_path / "out"),
                  "--seconds", "0", "--only-inputs", str(pcap))
    assert result.returncode == 1, result.stdout + result.stderr[-3000:]
    assert "Lua error" in result.stderr
    assert (tmp_path / "out" / "failures" / "kind3-original.pcap").is_file()
    # the same capture with a kind the script reads is fine
    fine = fixture_capture(tmp_path / "kind1.pcap", 1)
    result = fuzz("--epan-dir", str(tmp_path), "--lua", str(script), "--out", str(tmp_path / "out2"),
                  "--seconds", "0", "--only-inputs", str(fine))
    assert result.returncode == 0, result.stdout + result.stderr[-3000:]


@pytest.mark.parametrize("returncode, stdout, stderr, why", [
    (-11, b"", b"", "killed by signal 11"),
    (86, b"", b"==1==ERROR: AddressSanitizer: heap-buffer-overflow", "sanitizer report"),
    (1, b"", b"packet.c:10:3: runtime error: signed integer overflow", "sanitizer report"),
    (0, b"    [Dissector bug, protocol ur: proto.c:1: failed assertion]", b"", "dissector bug"),
    (0, b"    Lua Error: urwire.lua:10: attempt to index a nil value", b"", "Lua error"),
    (2, b"", b"tshark: The file \"-\" isn't a capture file", "exit status 2"),
    (0, b"Frame 1", b"Running as user \"root\"", None),
])
def test_what_counts_as_a_failure(returncode, stdout, stderr, why):
    found = fuzz_wireshark.problem(subprocess.CompletedProcess([], returncode, stdout, stderr))
    assert (found is None) if why is None else (found is not None and found.startswith(why))
