"""What `urwire decode` reads as a capture: a file that starts with a whole pcap file header or
pcapng section header, whatever --protocol says; anything else is a raw stream, even when its first
four bytes are a capture magic (a dashboard session may start with "\\n\\r\\r\\n", the pcapng one).
build/urwire-decode reads raw streams only, and the two print the same lines for such a stream."""
from __future__ import annotations

import json
import subprocess
import sys

import pytest

from tests.c.harness_c import get_build
from tests.tools import capture
from tests.tools.capture import Segment
from urwire.capture import is_capture

ROOT = __import__("pathlib").Path(__file__).resolve().parents[2]
ENV = {"PYTHONPATH": f"{ROOT / 'python'}:{ROOT / 'generated' / 'python'}"}
DASHBOARD = b"\n\r\r\nConnected: Universal Robots Dashboard Server\nPowering on\n"


def decode(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "urwire", "decode", *args], capture_output=True, text=True,
                          env=ENV, timeout=60)


@pytest.mark.parametrize("head", [
    b"\n\r\r\n",                                        # the pcapng magic
    b"\xa1\xb2\xc3\xd4", b"\xd4\xc3\xb2\xa1",           # pcap's, either byte order
    b"\xa1\xb2\x3c\x4d", b"\x4d\x3c\xb2\xa1",           # pcap's with nanoseconds
])
def test_a_raw_stream_that_starts_with_a_capture_magic_is_a_raw_stream(tmp_path, head):
    path = tmp_path / "dashboard.bin"
    path.write_bytes(head + b"\n" + DASHBOARD[4:])
    python = decode("--protocol", "ur_dashboard", str(path))
    c = subprocess.run([str(get_build("gcc").cli), "--protocol", "ur_dashboard", str(path)], capture_output=True,
                       text=True, timeout=60)
    assert (python.stdout, python.returncode) == (c.stdout, c.returncode), python.stderr
    replies = [json.loads(line)["reply"] for line in python.stdout.splitlines()]
    assert replies[-2:] == ["Connected: Universal Robots Dashboard Server", "Powering on"]


@pytest.mark.parametrize("pcapng", [False, True])
def test_a_capture_is_a_capture_whatever_the_protocol(tmp_path, pcapng):
    frames = capture.session_frames([Segment(True, DASHBOARD[4:])], port=29999)
    path = capture.write(tmp_path / ("cell.pcapng" if pcapng else "cell.pcap"), frames, pcapng=pcapng)
    assert is_capture(path.read_bytes()[:12])
    res = decode("--protocol", "ur_dashboard", str(path))
    assert res.returncode == 0, res.stderr
    records = [json.loads(line) for line in res.stdout.splitlines()]
    assert [r["reply"] for r in records] == ["Connected: Universal Robots Dashboard Server", "Powering on"]
    assert {r["direction"] for r in records} == {"from_robot"}


def test_the_rule_looks_at_the_whole_file_header():
    assert is_capture(b"\xd4\xc3\xb2\xa1\x02\x00\x04\x00")               # pcap, little-endian, 2.4
    assert is_capture(b"\xa1\xb2\xc3\xd4\x00\x02\x00\x04")               # pcap, big-endian
    assert not is_capture(b"\xa1\xb2\xc3\xd4\x02\x00\x04\x00")           # the version in the other order
    assert is_capture(b"\n\r\r\n\x1c\x00\x00\x00\x4d\x3c\x2b\x1a")       # pcapng, little-endian
    assert is_capture(b"\n\r\r\n\x00\x00\x00\x1c\x1a\x2b\x3c\x4d")       # pcapng, big-endian
    assert not is_capture(b"\n\r\r\nConnected")
    assert not is_capture(b"\n\r\r\n")
