"""`urwire serve` refuses what a real robot refuses, over real TCP on loopback: a dashboard line
longer than the limit gets one error reply and none of its bytes run as a command; an RTDE setup
at a frequency the robot would not run (NaN, infinite, zero, negative, above its generation's
maximum) gets a reply without a recipe, and the server neither streams nor spins. Every process
and socket is bounded in count and time."""
from __future__ import annotations

import math
import os
import socket
import subprocess
import sys
import time

import pytest

from tests.python.cell_server import ENV, CellServer, read_until
from urwire import rtde
from urwire.generated import rtde as g
from urwire.generated import ur_dashboard

BANNER = "Connected: Universal Robots Dashboard Server"


def dashboard_lines(sock, count: int) -> list:
    conversation = ur_dashboard.conversation()
    return read_until(sock, lambda chunk: conversation.feed(chunk, True), lambda r: len(r) >= count)


def test_an_overlong_dashboard_line_gets_one_error_reply_and_its_tail_never_runs(tmp_path):
    with CellServer(tmp_path, "--software", "5.11") as server:
        with server.connect("dashboard") as sock:
            sock.sendall(b"popup " + b"x" * 5000)
            time.sleep(0.2)                          # the tail comes in a write of its own
            sock.sendall(b"power off\nrobotmode\n")
            replies = dashboard_lines(sock, 3)
            assert [r.reply for r in replies] == [
                BANNER, "could not understand: 'line longer than 4096 bytes'", "Robotmode: RUNNING"]
            assert replies[1].error is True
        assert server.stop() == 0


def test_what_serve_says_decodes_as_the_decoder_splits_it(tmp_path):
    # The decoder's view of the same session: one error for the long line, and every reply
    # paired with its own command.
    said = b"popup " + b"y" * 4097 + b"\r\nrobotmode\n" + b"z" * 9000 + b"\nget robot model\n"
    with CellServer(tmp_path, "--software", "5.11") as server:
        with server.connect("dashboard") as sock:
            for at in range(0, len(said), 1000):
                sock.sendall(said[at:at + 1000])
            heard = b""
            deadline = time.monotonic() + 5
            while heard.count(b"\n") < 5 and time.monotonic() < deadline:
                heard += sock.recv(65536)
        assert server.stop() == 0
    conversation = ur_dashboard.conversation("5.11")
    records = conversation.feed(said, False) + conversation.feed(heard, True)
    errors = [r for r in records if not hasattr(r, "command_name")]
    replies = [(r.command_name, r.reply) for r in records if hasattr(r, "reply")]
    assert len(errors) == 2
    assert replies == [(None, BANNER), (None, "could not understand: 'line longer than 4096 bytes'"),
                       ("robotmode", "Robotmode: RUNNING"), (None, "could not understand: 'line longer than 4096 bytes'"),
                       ("get_robot_model", "UR5")]


# ---- RTDE: frequencies a robot refuses ------------------------------------------------------

def cpu_seconds(pid: int) -> float:
    """User and system CPU time of a process so far (/proc/<pid>/stat, in clock ticks)."""
    fields = open(f"/proc/{pid}/stat").read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def rtde_send(sock, conversation, data: bytes) -> None:
    conversation.feed(data, False)          # the replies are read in the protocol the requests ask
    sock.sendall(data)


def rtde_replies(sock, conversation, count: int) -> list:
    return read_until(sock, lambda chunk: conversation.feed(chunk, True), lambda r: len(r) >= count)


@pytest.mark.parametrize("software,frequency", [("5.11", math.nan), ("5.11", math.inf), ("5.11", -math.inf),
                                                ("5.11", 0.0), ("5.11", -125.0), ("5.11", 500.5), ("5.11", 1e308),
                                                ("3.15", 126.0), ("3.15", 500.0)])
def test_a_frequency_the_robot_refuses_gets_no_recipe_and_the_server_neither_streams_nor_spins(
        tmp_path, software, frequency):
    with CellServer(tmp_path, "--software", software) as server:
        with server.connect("rtde") as sock:
            conversation = rtde.Conversation(protocol=1)
            rtde_send(sock, conversation, rtde.request_protocol_version(2))
            rtde_replies(sock, conversation, 1)
            rtde_send(sock, conversation, g.SetupOutputs(frequency, ["timestamp", "actual_q"]).encode() + rtde.start())
            setup, start = rtde_replies(sock, conversation, 2)[:2]
            assert isinstance(setup, g.SetupOutputsReply) and setup.recipe_id == 0
            assert setup.types == ["DOUBLE", "VECTOR6D"]
            assert isinstance(start, g.StartReply) and not start.accepted
            before = cpu_seconds(server.proc.pid)
            sock.settimeout(1.0)
            with pytest.raises(socket.timeout):
                sock.recv(65536)                     # no data package comes
            sock.shutdown(socket.SHUT_WR)            # the client is done: the session ends
            sock.settimeout(5.0)
            assert sock.recv(65536) == b""
            assert cpu_seconds(server.proc.pid) - before < 0.5    # no core spun in that second
        assert server.stop() == 0


@pytest.mark.parametrize("software,frequency", [("5.11", 500.0), ("5.11", 0.5), ("3.15", 125.0)])
def test_a_frequency_the_robot_runs_gets_a_recipe_and_streams(tmp_path, software, frequency):
    with CellServer(tmp_path, "--software", software) as server:
        with server.connect("rtde") as sock:
            conversation = rtde.Conversation(protocol=1)
            rtde_send(sock, conversation, rtde.request_protocol_version(2))
            rtde_replies(sock, conversation, 1)
            rtde_send(sock, conversation, g.SetupOutputs(frequency, ["timestamp"]).encode() + rtde.start())
            setup, start, package = rtde_replies(sock, conversation, 3)[:3]
            assert setup.recipe_id == 1 and start.accepted and isinstance(package, g.DataPackage)
        assert server.stop() == 0


# ---- numbers on the command line that no robot would run ----------------------------------

def urwire(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "urwire", *args], capture_output=True, text=True, env=ENV,
                          timeout=30)


@pytest.mark.parametrize("args", [("--rate", "nan"), ("--rate", "inf"), ("--rate", "0"), ("--rate", "-10"),
                                  ("--rate", "1e308"), ("--rate", "1e6"), ("--rate", "500.5"),
                                  ("--duration", "nan"), ("--duration", "-1")])
def test_serve_refuses_a_rate_or_duration_it_could_only_spin_on(args):
    res = urwire("serve", "--port", "0", "--duration", "2", *args)
    assert res.returncode == 2 and "urwire serve" in res.stderr and args[0] in res.stderr, res.stderr
    assert "Traceback" not in res.stderr


@pytest.mark.parametrize("args", [("--frequency", "nan"), ("--frequency", "inf"), ("--frequency", "0"),
                                  ("--frequency", "-125"), ("--frequency", "500.5"), ("--idle-timeout", "nan"),
                                  ("--idle-timeout", "-1"), ("--duration", "nan"), ("--duration", "-1"),
                                  ("--count", "0")])
def test_listen_refuses_a_frequency_timeout_or_count_no_robot_would_take(args):
    res = urwire("listen", "127.0.0.1:9", "--rtde", "timestamp", "--duration", "1", *args)
    assert res.returncode == 2 and "urwire listen" in res.stderr and args[0] in res.stderr, res.stderr
    assert "Traceback" not in res.stderr and "cannot connect" not in res.stderr


def test_serve_runs_at_the_fastest_rate_a_controller_sends():
    res = urwire("serve", "--port", "0", "--rate", "500", "--duration", "0.3")
    assert res.returncode == 0, res.stderr


# ---- ports outside TCP's ----------------------------------------------------------------------

@pytest.mark.parametrize("args", [("--port", "-1"), ("--port", "65536"), ("--dashboard-port", "70000"),
                                  ("--rtde-port", "-5"), ("--realtime-port", "99999"), ("--port", "+80"),
                                  ("--dashboard-port", "\u0667")])
def test_serve_refuses_a_port_outside_tcps(args):
    res = urwire("serve", "--duration", "2", *args)
    assert res.returncode == 2 and "Traceback" not in res.stderr, res.stderr
    last = res.stderr.strip().splitlines()[-1]
    assert last.startswith("urwire serve: error: argument " + args[0]) and "0 to 65535" in last, res.stderr


@pytest.mark.parametrize("port,given,other", [("65533", (), "rtde"), ("65534", ("--rtde-port", "0"), "realtime"),
                                              ("1", (), "dashboard")])
def test_serve_refuses_a_port_that_puts_another_interface_outside_tcps(port, given, other):
    res = urwire("serve", "--port", port, *given, "--duration", "2")
    assert res.returncode == 2 and "Traceback" not in res.stderr, res.stderr
    (line,) = res.stderr.strip().splitlines()
    assert line.startswith(f"urwire serve: --port {port} puts the ") and line.endswith(f"give --{other}-port")


@pytest.mark.parametrize("port", ["99999", "65536", "0", "-1", "+30001", "\u0667"])
def test_listen_refuses_a_port_outside_tcps(port):
    res = urwire("listen", f"127.0.0.1:{port}", "--duration", "1")
    assert res.returncode == 2 and "Traceback" not in res.stderr, res.stderr
    (line,) = res.stderr.strip().splitlines()
    assert line.startswith(f"urwire listen: not an address: 127.0.0.1:{port}") and "1 to 65535" in line
