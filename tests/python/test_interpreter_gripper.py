"""Interpreter mode (30020) and the Robotiq gripper's socket (63352) in Python: their golden
vectors whole and split at every byte, a statement as any line no interpreter command is, and
their entries in the interfaces table."""
from __future__ import annotations

import pytest

from tests.interface_vectors import bytewise, conversation_cases
from urwire import to_dict
from urwire.generated import robotiq_gripper, ur_interpreter
from urwire.interfaces import INTERFACES, interface_of_port
from urwire.text_lines import find_command

MODULES = {m.NAME: m for m in (ur_interpreter, robotiq_gripper)}
CASES = [(name, case) for name in MODULES for case in conversation_cases(name)]


def decode(name: str, segments, version=None) -> list[dict]:
    conversation = MODULES[name].conversation(version)
    records = [r for s in segments for r in conversation.feed(s.data, s.from_robot)] + conversation.close()
    return [to_dict(r) for r in records]


@pytest.mark.parametrize("name,case", CASES, ids=[f"{n}/{c.name}" for n, c in CASES])
def test_golden_vectors_whole_and_one_byte_at_a_time(name, case):
    assert decode(name, case.segments, case.version) == case.expect
    assert decode(name, bytewise(case.segments), case.version) == case.expect


def test_a_statement_is_any_line_no_interpreter_command_is():
    assert find_command(ur_interpreter.LOOKUP, "abort") == (ur_interpreter.ABORT, None)
    assert find_command(ur_interpreter.LOOKUP, "abort()") == (ur_interpreter.STATEMENT, "abort()")
    assert find_command(ur_interpreter.LOOKUP, "") == (ur_interpreter.STATEMENT, "")
    assert ur_interpreter.LOOKUP[-1] is ur_interpreter.STATEMENT


def test_a_line_the_gripper_does_not_know_is_no_command():
    assert find_command(robotiq_gripper.LOOKUP, "GETPOS") == (None, None)
    assert find_command(robotiq_gripper.LOOKUP, "GET POS") == (robotiq_gripper.GET, "POS")


@pytest.mark.parametrize("name,port", [("ur_interpreter", 30020), ("robotiq_gripper", 63352)])
def test_each_is_the_robot_listening_on_its_port(name, port):
    interface = interface_of_port(port)
    assert interface is INTERFACES[name] and not interface.robot_is_client and interface.both_directions
