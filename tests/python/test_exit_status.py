"""One exit-status rule for every interface, in `urwire decode`, `build/urwire-decode` and
`urwire listen`: 0 when everything decoded, 1 when the output holds an error record (a record
{"type": "error"} or one carrying an "error" text, such as an RTDE message kept whole with one),
2 on a usage or I/O error."""
from __future__ import annotations

import json
import socket
import struct
import subprocess
import sys
import threading

import pytest

from tests.c.harness_c import get_build
from urwire import rtde
from urwire.generated import rtde as g

ROOT = __import__("pathlib").Path(__file__).resolve().parents[2]
ENV = {"PYTHONPATH": f"{ROOT / 'python'}:{ROOT / 'generated' / 'python'}"}
BANNER = b"Connected: Universal Robots Dashboard Server\n"


def _realtime(size: int) -> bytes:
    return struct.pack(">i", size) + bytes(size - 4)


# interface -> (a clean raw stream of the robot's side, streams that hold a fault)
CASES = {
    "ur_realtime": (_realtime(1116), {
        "unknown size": _realtime(20),
        "size below 12": _realtime(1116) + struct.pack(">i", 3) + _realtime(1116),
        "cut tail": _realtime(1116)[:100],
    }),
    "rtde": (b"\x00\x04V\x01", {
        "short reply": b"\x00\x03V",
        "unknown recipe": b"\x00\x0cU\x07" + bytes(8),
        "short data package": b"\x00\x03U",
        "bad header": b"\x00\x01V",
    }),
    "ur_dashboard": (BANNER + b"Powering on\n", {
        "overlong line": BANNER + b"x" * 5000 + b"\nPowering on\n",
        "cut tail": BANNER + b"Powering",
    }),
    "ur_script_sender": (b"request_program\n", {"cut tail": b"request_prog"}),
    "ur_reverse": (b"", {"bytes from the robot": bytes(4)}),
    "ur_trajectory": (b"", {"cut tail": bytes(3)}),
    "ur_script_command": (b"", {"bytes from the robot": bytes(3)}),
}


def _python(protocol: str, path) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "urwire", "decode", "--protocol", protocol, str(path)],
                          capture_output=True, text=True, env=ENV, timeout=60)


def _c(protocol: str, path) -> subprocess.CompletedProcess:
    return subprocess.run([str(get_build("gcc").cli), "--protocol", protocol, str(path)], capture_output=True,
                          text=True, timeout=60)


@pytest.mark.parametrize("protocol", sorted(CASES))
def test_every_interface_exits_by_the_same_rule_in_both_commands(tmp_path, protocol):
    clean, faulty = CASES[protocol]
    path = tmp_path / "clean.bin"
    path.write_bytes(clean)
    for run in (_python, _c):
        res = run(protocol, path)
        assert res.returncode == 0, (run.__name__, res.stdout, res.stderr)
    for name, data in faulty.items():
        path = tmp_path / "faulty.bin"
        path.write_bytes(data)
        results = [run(protocol, path) for run in (_python, _c)]
        for res in results:
            assert res.returncode == 1, (name, res.stdout, res.stderr)
            records = [json.loads(line) for line in res.stdout.splitlines()]
            assert any(r.get("type") == "error" or isinstance(r.get("error"), str) for r in records), name
        assert results[0].stdout == results[1].stdout, name


def test_a_dashboard_reply_that_says_error_is_not_a_fault(tmp_path):
    """"error": true is the robot's answer, decoded; the command has nothing to report."""
    client, robot = tmp_path / "client.bin", tmp_path / "robot.bin"
    client.write_bytes(b"load /programs/x.urp\n")
    robot.write_bytes(BANNER + b"Error while loading program: /programs/x.urp\n")
    python = subprocess.run([sys.executable, "-m", "urwire", "decode", "--protocol", "ur_dashboard", str(robot),
                             "--to-robot", str(client)], capture_output=True, text=True, env=ENV, timeout=60)
    c = subprocess.run([str(get_build("gcc").cli), "--protocol", "ur_dashboard", str(robot), "--to-robot",
                        str(client)], capture_output=True, text=True, timeout=60)
    for res in (python, c):
        assert res.returncode == 0 and '"error": true' in res.stdout, res.stdout


class WrongRecipePeer:
    """An RTDE robot that accepts protocol 2, the recipe (as recipe 1) and the start, then sends
    data packages of recipe 9, which the connection never set up."""

    def __init__(self, count: int):
        self.listener = socket.create_server(("127.0.0.1", 0))
        self.port = self.listener.getsockname()[1]
        self.count = count
        self.thread = threading.Thread(target=self.run, daemon=True)
        self.thread.start()

    def run(self) -> None:
        self.listener.settimeout(20)
        conn, _ = self.listener.accept()
        conversation = rtde.Conversation(protocol=2)     # what it will accept
        conn.settimeout(20)
        with conn:
            while True:
                data = conn.recv(65536)
                if not data:
                    return
                for message in conversation.feed(data, False):
                    if isinstance(message, g.RequestProtocolVersion):
                        reply = g.RequestProtocolVersionReply(True).encode()
                    elif isinstance(message, g.SetupOutputs):
                        reply = g.SetupOutputsReply(1, ["DOUBLE"] * len(message.variables)).encode()
                    elif isinstance(message, g.Start):
                        data_package = b"\x00\x0cU\x09" + struct.pack(">d", 1.5)
                        reply = g.StartReply(True).encode() + data_package * self.count
                    else:
                        continue
                    conn.sendall(reply)

    def close(self) -> None:
        self.listener.close()
        self.thread.join(5)


def test_listen_rtde_exits_1_when_its_records_hold_errors(tmp_path):
    peer = WrongRecipePeer(count=4)
    out = tmp_path / "records.jsonl"
    try:
        res = subprocess.run([sys.executable, "-m", "urwire", "listen", f"127.0.0.1:{peer.port}", "--rtde",
                              "timestamp", "--out", str(out), "--count", "7", "--duration", "30"],
                             capture_output=True, text=True, env=ENV, timeout=60)
    finally:
        peer.close()
    records = [json.loads(line) for line in out.read_text().splitlines()]
    assert [r["type"] for r in records[3:]] == ["data_package"] * 4
    assert all(r["error"] == "data package of a recipe this connection did not set up" for r in records[3:])
    assert res.returncode == 1, res.stderr


def _golden_exchanges():
    from tests.rtde_vectors import rtde_cases
    return [case for case in rtde_cases() if case.client_bytes and case.robot_bytes]


@pytest.mark.parametrize("case", _golden_exchanges(), ids=lambda case: case.name)
def test_an_rtde_record_with_an_error_text_makes_both_commands_exit_1(tmp_path, case):
    """A message the conversation could not follow (a request a full queue did not keep, a protocol
    version with no layouts) is decoded, but its record carries an error text: exit 1, as for a
    message kept whole with one."""
    robot, client = tmp_path / "robot.bin", tmp_path / "client.bin"
    robot.write_bytes(case.robot_bytes)
    client.write_bytes(case.client_bytes)
    python = subprocess.run([sys.executable, "-m", "urwire", "decode", "--protocol", "rtde", str(robot),
                             "--to-robot", str(client)], capture_output=True, text=True, env=ENV, timeout=60)
    c = subprocess.run([str(get_build("gcc").cli), "--protocol", "rtde", str(robot), "--to-robot", str(client)],
                       capture_output=True, text=True, timeout=60)
    assert python.stdout == c.stdout
    records = [json.loads(line) for line in python.stdout.splitlines()]
    expected = 1 if any(isinstance(r.get("error"), str) or r.get("type") == "error" for r in records) else 0
    assert (python.returncode, c.returncode) == (expected, expected), python.stdout
