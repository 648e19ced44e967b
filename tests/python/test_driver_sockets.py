"""The ROS driver's sockets (reverse 50001, trajectory 50003, script command 50004) in Python:
the golden vectors whole and one byte at a time, each release's layout, hostile input, and
their entries in the interfaces table."""
from __future__ import annotations

import random
import struct

import pytest

from tests.interface_vectors import bytewise, conversation_cases
from urwire import to_dict
from urwire.generated import ur_reverse, ur_script_command, ur_trajectory
from urwire.interfaces import INTERFACES, interface_of_port

MODULES = {m.NAME: m for m in (ur_reverse, ur_trajectory, ur_script_command)}
CASES = [(name, case) for name in MODULES for case in conversation_cases(name)]


def decode(module, segments, version=None) -> list[dict]:
    conversation = module.conversation(version)
    records = [r for s in segments for r in conversation.feed(s.data, s.from_robot)]
    return [to_dict(r) for r in records + conversation.close()]


@pytest.mark.parametrize("name,case", CASES, ids=[f"{n}/{c.name}" for n, c in CASES])
def test_golden_vectors(name, case):
    assert decode(MODULES[name], case.segments, case.version) == case.expect
    assert decode(MODULES[name], bytewise(case.segments), case.version) == case.expect


def test_each_release_reads_its_own_layout():
    sizes = {release: ur_trajectory.RECORDS[False].layout(release).size
             for release in [(1, 0, 0), (1, 3, 1), (1, 3, 2), (2, 9, 7), (2, 10, 0), (2, 14, 0)]}
    assert sizes == {(1, 0, 0): 36, (1, 3, 1): 36, (1, 3, 2): 84, (2, 9, 7): 84, (2, 10, 0): 84, (2, 14, 0): 84}
    point = struct.pack(">21i", *([0] * 18 + [2500, 0, 0]))
    assert decode(ur_trajectory, [_pc(point)], "2.9")[0]["duration"] == 2.5
    assert decode(ur_trajectory, [_pc(point)], "2.10")[0]["duration"] == 0.0025
    assert [ur_script_command.RECORDS[False].layout(r).size for r in [(0, 4, 0), (1, 3, 2), (1, 4, 9), (1, 5, 0)]] \
        == [20, 104, 104, 112]


def _pc(data: bytes):
    from tests.interface_vectors import Segment
    return Segment(False, data)


def test_random_bytes_in_random_pieces_never_raise_and_every_record_renders():
    rng = random.Random(50001)
    for module in MODULES.values():
        for _ in range(100):
            conversation = module.conversation(rng.choice([None, "1.0.0", "1.3.2", "2.10.0"]))
            for _ in range(rng.randint(1, 6)):
                data = bytes(rng.randrange(256) for _ in range(rng.randint(0, 200)))
                for record in conversation.feed(data, rng.random() < 0.5):
                    to_dict(record)
            for record in conversation.close():
                to_dict(record)


def test_the_interfaces_table_knows_the_sockets_by_port_and_that_the_robot_connects():
    for port, name in [(50001, "ur_reverse"), (50003, "ur_trajectory"), (50004, "ur_script_command")]:
        interface = interface_of_port(port)
        assert interface is INTERFACES[name] and interface.robot_is_client
    assert not INTERFACES["ur"].robot_is_client and not INTERFACES["ur_dashboard"].robot_is_client
