"""A tail belongs to the direction whose bytes it is: the client's unterminated line or cut message,
read with --to-robot, is an error record of `to_robot` and the client's file, in `urwire decode`
and in `build/urwire-decode` alike (the capture reader's side is in test_capture_gaps.py)."""
from __future__ import annotations

import json
import subprocess
import sys

import pytest

from tests.c.harness_c import get_build

ROOT = __import__("pathlib").Path(__file__).resolve().parents[2]
ENV = {"PYTHONPATH": f"{ROOT / 'python'}:{ROOT / 'generated' / 'python'}"}

# interface -> (the client's stream, cut; the robot's stream, whole)
CASES = {
    "ur_dashboard": (b"power on\npopup hel", b"Connected: Universal Robots Dashboard Server\nPowering on\n"),
    "rtde": (b"\x00\x05V\x00\x02\x00\x05V", b"\x00\x04V\x01"),
    "ur_reverse": (bytes(4 * 8 + 3), b""),
}


def _run(command: list[str], cwd) -> tuple[list[dict], int]:
    res = subprocess.run(command, capture_output=True, text=True, env=ENV, timeout=60, cwd=cwd)
    assert res.returncode in (0, 1), res.stderr
    return [json.loads(line) for line in res.stdout.splitlines()], res.returncode


@pytest.mark.parametrize("protocol", sorted(CASES))
def test_the_clients_cut_tail_is_the_clients_in_both_commands(tmp_path, protocol):
    client, robot = CASES[protocol]
    (tmp_path / "client.bin").write_bytes(client)
    (tmp_path / "robot.bin").write_bytes(robot)
    args = ["--protocol", protocol, "robot.bin", "--to-robot", "client.bin"]
    python = _run([sys.executable, "-m", "urwire", "decode", *args], tmp_path)
    c = _run([str(get_build("gcc").cli), *args], tmp_path)
    assert python == c
    records, status = python
    assert status == 1
    (tail,) = [r for r in records if r["type"] == "error"]
    assert (tail["direction"], tail["conversation"]) == ("to_robot", "client.bin")
    assert records[-1] == tail            # the client's tail, after every record of both streams
