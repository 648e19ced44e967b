"""`urwire listen` against a hostile peer on loopback: garbage, a 2^31 length, one byte per
segment, drops inside a message, silence and reconnect storms. Each run is bounded by
--duration (a few seconds) and a subprocess timeout; listen must never crash, hang or hold
what the peer announces, and what it records matches what decoding the bytes gives."""
from __future__ import annotations

import json
import random
import re
import socket
import struct
import time

import urwire

from tests.python.loopback_peer import Peer, listen, session_bytes

SESSION = session_bytes(3)


def sends(data: bytes, linger: float = 0.1):
    def script(conn: socket.socket) -> None:
        conn.sendall(data)
        time.sleep(linger)
    return script


def records(path) -> list[dict]:
    return [json.loads(line) for line in path.read_text().splitlines()]


def expected(data: bytes) -> list[str]:
    return [urwire.to_json_line(r) for r in urwire.decode_stream(data)]


def assert_survived(res) -> None:
    assert res.returncode in (0, 1), res.stderr
    assert "Traceback" not in res.stderr


def test_garbage_then_a_session(tmp_path):
    garbage = random.Random(7).randbytes(3000)
    out = tmp_path / "out.jsonl"
    with Peer([sends(garbage + SESSION)]) as peer:
        res = listen(peer.port, "--out", str(out), "--duration", "2")
    assert_survived(res)
    assert out.read_text().splitlines() == expected(garbage + SESSION)
    assert any(r["type"] == "version" for r in records(out))


def test_a_length_of_two_to_the_31(tmp_path):
    huge = struct.pack(">IB", 1 << 31, 20) + bytes(64)
    out = tmp_path / "out.jsonl"
    with Peer([sends(huge + SESSION)]) as peer:
        res = listen(peer.port, "--out", str(out), "--duration", "2")
    assert res.returncode == 1, res.stderr       # the bad length is an error record, and decoding goes on
    assert "Traceback" not in res.stderr
    assert out.read_text().splitlines() == expected(huge + SESSION)
    assert any(r["type"] == "version" for r in records(out))


def test_one_byte_per_segment(tmp_path):
    def script(conn: socket.socket) -> None:
        conn.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        for i in range(len(SESSION)):
            conn.sendall(SESSION[i:i + 1])
        time.sleep(0.1)
    out = tmp_path / "out.jsonl"
    with Peer([script]) as peer:
        res = listen(peer.port, "--out", str(out), "--duration", "3")
    assert res.returncode == 0, res.stderr
    assert out.read_text().splitlines() == expected(SESSION)


def test_drops_inside_headers_and_bodies(tmp_path):
    # Inside the Version message's header (no robot state came: the pause grows), then inside a
    # robot state's header and body after a whole one (data flowed: the pause starts again).
    working = len(session_bytes(1))
    cuts = [1, 4] + [working + cut for cut in (1, 4, 5, 60)] + [len(SESSION) - 1]
    out, raw = tmp_path / "out.jsonl", tmp_path / "s.raw"
    with Peer([sends(SESSION[:cut], linger=0) for cut in cuts]) as peer:
        res = listen(peer.port, "--out", str(out), "--raw", str(raw), "--duration", "6")
    assert_survived(res)
    assert out.read_text().splitlines() == [line for cut in cuts for line in expected(SESSION[:cut])]
    assert res.stderr.count("reconnected") >= len(cuts) - 1


def test_silence_after_half_a_message(tmp_path):
    half = SESSION[:len(session_bytes(1)) + 30]

    def script(conn: socket.socket) -> None:
        conn.sendall(half)
        conn.settimeout(5)
        conn.recv(1)            # silent until listen hangs up
    out = tmp_path / "out.jsonl"
    with Peer([script]) as peer:
        started = time.monotonic()
        res = listen(peer.port, "--out", str(out), "--idle-timeout", "0.5", "--duration", "2")
        took = time.monotonic() - started
    assert_survived(res)
    assert took < 4
    assert "no data" in res.stderr
    assert out.read_text().splitlines() == expected(half)    # the cut message is recorded when dropped


def test_storm_of_connections_closed_at_once(tmp_path):
    with Peer([sends(b"", linger=0)] * 20) as peer:
        res = listen(peer.port, "--duration", "4")
    assert res.returncode == 2
    assert res.stderr.splitlines()[-1] == f"urwire listen: nothing was received from 127.0.0.1:{peer.port}"
    assert "Traceback" not in res.stderr
    waits = [float(w) for w in re.findall(r"reconnecting in (\d+\.\d) s", res.stderr)]
    assert 2 <= len(waits) <= 5
    assert waits[:3] == sorted(waits[:3]) and waits[1] > waits[0]      # the pause grows: no busy loop


def test_storm_of_short_sessions(tmp_path):
    # Each session sends its Version and one tick: data flowed, so each reconnect waits 0.5 s.
    short = session_bytes(1)
    out = tmp_path / "out.jsonl"
    with Peer([sends(short, linger=0)] * 6) as peer:
        res = listen(peer.port, "--out", str(out), "--count", str(6 * len(expected(short))), "--duration", "8")
    assert res.returncode == 0, res.stderr
    assert out.read_text().splitlines() == expected(short) * 6
    assert set(re.findall(r"reconnecting in (\d+\.\d) s", res.stderr)) == {"0.5"}


def test_sessions_that_end_after_the_version_message_back_off(tmp_path):
    # A Version message and no robot state: no session worked, so the pause grows as when
    # nothing at all is received, and every message that came is recorded.
    version = session_bytes(0)
    out = tmp_path / "out.jsonl"
    with Peer([sends(version, linger=0)] * 6) as peer:
        res = listen(peer.port, "--out", str(out), "--duration", "4")
    assert res.returncode == 0, res.stderr
    waits = [float(w) for w in re.findall(r"reconnecting in (\d+\.\d) s", res.stderr)]
    assert waits[:3] == [0.5, 1.0, 2.0], res.stderr
    assert [r["type"] for r in records(out)] == ["version"] * (res.stderr.count("reconnected") + 1)
