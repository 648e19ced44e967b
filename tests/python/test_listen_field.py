"""`urwire listen` in the field, over real TCP on loopback: what --raw keeps decodes back to
exactly what --out recorded across reconnects, a full disk is an I/O error (exit 2) and not a lost
connection, a silent peer is dropped after the idle timeout, and each reconnect is said on stderr."""
from __future__ import annotations

import json
import re
import socket
import subprocess
import sys
import time

import pytest

from tests.python.loopback_peer import ENV, Peer, listen, session_bytes

CONNECTIONS = 4


def cut_session(states: int, keep: float = 0.5):
    """A script: a Version message and states, then the connection is dropped inside a message."""
    data = session_bytes(states)
    last_start = len(session_bytes(states - 1))

    def script(conn: socket.socket) -> None:
        conn.sendall(data[:last_start + int((len(data) - last_start) * keep)])
        time.sleep(0.1)
    return script


def whole_session(states: int):
    def script(conn: socket.socket) -> None:
        conn.sendall(session_bytes(states))
        time.sleep(0.1)
    return script


def silent(seconds: float):
    """A script: accept and say nothing, until the client hangs up or `seconds` pass."""
    def script(conn: socket.socket) -> None:
        conn.settimeout(seconds)
        conn.recv(1)
    return script


def raw_files(tmp_path, stem: str = "session"):
    first = tmp_path / f"{stem}.raw"
    rest = sorted(tmp_path.glob(f"{stem}.*.raw"), key=lambda p: int(p.suffixes[-2][1:]))
    return [first, *rest]


def decoded(path) -> list[str]:
    res = subprocess.run([sys.executable, "-m", "urwire", "decode", str(path)],
                         capture_output=True, text=True, env=ENV, timeout=30)
    assert res.returncode in (0, 1), res.stderr
    return res.stdout.splitlines()


def test_raw_across_reconnects_decodes_to_the_records(tmp_path):
    scripts = [cut_session(3 + n, keep=0.3 + 0.15 * n) for n in range(CONNECTIONS)]
    out, raw = tmp_path / "session.jsonl", tmp_path / "session.raw"
    with Peer(scripts) as peer:
        res = listen(peer.port, "--out", str(out), "--raw", str(raw), "--duration", "4")
    recorded = out.read_text().splitlines()
    files = raw_files(tmp_path)
    assert len(files) == CONNECTIONS, res.stderr
    assert [line for f in files for line in decoded(f)] == recorded
    versions = [line for line in recorded if json.loads(line)["type"] == "version"]
    assert len(versions) == CONNECTIONS
    # Each file holds its connection's bytes exactly, the cut message included.
    for n, f in enumerate(files):
        data = session_bytes(3 + n)
        last_start = len(session_bytes(2 + n))
        assert f.read_bytes() == data[:last_start + int((len(data) - last_start) * (0.3 + 0.15 * n))]


def test_stopped_inside_a_message_the_raw_file_still_decodes_to_the_records(tmp_path):
    data = session_bytes(3)
    cut = data[:len(data) - 40]

    def script(conn: socket.socket) -> None:
        conn.sendall(cut)
        conn.settimeout(5)
        conn.recv(1)            # silent, inside a message, until listen stops
    out, raw = tmp_path / "session.jsonl", tmp_path / "session.raw"
    with Peer([script]) as peer:
        res = listen(peer.port, "--out", str(out), "--raw", str(raw), "--idle-timeout", "10", "--duration", "1.5")
    assert res.returncode == 1, res.stderr      # the cut message is an error record
    assert raw.read_bytes() == cut
    assert decoded(raw) == out.read_text().splitlines()


def test_raw_file_names(tmp_path):
    from urwire.live.listen import earlier_raw_files, raw_path
    assert [raw_path("logs/session.raw", n) for n in range(3)] == \
        ["logs/session.raw", "logs/session.1.raw", "logs/session.2.raw"]
    assert raw_path("session", 4) == "session.4"
    for name in ("s.raw", "s.1.raw", "s.12.raw", "s.x.raw", "s.01.raw", "s.1.bin", "t.1.raw"):
        (tmp_path / name).write_bytes(b"")
    found = sorted(p.name for p in earlier_raw_files(str(tmp_path / "s.raw")))
    assert found == ["s.1.raw", "s.12.raw"]


def test_a_new_run_replaces_the_numbered_raw_files_of_a_longer_one(tmp_path):
    raw = tmp_path / "session.raw"
    for n in (1, 2, 3):
        (tmp_path / f"session.{n}.raw").write_bytes(b"from an earlier run")
    with Peer([whole_session(2), whole_session(2)]) as peer:
        listen(peer.port, "--out", str(tmp_path / "out.jsonl"), "--raw", str(raw),
               "--duration", "3")
    assert [f.name for f in raw_files(tmp_path)] == ["session.raw", "session.1.raw"]
    assert (tmp_path / "session.1.raw").read_bytes() == session_bytes(2)


@pytest.mark.parametrize("which", ["--out", "--raw"])
def test_full_disk_is_an_io_error_not_a_lost_connection(which, tmp_path):
    other = {"--out": str(tmp_path / "session.raw"), "--raw": str(tmp_path / "session.jsonl")}
    other_flag = "--raw" if which == "--out" else "--out"
    with Peer([whole_session(5)] * 3) as peer:
        res = listen(peer.port, which, "/dev/full", other_flag, other[which], "--duration", "5")
    assert res.returncode == 2, res.stderr
    assert "Traceback" not in res.stderr
    assert "/dev/full" in res.stderr and "No space left on device" in res.stderr
    assert "lost" not in res.stderr and "reconnect" not in res.stderr
    assert peer.served == 1


def test_full_standard_output_is_an_io_error(tmp_path):
    with Peer([whole_session(5)] * 3) as peer, open("/dev/full", "w") as full:
        res = subprocess.run([sys.executable, "-m", "urwire", "listen", f"127.0.0.1:{peer.port}", "--duration", "5"],
                             stdout=full, stderr=subprocess.PIPE, text=True, env=ENV, timeout=20)
    assert res.returncode == 2, res.stderr
    assert "standard output" in res.stderr and "No space left on device" in res.stderr
    assert "Traceback" not in res.stderr and "reconnect" not in res.stderr


def test_unwritable_output_is_said_before_connecting(tmp_path):
    missing = tmp_path / "no such folder" / "session.jsonl"
    res = listen(9, "--out", str(missing), "--duration", "2")     # port 9: nothing is contacted
    assert res.returncode == 2
    assert f"cannot write {missing}: No such file or directory" in res.stderr
    assert "connect" not in res.stderr


def test_silent_peer_is_dropped_after_the_idle_timeout(tmp_path):
    out = tmp_path / "session.jsonl"
    with Peer([silent(8), whole_session(3)]) as peer:
        started = time.monotonic()
        res = listen(peer.port, "--out", str(out), "--idle-timeout", "1", "--count", "4", "--duration", "8")
        took = time.monotonic() - started
    assert res.returncode == 0, res.stderr
    assert len(out.read_text().splitlines()) == 4
    assert took < 7
    assert re.search(r"no data .* for 1\.0 s", res.stderr)


def test_idle_timeout_defaults_to_two_seconds(tmp_path):
    with Peer([silent(6), whole_session(2)]) as peer:
        started = time.monotonic()
        res = listen(peer.port, "--count", "1", "--duration", "8")
        took = time.monotonic() - started
    assert res.returncode == 0, res.stderr
    assert 1.9 < took < 7
    assert "for 2.0 s" in res.stderr


def test_socket_has_keepalive():
    import importlib
    listen_module = importlib.import_module("urwire.live.listen")
    with socket.create_server(("127.0.0.1", 0)) as server:
        sock = listen_module.connect("127.0.0.1", server.getsockname()[1], timeout=2)
        with sock:
            assert sock.getsockopt(socket.SOL_SOCKET, socket.SO_KEEPALIVE)
            # Where the platform names them, a dead link is found in well under a minute.
            probes = {name: sock.getsockopt(socket.IPPROTO_TCP, getattr(socket, name))
                      for name in ("TCP_KEEPIDLE", "TCP_KEEPINTVL", "TCP_KEEPCNT") if hasattr(socket, name)}
            if len(probes) == 3:
                assert probes["TCP_KEEPIDLE"] + probes["TCP_KEEPINTVL"] * probes["TCP_KEEPCNT"] <= 30


def test_reconnects_are_said_on_stderr(tmp_path):
    out = tmp_path / "session.jsonl"
    with Peer([cut_session(3), silent(3), whole_session(2)]) as peer:
        res = listen(peer.port, "--out", str(out), "--idle-timeout", "1", "--duration", "4.5")
    lines = res.stderr.splitlines()
    records = len(out.read_text().splitlines())
    lost = [line for line in lines if "lost" in line]
    idle = [line for line in lines if "no data" in line]
    reconnected = [line for line in lines if "reconnected" in line]
    assert lost and re.search(r"closed by the peer; \d+ records so far; reconnecting in \d+\.\d s", lost[0])
    assert idle and re.search(r"; \d+ records so far; reconnecting in \d+\.\d s", idle[0])
    assert len(reconnected) >= 2
    assert re.search(r"reconnected to 127\.0\.0\.1:\d+ \(connection 2\); \d+ records so far", reconnected[0])
    # The counts said are the records written by then: the first loss follows the first session.
    first_loss = int(re.search(r"(\d+) records so far", lost[0]).group(1))
    assert 0 < first_loss <= records
