"""A dumpcap capture of `urwire serve` with a client on every interface (the primary and RTDE
through `urwire listen`, the real-time interface read, a dashboard conversation), over real TCP on
loopback: tshark with every dissector of generated/lua reads each interface with no Lua error and
no expert error (`tshark -z expert`), and `urwire decode` reads every conversation with no error
record. `serve` takes the standard ports on an address of its own, so every reader finds each
interface by its default port."""
from __future__ import annotations

import json
import shutil
import signal
import subprocess
import sys
import time

import pytest

from tests.python.cell_server import ENV, ROOT, CellServer, loopback_address, read_until
from urwire.generated import ur_dashboard
from urwire.realtime import RealtimeFramer

DISSECTORS = sorted((ROOT / "generated" / "lua").glob("*.lua"))
DASHBOARD = ["PolyscopeVersion", "programState", "robotmode", "stop", "programState", "play", "get serial number"]

pytestmark = pytest.mark.skipif(shutil.which("dumpcap") is None or shutil.which("tshark") is None,
                                reason="needs dumpcap and tshark (scripts/setup.sh installs them)")


def clients(server: CellServer, tmp) -> None:
    """A client on every interface, each run to its end."""
    host = server.host
    listens = [subprocess.Popen([sys.executable, "-m", "urwire", "listen", f"{host}:30001", "--count", "20",
                                 "--out", str(tmp / "primary.jsonl")], stderr=subprocess.PIPE, env=ENV),
               subprocess.Popen([sys.executable, "-m", "urwire", "listen", f"{host}:30004", "--rtde",
                                 "timestamp,actual_q,actual_TCP_pose,robot_mode,runtime_state", "--frequency", "125",
                                 "--count", "60", "--out", str(tmp / "rtde.jsonl")], stderr=subprocess.PIPE, env=ENV)]
    framer = RealtimeFramer((5, 11, 0))
    with server.connect("realtime") as sock:
        assert len(read_until(sock, framer.feed, lambda r: len(r) >= 100)) >= 100
    conversation = ur_dashboard.conversation()
    with server.connect("dashboard") as sock:
        for line in DASHBOARD:
            sock.sendall(line.encode() + b"\n")
            time.sleep(0.05)
        replies = read_until(sock, lambda chunk: conversation.feed(chunk, True), lambda r: len(r) > len(DASHBOARD))
        assert len(replies) == len(DASHBOARD) + 1
    for proc in listens:
        _, err = proc.communicate(timeout=60)
        assert proc.returncode == 0, err


def test_a_capture_of_the_whole_cell_reads_without_error(tmp_path):
    host = loopback_address()
    pcap = tmp_path / "cell.pcapng"
    cap = subprocess.Popen(["dumpcap", "-q", "-i", "lo", "-f", f"host {host}", "-w", str(pcap)],
                           stderr=subprocess.PIPE, text=True)
    try:
        assert "Capturing on" in cap.stderr.readline() + cap.stderr.readline()
        with CellServer(tmp_path, "--software", "5.11", host=host, port=30001) as server:
            clients(server, tmp_path)
            assert server.stop() == 0
    finally:
        time.sleep(1)  # dumpcap writes what the kernel still holds for it
        cap.send_signal(signal.SIGINT)
        cap.wait(timeout=10)
    tshark = ["tshark", "-r", str(pcap)] + [arg for lua in DISSECTORS for arg in ("-X", f"lua_script:{lua}")]
    # Frames, not messages: TCP may carry several messages in one.
    for protocol, least in (("ur", 10), ("rtde", 20), ("ur_realtime", 30), ("ur_dashboard", 8)):
        res = subprocess.run([*tshark, "-Y", protocol], capture_output=True, text=True, timeout=180)
        assert "Lua: Error" not in res.stderr and res.returncode == 0, res.stderr
        assert len(res.stdout.splitlines()) >= least, (protocol, res.stdout[-2000:])
    expert = subprocess.run([*tshark, "-q", "-z", "expert"], capture_output=True, text=True, timeout=180)
    assert expert.returncode == 0 and "Lua: Error" not in expert.stderr
    assert "Errors (" not in expert.stdout, expert.stdout
    errors = subprocess.run([*tshark, "-Y", "_ws.expert.severity == 0x800000 || _ws.malformed"],
                            capture_output=True, text=True, timeout=180)
    assert errors.returncode == 0 and errors.stdout == ""
    decoded = subprocess.run([sys.executable, "-m", "urwire", "decode", str(pcap)], capture_output=True, text=True,
                             env=ENV, timeout=180)
    assert decoded.returncode == 0, decoded.stderr
    records = [json.loads(line) for line in decoded.stdout.splitlines()]
    interfaces = {r.get("interface", "ur") for r in records}
    assert {"ur", "rtde", "ur_realtime", "ur_dashboard"} <= interfaces, interfaces
    data = [r for r in records if r.get("type") == "data_package"]
    assert len(data) >= 57 and all(len(r["actual_q"]) == 6 for r in data)
