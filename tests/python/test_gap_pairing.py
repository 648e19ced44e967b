"""After bytes are lost from a capture, no reply is paired with a request it did not answer: the
requests a gap may have swallowed, or whose replies it may have swallowed, leave the pairing
unknown, and every reply after that pairs with nothing and says so."""
from __future__ import annotations

import json
import subprocess
import sys

from tests.tools import capture
from tests.tools.capture import FIN, exchange_frames

ROOT = __import__("pathlib").Path(__file__).resolve().parents[2]
ENV = {"PYTHONPATH": f"{ROOT / 'python'}:{ROOT / 'generated' / 'python'}"}
DASHBOARD_UNKNOWN = "reply after bytes lost from the capture: its command is unknown"
LINE_CUT = "line after bytes lost from the capture: its start may be lost"
SETUP_UNKNOWN = "reply after bytes lost from the capture: its setup is unknown"
BANNER = b"Connected: Universal Robots Dashboard Server\n"


def decode(tmp_path, steps: list, port: int, lose: int) -> tuple[list[dict], int]:
    pcap = capture.write(tmp_path / "gap.pcap", exchange_frames(steps, port, lose=lose))
    res = subprocess.run([sys.executable, "-m", "urwire", "decode", str(pcap)], capture_output=True, text=True,
                         env=ENV, timeout=120)
    assert res.returncode in (0, 1), res.stderr
    return [json.loads(line) for line in res.stdout.splitlines()], res.returncode


ANSWERS = {"Powering on": "power_on", "Brake releasing": "brake_release", "Robotmode: IDLE": "robotmode",
           "Loaded program: /x.urp": "get_loaded_program", "Starting program": "play"}
COMMANDS = [b"power on\n", b"brake release\n", b"robotmode\n", b"get loaded program\n", b"play\n"]
REPLIES = [b"Powering on\n", b"Brake releasing\n", b"Robotmode: IDLE\n", b"Loaded program: /x.urp\n",
           b"Starting program\n"]


def replies(records: list[dict]) -> list[dict]:
    return [r for r in records if r["type"] == "reply" and r.get("reply_name") != "connected"]


def assert_none_mispaired(records: list[dict]) -> None:
    for reply in replies(records):
        assert reply.get("command_name") in (None, ANSWERS[reply["reply"]]), reply


def test_a_gap_that_swallows_a_reply_leaves_the_later_replies_unpaired(tmp_path):
    """A client that waits for each reply: the robot's reply to robotmode is lost, and the robot's
    later segments wait in the reader until its side closes, behind the commands they answer."""
    steps = [(True, BANNER)]
    for command, reply in zip(COMMANDS, REPLIES):
        steps += [(False, command), (True, reply)]
    steps += [(True, FIN), (False, FIN)]
    records, status = decode(tmp_path, steps, 29999, lose=6)
    assert status == 1
    assert_none_mispaired(records)
    paired = [(r["reply"], r.get("command_name"), r.get("error")) for r in replies(records)]
    assert paired == [("Powering on", "power_on", False), ("Brake releasing", "brake_release", False),
                      ("Loaded program: /x.urp", None, LINE_CUT),
                      ("Starting program", None, DASHBOARD_UNKNOWN)]


def test_a_gap_that_swallows_a_command_leaves_the_later_replies_unpaired(tmp_path):
    """A client that sends its commands at once and closes its side: brake release is lost; the
    reply to power on, sent before it, still pairs; every later one pairs with nothing."""
    steps = [(True, BANNER)] + [(False, c) for c in COMMANDS] + [(False, FIN)]
    steps += [(True, r) for r in REPLIES] + [(True, FIN)]
    records, status = decode(tmp_path, steps, 29999, lose=2)
    assert status == 1
    assert_none_mispaired(records)
    paired = [(r["reply"], r.get("command_name"), r.get("error")) for r in replies(records)]
    assert paired == [("Powering on", "power_on", False)] + [(r.decode().strip(), None, DASHBOARD_UNKNOWN)
                                                             for r in REPLIES[1:]]
    gap = [r for r in records if r["type"] == "error" and "missing from the capture" in r["error"]]
    assert [g["direction"] for g in gap] == ["to_robot"]
    # The commands after the gap are decoded, and are not the overflow's: only the gap is an error.
    # The first line after the gap may be the end of a longer one, and says so.
    assert [(r["command_name"], r.get("error")) for r in records if r["type"] == "command"] == [
        ("power_on", None), ("robotmode", LINE_CUT), ("get_loaded_program", None), ("play", None)]


def test_the_end_of_a_line_after_a_gap_is_not_taken_for_a_whole_command(tmp_path):
    """"popup power off" whose first segment is lost: "power off" is decoded, but not as a
    command the client surely sent."""
    steps = [(True, BANNER), (False, b"power on\n"), (True, REPLIES[0]), (False, b"popup "), (False, b"power off\n"),
             (True, b"showing popup\n"), (False, b"robotmode\n"), (True, REPLIES[2]), (False, FIN), (True, FIN)]
    records, status = decode(tmp_path, steps, 29999, lose=3)
    assert status == 1
    commands = [(r["command"], r.get("error")) for r in records if r["type"] == "command"]
    assert commands == [("power on", None), ("power off", LINE_CUT), ("robotmode", None)]


def test_a_gap_in_the_replies_when_none_awaits_keeps_the_pairing():
    """Bytes the robot sent while no command awaited a reply cannot hold one: pairing goes on (the
    capture reader names such a gap when the robot's later bytes come, before what they answer)."""
    from urwire.generated import ur_dashboard

    conversation = ur_dashboard.conversation()
    conversation.feed(BANNER, True)
    conversation.feed(COMMANDS[0], False)
    conversation.feed(REPLIES[0], True)
    conversation.lost(True, len(BANNER) + len(REPLIES[0]) + 11)
    conversation.feed(COMMANDS[1], False)
    (cut,) = conversation.feed(b"ing\n", True)     # the end of a line the lost bytes began
    assert (cut.command_name, cut.error) == (None, LINE_CUT)
    (reply,) = conversation.feed(REPLIES[1], True)
    assert (reply.command_name, reply.error) == ("brake_release", False)
    conversation.feed(COMMANDS[2], False)
    conversation.lost(True, 200)                    # now one awaits: its reply may be among the lost
    (reply,) = conversation.feed(REPLIES[2], True)
    assert (reply.command_name, reply.error) == (None, LINE_CUT)
    conversation.feed(COMMANDS[3], False)
    (reply,) = conversation.feed(REPLIES[3], True)
    assert (reply.command_name, reply.error) == (None, DASHBOARD_UNKNOWN)


def test_the_script_senders_latest_request_is_unknown_after_a_gap_in_the_requests():
    """The program lines answer the latest request_program: after a gap in the robot's requests
    they answer one that may be lost, until the next request comes."""
    from urwire.generated import ur_script_sender

    conversation = ur_script_sender.conversation()
    conversation.feed(b"request_program\n", True)
    assert conversation.feed(b"def prog():\n", False)[0].command_name == "request_program"
    conversation.lost(False, 100)                   # the program's lines: the request is still known
    (cut,) = conversation.feed(b"x = 1\n", False)   # but this line's start may be lost
    assert (cut.command_name, cut.error) == (None, LINE_CUT)
    assert conversation.feed(b"end\n", False)[0].command_name == "request_program"
    conversation.lost(True, 100)
    (line,) = conversation.feed(b"def prog():\n", False)
    assert (line.command_name, line.error) == (None, DASHBOARD_UNKNOWN)
    conversation.feed(b"request_program\n", True)
    assert conversation.feed(b"end\n", False)[0].command_name == "request_program"


def test_an_rtde_gap_that_swallows_a_setup_request_makes_no_recipe_from_another(tmp_path):
    """The first of two setups is lost: its reply does not take the second's names, the recipe
    set up before the gap is kept, and no data package is read with names it was not set up with."""
    from urwire import rtde
    from urwire.generated import rtde as g

    first = rtde.Recipe(1, "outputs", ["timestamp"], ["DOUBLE"], g.VALUE_TYPES)
    second = rtde.Recipe(2, "outputs", ["target_speed_fraction"], ["DOUBLE"], g.VALUE_TYPES)
    third = rtde.Recipe(3, "outputs", ["speed_scaling"], ["DOUBLE"], g.VALUE_TYPES)
    steps = [(False, rtde.request_protocol_version(2)), (True, g.RequestProtocolVersionReply(True).encode()),
             (False, rtde.setup_outputs(["timestamp"], 125.0)), (True, g.SetupOutputsReply(1, ["DOUBLE"]).encode()),
             (False, rtde.setup_outputs(["target_speed_fraction"], 125.0)),       # lost
             (False, rtde.setup_outputs(["speed_scaling"], 125.0)),
             (False, rtde.start()), (False, FIN),
             (True, g.SetupOutputsReply(2, ["DOUBLE"]).encode()), (True, g.SetupOutputsReply(3, ["DOUBLE"]).encode()),
             (True, g.StartReply(True).encode())]
    steps += [(True, g.DataPackage(r.id, {r.names[0]: 0.5}).encode(r)) for r in (first, second, third)]
    steps += [(True, FIN)]
    records, status = decode(tmp_path, steps, 30004, lose=4)
    assert status == 1
    asked = [r for r in records if r["type"] == "setup_outputs"]
    assert [("error" in r) for r in asked] == [False, False]            # the gap's record says it
    setups = [r for r in records if r["type"] == "setup_outputs_reply"]
    assert [(s["recipe_id"], s.get("error")) for s in setups] == [(1, None), (2, SETUP_UNKNOWN), (3, SETUP_UNKNOWN)]
    data = [r for r in records if r["type"] == "data_package"]
    assert data[0]["timestamp"] == 0.5 and "error" not in data[0]          # set up before the gap
    assert [d["recipe_id"] for d in data[1:]] == [2, 3]
    assert all("error" in d and "speed_scaling" not in d and "target_speed_fraction" not in d for d in data[1:])


def test_a_driver_socket_cuts_its_records_on_their_grid_after_a_gap():
    """Records of one size from the stream's start: after a gap that ends inside one, its end is
    named and the next records are read whole, not shifted by the gap's remainder."""
    from urwire.generated import ur_reverse

    conversation = ur_reverse.conversation("1.3.4")
    size = ur_reverse.RECORDS[False].layout((1, 3, 4)).size
    record = lambda keepalive: (b"".join(int.to_bytes(v, 4, "big", signed=True)   # noqa: E731
                                         for v in [keepalive] + [0] * (size // 4 - 1)))
    stream = b"".join(record(i) for i in range(6))
    assert [r.read_timeout for r in conversation.feed(stream[:size], False)] == [0]
    cut = 2 * size + 12                             # bytes from size on lost, up to 12 bytes into record 2
    assert conversation.lost(False, cut) == []
    out = conversation.feed(stream[cut:], False)
    assert out[0].offset == cut and out[0].error.startswith(f"{size - 12} bytes after bytes lost")
    assert [r.read_timeout for r in out[1:]] == [3, 4, 5]
    # A stream that ends before the next record's start names what it dropped when it closes.
    conversation.lost(False, 7 * size + 4)
    assert conversation.feed(b"\0" * 8, False) == []
    (end,) = conversation.close(False)
    assert (end.offset, end.error) == (7 * size + 4, "8 bytes after bytes lost from the capture: the end of a "
                                                     "record whose start is lost")
