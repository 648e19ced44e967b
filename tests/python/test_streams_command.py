"""`urwire streams CAPTURE OUTDIR`: a capture's TCP payloads as raw streams, a file per
conversation and direction, which decode as the capture's own records do."""
from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

from tests.tools import capture
from tests.tools.capture import Segment

ROOT = Path(__file__).resolve().parents[2]
ENV = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT / "python"), str(ROOT / "generated" / "python")]))
CELL = ROOT / "dissector" / "samples" / "cell_session.pcapng"


def urwire(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "urwire", *args], capture_output=True, text=True, env=ENV,
                          timeout=300)


def records(*args: str) -> list[dict]:
    res = urwire("decode", *args)
    assert res.returncode in (0, 1), res.stderr
    return [json.loads(line) for line in res.stdout.splitlines()]


def test_every_conversation_and_direction_of_the_cell_capture_is_a_file(tmp_path):
    res = urwire("streams", str(CELL), str(tmp_path / "out"))
    assert res.returncode == 0, res.stderr
    listed = dict(line.split("\t") for line in res.stdout.splitlines())
    files = {p.name: p.stat().st_size for p in (tmp_path / "out").iterdir()}
    assert {Path(p).name: int(n) for p, n in listed.items()} == files
    ends = {(r["interface"], r["conversation"], r["direction"]) for r in records(str(CELL))}
    # Every direction that had a record has its file (a direction may carry bytes but no record).
    names = {f"{i}_{c.replace(':', '_').replace('-', '_')}_{d}.bin" for i, c, d in ends}
    assert names <= set(files)
    assert "ur_192.168.56.101_30001_192.168.56.1_50101_from_robot.bin" in files
    # The driver's sockets: the control PC listens, and what reaches its port comes from the robot.
    assert "ur_reverse_192.168.56.1_50001_192.168.56.101_40001_to_robot.bin" in files


def test_the_primary_stream_decodes_as_the_capture_does(tmp_path):
    assert urwire("streams", str(CELL), str(tmp_path)).returncode == 0
    raw = tmp_path / "ur_192.168.56.101_30001_192.168.56.1_50101_from_robot.bin"
    from_capture = [{k: v for k, v in r.items() if k not in ("interface", "direction", "conversation")}
                    for r in records(str(CELL), "--protocol", "ur")]
    assert records(str(raw)) == from_capture
    assert len(from_capture) == 2


def test_both_directions_of_an_rtde_conversation_decode_as_the_capture_does(tmp_path):
    assert urwire("streams", "--protocol", "rtde", str(CELL), str(tmp_path)).returncode == 0
    assert {p.name.split("_")[0] for p in tmp_path.iterdir()} == {"rtde"}
    stem = "rtde_192.168.56.101_30004_192.168.56.1_50103"
    from_raw = records("--protocol", "rtde", str(tmp_path / f"{stem}_from_robot.bin"),
                       "--to-robot", str(tmp_path / f"{stem}_to_robot.bin"))
    conversation = "192.168.56.101:30004-192.168.56.1:50103"
    from_capture = [r for r in records(str(CELL), "--protocol", "rtde") if r["conversation"] == conversation]
    # The robot's records: the client's stream is read whole first, so the order of the two
    # directions is the capture's only within each.
    robot = [r for r in from_capture if r["direction"] == "from_robot"]
    assert any(r["type"] == "data_package" for r in robot)
    assert [r for r in from_raw if r["direction"] == "from_robot"] == [
        dict(r, conversation=str(tmp_path / f"{stem}_from_robot.bin")) for r in robot]


def test_bytes_the_capture_lacks_are_left_out_and_named(tmp_path):
    payloads = [b"A" * 100, b"B" * 100, b"C" * 100]
    frames = capture.session_frames([Segment(True, p) for p in payloads], port=30003)
    del frames[3 + 2]                                    # the robot's second segment
    pcap = capture.write(tmp_path / "lost.pcap", frames)
    res = urwire("streams", str(pcap), str(tmp_path / "out"))
    assert res.returncode == 1
    assert "100 bytes missing from the capture at offset 100" in res.stderr
    [written] = (tmp_path / "out").iterdir()
    assert written.read_bytes() == b"A" * 100 + b"C" * 100


def test_a_raw_stream_is_refused(tmp_path):
    raw = tmp_path / "x.bin"
    raw.write_bytes(b"\x00\x00\x00\x05\x14")
    res = urwire("streams", str(raw), str(tmp_path / "out"))
    assert res.returncode == 2
    assert "not a .pcap or .pcapng capture" in res.stderr
    assert not (tmp_path / "out").exists()
