"""`urwire serve`'s interpreter mode (30020) and Robotiq gripper socket (63352): over loopback TCP
every line gets one reply that urwire's own decoder reads as one of the spec's; and, on a clock
the test moves, the interpreter's ids and queue and the gripper's activation and grasp."""
from __future__ import annotations

import pytest

from tests.python.cell_server import CellServer, read_until
from urwire import to_dict
from urwire.generated import robotiq_gripper, ur_interpreter
from urwire.live.serve_gripper import OBJECT_AT, Gripper, GripperSession
from urwire.live.serve_interpreter import MOVE_SECONDS, Interpreter, InterpreterSession, compiles

STATEMENTS = [b"set_digital_out(1, True)", b"movej([0.94, -1.3, 2.2, -2.6, -1, 4], a=1, v=1)", b"statelastexecuted",
              b"statelastinterpreted", b"stateunexecuted", b"statelastcleared", b"skipbuffer", b"abort",
              b"clear_interpreter()", b'textmsg("unclosed"']
GRIPPER = [b"GET STA", b"SET ACT 1", b"GET ACT", b"SET POS 255 SPE 128 FOR 64 GTO 1", b"GET PRE", b"GET OBJ",
           b"GET POS", b"GET FLT", b"GET SPE"]


def exchange(server: CellServer, interface: str, tables, lines: list) -> list:
    """Every line sent at once, and the records of both directions once each has its reply."""
    conversation = tables.conversation()
    with server.connect(interface) as sock:
        sock.sendall(b"".join(line + b"\n" for line in lines))
        commands = conversation.feed(b"".join(line + b"\n" for line in lines), False)
        replies = read_until(sock, lambda data: conversation.feed(data, True), lambda r: len(r) >= len(lines))
    return [to_dict(r) for r in commands], [to_dict(r) for r in replies]


@pytest.fixture(scope="module")
def server(tmp_path_factory):
    with CellServer(tmp_path_factory.mktemp("serve"), "--software", "5.11") as cell:
        yield cell


def test_the_interpreter_answers_each_line_with_one_of_its_replies(server):
    commands, replies = exchange(server, "interpreter", ur_interpreter, STATEMENTS)
    assert [r["command_name"] for r in replies] == [c["command_name"] for c in commands]
    assert [r["reply_name"] for r in replies] == ["ack", "ack", "state", "state", "state", "state", "ack", "ack",
                                                  "ack", "discard"]
    assert replies[0]["reply"] == "ack: 1: set_digital_out(1, True)" and replies[3]["reply"].startswith("state: 2: ")
    assert [r["error"] for r in replies] == [False] * 9 + [True]


def test_the_gripper_answers_each_line_with_one_of_its_replies(server):
    commands, replies = exchange(server, "gripper", robotiq_gripper, GRIPPER)
    assert [r["reply_name"] for r in replies] == ["value", "ack", "value", "ack", "value", "value", "value", "value",
                                                  "value"]
    assert [r["reply"] for r in replies][:5] == ["STA 0", "ack", "ACT 1", "ack", "PRE 255"]
    assert replies[-1]["reply"] == "SPE 128"


def test_a_cb3_has_no_interpreter_mode_but_may_carry_a_gripper(tmp_path):
    with CellServer(tmp_path, "--software", "3.15") as cell:
        assert "interpreter" not in cell.ports and "gripper" in cell.ports


class Clock:
    def __init__(self):
        self.now = 0.0

    def __call__(self) -> float:
        return self.now


def lines(session, *sent: str) -> list[str]:
    return session.received("".join(s + "\n" for s in sent).encode()).decode().splitlines()


def test_statements_run_one_after_another_on_the_clock():
    clock = Clock()
    session = InterpreterSession(Interpreter(), clock)
    assert lines(session, "movej([0,0,0,0,0,0])", "movel([1,1,1,1,1,1])", "sleep(0.5)") == [
        "ack: 1: movej([0,0,0,0,0,0])", "ack: 2: movel([1,1,1,1,1,1])", "ack: 3: sleep(0.5)"]
    assert lines(session, "statelastexecuted", "stateunexecuted") == ["state: 1: statelastexecuted",
                                                                      "state: 2: stateunexecuted"]
    clock.now = MOVE_SECONDS
    assert lines(session, "statelastexecuted", "stateunexecuted") == ["state: 2: statelastexecuted",
                                                                      "state: 1: stateunexecuted"]
    assert lines(session, "skipbuffer", "stateunexecuted", "abort") == [
        "ack: 3: skipbuffer", "state: 0: stateunexecuted", "ack: 3: abort"]
    assert lines(session, "clear_interpreter()", "statelastcleared", "statelastexecuted") == [
        "ack: 4: clear_interpreter()", "state: 3: statelastcleared", "state: 4: statelastexecuted"]


@pytest.mark.parametrize("statement,ok", [("f(1, [2, 3])", True), ('textmsg("(")', True), ("f(1", False),
                                          ("f(1]", False), ('textmsg("x)', False), ("a = 1", True)])
def test_a_statement_is_discarded_when_its_brackets_or_quotes_do_not_close(statement, ok):
    assert compiles(statement) is ok


def test_the_gripper_activates_then_closes_onto_the_part_and_opens():
    clock = Clock()
    session = GripperSession(Gripper(), clock)
    assert lines(session, "SET POS 255 GTO 1", "GET FLT", "SET ACT 1", "GET STA") == ["ack", "FLT 7", "ack", "STA 1"]
    clock.now = 1.0
    assert lines(session, "GET STA", "SET POS 255 SPE 255 GTO 1", "GET FLT", "GET OBJ") == [
        "STA 3", "ack", "FLT 0", "OBJ 0"]
    clock.now = 3.0
    assert lines(session, "GET POS", "GET OBJ", "GET PRE") == [f"POS {OBJECT_AT}", "OBJ 2", "PRE 255"]
    assert lines(session, "SET POS 0 GTO 1") == ["ack"]
    clock.now = 5.0
    assert lines(session, "GET POS", "GET OBJ", "HELLO", "GET NOPE") == ["POS 0", "OBJ 3", "?", "?"]
